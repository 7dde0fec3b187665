"""Floor surfaces of the Roomba experiment (thesis 6.2) as periodic height fields.

Four floors, each from its construction standard or typical datasheet values
(the thesis shows photographs, figure 6.1, but gives no dimensions):

* **rough carpet** - a level-loop pile carpet tile: loops on a lattice of gauge
  (row spacing) by stitch (loop spacing along a row);
* **smooth carpet** - a cut-pile (velour) carpet tile: a finer, denser lattice of
  tufts whose cut ends make a nearly level brush;
* **tarmac** - a dense asphalt surface course: aggregate chips in bitumen, scaled to
  a mean texture depth (the macrotexture measure of EN 13036-1 / ISO 13473-1);
* **vinyl** - homogeneous PVC sheet flooring: smooth with a fine emboss.

**Carpet compliance.** A height field is rigid; carpet pile is not. The loops and
tufts are kept as the rigid relief of their tops (what the whisker tip slides over),
and the pile's compliance goes into the contact's normal stiffness
(:attr:`FloorSpec.stiffness_n_m`, a Winkler spring under the tip): the tip sinks
into the pile in proportion to its load, and every bump is felt through that
spring. Fibre bending along the surface (the pile "combing" under the tip) is not
represented; the pile's tangential give is folded into the friction coefficient.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from vibrissa._validate import positive
from vibrissa.whisker.surfaces import Surface

__all__ = ["FLOORS", "FloorSpec", "floor_names", "floor_spec", "make_floor", "texture_depth_mm"]


@dataclass(frozen=True)
class FloorSpec:
    """Recipe of a floor preset.

    Attributes
    ----------
    name : str
        Preset name.
    kind : {"pile", "aggregate", "smooth"}
        A lattice of loops or tufts, random aggregate chips, or a smooth sheet.
    element_mm : float
        Loop / tuft diameter, or the mean aggregate chip size (mm); 0 for smooth.
    lattice_mm : tuple of float
        Pile: (stitch, gauge), spacing of the elements along and across the rows
        (mm); unused otherwise.
    relief_mm : float
        Pile: height of the element tops above the gaps between them as the tip
        meets them (mm). Aggregate: the mean texture depth MTD (mm) the field is
        scaled to. Unused for smooth floors.
    roughness_um : float
        RMS height of the fine roughness added everywhere (fibres, micro-texture,
        emboss), um.
    correlation_mm : float
        Correlation length of that fine roughness (mm).
    friction : float
        Coulomb coefficient between the ABS whisker and the floor.
    stiffness_n_m : float
        Normal stiffness of the contact under the tip (N/m): the pile's compliance
        for carpets, the (stiff) penalty of a hard floor.
    source : str
        Where the numbers come from.
    """

    name: str
    kind: str
    element_mm: float
    lattice_mm: tuple[float, float]
    relief_mm: float
    roughness_um: float
    correlation_mm: float
    friction: float
    stiffness_n_m: float
    source: str = field(default="", compare=False)


#: The four floors of thesis 6.2 (figure 6.1), in the thesis' table order.
FLOORS: dict[str, FloorSpec] = {
    "rough-carpet": FloorSpec(
        "rough-carpet",
        "pile",
        element_mm=3.0,
        lattice_mm=(3.6, 4.0),
        relief_mm=1.2,
        roughness_um=40.0,
        correlation_mm=0.1,
        friction=0.6,
        stiffness_n_m=400.0,
        source=(
            "Level-loop pile carpet tile: gauge 5/32 in (4.0 mm) and about 28 stitches per "
            "10 cm (3.6 mm), typical of loop-pile tile datasheets classified under EN 1307; "
            "loops ~3 mm across (a tufted yarn bundle); loop tops 1.2 mm above the gaps "
            "between loops as a 1 mm tip meets them (pile thickness per ISO 1766 is ~4-6 "
            "mm, most of it hidden below the neighbouring loops); fibre-scale roughness 40 "
            "um (nylon 6,6 filaments ~20-40 um). Pile compliance: ~10 kPa per mm of "
            "compression under a ~3 mm^2 tip footprint (thickness under 2 kPa and 200 kPa, "
            "ISO 1765) gives of order 100-1000 N/m; loops are the stiffer pile: 400 N/m. "
            "Friction of ABS on nylon pile ~0.6."
        ),
    ),
    "vinyl": FloorSpec(
        "vinyl",
        "smooth",
        element_mm=0.0,
        lattice_mm=(0.0, 0.0),
        relief_mm=0.0,
        roughness_um=25.0,
        correlation_mm=0.4,
        friction=0.45,
        stiffness_n_m=2.0e4,
        source=(
            "Vinyl (PVC) floor covering (EN ISO 10582 heterogeneous / EN ISO 10581 "
            "homogeneous): a smooth wear layer with an embossed finish, taken as 25 um RMS "
            "over ~0.4 mm (our assumption: emboss depths of sheet vinyl are ~0.05-0.2 mm and "
            "the thesis' vinyl gave signals above its variance threshold, 6.2.1); rigid "
            "under a whisker (the contact's default penalty stiffness); friction of ABS on "
            "PVC, dry, ~0.4-0.5."
        ),
    ),
    "smooth-carpet": FloorSpec(
        "smooth-carpet",
        "pile",
        element_mm=1.8,
        lattice_mm=(2.2, 2.5),
        relief_mm=0.35,
        roughness_um=30.0,
        correlation_mm=0.1,
        friction=0.7,
        stiffness_n_m=120.0,
        source=(
            "Cut-pile (velour) carpet tile: gauge 1/10 in (2.5 mm), ~45 stitches per 10 cm "
            "(2.2 mm), tufts ~1.8 mm across whose cut ends form a nearly level brush (0.35 "
            "mm of relief at the tip); fibre roughness 30 um. Cut pile is softer than loop "
            "pile under a point load: 120 N/m (same estimate as rough carpet). Friction of "
            "ABS on a cut-pile brush ~0.7."
        ),
    ),
    "tarmac": FloorSpec(
        "tarmac",
        "aggregate",
        element_mm=6.0,
        lattice_mm=(0.0, 0.0),
        relief_mm=0.8,
        roughness_um=50.0,
        correlation_mm=0.2,
        friction=0.6,
        stiffness_n_m=2.0e4,
        source=(
            "Dense asphalt surface course with 6 mm nominal aggregate (an AC 6 of EN "
            "13108-1, the finest road/footway tarmac); mean texture depth 0.8 mm, within "
            "the 0.5-1.2 mm of dense asphalts measured by the volumetric patch method of "
            "EN 13036-1 (macrotexture as defined in ISO 13473-1); chip micro-texture 50 um "
            "RMS; rigid; friction of ABS on stone/bitumen ~0.6."
        ),
    ),
}


def floor_names() -> list[str]:
    """Names of the floor presets, in the thesis' table order."""
    return list(FLOORS)


