"""A whisking head's whisks in the box world: what each whisker meets, and the physics.

:func:`first_contact` sweeps a straight whisker from full retraction to full
protraction about its follicle pivot and finds the first obstacle: with convex boxes
and straight faces, a rotating straight whisker first meets either a face with its tip
("tip"), or a convex box vertex with its shaft ("shaft": thesis 2.5.1, "contacts along
the whisker shaft will be with the corners of objects"); a whisker that already
intersects something at full retraction is "pressed" (the robot must move away).

:func:`whisk` simulates each whisker's whisks on the rod model
(:func:`vibrissa.robots.whisking.run_whisking`, unmodulated) against that object,
built in the whisker's frame (``z`` its rest direction, ``+x`` protraction, the
follicle pivot ``follicle_depth_mm`` behind its base on ``-z``): a corner is a
stationary :class:`~vibrissa.whisker.simulate.PoleContact` whose surface touches the
vertex, a face a stationary textured
:class:`~vibrissa.whisker.simulate.SurfaceContact` plane through it. The Hall output
has the self-motion cancelled as SCRATCHbot's protocol does (6.3): minus the same whisk
in air (noise-free, cached per head), plus the sensor's rest output.

Not modelled: only the first obstacle of each whisker is simulated (a whisker bent
round a corner cannot then touch a second face), and a face is an infinite plane (a
tip sliding along a face cannot slide off its end).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from vibrissa._validate import non_negative
from vibrissa.robots.boxworld.head import HeadPose, WhiskingHead, whisker_frame
from vibrissa.robots.boxworld.scene import BoxWorld
from vibrissa.robots.whisking import WhiskerSetup, WhiskPattern, motor_follow
from vibrissa.whisker.geometry import preset
from vibrissa.whisker.hall import HallSensor
from vibrissa.whisker.rod import RodModel
from vibrissa.whisker.simulate import (
    BaseMotion,
    PoleContact,
    SurfaceContact,
    Trajectory,
    simulate,
)
from vibrissa.whisker.surfaces import Surface, make_surface

__all__ = [
    "CONTACT_KINDS",
    "ContactGeometry",
    "WhiskRecord",
    "can_move",
    "first_contact",
    "whisk",
]

#: The kinds of :class:`ContactGeometry`.
CONTACT_KINDS = ("tip", "shaft", "pressed")

_EPS = 1e-9


@dataclass(frozen=True)
class ContactGeometry:
    """The first obstacle a straight whisker meets in a protraction.

    Attributes
    ----------
    kind
        "tip" (the tip meets a face), "shaft" (the shaft meets a convex box vertex) or
        "pressed" (at full retraction the whisker already crosses a solid, or its
        pivot is inside one, or its root runs into a face during the protraction).
    whisker
        The whisker's index.
    sweep_deg
        The housing's angle from full retraction at the contact (0 when pressed at
        rest; where the root meets the face when it runs into one).
    radial_distance_mm
        Distance along the whisker from its base to the contact (its length for a tip;
        NaN when pressed).
    point_mm
        The contact point in the world (x, y) mm (NaN when pressed).
    face
        For a tip, the index of the face into ``world.faces``; for a shaft, the two
        faces adjoining the vertex; for pressed, the faces crossed (may be empty).
    texture
        The face's texture (tip), else None.
    surface_angle_deg
        Tip: the face's angle to the whisker's rest axis ``z`` in the convention of
        :attr:`SurfaceContact.angle_deg` (in [-90, 90]); NaN otherwise.
    surface_side
        Tip: the :attr:`SurfaceContact.side` of the face in the whisker frame (-1: it
        faces ``-x``); 0 otherwise.
    world_face_direction_deg
        Tip: the face's orientation in the world (deg mod 180); NaN otherwise.
    corner
        Shaft: index into ``world.corners()``; -1 otherwise.
    """

    kind: str
    whisker: int
    sweep_deg: float
    radial_distance_mm: float
    point_mm: tuple[float, float]
    face: int | tuple[int, ...]
    texture: str | None = None
    surface_angle_deg: float = math.nan
    surface_side: int = 0
    world_face_direction_deg: float = math.nan
    corner: int = -1


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _segments_cross(p: np.ndarray, q: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Which segments ``a[k] b[k]`` touch or cross the segment ``p q`` (closed)."""
    r = q - p
    s = b - a
    den = _cross(r, s)
    ap = a - p
    with np.errstate(divide="ignore", invalid="ignore"):
        t = _cross(ap, s) / den
        u = _cross(ap, r) / den
    hit = (np.abs(den) > _EPS) & (t >= -_EPS) & (t <= 1 + _EPS) & (u >= -_EPS) & (u <= 1 + _EPS)
    # collinear overlaps
    col = (np.abs(den) <= _EPS) & (np.abs(_cross(ap, r)) <= _EPS * max(1.0, float(r @ r)))
    if np.any(col):
        rr = float(r @ r)
        t0 = (ap @ r) / rr
        t1 = ((b - p) @ r) / rr
        lo, hi = np.minimum(t0, t1), np.maximum(t0, t1)
        hit |= col & (hi >= -_EPS) & (lo <= 1 + _EPS)
    return hit


