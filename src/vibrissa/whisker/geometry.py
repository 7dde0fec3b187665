"""Whisker geometry, material and follicle parameters, with the thesis' presets.

Coordinate frame used throughout :mod:`vibrissa.whisker`: the whisker's rest
axis is ``+z``; its base (where the shaft leaves the follicle case) is at the
origin; the follicle pivot lies ``follicle_depth_mm`` below it on ``-z``. The
two bending planes are ``x-z`` and ``y-z``; the Hall sensor's ``x`` and ``y``
outputs measure the magnet's tilt toward ``+x`` and ``+y``. Radial distance is
measured along the undeformed shaft from the base (``z``).
"""

from __future__ import annotations

import dataclasses
import json
import math
from dataclasses import dataclass, field
from typing import Any

from vibrissa._validate import finite, in_range, positive

__all__ = ["PRESETS", "WhiskerGeometry", "preset", "preset_names"]


#: Longest whisker the model accepts, mm.
MAX_LENGTH_MM = 2000.0
#: Thinnest radius, mm: 1 um, finer than the tip of any natural whisker (a rat's
#: whisker tapers to a few micrometres); below it the modal solvers lose precision.
MIN_RADIUS_MM = 1e-3
#: Young's modulus of solids, GPa: from soft rubber (~1 MPa) to diamond (~1200 GPa).
YOUNGS_MODULUS_RANGE_GPA = (1e-3, 1200.0)
#: Density of solids, kg/m^3: from aerogel (~1) to osmium (22,590).
DENSITY_RANGE_KG_M3 = (1.0, 23_000.0)


def _physical(name: str, value: float, bounds: tuple[float, float], unit: str, why: str) -> None:
    """Refuse ``value`` outside the physical ``bounds``, saying where they come from."""
    v = finite(name, value)
    if not bounds[0] <= v <= bounds[1]:
        raise ValueError(
            f"{name} must lie in [{bounds[0]:g}, {bounds[1]:g}] {unit} ({why}), got {value!r}"
        )


