"""The thesis' tactile "box world" (2.5): square-cornered, straight-sided objects, top view.

"A world of reduced complexity, where objects are square cornered, straight sided,
vertically aligned and vary only in location and texture" (thesis 2.5): a room whose
walls face inward and convex boxes (furniture legs) standing in it, every face with
one of the chapter-5 textures (:data:`vibrissa.whisker.surfaces.TEXTURES`). Everything
is 2-D (the objects are vertically aligned), in mm, angles in degrees
counter-clockwise from ``+x``.

* :class:`Face`: one straight side, free space on the side of its unit ``normal``
  (the right-hand normal of ``end - start``), its ``texture`` and the ``box`` it
  belongs to (-1: a room wall).
* :class:`Box`: a convex polygon, vertices counter-clockwise, one texture per edge.
* :class:`BoxWorld`: the boxes and the room; ``faces`` (boxes first, in order, then
  the walls), ``corners()`` (the convex box vertices, where shaft contacts happen),
  ``inside``, ``clearance_mm`` and the ground truth on a grid (``ground_truth``).

Presets (:func:`box_world`, :data:`BOX_WORLDS`): ``"furniture"`` and ``"corner"``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np

from vibrissa._validate import finite, positive
from vibrissa.data.schema import TEXTURE_CODES

__all__ = [
    "BOX_WORLDS",
    "Box",
    "BoxWorld",
    "Face",
    "box_world",
]


def _point(name: str, p: Sequence[float]) -> tuple[float, float]:
    arr = np.asarray(p, dtype=float)
    if arr.shape != (2,):
        raise ValueError(f"{name} must be a 2-vector (x, y) in mm, got shape {arr.shape}")
    return (finite(f"{name}[0]", float(arr[0])), finite(f"{name}[1]", float(arr[1])))


def _texture(name: str, t: str) -> str:
    if not isinstance(t, str) or t not in TEXTURE_CODES:
        raise ValueError(f"{name} must be one of {', '.join(TEXTURE_CODES)}, got {t!r}")
    return t


@dataclass(frozen=True)
class Face:
    """One straight side of a box or a room wall (a segment in the top view).

    Parameters
    ----------
    start_mm, end_mm
        The segment's ends (x, y) in mm; free space lies to the right of
        ``end_mm - start_mm`` (the side of :attr:`normal`).
    texture
        A chapter-5 texture name (``vibrissa.data.schema.TEXTURE_CODES``).
    box
        Index of the box it belongs to; -1 for a room wall.
    """

    start_mm: tuple[float, float]
    end_mm: tuple[float, float]
    texture: str
    box: int = -1

    def __post_init__(self) -> None:
        object.__setattr__(self, "start_mm", _point("start_mm", self.start_mm))
        object.__setattr__(self, "end_mm", _point("end_mm", self.end_mm))
        _texture("texture", self.texture)
        if self.length_mm <= 0.0:
            raise ValueError("a face needs start_mm != end_mm")

    @property
    def length_mm(self) -> float:
        """The segment's length (mm)."""
        return math.dist(self.start_mm, self.end_mm)

    @property
    def tangent(self) -> np.ndarray:
        """Unit vector from ``start_mm`` to ``end_mm``."""
        d = np.subtract(self.end_mm, self.start_mm)
        return d / np.linalg.norm(d)

    @property
    def normal(self) -> np.ndarray:
        """Unit outward normal, pointing into free space."""
        t = self.tangent
        return np.array([t[1], -t[0]])

    @property
    def direction_deg(self) -> float:
        """The face's orientation (deg, counter-clockwise from +x), modulo 180, in [0, 180)."""
        t = self.tangent
        return float(math.degrees(math.atan2(t[1], t[0])) % 180.0)

    def distance_mm(self, point: Sequence[float]) -> float:
        """Distance (mm) from ``point`` to the segment."""
        p = np.asarray(point, dtype=float)
        a = np.asarray(self.start_mm)
        d = np.subtract(self.end_mm, a)
        u = float(np.clip((p - a) @ d / (d @ d), 0.0, 1.0))
        return float(np.linalg.norm(a + u * d - p))


