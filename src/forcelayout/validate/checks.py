"""Deterministic checks of a finished layout (stage V of the method).

:func:`check_layout` runs, in order:

``collision``
    No two floor objects' footprints overlap by more than ``max_overlap`` m².
``outside``
    No floor object's footprint lies outside the floor polygon by more than
    ``max_overlap`` m².
``door``
    No floor object covers more than ``max_overlap`` m² of the square of door
    width in front of any door (its swing area).
``surface``
    Objects off the floor rest where they say: on top of a placed parent and
    inside its top; on an existing wall, within its ends, below the ceiling;
    on the ceiling above the floor.
``navigable``
    Floor objects inflated by the agent radius, and the walls, leave at
    least ``min_free_fraction`` of the floor cells free for the agent's centre.
``reachable``
    Every primary floor object has a free cell within ``agent_radius + reach``
    of its footprint (the agent's body comes within ``reach`` of it) that is
    4-connected through free cells to the cells just inside each door. A room
    without doors is checked from its largest free region instead.

Each failure is a line ``"<check>: <reason naming the objects>"``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import shapely
from scipy import ndimage

from forcelayout.geometry import front_vectors, right_vectors, separation_matrix
from forcelayout.validate.occupancy import _floor_arrays, _footprint_dist2, room_grid

if TYPE_CHECKING:
    from forcelayout.layout import Layout

__all__ = ["CheckReport", "check_layout", "CHECKS"]

#: Names of the checks, in the order they run.
CHECKS = ("collision", "outside", "door", "surface", "navigable", "reachable")

_SURFACE_TOL = 0.01  # metres of slack for objects on walls


@dataclass
class CheckReport:
    """Outcome of :func:`check_layout`.

    Attributes
    ----------
    ok : bool
        True when no check failed.
    failures : list of str
        One line per problem, ``"<check>: <reason naming the objects>"``.
    free_fraction : float
        Fraction of the floor cells free for the agent's centre, in [0, 1].
    unreachable : list of str
        Ids of primary objects not reachable from every door.
    free_mask : ndarray of bool, shape (H, W), optional
        Free cells (rows along +y, columns along +x).
    origin : ndarray, shape (2,), optional
        World position of the lower-left corner of cell ``[0, 0]``, metres.
    grid : float
        Cell size, metres.
    """

    ok: bool
    failures: list[str] = field(default_factory=list)
    free_fraction: float = 1.0
    unreachable: list[str] = field(default_factory=list)
    free_mask: np.ndarray | None = field(default=None, repr=False)
    origin: np.ndarray | None = field(default=None, repr=False)
    grid: float = 0.05

    def by_check(self) -> dict[str, list[str]]:
        """Failures grouped by check name (every name of :data:`CHECKS` is a key)."""
        out: dict[str, list[str]] = {c: [] for c in CHECKS}
        for f in self.failures:
            name, _, reason = f.partition(": ")
            out.setdefault(name, []).append(reason)
        return out

    def failed(self, check: str) -> bool:
        """Whether the named check (e.g. ``"collision"``) reported a failure."""
        if check not in CHECKS:
            raise ValueError(f"unknown check {check!r}; the checks are {', '.join(CHECKS)}")
        return any(f.startswith(check + ": ") for f in self.failures)

    def __bool__(self) -> bool:
        return self.ok

    def __str__(self) -> str:
        head = (f"{'ok' if self.ok else 'FAILED'}: {self.free_fraction:.0%} of the floor free")
        return "\n".join([head, *(f"  {f}" for f in self.failures)])


def _area(a: float) -> str:
    return f"{a:.2f}" if a >= 0.01 else f"{a:.2g}"


def _polygons(corners: np.ndarray) -> np.ndarray:
    if len(corners) == 0:
        return np.empty(0, dtype=object)
    return shapely.polygons(corners)


def _corners(pos: np.ndarray, right: np.ndarray, front: np.ndarray, half: np.ndarray
             ) -> np.ndarray:
    sx = np.array([-1.0, 1.0, 1.0, -1.0])[None, :, None]
    sy = np.array([-1.0, -1.0, 1.0, 1.0])[None, :, None]
    return (pos[:, None, :] + sx * half[:, None, 0:1] * right[:, None, :]
            + sy * half[:, None, 1:2] * front[:, None, :])


def _check_positive(name: str, value: float, *, allow_zero: bool = True) -> None:
    ok = np.isfinite(value) and (value >= 0 if allow_zero else value > 0)
    if not ok:
        need = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"check_layout: {name} must be a finite number {need}, got {value!r}")


def check_layout(
    layout: Layout,
    *,
    agent_radius: float = 0.2,
    grid: float = 0.05,
    min_free_fraction: float = 0.3,
    reach: float = 0.25,
    max_overlap: float = 1e-4,
    door_clearance: bool = True,
) -> CheckReport:
    """Run the deterministic checks on a layout.

    Parameters
    ----------
    layout : Layout
        Poses per object; objects whose surface is ``"floor"`` are obstacles.
    agent_radius : float
        Radius of the disc-shaped agent, metres (default 0.2).
    grid : float
        Cell size of the floor grid used by ``navigable`` and ``reachable``,
        metres (default 0.05).
    min_free_fraction : float
        Smallest fraction of the floor that must stay free for the agent's
        centre, in [0, 1] (default 0.3).
    reach : float
        How close, in metres, the agent's body must get to each primary
        object (default 0.25).
    max_overlap : float
        Overlap area tolerated by ``collision``, ``outside``, ``door`` and
        on-top placement, m² (default 1e-4).
    door_clearance : bool
        Run the ``door`` check (default True).

    Returns
    -------
    CheckReport
        ``ok``, the failure lines, the free fraction, unreachable primary
        objects and the free-cell mask.

    Examples
    --------
    >>> report = layout.check()                    # doctest: +SKIP
    >>> report.ok, report.failures                 # doctest: +SKIP
    (False, ["door: 'wardrobe' blocks the swing area of door 0"])
    """
    _check_positive("agent_radius", agent_radius)
    _check_positive("grid", grid, allow_zero=False)
    _check_positive("reach", reach)
    _check_positive("max_overlap", max_overlap)
    if not 0.0 <= min_free_fraction <= 1.0:
        raise ValueError(f"check_layout: min_free_fraction must lie in [0, 1], "
                         f"got {min_free_fraction!r}")
    room = layout.room
    failures: list[str] = []
    ids, pos, yaw, half = _floor_arrays(layout)
    right, front = right_vectors(yaw), front_vectors(yaw)
    corners = _corners(pos, right, front, half)
    polys = _polygons(corners)

    failures += _collisions(ids, pos, right, front, half, polys, max_overlap)
    failures += _outside(ids, corners, polys, room, max_overlap)
    if door_clearance:
        failures += _doors(ids, pos, right, front, half, polys, room, max_overlap)
    failures += _surfaces(layout, max_overlap)

    rg = room_grid(room, grid=grid, agent_radius=agent_radius)
    if len(ids):
        dist2 = _footprint_dist2(rg.xs, rg.ys, pos - rg.origin, yaw, half)
        free = rg.wall_free & (dist2.min(0) > np.float32(agent_radius) ** 2)
    else:
        dist2 = np.zeros((0, *rg.shape), dtype=np.float32)
        free = rg.wall_free.copy()
    free_fraction = float(free.sum()) / max(rg.n_floor, 1)
    if free_fraction < min_free_fraction:
        failures.append(
            f"navigable: only {free_fraction:.0%} of the floor is free for an agent of radius "
            f"{agent_radius:g} m (need {min_free_fraction:.0%})")

    unreachable, reach_fail = _reachable(layout, ids, dist2, free, rg.door_seeds,
                                         agent_radius + reach)
    failures += reach_fail
    return CheckReport(ok=not failures, failures=failures, free_fraction=free_fraction,
                       unreachable=unreachable, free_mask=free, origin=rg.origin.copy(),
                       grid=float(grid))


def _collisions(ids: list[str], pos: np.ndarray, right: np.ndarray, front: np.ndarray,
                half: np.ndarray, polys: np.ndarray, max_overlap: float) -> list[str]:
    if len(ids) < 2:
        return []
    sep = separation_matrix(pos, right, front, half)
    i, j = np.nonzero(np.triu(sep < 0.0, k=1))
    if len(i) == 0:
        return []
    area = shapely.area(shapely.intersection(polys[i], polys[j]))
    bad = area > max_overlap
    return [f"collision: {ids[a]!r} and {ids[b]!r} overlap by {_area(s)} m²"
            for a, b, s in zip(i[bad], j[bad], area[bad], strict=True)]


def _surely_inside(corners: np.ndarray, room) -> np.ndarray:
    """Footprints certainly inside the floor: all corners inside, no wall vertex inside them."""
    inside = room.contains(corners).all(-1)  # (N,)
    # a wall vertex strictly inside a footprint means the floor cuts into it
    rel = room.polygon[None, :, :] - corners.mean(1)[:, None, :]  # (N, V, 2)
    ax = corners[:, 1] - corners[:, 0]
    ay = corners[:, 3] - corners[:, 0]
    hx = 0.5 * np.linalg.norm(ax, axis=-1)
    hy = 0.5 * np.linalg.norm(ay, axis=-1)
    u = np.abs((rel * ax[:, None, :]).sum(-1)) / np.maximum(2 * hx[:, None], 1e-12)
    v = np.abs((rel * ay[:, None, :]).sum(-1)) / np.maximum(2 * hy[:, None], 1e-12)
    vertex_in = ((u < hx[:, None] - 1e-9) & (v < hy[:, None] - 1e-9)).any(-1)
    return inside & ~vertex_in


def _outside(ids: list[str], corners: np.ndarray, polys: np.ndarray, room,
             max_overlap: float) -> list[str]:
    if not ids:
        return []
    cand = np.nonzero(~_surely_inside(corners, room))[0]
    if len(cand) == 0:
        return []
    area = shapely.area(shapely.difference(polys[cand], room.shape))
    bad = area > max_overlap
    return [f"outside: {ids[k]!r} pokes {_area(a)} m² out of the room"
            for k, a in zip(cand[bad], area[bad], strict=True)]


def _doors(ids: list[str], pos: np.ndarray, right: np.ndarray, front: np.ndarray,
           half: np.ndarray, polys: np.ndarray, room, max_overlap: float) -> list[str]:
    n_doors = len(room.doors)
    if not ids or n_doors == 0:
        return []
    dc, dr, df, dh = room.door_squares
    allpos = np.vstack([pos, dc])
    sep = separation_matrix(allpos, np.vstack([right, dr]), np.vstack([front, df]),
                            np.vstack([half, dh]))[: len(ids), len(ids):]  # (N, D)
    k, d = np.nonzero(sep < 0.0)
    if len(k) == 0:
        return []
    squares = _polygons(_corners(dc, dr, df, dh))
    area = shapely.area(shapely.intersection(polys[k], squares[d]))
    bad = area > max_overlap
    return [f"door: {ids[a]!r} blocks the swing area of door {b}"
            for a, b in zip(k[bad], d[bad], strict=True)]


def _pose_corners(layout: Layout, oid: str) -> np.ndarray:
    p = layout.poses[oid]
    yaw = np.array([p.yaw])
    return _corners(np.array([[p.x, p.y]]), right_vectors(yaw), front_vectors(yaw),
                    0.5 * np.array([layout.plan.object(oid).size[:2]], dtype=float))[0]


def _surfaces(layout: Layout, max_overlap: float) -> list[str]:
    out: list[str] = []
    poses = layout.poses
    room = layout.room
    plan = layout.plan
    off = [oid for oid in layout.ids() if poses[oid].surface != "floor"]
    for oid in off:  # one pass over the off-floor objects; each test is O(1) or one shapely op
        p = poses[oid]
        surf = p.surface
        if surf == "ceiling":
            c = _pose_corners(layout, oid)
            if _surely_inside(c[None], room)[0]:
                continue
            a = shapely.area(shapely.difference(shapely.Polygon(c), room.shape))
            if a > max_overlap:
                out.append(f"surface: {oid!r} on the ceiling pokes {_area(a)} m² out of the room")
        elif surf.startswith("wall:"):
            out += _wall_surface(oid, p, plan.object(oid).size, surf, room)
        elif surf in poses:
            c = _pose_corners(layout, oid)
            top = _pose_corners(layout, surf)
            # the parent's top is convex: inside when every corner of the child is
            ex, ey = top[1] - top[0], top[3] - top[0]
            rel = c - top.mean(0)
            u = np.abs(rel @ ex) / max(float(ex @ ex), 1e-18)
            v = np.abs(rel @ ey) / max(float(ey @ ey), 1e-18)
            if (u <= 0.5 + 1e-9).all() and (v <= 0.5 + 1e-9).all():
                continue
            a = shapely.area(shapely.difference(shapely.Polygon(c), shapely.Polygon(top)))
            if a > max_overlap:
                out.append(f"surface: {oid!r} overhangs the top of {surf!r} by {_area(a)} m²")
        elif surf in plan.ids:
            out.append(f"surface: {oid!r} rests on {surf!r}, which is not placed")
        else:
            out.append(f"surface: {oid!r} has unknown surface {surf!r} (expected 'floor', a "
                       "placed object id, 'wall:<i>' or 'ceiling')")
    return out


def _wall_surface(oid: str, p, size: tuple[float, float, float], surf: str, room) -> list[str]:
    try:
        w = int(surf.split(":", 1)[1])
    except ValueError:
        return [f"surface: {oid!r} has unknown surface {surf!r} (expected 'wall:<i>')"]
    if not 0 <= w < room.n_walls:
        return [f"surface: {oid!r} is on wall {w}, but the room has walls 0..{room.n_walls - 1}"]
    c = np.array([p.x, p.y]) - room.a[w]
    t = float(c @ room.tangent[w])
    n = float(c @ room.normal[w])
    width, depth, height = size
    out = []
    if abs(n) > 0.5 * depth + _SURFACE_TOL:
        out.append(f"surface: {oid!r} is {abs(n):.2f} m from wall {w}, not on it")
    if t - 0.5 * width < -_SURFACE_TOL or t + 0.5 * width > room.length[w] + _SURFACE_TOL:
        out.append(f"surface: {oid!r} extends past the ends of wall {w}")
    if p.z < -_SURFACE_TOL or p.z + height > room.height + _SURFACE_TOL:
        out.append(f"surface: {oid!r} on wall {w} is not between the floor and the ceiling "
                   f"(z = {p.z:.2f} m, height {height:.2f} m, room {room.height:.2f} m)")
    return out


def _reachable(layout: Layout, ids: list[str], dist2: np.ndarray, free: np.ndarray,
               seeds: np.ndarray, near: float) -> tuple[list[str], list[str]]:
    prim = [k for k, oid in enumerate(ids) if layout.plan.object(oid).primary]
    if not prim:
        return [], []
    labels, n = ndimage.label(free)  # 4-connected in 2D
    if len(seeds):
        door_labels = [np.unique(labels[s & free]) for s in seeds]
        door_labels = [lab[lab > 0] for lab in door_labels]
        names = [f"door {k}" for k in range(len(seeds))]
    else:
        if n == 0:
            door_labels = [np.zeros(0, dtype=int)]
        else:
            sizes = np.bincount(labels.ravel(), minlength=n + 1)
            sizes[0] = 0
            door_labels = [np.array([int(sizes.argmax())])]
        names = ["the largest free region"]
    # label membership per region: (n + 1,) bool table per door
    table = np.zeros((len(door_labels), n + 1), dtype=bool)
    for k, lab in enumerate(door_labels):
        table[k, lab] = True
    near_cells = dist2[prim] <= np.float32(near) ** 2  # (P, H, W)
    unreachable: list[str] = []
    failures: list[str] = []
    for row, k in enumerate(prim):
        labs = np.unique(labels[near_cells[row] & free])
        labs = labs[labs > 0]
        ok = table[:, labs].any(-1) if len(labs) else np.zeros(len(table), dtype=bool)
        if not ok.all():
            unreachable.append(ids[k])
            for d in np.nonzero(~ok)[0]:
                failures.append(f"reachable: {ids[k]!r} cannot be reached from {names[d]}")
    return unreachable, failures
