"""Rough surfaces as periodic height fields, with the thesis' textures as presets.

A :class:`Surface` is a tile of heights ``h(u, w)`` (metres) on a regular grid in
surface coordinates (``u`` along the surface in the whisker's bending plane, ``w``
across it), repeated periodically. Sandpapers are built from their grit
standard's mean grain size (FEPA P-grades, as in thesis 5.5: "P180 sandpaper has
mean grain size of 63-90 um, and P80 has a mean grain size of 180-212 um"):
grains are spherical caps of log-normally distributed diameter scattered over the
backing at random, the height field being the upper envelope of the caps.

What the whisker feels is not ``h`` itself but the surface as seen by its
rounded tip: :meth:`Surface.for_tip` returns the envelope traced by the centre of
a sphere of the tip's radius (a grey-scale dilation with a paraboloidal
structuring element, exact to second order in slope and separable in u and w).
Grains much smaller than the tip are bridged by it; grains larger than the tip
catch it - the mechanism 5.5 proposes for why P-grades are hard to tell apart.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from vibrissa._validate import non_negative, positive
from vibrissa.whisker import _kernels

__all__ = ["TEXTURES", "Surface", "TextureSpec", "make_surface", "texture_names"]


@dataclass(frozen=True)
class TextureSpec:
    """Recipe of a texture preset.

    Attributes
    ----------
    name
        Preset name.
    grain_diameter_um
        Mean grain diameter (um); 0 for a smooth surface.
    roughness_um
        RMS height of fine random roughness added everywhere (um).
    friction
        Coulomb friction coefficient between the whisker (ABS) and the surface.
    source
        Where the numbers come from.
    """

    name: str
    grain_diameter_um: float
    roughness_um: float
    friction: float
    source: str = field(default="", compare=False)


#: FEPA P-grade mean grain sizes (FEPA 43-1:2006 / ISO 6344-2): P80 201 um,
#: P180 82 um, P600 25.8 um. Friction: ABS on machined aluminium ~0.25-0.35
#: (polymer-on-metal tables); on abrasive paper the measured coefficient is
#: dominated by grain interlocking, which the height field supplies, so the
#: microscopic coefficient is set to 0.45 for every sandpaper.
TEXTURES: dict[str, TextureSpec] = {
    "aluminium": TextureSpec("aluminium", 0.0, 0.4, 0.3, "smooth rolled aluminium, Ra ~ 0.4 um"),
    "p600": TextureSpec("p600", 25.8, 0.4, 0.45, "FEPA P600, mean grain 25.8 um"),
    "p180": TextureSpec("p180", 82.0, 0.4, 0.45, "FEPA P180, mean grain 82 um (thesis: 63-90 um)"),
    "p80": TextureSpec("p80", 201.0, 0.4, 0.45, "FEPA P80, mean grain 201 um (thesis: 180-212 um)"),
}


def texture_names() -> list[str]:
    """Names of the texture presets."""
    return list(TEXTURES)


@dataclass(frozen=True)
class Surface:
    """A periodic height field.

    Attributes
    ----------
    heights_m
        Heights (m), shape ``(n_u, n_w)``; the tile repeats in both directions.
    spacing_m
        Grid spacing (m) in u and w.
    friction
        Coulomb friction coefficient.
    name
        Texture name.
    """

    heights_m: np.ndarray
    spacing_m: float
    friction: float
    name: str = "custom"

    def __post_init__(self) -> None:
        h = np.asarray(self.heights_m, dtype=float)
        if h.ndim != 2 or min(h.shape) < 1:
            raise ValueError(f"heights_m must be a 2-D array, got shape {h.shape}")
        if not np.all(np.isfinite(h)):
            raise ValueError("heights_m contains NaN or infinite values")
        positive("spacing_m", self.spacing_m)
        non_negative("friction", self.friction)
        object.__setattr__(self, "heights_m", np.ascontiguousarray(h))

    @property
    def is_flat(self) -> bool:
        """True if the height field is constant."""
        return bool(np.ptp(self.heights_m) == 0.0)

    def for_tip(self, tip_radius_m: float) -> np.ndarray:
        """Heights of the envelope a sphere of radius ``tip_radius_m`` rides on (m).

        ``h_eff(p) = max_q [h(q) - |p - q|^2 / (2 R)]``; the tip sphere's centre sits at
        ``h_eff + R`` when touching.
        """
        R = positive("tip_radius_m", tip_radius_m)
        h = self.heights_m
        if self.is_flat:
            return h.copy()
        reach = math.sqrt(2.0 * R * max(float(np.ptp(h)), 1e-12))
        k = int(math.ceil(reach / self.spacing_m))
        out = _kernels.dilate_axis(h, self.spacing_m, R, min(k, h.shape[0] - 1))
        out = _kernels.dilate_axis(out.T.copy(), self.spacing_m, R, min(k, h.shape[1] - 1)).T
        return np.ascontiguousarray(out)


def make_surface(
    texture: str | TextureSpec,
    seed: int | np.random.Generator = 0,
    tile_u_mm: float = 8.0,
    tile_w_mm: float = 2.0,
) -> Surface:
    """Build a texture's height field.

    Parameters
    ----------
    texture
        A preset name (see :data:`TEXTURES`) or a :class:`TextureSpec`.
    seed
        Seed or generator for the random grain layout.
    tile_u_mm, tile_w_mm
        Size of the periodic tile (mm).

    Returns
    -------
    Surface
    """
    if isinstance(texture, str):
        key = texture.lower()
        if key not in TEXTURES:
            raise ValueError(f"unknown texture {texture!r}; choose one of {', '.join(TEXTURES)}")
        spec = TEXTURES[key]
    else:
        spec = texture
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    Lu = positive("tile_u_mm", tile_u_mm) * 1e-3
    Lw = positive("tile_w_mm", tile_w_mm) * 1e-3
    D = spec.grain_diameter_um * 1e-6
    dx = min(25e-6, D / 6.0) if D > 0 else 20e-6
    nu = max(8, int(round(Lu / dx)))
    nw = max(8, int(round(Lw / dx)))
    dx = Lu / nu
    H = np.zeros((nu, nw))
    if D > 0:
        # close coat: about 0.6 grains per D^2 of backing
        n_grains = int(0.6 * Lu * Lw / D**2)
        diam = D * rng.lognormal(0.0, 0.15, n_grains)
        cu = rng.uniform(0, Lu, n_grains)
        cw = rng.uniform(0, Lw, n_grains)
        # grains sit in the resin at random depth: protrude 30-70 % of their diameter
        top = diam * rng.uniform(0.3, 0.7, n_grains)
        _kernels.stamp_grains(H, dx, cu, cw, 0.5 * diam, top)
    if spec.roughness_um > 0:
        from scipy.ndimage import gaussian_filter

        noise = gaussian_filter(rng.standard_normal((nu, nw)), sigma=2.0, mode="wrap")
        noise *= spec.roughness_um * 1e-6 / max(float(noise.std()), 1e-30)
        H = H + noise
    return Surface(heights_m=H, spacing_m=dx, friction=spec.friction, name=spec.name)