_NAN2 = (math.nan, math.nan)


def _arc_meets_faces(
    world: BoxWorld, centre: np.ndarray, z: np.ndarray, x: np.ndarray, radius: float, amp: float
) -> list[tuple[int, np.ndarray, float]]:
    """Where the arc of ``radius`` about the pivot, swept from 0 to ``amp``, meets a face.

    Only crossings where the point on the arc moves into the face (from its free side)
    count. Returns ``(face index, point, housing angle rad)`` for each.
    """
    a, b = world.face_segments()
    out = []
    for k in range(a.shape[0]):
        d = b[k] - a[k]
        f = a[k] - centre
        qa, qb, qc = d @ d, 2.0 * (f @ d), f @ f - radius * radius
        disc = qb * qb - 4 * qa * qc
        if disc < 0.0:
            continue
        sq = math.sqrt(disc)
        n = world.faces[k].normal
        for t in ((-qb - sq) / (2 * qa), (-qb + sq) / (2 * qa)):
            if not -_EPS <= t <= 1 + _EPS:
                continue
            q = a[k] + t * d
            rq = q - centre
            th = math.atan2(float(rq @ x), float(rq @ z))
            if not 0.0 < th <= amp:
                continue
            vel = -math.sin(th) * z + math.cos(th) * x  # the point's direction of motion
            if float(n @ vel) >= 0.0:
                continue  # leaving the face, not meeting it
            out.append((k, q, th))
    return out


def _geometry(pose: HeadPose, head: WhiskingHead, i: int) -> tuple[np.ndarray, ...]:
    base, z, x = whisker_frame(pose, head, i)
    depth = float(preset(head.whisker).follicle_depth_mm)
    return base, z, x, base - depth * z, depth


