"""CrunchBot's two floor whiskers brushing the arena's tiles (thesis 6.5.2, 6.5.6.1).

"The outer two of CrunchBot's six whiskers are angled downwards to make a light,
brushing contact with the floor surface" (6.5.2). Each is a ``crunchbot`` whisker (RC25,
140 mm free) whose tip rests on the floor at :data:`~vibrissa.robots.crunchbot.synthetic.
FLOOR_WHISKERS_M` (robot frame, left then right), pointing straight back and down at the
Roomba's ``tilt_deg`` to the floor with its base ahead of the tip ("angle as far back as
possible", 6.5.6.1), pressed on by ``preload_mm``.

**Kinematics** (those of :mod:`vibrissa.robots.roomba`, for any tip position): from the
robot's true poses, the tip's displacement between samples, written in the robot's frame,
is ``(dX, dY)``; the floor slides under the tip along the whisker's in-plane axis ``u``
(base toward tip, robot ``-X``) by ``dX`` and across the bending plane by ``-dY``. For the
Roomba's tip at ``(-L cos(tilt), -r)`` this is its ``v + omega r`` along and
``omega L cos(tilt)`` across. The floor translates under the tip without rotating.

**Tiles.** Each texture is one periodic sheet (:func:`vibrissa.whisker.floors.make_floor`,
seeded per texture). The tip's place on the sheet is the slide accumulated since the run
began (plus a random start per whisker), whatever tile it is on: at a tile boundary the
simulation is split at the sample where the tile under the tip changes, the whisker's
:class:`~vibrissa.whisker.simulate.DynamicState` carried over, and the new texture's sheet
(and its contact stiffness and friction) continues under the tip at the same place. The
base planes of all tiles are at one height: the tiles' thicknesses are not modelled (the
catch on a tile edge of 6.5.6.1 is not reproduced); the heights of the pile's relief do
change at the boundary (a rough-carpet loop top stands 1.2 mm above vinyl).

**Window mode.** A floor whisker is always in contact, so it runs on the nonlinear rod
(about 20 times faster than real time). ``advance(..., window_s=w)`` simulates only the
step's last ``w`` seconds and a lead-in of :data:`LEAD_IN_S` before them, from the whisker
settled at rest on that texture (:meth:`FloorWhiskers.settled`), with the floor sliding as
the poses say; the rest of the step is NaN. The lead-in length is the one measured by
``scripts/floor_whisker_lead_in.py``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from vibrissa._validate import finite_array, in_range, positive
from vibrissa.robots.crunchbot._threads import default_workers, map_threads
from vibrissa.robots.crunchbot.arena import ROBOT_RADIUS_M, Arena, Pose
from vibrissa.robots.crunchbot.synthetic import FLOOR_WHISKERS_M
from vibrissa.robots.roomba import SETTLE_S, Roomba
from vibrissa.whisker.floors import floor_names, floor_spec, make_floor
from vibrissa.whisker.geometry import preset
from vibrissa.whisker.hall import HallSensor, HallSettings, steps_per_sample
from vibrissa.whisker.rod import RodModel, SimulationError
from vibrissa.whisker.simulate import (
    DynamicState,
    SimulationResult,
    SurfaceContact,
    Trajectory,
    simulate,
)
from vibrissa.whisker.surfaces import Surface

__all__ = [
    "FIGURE_6_11",
    "FWD_SPEED_M_S",
    "LEAD_IN_S",
    "FloorWhiskers",
    "TextureCourse",
    "WINDOW_SAMPLES",
    "collect_floor_training",
    "texture_course",
]

#: FWD_1 speed (6.5.3), at which the texture training and test runs drive.
FWD_SPEED_M_S = 0.05
#: Seconds simulated before a window in window mode (see the module doc).
LEAD_IN_S = 0.15
#: Window mode starts its lead-in from the whisker already sliding at FWD speed for this
#: long (s): started from rest, the breakaway of static friction rings on stiff vinyl.
SLIDING_S = 0.3
#: Times the time step is halved to retry a segment that diverges.
RETRY_HALVINGS = 2
#: Rod elements of a floor whisker: on rough carpet the Hall signal's mean and standard
#: deviation differ by < 2 % between 8 and 28 elements, and 8 cost a third as much.
N_ELEMENTS = 8
#: Samples of one real-time texture window (100 ms at 2 kHz, 6.5.2).
WINDOW_SAMPLES = 200
#: The figure-6.11 course: a tile of rough carpet, one of vinyl, one of rough carpet.
FIGURE_6_11 = ("rough-carpet", "vinyl", "rough-carpet")

_ROOMBA = Roomba()


def _tips(pose: np.ndarray) -> np.ndarray:
    """Arena-frame tip positions ``(n, 2 whiskers, 2)`` at poses ``(n, 3)``."""
    c, s = np.cos(pose[:, 2])[:, None], np.sin(pose[:, 2])[:, None]
    tx, ty = FLOOR_WHISKERS_M[:, 0][None], FLOOR_WHISKERS_M[:, 1][None]
    return np.stack([pose[:, :1] + c * tx - s * ty, pose[:, 1:2] + s * tx + c * ty], axis=-1)


def _slides(pose: np.ndarray) -> np.ndarray:
    """Slide increments ``(n - 1, 2 whiskers, 2)`` (along u, across y; mm) between poses."""
    d = np.diff(_tips(pose), axis=0)
    turn = (np.diff(pose[:, 2]) + math.pi) % math.tau - math.pi
    mid = pose[:-1, 2] + 0.5 * turn
    c, s = np.cos(mid)[:, None], np.sin(mid)[:, None]
    along = c * d[..., 0] + s * d[..., 1]
    across = -(-s * d[..., 0] + c * d[..., 1])
    return 1e3 * np.stack([along, across], axis=-1)


def _spline_height(H: np.ndarray, spacing_m: float, U: float, W: float) -> float:
    """Height (m) of a periodic height field at surface coordinates (m).

    The field is read as the contact kernel reads it: a uniform quadratic B-spline through
    the grid values.
    """
    fu, fw = U / spacing_m, W / spacing_m
    iu, iw = math.floor(fu + 0.5), math.floor(fw + 0.5)
    tu, tw = fu - iu, fw - iw
    bu = np.array([0.5 * (0.5 - tu) ** 2, 0.75 - tu * tu, 0.5 * (0.5 + tu) ** 2])
    bw = np.array([0.5 * (0.5 - tw) ** 2, 0.75 - tw * tw, 0.5 * (0.5 + tw) ** 2])
    rows = (iu - 1 + np.arange(3)) % H.shape[0]
    cols = (iw - 1 + np.arange(3)) % H.shape[1]
    return float(bu @ H[np.ix_(rows, cols)] @ bw)


class FloorWhiskers:
    """The two outer whiskers brushing the floor tiles, with their state.

    Parameters
    ----------
    arena : Arena
        Its tiles give the texture under each tip; an arena without tiles is floored
        with ``default_texture``.
    sample_rate_hz : float
        Sensor sample rate (2 kHz, 3.5.2).
    seed : int
        Seed of the floor sheets, the start places on them and the sensor noise.
    tilt_deg : float
        Angle between the undeflected whisker and the floor (the Roomba's 30 deg).
    preload_mm : float
        How far the floor would cut into the undeflected tip along its normal (mm): the
        Roomba's 15 mm on a 200 mm whisker scaled to 140 mm.
    n_elements : int
        Rod discretisation.
    dt_s : float
        Internal time step (s); must divide the sample period.
    sensor : HallSettings, optional
        Hall sensor set-up (default: :class:`HallSettings` at ``sample_rate_hz``).
    default_texture : str
        Floor where the arena has no tiles.
    lead_in_s : float
        Lead-in of window mode (s).
    """

    def __init__(
        self,
        arena: Arena,
        sample_rate_hz: float = 2000.0,
        seed: int = 0,
        *,
        tilt_deg: float = _ROOMBA.tilt_deg,
        preload_mm: float = 10.0,
        n_elements: int = N_ELEMENTS,
        dt_s: float = 1.25e-4,
        sensor: HallSettings | None = None,
        default_texture: str = "vinyl",
        lead_in_s: float = LEAD_IN_S,
    ) -> None:
        if not isinstance(arena, Arena):
            raise TypeError(f"arena must be an Arena, got {type(arena).__name__}")
        self.arena = arena
        self.sample_rate_hz = positive("sample_rate_hz", sample_rate_hz)
        self._step = steps_per_sample(dt_s, self.sample_rate_hz)
        self.dt_s = float(dt_s)
        if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
            raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
        self.seed = int(seed)
        self.tilt_deg = in_range("tilt_deg", tilt_deg, 1.0, 89.0, "deg")
        self.preload_mm = positive("preload_mm", preload_mm)
        self.default_texture = floor_spec(default_texture).name
        self.lead_in_s = positive("lead_in_s", lead_in_s)
        geometry = preset("crunchbot")
        self.model = RodModel(geometry, n_elements)
        settings = sensor if sensor is not None else HallSettings(sample_rate_hz=sample_rate_hz)
        if abs(settings.sample_rate_hz - self.sample_rate_hz) > 1e-9 * self.sample_rate_hz:
            raise ValueError(
                f"sensor samples at {settings.sample_rate_hz:g} Hz, but "
                f"sample_rate_hz is {self.sample_rate_hz:g} Hz"
            )
        self.sensor: HallSensor = settings.calibrate(geometry, n_elements)
        self._sheets: dict[str, Surface] = {}
        self._contacts: dict[str, SurfaceContact] = {}
        self._settled: dict[tuple, DynamicState] = {}
        self._base: tuple[np.ndarray, np.ndarray] | None = None
        ss = np.random.SeedSequence([self.seed, 16, 2])
        self._noise = [np.random.default_rng(s) for s in ss.spawn(2)]
        start = np.random.default_rng(np.random.SeedSequence([self.seed, 16, 3]))
        # where each tip starts on the sheets (mm): any place on the periodic tile
        self._start_mm = start.uniform(0.0, 1.0, (2, 2)) * np.array([160.0, 64.0])
        self.reset()

    # ------------------------------------------------------------------ floor
    def reset(self) -> None:
        """Forget the run: the next :meth:`advance` starts with the whiskers settled."""
        self._t: float | None = None
        self._pose: np.ndarray | None = None
        self._slide = self._start_mm.copy()  # (whisker, (u, y)) mm at time self._t
        self._state: list[DynamicState | None] = [None, None]
        self._hist_t = np.zeros(0)
        self._hist_slide = np.zeros((0, 2, 2))
        self._hist_tex = np.zeros((0, 2), dtype=object)
        #: Per whisker, the last simulation's pieces ``(start time, texture)``: a new
        #: piece where the tip crossed onto another tile.
        self.last_segments: list[tuple[tuple[float, str], ...]] = [(), ()]
        #: Per whisker, the fraction of the last simulation's steps in contact.
        self.last_contact_fraction = [float("nan"), float("nan")]

    def textures_at(self, pose: np.ndarray) -> tuple[str, str]:
        """Tile texture under each tip (left, right) at an arena-frame pose ``(3,)``."""
        p = finite_array("pose", pose)
        if p.shape != (3,):
            raise ValueError(f"pose must be (x_m, y_m, heading_rad), got shape {p.shape}")
        left, right = self._tile_names(p[None])[0]
        return str(left), str(right)

    def _tile_names(self, pose: np.ndarray) -> np.ndarray:
        """Texture ``(n, 2)`` under the tips; a tip beyond the walls reads the nearest tile."""
        tips = _tips(pose)
        edge = self.arena.size_m * (1.0 - 1e-9)
        tips = np.clip(tips, 0.0, edge)
        names = self.arena.texture_at(tips[..., 0], tips[..., 1])
        names[names == ""] = self.default_texture
        return names

    def _sheet(self, texture: str) -> SurfaceContact:
        if texture not in self._contacts:
            spec = floor_spec(texture)
            key = floor_names().index(spec.name)
            rng = np.random.default_rng(np.random.SeedSequence([self.seed, 16, 1, key]))
            self._sheets[texture] = make_floor(spec, seed=rng)
            self._contacts[texture] = SurfaceContact(
                self._sheets[texture], angle_deg=self.tilt_deg, stiffness_n_m=spec.stiffness_n_m
            )
        return self._contacts[texture]

    def _plane(self) -> tuple[np.ndarray, np.ndarray]:
        """The pressed floor's base point (x, z; mm) at slide 0 and the u direction (x, z)."""
        if self._base is None:
            n, u, _ = SurfaceContact(
                make_floor("vinyl", tile_u_mm=1.0, tile_w_mm=1.0), angle_deg=self.tilt_deg
            ).frame()
            tip = np.array([0.0, 0.0, self.model.geometry.length_mm])
            self._base = ((tip + n * self.preload_mm)[[0, 2]], u[[0, 2]])
        return self._base

    def settled(
        self, texture: str, slide_mm: Sequence[float] = (0.0, 0.0), sliding_s: float = 0.0
    ) -> DynamicState:
        """The whisker settled on ``texture``, then dragged along ``u`` if ``sliding_s`` > 0.

        It is pressed on from a 2 mm gap over the Roomba's settling time, then (``sliding_s`` >
        0) dragged along ``u`` at FWD speed for ``sliding_s``, ending with the sheet at
        ``slide_mm`` (along u, across y) under the tip. Cached per argument; a copy is returned.
        """
        texture = floor_spec(texture).name
        key = (texture, float(slide_mm[0]), float(slide_mm[1]), float(sliding_s))
        if key not in self._settled:
            contact = self._sheet(texture)
            n = contact.frame()[0]
            base, u = self._plane()
            gap = 2.0 + self.model.geometry.tip_radius_mm
            t = np.linspace(0.0, SETTLE_S, 121)
            away = (gap + self.preload_mm) * (1.0 - np.clip(t / (0.5 * SETTLE_S), 0.0, 1.0))
            along = np.full(t.size, float(slide_mm[0]) - 1e3 * FWD_SPEED_M_S * sliding_s)
            if sliding_s > 0:
                ts = SETTLE_S + np.linspace(0.0, sliding_s, 61)[1:]
                t = np.concatenate([t, ts])
                away = np.concatenate([away, np.zeros(ts.size)])
                along = np.concatenate([along, along[-1] + 1e3 * FWD_SPEED_M_S * (ts - SETTLE_S)])
            pos = base[None] - n[[0, 2]][None] * away[:, None] + u[None] * along[:, None]
            traj = Trajectory(t, pos, lateral_mm=np.full(t.size, float(slide_mm[1])))
            res = simulate(self.model, contact, traj, float(t[-1]), self.dt_s)
            self._settled[key] = res.final_state
        return self._settled[key].copy()

    # ------------------------------------------------------------------ stepping
    def advance(
        self, time_s: np.ndarray, pose: np.ndarray, window_s: float | None = None
    ) -> np.ndarray:
        """Simulate both floor whiskers over one step of the robot.

        Parameters
        ----------
        time_s : ndarray of shape (n,)
            The step's sample times (s), strictly increasing at the sample rate, after
            those of the previous call.
        pose : ndarray of shape (n, 3)
            True arena-frame poses ``(x_m, y_m, heading_rad)`` at those times.
        window_s : float, optional
            ``None``: the whole step, continuing the whiskers' state (the first call
            starts from the whiskers settled at rest). ``w``: only the step's last ``w``
            seconds are valid (the rest NaN), simulated from the whiskers settled and
            sliding, put down :attr:`lead_in_s` before them (the lead-in may reach back
            into the previous steps' poses). A continuous call after a window-mode one
            starts again from the whiskers settled at rest.

        Returns
        -------
        ndarray of shape (n, 2, 2), float32
            Hall outputs (V) ``[sample, whisker (left, right), (x, y)]``.
        """
        t = np.asarray(time_s, dtype=float)
        p = np.asarray(pose, dtype=float)
        if t.ndim != 1:
            raise ValueError(f"time_s must be 1-D, got shape {t.shape}")
        if p.shape != (t.size, 3):
            raise ValueError(f"pose must have shape ({t.size}, 3), got {p.shape}")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(p))):
            raise ValueError("time_s and pose must be finite")
        if window_s is not None:
            positive("window_s", window_s)
        out = np.full((t.size, 2, 2), np.nan, dtype=np.float32)
        if t.size == 0:
            return out
        period = 1.0 / self.sample_rate_hz
        if np.any(np.abs(np.diff(t) - period) > 1e-6 * period):
            raise ValueError(f"time_s must step by one sample period ({period:g} s)")
        first = self._t is None
        if first:
            self._t, self._pose = t[0] - period, p[0].copy()
        elif t[0] <= self._t:
            raise ValueError(
                f"time_s must start after the last call's end ({self._t:g} s), got {t[0]:g} s"
            )
        times = np.concatenate([[self._t], t])
        poses = np.vstack([self._pose, p])
        slide = self._slide[None] + np.concatenate(
            [np.zeros((1, 2, 2)), np.cumsum(_slides(poses), axis=0)]
        )
        tex = self._tile_names(poses)
        if window_s is None:
            for w in range(2):
                state = self._state[w]
                if state is None:
                    state = self.settled(tex[0, w], slide[0, w])
                    state.time_s = float(times[0])
                    state.plane_anchors[:] = 0.0
                out[:, w], self._state[w] = self._run(w, times, slide[:, w], tex[:, w], state)
        else:
            self._state = [None, None]
            out[:] = self._window(t, times, slide, tex, float(window_s))
        self._remember(times, slide, tex, float(window_s or 0.0))
        self._t, self._pose, self._slide = float(t[-1]), p[-1].copy(), slide[-1].copy()
        return out

    def _remember(
        self, times: np.ndarray, slide: np.ndarray, tex: np.ndarray, window_s: float
    ) -> None:
        """Keep the last lead-in + window of slide and texture for window mode."""
        keep = times[-1] - (self.lead_in_s + max(window_s, 0.5) + 1e-9)
        ht = np.concatenate([self._hist_t, times[1:] if self._hist_t.size else times])
        hs = np.concatenate([self._hist_slide, slide[1:] if self._hist_t.size else slide])
        hx = np.concatenate([self._hist_tex, tex[1:] if self._hist_t.size else tex])
        m = ht >= keep
        self._hist_t, self._hist_slide, self._hist_tex = ht[m], hs[m], hx[m]

    def _window(
        self, t: np.ndarray, times: np.ndarray, slide: np.ndarray, tex: np.ndarray, window_s: float
    ) -> np.ndarray:
        """Window mode: lead-in + window from the settled whiskers."""
        out = np.full((t.size, 2, 2), np.nan, dtype=np.float32)
        if self._hist_t.size:
            times = np.concatenate([self._hist_t[:-1], times])
            slide = np.concatenate([self._hist_slide[:-1], slide])
            tex = np.concatenate([self._hist_tex[:-1], tex])
        t_win = t[-1] - window_s
        begin = int(np.searchsorted(times, t_win - self.lead_in_s - 1e-9))
        begin = min(begin, times.size - 2)
        times, slide, tex = times[begin:], slide[begin:], tex[begin:]
        valid = np.arange(t.size) >= t.size - max(1, int(round(window_s * self.sample_rate_hz)))

        def one(w: int) -> None:
            state = self.settled(tex[0, w], sliding_s=SLIDING_S)
            state.time_s = float(times[0])
            state.plane_anchors[:] = 0.0
            # the whisker, settled sliding onto the sheet's origin, is put down where the
            # tip is now, the floor shifted along its normal so the tip presses into it
            # as deep as it did there (on vinyl a micrometre more is a jolt many times
            # the preload); the shift fades out over the lead-in
            lift = self._height_change(tex[0, w], state, slide[0, w])
            fade = np.clip(1.0 - (times - times[0]) / self.lead_in_s, 0.0, 1.0)
            hall, _ = self._run(w, times, slide[:, w], tex[:, w], state, lift * fade)
            # the run may start in an earlier step (the lead-in reaches back into the
            # kept history) or inside this one: align the ends
            n = min(hall.shape[0], t.size)
            out[-n:, w][valid[-n:]] = hall[-n:][valid[-n:]]

        # the two whiskers are independent (each its own noise stream): side by side
        map_threads(one, range(2), default_workers())
        return out

    def _height_change(self, texture: str, state: DynamicState, slide_mm: np.ndarray) -> float:
        """How much lower (mm) the tip-envelope is under the settled tip than at ``slide_mm``.

        Under the settled tip the sheet is at slide 0; the comparison is with the sheet at
        ``slide_mm``.
        """
        contact = self._sheet(texture)
        H = contact.surface_for(self.model)
        dx = contact.surface.spacing_m
        n, u, w = contact.frame()
        base, _ = self._plane()
        tip = state.positions_m[-1]
        heights = []
        for su, sy in ((0.0, 0.0), (float(slide_mm[0]), float(slide_mm[1]))):
            origin = 1e-3 * np.array([base[0] + u[0] * su, sy, base[1] + u[2] * su])
            r = tip - origin
            heights.append(_spline_height(H, dx, float(r @ u), float(r @ w)))
        return 1e3 * (heights[0] - heights[1])

    def _simulate(
        self, contact: SurfaceContact, traj: Trajectory, state: DynamicState
    ) -> SimulationResult:
        """:func:`simulate` over ``traj`` from ``state``, retrying a step that diverges.

        A step that diverges (a tip caught hard on a carpet loop) is retried with the time step
        halved, twice.
        """
        duration = float(traj.time_s[-1] - traj.time_s[0])
        for halving in range(RETRY_HALVINGS + 1):
            try:
                return simulate(
                    self.model, contact, traj, duration, self.dt_s / 2**halving, initial_state=state
                )
            except SimulationError:
                if halving == RETRY_HALVINGS:
                    raise
        raise AssertionError("unreachable")  # pragma: no cover

    def _run(
        self,
        w: int,
        times: np.ndarray,
        slide: np.ndarray,
        tex: np.ndarray,
        state: DynamicState,
        lift_mm: np.ndarray | None = None,
    ) -> tuple[np.ndarray, DynamicState]:
        """Simulate whisker ``w`` over ``times`` (``times[0]`` = the state's time).

        The run is split at texture changes, the floor shifted along its normal by ``lift_mm``;
        returns the Hall volts at ``times[1:]``.
        """
        base, u = self._plane()
        normal = self._sheet(tex[-1]).frame()[0][[0, 2]]
        lift = np.zeros(times.size) if lift_mm is None else lift_mm
        m = times.size - 1
        change = [i - 1 for i in range(2, m + 1) if tex[i] != tex[i - 1]]
        cuts = [0, *change, m]
        tan = np.empty((m, 2))
        segments, touching, steps = [], 0, 0
        for a, b in zip(cuts[:-1], cuts[1:], strict=True):
            if b <= a:
                continue
            seg_t = times[a : b + 1]
            pos = (
                base[None]
                + u[None] * slide[a : b + 1, 0][:, None]
                + normal[None] * lift[a : b + 1, None]
            )
            traj = Trajectory(seg_t, pos, lateral_mm=slide[a : b + 1, 1])
            res = self._simulate(self._sheet(tex[a + 1]), traj, state)
            rows = np.rint((seg_t[1:] - seg_t[0]) / res.dt_s).astype(int)
            tan[a:b] = res.tan_xy[np.minimum(rows, res.tan_xy.shape[0] - 1)]
            state = res.final_state
            segments.append((float(seg_t[0]), str(tex[a + 1])))
            touching += int(np.count_nonzero(res.contact_force_n[1:] > 0))
            steps += res.contact_force_n.size - 1
        self.last_segments[w] = tuple(segments)
        self.last_contact_fraction[w] = touching / max(steps, 1)
        return self.sensor.read(tan, self.sample_rate_hz, self._noise[w]), state