@dataclass(frozen=True)
class Box:
    """A convex, vertically aligned object: a polygon in the top view.

    Parameters
    ----------
    vertices_mm
        Shape ``(n, 2)``, counter-clockwise, n >= 3, strictly convex.
    textures
        One texture per edge (edge i runs from vertex i to vertex i + 1).
    """

    vertices_mm: tuple[tuple[float, float], ...]
    textures: tuple[str, ...]

    def __post_init__(self) -> None:
        v = np.asarray(self.vertices_mm, dtype=float)
        if v.ndim != 2 or v.shape[1] != 2 or v.shape[0] < 3:
            raise ValueError(f"vertices_mm must have shape (n >= 3, 2), got {v.shape}")
        if not np.all(np.isfinite(v)):
            raise ValueError("vertices_mm contains NaN or infinite values")
        e = np.roll(v, -1, axis=0) - v
        cross = e[:, 0] * np.roll(e, -1, axis=0)[:, 1] - e[:, 1] * np.roll(e, -1, axis=0)[:, 0]
        if np.any(cross <= 0.0):
            raise ValueError("vertices_mm must form a strictly convex, counter-clockwise polygon")
        tex = (self.textures,) * len(v) if isinstance(self.textures, str) else self.textures
        tex = tuple(tex)
        if len(tex) != len(v):
            raise ValueError(f"textures must give one texture per edge ({len(v)}), got {len(tex)}")
        for t in tex:
            _texture("textures", t)
        object.__setattr__(self, "vertices_mm", tuple((float(a), float(b)) for a, b in v))
        object.__setattr__(self, "textures", tex)

    @classmethod
    def square(
        cls,
        center_mm: Sequence[float],
        side_mm: float,
        rotation_deg: float = 0.0,
        textures: str | Sequence[str] = "aluminium",
    ) -> Box:
        """A square of side ``side_mm`` centred at ``center_mm``, turned by ``rotation_deg``.

        Edge 0 is the bottom edge before the rotation (from the lower-left vertex).
        """
        c = np.asarray(_point("center_mm", center_mm))
        h = 0.5 * positive("side_mm", side_mm)
        a = math.radians(finite("rotation_deg", rotation_deg))
        rot = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
        local = np.array([[-h, -h], [h, -h], [h, h], [-h, h]])
        verts = local @ rot.T + c
        tex = (textures,) * 4 if isinstance(textures, str) else tuple(textures)
        return cls(tuple(map(tuple, verts)), tex)

    @property
    def vertices(self) -> np.ndarray:
        """The vertices as an array ``(n, 2)``."""
        return np.asarray(self.vertices_mm, dtype=float)

    def contains(self, point: Sequence[float]) -> bool:
        """Whether ``point`` lies in the closed polygon."""
        v = self.vertices
        e = np.roll(v, -1, axis=0) - v
        r = np.asarray(point, dtype=float) - v
        return bool(np.all(e[:, 0] * r[:, 1] - e[:, 1] * r[:, 0] >= 0.0))


def _wall_corners(room: tuple[float, float, float, float]) -> list[tuple[float, float]]:
    x0, y0, x1, y1 = room
    # clockwise, so that each wall's right-hand normal points into the room
    return [(x0, y0), (x0, y1), (x1, y1), (x1, y0)]


