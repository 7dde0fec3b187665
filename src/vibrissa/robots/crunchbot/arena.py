"""CrunchBot's arenas (thesis 6.5.1, 6.5.3): walls, 0.5 m floor tiles, square obstacles.

An arena is a small file a user can write, TOML or JSON::

    name = "my-arena"
    size_m = 1.25                     # a square arena, walls on its border
    tile_m = 0.5                      # optional, default 0.5
    tiles = [["vinyl", "rough-carpet"], ...]   # optional, rows from y = 0 upward
    start = {x_m = 0.3, y_m = 0.3, heading_deg = 0.0}

    [[obstacles]]                     # squares, lower-left corner and side
    x_m = 0.5
    y_m = 0.5
    size_m = 0.25

Coordinates are metres in the arena's frame: the origin is the lower-left corner, x to
the right, y up, headings anticlockwise from +x. Tile textures are the floor names of
:mod:`vibrissa.whisker.floors`.

The figures of the thesis (3.10(b), 6.8, 6.10) are photographs and a grid image that are
not in the text we have, so the presets' layouts are our reading of the text; each says
what it rests on (``Arena.note``).
"""

from __future__ import annotations

import json
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from vibrissa import _validate as v
from vibrissa.whisker.floors import floor_names

#: The iRobot Create's body radius (its diameter is 33.9 cm, iRobot Create Owner's Guide).
ROBOT_RADIUS_M = 0.17


@dataclass(frozen=True)
class Obstacle:
    """A square obstacle: lower-left corner ``(x_m, y_m)`` and side ``size_m``."""

    x_m: float
    y_m: float
    size_m: float

    def bounds(self) -> tuple[float, float, float, float]:
        """``(x0, y0, x1, y1)`` in metres."""
        return (self.x_m, self.y_m, self.x_m + self.size_m, self.y_m + self.size_m)


@dataclass(frozen=True)
class Pose:
    """A planar pose: position in metres, heading in radians anticlockwise from +x."""

    x_m: float
    y_m: float
    heading_rad: float = 0.0

    def as_array(self) -> np.ndarray:
        """``[x_m, y_m, heading_rad]``."""
        return np.array([self.x_m, self.y_m, self.heading_rad])