def first_contact(
    world: BoxWorld, pose: HeadPose, head: WhiskingHead, i: int
) -> ContactGeometry | None:
    """The first obstacle whisker ``i`` (straight) meets from full retraction to protraction.

    The whisker turns about its follicle pivot (``follicle_depth_mm`` behind its base);
    its tip's arc may meet a face (approaching it from its free side), its shaft a
    convex box vertex; the smallest housing angle wins. None: the whisk is in air.

    Parameters
    ----------
    world, pose, head
        The scene, the head's pose and the head.
    i
        The whisker's index.

    Returns
    -------
    ContactGeometry or None
    """
    base, z, x, centre, depth = _geometry(pose, head, i)
    L = head.length_mm
    amp = math.radians(head.amplitude_deg)
    a, b = world.face_segments()
    tip = base + L * z
    if world.inside(base) or world.inside(centre):
        return ContactGeometry("pressed", i, 0.0, math.nan, (math.nan, math.nan), ())
    crossed = np.flatnonzero(_segments_cross(base, tip, a, b)) if a.shape[0] else []
    if len(crossed):
        return ContactGeometry(
            "pressed", i, 0.0, math.nan, (math.nan, math.nan), tuple(int(k) for k in crossed)
        )
    best: tuple[float, ContactGeometry] | None = None
    # the shaft meets a convex box vertex
    corners = world.corners()
    if corners.shape[0]:
        rel = corners - centre
        rad = np.linalg.norm(rel, axis=1)
        ang = np.arctan2(rel @ x, rel @ z)
        ok = (rad > depth) & (rad < depth + L) & (ang > 0.0) & (ang <= amp)
        faces = world.corner_faces()
        for k in np.flatnonzero(ok):
            th = float(ang[k])
            if best is None or th < best[0]:
                best = (
                    th,
                    ContactGeometry(
                        "shaft",
                        i,
                        math.degrees(th),
                        float(rad[k] - depth),
                        (float(corners[k, 0]), float(corners[k, 1])),
                        faces[k],
                        corner=int(k),
                    ),
                )
    faces_all = world.faces
    # the whisker's root (its base, radius depth about the pivot) runs into a face: the
    # head is against the obstacle, the whisker pressed from there on
    for k, _q, th in _arc_meets_faces(world, centre, z, x, depth, amp):
        if best is None or th < best[0]:
            best = (th, ContactGeometry("pressed", i, math.degrees(th), math.nan, _NAN2, (k,)))
    # the tip's arc (radius depth + L about the pivot) meets a face
    for k, q, th in _arc_meets_faces(world, centre, z, x, depth + L, amp):
        if best is not None and th >= best[0]:
            continue
        n = faces_all[k].normal
        nx, nz = float(n @ x), float(n @ z)
        side = 1 if nx > 0.0 else -1
        angle = math.degrees(math.asin(min(1.0, max(-1.0, -nz))))
        best = (
            th,
            ContactGeometry(
                "tip",
                i,
                math.degrees(th),
                L,
                (float(q[0]), float(q[1])),
                int(k),
                faces_all[k].texture,
                angle,
                side,
                faces_all[k].direction_deg,
            ),
        )
    return None if best is None else best[1]


@dataclass
class WhiskRecord:
    """The whisks of every whisker of the head at one pose.

    Attributes
    ----------
    time_s : ndarray, shape (n,)
        Sample times from the start of the first whisk (s).
    hall_v : ndarray, shape (n, n_whiskers, 2)
        Hall x, y (V) after self-motion cancellation (minus the same whisk in air, plus
        the sensor's rest output), noise on.
    contacts : list of ContactGeometry or None
        Each whisker's :func:`first_contact`.
    truth_onsets_s, truth_ends_s : ndarray, shape (n_whiskers, n_whisks)
        Per whisker and whisk, the first and last time the simulated contact force is
        above zero within the whisk (NaN: no contact).
    contact_force_n : ndarray, shape (n, n_whiskers)
        The simulated contact force at the samples (N).
    pose : HeadPose
    sample_rate_hz : float
    rest_v : float
        The sensor's rest output (V).
    """

    time_s: np.ndarray
    hall_v: np.ndarray
    contacts: list[ContactGeometry | None]
    truth_onsets_s: np.ndarray
    truth_ends_s: np.ndarray
    contact_force_n: np.ndarray
    pose: HeadPose
    sample_rate_hz: float
    rest_v: float


@lru_cache(maxsize=8)
def _model(whisker: str, n_elements: int) -> RodModel:
    return RodModel(preset(whisker), n_elements)


@lru_cache(maxsize=8)
def _sensor(head: WhiskingHead) -> HallSensor:
    return head.hall.calibrate(preset(head.whisker), head.n_elements)


@lru_cache(maxsize=32)
def _sheet(texture: str, face: int) -> Surface:
    """The physical sheet covering face ``face`` (one fixed sheet per face, cached)."""
    return make_surface(texture, seed=np.random.default_rng([face, 7919]))


