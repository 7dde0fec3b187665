"""CrunchBot's four forward obstacle whiskers on the simulated rod (thesis 3.5.2, 6.5.3).

Each whisker (preset ``crunchbot``, layout :data:`~vibrissa.robots.crunchbot.synthetic.
CRUNCHBOT_LAYOUT`) lies horizontal: its bending plane is the floor plane, the whisker
frame's ``z`` its rest direction, ``x`` the left normal in the floor plane and ``y``
vertical (up). Walls and obstacle faces are vertical planes, a flat
:class:`~vibrissa.whisker.simulate.SurfaceContact` at the face's angle to the whisker
(``side`` from the face's normal; faces within 5 deg of square to the whisker are
simulated at 85 deg, since the perfectly symmetric axial push of a straight rod has no
way to buckle); obstacle corners are a :class:`~vibrissa.whisker.simulate.PoleContact`
of radius :data:`CORNER_RADIUS_MM` (a vertical edge of a wooden block, ours).

The robot's motion enters as rigid motion, in a frame that translates with the whisker's
base and keeps the whisker's orientation at the frame's start: the robot's rotation turns
the follicle housing about ``y`` (:class:`~vibrissa.whisker.simulate.BaseMotion`, positive
= anticlockwise seen from above), its translation and the base's swing move the object
(:class:`~vibrissa.whisker.simulate.Trajectory`, mm). The base's translational
acceleration is left out (steps start and stop at once, :mod:`.body`). The frame is set
again at every step (and every 0.5 rad of a turn) by turning the rod's state back with
the housing, which is exact for the rod; only the stick anchors of friction are dropped
then (the contact re-anchors where it is, an error within the presliding distance).

The simulator takes one object per call: each step the whisker meets the feature its
swept straight shaft comes within :data:`REACH_MARGIN_M` of first, and keeps it while it
touches; its :class:`~vibrissa.whisker.simulate.DynamicState` is carried across steps
while it touches or rings. A whisker at rest with nothing within reach skips the
physics: its output is the rest value plus sensor noise, exact for a free whisker on a
base at constant velocity.

Strain (:data:`STRAIN_SOURCE`): what the robot can read of it, the Hall output's
deflection magnitude ``|(V_x, V_y) - rest|`` as a fraction of the sensor's calibrated half
range (1.0 at full scale; each axis clamps there as the sensor does), which is the magnet's
tilt and so the moment at the whisker's base. It is averaged over the latest 10 ms so a
millisecond flick at first touch does not count, and counted only while the whisker
touches (a whisker ringing free after it slipped off is not strained by an object). The
FSM's safety threshold (``FsmSettings.strain_limit``) is in these units.
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass, field

import numpy as np

from vibrissa.robots.crunchbot._threads import default_workers, map_threads
from vibrissa.robots.crunchbot.arena import Arena
from vibrissa.robots.crunchbot.synthetic import CRUNCHBOT_LAYOUT
from vibrissa.slam.log import WhiskerLayout
from vibrissa.whisker.geometry import preset
from vibrissa.whisker.hall import HallSensor, HallSettings
from vibrissa.whisker.modal import linear_modes
from vibrissa.whisker.rod import RodModel, SimulationError
from vibrissa.whisker.simulate import (
    BaseMotion,
    DynamicState,
    PoleContact,
    SurfaceContact,
    Trajectory,
    simulate,
)
from vibrissa.whisker.surfaces import Surface

__all__ = [
    "CORNER_RADIUS_MM",
    "REACH_MARGIN_M",
    "STRAIN_SOURCE",
    "Feature",
    "ObstacleWhiskers",
    "StepSignals",
    "arena_features",
    "feature_distances",
]

#: Radius of an obstacle's vertical corner edge (mm; ours).
CORNER_RADIUS_MM = 1.0
#: A feature closer than this to the straight swept whisker is within reach (m).
REACH_MARGIN_M = 0.02
#: A feature closer than this to the straight whisker is touching it (m).
CONTACT_TOL_M = 2e-3
#: Largest surface angle simulated (deg): see the module's note.
MAX_SURFACE_ANGLE_DEG = 85.0
#: Wall friction coefficient (painted wood against the whisker; ours).
WALL_FRICTION = 0.3
#: Largest housing turn within one simulate call (rad) before the frame is set again.
MAX_FRAME_TURN_RAD = 0.5
#: A carried state lying deeper than this inside a newly met face (m) has bent round
#: the face's end: that step it meets nothing (the simulator's faces are unbounded).
PENETRATION_LIMIT_M = 1e-3
#: Rod elements of each whisker (the default 28 costs twice the time for a tilt 0.6 %
#: different in a wall push).
N_ELEMENTS = 16
#: Trailing average of the strain (samples at 2 kHz: 10 ms).
STRAIN_WINDOW = 20
#: Where the strain measure comes from.
STRAIN_SOURCE = (
    "Hall deflection magnitude |(V_x, V_y) - rest| over the sensor's calibrated half range "
    "(each axis clamped at full scale; proportional to the base moment), 10 ms trailing "
    "average, counted while the whisker touches"
)
_REST_TOL_V = 2.5e-4
_FLAT = Surface(np.zeros((4, 4)), 1e-3, WALL_FRICTION, "wall")


@dataclass(frozen=True)
class Feature:
    """Something a whisker can touch: a vertical face or a vertical corner edge.

    A face is a ``"plane"``, from ``a`` to ``b``, ``normal`` pointing out of the solid; a
    corner edge is a ``"pole"`` at ``a``.
    """

    kind: str
    a: np.ndarray
    b: np.ndarray = field(default_factory=lambda: np.zeros(2))
    normal: np.ndarray = field(default_factory=lambda: np.zeros(2))


def _on_border(p: np.ndarray, size: float) -> bool:
    return bool(min(p[0], p[1], size - p[0], size - p[1]) < 1e-9)


def _along_border(a: np.ndarray, b: np.ndarray, size: float) -> bool:
    """Whether segment ``a``-``b`` lies on one of the arena's walls (hidden by it)."""
    return any(
        abs(a[i] - edge) < 1e-9 and abs(b[i] - edge) < 1e-9 for i in (0, 1) for edge in (0.0, size)
    )