@dataclass(frozen=True)
class TextureCourse:
    """A drive across tiles (figure 6.11).

    Attributes
    ----------
    time_s : ndarray (n,)
    hall_v : ndarray (n, 2, 2) float32
        Hall outputs of the floor whiskers (left, right), V.
    texture_true : ndarray (n, 2) of str
        Tile under each tip at each sample.
    decision_time_s : ndarray (k,)
        End of each 100 ms window classified.
    texture_pred : ndarray (k, 2) of str
        The classifier's choice per window and whisker (``""`` without a classifier).
    loglik : ndarray (k, 2, n_classes)
        Its log-likelihoods (empty without a classifier).
    classes : tuple of str
    """

    time_s: np.ndarray
    hall_v: np.ndarray
    texture_true: np.ndarray
    decision_time_s: np.ndarray
    texture_pred: np.ndarray
    loglik: np.ndarray
    classes: tuple[str, ...] = ()

    @property
    def truth_at_decisions(self) -> np.ndarray:
        """Tile under each tip at the end of each window, ``(k, 2)``."""
        idx = np.searchsorted(self.time_s, self.decision_time_s - 1e-9)
        return self.texture_true[idx]

    def accuracy(self) -> float:
        """Fraction of windows (both whiskers) classified as the tile under the tip."""
        if not self.classes:
            return float("nan")
        return float(np.mean(self.texture_pred == self.truth_at_decisions))