def floor_spec(floor: str | FloorSpec) -> FloorSpec:
    """The :class:`FloorSpec` of a preset name (or ``floor`` itself).

    Raises
    ------
    ValueError
        For an unknown name, listing the presets.
    """
    if isinstance(floor, FloorSpec):
        return floor
    if floor not in FLOORS:
        raise ValueError(f"unknown floor texture {floor!r}; choose one of {', '.join(FLOORS)}")
    return FLOORS[floor]


def _caps(
    H: np.ndarray, dx: float, cu: np.ndarray, cw: np.ndarray, rad: np.ndarray, top: np.ndarray
) -> None:
    """Stamp spherical caps into ``H`` as an upper envelope, periodically.

    Each cap has centre ``cu, cw``, radius ``rad`` and summit ``top`` (m).
    """
    n, m = H.shape
    for u0, w0, r, t in zip(cu, cw, rad, top, strict=True):
        k = int(r / dx) + 1
        iu = int(u0 / dx) + np.arange(-k, k + 1)
        iw = int(w0 / dx) + np.arange(-k, k + 1)
        du = iu * dx - u0
        dw = iw * dx - w0
        q = r * r - du[:, None] ** 2 - dw[None, :] ** 2
        z = np.where(q > 0.0, t - r + np.sqrt(np.maximum(q, 0.0)), -np.inf)
        block = np.ix_(iu % n, iw % m)
        H[block] = np.maximum(H[block], z)