@dataclass(frozen=True)
class WhiskerGeometry:
    """A tapered (truncated-cone) elastic whisker in a rubber follicle.

    Parameters
    ----------
    length_mm
        Free length from the base (follicle mouth) to the tip, mm.
    base_radius_mm, tip_radius_mm
        Radii at the base and at the tip, mm (linear taper; ``tip <= base``).
    youngs_modulus_gpa
        Young's modulus of the shaft material, GPa.
    density_kg_m3
        Density of the shaft material, kg/m^3.
    damping_ratio
        Damping ratio of the mounted whisker's first bending mode, dimensionless in
        [0, 0.5]. It is realised mostly by the rubber follicle's rotational damper
        (see ``docs/physics.md``); values below the shaft's own material damping
        leave the follicle undamped.
    material_damping_ratio
        Damping ratio of the shaft material at 100 Hz (stiffness-proportional, so it
        grows with frequency); ABS and cured acrylate resins have loss factors of
        0.02-0.05, i.e. damping ratios of 0.01-0.025.
    follicle_stiffness_nm_per_rad
        Rotational stiffness of the rubber-filled follicle case about the pivot,
        N m/rad, isotropic in the two bending axes.
    follicle_depth_mm
        Distance from the pivot (centre of the polyurethane bearing) to the base
        of the free shaft, mm.
    follicle_inertia_kg_m2
        Rotational inertia of magnet, embedded shaft and follicle about the pivot.
    name
        Label of the whisker (the preset name, or ``"custom"``).
    source
        Where the values come from.
    """

    length_mm: float = 185.0
    base_radius_mm: float = 1.0
    tip_radius_mm: float = 0.25
    youngs_modulus_gpa: float = 2.35
    density_kg_m3: float = 1050.0
    damping_ratio: float = 0.05
    material_damping_ratio: float = 0.01
    follicle_stiffness_nm_per_rad: float = 0.05
    follicle_depth_mm: float = 10.0
    follicle_inertia_kg_m2: float = 5.0e-9
    name: str = "custom"
    source: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        # the thesis' whiskers are 80-230 mm long; 2 m is beyond any whisker robot and
        # keeps the modal solvers in their range (a 1e20 mm rod has no bracketed root)
        in_range("length_mm", self.length_mm, 1.0, MAX_LENGTH_MM, "mm")
        # radii, modulus and density: the ranges of real whiskers and solids
        for name in ("base_radius_mm", "tip_radius_mm"):
            _physical(
                name,
                getattr(self, name),
                (MIN_RADIUS_MM, MAX_LENGTH_MM / 4),
                "mm",
                "1 um is finer than any whisker's tip",
            )
        if self.tip_radius_mm > self.base_radius_mm:
            raise ValueError(
                f"tip_radius_mm ({self.tip_radius_mm}) must not exceed base_radius_mm "
                f"({self.base_radius_mm}): a whisker tapers toward its tip"
            )
        if self.base_radius_mm * 4 > self.length_mm:
            raise ValueError(
                f"base_radius_mm ({self.base_radius_mm}) is too large for length_mm "
                f"({self.length_mm}): the rod model needs a slender whisker (length > 4 x radius)"
            )
        _physical(
            "youngs_modulus_gpa",
            self.youngs_modulus_gpa,
            YOUNGS_MODULUS_RANGE_GPA,
            "GPa",
            "soft rubber to diamond",
        )
        _physical(
            "density_kg_m3", self.density_kg_m3, DENSITY_RANGE_KG_M3, "kg/m^3", "aerogel to osmium"
        )
        # above ~0.5 the first mode of a compliant-follicle whisker becomes
        # overdamped and "the first mode's damping ratio" stops being a dial
        in_range("damping_ratio", self.damping_ratio, 0.0, 0.5)
        in_range("material_damping_ratio", self.material_damping_ratio, 0.0, 0.5)
        positive("follicle_stiffness_nm_per_rad", self.follicle_stiffness_nm_per_rad)
        positive("follicle_depth_mm", self.follicle_depth_mm)
        positive("follicle_inertia_kg_m2", self.follicle_inertia_kg_m2)

    # --- derived quantities (SI) ---------------------------------------------
    @property
    def length_m(self) -> float:
        """Free length in metres."""
        return self.length_mm * 1e-3

    def radius_m(self, s_m: Any) -> Any:
        """Radius (m) at arc length ``s_m`` (m) from the base (linear taper)."""
        rb, rt = self.base_radius_mm * 1e-3, self.tip_radius_mm * 1e-3
        return rb + (rt - rb) * (s_m / self.length_m)

    @property
    def bending_stiffness_base_nm2(self) -> float:
        """E I at the base, N m^2, with I = pi r^4 / 4."""
        return self.youngs_modulus_gpa * 1e9 * math.pi * (self.base_radius_mm * 1e-3) ** 4 / 4

    @property
    def mass_kg(self) -> float:
        """Mass of the free shaft (truncated cone), kg."""
        rb, rt = self.base_radius_mm * 1e-3, self.tip_radius_mm * 1e-3
        return self.density_kg_m3 * math.pi * self.length_m / 3 * (rb * rb + rb * rt + rt * rt)

    def replace(self, **changes: Any) -> WhiskerGeometry:
        """Return a copy with some fields changed (validated again)."""
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict[str, Any]:
        """Plain dict of every field (JSON-serialisable)."""
        return dataclasses.asdict(self)

    def to_json(self) -> str:
        """The geometry as a JSON string."""
        return json.dumps(self.to_dict(), sort_keys=True)

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> WhiskerGeometry:
        """Build from a dict as produced by :meth:`to_dict` (unknown keys rejected)."""
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = set(d) - names
        if unknown:
            raise ValueError(f"unknown whisker parameter(s): {sorted(unknown)}")
        return cls(**d)


# Densities: ABS 1.04-1.06 g/cm^3 (typical datasheet values; 1.05 used).
# Nanocure RC25 is an acrylate photopolymer resin for DLP printers; the thesis gives
# neither its modulus nor its density. Cured acrylate resins of this class have
# E ~ 1.5-2.5 GPa and density ~1.1-1.2 g/cm^3; we use E = 2.0 GPa and 1150 kg/m^3.
# Damping: the thesis quotes zeta ~ 0.15 for rat whiskers (3.2.2, Hartmann et al. 2003)
# and notes ringing after contact in the artificial whisker (5.5, figure 5.2), i.e. it is
# less damped. ABS and cured acrylates have loss factors ~0.02-0.05 (zeta = eta / 2 ~
# 0.01-0.025): we use a material damping ratio of 0.01 at 100 Hz. The polyurethane-filled
# follicle adds most of the damping of the mounted whisker's first mode; we use
# zeta_1 = 0.05 (Q = 10), enough to ring visibly after a contact as in figure 5.2.
# Follicle stiffness: not given in the thesis; identified from its 30 Hz resonance
# (5.3.1, "identified by inspection of the FFT" of the chapter-5 recordings). The free
# whisker cannot ring at 30 Hz with the thesis' dimensions: even rigidly clamped its
# first mode is 20.2 Hz (it would need E ~ 5 GPa, twice ABS's). In chapter 5 the
# surface holds the tip for most of each recording, and the first mode of the whisker
# with its tip pinned runs from 24.8 Hz (k_f = 0.02) to 38.9 Hz (rigid follicle):
# 30 Hz gives k_f = 0.050 N m/rad (scripts/identify_parameters.py; docs/physics.md).
# The free first mode is then 16.4 Hz, and the Hall calibration push of the chapter-4
# protocol (60 mm at r = 80 mm) turns the magnet by 14.6 degrees.
# Other whiskers: scaled with the base bending stiffness E I_base.
_K_FOLLICLE_XY = 0.05
_EI_XY = 2.35e9 * math.pi * (1e-3) ** 4 / 4