def _line_arena(textures: Sequence[str], start_x_m: float) -> Arena:
    """A square arena of ``len(textures)`` columns of 0.5 m tiles, each column one texture."""
    n = len(textures)
    row = tuple(floor_spec(x).name for x in textures)
    return Arena(
        name="texture-course",
        size_m=0.5 * n,
        start=Pose(start_x_m, 0.25 * n, 0.0),
        tiles=(row,) * n,
    )


def _drive(
    arena: Arena, seconds: float, speed_m_s: float, seed: int, step_s: float = 0.5, **kwargs: object
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Drive straight along +x from the arena's start; time, Hall, truth per sample."""
    fw = FloorWhiskers(arena, seed=seed, **kwargs)  # type: ignore[arg-type]
    fs = fw.sample_rate_hz
    n = int(round(seconds * fs))
    t = np.arange(1, n + 1) / fs
    s = arena.start
    pose = np.column_stack([s.x_m + speed_m_s * t, np.full(n, s.y_m), np.full(n, s.heading_rad)])
    hall = np.empty((n, 2, 2), dtype=np.float32)
    per = max(1, int(round(step_s * fs)))
    for a in range(0, n, per):
        hall[a : a + per] = fw.advance(t[a : a + per], pose[a : a + per])
    return t, hall, fw._tile_names(pose)


def collect_floor_training(
    textures: Sequence[str] = ("vinyl", "smooth-carpet", "rough-carpet"),
    seconds_per_texture: float = 50.0,
    seed: int = 0,
    *,
    speed_m_s: float = FWD_SPEED_M_S,
    window_samples: int = WINDOW_SAMPLES,
    **kwargs: object,
) -> tuple[np.ndarray, np.ndarray]:
    """6.5.2's training data: the robot driven over tiles of one texture at a time.

    "Training data for floor texture discrimination was collected by running the robot
    over lengths of five floor tiles of a single texture": per texture, a straight run at
    FWD speed (50 s at 0.05 m/s cross five 0.5 m tiles), cut into consecutive windows of
    ``window_samples`` of each floor whisker.

    Returns
    -------
    windows : ndarray (n, window_samples, 2)
        Hall x, y of one floor whisker per window (left and right whiskers' windows
        interleaved).
    labels : ndarray (n,) of str
    """
    names = [floor_spec(x).name for x in textures]
    if not names:
        raise ValueError("textures: at least one floor texture is needed")
    T = positive("seconds_per_texture", seconds_per_texture)
    out, labels = [], []
    for k, name in enumerate(names):
        n_tiles = math.ceil((2 * ROBOT_RADIUS_M + speed_m_s * T) / 0.5) + 1
        arena = _line_arena([name] * n_tiles, ROBOT_RADIUS_M + 0.01)
        _, hall, _ = _drive(arena, T, speed_m_s, seed + 7919 * k, **kwargs)
        m = hall.shape[0] // window_samples
        if m == 0:
            raise ValueError(f"seconds_per_texture ({T:g} s) is shorter than one window")
        win = hall[: m * window_samples].reshape(m, window_samples, 2, 2)
        out.append(np.moveaxis(win, 2, 1).reshape(2 * m, window_samples, 2))
        labels += [name] * (2 * m)
    return np.concatenate(out).astype(float), np.array(labels)


def texture_course(
    textures: Sequence[str] = FIGURE_6_11,
    seed: int = 0,
    classifier: object | None = None,
    *,
    speed_m_s: float = FWD_SPEED_M_S,
    seconds: float | None = None,
    decision_s: float = 0.1,
    **kwargs: object,
) -> TextureCourse:
    """Figure 6.11: drive across a line of tiles, classifying every 100 ms.

    Parameters
    ----------
    textures : sequence of str
        The tiles in driving order (figure 6.11: rough carpet, vinyl, rough carpet).
    seed : int
    classifier : FloorTextureNB, optional
        A fitted floor-texture classifier; every ``decision_s`` its :meth:`loglik` is given
        the latest 200 samples of each floor whisker.
    speed_m_s : float
        Forward speed (FWD_1: 0.05 m/s).
    seconds : float, optional
        Driving time; default: until the tips are 50 mm from the far end.
    """
    names = [floor_spec(x).name for x in textures]
    if not names:
        raise ValueError("textures: at least one floor texture is needed")
    arena = _line_arena(names, ROBOT_RADIUS_M + 0.01)
    tip_x = arena.start.x_m + float(FLOOR_WHISKERS_M[0, 0])
    T = seconds if seconds is not None else (arena.size_m - 0.05 - tip_x) / speed_m_s
    t, hall, truth = _drive(arena, positive("seconds", T), speed_m_s, seed, **kwargs)
    fs = 1.0 / (t[1] - t[0])
    every = int(round(decision_s * fs))
    ends = np.arange(max(every, WINDOW_SAMPLES), t.size + 1, every)
    if classifier is None:
        return TextureCourse(
            t, hall, truth, t[ends - 1], np.full((ends.size, 2), ""), np.zeros((ends.size, 2, 0))
        )
    classes = tuple(classifier.classes_)  # type: ignore[attr-defined]
    ll = np.empty((ends.size, 2, len(classes)))
    for i, e in enumerate(ends):
        for w in range(2):
            ll[i, w] = classifier.loglik(hall[e - WINDOW_SAMPLES : e, w])  # type: ignore[attr-defined]
    pred = np.array(classes, dtype=object)[np.argmax(ll, axis=-1)]
    return TextureCourse(t, hall, truth, t[ends - 1], pred, ll, classes)
