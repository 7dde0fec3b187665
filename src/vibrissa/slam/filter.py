"""Tactile SLAM particle filter (thesis 6.5.3, 6.5.5): poses + per-particle occupancy grids.

Each of ``n_particles`` particles carries a continuous pose ``(x, y, heading)`` and a
``n_cells x n_cells`` log-odds grid (:mod:`vibrissa.slam.grid`); weights are kept as
log-weights. Each FSM step of a :class:`~vibrissa.slam.log.SensorLog`:

1. **motion**: every particle moves by the odometry increment with Gaussian noise of
   ``odometry_error`` times the movement (6.5.3: odometry accurate to about 10 %);
2. **weights** (not in ``BACK`` steps, which revisit places just seen, nor in the
   zero-length event steps ``HIT_1``, ``HIT_2``, ``ABORT``, which repeat the sensing of
   the step before them): each contact
   point is scored by the particle's occupancy there, each free whisker's shaft and the
   body by their emptiness, the floor whiskers' texture log-likelihoods by a known tile
   map if one is given; all with the grid as it was before this step;
3. **map** (same steps): negative evidence along free whiskers and under the body (eq.
   6.1) in every mode, and the mode's evidence, by the filter's mapper
   (:mod:`vibrissa.slam.mappers`, one class per mode registered in
   :data:`~vibrissa.slam.mappers.MAPPERS`): ``blob`` a blob at every contact;
   ``geometric`` one edge per contact episode (first contact to ``HIT_2``) through the
   first two whiskers' contacts; ``template`` one edge per episode at the surface angle
   the log reports (on ``HIT_2``); an episode ending (``ABORT``, ``BACK``, ``TURN``)
   without an edge leaves a blob at its first contact (6.5.5.2);
4. **resampling**, systematic, when the effective sample size falls below
   ``resample_fraction * n_particles``.

A filter built with a log is an iterator over it (the shape of ``particles``'
``SMC.__next__``): each ``next`` is one FSM step and returns its ESS; the last one also
closes a contact episode still open when the log ends. Collectors
(:mod:`vibrissa.slam.collectors`) record the state before the first step and after each
step; :func:`run_slam` runs the iterator to the end.

Everything is vectorised over particles with numpy; a step costs a few small array
operations per whisker.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.special import logsumexp

from vibrissa import _validate as v
from vibrissa.slam import grid
from vibrissa.slam.collectors import Collector, PoseEstimates
from vibrissa.slam.log import SensorLog, WhiskerLayout
from vibrissa.slam.mappers import MAPPERS, MODES, Mapper

__all__ = [
    "MODES",
    "SHAFT_POINTS",
    "ParticleFilter",
    "SlamRun",
    "SlamSettings",
    "apply_motion",
    "effective_sample_size",
    "noisy_increment",
    "run_slam",
    "systematic_resample",
    "to_world",
]

SHAFT_POINTS = 5
"""Points sampled along each free whisker's shaft to weigh its emptiness; the weighting
divides by it so that each free whisker counts as one mean over its points."""
_NO_EVIDENCE = ("BACK",)
_EVENTS = ("HIT_1", "HIT_2", "ABORT")
_EPISODE_END = ("ABORT", "BACK", "TURN")


@dataclass(frozen=True)
class SlamSettings:
    """The filter's numbers (thesis 6.5.3 and 6.5.5 where it gives them, else ours).

    ``contact_p``, ``free_whisker_p``, ``body_p`` and ``edge_p`` are the peak likelihoods
    ``Delta[x_c, y_c]`` (the thesis: a constant > 0.5 at contacts, < 0.5 for free
    whiskers and the body). ``blob_sigma_m`` = one cell: a blob 'affects a radius of
    about two pixels'. ``sigma_r_m`` and ``sigma_theta_rad`` are eq. 6.2's.
    ``heading_drift_rad_m`` adds heading noise per metre driven straight (ours).
    ``sensor_floor`` keeps every point likelihood in ``[sensor_floor, 1 - sensor_floor]``
    so that one wrong contact cannot wipe out a particle. ``mode`` names a mapper of
    :data:`~vibrissa.slam.mappers.MAPPERS`.
    """

    n_particles: int = 100
    n_cells: int = 50
    cell_m: float = 0.05
    mode: str = "blob"
    odometry_error: float = 0.1
    heading_drift_rad_m: float = 0.1
    contact_p: float = 0.75
    edge_p: float = 0.75
    free_whisker_p: float = 0.4
    body_p: float = 0.35
    blob_sigma_m: float = 0.05
    free_sigma_m: float = 0.035
    body_sigma_m: float = 0.085
    sigma_r_m: float = 0.25
    sigma_theta_rad: float = math.pi / 12
    sensor_floor: float = 0.05
    resample_fraction: float = 0.5
    logodds_limit: float = 10.0

    def __post_init__(self) -> None:
        for name in ("n_particles", "n_cells"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int | np.integer) or value <= 0:
                raise ValueError(f"{name} must be a positive integer, got {value!r}")
        if self.mode not in MAPPERS:
            raise ValueError(
                f"unknown mapping mode {self.mode!r}; choose one of {', '.join(MAPPERS)}"
            )
        for name in (
            "cell_m",
            "blob_sigma_m",
            "free_sigma_m",
            "body_sigma_m",
            "sigma_r_m",
            "sigma_theta_rad",
            "logodds_limit",
        ):
            v.positive(name, getattr(self, name))
        for name in ("odometry_error", "heading_drift_rad_m"):
            v.non_negative(name, getattr(self, name))
        for name in ("contact_p", "edge_p"):
            v.in_range(name, getattr(self, name), 0.5, 1.0)
        for name in ("free_whisker_p", "body_p"):
            v.in_range(name, getattr(self, name), 0.0, 0.5)
        for name in ("contact_p", "edge_p", "free_whisker_p", "body_p"):
            if getattr(self, name) in (0.0, 1.0):
                raise ValueError(f"{name} must lie strictly between 0 and 1")
        v.in_range("sensor_floor", self.sensor_floor, 0.0, 0.49)
        v.in_range("resample_fraction", self.resample_fraction, 0.0, 1.0)

    @property
    def map_size_m(self) -> float:
        """The map's side in metres."""
        return self.n_cells * self.cell_m