@dataclass(frozen=True)
class BoxWorld:
    """Boxes in an optional rectangular room.

    Parameters
    ----------
    boxes
        The objects (convex polygons); they must not overlap each other.
    room
        ``(xmin, ymin, xmax, ymax)`` of a room whose walls face inward (None: no walls,
        open space around the boxes).
    wall_textures
        Textures of the walls in the order west (x = xmin), north (y = ymax), east,
        south; one name for all four.
    """

    boxes: tuple[Box, ...] = ()
    room: tuple[float, float, float, float] | None = None
    wall_textures: tuple[str, ...] = field(default=("aluminium",) * 4)

    def __post_init__(self) -> None:
        boxes = tuple(self.boxes)
        for b in boxes:
            if not isinstance(b, Box):
                raise TypeError(f"boxes must hold Box objects, got {type(b).__name__}")
        object.__setattr__(self, "boxes", boxes)
        wt = self.wall_textures
        wt = (wt,) * 4 if isinstance(wt, str) else tuple(wt)
        if len(wt) != 4:
            raise ValueError(f"wall_textures must give 4 textures, got {len(wt)}")
        for t in wt:
            _texture("wall_textures", t)
        object.__setattr__(self, "wall_textures", wt)
        if self.room is not None:
            r = tuple(finite("room", float(x)) for x in self.room)
            if len(r) != 4 or r[2] <= r[0] or r[3] <= r[1]:
                raise ValueError(f"room must be (xmin, ymin, xmax, ymax) with max > min, got {r}")
            object.__setattr__(self, "room", r)
            for b in boxes:
                v = b.vertices
                if np.any(v[:, 0] <= r[0]) or np.any(v[:, 0] >= r[2]):
                    raise ValueError("every box must stand inside the room")
                if np.any(v[:, 1] <= r[1]) or np.any(v[:, 1] >= r[3]):
                    raise ValueError("every box must stand inside the room")
        for i, a in enumerate(boxes):
            for b in boxes[i + 1 :]:
                if _convex_overlap(a.vertices, b.vertices):
                    raise ValueError("boxes must not overlap")

    @cached_property
    def faces(self) -> tuple[Face, ...]:
        """Every face: the boxes' edges in order, then the walls (west, north, east, south)."""
        out = []
        for k, b in enumerate(self.boxes):
            v = b.vertices_mm
            for i in range(len(v)):
                out.append(Face(v[i], v[(i + 1) % len(v)], b.textures[i], k))
        if self.room is not None:
            c = _wall_corners(self.room)
            for i in range(4):
                out.append(Face(c[i], c[(i + 1) % 4], self.wall_textures[i], -1))
        return tuple(out)

    @cached_property
    def _face_arrays(self) -> tuple[np.ndarray, np.ndarray]:
        f = self.faces
        if not f:
            return np.zeros((0, 2)), np.zeros((0, 2))
        return np.array([x.start_mm for x in f]), np.array([x.end_mm for x in f])

    def face_segments(self) -> tuple[np.ndarray, np.ndarray]:
        """Starts and ends of every face, two arrays ``(n_faces, 2)`` (mm)."""
        a, b = self._face_arrays
        return a.copy(), b.copy()

    def corners(self) -> np.ndarray:
        """The convex box vertices ``(m, 2)`` (mm), box by box: where shaft contacts happen."""
        if not self.boxes:
            return np.zeros((0, 2))
        return np.vstack([b.vertices for b in self.boxes])

    def corner_faces(self) -> tuple[tuple[int, int], ...]:
        """For each of :meth:`corners`, the indices (into :attr:`faces`) of its two faces.

        The face ending at the vertex, then the face starting there.
        """
        out = []
        start = 0
        for b in self.boxes:
            n = len(b.vertices_mm)
            for i in range(n):
                out.append((start + (i - 1) % n, start + i))
            start += n
        return tuple(out)

    def inside(self, point: Sequence[float]) -> bool:
        """Whether ``point`` is solid: in a box (boundary included) or outside the room."""
        x, y = _point("point", point)
        if self.room is not None:
            r = self.room
            if not (r[0] < x < r[2] and r[1] < y < r[3]):
                return True
        return any(b.contains((x, y)) for b in self.boxes)

    def clearance_mm(self, point: Sequence[float]) -> float:
        """Distance (mm) from ``point`` to the nearest face; negative inside a solid.

        ``inf`` in an empty world.
        """
        p = np.asarray(_point("point", point))
        a, b = self._face_arrays
        if a.shape[0] == 0:
            return math.inf
        d = b - a
        u = np.clip(np.einsum("ij,ij->i", p - a, d) / np.einsum("ij,ij->i", d, d), 0.0, 1.0)
        dist = float(np.min(np.linalg.norm(a + u[:, None] * d - p, axis=1)))
        return -dist if self.inside(p) else dist

    def ground_truth(
        self,
        cell_mm: float = 10.0,
        extent_mm: tuple[float, float, float, float] | None = None,
    ) -> dict[str, Any]:
        """The world on a grid (indexing ``[ix, iy]``, x first; cell centres sampled).

        Parameters
        ----------
        cell_mm
            Cell size (mm).
        extent_mm
            ``(xmin, ymin, xmax, ymax)`` of the grid; default the room (or the boxes'
            bounds plus 10 %).

        Returns
        -------
        dict
            ``occupancy`` (1 solid, 0 free: the cell's centre), ``face_index`` (the face
            whose segment crosses the cell, the one with most of its length in it; -1
            none), ``texture_code`` (that face's ``TEXTURE_CODES`` code, -1 none),
            ``face_direction_deg`` (its orientation mod 180, NaN none), ``origin_mm``
            (the grid's lower-left corner), ``cell_mm`` and ``shape``.
        """
        cell = positive("cell_mm", cell_mm)
        ext = self._extent() if extent_mm is None else tuple(float(v) for v in extent_mm)
        if len(ext) != 4 or ext[2] <= ext[0] or ext[3] <= ext[1]:
            raise ValueError(f"extent_mm must be (xmin, ymin, xmax, ymax), got {extent_mm!r}")
        nx = int(math.ceil((ext[2] - ext[0]) / cell - 1e-9))
        ny = int(math.ceil((ext[3] - ext[1]) / cell - 1e-9))
        xc = ext[0] + (np.arange(nx) + 0.5) * cell
        yc = ext[1] + (np.arange(ny) + 0.5) * cell
        X, Y = np.meshgrid(xc, yc, indexing="ij")
        occ = np.zeros((nx, ny), dtype=np.int8)
        if self.room is not None:
            r = self.room
            occ |= ~((X > r[0]) & (X < r[2]) & (Y > r[1]) & (Y < r[3]))
        for b in self.boxes:
            v = b.vertices
            e = np.roll(v, -1, axis=0) - v
            inside = np.ones_like(X, dtype=bool)
            for k in range(len(v)):
                inside &= e[k, 0] * (Y - v[k, 1]) - e[k, 1] * (X - v[k, 0]) >= 0.0
            occ |= inside
        best = np.zeros((nx, ny))
        face_index = np.full((nx, ny), -1, dtype=np.int64)
        for k, f in enumerate(self.faces):
            n_s = max(2, int(math.ceil(f.length_mm / (0.1 * cell))) + 1)
            t = np.linspace(0.0, 1.0, n_s)
            pts = np.asarray(f.start_mm) + t[:, None] * np.subtract(f.end_mm, f.start_mm)
            ix = np.floor((pts[:, 0] - ext[0]) / cell).astype(int)
            iy = np.floor((pts[:, 1] - ext[1]) / cell).astype(int)
            ok = (ix >= 0) & (ix < nx) & (iy >= 0) & (iy < ny)
            counts = np.zeros((nx, ny))
            np.add.at(counts, (ix[ok], iy[ok]), 1.0)
            better = counts > best
            face_index[better] = k
            best = np.maximum(best, counts)
        codes = np.array([TEXTURE_CODES[f.texture] for f in self.faces] + [-1], dtype=np.int64)
        dirs = np.array([f.direction_deg for f in self.faces] + [math.nan])
        return {
            "occupancy": occ.astype(np.int8),
            "face_index": face_index,
            "texture_code": codes[face_index],
            "face_direction_deg": dirs[face_index],
            "origin_mm": (float(ext[0]), float(ext[1])),
            "cell_mm": cell,
            "shape": (nx, ny),
        }

    def _extent(self) -> tuple[float, float, float, float]:
        if self.room is not None:
            return self.room
        if not self.boxes:
            raise ValueError("extent_mm is needed for a world with no room and no boxes")
        c = self.corners()
        lo, hi = c.min(axis=0), c.max(axis=0)
        pad = 0.1 * float(max(hi - lo))
        return (lo[0] - pad, lo[1] - pad, hi[0] + pad, hi[1] + pad)

    def to_dict(self) -> dict[str, Any]:
        """The world as plain values (JSON-ready)."""
        return {
            "boxes": [
                {"vertices_mm": [list(v) for v in b.vertices_mm], "textures": list(b.textures)}
                for b in self.boxes
            ],
            "room": None if self.room is None else list(self.room),
            "wall_textures": list(self.wall_textures),
        }

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> BoxWorld:
        """The world :meth:`to_dict` described."""
        boxes = tuple(
            Box(tuple(tuple(v) for v in b["vertices_mm"]), tuple(b["textures"]))
            for b in d.get("boxes", [])
        )
        room = d.get("room")
        return cls(
            boxes,
            None if room is None else tuple(room),
            tuple(d.get("wall_textures", ("aluminium",) * 4)),
        )