def arena_features(arena: Arena) -> tuple[Feature, ...]:
    """The arena's walls, the obstacles' free faces and their free (convex) corners."""
    out: list[Feature] = []
    segs = arena.segments()
    size = arena.size_m
    for i, (x0, y0, x1, y1) in enumerate(segs):
        a, b = np.array([x0, y0]), np.array([x1, y1])
        d = (b - a) / np.linalg.norm(b - a)
        left = np.array([-d[1], d[0]])
        if i < 4:  # the arena's border, anticlockwise: its inside is on the left
            out.append(Feature("plane", a, b, left))
        elif not _along_border(a, b, size):
            out.append(Feature("plane", a, b, -left))  # an obstacle: outside on the right
    for ob in arena.obstacles:
        x0, y0, x1, y1 = ob.bounds()
        for c in ((x0, y0), (x1, y0), (x1, y1), (x0, y1)):
            p = np.array(c, float)
            if not _on_border(p, size):
                out.append(Feature("pole", p))
    return tuple(out)


def _point_segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance from points ``p`` to segments ``a``-``b`` (all broadcast, last axis 2)."""
    abx, aby = b[..., 0] - a[..., 0], b[..., 1] - a[..., 1]
    apx, apy = p[..., 0] - a[..., 0], p[..., 1] - a[..., 1]
    t = np.clip((apx * abx + apy * aby) / np.maximum(abx * abx + aby * aby, 1e-18), 0.0, 1.0)
    return np.hypot(apx - t * abx, apy - t * aby)


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def feature_distances(
    base: np.ndarray, tip: np.ndarray, a: np.ndarray, b: np.ndarray, is_pole: np.ndarray
) -> np.ndarray:
    """Distance of each feature from each straight whisker ``base``-``tip``: ``(..., F)``.

    ``base`` and ``tip`` are ``(..., 2)``. A corner (``is_pole``) is a point ``a``; a face is
    the segment ``a``-``b``, and where it is nearest the whisker at one of its ends it counts
    1 mm further: there its end (a corner, or the next wall) is what the whisker meets.
    """
    p0, p1 = base[..., None, :], tip[..., None, :]
    to_a = _point_segment_distance(a, p0, p1)
    to_b = _point_segment_distance(b, p0, p1)
    ends = np.minimum(_point_segment_distance(p0, a, b), _point_segment_distance(p1, a, b))
    r, q = p1 - p0, b - a
    den = _cross(r, q)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = _cross(a - p0, q) / den
        u = _cross(a - p0, r) / den
    crossing = (den != 0) & (t >= 0) & (t <= 1) & (u > 0) & (u < 1)
    face = np.where(crossing, 0.0, np.minimum(ends, np.minimum(to_a, to_b) + 1e-3))
    return np.where(is_pole, to_a, face)


@dataclass
class StepSignals:
    """What the four obstacle whiskers sensed in one step.

    Attributes
    ----------
    hall_v
        ``(m, 4, 2)`` Hall outputs (V) at the step's samples.
    contact
        ``(m, 4)`` bool, touching at the sample.
    first_contact_m
        ``(4,)`` true radial distance of the first point touched in the step (NaN: none).
    strain
        ``(m, 4)`` strain as a fraction of the sensor's full scale (:data:`STRAIN_SOURCE`).
    physics
        ``(4,)`` bool, whether the whisker ran the physics this step.
    """

    hall_v: np.ndarray
    contact: np.ndarray
    first_contact_m: np.ndarray
    strain: np.ndarray
    physics: np.ndarray


@dataclass
class _Whisker:
    state: DynamicState | None = None  # None: at rest in its housing
    feature: int = -1  # the feature it touches or last met (-1: none)
    touching: bool = False
    sim_feature: int = -1  # the feature its state's friction anchors refer to


def _turn_state(st: DynamicState, theta: float) -> DynamicState:
    """The state turned by ``theta`` about ``y`` through node 0, stick anchors dropped."""
    c, s = math.cos(theta), math.sin(theta)

    def rot(v: np.ndarray, about: np.ndarray | None) -> np.ndarray:
        r = v - about if about is not None else v.copy()
        out = r.copy()
        out[:, 0] = c * r[:, 0] + s * r[:, 2]
        out[:, 2] = -s * r[:, 0] + c * r[:, 2]
        return out + (about if about is not None else 0.0)

    x = st.positions_m
    pole = np.zeros_like(st.pole_anchor)
    pole[4] = st.pole_anchor[4]  # which side of the pole the shaft is on survives
    return DynamicState(
        rot(x, x[0].copy()),
        rot(st.velocities_m_s, None),
        rot(st.accelerations_m_s2, None),
        pole,
        np.zeros_like(st.plane_anchors),
        st.time_s,
    )


class ObstacleWhiskers:
    """The four obstacle whiskers of one robot with their dynamic state.

    Parameters
    ----------
    arena
        The arena whose walls and obstacles they touch.
    sample_rate_hz
        The Hall sensors' rate (2 kHz, thesis 3.5.2).
    layout
        Where the whiskers sit on the robot.
    hall
        The sensors' settings (calibrated on the ``crunchbot`` whisker).
    dt_s
        The rod's internal step. A step that fails to converge is tried again at half and
        a quarter of it; if that fails too, the whisker meets nothing that step (counted
        in ``failures``: rare deep contacts where the rod model gives up).
    """

    def __init__(
        self,
        arena: Arena,
        sample_rate_hz: float = 2000.0,
        layout: WhiskerLayout = CRUNCHBOT_LAYOUT,
        hall: HallSettings | None = None,
        dt_s: float = 2.5e-4,
    ) -> None:
        self.arena = arena
        self.layout = layout
        self.rate = float(sample_rate_hz)
        self.dt_s = float(dt_s)
        self.model = RodModel(preset("crunchbot"), n_elements=N_ELEMENTS)
        settings = hall or HallSettings(sample_rate_hz=self.rate)
        self.sensor: HallSensor = settings.calibrate(self.model.geometry, self.model.n_elements)
        # the magnet tilt (tan) at the sensor's full scale: strain 1.0
        self.tan_full_scale = (self.sensor.v_max - self.sensor.offset_v) / self.sensor.gain_v
        self.length_m = self.model.geometry.length_mm * 1e-3
        self.features = arena_features(arena)
        self.whiskers = [_Whisker() for _ in range(layout.n_whiskers)]
        self.physics_steps = 0
        self.physics_whisker_steps = 0
        self.failures = 0
        self.steps = 0
        self._fa = np.array([f.a for f in self.features])
        self._fb = np.array([f.b if f.kind == "plane" else f.a for f in self.features])
        self._is_pole = np.array([f.kind == "pole" for f in self.features])
        self._node_arc = self.model.x_rest[:, 2].copy()
        # the whiskers of one step are independent: their rod kernels release the
        # GIL, so they run on threads (the model's lazily built parts are built here,
        # before any thread shares them)
        linear_modes(self.model)
        _ = self.model.damping
        self.workers = default_workers()
        self._lock = threading.Lock()

    # ---------------------------------------------------------------- geometry
    def bases(self, poses: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Whisker bases ``(n, W, 2)`` and directions ``(n, W)`` (rad) at poses ``(n, 3)``."""
        c, s = np.cos(poses[:, 2])[:, None], np.sin(poses[:, 2])[:, None]
        bx, by = self.layout.base_m[:, 0], self.layout.base_m[:, 1]
        base = np.stack(
            [poses[:, 0, None] + c * bx - s * by, poses[:, 1, None] + s * bx + c * by], axis=-1
        )
        return base, poses[:, 2, None] + np.asarray(self.layout.angle_rad)[None, :]

    def _distances(self, poses: np.ndarray) -> np.ndarray:
        """``(n, W, F)`` distance of each feature from each straight whisker."""
        base, ang = self.bases(poses)
        tip = base + self.length_m * np.stack([np.cos(ang), np.sin(ang)], axis=-1)
        return feature_distances(base, tip, self._fa, self._fb, self._is_pole)

    def _first_met(self, dist: np.ndarray) -> np.ndarray:
        """Per whisker the feature the straight swept whisker meets first, else the nearest.

        Meeting counts within :data:`CONTACT_TOL_M`; the nearest is taken within reach (-1:
        none).
        """
        out = np.full(dist.shape[1], -1)
        for w in range(dist.shape[1]):
            d = dist[:, w]
            touch = d < CONTACT_TOL_M
            if touch.any():
                k = int(np.flatnonzero(touch.any(axis=1))[0])
                out[w] = int(np.argmin(d[k]))
            elif d.min() < REACH_MARGIN_M:
                out[w] = int(np.argmin(d.min(axis=0)))
        return out

    # ---------------------------------------------------------------- physics
    def _contact_for(
        self, feat: Feature, base0: np.ndarray, phi0: float
    ) -> tuple[PoleContact | SurfaceContact, np.ndarray]:
        """The simulator's contact for ``feat`` and the object's point the trajectory follows.

        The contact is in a frame with rest direction ``phi0`` and base ``base0`` (arena m). The
        point is fixed on the object (arena m) and the trajectory follows its motion: the
        corner, or where the whisker's rest line meets the face (the foot of the perpendicular
        from the base if it runs along).
        """
        if feat.kind == "pole":
            return PoleContact(radius_mm=CORNER_RADIUS_MM, friction=WALL_FRICTION), feat.a
        d = np.array([math.cos(phi0), math.sin(phi0)])
        e = feat.b - feat.a
        e = e / np.linalg.norm(e)
        foot = feat.a + e * float((base0 - feat.a) @ e)
        denom = float(d @ feat.normal)
        t = float((foot - base0) @ feat.normal) / denom if abs(denom) > 0.2 else math.inf
        point = base0 + t * d if 0.0 <= t <= 2 * self.length_m else foot
        nx = float(feat.normal @ np.array([-d[1], d[0]]))
        nz = float(feat.normal @ d)
        angle = math.degrees(math.asin(min(max(-nz, 0.0), 1.0)))
        side = 1 if nx >= 0 else -1
        return SurfaceContact(
            _FLAT, angle_deg=min(angle, MAX_SURFACE_ANGLE_DEG), side=side, friction=WALL_FRICTION
        ), point

    def _to_frame(self, pts: np.ndarray, base: np.ndarray, phi0: float) -> np.ndarray:
        """Arena points ``(n, 2)`` relative to ``base`` ``(n, 2)`` in the frame (x, z) mm."""
        r = pts - base
        return 1e3 * np.column_stack(
            [
                -math.sin(phi0) * r[:, 0] + math.cos(phi0) * r[:, 1],
                math.cos(phi0) * r[:, 0] + math.sin(phi0) * r[:, 1],
            ]
        )

    def _simulate(
        self, w: int, poses: np.ndarray, feature: int, state: DynamicState | None
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, DynamicState, float]:
        """Run whisker ``w`` over ``poses`` (start pose first, then the samples).

        Returns tan ``(m, 2)``, contact ``(m,)``, first-contact arc (m, NaN per sample
        with no pole contact) ``(m,)``, the final state and the first-touch distance
        for planes (m, NaN: none).
        """
        m = len(poses) - 1
        base, ang = self.bases(poses)
        base, ang = base[:, w], ang[:, w]
        phi0 = float(ang[0])
        times = np.arange(m + 1) / self.rate  # each call runs in its own local time
        theta = ang - phi0
        if state is not None:
            state = DynamicState(
                state.positions_m,
                state.velocities_m_s,
                state.accelerations_m_s2,
                state.pole_anchor,
                state.plane_anchors,
                0.0,
            )
        contact, traj = None, None
        if feature >= 0:
            feat = self.features[feature]
            contact, point = self._contact_for(feat, base[0], phi0)
            rel = self._to_frame(np.broadcast_to(point, base.shape), base, phi0)
            traj = Trajectory(times, rel)
        if (
            isinstance(contact, SurfaceContact)
            and state is not None
            and self._penetration(state, contact, traj) > PENETRATION_LIMIT_M
        ):
            contact, traj = None, None  # bent round the face's end: the face is not there
        motion = None
        if np.any(theta != 0.0):
            motion = BaseMotion(times, theta, np.gradient(theta, times))
        dt = self.dt_s
        for attempt in range(4):
            try:
                res = simulate(
                    self.model,
                    contact,
                    traj,
                    m / self.rate,
                    dt_s=dt,
                    initial_state=state,
                    base_motion=motion,
                )
                break
            except SimulationError:
                if attempt == 3:
                    raise
                if attempt == 2:  # give up the object for this step, count it
                    with self._lock:
                        self.failures += 1
                    contact, traj, dt = None, None, self.dt_s
                else:
                    dt *= 0.5
        step = int(round(1.0 / (self.rate * dt)))
        force = res.contact_force_n[1:].reshape(m, step)
        touching = (force > 0).any(axis=1)
        arcs = res.contact_arc_mm[1:].reshape(m, step)
        arc = np.where(np.isfinite(arcs[:, -1]), arcs[:, -1], arcs[:, 0]) * 1e-3
        plane_first = math.nan
        if contact is not None and touching.any() and isinstance(contact, SurfaceContact):
            plane_first = self.length_m
            if state is not None:  # already pressing: the node nearest the face
                plane_first = self._plane_contact_arc(state, contact, traj)
        final = res.final_state
        end_theta = float(theta[-1])
        if end_theta != 0.0:
            final = _turn_state(final, -end_theta)
        return res.tan_xy[step::step][:m], touching, arc, final, plane_first

    @staticmethod
    def _gaps(state: DynamicState, contact: SurfaceContact, traj: Trajectory) -> np.ndarray:
        """Each node's distance (m) outside the face at the state's time (0)."""
        n, _, _ = contact.frame()
        p, _ = traj.sample(np.array([0.0]))
        origin = np.array([p[0, 0], 0.0, p[0, 1]]) * 1e-3
        return (state.positions_m - origin) @ n

    def _penetration(self, state: DynamicState, contact: SurfaceContact, traj: Trajectory) -> float:
        """How deep (m) the state's shaft lies inside the face (0: outside)."""
        return max(0.0, -float(self._gaps(state, contact, traj)[2:].min()))

    def _plane_contact_arc(
        self, state: DynamicState, contact: SurfaceContact, traj: Trajectory
    ) -> float:
        """Arc length (m) of the node nearest the face at the state's time (0)."""
        j = int(np.argmin(self._gaps(state, contact, traj)[2:])) + 2
        return float(self._node_arc[j])

    def _at_rest(self, tan: np.ndarray, touching: np.ndarray) -> bool:
        tail = tan[-max(1, int(0.02 * self.rate)) :]
        return (not touching[-1]) and float(np.abs(tail).max()) * self.sensor.gain_v < _REST_TOL_V

    def advance(
        self,
        start_pose: np.ndarray,
        poses: np.ndarray,
        rng: np.random.Generator,
        stop_strain: float | None = None,
        stop_on_contact: bool = False,
    ) -> tuple[StepSignals, int]:
        """Carry the whiskers through one step of the body.

        Parameters
        ----------
        start_pose
            ``(3,)`` arena pose at the step's start (time ``t0``).
        poses
            ``(m, 3)`` poses at the step's samples ``t0 + k / rate``, ``k = 1..m``.
        rng
            The sensor-noise stream.
        stop_strain
            Forward motion: cut the step at the first sample where a whisker's strain
            passes this (the Create stops at once); ``None``: never.
        stop_on_contact
            Cut the step at the first sample where any whisker touches (FWD_1 drives
            "until a whisker hits something", 6.5.3).

        Returns
        -------
        signals, m_used
            What the whiskers sensed over the first ``m_used`` samples (``m_used = m``
            unless the strain stop cut the step).
        """
        m = len(poses)
        W = self.layout.n_whiskers
        self.steps += 1
        if m == 0:
            return StepSignals(
                np.zeros((0, W, 2)),
                np.zeros((0, W), bool),
                np.full(W, np.nan),
                np.zeros((0, W)),
                np.zeros(W, bool),
            ), 0
        allp = np.vstack([start_pose[None, :], poses])
        sub = allp[np.unique(np.r_[np.arange(0, m + 1, 10), m])]
        met = self._first_met(self._distances(sub))
        run = []
        for w, wk in enumerate(self.whiskers):
            if not wk.touching:
                wk.feature = int(met[w])
            if wk.state is not None or wk.feature >= 0:
                run.append(w)
        results = self._run_all(run, allp)
        m_used = m
        for r in results.values():
            stop = r[1] if stop_on_contact else np.zeros(len(r[1]), bool)
            if stop_strain is not None:
                stop = stop | (self._strain(r[0], r[1]) > stop_strain)
            if stop.any():
                m_used = min(m_used, int(np.argmax(stop)) + 1)
        if m_used < m:
            results = self._run_all(run, allp[: m_used + 1])
        tan = np.zeros((m_used, W, 2))
        contact = np.zeros((m_used, W), bool)
        first = np.full(W, np.nan)
        for w, (tw, touch, arc, final, plane_first) in results.items():
            wk = self.whiskers[w]
            tan[:, w] = tw
            contact[:, w] = touch
            if touch.any():
                k = int(np.argmax(touch))
                first[w] = plane_first if np.isfinite(plane_first) else arc[k]
            wk.touching = bool(touch[-1])
            wk.sim_feature = wk.feature
            wk.state = None if self._at_rest(tw, touch) else final
        self.physics_steps += int(len(run) > 0)
        self.physics_whisker_steps += len(run)
        volts = self.sensor.read(tan.reshape(-1, 2), self.rate, rng)
        hall = volts.reshape(m_used, W, 2)
        strain = np.stack([self._strain(tan[:, w], contact[:, w]) for w in range(W)], axis=1)
        physics = np.zeros(W, bool)
        physics[run] = True
        return StepSignals(hall, contact, first, strain, physics), m_used

    def _strain(self, tan: np.ndarray, touching: np.ndarray) -> np.ndarray:
        """Strain per sample (:data:`STRAIN_SOURCE`), 0 where the whisker is free."""
        read = np.clip(tan, -self.tan_full_scale, self.tan_full_scale)
        mag = np.hypot(read[:, 0], read[:, 1]) / self.tan_full_scale
        c = np.cumsum(np.r_[0.0, mag])
        k = np.arange(1, len(mag) + 1)
        lo = np.maximum(k - STRAIN_WINDOW, 0)
        return np.where(touching, (c[k] - c[lo]) / (k - lo), 0.0)

    def _run_all(self, run: list[int], allp: np.ndarray) -> dict[int, tuple]:
        """:meth:`_run` for each whisker in ``run``, on up to :attr:`workers` threads."""
        return dict(
            zip(run, map_threads(lambda w: self._run(w, allp), run, self.workers), strict=True)
        )

    def _run(self, w: int, allp: np.ndarray) -> tuple:
        """Whisker ``w`` over the poses, split so no piece turns the housing too far."""
        wk = self.whiskers[w]
        heading = allp[:, 2]
        turn = np.abs(heading - heading[0])
        pieces = max(1, int(math.ceil(float(turn.max()) / MAX_FRAME_TURN_RAD)))
        m = len(allp) - 1
        cuts = np.linspace(0, m, pieces + 1).round().astype(int)
        state, feature = wk.state, wk.feature
        if state is not None and feature != wk.sim_feature:  # a new object: no old anchors
            state = _turn_state(state, 0.0)
        outs = []
        for a, b in zip(cuts[:-1], cuts[1:], strict=True):
            if b <= a:
                continue
            outs.append(self._simulate(w, allp[a : b + 1], feature, state))
            state = outs[-1][3]
        tan = np.vstack([o[0] for o in outs])
        touch = np.concatenate([o[1] for o in outs])
        arc = np.concatenate([o[2] for o in outs])
        plane_first = next((o[4] for o in outs if np.isfinite(o[4])), math.nan)
        return tan, touch, arc, state, plane_first
