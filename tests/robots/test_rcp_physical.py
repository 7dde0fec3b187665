"""RCP on the physical SCRATCHbot whisker in closed loop: figure 3.9's two outcomes (3.4.2).

The contact signal's scale (``CONTACT_SIGNAL_SCALE``) was identified so that, whisking
into the SCRATCHbot protocol's pole, sigma_z 0.7 with tau_z T_w/4 gives one contact per
whisk and sigma_z 2 with tau_z T_w/10 the biphasic whisk (scripts/identify_rcp.py).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vibrissa.robots.biotact import G1_CONTACT_SIGNAL_SCALE
from vibrissa.robots.whisking import (
    CONTACT_DIP_FRACTION,
    CONTACT_SIGNAL_SCALE,
    FIGURE_3_9_SETTINGS,
    RCPControl,
    WhiskPattern,
    pole_whisker,
    run_whisking,
    whisk_contacts,
)
from vibrissa.whisker.geometry import preset
from vibrissa.whisker.hall import HallSettings
from vibrissa.whisker.rod import RodModel

ROOT = Path(__file__).resolve().parents[2]

#: The SCRATCHbot protocol's closed-loop comparison: its whisker, pole and whisk.
RADIUS_MM, CONTACT_DEG, AMPLITUDE_DEG, FREQUENCY_HZ, WHISKS = 100.0, 6.0, 12.0, 2.0, 4


@pytest.fixture(scope="module")
def runs() -> dict[str, tuple[np.ndarray, float]]:
    """Figure 3.9's panel -> (contacts per whisk, largest z) on the physical whisker."""
    g = preset("scratchbot")
    model = RodModel(g, 28)
    gain = HallSettings().calibrate(g, 28).gain_v
    out = {}
    for key, (sigma, tau) in FIGURE_3_9_SETTINGS.items():
        res = run_whisking(
            [pole_whisker(model, RADIUS_MM, CONTACT_DEG, 0.5, hall_gain_v=gain)],
            WhiskPattern(FREQUENCY_HZ, AMPLITUDE_DEG, 0.0),
            RCPControl(sigma, tau),
            WHISKS / FREQUENCY_HZ,
        )
        counts = whisk_contacts(
            res.time_s,
            res.angle_deg[0],
            res.contact_force_n[0] > 0,
            FREQUENCY_HZ,
            CONTACT_DIP_FRACTION * AMPLITUDE_DEG,
        )[:WHISKS]
        out[key] = (counts, float(res.gating[0].max()))
    return out


def test_the_identified_scales_are_the_defaults():
    # the committed identification (scripts/identify_rcp.py) chose them
    record = json.loads((ROOT / "docs" / "runs" / "identify_rcp.json").read_text())
    assert RCPControl().signal_scale == CONTACT_SIGNAL_SCALE == record["chosen"]["scale"]
    assert G1_CONTACT_SIGNAL_SCALE == record["g1_chosen"]["scale"]


def test_panel_a_one_contact_per_whisk_on_the_physical_whisker(runs):
    counts, z_max = runs["a"]
    assert counts.tolist() == [1] * WHISKS
    assert 0.0 < z_max < 1.0  # protraction suppressed, not stopped


def test_panel_b_the_biphasic_whisk_on_the_physical_whisker(runs):
    counts, _ = runs["b"]
    assert counts.size == WHISKS and (counts >= 2).all(), counts


def _episodes(pattern: list[tuple[float, float]], n: int = 1000) -> np.ndarray:
    on = np.zeros(n, dtype=bool)
    for a, b in pattern:
        on[int(a * n) : int(b * n)] = True
    return on


def test_a_bounce_while_the_housing_protracts_is_one_contact():
    t = np.arange(1000) / 1000.0  # one whisk at 1 Hz
    angle = 6.0 * (1 - np.cos(2 * np.pi * t))
    on = _episodes([(0.30, 0.32), (0.34, 0.70)])  # a bounce at impact, then pressing on
    assert whisk_contacts(t, angle, on, 1.0, 0.6).tolist() == [1]


def test_a_withdrawal_and_a_resumed_protraction_make_two_contacts():
    t = np.arange(1000) / 1000.0
    angle = 6.0 * (1 - np.cos(2 * np.pi * t))
    angle[300:450] = np.interp(np.arange(300, 450), [300, 370, 450], [angle[300], 3.0, 8.0])
    on = _episodes([(0.25, 0.30), (0.42, 0.70)])
    assert whisk_contacts(t, angle, on, 1.0, 0.6).tolist() == [2]
    # the ringing re-touch of a retracting housing is no resumed protraction
    angle2 = 6.0 * (1 - np.cos(2 * np.pi * t))
    on2 = _episodes([(0.25, 0.60), (0.70, 0.72)])
    assert whisk_contacts(t, angle2, on2, 1.0, 0.6).tolist() == [1]


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (([0.0, 1.0], [0.0], [True, False], 1.0, 0.5), "same length"),
        (([0.0, 1.0], [0.0, 1.0], [True, False], 0.0, 0.5), "frequency_hz"),
        (([0.0, 1.0], [0.0, 1.0], [True, False], 1.0, 0.0), "dip_deg"),
        (([0.0, np.nan], [0.0, 1.0], [True, False], 1.0, 0.5), "time_s"),
    ],
)
def test_whisk_contacts_refuses_bad_input(args, match):
    with pytest.raises(ValueError, match=match):
        whisk_contacts(*args)


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.booleans(), min_size=20, max_size=300),
    st.lists(st.floats(-20, 20, allow_nan=False), min_size=20, max_size=300),
    st.floats(0.1, 5.0),
)
def test_contacts_never_exceed_the_runs_of_contact(on, angle, dip):
    n = min(len(on), len(angle))
    on_a, ang = np.array(on[:n]), np.array(angle[:n])
    t = np.arange(n) / 100.0
    counts = whisk_contacts(t, ang, on_a, 2.0, dip)
    runs = int(np.count_nonzero(np.diff(np.concatenate([[0], on_a.astype(int)])) == 1))
    assert counts.sum() <= runs
    assert (counts.sum() >= 1) == (runs >= 1)
    assert counts.size == int(np.floor(2.0 * t[-1])) + 1