def systematic_resample(log_weights: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Indices drawn by systematic resampling (Kitagawa 1996; Doucet & Johansen 2009).

    One uniform offset ``u ~ U[0, 1/N)`` and the points ``u + k/N`` read through the
    cumulative normalised weights. Written here rather than taken from ``filterpy`` or
    ``particles`` because both draw from numpy's global random state (no ``Generator``,
    so a run could not be reproduced from its seed), and ``particles`` pins ``numpy<2``.
    """
    lw = np.asarray(log_weights, float)
    n = lw.size
    w = np.exp(lw - logsumexp(lw))
    cdf = np.cumsum(w)
    cdf[-1] = 1.0
    positions = (rng.random() + np.arange(n)) / n
    return np.searchsorted(cdf, positions, side="right").clip(max=n - 1)


def effective_sample_size(log_weights: np.ndarray) -> float:
    """``1 / sum(w^2)`` of the normalised weights."""
    lw = np.asarray(log_weights, float)
    return float(np.exp(-logsumexp(2 * (lw - logsumexp(lw)))))


def to_world(poses: np.ndarray, points_robot: np.ndarray) -> np.ndarray:
    """Robot-frame points ``(k, 2)`` seen from every pose ``(P, 3)``: ``(P, k, 2)``."""
    c, s = np.cos(poses[:, 2])[:, None], np.sin(poses[:, 2])[:, None]
    px, py = points_robot[None, :, 0], points_robot[None, :, 1]
    return np.stack(
        [poses[:, 0, None] + c * px - s * py, poses[:, 1, None] + s * px + c * py], axis=-1
    )


def apply_motion(poses: np.ndarray, increment: np.ndarray) -> np.ndarray:
    """Compose poses ``(..., 3)`` with robot-frame increments ``(forward, left, rotation)``.

    The translation happens in the frame of the pose at the step's start.
    """
    c, s = np.cos(poses[..., 2]), np.sin(poses[..., 2])
    dx, dy, da = increment[..., 0], increment[..., 1], increment[..., 2]
    return np.stack(
        [poses[..., 0] + c * dx - s * dy, poses[..., 1] + s * dx + c * dy, poses[..., 2] + da],
        axis=-1,
    )


def noisy_increment(
    increment: np.ndarray, n: int, error: float, drift_rad_m: float, rng: np.random.Generator
) -> np.ndarray:
    """``n`` noisy copies ``(n, 3)`` of one odometry increment (error times the movement)."""
    inc = np.asarray(increment, float)
    dist = math.hypot(inc[0], inc[1])
    z = rng.standard_normal((n, 3))
    out = np.empty((n, 3))
    out[:, 0] = inc[0] + error * abs(inc[0]) * z[:, 0]
    out[:, 1] = inc[1] + error * abs(inc[1]) * z[:, 1]
    out[:, 2] = inc[2] + (error * abs(inc[2]) + drift_rad_m * dist) * z[:, 2]
    return out


@dataclass
class SlamRun:
    """The outcome of :func:`run_slam`.

    Attributes
    ----------
    pose_estimate
        ``(n_steps + 1, 3)`` weighted mean pose before each step and after the last.
    logodds, visited
        ``(n_particles, n, n)`` final grids.
    log_weights
        ``(n_particles,)`` final normalised log-weights.
    ess
        ``(n_steps,)`` effective sample size after each step's weighting.
    n_resamples
        How often the particles were resampled.
    collected
        Collector name -> :meth:`Collector.result() <vibrissa.slam.collectors.Collector.result>`
        of the collectors given to :func:`run_slam` in ``collect``.
    """

    pose_estimate: np.ndarray
    logodds: np.ndarray
    visited: np.ndarray
    log_weights: np.ndarray
    ess: np.ndarray
    n_resamples: int
    collected: dict[str, Any] = field(default_factory=dict)

    def best_map(self, unexplored: float = 0.3) -> np.ndarray:
        """The most probable particle's occupancy grid, ``unexplored`` where it saw nothing."""
        k = int(np.argmax(self.log_weights))
        return np.where(self.visited[k], grid.occupancy(self.logodds[k]), unexplored)


