"""The room and the objects of a layout as plain boxes and meshes (numpy only).

Every exporter of :mod:`forcelayout.export` draws from these records, so the
GLB, OBJ, Habitat, USD files and the isometric picture show the same scene.

Frame: metres, z up, the floor's top at ``z = 0``. A box is given by its
centre, its extents along its local axes and a yaw (radians CCW about +z):
local +x points along ``(cos yaw, sin yaw)``, local +y along
``(-sin yaw, cos yaw)`` (an object's front).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np
import shapely

from forcelayout.layout import Layout
from forcelayout.plan import Room

__all__ = ["Box", "room_boxes", "object_boxes", "floor_mesh", "box_mesh", "wall_convexity",
           "movable_names", "is_movable", "collides", "DEFAULT_DENSITY"]

#: Kilograms per cubic metre of an object's box when it is exported as a movable body
#: (a box full of wood would be ~600; furniture is mostly air).
DEFAULT_DENSITY = 100.0

#: Cap on the pieces one wall is cut into (openings are few; this only bounds the loop).
_MAX_PIECES = 10_000
_EPS = 1e-9


@dataclass(frozen=True)
class Box:
    """One box of the scene.

    Attributes
    ----------
    name : str
        Object id, or ``"wall_<i>_<k>"`` for piece ``k`` of wall ``i``.
    centre : ndarray, shape (3,)
        Centre of the box, metres.
    extents : ndarray, shape (3,)
        Full size along local x, local y and z, metres.
    yaw : float
        Radians CCW about +z.
    kind : str
        ``"object"`` or ``"wall"``.
    category : str
        The object's category, or ``"wall"``.
    meta : dict
        Extra facts: a wall piece's ``wall`` index and ``inward`` unit normal
        (x, y) pointing into the room; an object's ``surface`` and whether
        it is ``walkable`` (a floor cover such as a rug, see
        :attr:`forcelayout.plan.SceneObject.is_walkable`).
    """

    name: str
    centre: np.ndarray
    extents: np.ndarray
    yaw: float
    kind: str
    category: str
    meta: dict = field(default_factory=dict)

    @property
    def bottom(self) -> float:
        """Height of the box's bottom face, metres."""
        return float(self.centre[2] - self.extents[2] / 2)

    def transform(self, *, origin: str = "centre") -> np.ndarray:
        """4x4 pose matrix of the box's frame (``origin`` ``"centre"`` or ``"bottom"``)."""
        c, s = np.cos(self.yaw), np.sin(self.yaw)
        m = np.eye(4)
        m[:2, :2] = [[c, -s], [s, c]]
        m[:3, 3] = self.centre
        if origin == "bottom":
            m[2, 3] = self.bottom
        return m

    def corners(self) -> np.ndarray:
        """The 8 corners in world coordinates, shape (8, 3), bottom four first (CCW)."""
        v, _ = box_mesh(self.extents)
        return v @ self.transform()[:3, :3].T + self.centre