@dataclass(frozen=True)
class Arena:
    """A square walled arena with floor tiles, square obstacles and the robot's start.

    Raises
    ------
    ValueError
        One line naming the problem: an unknown tile texture, a tile grid that does not
        cover the arena, an obstacle outside the arena or overlapping another, a robot
        starting outside the arena or inside an obstacle.
    """

    name: str
    size_m: float
    start: Pose
    obstacles: tuple[Obstacle, ...] = ()
    tiles: tuple[tuple[str, ...], ...] = ()
    tile_m: float = 0.5
    note: str = field(default="", compare=False)
    path: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        where = f"{self.path}: arena {self.name!r}" if self.path else f"arena {self.name!r}"
        v.positive(f"{where}: size_m", self.size_m)
        v.positive(f"{where}: tile_m", self.tile_m)
        self._check_tiles(where)
        for i, ob in enumerate(self.obstacles):
            for key in ("x_m", "y_m"):
                v.finite(f"{where}: obstacles[{i}].{key}", getattr(ob, key))
            v.positive(f"{where}: obstacles[{i}].size_m", ob.size_m)
            x0, y0, x1, y1 = ob.bounds()
            if x0 < 0 or y0 < 0 or x1 > self.size_m or y1 > self.size_m:
                raise ValueError(f"{where}: obstacles[{i}] lies outside the {self.size_m} m arena")
            for j in range(i):
                if _overlap(ob.bounds(), self.obstacles[j].bounds()) > 0:
                    raise ValueError(f"{where}: obstacles[{i}] overlaps obstacles[{j}]")
        self._check_start(where)

    def _check_tiles(self, where: str) -> None:
        if not self.tiles:
            return
        n = self.size_m / self.tile_m
        if (
            abs(n - round(n)) > 1e-9
            or len(self.tiles) != round(n)
            or any(len(row) != round(n) for row in self.tiles)
        ):
            raise ValueError(
                f"{where}: tiles must be {round(n)} rows of {round(n)} names "
                f"({self.tile_m} m tiles over {self.size_m} m)"
            )
        known = floor_names()
        for r, row in enumerate(self.tiles):
            for c, name in enumerate(row):
                if name not in known:
                    raise ValueError(
                        f"{where}: unknown tile texture {name!r} at row {r}, "
                        f"column {c}; choose one of {', '.join(known)}"
                    )

    def _check_start(self, where: str) -> None:
        s = self.start
        for key in ("x_m", "y_m", "heading_rad"):
            v.finite(f"{where}: start.{key}", getattr(s, key))
        r = ROBOT_RADIUS_M
        if not (r <= s.x_m <= self.size_m - r and r <= s.y_m <= self.size_m - r):
            raise ValueError(
                f"{where}: the robot starts outside the arena (its body, radius "
                f"{r} m, at ({s.x_m}, {s.y_m}) m must lie inside the walls)"
            )
        for i, ob in enumerate(self.obstacles):
            if _disc_hits_box(s.x_m, s.y_m, r, ob.bounds()):
                raise ValueError(
                    f"{where}: the robot starts inside obstacles[{i}] (its "
                    f"body, radius {r} m, at ({s.x_m}, {s.y_m}) m)"
                )

    def texture_at(self, x_m: np.ndarray, y_m: np.ndarray) -> np.ndarray:
        """Tile texture names under points (``""`` outside the arena or with no tiles)."""
        x, y = np.broadcast_arrays(np.asarray(x_m, float), np.asarray(y_m, float))
        out = np.full(x.shape, "", dtype=object)
        if not self.tiles:
            return out
        inside = (x >= 0) & (y >= 0) & (x < self.size_m) & (y < self.size_m)
        col = np.floor(x[inside] / self.tile_m).astype(int)
        row = np.floor(y[inside] / self.tile_m).astype(int)
        grid = np.array(self.tiles, dtype=object)
        out[inside] = grid[row, col]
        return out

    def segments(self) -> np.ndarray:
        """Every wall and obstacle edge as rows ``(x0, y0, x1, y1)`` in metres."""
        boxes = [(0.0, 0.0, self.size_m, self.size_m)] + [o.bounds() for o in self.obstacles]
        out = []
        for x0, y0, x1, y1 in boxes:
            out += [(x0, y0, x1, y0), (x1, y0, x1, y1), (x1, y1, x0, y1), (x0, y1, x0, y0)]
        return np.array(out)

    def map_offset_m(self, map_size_m: float, cell_m: float) -> float:
        """Where the arena's corner sits in a square map: centred, on a cell boundary."""
        return max(0.0, round((map_size_m - self.size_m) / 2 / cell_m) * cell_m)

    def occupancy_grid(self, cell_m: float = 0.05, map_size_m: float = 2.5) -> np.ndarray:
        """The ground-truth occupancy grid (1 occupied, 0 free) of the arena in a square map.

        The arena sits centred in the map (:meth:`map_offset_m`), as CrunchBot's 2.5 m map
        holds the 1.25 m arena with room for overspill (6.5.3). A cell is occupied when its
        centre lies inside an obstacle or in the walls, taken as one cell thick just outside
        the arena's border. Indexing is ``grid[ix, iy]``, x first.
        """
        v.positive("cell_m", cell_m)
        v.positive("map_size_m", map_size_m)
        n = int(round(map_size_m / cell_m))
        centres = (np.arange(n) + 0.5) * cell_m - self.map_offset_m(map_size_m, cell_m)
        x, y = np.meshgrid(centres, centres, indexing="ij")
        outside = (x < 0) | (y < 0) | (x > self.size_m) | (y > self.size_m)
        wall = (
            outside
            & (x > -cell_m)
            & (y > -cell_m)
            & (x < self.size_m + cell_m)
            & (y < self.size_m + cell_m)
        )
        occ = wall.copy()
        for ob in self.obstacles:
            x0, y0, x1, y1 = ob.bounds()
            occ |= (x >= x0) & (x <= x1) & (y >= y0) & (y <= y1)
        return occ.astype(float)


def _overlap(a: tuple[float, ...], b: tuple[float, ...]) -> float:
    """Area shared by two boxes ``(x0, y0, x1, y1)``."""
    w = min(a[2], b[2]) - max(a[0], b[0])
    h = min(a[3], b[3]) - max(a[1], b[1])
    return max(w, 0.0) * max(h, 0.0)


def _disc_hits_box(x: float, y: float, r: float, box: tuple[float, ...]) -> bool:
    """Whether a disc of radius ``r`` at ``(x, y)`` overlaps a box (touching does not)."""
    dx = x - min(max(x, box[0]), box[2])
    dy = y - min(max(y, box[1]), box[3])
    return dx * dx + dy * dy < r * r


