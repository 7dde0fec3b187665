"""The compiled RCP loop (``vibrissa.whisker.simulate.rcp_loop``) under ``run_whisking``.

``run_whisking`` runs a closed loop in one compiled call when every object stands still;
the loop in Python stays for moving objects. Both must give the same numbers bit for
bit: a two-sided head of textured sheets with contact-induced asymmetry, and a side of
mixed whiskers (a pole, air). A step that fails must surface as a ``SimulationError``
naming the time, as the loop in Python does.
"""

from __future__ import annotations

import numpy as np
import pytest

import vibrissa.robots.whisking as whisking
from vibrissa.robots.biotact import G1_CONTACT_SIGNAL_SCALE, G1Head
from vibrissa.robots.whisking import (
    RCPControl,
    VaryingWhiskPattern,
    WhiskerSetup,
    WhiskPattern,
    pole_whisker,
    run_whisking,
)
from vibrissa.whisker.geometry import preset
from vibrissa.whisker.rod import RodModel, SimulationError
from vibrissa.whisker.simulate import ClosedLoopStepper, PoleContact, Trajectory, rcp_loop
from vibrissa.whisker.surfaces import make_surface

FIELDS = ("tan_x", "tan_y", "contact_force_n", "angle_deg", "command_deg")
CONTROL = ("contact_signal", "gating", "deflection")


@pytest.fixture(scope="module")
def model() -> RodModel:
    return RodModel(preset("scratchbot"), 12)


def _sheets() -> tuple[list[WhiskerSetup], list[VaryingWhiskPattern]]:
    # the BIOTACT G1's two rows of three, each facing a P180 sheet 5 mm
    # ahead, every whisk of its own amplitude
    head = G1Head()
    out = []
    for side in range(2):
        for i, length in enumerate(head.lengths_mm):
            rod = RodModel(preset(f"biotact-g1-{length:g}"), 20)
            sheet = make_surface("p180", seed=side + 1)
            out.append(head.whisker(i, rod, sheet, 5.0, side, 20.0, 0.45, (1.0 * i, 2.0)))
    patterns = [
        VaryingWhiskPattern(4.0, head.amplitude_deg, 0.0, amplitudes_deg=amps)
        for amps in ((35.0, 37.0, 33.0), (34.0, 36.0))
    ]
    return out, patterns


def _both(monkeypatch, whiskers, patterns, control, duration_s):
    calls = []

    def counted(*args):
        calls.append(1)
        return rcp_loop(*args)

    with monkeypatch.context() as m:
        m.setattr(whisking, "rcp_loop", counted)
        fast = run_whisking(whiskers, patterns, control, duration_s)
    with monkeypatch.context() as m:
        m.setattr(whisking, "rcp_loop", None)  # the compiled loop must not be reached
        m.setattr(whisking, "_compiled_inputs", lambda *a: None)
        slow = run_whisking(whiskers, patterns, control, duration_s)
    return fast, slow, len(calls)


def _assert_same(fast, slow) -> None:
    for name in (*FIELDS, *CONTROL):
        np.testing.assert_array_equal(getattr(fast, name), getattr(slow, name), err_msg=name)


def test_a_head_of_textured_sheets_runs_compiled_bit_for_bit(monkeypatch):
    whiskers, patterns = _sheets()
    ctrl = RCPControl(0.7, cia_gain=0.3, signal_scale=G1_CONTACT_SIGNAL_SCALE)
    fast, slow, calls = _both(monkeypatch, whiskers, patterns, ctrl, 0.5)
    assert calls == 1
    _assert_same(fast, slow)
    # the comparison means something: both sides touch, gate and modulate
    assert (fast.contact_force_n.max(axis=1) > 1e-3).all()
    assert (fast.gating.max(axis=1) > 0.1).all()


def test_a_side_of_mixed_whiskers_runs_compiled_bit_for_bit(monkeypatch, model):
    short = RodModel(preset("biotact-g1-80"), 12)
    whiskers = [
        pole_whisker(model, 100.0, 10.0),
        WhiskerSetup(short, side=0),
        WhiskerSetup(model, side=1),
    ]
    fast, slow, calls = _both(
        monkeypatch, whiskers, WhiskPattern(2.0, 20.0), RCPControl(0.7, cia_gain=0.5), 0.5
    )
    assert calls == 1
    _assert_same(fast, slow)
    assert fast.contact_force_n[0].max() > 1e-3


def test_a_moving_object_keeps_the_loop_in_python(monkeypatch, model):
    moving = WhiskerSetup(model, PoleContact(), Trajectory.linear((50.0, 100.0), (-80.0, 0.0), 0.3))
    with monkeypatch.context() as m:
        m.setattr(whisking, "rcp_loop", None)  # would raise TypeError if called
        res = run_whisking([moving], WhiskPattern(2.0, 20.0), RCPControl(0.7), 0.3)
    assert res.contact_force_n.max() > 1e-3


def test_a_failed_step_stops_the_loop_and_names_the_time(monkeypatch, model):
    # a non-finite object row makes the first step non-finite: the loop reports the
    # period, the whisker and its completed steps, and returns at once
    st = ClosedLoopStepper(model, None, None, 2.5e-4)
    k = st.kernel_inputs(0.0, 0.0)
    n_steps, spp = 8, 2
    out = {n: np.zeros((1, n_steps + 1)) for n in ("tx", "ty", "f", "a")}
    ctl = {n: np.zeros((1, n_steps // spp + 1)) for n in ("c", "p", "z", "d")}
    failure = np.full(3, -1, dtype=np.int64)
    done = rcp_loop(
        (k.state,),
        (k.anchors,),
        (k.rod,),
        (k.damping,),
        (k.contact,),
        k.settings,
        np.full((1, 6), np.nan),
        np.zeros(1, dtype=np.int64),
        np.full((1, n_steps + 1), np.nan),
        np.zeros((1, n_steps // spp + 1)),
        np.zeros(1),
        np.array([1.0, 0.0, 0.0, 1.0]),
        np.zeros((1, 2)),
        np.array([[1.0, 0.0, 0.0, 0.0, 0.0]]),
        np.zeros((1, 1, 2)),
        np.ones(1),
        np.full(1, 0.9),
        0.7,
        0.0,
        3.0,
        spp,
        out["tx"],
        out["ty"],
        out["f"],
        out["a"],
        ctl["c"],
        ctl["p"],
        ctl["z"],
        ctl["d"],
        failure,
    )
    assert done == 0
    assert failure[0] == 0 and failure[1] == 0 and 0 <= failure[2] <= spp

    def failing(*args):
        args[-1][:] = (3, 0, 1)
        return 3

    monkeypatch.setattr(whisking, "rcp_loop", failing)
    with pytest.raises(SimulationError, match=r"t = 0\.00325 s \(step 1 of 4\)"):
        run_whisking([WhiskerSetup(model)], WhiskPattern(2.0, 20.0), RCPControl(0.7), 0.1)