def _convex_overlap(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether two convex polygons overlap (separating axis test; touching counts as apart)."""
    for poly in (a, b):
        e = np.roll(poly, -1, axis=0) - poly
        for k in range(len(poly)):
            n = np.array([e[k, 1], -e[k, 0]])
            pa, pb = a @ n, b @ n
            if pa.max() <= pb.min() + 1e-9 or pb.max() <= pa.min() + 1e-9:
                return False
    return True


def _furniture() -> BoxWorld:
    # a 1.5 m square room; four legs of 60-200 mm sides at 0, 20, 45 and 70 deg, every
    # face textured and all four chapter-5 textures used on the boxes and the walls
    boxes = (
        Box.square((400.0, 450.0), 200.0, 0.0, ("aluminium", "p600", "p180", "p80")),
        Box.square((1100.0, 400.0), 120.0, 20.0, ("p80", "aluminium", "p600", "p180")),
        Box.square((1050.0, 1100.0), 90.0, 45.0, ("p180", "p80", "aluminium", "p600")),
        Box.square((450.0, 1050.0), 60.0, 70.0, ("p600", "p180", "p80", "aluminium")),
    )
    return BoxWorld(boxes, (0.0, 0.0, 1500.0, 1500.0), ("p180", "aluminium", "p80", "p600"))


def _corner() -> BoxWorld:
    # one 200 mm box, square to the axes, in an empty 1.5 m room
    box = Box.square((750.0, 750.0), 200.0, 0.0, ("aluminium", "p600", "p180", "p80"))
    return BoxWorld((box,), (0.0, 0.0, 1500.0, 1500.0), ("aluminium",) * 4)


def _calibration() -> BoxWorld:
    # a calibration rig: two boxes (200 mm square to the axes, 150 mm at 30 deg) and four
    # walls, every texture on two box faces and one wall, so that a patrol meets the four
    # textures about equally often (the "corner" world's aluminium walls made half of its
    # tip contacts aluminium)
    boxes = (
        Box.square((550.0, 750.0), 200.0, 0.0, ("p80", "p180", "p600", "aluminium")),
        Box.square((1000.0, 750.0), 150.0, 30.0, ("p600", "aluminium", "p80", "p180")),
    )
    return BoxWorld(boxes, (0.0, 0.0, 1500.0, 1500.0), ("aluminium", "p600", "p180", "p80"))


#: Preset worlds: name -> a builder.
BOX_WORLDS = {"furniture": _furniture, "corner": _corner, "calibration": _calibration}


def box_world(name: str) -> BoxWorld:
    """The preset world ``name`` (see :data:`BOX_WORLDS`)."""
    if name not in BOX_WORLDS:
        raise ValueError(f"unknown box world {name!r}; choose one of {', '.join(BOX_WORLDS)}")
    return BOX_WORLDS[name]()