def _weighted_pose(poses: np.ndarray, log_weights: np.ndarray) -> np.ndarray:
    w = np.exp(log_weights - logsumexp(log_weights))
    heading = math.atan2(float(w @ np.sin(poses[:, 2])), float(w @ np.cos(poses[:, 2])))
    return np.array([w @ poses[:, 0], w @ poses[:, 1], heading])


class ParticleFilter:
    """Tactile SLAM over a sensor log; see the module's docstring for one step.

    Built with ``log``, the filter is an iterator over it: each ``next(pf)`` runs the next
    FSM step (:meth:`step`) and returns its ESS; the last one (step ``n_steps - 1``) then
    closes a contact episode still open (its pending first contact becomes a blob, as at
    an ``ABORT``); the next raises :class:`StopIteration`, so iterating yields exactly
    ``log.n_steps`` values. The collectors are called on the state before the first step
    (at the first ``next``) and after each step, the last call after the closing:
    ``n_steps + 1`` calls.

    Parameters
    ----------
    settings
        :class:`SlamSettings`.
    start_pose
        ``(3,)`` the known start in the map frame; every particle starts there.
    rng
        The filter's random stream (motion noise, resampling).
    floor_map
        Optional ``(n_cells, n_cells)`` texture index per cell (``-1`` unknown) used to
        weigh the floor whiskers' texture log-likelihoods.
    prior_map
        Optional ``(n_cells, n_cells)`` occupancy probabilities every particle starts
        from (NaN: unexplored): localisation on a known map, or a map from an earlier run.
    log
        The sensor log to iterate over; without one the filter is stepped by hand
        (:meth:`step`) and cannot be iterated.
    collect
        :class:`~vibrissa.slam.collectors.Collector` instances called while iterating.

    Attributes
    ----------
    s
        The settings.
    poses, log_weights
        ``(n_particles, 3)`` poses and ``(n_particles,)`` normalised log-weights.
    logodds, visited
        ``(n_particles, n_cells, n_cells)`` log-odds grids and where each particle has
        seen anything.
    mapper
        The :class:`~vibrissa.slam.mappers.Mapper` of ``settings.mode``.
    log, collectors
        As given.
    t
        Steps the iterator has run.
    n_resamples
        How often the particles were resampled.
    """

    def __init__(
        self,
        settings: SlamSettings,
        start_pose: np.ndarray,
        rng: np.random.Generator,
        floor_map: np.ndarray | None = None,
        prior_map: np.ndarray | None = None,
        *,
        log: SensorLog | None = None,
        collect: Sequence[Collector] = (),
    ) -> None:
        s = settings
        self.s = s
        self.rng = rng
        self.poses = np.tile(v.finite_array("start_pose", start_pose), (s.n_particles, 1))
        self.log_weights = np.full(s.n_particles, -math.log(s.n_particles))
        self.logodds = np.zeros((s.n_particles, s.n_cells, s.n_cells))
        self.visited = np.zeros(self.logodds.shape, dtype=bool)
        if prior_map is not None:
            prior = np.asarray(prior_map, float)
            if prior.shape != (s.n_cells, s.n_cells) or np.any((prior < 0) | (prior > 1)):
                raise ValueError(
                    f"prior_map must be {(s.n_cells, s.n_cells)} probabilities "
                    "in [0, 1] (NaN: unexplored)"
                )
            known = np.isfinite(prior)
            lim = s.logodds_limit
            self.logodds[:] = np.where(
                known,
                np.clip(
                    grid.logit(np.clip(np.nan_to_num(prior, nan=0.5), 1e-9, 1 - 1e-9)), -lim, lim
                ),
                0.0,
            )
            self.visited[:] = known
        if floor_map is not None and np.shape(floor_map) != (s.n_cells, s.n_cells):
            raise ValueError(f"floor_map must have shape {(s.n_cells, s.n_cells)}")
        self.floor_map = None if floor_map is None else np.asarray(floor_map, np.int64)
        self.mapper: Mapper = MAPPERS[s.mode]()
        self.n_resamples = 0
        self.log = log
        self.collectors: tuple[Collector, ...] = tuple(collect)
        self.t = 0
        self._started = False

    # -- iteration ----------------------------------------------------------------------
    def __iter__(self) -> ParticleFilter:
        self._iterated_log()
        return self

    def __next__(self) -> float:
        """Run the next step of the log (see the class's docstring); its ESS.

        Raises
        ------
        StopIteration
            Every step of the log has run.
        """
        log = self._iterated_log()
        if not self._started:
            self._started = True
            self._collect()
        if self.t >= log.n_steps:
            raise StopIteration
        ess = self.step(log, self.t)
        self.t += 1
        if self.t == log.n_steps:
            self.mapper.on_episode_end(self)  # the log ends: close an open episode
        self._collect()
        return ess

    def _iterated_log(self) -> SensorLog:
        if self.log is None:
            raise TypeError(
                "a ParticleFilter built without a log cannot be iterated; "
                "pass log=... or call step(log, t)"
            )
        return self.log

    def _collect(self) -> None:
        for c in self.collectors:
            c.collect(self)

    # -- evidence -------------------------------------------------------------------
    def _point_loglik(self, points: np.ndarray, occupied: bool) -> np.ndarray:
        p = grid.occupancy_at(self.logodds, points, self.s.cell_m)
        q = p if occupied else 1.0 - p
        f = self.s.sensor_floor
        return np.log(f + (1 - 2 * f) * q)

    def _weigh(self, log: SensorLog, t: int, hit_world: np.ndarray, free_world: np.ndarray) -> None:
        lw = np.zeros(self.s.n_particles)
        if hit_world.shape[1]:
            lw += self._point_loglik(hit_world, True).sum(axis=1)
        if free_world.shape[1]:
            # the mean over a free whisker's SHAFT_POINTS points, summed over free whiskers
            lw += (
                self._point_loglik(free_world, False).mean(axis=1)
                * free_world.shape[1]
                / SHAFT_POINTS
            )
        body = to_world(self.poses, _body_points(log.layout.body_radius_m))
        lw += self._point_loglik(body, False).mean(axis=1)
        floor_map, floor_loglik = self.floor_map, log.floor_loglik
        if floor_map is not None and floor_loglik is not None:
            lw += self._floor_loglik(log, floor_map, floor_loglik[t])
        self.log_weights = self.log_weights + lw
        self.log_weights -= logsumexp(self.log_weights)

    def _floor_loglik(
        self, log: SensorLog, floor_map: np.ndarray, floor_loglik_t: np.ndarray
    ) -> np.ndarray:
        # floor_map: self.floor_map; floor_loglik_t: the step's row of log.floor_loglik
        pts = to_world(self.poses, np.asarray(log.floor_whisker_m, float))
        c = grid.cell_of(pts, self.s.cell_m)
        n = self.s.n_cells
        inside = np.all((c >= 0) & (c < n), axis=-1)
        c = np.where(inside[..., None], c, 0)
        tex = np.where(inside, floor_map[c[..., 0], c[..., 1]], -1)
        ll = np.asarray(floor_loglik_t, float)  # (F, K)
        known = tex >= 0
        f_idx = np.broadcast_to(np.arange(ll.shape[0])[None, :], tex.shape)
        uninformed = logsumexp(ll, axis=1) - math.log(ll.shape[1])  # mean likelihood
        out = np.where(known, ll[f_idx, np.where(known, tex, 0)], uninformed[f_idx])
        return out.sum(axis=1)

    def _negative_evidence(self, log: SensorLog, free: np.ndarray) -> None:
        s = self.s
        lay = log.layout
        mid = lay.points(np.asarray(lay.length_m) / 2)[free]
        for w in range(mid.shape[0]):
            grid.add_blob(
                self.logodds,
                self.visited,
                to_world(self.poses, mid[w : w + 1])[:, 0],
                s.free_whisker_p,
                s.free_sigma_m,
                s.cell_m,
                limit=s.logodds_limit,
            )
        grid.add_blob(
            self.logodds,
            self.visited,
            self.poses[:, :2],
            s.body_p,
            s.body_sigma_m,
            s.cell_m,
            radius_cells=int(np.ceil(2 * lay.body_radius_m / s.cell_m)),
            limit=s.logodds_limit,
        )

    # -- one step ---------------------------------------------------------------------
    def step(self, log: SensorLog, t: int) -> float:
        """Advance over step ``t`` of ``log``; returns the ESS after weighting.

        This does not advance the iterator (:attr:`t`) nor call the collectors, and it
        never closes an episode at the log's end; iterate the filter for that.
        """
        s = self.s
        inc = noisy_increment(
            log.odometry[t], s.n_particles, s.odometry_error, s.heading_drift_rad_m, self.rng
        )
        self.poses = apply_motion(self.poses, inc)
        state = str(log.state[t])
        if state not in _NO_EVIDENCE:
            contact = np.asarray(log.contact[t], bool)
            lay = log.layout
            hit_idx = np.flatnonzero(contact)
            hit_world = to_world(
                self.poses, lay.points(np.asarray(log.radial_distance_m[t]))[hit_idx]
            )
            if state not in _EVENTS:
                free_world = to_world(self.poses, _shaft_points(lay)[~contact].reshape(-1, 2))
                self._weigh(log, t, hit_world, free_world)
                self._negative_evidence(log, ~contact)
                self.mapper.on_sensing(self, hit_world)
            self.mapper.on_evidence(self, log, t, hit_idx, hit_world)
        if state in _EPISODE_END:
            self.mapper.on_episode_end(self)
        ess = effective_sample_size(self.log_weights)
        if ess < s.resample_fraction * s.n_particles:
            self._resample()
        return ess

    def _resample(self) -> None:
        idx = systematic_resample(self.log_weights, self.rng)
        self.poses = self.poses[idx]
        self.logodds = self.logodds[idx]
        self.visited = self.visited[idx]
        self.mapper.on_resample(idx)
        self.log_weights = np.full(self.s.n_particles, -math.log(self.s.n_particles))
        self.n_resamples += 1

    def pose_estimate(self) -> np.ndarray:
        """The weighted mean pose (circular mean heading)."""
        return _weighted_pose(self.poses, self.log_weights)


