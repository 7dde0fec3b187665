"""The Roomba floor-texture protocol (thesis 6.2) and its generation."""

from __future__ import annotations

import numpy as np
import pytest

from vibrissa.experiments.generate import dataset_bytes, generate
from vibrissa.thesis.floor_texture.protocol import FloorProtocol, floor_protocol


def test_the_thesis_session_and_the_quick_one():
    p = floor_protocol()
    assert p.n_trials == 4 * 3 * 4 == len(p.trials())
    assert p.n_samples == 16 * 2000
    assert p.sensor.sample_rate_hz == 2000.0 and p.whisker == "scratchbot"
    q = floor_protocol(quick=True)
    assert q.n_trials == 24 and q.duration_s == 4.0
    assert dataset_bytes(p) == 48 * 2 * 32000 * 8
    # canonical order: condition, floor, repetition
    first = p.trials()[:5]
    assert [(s.condition, s.floor, s.trial) for s in first] == [
        ("clockwise", "rough-carpet", k) for k in (1, 2, 3, 4)
    ] + [("clockwise", "vinyl", 1)]
    assert p.fingerprint() != q.fingerprint()
    assert floor_protocol(seed=1).fingerprint() != p.fingerprint()


@pytest.mark.parametrize(
    "changes, match",
    [
        ({"floors": ("vinyl", "shag")}, "unknown floor texture 'shag'"),
        ({"floors": ()}, "at least one floor"),
        ({"floors": ("vinyl", "vinyl")}, "each floor texture once"),
        ({"conditions": ("clockwise", "sideways")}, "conditions must be"),
        ({"trials_per_condition": 0}, "trials_per_condition"),
        ({"duration_s": -1.0}, "duration_s"),
        ({"seed": -2}, "seed"),
    ],
)
def test_bad_settings_are_refused_before_any_simulation(changes, match):
    with pytest.raises(ValueError, match=match):
        FloorProtocol(**changes)


def test_generation_is_the_same_bytes_whatever_the_chunking(tmp_path):
    p = FloorProtocol(
        floors=("vinyl", "tarmac"), conditions=("spot",), trials_per_condition=1, duration_s=0.3
    )
    a = generate(p, tmp_path / "a.nc", workers=1, chunk_size=1)
    b = generate(p, tmp_path / "b.nc", workers=1, chunk_size=2)
    np.testing.assert_array_equal(a["signal"].values, b["signal"].values)
    assert a["signal"].shape == (2, 2, 600)
    assert list(a["floor"].values) == ["vinyl", "tarmac"]
    assert list(a["condition"].values) == ["spot", "spot"]
    assert a.attrs["protocol"] == "floor-texture" and a.attrs["sample_rate_hz"] == 2000.0
    assert 0.0 <= float(a["moving_fraction"][0]) <= 1.0
    # a different piece of floor under the same robot: different signals
    assert not np.array_equal(a["signal"].values[0], a["signal"].values[1])


def test_each_session_is_the_one_session_protocol_of_its_seed():
    kw = dict(floors=("vinyl", "tarmac"), conditions=("clockwise",), trials_per_condition=1)
    p = FloorProtocol(duration_s=0.2, seed=3, n_seeds=2, **kw)
    assert p.n_trials == 4 == len(p.trials()) and p.seeds == [3, 4]
    specs = p.trials()
    assert [(s.session, s.within, s.floor) for s in specs] == [
        (0, 0, "vinyl"),
        (0, 1, "tarmac"),
        (1, 0, "vinyl"),
        (1, 1, "tarmac"),
    ]
    second = p.simulate_trials([3])
    alone = FloorProtocol(duration_s=0.2, seed=4, **kw).simulate_trials([1])
    np.testing.assert_array_equal(second["signal"], alone["signal"])
    assert p.fingerprint() != FloorProtocol(duration_s=0.2, seed=3, **kw).fingerprint()
    ds = p.build_dataset(p.simulate_trials(range(4)))
    assert ds["seed"].values.tolist() == [3, 3, 4, 4]
    assert set(ds.coords) >= {"catches", "catch_fraction", "rail_fraction", "contact_force_n"}
    with pytest.raises(ValueError, match="n_seeds"):
        FloorProtocol(n_seeds=0)
