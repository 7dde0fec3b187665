"""The BIOTACT G1 head (thesis 3.4, 6.4): a cone with two rows of three whiskers.

The thesis gives the whisker lengths (80, 112 and 158 mm, "increased from front to
rear in order that all whiskers could touch a plane surface orthogonal to the axis
of the cone", 3.4.1), the two bilaterally symmetric rows in a horizontal plane and
the surface's horizontal (axial) distance from the front of the head (5, 10, 15 mm,
6.4.1); not the cone's size nor where on it the whiskers stand. Chosen here
(:class:`G1Head`), physical and documented:

* a truncated cone of half angle 22.5 deg with a 15 mm front radius;
* each row's whisker pivots 30, 46 and 69 mm behind the front face (on the cone,
  at radii 27.4, 34.1 and 43.6 mm), spaced in proportion to the length steps
  (32 and 46 mm) times cos 60 deg: with the surface 10 mm ahead, every straight
  whisker's tip reaches the plane when it points 60 deg from the axis, so the three
  touch it together, as the thesis designed (at 5 and 15 mm within about 2 deg of each
  other);
* full retraction points a whisker 85 deg from the axis (nearly sideways), the
  35 deg whisk protracts it to 50 deg; the middle of the whisk (67.5 deg) is square
  to the cone's surface (90 - 22.5 deg), "oriented outwards from the cone surface".

Each whisker whisks in the horizontal plane, its own x-z plane: ``z`` is its
direction at full retraction and ``+x`` the protraction, so the head's axis is
``F = (sin 85 deg, 0, cos 85 deg)`` and the vertical surface ahead is a
:class:`~vibrissa.whisker.simulate.SurfaceContact` at 5 deg to ``z`` facing ``-x``
(``side=-1``), its base plane ``setback + distance`` along ``F`` from the pivot.
Whiskers do not touch each other or the cone in this geometry (the rear whiskers
stand further out and point the same way); the model does not check it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vibrissa._validate import finite, positive
from vibrissa.robots.whisking import WhiskerSetup
from vibrissa.whisker.rod import RodModel
from vibrissa.whisker.simulate import SurfaceContact, Trajectory
from vibrissa.whisker.surfaces import Surface

__all__ = ["G1_CONTACT_SIGNAL_SCALE", "G1Head"]

#: RCP's contact-signal scale on the G1 (``RCPControl.signal_scale``, see
#: :data:`vibrissa.robots.whisking.CONTACT_SIGNAL_SCALE`). Identified by
#: scripts/identify_rcp.py (docs/runs/identify_rcp.json, ``g1_chosen``): SCRATCHbot's
#: scale (from figure 3.9's outcomes) makes the G1's loop run away on these longer
#: whiskers (z pinned at 1 by the whiskers' own ringing, RCP7 and RCP9 rows that never
#: reach the surface at 15 mm), against 6.4, where RCP whisks touch and are classified,
#: and 3.4.2 (no biphasic whisk at sigma_z <= 0.9, tau_z T_w/4). The G1 takes the scale
#: nearest SCRATCHbot's at which every row touches in every whisk and no whisk is
#: biphasic under RCP7 and RCP9 (that record's ``g1_check`` lists the grid scales that
#: hold). Identified again after the closed loop stopped reading a zero housing rate at
#: the end of most control periods (issue 32): 2.25, was 2.0.
G1_CONTACT_SIGNAL_SCALE = 2.25


@dataclass(frozen=True)
class G1Head:
    """One row's geometry of the G1 head (the other row is its mirror image).

    Parameters
    ----------
    lengths_mm
        Whisker lengths, front to rear (thesis: 80, 112, 158 mm).
    setbacks_mm
        Axial distance of each whisker's pivot behind the head's front face (mm).
    cone_half_angle_deg, front_radius_mm
        The truncated cone (its front face's radius).
    retracted_deg
        Whisker direction at full retraction, from the head's axis (deg).
    amplitude_deg
        Whisk amplitude (deg): full protraction points ``retracted_deg -
        amplitude_deg`` from the axis.
    """

    lengths_mm: tuple[float, ...] = (80.0, 112.0, 158.0)
    setbacks_mm: tuple[float, ...] = (30.0, 46.0, 69.0)
    cone_half_angle_deg: float = 22.5
    front_radius_mm: float = 15.0
    retracted_deg: float = 85.0
    amplitude_deg: float = 35.0

    def __post_init__(self) -> None:
        if not self.lengths_mm or len(self.lengths_mm) != len(self.setbacks_mm):
            raise ValueError("lengths_mm and setbacks_mm must give one value per whisker")
        for v in self.lengths_mm:
            positive("whisker length_mm", v)
        for v in self.setbacks_mm:
            finite("setback_mm", v)
            if v < 0:
                raise ValueError(f"setbacks_mm must be >= 0 (behind the front face), got {v!r}")
        if not 0.0 < finite("cone_half_angle_deg", self.cone_half_angle_deg) < 90.0:
            raise ValueError(
                f"cone_half_angle_deg must lie in (0, 90), got {self.cone_half_angle_deg!r}"
            )
        positive("front_radius_mm", self.front_radius_mm)
        if not 0.0 < finite("retracted_deg", self.retracted_deg) <= 90.0:
            raise ValueError(f"retracted_deg must lie in (0, 90], got {self.retracted_deg!r}")
        a = positive("amplitude_deg", self.amplitude_deg)
        if a >= self.retracted_deg:
            raise ValueError(
                f"amplitude_deg ({a:g}) must be below retracted_deg "
                f"({self.retracted_deg:g}): a whisker may not cross the axis"
            )

    @property
    def n_whiskers(self) -> int:
        """Whiskers per row."""
        return len(self.lengths_mm)

    @property
    def surface_angle_deg(self) -> float:
        """Angle between the surface and a whisker at full retraction (deg)."""
        return 90.0 - self.retracted_deg

    def axis(self) -> np.ndarray:
        """The head's axis (toward the surface) in a whisker's (x, z) frame."""
        a = math.radians(self.retracted_deg)
        return np.array([math.sin(a), math.cos(a)])

    def base_radius_mm(self, i: int) -> float:
        """Distance of whisker ``i``'s pivot from the head's axis (on the cone)."""
        return self.front_radius_mm + self.setbacks_mm[i] * math.tan(
            math.radians(self.cone_half_angle_deg)
        )

    def contact_direction_deg(self, i: int, distance_mm: float) -> float:
        """Direction (deg from the axis) at which whisker ``i`` first reaches the surface.

        The whisker is straight, the surface ``distance_mm`` ahead of the front face (NaN if
        the whisker never reaches it).
        """
        c = (self.setbacks_mm[i] + distance_mm) / self.lengths_mm[i]
        return math.degrees(math.acos(c)) if 0.0 <= c <= 1.0 else math.nan

    def check_distance(self, distance_mm: float, name: str = "distance_mm") -> float:
        """The surface's distance checked against the head, before any simulation.

        The surface must stand ahead of the head (> 0: at 0 or less the head is
        inside it), beyond every whisker's reach at full retraction, and within
        every whisker's reach at full protraction (with 1 deg to spare).

        Raises
        ------
        ValueError
            One line naming ``name``.
        """
        d = finite(name, distance_mm)
        if d <= 0.0:
            raise ValueError(
                f"{name} ({d:g} mm) places the head inside the surface: the "
                "surface must stand ahead of the head's front face (> 0 mm)"
            )
        top = self.retracted_deg - self.amplitude_deg
        for i, L in enumerate(self.lengths_mm):
            c = self.contact_direction_deg(i, d)  # NaN: beyond the whisker's length
            if not c > top + 1.0:
                raise ValueError(
                    f"{name} ({d:g} mm) is beyond the {L:g} mm whisker's reach at full "
                    f"protraction ({top:g} deg from the axis)"
                )
            if c >= self.retracted_deg:
                raise ValueError(
                    f"{name} ({d:g} mm) places the surface inside the {L:g} mm whisker's "
                    f"reach at full retraction ({self.retracted_deg:g} deg from the axis)"
                )
        return d

    def whisker(
        self,
        i: int,
        model: RodModel,
        surface: Surface,
        distance_mm: float,
        side: int,
        hall_gain_v: float,
        friction: float | None = None,
        offset_mm: tuple[float, float] = (0.0, 0.0),
    ) -> WhiskerSetup:
        """Whisker ``i`` of the row on ``side`` facing ``surface`` ``distance_mm`` ahead.

        ``offset_mm``: where on the sheet the whisker meets it, (along the plane in
        the whisking plane, across it): the surface is shifted by that much.
        """
        d = self.check_distance(distance_mm)
        contact = SurfaceContact(
            surface, angle_deg=self.surface_angle_deg, side=-1, friction=friction
        )
        _, u, _ = contact.frame()
        p = self.axis() * (self.setbacks_mm[i] + d) + u[[0, 2]] * float(offset_mm[0])
        t = np.array([0.0, 1e6])
        traj = Trajectory(t, np.array([p, p]), lateral_mm=np.full(2, float(offset_mm[1])))
        return WhiskerSetup(model, contact, traj, side, hall_gain_v)
