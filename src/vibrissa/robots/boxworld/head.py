"""A whisking head for the box world: its pose, its whiskers and their frames.

The thesis gives SCRATCHbot's head only in outline (3.2: rows of whiskers on each side
of a head on a neck, whisked by the pattern generator), so the values here are chosen
and documented in :class:`WhiskingHead`. Each whisker whisks in the horizontal plane
about its pivot; its frame is the rod model's (:mod:`vibrissa.whisker.simulate`): ``z``
is the whisker's direction at full retraction, ``+x`` the direction of protraction.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from vibrissa._validate import finite, in_range, positive
from vibrissa.whisker.geometry import PRESETS, preset
from vibrissa.whisker.hall import HallSettings

__all__ = ["HeadPose", "WhiskingHead", "whisker_frame"]


@dataclass(frozen=True)
class HeadPose:
    """Where the head is: the origin of its frame (mm) and its heading (deg, CCW from +x)."""

    x_mm: float = 0.0
    y_mm: float = 0.0
    heading_deg: float = 0.0

    def __post_init__(self) -> None:
        finite("x_mm", self.x_mm)
        finite("y_mm", self.y_mm)
        finite("heading_deg", self.heading_deg)

    @property
    def position_mm(self) -> np.ndarray:
        """``(x, y)`` in mm."""
        return np.array([self.x_mm, self.y_mm], dtype=float)

    def to_world(self, forward_mm: float, left_mm: float) -> np.ndarray:
        """A point of the head frame (forward, left) in world mm."""
        h = math.radians(self.heading_deg)
        c, s = math.cos(h), math.sin(h)
        return np.array(
            [self.x_mm + c * forward_mm - s * left_mm, self.y_mm + s * forward_mm + c * left_mm]
        )

    def moved(self, forward_mm: float, left_mm: float = 0.0, turn_deg: float = 0.0) -> HeadPose:
        """The pose after moving by (forward, left) in the head's frame, then turning."""
        p = self.to_world(finite("forward_mm", forward_mm), finite("left_mm", left_mm))
        return HeadPose(float(p[0]), float(p[1]), self.heading_deg + finite("turn_deg", turn_deg))

    def translated(self, dx_mm: float, dy_mm: float) -> HeadPose:
        """The pose shifted by (dx, dy) in world mm, heading unchanged."""
        return HeadPose(
            self.x_mm + finite("dx_mm", dx_mm), self.y_mm + finite("dy_mm", dy_mm), self.heading_deg
        )


