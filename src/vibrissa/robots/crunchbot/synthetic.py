"""An exact whisker-contact oracle and a synthetic CrunchBot run (no whisker physics).

Each obstacle whisker is a rigid ray of fixed length from its base on the robot; it
touches where the ray first crosses a wall or obstacle edge of the arena, at exactly that
radial distance. The robot runs the 6.5.3 FSM
(:mod:`vibrissa.robots.crunchbot.fsm`) on these contacts, moving in sub-steps so it
stops early when a whisker's strain passes the limit or its body would hit something; the
odometry it reports is the true movement plus the same relative error the filter assumes.
Floor whiskers report a fixed likelihood for the true tile texture. The result is a
:class:`~vibrissa.slam.log.SensorLog` with perfect sensors, for tests and benchmarks; the
simulated robot with real whiskers will write the same log. :func:`synthetic_record`
wraps it in a :class:`~vibrissa.robots.crunchbot.record.RunRecord` with made-up
(synthetic) Hall signals, for fast tests and the viewer.
"""

from __future__ import annotations

import math

import numpy as np

from vibrissa import _validate as v
from vibrissa.robots.crunchbot import fsm
from vibrissa.robots.crunchbot.arena import ROBOT_RADIUS_M, Arena
from vibrissa.robots.crunchbot.record import N_OBSTACLE_WHISKERS, RunRecord
from vibrissa.slam.filter import apply_motion, noisy_increment
from vibrissa.slam.log import SensorLog, WhiskerLayout


def front_array_layout(
    pitch_m: float, splay_rad: float, radius_m: float = 0.15, length_m: float = 0.14
) -> WhiskerLayout:
    """Four forward whiskers side by side on the Create's front edge.

    The bases sit on the front arc of radius ``radius_m`` at lateral offsets
    ``-3/2, -1/2, 1/2, 3/2`` times ``pitch_m`` (right to left); the outer two point
    ``splay_rad`` outward from straight ahead, the inner two a third of that.

    Parameters
    ----------
    pitch_m
        Distance between neighbouring bases across the robot (m).
    splay_rad
        Direction of the outer whiskers from straight ahead (rad, >= 0).
    radius_m
        The arc the bases sit on (m, the body's front edge less the follicle housing).
    length_m
        Each whisker's length outside the follicle (m).
    """
    v.positive("pitch_m", pitch_m)
    v.non_negative("splay_rad", splay_rad)
    v.positive("radius_m", radius_m)
    v.positive("length_m", length_m)
    y = pitch_m * np.array([-1.5, -0.5, 0.5, 1.5])
    if np.abs(y).max() >= radius_m:
        raise ValueError(f"pitch_m {pitch_m} puts the outer bases off the {radius_m} m front arc")
    return WhiskerLayout(
        base_m=np.stack([np.sqrt(radius_m**2 - y**2), y], axis=1),
        angle_rad=splay_rad * np.array([-1.0, -1.0 / 3.0, 1.0 / 3.0, 1.0]),
        length_m=np.full(4, length_m),
        body_radius_m=ROBOT_RADIUS_M,
    )


#: Pitch of the four obstacle whiskers (m) and splay of the outer two (rad): the thesis
#: gives no layout; identified from its stated outcome that FWD_2 ends in HIT_2 and only
#: "in some cases" in ABORT (6.5.5.2) as the widest layout at which every run does so
#: (``scripts/identify_crunchbot_layout.py``, ``docs/runs/identify_crunchbot_layout.json``).
#: Side by side at 30 mm, whisker units about as wide as their follicle housings.
CRUNCHBOT_PITCH_M = 0.03
CRUNCHBOT_SPLAY_RAD = 0.3
#: Four forward whiskers on the Create's front edge (:func:`front_array_layout`; RC25
#: whiskers are 160 mm long, 140 mm outside the follicle, 6.5.4).
CRUNCHBOT_LAYOUT = front_array_layout(CRUNCHBOT_PITCH_M, CRUNCHBOT_SPLAY_RAD)
#: Where the two outer, downward whiskers brush the floor (robot frame; ours).
FLOOR_WHISKERS_M = np.array([[0.12, 0.16], [0.12, -0.16]])