def _texture_depth(H: np.ndarray) -> float:
    """Mean depth (m) below the plane of the highest summits (the 99.5th percentile).

    This is what a volumetric patch (EN 13036-1) fills.
    """
    return float(np.percentile(H, 99.5) - H.mean())


def make_floor(
    floor: str | FloorSpec,
    seed: int | np.random.Generator = 0,
    tile_u_mm: float = 160.0,
    tile_w_mm: float = 64.0,
    spacing_mm: float = 0.1,
) -> Surface:
    """Build a floor's height field (a :class:`~vibrissa.whisker.surfaces.Surface`).

    Parameters
    ----------
    floor : str or FloorSpec
        A preset name (see :data:`FLOORS`) or a spec.
    seed : int or numpy.random.Generator
        Seed of the random layout (jitter of the pile, chips, roughness).
    tile_u_mm, tile_w_mm : float
        Size of the periodic tile (mm).
    spacing_mm : float
        Grid spacing (mm); 0.1 mm resolves the pile and the chips, and the whisker's
        rounded tip bridges anything finer.

    Returns
    -------
    Surface
        With the floor's friction; the contact stiffness is ``spec.stiffness_n_m``.

    Raises
    ------
    ValueError
        For an unknown preset or a non-positive size.
    """
    spec = floor_spec(floor)
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    dx = positive("spacing_mm", spacing_mm) * 1e-3
    nu = max(8, int(round(positive("tile_u_mm", tile_u_mm) * 1e-3 / dx)))
    nw = max(8, int(round(positive("tile_w_mm", tile_w_mm) * 1e-3 / dx)))
    Lu, Lw = nu * dx, nw * dx
    H = np.zeros((nu, nw))
    if spec.kind == "pile":
        stitch, gauge = (v * 1e-3 for v in spec.lattice_mm)
        # whole numbers of rows and stitches per tile, so the lattice tiles seamlessly
        ku, kw = max(1, round(Lu / stitch)), max(1, round(Lw / gauge))
        gu, gw = np.meshgrid(
            (np.arange(ku) + 0.5) * Lu / ku, (np.arange(kw) + 0.5) * Lw / kw, indexing="ij"
        )
        n = gu.size
        cu = gu.ravel() + rng.normal(0.0, 0.12 * stitch, n)
        cw = gw.ravel() + rng.normal(0.0, 0.12 * gauge, n)
        rad = 0.5 * spec.element_mm * 1e-3 * rng.lognormal(0.0, 0.1, n)
        top = spec.relief_mm * 1e-3 * rng.uniform(0.8, 1.0, n)
        _caps(H, dx, cu % Lu, cw % Lw, rad, top)
        H = np.maximum(H, 0.0)
    elif spec.kind == "aggregate":
        D = spec.element_mm * 1e-3
        n = int(0.6 * Lu * Lw / D**2)
        diam = D * rng.lognormal(0.0, 0.25, n)
        cu, cw = rng.uniform(0, Lu, n), rng.uniform(0, Lw, n)
        _caps(H, dx, cu, cw, 0.5 * diam, diam * rng.uniform(0.2, 0.6, n))
        H = np.maximum(H, 0.0)
        H *= spec.relief_mm * 1e-3 / max(_texture_depth(H), 1e-12)
    elif spec.kind != "smooth":
        raise ValueError(f"floor kind must be 'pile', 'aggregate' or 'smooth', got {spec.kind!r}")
    if spec.roughness_um > 0:
        from scipy.ndimage import gaussian_filter

        sigma = max(spec.correlation_mm * 1e-3 / dx, 0.5)
        noise = gaussian_filter(rng.standard_normal((nu, nw)), sigma=sigma, mode="wrap")
        noise *= spec.roughness_um * 1e-6 / max(float(noise.std()), 1e-30)
        H = H + noise
    return Surface(heights_m=H, spacing_m=dx, friction=spec.friction, name=spec.name)


def texture_depth_mm(surface: Surface) -> float:
    """Mean texture depth of a height field (mm): mean depth below its summit plane."""
    return _texture_depth(surface.heights_m) * 1e3