def arena_from_dict(spec: dict, source: str = "") -> Arena:
    """Build an :class:`Arena` from a parsed file's table (TOML or JSON keys above).

    Raises
    ------
    ValueError
        Naming a missing or unknown key, or the arena's own problem.
    """
    where = source or "arena"
    if not isinstance(spec, dict):
        raise ValueError(f"{where}: an arena must be a table of keys")
    allowed = {"name", "size_m", "tile_m", "tiles", "obstacles", "start"}
    extra = sorted(set(spec) - allowed)
    if extra:
        raise ValueError(
            f"{where}: unknown key {extra[0]!r}; keys are {', '.join(sorted(allowed))}"
        )
    for key in ("size_m", "start"):
        if key not in spec:
            raise ValueError(f"{where}: missing key {key!r}")
    start = spec["start"]
    if not isinstance(start, dict) or not {"x_m", "y_m"} <= set(start):
        raise ValueError(f"{where}: start must be a table with x_m, y_m and heading_deg")
    try:
        obstacles = tuple(
            Obstacle(float(o["x_m"]), float(o["y_m"]), float(o["size_m"]))
            for o in spec.get("obstacles", [])
        )
        pose = Pose(
            float(start["x_m"]),
            float(start["y_m"]),
            math.radians(float(start.get("heading_deg", 0.0))),
        )
        tiles = tuple(tuple(str(t) for t in row) for row in spec.get("tiles", []))
        return Arena(
            name=str(spec.get("name", Path(where).stem)),
            size_m=float(spec["size_m"]),
            start=pose,
            obstacles=obstacles,
            tiles=tiles,
            tile_m=float(spec.get("tile_m", 0.5)),
            path=source,
        )
    except (KeyError, TypeError) as exc:
        raise ValueError(
            f"{where}: each obstacle needs x_m, y_m and size_m numbers ({exc})"
        ) from None


def load_arena(path: str | Path) -> Arena:
    """Read an arena file (``.toml`` or ``.json``).

    Raises
    ------
    ValueError
        An unreadable format or a bad arena, naming the file.
    OSError
        The file cannot be read.
    """
    p = Path(path)
    text = p.read_text()
    try:
        if p.suffix.lower() == ".json":
            spec = json.loads(text)
        elif p.suffix.lower() == ".toml":
            spec = tomllib.loads(text)
        else:
            raise ValueError(f"{p}: an arena file must end in .toml or .json")
    except (json.JSONDecodeError, tomllib.TOMLDecodeError) as exc:
        raise ValueError(f"{p}: not valid {p.suffix[1:].upper()}: {exc}") from None
    return arena_from_dict(spec, str(p))


_ROW_A = ("vinyl", "smooth-carpet", "rough-carpet", "vinyl", "smooth-carpet")
_ROW_B = ("rough-carpet", "vinyl", "smooth-carpet", "rough-carpet", "vinyl")
_ROW_C = ("smooth-carpet", "rough-carpet", "vinyl", "smooth-carpet", "rough-carpet")

#: The thesis' two arenas. Positions are ours, read from the text (the figures are images
#: we do not have): see each preset's ``note``.
PRESETS: dict[str, Arena] = {
    "tiles": Arena(
        name="tiles",
        size_m=2.5,
        start=Pose(0.75, 0.75, 0.0),
        tiles=(_ROW_A, _ROW_B, _ROW_C, _ROW_A, _ROW_B),
        obstacles=(Obstacle(1.5, 0.5, 0.5), Obstacle(0.5, 1.5, 0.5)),
        note=(
            "6.5.1: a 2.5 m square arena paved with twenty-five 0.5 m tiles of vinyl, smooth "
            "and rough carpet, 'a few 0.5 m square obstacles placed over some carpet tiles'. "
            "The textures are laid in diagonal stripes so every texture borders the other "
            "two (figure 6.11's traces cross tile boundaries); two obstacles stand on carpet "
            "tiles. The layout of figure 3.10(b) itself is not in the text."
        ),
    ),
    "slam": Arena(
        name="slam",
        size_m=1.25,
        start=Pose(0.3, 0.3, 0.0),
        obstacles=(Obstacle(0.5, 0.5, 0.25), Obstacle(1.05, 0.0, 0.2), Obstacle(0.0, 1.05, 0.2)),
        note=(
            "6.5.3: a 1.25 m square arena 'containing several square objects' that the robot "
            "circles anticlockwise 3 or 4 times in 6 minutes; 6.5.7: the lower right "
            "quadrant holds mapped structure and the lower region of the maps shows sharp "
            "corners. Ours: a 0.25 m square in the middle (the robot circles it; the 0.5 m "
            "corridors around it are wider than the 0.34 m Create) and two 0.2 m squares in "
            "the lower-right and upper-left corners against the walls. Figure 6.10(b)'s "
            "exact layout is not in the text."
        ),
    ),
}


def get_arena(name_or_path: str | Path) -> Arena:
    """A preset by name (:data:`PRESETS`) or an arena file by path.

    Raises
    ------
    ValueError
        Neither a preset nor a ``.toml``/``.json`` path.
    """
    key = str(name_or_path)
    if key in PRESETS:
        return PRESETS[key]
    if Path(key).suffix.lower() in (".toml", ".json"):
        return load_arena(key)
    raise ValueError(
        f"unknown arena {key!r}; choose a preset ({', '.join(PRESETS)}) or a .toml/.json file"
    )