def _follicle_k(youngs_gpa: float, base_radius_mm: float) -> float:
    ei = youngs_gpa * 1e9 * math.pi * (base_radius_mm * 1e-3) ** 4 / 4
    return round(_K_FOLLICLE_XY * ei / _EI_XY, 7)


PRESETS: dict[str, WhiskerGeometry] = {
    "xy-robot": WhiskerGeometry(
        length_mm=185.0,
        base_radius_mm=1.0,
        tip_radius_mm=0.25,
        youngs_modulus_gpa=2.35,
        density_kg_m3=1050.0,
        damping_ratio=0.05,
        follicle_stiffness_nm_per_rad=_K_FOLLICLE_XY,
        name="xy-robot",
        source=(
            "Thesis ch. 4-5: ABS whisker on the XY positioning robot, 185 mm long (4.2), "
            "base radius 1 mm and tip diameter 0.5 mm (table 4.1, end of 4.5); "
            "E ~ 2.3-2.4 GPa (3.2.3, table 4.1). Follicle stiffness identified from the "
            "30 Hz resonance of 5.3.1 (tip held by the surface)."
        ),
    ),
    "scratchbot": WhiskerGeometry(
        length_mm=200.0,
        base_radius_mm=1.0,
        tip_radius_mm=1.0,
        youngs_modulus_gpa=2.3,
        density_kg_m3=1050.0,
        damping_ratio=0.05,
        follicle_stiffness_nm_per_rad=_follicle_k(2.3, 1.0),
        name="scratchbot",
        source=(
            "Thesis 3.2.3: SCRATCHbot ABS whisker shaft, 200 mm long, 2 mm diameter, E ~ 2.3 GPa."
        ),
    ),
    **{
        f"biotact-g1-{length}": WhiskerGeometry(
            length_mm=float(length),
            base_radius_mm=0.75,
            tip_radius_mm=0.15,
            youngs_modulus_gpa=2.0,
            density_kg_m3=1150.0,
            damping_ratio=0.05,
            follicle_stiffness_nm_per_rad=_follicle_k(2.0, 0.75),
            name=f"biotact-g1-{length}",
            source=(
                f"Thesis 3.4.1: BIOTACT G1 Nanocure RC25 whiskers of 80, 112 and 158 mm "
                f"(this one {length} mm). Radii are not given for G1; we use CrunchBot's "
                "RC25 taper (1.45 -> 0.3 mm diameter, 3.5.2), rounded to 1.5 -> 0.3 mm."
            ),
        )
        for length in (80, 112, 158)
    },
    "crunchbot": WhiskerGeometry(
        length_mm=140.0,
        base_radius_mm=0.725 - (0.725 - 0.15) * 20.0 / 160.0,
        tip_radius_mm=0.15,
        youngs_modulus_gpa=2.0,
        density_kg_m3=1150.0,
        damping_ratio=0.05,
        follicle_stiffness_nm_per_rad=_follicle_k(2.0, 0.725 - (0.725 - 0.15) * 20.0 / 160.0),
        follicle_depth_mm=20.0,
        name="crunchbot",
        source=(
            "Thesis 3.5.2 and 6.5.4: CrunchBot Nanocure RC25 whisker, 160 mm long, 1.45 mm "
            "diameter at the base tapering linearly to 0.3 mm at the tip, 140 mm outside the "
            "follicle; the free part modelled here starts 20 mm up the taper."
        ),
    ),
}


def preset_names() -> list[str]:
    """Names of the built-in whisker presets."""
    return list(PRESETS)


def preset(name: str) -> WhiskerGeometry:
    """Return the preset called ``name``.

    Raises
    ------
    ValueError
        If there is no such preset (the message lists the valid names).
    """
    try:
        return PRESETS[name]
    except KeyError:
        raise ValueError(
            f"unknown whisker preset {name!r}; choose one of {', '.join(PRESETS)}"
        ) from None
