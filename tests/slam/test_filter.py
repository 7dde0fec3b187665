"""The tactile SLAM particle filter: resampling, motion, evidence per mode, tracking."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vibrissa.robots.crunchbot.arena import PRESETS
from vibrissa.robots.crunchbot.synthetic import synthetic_log, texture_grid
from vibrissa.slam import filter as filter_module
from vibrissa.slam.collectors import Collector, Frames, PoseEstimates, Progress
from vibrissa.slam.filter import (
    MODES,
    ParticleFilter,
    SlamSettings,
    apply_motion,
    effective_sample_size,
    noisy_increment,
    run_slam,
    systematic_resample,
)
from vibrissa.slam.grid import occupancy
from vibrissa.slam.log import SensorLog, WhiskerLayout
from vibrissa.slam.mappers import MAPPERS, BlobMapper, Mapper, register_mapper

# two whiskers pointing straight ahead from the body's front, 0.1 m apart
LAYOUT = WhiskerLayout(
    base_m=np.array([[0.15, 0.05], [0.15, -0.05]]), angle_rad=np.zeros(2), length_m=np.full(2, 0.14)
)


def _log(
    states: list[str],
    contact: list[list[bool]],
    dist: list[list[float]],
    angle: list[float] | None = None,
    odometry: np.ndarray | None = None,
    **kw: object,
) -> SensorLog:
    n = len(states)
    return SensorLog(
        layout=LAYOUT,
        state=np.array(states),
        odometry=np.zeros((n, 3)) if odometry is None else odometry,
        contact=np.array(contact),
        radial_distance_m=np.array(dist),
        surface_angle_rad=np.full(n, np.nan) if angle is None else np.array(angle),
        start_pose=np.array([1.0, 1.0, 0.0]),
        **kw,
    )


def test_systematic_resampling_keeps_counts_within_one_of_n_times_the_weight() -> None:
    w = np.array([0.05, 0.4, 0.0, 0.35, 0.2])
    for seed in range(20):
        idx = systematic_resample(np.log(w + 1e-300), np.random.default_rng(seed))
        counts = np.bincount(idx, minlength=5)
        assert np.all(counts >= np.floor(5 * w)) and np.all(counts <= np.ceil(5 * w))
    uniform = systematic_resample(np.zeros(8), np.random.default_rng(0))
    np.testing.assert_array_equal(uniform, np.arange(8))
    a = systematic_resample(np.log(w + 1e-300), np.random.default_rng(3))
    np.testing.assert_array_equal(
        a, systematic_resample(np.log(w + 1e-300), np.random.default_rng(3))
    )


def test_effective_sample_size() -> None:
    assert effective_sample_size(np.zeros(10)) == pytest.approx(10)
    assert effective_sample_size(np.array([0.0, -np.inf, -np.inf])) == pytest.approx(1)


@pytest.mark.parametrize(
    ("kw", "words"),
    [
        ({"n_particles": 0}, "n_particles must be a positive integer"),
        ({"n_particles": -5}, "n_particles must be a positive integer"),
        ({"n_particles": 2.5}, "n_particles must be a positive integer"),
        ({"n_particles": True}, "n_particles must be a positive integer"),
        ({"n_cells": 0}, "n_cells must be a positive integer"),
        ({"mode": "lidar"}, "unknown mapping mode 'lidar'"),
        ({"contact_p": 0.3}, "contact_p must lie in"),
        ({"body_p": 0.0}, "body_p must lie strictly"),
        ({"odometry_error": -0.1}, "odometry_error must be non-negative"),
    ],
)
def test_bad_settings_are_refused(kw: dict, words: str) -> None:
    with pytest.raises(ValueError, match=words):
        SlamSettings(**kw)


def test_motion_composes_in_the_robot_frame_and_noise_scales_with_movement() -> None:
    pose = np.array([1.0, 2.0, math.pi / 2])
    np.testing.assert_allclose(
        apply_motion(pose, np.array([0.5, 0.1, 0.3])), [0.9, 2.5, math.pi / 2 + 0.3], atol=1e-12
    )
    rng = np.random.default_rng(0)
    exact = noisy_increment(np.array([0.2, 0.0, 0.0]), 3, 0.0, 0.0, rng)
    np.testing.assert_array_equal(exact, np.tile([0.2, 0.0, 0.0], (3, 1)))
    noisy = noisy_increment(np.array([0.2, 0.0, 1.0]), 20000, 0.1, 0.0, rng)
    assert noisy[:, 0].std() == pytest.approx(0.02, rel=0.05)
    assert noisy[:, 2].std() == pytest.approx(0.1, rel=0.05)


def test_the_sensor_log_checks_its_shapes() -> None:
    with pytest.raises(ValueError, match="contact must have shape"):
        _log(["FWD_1"], [[True]], [[0.1, np.nan]])
    with pytest.raises(ValueError, match="contact without a finite radial_distance_m"):
        _log(["FWD_1"], [[True, False]], [[np.nan, np.nan]])


def test_back_steps_move_the_particles_but_add_no_evidence() -> None:
    log = _log(
        ["BACK"] * 3,
        [[True, True]] * 3,
        [[0.1, 0.1]] * 3,
        odometry=np.tile([-0.025, 0.0, 0.0], (3, 1)),
    )
    run = run_slam(log, SlamSettings(n_particles=5, odometry_error=0.0, heading_drift_rad_m=0.0))
    assert not run.visited.any()
    np.testing.assert_allclose(run.pose_estimate[-1], [0.925, 1.0, 0.0], atol=1e-12)


def test_blob_mode_marks_each_contact_and_frees_the_body() -> None:
    log = _log(["FWD_1"], [[True, False]], [[0.1, np.nan]])
    run = run_slam(log, SlamSettings(n_particles=3, odometry_error=0.0))
    m = occupancy(run.logodds[0])
    # whisker 0: base (0.15, 0.05) + 0.1 m ahead, from the pose (1, 1, 0)
    hit = (int(1.25 / 0.05), int(1.05 / 0.05))
    assert m[hit] == pytest.approx(0.75, abs=0.02)
    assert m[20, 20] < 0.4  # under the body
    assert run.visited[0][hit]


def test_geometric_mode_lays_an_edge_through_two_contacts() -> None:
    # two whiskers touch a wall 0.1 m ahead, perpendicular to the heading (a wall along y)
    log = _log(["FWD_1", "HIT_1"], [[True, True]] * 2, [[0.1, 0.1]] * 2)
    run = run_slam(log, SlamSettings(n_particles=2, odometry_error=0.0, mode="geometric"))
    m = occupancy(run.logodds[0])
    x = int(1.25 / 0.05)
    assert m[x, int(1.25 / 0.05)] > 0.6  # 0.25 m along the wall: still an edge
    assert m[x + 4, 20] < 0.55  # 0.2 m beyond the wall, straight ahead: no edge


def test_template_mode_uses_the_reported_surface_angle() -> None:
    # one contact, the template says the surface runs along the robot's heading (angle 0)
    log = _log(["FWD_1", "HIT_2"], [[True, False]] * 2, [[0.1, np.nan]] * 2, angle=[np.nan, 0.0])
    run = run_slam(log, SlamSettings(n_particles=2, odometry_error=0.0, mode="template"))
    m = occupancy(run.logodds[0])
    y = int(1.05 / 0.05)
    assert m[int(1.5 / 0.05), y] > 0.6  # 0.25 m along the reported surface
    assert m[int(1.25 / 0.05), y + 5] < 0.55  # 0.25 m across it


def test_floor_texture_likelihoods_weigh_the_particles() -> None:
    floor_map = np.zeros((50, 50), dtype=np.int64)
    floor_map[25:] = 1  # texture 1 for x >= 1.25 m
    log = _log(
        ["FWD_1"],
        [[False, False]],
        [[np.nan, np.nan]],
        floor_loglik=np.log([[[0.1, 0.9]]]),
        floor_whisker_m=np.array([[0.0, 0.0]]),
        textures=("vinyl", "rough-carpet"),
    )
    pf = ParticleFilter(
        SlamSettings(n_particles=2, odometry_error=0.0),
        log.start_pose,
        np.random.default_rng(0),
        floor_map,
    )
    pf.poses = np.array([[1.0, 1.0, 0.0], [1.5, 1.0, 0.0]])
    pf.step(log, 0)
    assert pf.log_weights[1] - pf.log_weights[0] == pytest.approx(math.log(9))


def test_perfect_sensors_give_a_map_on_the_arenas_walls_and_obstacles() -> None:
    arena = PRESETS["slam"]
    log = synthetic_log(arena, 240.0, seed=0, odometry_error=0.0, heading_drift_rad_m=0.0)
    run = run_slam(log, SlamSettings(odometry_error=0.01, heading_drift_rad_m=0.01), seed=0)
    err = np.hypot(*(run.pose_estimate[:, :2] - log.true_pose[:, :2]).T)
    # the filter's own 1 % motion noise drifts a lone particle by a few cm over the run;
    # the filter must stay about as close (a wrong frame or sign would lose it by metres)
    assert err.mean() < 0.05 and err.max() < 0.1
    truth = arena.occupancy_grid()
    near = np.zeros_like(truth, dtype=bool)
    for dx in range(-2, 3):  # a blob's own cell and its neighbours (sigma = one cell)
        for dy in range(-2, 3):
            near |= np.roll(np.roll(truth > 0, dx, 0), dy, 1)
    occupied = run.best_map() > 0.6
    assert occupied.sum() > 20
    assert near[occupied].mean() > 0.9


def test_on_a_known_map_the_filter_localises_where_dead_reckoning_drifts() -> None:
    """10 % odometry error (6.5.3), exact contacts, the arena's map given: the median over
    three runs of the filter's mean position error is under half dead reckoning's (a run
    can still be lost when one turn's odometry is off by more than the particles spread)."""
    arena = PRESETS["slam"]
    prior = np.where(arena.occupancy_grid() > 0, 0.9, 0.1)
    filt, dead = [], []
    for seed in range(3):
        log = synthetic_log(arena, 360.0, seed=seed)
        run = run_slam(log, SlamSettings(), seed=seed, prior_map=prior)
        pose = log.start_pose.copy()
        path = [pose]
        for inc in log.odometry:
            pose = apply_motion(pose, inc)
            path.append(pose)
        dead.append(np.hypot(*(np.array(path)[:, :2] - log.true_pose[:, :2]).T).mean())
        filt.append(np.hypot(*(run.pose_estimate[:, :2] - log.true_pose[:, :2]).T).mean())
    assert np.median(filt) < 0.5 * np.median(dead)


def test_a_prior_map_must_be_probabilities_of_the_grid_shape() -> None:
    with pytest.raises(ValueError, match="prior_map must be"):
        ParticleFilter(
            SlamSettings(n_particles=2),
            np.zeros(3),
            np.random.default_rng(0),
            prior_map=np.full((3, 3), 0.5),
        )
    pf = ParticleFilter(
        SlamSettings(n_particles=2),
        np.zeros(3),
        np.random.default_rng(0),
        prior_map=np.full((50, 50), np.nan),
    )
    assert not pf.visited.any()


def test_same_seed_same_run() -> None:
    log = synthetic_log(PRESETS["slam"], 30.0, seed=4)
    a = run_slam(log, SlamSettings(n_particles=20), seed=1)
    b = run_slam(log, SlamSettings(n_particles=20), seed=1)
    np.testing.assert_array_equal(a.pose_estimate, b.pose_estimate)
    np.testing.assert_array_equal(a.logodds, b.logodds)


def test_known_floor_map_of_the_tiled_arena_matches_its_tiles() -> None:
    arena = PRESETS["tiles"]
    textures = ("rough-carpet", "smooth-carpet", "vinyl")
    g = texture_grid(arena, textures)
    assert g.shape == (50, 50) and g.min() == 0
    assert textures[g[15, 15]] == arena.tiles[1][1]


def test_a_log_cut_to_its_head_keeps_every_array_in_step() -> None:
    log = synthetic_log(PRESETS["tiles"], 20.0, seed=0)
    short = log.head(5)
    assert short.n_steps == 5 and short.true_pose.shape == (6, 3)
    assert short.floor_loglik.shape[0] == 5
    np.testing.assert_array_equal(short.contact, log.contact[:5])
    with pytest.raises(ValueError, match="n_steps must be an integer in 1.."):
        log.head(0)


def test_geometric_mode_lays_one_edge_per_episode_and_events_add_nothing() -> None:
    one = [[True, False], [True, True]]
    d = [[0.1, np.nan], [0.1, 0.1]]
    settings = SlamSettings(
        n_particles=2, odometry_error=0.0, heading_drift_rad_m=0.0, mode="geometric"
    )
    a = run_slam(_log(["FWD_1", "FWD_2"], one, d), settings)
    b = run_slam(
        _log(["FWD_1", "FWD_2", "HIT_2"], [*one, [True, True]], [*d, [0.1, 0.1]]), settings
    )
    np.testing.assert_array_equal(a.logodds, b.logodds)
    assert occupancy(a.logodds[0])[int(1.25 / 0.05), int(1.25 / 0.05)] > 0.6


def test_an_aborted_episode_leaves_a_blob_at_its_first_contact() -> None:
    log = _log(["FWD_1", "HIT_1", "FWD_2", "ABORT"], [[True, False]] * 4, [[0.1, np.nan]] * 4)
    for mode in ("geometric", "template"):
        run = run_slam(log, SlamSettings(n_particles=2, odometry_error=0.0, mode=mode))
        m = occupancy(run.logodds[0])
        hit = (int(1.25 / 0.05), int(1.05 / 0.05))
        assert m[hit] == pytest.approx(0.75, abs=0.02)
        assert m[hit[0], hit[1] + 5] == pytest.approx(0.5)  # no edge


# -- the filter as an iterator, collectors, registered mappers ---------------------------
class _Steps(Collector):
    """Records ``pf.t`` at every call."""

    name = "steps"

    def __init__(self) -> None:
        super().__init__()
        self.seen: list[int] = []

    def collect(self, pf: ParticleFilter) -> None:
        self.seen.append(pf.t)

    def result(self) -> list[int]:
        return self.seen


# one contact at the end of the log: an episode still open when the log ends
_OPEN = dict(states=["FWD_1", "HIT_1"], contact=[[True, False]] * 2, dist=[[0.1, np.nan]] * 2)
_HIT = (int(1.25 / 0.05), int(1.05 / 0.05))


def test_the_filter_iterates_one_step_per_next_and_collectors_see_every_frame() -> None:
    log = synthetic_log(PRESETS["slam"], 15.0, seed=5)
    settings = SlamSettings(n_particles=10, mode="geometric")
    steps, frames = _Steps(), Frames()
    pf = ParticleFilter(
        settings, log.start_pose, np.random.default_rng(3), log=log, collect=[steps, frames]
    )
    ess = list(pf)
    assert len(ess) == log.n_steps and pf.t == log.n_steps
    with pytest.raises(StopIteration):
        next(pf)
    assert steps.seen == list(range(log.n_steps + 1))  # the start, then after each step
    rec = frames.result()
    assert rec.particles.shape == (log.n_steps + 1, 10, 3) and rec.particles.dtype == np.float32
    assert rec.maps.shape == (log.n_steps + 1, 50, 50) and rec.maps.dtype == np.uint8
    run = run_slam(log, settings, seed=3)
    np.testing.assert_array_equal(ess, run.ess)
    np.testing.assert_array_equal(rec.estimate, run.pose_estimate)
    np.testing.assert_array_equal(pf.logodds, run.logodds)


def test_the_last_step_closes_an_open_episode_before_the_last_frame() -> None:
    log = _log(**_OPEN)
    settings = SlamSettings(n_particles=2, odometry_error=0.0, mode="geometric")
    by_hand = ParticleFilter(settings, log.start_pose, np.random.default_rng(0))
    for t in range(log.n_steps):
        by_hand.step(log, t)
    assert occupancy(by_hand.logodds[0])[_HIT] == pytest.approx(0.5)  # still pending
    run = run_slam(log, settings, collect=[Frames()])
    rec = run.collected["frames"]
    assert occupancy(run.logodds[0])[_HIT] == pytest.approx(0.75, abs=0.02)
    assert rec.maps[-1][_HIT] > 180 and rec.maps[-2][_HIT] == 128
    assert rec.maps.shape[0] == log.n_steps + 1


def test_run_slam_gives_every_collectors_result_by_name() -> None:
    log = _log(**_OPEN)
    calls: list[tuple[int, int]] = []
    run = run_slam(
        log,
        SlamSettings(n_particles=3),
        seed=1,
        collect=[
            PoseEstimates(),
            Progress(lambda d, n: calls.append((d, n))),
            Frames(name="viewer"),
        ],
    )
    assert set(run.collected) == {"pose_estimate", "progress", "viewer"}
    np.testing.assert_array_equal(run.collected["pose_estimate"], run.pose_estimate)
    assert calls == [(1, 3), (2, 3), (3, 3)] and run.collected["progress"] == 3
    with pytest.raises(ValueError, match="distinct names"):
        run_slam(log, collect=[Frames(), Frames()])


def test_a_filter_without_a_log_is_stepped_by_hand_and_cannot_be_iterated() -> None:
    pf = ParticleFilter(SlamSettings(n_particles=2), np.zeros(3), np.random.default_rng(0))
    with pytest.raises(TypeError, match="without a log cannot be iterated"):
        iter(pf)
    with pytest.raises(TypeError, match="without a log cannot be iterated"):
        next(pf)


def test_mapping_modes_are_the_registered_mappers(monkeypatch: pytest.MonkeyPatch) -> None:
    assert MODES == ("blob", "geometric", "template") == tuple(MAPPERS)
    for mode in MODES:
        pf = ParticleFilter(
            SlamSettings(n_particles=2, mode=mode), np.zeros(3), np.random.default_rng(0)
        )
        assert type(pf.mapper) is MAPPERS[mode] and pf.mapper.name == mode
    with pytest.raises(ValueError, match="already registered as 'blob'"):
        register_mapper(type("Other", (BlobMapper,), {}))
    with pytest.raises(ValueError, match="has no name"):
        register_mapper(type("Nameless", (Mapper,), {}))

    class Nothing(Mapper):
        name = "nothing"  # contacts add no evidence; the free whiskers and body still do

    monkeypatch.setitem(MAPPERS, "nothing", Nothing)
    with pytest.raises(ValueError, match="choose one of blob, geometric, template, nothing"):
        SlamSettings(mode="lidar")
    log = _log(["FWD_1"], [[True, False]], [[0.1, np.nan]])
    run = run_slam(log, SlamSettings(n_particles=2, odometry_error=0.0, mode="nothing"))
    blob = run_slam(log, SlamSettings(n_particles=2, odometry_error=0.0))
    assert occupancy(run.logodds[0])[_HIT] == pytest.approx(0.5)
    assert occupancy(blob.logodds[0])[_HIT] > 0.7
    np.testing.assert_array_equal(run.logodds[0, 20, 20], blob.logodds[0, 20, 20])


@pytest.mark.parametrize("n_points", [1, 5, 9])
def test_each_free_whisker_weighs_once_whatever_the_points_along_its_shaft(
    n_points: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(filter_module, "SHAFT_POINTS", n_points)
    prior = np.full((50, 50), 0.3)
    prior[22:] = 0.6  # x >= 1.1 m: the free whiskers of particle 0, facing +x
    settings = SlamSettings(n_particles=2, odometry_error=0.0, heading_drift_rad_m=0.0)
    pf = ParticleFilter(settings, np.zeros(3), np.random.default_rng(0), prior_map=prior)
    pf.poses = np.array([[1.0, 1.0, 0.0], [1.0, 1.0, math.pi]])  # the same body points
    pf.step(_log(["FWD_1"], [[False, False]], [[np.nan, np.nan]]), 0)
    f = settings.sensor_floor
    per_whisker = math.log(f + (1 - 2 * f) * 0.7) - math.log(f + (1 - 2 * f) * 0.4)
    assert pf.log_weights[1] - pf.log_weights[0] == pytest.approx(2 * per_whisker)
