"""The floor presets of thesis 6.2: sources, sizes, the texture depth they are built to."""

from __future__ import annotations

import numpy as np
import pytest

from vibrissa.whisker.floors import FLOORS, floor_names, floor_spec, make_floor, texture_depth_mm


def test_the_four_floors_in_the_thesis_order_each_with_a_source():
    assert floor_names() == ["rough-carpet", "vinyl", "smooth-carpet", "tarmac"]
    for spec in FLOORS.values():
        assert len(spec.source) > 40
        assert spec.friction > 0 and spec.stiffness_n_m > 0


def test_unknown_floor_names_the_presets():
    with pytest.raises(ValueError, match="unknown floor texture 'shag'.*rough-carpet"):
        make_floor("shag")
    with pytest.raises(ValueError, match="unknown floor texture"):
        floor_spec("p80")


def test_tarmac_is_scaled_to_its_mean_texture_depth():
    s = make_floor("tarmac", seed=3)
    assert texture_depth_mm(s) == pytest.approx(FLOORS["tarmac"].relief_mm, rel=0.1)


def test_relief_orders_the_floors_as_a_hand_would():
    rms = {f: make_floor(f, seed=1).heights_m.std() for f in FLOORS}
    assert rms["rough-carpet"] > rms["smooth-carpet"] > rms["vinyl"]
    assert rms["tarmac"] > rms["smooth-carpet"]


def test_pile_tops_sit_at_the_relief_and_carpet_is_compliant():
    for name in ("rough-carpet", "smooth-carpet"):
        spec = FLOORS[name]
        h = make_floor(name, seed=0).heights_m * 1e3
        tops = np.percentile(h, 99.9)
        assert 0.75 * spec.relief_mm < tops < spec.relief_mm + 5 * spec.roughness_um * 1e-3
        assert spec.stiffness_n_m < FLOORS["vinyl"].stiffness_n_m / 10


def test_same_seed_same_floor_and_the_tile_size():
    a = make_floor("rough-carpet", seed=5, tile_u_mm=40.0, tile_w_mm=20.0)
    b = make_floor("rough-carpet", seed=5, tile_u_mm=40.0, tile_w_mm=20.0)
    np.testing.assert_array_equal(a.heights_m, b.heights_m)
    assert a.heights_m.shape == (400, 200)
    assert a.friction == FLOORS["rough-carpet"].friction
    c = make_floor("rough-carpet", seed=6, tile_u_mm=40.0, tile_w_mm=20.0)
    assert not np.array_equal(a.heights_m, c.heights_m)


def test_refuses_a_non_positive_size():
    with pytest.raises(ValueError, match="tile_u_mm"):
        make_floor("vinyl", tile_u_mm=0.0)