@dataclass(frozen=True)
class WhiskingHead:
    """A head with one row of whiskers on one side, whisked together.

    Parameters
    ----------
    whisker
        Whisker preset (:data:`vibrissa.whisker.geometry.PRESETS`). Default
        ``"xy-robot"``: the 185 mm ABS whisker of chapters 4-5, so that those chapters'
        classifiers can be tried on this head.
    n_whiskers
        Whiskers in the row (default 3, as a G1 row, 3.4.1).
    side
        -1: the row is on the right of the heading; +1: on the left.
    pivots_mm
        Each whisker's pivot in the head frame, (forward, lateral) in mm, the lateral
        distance measured toward ``side``. Default (0, 40), (35, 40), (70, 40): a row
        along a 40 mm-wide snout, 35 mm apart (chosen: SCRATCHbot's head is given only
        in outline, 3.2; the spacing keeps neighbouring 185 mm whiskers' sweeps
        overlapping).
    retracted_deg
        Each whisker's direction at full retraction, in degrees from the heading toward
        ``side`` (default 110, 100, 90 for the rear, middle and front whisker: sideways
        and somewhat back, fanned so that the row covers 50-110 deg). Must lie in
        (0, 180).
    amplitude_deg
        Whisk amplitude (default 40 deg): full protraction points ``retracted_deg -
        amplitude_deg`` from the heading (50-70 deg, forward of sideways). Must stay
        below ``retracted_deg`` and 80 deg (the pattern generator's limit).
    frequency_hz
        Whisk frequency; one whisk is one period (default 0.5 Hz). The housing's
        rate is ``pi f A sin(phase)`` at most ``pi f A`` = 1.10 rad/s with 40 deg;
        a contact at radial distance r moves at that times r: at most 88 mm/s at 80 mm
        and 203 mm/s at 185 mm (the tip), so contacts from 80 mm (the closest without
        saturating the sensor, 4.2) to the tip fall within chapter 4's 36-216 mm/s
        wherever the whisk is faster than 0.45 rad/s (all but the first and last 2 deg
        of the sweep at 80 mm). At 1 Hz tip contacts would reach 405 mm/s, which
        chapter 4 found makes the whisker slip past or saturate (4.2).
    sample_rate_hz
        Hall sampling rate (default 4 kHz, chapter 5's; chapter 4 used 1 kHz).
    dt_s
        The rod's internal step (default 2.5e-4 s, 4 kHz: must divide the sample
        period; chapter 5's protocol used 1.25e-4 s).
    n_elements
        Rod elements of the whisker model (default 28, the protocols' default).
    hall
        The Hall sensor's set-up (noise on; its sample rate is replaced by
        ``sample_rate_hz``). Default: :class:`HallSettings` calibrated at (80 mm,
        60 mm), chapter 4's session calibration (the closest contacts must not saturate).
    pole_radius_mm
        Radius of the pole standing for a square corner's edge (0.5 mm, the pole of 6.3).
    motor_bandwidth_hz
        The housing servo's bandwidth (:func:`vibrissa.robots.whisking.run_whisking`).
    body_radius_mm
        Radius of the robot's body about the head's origin, for :func:`can_move`
        (default 50 mm).
    reflex_latency_s
        Rapid cessation of protraction (3.4, eqs. 3.2-3.3), modelled as a reflex: this
        long after the first whisker of the row touches, the row's command returns to
        full retraction for the rest of the whisk (``z`` at 1); the servo follows.
        ``None``: unmodulated whisking, every contact pushed to full protraction.
        Default 0.3 s: the XY robot's minimal-impingement loop, which retracts "~300 ms
        from initial contact" (3.3.2; :mod:`vibrissa.robots.xy_stage`), so that a contact
        on this head lasts about as long as the chapter-4/5 contacts whose classifiers the
        framework uses. Measured on 160 calibration whisks (single-contact MiniRocket,
        4-fold cross-validation): a 0.1 s reflex gave texture 0.43 and angle 0.72 right
        (peak deflection 0.24 V), 0.3 s gave 0.78 and 0.70 (0.37 V); a 20 ms reflex (the
        50 Hz contact filter's delay) left 5 of 24 whisks with a contact above the 0.1 V
        detection threshold. Unmodulated whisking costs about four times the simulation
        per contact, the tip sliding on for the whole protraction.
    """

    whisker: str = "xy-robot"
    n_whiskers: int = 3
    side: int = -1
    pivots_mm: tuple[tuple[float, float], ...] = ((0.0, 40.0), (35.0, 40.0), (70.0, 40.0))
    retracted_deg: tuple[float, ...] = (110.0, 100.0, 90.0)
    amplitude_deg: float = 40.0
    frequency_hz: float = 0.5
    sample_rate_hz: float = 4000.0
    dt_s: float = 2.5e-4
    n_elements: int = 28
    hall: HallSettings = dataclasses.field(
        default_factory=lambda: HallSettings(calibration_mm=(80.0, 60.0))
    )
    pole_radius_mm: float = 0.5
    motor_bandwidth_hz: float = 20.0
    body_radius_mm: float = 50.0
    reflex_latency_s: float | None = 0.3

    def __post_init__(self) -> None:
        if self.whisker not in PRESETS:
            raise ValueError(f"whisker must be one of {', '.join(PRESETS)}, got {self.whisker!r}")
        n = self.n_whiskers
        if isinstance(n, bool) or not isinstance(n, int) or n < 1:
            raise ValueError(f"n_whiskers must be a positive integer, got {n!r}")
        if self.side not in (1, -1):
            raise ValueError(f"side must be +1 or -1, got {self.side!r}")
        piv = tuple((float(a), float(b)) for a, b in self.pivots_mm)
        ret = tuple(float(r) for r in self.retracted_deg)
        if len(piv) != n:
            raise ValueError(f"pivots_mm must give {n} pivots (n_whiskers), got {len(piv)}")
        if len(ret) != n:
            raise ValueError(f"retracted_deg must give {n} angles (n_whiskers), got {len(ret)}")
        for p in piv:
            finite("pivots_mm", p[0])
            finite("pivots_mm", p[1])
        a = positive("amplitude_deg", self.amplitude_deg)
        if a >= 80.0:
            raise ValueError(f"amplitude_deg must be below 80 deg, got {a!r}")
        for r in ret:
            in_range("retracted_deg", r, 0.0, 180.0, "deg")
            if r - a <= 0.0:
                raise ValueError(
                    f"amplitude_deg ({a:g}) must be below every retracted_deg ({r:g}): "
                    "a whisker may not protract across the heading"
                )
        in_range("frequency_hz", self.frequency_hz, 1e-3, 20.0, "Hz")
        positive("sample_rate_hz", self.sample_rate_hz)
        positive("dt_s", self.dt_s)
        if not isinstance(self.hall, HallSettings):
            raise TypeError(f"hall must be a HallSettings, got {type(self.hall).__name__}")
        positive("pole_radius_mm", self.pole_radius_mm)
        positive("motor_bandwidth_hz", self.motor_bandwidth_hz)
        positive("body_radius_mm", self.body_radius_mm)
        if self.reflex_latency_s is not None:
            in_range("reflex_latency_s", self.reflex_latency_s, 0.0, 0.5 * self.period_s, "s")
        object.__setattr__(self, "pivots_mm", piv)
        object.__setattr__(self, "retracted_deg", ret)
        object.__setattr__(
            self, "hall", dataclasses.replace(self.hall, sample_rate_hz=self.sample_rate_hz)
        )

    @property
    def length_mm(self) -> float:
        """The whisker's length (mm)."""
        return float(preset(self.whisker).length_mm)

    @property
    def period_s(self) -> float:
        """One whisk (s)."""
        return 1.0 / self.frequency_hz


def whisker_frame(
    pose: HeadPose, head: WhiskingHead, i: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Whisker ``i``'s pivot (world mm) and its frame's axes in the world.

    Returns
    -------
    pivot_mm, z, x : ndarray, shape (2,)
        The pivot; the unit direction of the whisker at full retraction (the frame's
        ``z``); the unit direction of protraction (the frame's ``+x``).
    """
    if isinstance(i, bool) or not isinstance(i, int | np.integer) or not 0 <= i < head.n_whiskers:
        raise ValueError(f"whisker index i must lie in [0, {head.n_whiskers - 1}], got {i!r}")
    fwd, lat = head.pivots_mm[i]
    pivot = pose.to_world(fwd, head.side * lat)
    ang = math.radians(pose.heading_deg + head.side * head.retracted_deg[i])
    z = np.array([math.cos(ang), math.sin(ang)])
    # protraction turns the whisker toward the heading: counter-clockwise on the right
    # (side -1), clockwise on the left
    s = -head.side
    x = np.array([-s * z[1], s * z[0]])
    return pivot, z, x