def _shaft_points(layout: WhiskerLayout) -> np.ndarray:
    """``(n_whiskers, SHAFT_POINTS, 2)`` robot-frame points spread along each whisker's shaft."""
    n = SHAFT_POINTS
    frac = (np.arange(n) + 0.5) / n
    return np.stack([layout.points(np.asarray(layout.length_m) * f) for f in frac], axis=1)


def _body_points(radius_m: float) -> np.ndarray:
    """Robot-frame points covering the body: its centre and a ring at half its radius."""
    a = np.arange(6) * math.pi / 3
    ring = 0.5 * radius_m * np.stack([np.cos(a), np.sin(a)], axis=1)
    return np.vstack([[0.0, 0.0], ring])


def run_slam(
    log: SensorLog,
    settings: SlamSettings | None = None,
    seed: int = 0,
    floor_map: np.ndarray | None = None,
    prior_map: np.ndarray | None = None,
    *,
    collect: Sequence[Collector] = (),
) -> SlamRun:
    """Run the particle filter over a whole sensor log (iterate it to the end).

    Parameters
    ----------
    log
        The run's observations.
    settings
        :class:`SlamSettings` (mode, particle count, ...); default the thesis' blob mode.
    seed
        Seeds the filter's own random stream.
    floor_map
        Optional known texture map (indices into ``log.textures``, ``-1`` unknown).
    prior_map
        Optional occupancy every particle starts from (:class:`ParticleFilter`).
    collect
        :class:`~vibrissa.slam.collectors.Collector` instances with distinct names, called
        on the state before the first step and after each step (``log.n_steps + 1``
        calls, the last after closing an open episode); their results are in
        :attr:`SlamRun.collected` by name.

    Returns
    -------
    SlamRun
        The final particles' grids and weights, the pose estimate of every frame, the ESS
        of every step and the collectors' results.

    Raises
    ------
    ValueError
        Two collectors share a name.
    """
    names = [c.name for c in collect]
    if len(set(names)) != len(names):
        raise ValueError(f"collectors must have distinct names, got {names}")
    s = settings or SlamSettings()
    est = PoseEstimates()
    pf = ParticleFilter(
        s,
        log.start_pose,
        np.random.default_rng(seed),
        floor_map,
        prior_map,
        log=log,
        collect=[est, *collect],
    )
    ess = np.fromiter(pf, dtype=float)
    return SlamRun(
        est.result(),
        pf.logodds,
        pf.visited,
        pf.log_weights,
        ess,
        pf.n_resamples,
        {c.name: c.result() for c in collect},
    )