def _housing(
    head: WhiskingHead, n_whisks: int, reflex_s: tuple[float, ...] | None = None
) -> BaseMotion:
    """The housing's angle over ``n_whisks`` whisks from rest, as ``run_whisking`` drives it.

    The unmodulated pattern (full retraction at 0 in the whisker's frame) followed by
    the critically damped servo (:func:`vibrissa.robots.whisking.motor_follow`). With
    ``reflex_s`` (one time per whisk, NaN: no reflex in that whisk) the command returns to
    full retraction from that time to the whisk's end (RCP at saturating gain).
    """
    pattern = WhiskPattern(head.frequency_hz, head.amplitude_deg, 0.0)
    n_steps = int(round(n_whisks * head.period_s / head.dt_s))
    t = np.arange(n_steps + 1) * head.dt_s
    command = pattern.command_deg(t[:-1], 0.0)
    if reflex_s is not None:
        for w, tr in enumerate(reflex_s):
            if math.isfinite(tr):
                cut = (t[:-1] >= tr) & (t[:-1] < (w + 1) * head.period_s)
                command = np.where(cut, 0.0, command)
    ang, rate = motor_follow(command, head.dt_s, head.motor_bandwidth_hz, (0.0, 0.0))
    return BaseMotion(t, np.radians(ang), np.radians(rate))


def _reflex_times(
    head: WhiskingHead, contacts: list[ContactGeometry | None], n_whisks: int
) -> tuple[float, ...] | None:
    """Per whisk, when the row's reflex retracts it: first touch of any whisker + latency.

    The first touch is when the unmodulated housing reaches the straight whisker's contact
    angle (before it touches, a whisker is undeflected but for its own inertia).
    """
    if head.reflex_latency_s is None:
        return None
    touching = [c.sweep_deg for c in contacts if c is not None and c.kind in ("tip", "shaft")]
    if not touching:
        return None
    free = _housing(head, n_whisks)
    first = math.radians(min(touching))
    per = head.period_s
    out = []
    for w in range(n_whisks):
        sel = (free.time_s >= w * per) & (free.time_s < (w + 1) * per)
        hit = np.flatnonzero(free.angle_rad[sel] >= first)
        out.append(
            float(free.time_s[sel][hit[0]] + head.reflex_latency_s) if hit.size else math.nan
        )
    return tuple(out)


def _contact_windows(bm: BaseMotion, c: ContactGeometry) -> list[tuple[int, int]]:
    """Step ranges in which whisker and object may touch (the object is left out elsewhere).

    From ``margin`` before the straight whisker's contact angle in each protraction to
    ``margin`` below it again in the retraction (``margin``: the larger of 3 deg and
    the angle 5 mm subtends at the contact).
    """
    margin = max(math.radians(3.0), 5.0 / max(c.radial_distance_mm, 1.0))
    near = bm.angle_rad >= math.radians(c.sweep_deg) - margin
    edges = np.flatnonzero(np.diff(near.astype(np.int8)))
    starts = [int(e) for e in edges if near[e + 1]]
    ends = [int(e) + 1 for e in edges if not near[e + 1]]
    if near[0]:
        starts.insert(0, 0)
    if len(ends) < len(starts):
        ends.append(near.size - 1)
    return list(zip(starts, ends, strict=True))