def cast_rays(
    segments: np.ndarray, origins: np.ndarray, directions: np.ndarray, length: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """First crossing of each ray with any segment, within its length.

    Parameters
    ----------
    segments
        ``(S, 4)`` rows ``(x0, y0, x1, y1)``.
    origins, directions
        ``(W, 2)`` ray starts and unit directions.
    length
        ``(W,)`` ray lengths.

    Returns
    -------
    distance, segment
        ``(W,)`` distance to the first crossing (``inf`` if none) and the segment's row
        (``-1`` if none).
    """
    p = origins[:, None, :]
    r = directions[:, None, :] * np.asarray(length, float)[:, None, None]
    q = segments[None, :, :2]
    s = segments[None, :, 2:] - q
    denom = r[..., 0] * s[..., 1] - r[..., 1] * s[..., 0]
    qp = q - p
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (qp[..., 0] * s[..., 1] - qp[..., 1] * s[..., 0]) / denom
        u = (qp[..., 0] * r[..., 1] - qp[..., 1] * r[..., 0]) / denom
    hit = (denom != 0) & (t >= 0) & (t <= 1) & (u >= 0) & (u <= 1)
    t = np.where(hit, t, np.inf)
    seg = np.argmin(t, axis=1)
    best = t[np.arange(len(t)), seg]
    found = np.isfinite(best)
    return np.where(found, best * length, np.inf), np.where(found, seg, -1)


def whisker_contacts(
    arena: Arena, pose: np.ndarray, layout: WhiskerLayout = CRUNCHBOT_LAYOUT
) -> tuple[np.ndarray, np.ndarray]:
    """Radial distance of each whisker's contact at an arena-frame pose (``inf``: none).

    Also the touched segment of :meth:`Arena.segments` (``-1``: none).
    """
    base = apply_motion(np.asarray(pose, float), np.c_[layout.base_m, np.zeros(layout.n_whiskers)])[
        :, :2
    ]
    ang = pose[2] + np.asarray(layout.angle_rad, float)
    d = np.stack([np.cos(ang), np.sin(ang)], axis=1)
    return cast_rays(arena.segments(), base, d, np.asarray(layout.length_m, float))


def body_collides(arena: Arena, pose: np.ndarray, radius_m: float) -> bool:
    """Whether the body disc leaves the arena or overlaps an obstacle."""
    x, y = float(pose[0]), float(pose[1])
    if not (radius_m <= x <= arena.size_m - radius_m and radius_m <= y <= arena.size_m - radius_m):
        return True
    for ob in arena.obstacles:
        x0, y0, x1, y1 = ob.bounds()
        dx = x - min(max(x, x0), x1)
        dy = y - min(max(y, y0), y1)
        if dx * dx + dy * dy < radius_m * radius_m:
            return True
    return False


def texture_grid(
    arena: Arena, textures: tuple[str, ...], cell_m: float = 0.05, map_size_m: float = 2.5
) -> np.ndarray:
    """The arena's tiles as a map-frame grid of indices into ``textures`` (-1: none)."""
    n = int(round(map_size_m / cell_m))
    c = (np.arange(n) + 0.5) * cell_m - arena.map_offset_m(map_size_m, cell_m)
    x, y = np.meshgrid(c, c, indexing="ij")
    names = arena.texture_at(x, y)
    lookup = {t: i for i, t in enumerate(textures)}
    return np.vectorize(lambda s: lookup.get(s, -1), otypes=[np.int64])(names)


def _strain(distance: np.ndarray, layout: WhiskerLayout) -> np.ndarray:
    """Stand-in strain (fraction of full scale): 0 at a tip contact, 1 at half the length."""
    length = np.asarray(layout.length_m, float)
    return np.where(np.isfinite(distance), 2 * (length - distance) / length, 0.0)


def synthetic_log(
    arena: Arena,
    seconds: float = 360.0,
    seed: int = 0,
    layout: WhiskerLayout = CRUNCHBOT_LAYOUT,
    odometry_error: float = 0.1,
    heading_drift_rad_m: float = 0.1,
    settings: fsm.FsmSettings | None = None,
    map_size_m: float = 2.5,
    cell_m: float = 0.05,
    substeps: int = 10,
    floor_likelihood: float = 0.8,
) -> SensorLog:
    """Drive the FSM in ``arena`` for ``seconds`` of robot time with exact sensors.

    Returns a :class:`SensorLog` in the map frame (the arena centred in a ``map_size_m``
    map) with ``true_pose``. The template angle (``surface_angle_rad``) is given on
    ``HIT_2`` rows: the exact angle, in the robot's frame, of the edge the episode's
    first contact touched.
    """
    v.positive("seconds", seconds)
    v.non_negative("odometry_error", odometry_error)
    v.in_range("floor_likelihood", floor_likelihood, 0.0, 1.0)
    s = settings or fsm.FsmSettings()
    rng = np.random.default_rng(seed)
    segs = arena.segments()
    textures = tuple(sorted({t for row in arena.tiles for t in row}))
    pose = arena.start.as_array()
    state = fsm.FsmState(fsm.FWD_1)
    command = fsm.command_for(fsm.FWD_1, s, rng)
    rows: dict[str, list] = {
        k: [] for k in ("state", "odo", "contact", "dist", "angle", "floor", "pose")
    }
    first_segment = -1
    elapsed = 0.0
    while elapsed < seconds:
        start = pose.copy()
        dist, seg = whisker_contacts(arena, pose, layout)
        peak = _strain(dist, layout)
        bumped = False
        if command.duration_s > 0:
            dt = command.duration_s / substeps
            for _ in range(substeps):
                nxt = apply_motion(
                    pose, np.array([command.linear_m_s * dt, 0.0, command.angular_rad_s * dt])
                )
                if body_collides(arena, nxt, layout.body_radius_m):
                    bumped = True
                    break
                pose = nxt
                dist, seg = whisker_contacts(arena, pose, layout)
                peak = np.maximum(peak, _strain(dist, layout))
                watched = command.linear_m_s > 0 or (state.name == fsm.TURN and s.monitor_turn)
                if watched and peak.max() > s.strain_limit:
                    break
        elapsed += command.duration_s
        touching = np.isfinite(dist)
        c, sn = math.cos(start[2]), math.sin(start[2])
        dx, dy = pose[0] - start[0], pose[1] - start[1]
        true_inc = np.array(
            [c * dx + sn * dy, -sn * dx + c * dy, math.remainder(pose[2] - start[2], math.tau)]
        )
        odo = noisy_increment(true_inc, 1, odometry_error, heading_drift_rad_m, rng)[0]
        if state.name == fsm.FWD_1 and touching.any():
            first_segment = int(seg[np.flatnonzero(touching)[0]])
        angle = math.nan
        if state.name == fsm.HIT_2 and first_segment >= 0:
            x0, y0, x1, y1 = segs[first_segment]
            angle = math.remainder(math.atan2(y1 - y0, x1 - x0) - pose[2], math.pi)
        rows["state"].append(state.name)
        rows["odo"].append(odo)
        rows["contact"].append(touching)
        rows["dist"].append(np.where(touching, dist, np.nan))
        rows["angle"].append(angle)
        rows["pose"].append(start)
        if textures:
            fl = apply_motion(pose, np.c_[FLOOR_WHISKERS_M, np.zeros(len(FLOOR_WHISKERS_M))])
            names = arena.texture_at(fl[:, 0], fl[:, 1])
            other = (1 - floor_likelihood) / max(len(textures) - 1, 1)
            rows["floor"].append(
                np.log([[floor_likelihood if t == n else other for t in textures] for n in names])
            )
        obs = fsm.Observation(
            tuple(bool(x) for x in touching), tuple(float(x) for x in peak), bumped
        )
        state, command = fsm.transition(state, obs, rng, s)
    offset = arena.map_offset_m(map_size_m, cell_m)
    shift = np.array([offset, offset, 0.0])
    true_pose = np.vstack([*rows["pose"], pose]) + shift
    return SensorLog(
        layout=layout,
        state=np.array(rows["state"]),
        odometry=np.array(rows["odo"]),
        contact=np.array(rows["contact"]),
        radial_distance_m=np.array(rows["dist"]),
        surface_angle_rad=np.array(rows["angle"]),
        start_pose=true_pose[0].copy(),
        floor_loglik=np.array(rows["floor"]) if textures else None,
        floor_whisker_m=FLOOR_WHISKERS_M if textures else None,
        textures=textures,
        true_pose=true_pose,
    )


def _step_durations(log: SensorLog, settings: fsm.FsmSettings) -> np.ndarray:
    """Robot time of each step of a synthetic log.

    FWD/BACK take one step, TURN its rotation at the turn rate, the HIT/ABORT events none.
    """
    state = np.asarray(log.state)
    dur = np.where(np.isin(state, (fsm.FWD_1, fsm.FWD_2, fsm.BACK)), settings.step_s, 0.0)
    turn = np.abs(np.diff(np.unwrap(np.asarray(log.true_pose)[:, 2])))
    return np.where(state == fsm.TURN, turn / settings.turn_rate_rad_s, dur)


#: Standard deviation (V) of the synthetic floor whiskers' noise per texture (made up).
_SYNTHETIC_FLOOR_NOISE_V = {"vinyl": 0.01, "smooth-carpet": 0.03, "rough-carpet": 0.06}


def synthetic_record(
    arena: Arena,
    seconds: float = 360.0,
    seed: int = 0,
    sample_rate_hz: float = 2000.0,
    gain_v: float = 1.0,
    noise_v: float = 0.005,
    **log_options,
) -> RunRecord:
    """A :class:`RunRecord` from :func:`synthetic_log`: SYNTHETIC Hall signals, no physics.

    For tests and the viewer while the simulated robot is not there: the contacts are the
    exact ray-cast ones of :func:`synthetic_log`; the Hall outputs are made up from them.
    An obstacle whisker touching at ``d`` from its base reads ``gain_v * (L - d) / L`` in
    x through the whole step (0 when free), a floor whisker reads noise whose size
    depends on the tile under it, and every channel gets Gaussian noise of ``noise_v``.
    Poses between step boundaries are interpolated linearly. The floor prediction is the
    most likely texture of the log (the true one); ``latency_s`` is empty (no classifier
    ran); ``wall_seconds`` is the time this function took.

    Parameters
    ----------
    arena, seconds, seed
        As :func:`synthetic_log` (``log_options`` go there too).
    sample_rate_hz
        Rate of the synthetic whisker samples.
    """
    import time

    t0 = time.perf_counter()
    v.positive("sample_rate_hz", sample_rate_hz)
    settings = log_options.get("settings") or fsm.FsmSettings()
    log = synthetic_log(arena, seconds, seed, **log_options)
    rng = np.random.default_rng([seed, 1])
    offset = arena.map_offset_m(log_options.get("map_size_m", 2.5), log_options.get("cell_m", 0.05))
    true = np.asarray(log.true_pose) - np.array([offset, offset, 0.0])
    true[:, 2] = np.unwrap(true[:, 2])
    counts = np.round(_step_durations(log, settings) * sample_rate_hz).astype(np.int64)
    start = np.concatenate([[0], np.cumsum(counts)])
    n = int(start[-1])
    step = np.repeat(np.arange(log.n_steps), counts)
    frac = (np.arange(n) - start[step]) / np.maximum(counts[step], 1)
    pose = true[step] + frac[:, None] * (true[step + 1] - true[step])
    length = np.asarray(log.layout.length_m, float)
    defl = np.where(
        log.contact, gain_v * (length - np.nan_to_num(log.radial_distance_m, nan=0.0)) / length, 0.0
    )
    hall = rng.normal(0.0, noise_v, (n, 6, 2))
    hall[:, :N_OBSTACLE_WHISKERS, 0] += defl[step]
    fl = apply_motion(true[1:, None, :], np.c_[FLOOR_WHISKERS_M, np.zeros(2)][None])
    tex_true = arena.texture_at(fl[..., 0], fl[..., 1]).astype(str)
    sd = np.vectorize(lambda t: _SYNTHETIC_FLOOR_NOISE_V.get(t, 0.0), otypes=[float])(tex_true)
    hall[:, N_OBSTACLE_WHISKERS:, :] += rng.standard_normal((n, 2, 2)) * sd[step][..., None]
    if log.floor_loglik is not None and log.textures:
        pred = np.asarray(log.textures, dtype=object)[np.argmax(log.floor_loglik, axis=2)]
    else:
        pred = np.full((log.n_steps, 2), "", dtype=object)
    return RunRecord(
        arena=arena,
        seed=seed,
        log=log,
        sample_rate_hz=float(sample_rate_hz),
        time_s=np.arange(n) / sample_rate_hz,
        hall_v=hall.astype(np.float32),
        pose=pose,
        step_start=start,
        contact_true_m=np.where(log.contact, log.radial_distance_m, np.nan),
        floor_texture_true=tex_true.astype(object),
        floor_texture_pred=pred.astype(object),
        latency_s={},
        wall_seconds=time.perf_counter() - t0,
    )