def box_mesh(extents: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (8, 3) and outward-facing triangles (12, 3) of a box centred at the origin."""
    hx, hy, hz = np.asarray(extents, dtype=float) / 2
    v = np.array([[-hx, -hy, -hz], [hx, -hy, -hz], [hx, hy, -hz], [-hx, hy, -hz],
                  [-hx, -hy, hz], [hx, -hy, hz], [hx, hy, hz], [-hx, hy, hz]])
    f = np.array([[0, 2, 1], [0, 3, 2],      # bottom (-z)
                  [4, 5, 6], [4, 6, 7],      # top (+z)
                  [0, 1, 5], [0, 5, 4],      # -y
                  [1, 2, 6], [1, 6, 5],      # +x
                  [2, 3, 7], [2, 7, 6],      # +y
                  [3, 0, 4], [3, 4, 7]])     # -x
    return v, f


def wall_convexity(polygon: np.ndarray) -> np.ndarray:
    """Whether each vertex of a floor polygon is convex (interior angle < 180°), shape (V,)."""
    p = np.asarray(polygon, dtype=float)
    x, y = p[:, 0], p[:, 1]
    sign = np.sign(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
    d_in = p - np.roll(p, 1, axis=0)   # edge arriving at vertex k
    d_out = np.roll(p, -1, axis=0) - p  # edge leaving vertex k
    cross = d_in[:, 0] * d_out[:, 1] - d_in[:, 1] * d_out[:, 0]
    return cross * sign > 0


def _openings_on(room: Room, wall: int) -> list[tuple[float, float, float, float]]:
    """(start, end, bottom, top) of the doors and windows cut into one wall, metres."""
    cuts = [(d.offset - d.width / 2, d.offset + d.width / 2, 0.0, d.height)
            for d in room.doors if d.wall == wall]
    cuts += [(w.offset - w.width / 2, w.offset + w.width / 2, w.sill, w.sill + w.height)
             for w in room.windows if w.wall == wall]
    return cuts


def _solid_bands(holes: list[tuple[float, float]], height: float) -> list[tuple[float, float]]:
    """The parts of [0, height] not covered by any of ``holes``."""
    bands: list[tuple[float, float]] = []
    z = 0.0
    for lo, hi in sorted((max(0.0, a), min(height, b)) for a, b in holes):
        if lo > z + _EPS:
            bands.append((z, lo))
        z = max(z, hi)
    if height > z + _EPS:
        bands.append((z, height))
    return bands


def room_boxes(room: Room, *, wall_thickness: float = 0.1) -> list[Box]:
    """The walls of a room as boxes, with doors and windows cut out as gaps.

    Each wall stands outside the floor polygon (its inner face on the polygon's
    edge, so the free floor is exactly the plan's), from the floor up to the
    room's height, ``wall_thickness`` metres thick; at convex corners it runs
    on by ``wall_thickness`` so the corners are closed. A door leaves a gap from
    the floor up to its height (the wall above it stays); a window leaves a gap
    between its sill and ``sill + height`` (the wall below and above stays).

    Parameters
    ----------
    room : Room
        The plan's room.
    wall_thickness : float
        Metres, > 0.

    Returns
    -------
    list of Box
        Named ``wall_<i>_<k>`` (piece k of wall i), ``kind="wall"``.
    """
    if not np.isfinite(wall_thickness) or wall_thickness <= 0:
        raise ValueError(f"wall_thickness must be a positive number of metres, got "
                         f"{wall_thickness!r}")
    poly = np.asarray(room.polygon, dtype=float)
    n = len(poly)
    x, y = poly[:, 0], poly[:, 1]
    orient = 1.0 if np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) > 0 else -1.0
    convex = wall_convexity(poly)
    t = float(wall_thickness)
    boxes: list[Box] = []
    for i in range(n):
        a, b = poly[i], poly[(i + 1) % n]
        length = float(np.hypot(*(b - a)))
        if length < _EPS:
            continue
        tangent = (b - a) / length
        inward = orient * np.array([-tangent[1], tangent[0]])
        start = -t if convex[i] else 0.0
        end = length + (t if convex[(i + 1) % n] else 0.0)
        cuts = _openings_on(room, i)
        stops = sorted({start, end, *(min(max(c[k], start), end) for c in cuts for k in (0, 1))})
        # pieces: runs of the wall with the same solid height bands, merged
        runs: list[tuple[float, float, list[tuple[float, float]]]] = []
        for u0, u1 in zip(stops[:-1], stops[1:], strict=True):
            if u1 - u0 < _EPS:
                continue
            mid = 0.5 * (u0 + u1)
            bands = _solid_bands([(c[2], c[3]) for c in cuts if c[0] < mid < c[1]], room.height)
            if runs and runs[-1][2] == bands and abs(runs[-1][1] - u0) < _EPS:
                runs[-1] = (runs[-1][0], u1, bands)
            else:
                runs.append((u0, u1, bands))
        yaw = float(np.arctan2(tangent[1], tangent[0]))
        k = 0
        for u0, u1, bands in runs:
            for z0, z1 in bands:
                if k >= _MAX_PIECES:
                    raise RuntimeError(f"wall {i} was cut into more than {_MAX_PIECES} pieces")
                xy = a + tangent * (0.5 * (u0 + u1)) - inward * (t / 2)
                boxes.append(Box(
                    name=f"wall_{i}_{k}",
                    centre=np.array([xy[0], xy[1], 0.5 * (z0 + z1)]),
                    extents=np.array([u1 - u0, t, z1 - z0]),
                    yaw=yaw, kind="wall", category="wall",
                    meta={"wall": i, "inward": (float(inward[0]), float(inward[1]))},
                ))
                k += 1
    return boxes


def object_boxes(layout: Layout) -> list[Box]:
    """Every placed object as a box of its size at its pose, in plan order.

    The box's centre is ``(pose.x, pose.y, pose.z + height / 2)``: ``pose.z``
    is the height of its bottom (0 on the floor; for objects on a wall, their
    bottom height as given). It is turned by ``pose.yaw`` about +z, so its
    local +y (front) faces ``(-sin yaw, cos yaw)``.
    """
    out: list[Box] = []
    for oid in layout.ids():
        obj = layout.plan.object(oid)
        p = layout.poses[oid]
        w, d, h = (float(v) for v in obj.size)
        out.append(Box(
            name=oid,
            centre=np.array([p.x, p.y, p.z + h / 2]),
            extents=np.array([w, d, h]),
            yaw=float(p.yaw), kind="object", category=obj.category,
            meta={"surface": p.surface, "walkable": obj.is_walkable},
        ))
    return out


def floor_mesh(polygon: np.ndarray, *, thickness: float = 0.05) -> tuple[np.ndarray, np.ndarray]:
    """The floor polygon extruded downwards: top face at z = 0, bottom at ``-thickness``.

    Works for any simple polygon (L-shaped and other concave rooms too); the
    top is triangulated by constrained Delaunay triangulation (shapely).

    Returns
    -------
    vertices : ndarray, shape (2V, 3)
        Top ring first, then the bottom ring, metres.
    faces : ndarray, shape (F, 3)
        Triangles with outward normals (counter-clockwise seen from outside).
    """
    p = np.asarray(polygon, dtype=float)
    x, y = p[:, 0], p[:, 1]
    if np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) < 0:
        p = p[::-1]
    n = len(p)
    tris = shapely.constrained_delaunay_triangles(shapely.Polygon(p))
    index = {(round(float(q[0]), 9), round(float(q[1]), 9)): k for k, q in enumerate(p)}
    top = []
    for tri in shapely.get_parts(tris):
        ring = np.asarray(tri.exterior.coords)[:3]
        try:
            ids = [index[(round(float(q[0]), 9), round(float(q[1]), 9))] for q in ring]
        except KeyError as e:  # the triangulation added a vertex: cannot happen for simple rings
            raise ValueError(f"could not triangulate the floor polygon at {e}") from None
        a, b, c = p[ids]
        if (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) < 0:
            ids = ids[::-1]
        top.append(ids)
    top_f = np.array(top, dtype=int).reshape(-1, 3)
    bottom_f = top_f[:, ::-1] + n
    k = np.arange(n)
    k1 = (k + 1) % n
    sides = np.concatenate([np.stack([k, k1 + n, k1], 1), np.stack([k, k + n, k1 + n], 1)])
    vertices = np.concatenate([np.column_stack([p, np.zeros(n)]),
                               np.column_stack([p, np.full(n, -float(thickness))])])
    return vertices, np.concatenate([top_f, bottom_f, sides])


def movable_names(movable: str | Iterable[str] | None) -> frozenset[str]:
    """The categories (or object ids) given as ``movable``, as a set.

    A string is read as a comma-separated list (``"chair,lamp"``); blanks are
    dropped.
    """
    if movable is None:
        return frozenset()
    items = movable.split(",") if isinstance(movable, str) else list(movable)
    out = set()
    for item in items:
        if not isinstance(item, str):
            raise TypeError(f"movable: expected category names (str), got {item!r}")
        if item.strip():
            out.add(item.strip())
    return frozenset(out)


def is_movable(box: Box, movable: frozenset[str]) -> bool:
    """Whether an object's box is exported as a movable body: its category or its id is listed.

    Names that no object of the layout has are ignored (one list serves many
    plans). Objects on a wall or the ceiling hang there and stay static, and
    so do walkable floor covers (they do not collide, see :func:`collides`).
    """
    surface = str(box.meta.get("surface", "floor"))
    hanging = surface == "ceiling" or surface.startswith("wall:")
    return (box.kind == "object" and not hanging and collides(box)
            and (box.category in movable or box.name in movable))


def collides(box: Box) -> bool:
    """Whether a box gets a collision shape: walkable floor covers (rugs, mats) do not.

    The library treats them as no obstacle (furniture stands on them, people
    walk over them), and their box overlaps the feet of what stands on them,
    which a physics engine would push apart.
    """
    return not box.meta.get("walkable", False)