def _simulate(
    head: WhiskingHead,
    setup: WhiskerSetup,
    c: ContactGeometry | None,
    n_whisks: int,
    reflex_s: tuple[float, ...] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """One whisker's continuous run: magnet tangents ``(n_steps + 1, 2)`` and contact force.

    The housing is driven as :func:`~vibrissa.robots.whisking.run_whisking` drives it
    unmodulated. Outside the contact windows (:func:`_contact_windows`) the object is
    left out, so the whisker advances in its linear modes (the linear free flight of
    :func:`~vibrissa.whisker.simulate.simulate`); within them the rod meets the
    object (a surface contact runs the nonlinear rod throughout its window).
    ``run_whisking`` integrates every step nonlinearly, about 10 times slower.
    """
    bm = _housing(head, n_whisks, reflex_s)
    n_steps = bm.time_s.size - 1
    tan = np.zeros((n_steps + 1, 2))
    force = np.zeros(n_steps + 1)
    windows = [] if setup.contact is None or c is None else _contact_windows(bm, c)
    plan: list[tuple[int, int, bool]] = []
    k = 0
    for a, b in windows:
        if a > k:
            plan.append((k, a, False))
        plan.append((a, b, True))
        k = b
    if k < n_steps:
        plan.append((k, n_steps, False))
    state = None
    for a, b, touch in plan:
        if b <= a:
            continue
        res = simulate(
            setup.model,
            setup.contact if touch else None,
            setup.trajectory if touch else None,
            (b - a) * head.dt_s,
            head.dt_s,
            initial_state=state,
            base_motion=bm,
        )
        m = min(res.time_s.size, n_steps + 1 - a)
        tan[a : a + m] = res.tan_xy[:m]
        force[a : a + m] = res.contact_force_n[:m]
        state = res.final_state
    return tan, force


@lru_cache(maxsize=64)
def _air_tan(
    head: WhiskingHead, n_whisks: int, reflex_s: tuple[float, ...] | None = None
) -> np.ndarray:
    """The magnet's tangents ``(n_steps + 1, 2)`` of the same commanded whisks in air (cached).

    The robot's prediction of its own whisking (its efference copy of the command, with the
    reflex when there was one).
    """
    model = _model(head.whisker, head.n_elements)
    tan, _ = _simulate(head, WhiskerSetup(model), None, n_whisks, reflex_s)
    tan.setflags(write=False)
    return tan


def _setup(
    world: BoxWorld,
    pose: HeadPose,
    head: WhiskingHead,
    c: ContactGeometry | None,
    model: RodModel,
    gain_v: float,
    rng: np.random.Generator,
) -> WhiskerSetup:
    """Whisker ``c.whisker``'s object in its frame (None or pressed: in air)."""
    if c is None or c.kind not in ("tip", "shaft"):
        return WhiskerSetup(model, hall_gain_v=gain_v)
    base, z, x, _, _ = _geometry(pose, head, c.whisker)

    def local(p: np.ndarray) -> np.ndarray:
        r = np.asarray(p, dtype=float) - base
        return np.array([r @ x, r @ z])

    t = np.array([0.0, 1e6])
    if c.kind == "shaft":
        f1, f2 = c.face  # type: ignore[misc]
        n = world.faces[f1].normal + world.faces[f2].normal
        centre = np.asarray(c.point_mm) - head.pole_radius_mm * n / np.linalg.norm(n)
        p = local(centre)
        return WhiskerSetup(
            model,
            PoleContact(radius_mm=head.pole_radius_mm),
            Trajectory(t, np.array([p, p])),
            0,
            gain_v,
        )
    k = int(c.face)  # type: ignore[arg-type]
    face = world.faces[k]
    contact = SurfaceContact(
        _sheet(face.texture, k), angle_deg=c.surface_angle_deg, side=c.surface_side
    )
    # a random place on the sheet (the plane itself is the face's): each whisk meets
    # different grains, as the chapter-5 protocol's trials do
    p = local(np.asarray(c.point_mm)) + contact.frame()[1][[0, 2]] * rng.uniform(0.0, 8.0)
    lateral = np.full(2, rng.uniform(0.0, 2.0))
    return WhiskerSetup(
        model, contact, Trajectory(t, np.array([p, p]), lateral_mm=lateral), 0, gain_v
    )


def whisk(
    world: BoxWorld,
    pose: HeadPose,
    head: WhiskingHead,
    rng: np.random.Generator | int,
    n_whisks: int = 1,
) -> WhiskRecord:
    """Whisk every whisker of ``head`` at ``pose`` for ``n_whisks`` periods, from rest.

    Parameters
    ----------
    world, pose, head
        The scene, where the head is and the head.
    rng
        Generator (or seed) of the sensor noise and of where on a face's sheet a tip lands.
    n_whisks
        Whisks, one continuous run per whisker.

    Returns
    -------
    WhiskRecord
    """
    if isinstance(n_whisks, bool) or not isinstance(n_whisks, int) or n_whisks < 1:
        raise ValueError(f"n_whisks must be a positive integer, got {n_whisks!r}")
    gen = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
    sensor = _sensor(head)
    model = _model(head.whisker, head.n_elements)
    contacts = [first_contact(world, pose, head, i) for i in range(head.n_whiskers)]
    setups = [_setup(world, pose, head, c, model, sensor.gain_v, gen) for c in contacts]
    rate = 1.0 / head.dt_s
    reflex = _reflex_times(head, contacts, n_whisks)
    air_tan = _air_tan(head, n_whisks, reflex)
    air = sensor.read(air_tan, rate)  # the prediction of the whisk, noise-free
    n = air.shape[0]
    step = int(round(rate / head.sample_rate_hz))
    hall = np.empty((n, head.n_whiskers, 2))
    force = np.zeros((n, head.n_whiskers))
    onsets = np.full((head.n_whiskers, n_whisks), math.nan)
    ends = np.full((head.n_whiskers, n_whisks), math.nan)
    per = int(round(head.period_s / head.dt_s))
    for i, (s, c) in enumerate(zip(setups, contacts, strict=True)):
        if s.contact is None:
            volts = sensor.read(air_tan, rate, gen)
        else:
            tan, f = _simulate(head, s, c, n_whisks, reflex)
            volts = sensor.read(tan, rate, gen)
            force[:, i] = f[::step][:n]
            for w in range(n_whisks):
                on = np.flatnonzero(f[w * per : (w + 1) * per + 1] > 0.0)
                if on.size:
                    onsets[i, w] = (w * per + on[0]) * head.dt_s
                    ends[i, w] = (w * per + on[-1]) * head.dt_s
        hall[:, i, :] = volts - air + sensor.offset_v
    t = np.arange(n) / head.sample_rate_hz
    return WhiskRecord(
        t, hall, contacts, onsets, ends, force, pose, float(head.sample_rate_hz), sensor.offset_v
    )


def can_move(
    world: BoxWorld,
    pose: HeadPose,
    head: WhiskingHead,
    new_pose: HeadPose,
    margin_mm: float = 10.0,
) -> bool:
    """Whether the head can move straight from ``pose`` to ``new_pose``.

    Along the segment (position and heading interpolated, in steps of at most half the
    margin and 2 deg) the body (a disc of ``head.body_radius_mm`` about the head's
    origin) and every whisker's base and follicle pivot keep ``margin_mm`` clear of
    every solid. The whiskers are retracted while moving and are not checked; a
    whisker crossing a solid at the new pose makes the next whisk "pressed".
    """
    m = non_negative("margin_mm", margin_mm)
    dist = math.dist((pose.x_mm, pose.y_mm), (new_pose.x_mm, new_pose.y_mm))
    turn = new_pose.heading_deg - pose.heading_deg
    n = max(1, int(math.ceil(dist / max(0.5 * m, 1.0))), int(math.ceil(abs(turn) / 2.0)))
    for k in range(n + 1):
        u = k / n
        p = HeadPose(
            pose.x_mm + u * (new_pose.x_mm - pose.x_mm),
            pose.y_mm + u * (new_pose.y_mm - pose.y_mm),
            pose.heading_deg + u * turn,
        )
        if world.clearance_mm((p.x_mm, p.y_mm)) < head.body_radius_mm + m:
            return False
        for i in range(head.n_whiskers):
            base, _, _, centre, _ = _geometry(p, head, i)
            if world.clearance_mm(base) < m or world.clearance_mm(centre) < m:
                return False
    return True
