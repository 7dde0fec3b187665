"""The BIOTACT G1 protocol (thesis 6.4): grid, refusals before any simulation, whisks."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from vibrissa.thesis.biotact_g1.protocol import BiotactProtocol, biotact_protocol


def test_the_thesis_grid_and_the_quick_one():
    p = biotact_protocol()
    assert p.n_trials == 3 * 3 * 3 * 12 == len(p.trials())
    assert p.n_samples == 1000 and p.n_channels == 12  # a 2 Hz whisk at 2 kHz, 6 whiskers
    assert p.channel_names()[:2] == ["L1x", "L1y"] and p.channel_names()[-1] == "R3y"
    specs = p.trials()
    assert [s.whisk for s in specs[:13]] == [*range(1, 13), 1]
    # a class's whisks are consecutive, one chunk (one continuous run) each
    assert p.chunk_size == 12
    assert {(s.strategy, s.texture, s.distance_mm) for s in specs[:12]} == {
        ("unmodulated", "plastic", 5.0)
    }
    q = biotact_protocol(quick=True)
    assert q.n_trials == 3 * 2 * 2 * 2


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"whisk_frequency_hz": 0.0}, "whisk_frequency_hz must be > 0"),
        ({"whisk_frequency_hz": -2.0}, "whisk_frequency_hz must be > 0"),
        ({"whisk_frequency_hz": 3.0}, "whole number of samples"),
        ({"tau_z_periods": -0.25}, "tau_z_periods"),
        ({"amplitude_jitter_deg": -1.0}, "amplitude_jitter_deg"),
        ({"distances_mm": (0.0, 10.0)}, "places the head inside the surface"),
        ({"distances_mm": (5.0, 5.0)}, "each distance once"),
        ({"textures": ("plastic", "velvet")}, "unknown texture 'velvet'"),
        ({"strategies": ("rcp5",)}, "unknown strategy 'rcp5'"),
        ({"n_whisks": 1}, "n_whisks must be an integer >= 2"),
    ],
)
def test_bad_settings_are_refused_in_one_line(kwargs, match):
    with pytest.raises(ValueError, match=match) as err:
        BiotactProtocol(**kwargs)
    assert "\n" not in str(err.value)


@pytest.fixture(scope="module")
def tiny() -> BiotactProtocol:
    # the farthest surface, where the whiskers touch least
    return BiotactProtocol(
        textures=("p180",), distances_mm=(15.0,), n_whisks=2, strategies=("unmodulated", "rcp7")
    )


def test_every_whisker_of_both_rows_touches_the_surface_on_every_whisk(tiny):
    r = tiny.simulate_trials([0, 1])
    assert r["signal"].shape == (2, 12, 1000)
    touched = (r["force_n"] > 0).any(axis=2)
    assert touched.all(), touched
    # and leaves it again before the whisk ends at full retraction
    assert not (r["force_n"][:, :, -50:] > 0).any()
    assert np.all(r["gating"] == 0.0)  # unmodulated
    assert np.all(r["angle_deg"][:, :, 0] < 1.0)  # each whisk starts fully retracted


def test_the_bytes_of_a_whisk_do_not_depend_on_the_chunk(tiny):
    both = tiny.simulate_trials([0, 1])
    one = tiny.simulate_trials([1])
    for key in ("signal", "force_n", "angle_deg"):
        np.testing.assert_array_equal(both[key][1], one[key][0])


def test_rcp_gates_protraction_and_presses_less(tiny):
    r = tiny.simulate_trials([0, 1, 2, 3])  # unmodulated, then rcp7
    x = r["signal"][:, 0::2, :]
    peak = np.abs(x - x[:, :, :1]).max(axis=2).mean(axis=1)
    assert peak[2:].max() < peak[:2].min()
    assert r["gating"][2:].max() > 0.05 and r["gating"][:2].max() == 0.0
    # protraction suppressed: the housing turns less far
    assert r["angle_deg"][2:].max() < r["angle_deg"][:2].max() - 1.0


def test_build_dataset_keeps_the_labels_and_the_robot(tiny):
    r = tiny.simulate_trials(range(tiny.n_trials))
    ds = tiny.build_dataset(r)
    assert list(ds["strategy"].values) == ["unmodulated"] * 2 + ["rcp7"] * 2
    assert list(ds["whisk"].values) == [1, 2, 1, 2]
    assert ds["signal"].dims == ("trial", "channel", "time")
    assert ds.attrs["sample_rate_hz"] == 2000.0
    assert ds["force_n"].shape == (4, 6, 1000)
    with pytest.raises(ValueError, match="expected 4 trials"):
        tiny.build_dataset({k: v[:2] for k, v in r.items()})


def test_a_changed_protocol_changes_the_fingerprint(tiny):
    assert dataclasses.replace(tiny, amplitude_jitter_deg=0.4).fingerprint() != tiny.fingerprint()


def test_generation_resumes_class_by_class_to_the_same_bytes(tiny, tmp_path):
    from vibrissa.data import validate_dataset
    from vibrissa.experiments.generate import generate

    out = tmp_path / "g1.nc"
    # interrupted after one chunk (one class's continuous run), then resumed
    assert generate(tiny, out, workers=1, chunk_size=tiny.chunk_size, max_chunks=1) is None
    ds = generate(tiny, out, workers=1, chunk_size=tiny.chunk_size)
    validate_dataset(ds)
    direct = tiny.simulate_trials(range(tiny.n_trials))
    np.testing.assert_array_equal(ds["signal"].values, direct["signal"])


def test_a_session_of_a_multi_seed_run_is_the_single_session_of_its_seed():
    kw = dict(textures=("p180",), distances_mm=(15.0,), n_whisks=2, strategies=("unmodulated",))
    two = BiotactProtocol(n_seeds=2, seed=3, **kw)
    assert two.n_trials == 4 and [s.session_seed for s in two.trials()] == [3, 3, 4, 4]
    alone = BiotactProtocol(seed=4, **kw)
    np.testing.assert_array_equal(
        two.simulate_trials([2, 3])["signal"], alone.simulate_trials([0, 1])["signal"]
    )
    ds = two.build_dataset(two.simulate_trials(range(4)))
    assert list(ds["session_seed"].values) == [3, 3, 4, 4]
    with pytest.raises(ValueError, match="n_seeds must be a positive integer"):
        BiotactProtocol(n_seeds=0, **kw)
