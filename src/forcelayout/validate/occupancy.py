"""The floor as a grid: where an agent's centre may stand.

The floor's bounding box is cut into square cells of ``grid`` metres; cell
``[row, col]`` has its centre at ``origin + ((col + 0.5) * grid, (row + 0.5) * grid)``,
so rows run along +y and columns along +x. A cell is *floor* when its centre
lies inside the floor polygon. A floor cell is *free* for a disc-shaped agent
of radius ``agent_radius`` when its centre is farther than ``agent_radius``
from every floor obstacle's footprint (walkable covers such as rugs are none)
and at least ``agent_radius`` from every solid part of a wall (door openings
are not solid, so an agent can pass).

Per-room grids (floor cells, wall clearance, the cells just inside each
door) depend only on the room, the grid size and the agent radius; they are
computed once and cached.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np

from forcelayout._compiled import kernels
from forcelayout.geometry import RoomGeometry, point_segment_distance

if TYPE_CHECKING:
    from forcelayout.layout import Layout

__all__ = ["RoomGrid", "room_grid", "footprint_distance", "occupancy_mask"]

#: Largest number of cells a room grid may have (a 100 x 100 m room at 5 cm).
MAX_CELLS = 4_000_000


@dataclass(frozen=True)
class RoomGrid:
    """Cached rasterisation of one room at one grid size and agent radius.

    Attributes
    ----------
    origin : ndarray, shape (2,)
        World position of the lower-left corner of cell ``[0, 0]``, metres.
    grid : float
        Cell size, metres.
    xs, ys : ndarray, shapes (W,), (H,)
        Cell-centre coordinates relative to ``origin``, metres.
    floor : ndarray of bool, shape (H, W)
        Cells whose centre lies inside the floor polygon.
    wall_free : ndarray of bool, shape (H, W)
        Floor cells at least the agent radius away from solid walls.
    door_seeds : ndarray of bool, shape (D, H, W)
        Per door, the floor cells just inside its opening (where an agent
        coming through the door stands).
    """

    origin: np.ndarray
    grid: float
    xs: np.ndarray
    ys: np.ndarray
    floor: np.ndarray
    wall_free: np.ndarray
    door_seeds: np.ndarray

    @property
    def shape(self) -> tuple[int, int]:
        """``(H, W)``: rows (along y) and columns (along x)."""
        return self.floor.shape  # type: ignore[return-value]

    @property
    def n_floor(self) -> int:
        """Number of floor cells."""
        return int(self._n_floor)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_n_floor", int(self.floor.sum()))


def _solid_walls(room: RoomGeometry) -> tuple[np.ndarray, np.ndarray]:
    """Wall segments with the door openings cut out, as (S, 2) start and end points."""
    starts: list[np.ndarray] = []
    ends: list[np.ndarray] = []
    d = room.doors
    for w in range(room.n_walls):
        length = float(room.length[w])
        cuts = sorted(
            (float(np.dot(d.centre[k] - room.a[w], room.tangent[w])), float(d.width[k]))
            for k in range(len(d)) if int(d.wall[k]) == w
        )
        t = 0.0
        for centre, width in cuts:
            lo = max(0.0, centre - 0.5 * width)
            if lo > t:
                starts.append(room.a[w] + room.tangent[w] * t)
                ends.append(room.a[w] + room.tangent[w] * lo)
            t = max(t, min(length, centre + 0.5 * width))
        if t < length:
            starts.append(room.a[w] + room.tangent[w] * t)
            ends.append(room.b[w])
    if not starts:
        return np.zeros((0, 2)), np.zeros((0, 2))
    return np.array(starts), np.array(ends)


@lru_cache(maxsize=64)
def _room_grid_cached(
    polygon: tuple[tuple[float, float], ...],
    doors: tuple[tuple[int, float, float], ...],
    grid: float,
    agent_radius: float,
) -> RoomGrid:
    room = RoomGeometry(np.array(polygon, dtype=float), doors=list(doors))
    lo, hi = room.bounds[:2], room.bounds[2:]
    w = max(1, int(np.ceil((hi[0] - lo[0]) / grid - 1e-9)))
    h = max(1, int(np.ceil((hi[1] - lo[1]) / grid - 1e-9)))
    if w * h > MAX_CELLS:
        raise ValueError(
            f"grid: a {grid} m grid over this {hi[0] - lo[0]:.1f} x {hi[1] - lo[1]:.1f} m room "
            f"has {w * h} cells (limit {MAX_CELLS}); use a coarser grid")
    xs = (np.arange(w) + 0.5) * grid
    ys = (np.arange(h) + 0.5) * grid
    rel = RoomGeometry(room.polygon - lo, doors=list(doors))
    centres = np.stack(np.meshgrid(xs, ys), axis=-1)  # (H, W, 2)
    floor = rel.contains(centres)
    sa, sb = _solid_walls(rel)
    if len(sa):
        dist, _ = point_segment_distance(centres[..., None, :], sa, sb)
        wall_free = floor & (dist.min(-1) >= agent_radius)
    else:
        wall_free = floor.copy()
    dd = rel.doors
    seeds = np.zeros((len(dd), h, w), dtype=bool)
    depth = max(agent_radius, grid) + grid
    for k in range(len(dd)):
        off = centres - dd.centre[k]
        t = off @ dd.tangent[k]
        n = off @ dd.normal[k]
        seeds[k] = floor & (np.abs(t) <= 0.5 * dd.width[k]) & (n >= 0.0) & (n <= depth)
    for arr in (floor, wall_free, seeds, xs, ys):
        arr.setflags(write=False)
    return RoomGrid(lo.copy(), float(grid), xs, ys, floor, wall_free, seeds)


def room_grid(room: RoomGeometry, *, grid: float = 0.05, agent_radius: float = 0.2) -> RoomGrid:
    """The cached :class:`RoomGrid` of a room.

    Parameters
    ----------
    room : RoomGeometry
        The room (only its polygon and doors matter).
    grid : float
        Cell size, metres (> 0).
    agent_radius : float
        Radius of the disc-shaped agent, metres (>= 0).

    Returns
    -------
    RoomGrid
        Read-only arrays, shared between calls with the same room and settings.
    """
    if not grid > 0 or not np.isfinite(grid):
        raise ValueError(f"grid must be a positive number of metres, got {grid!r}")
    if not agent_radius >= 0 or not np.isfinite(agent_radius):
        raise ValueError(f"agent_radius must be >= 0 metres, got {agent_radius!r}")
    poly = tuple((float(x), float(y)) for x, y in room.polygon)
    d = room.doors
    dist_along = ((d.centre - room.a[d.wall]) * room.tangent[d.wall]).sum(-1)
    doors = tuple((int(w), float(o), float(wd))
                  for w, o, wd in zip(d.wall, dist_along, d.width, strict=True))
    return _room_grid_cached(poly, doors, float(grid), float(agent_radius))


def footprint_distance(
    xs: np.ndarray, ys: np.ndarray, pos: np.ndarray, yaw: np.ndarray, half: np.ndarray
) -> np.ndarray:
    """Distance from every cell centre to every oriented rectangle.

    Parameters
    ----------
    xs, ys : ndarray, shapes (W,), (H,)
        Cell-centre coordinates, metres (same frame as ``pos``; keep the
        frame's origin near the room, as the work is done in float32).
    pos : ndarray, shape (N, 2)
        Footprint centres, metres.
    yaw : ndarray, shape (N,)
        Headings, radians CCW.
    half : ndarray, shape (N, 2)
        Half width and half depth, metres.

    Returns
    -------
    ndarray of float32, shape (N, H, W)
        Euclidean distance in metres from each cell centre to each footprint
        (0 inside it).
    """
    return np.sqrt(_footprint_dist2(xs, ys, pos, yaw, half))


def _footprint_dist2(
    xs: np.ndarray, ys: np.ndarray, pos: np.ndarray, yaw: np.ndarray, half: np.ndarray
) -> np.ndarray:
    """Squared form of :func:`footprint_distance`, in float32 (m²); a compiled loop where
    numba is installed (:mod:`forcelayout._compiled`, the same values bit for bit)."""
    f = np.float32
    xs, ys = np.asarray(xs, dtype=f), np.asarray(ys, dtype=f)
    pos, half = np.asarray(pos, dtype=f), np.asarray(half, dtype=f)
    yaw = np.asarray(yaw, dtype=f)
    fast = kernels()
    if fast is not None:
        def flat(a: np.ndarray) -> np.ndarray:
            return np.ascontiguousarray(a, dtype=f).reshape(-1)

        return fast.footprint_dist2(flat(xs), flat(ys), flat(pos[:, 0]), flat(pos[:, 1]),
                                    flat(np.cos(yaw)), flat(np.sin(yaw)), flat(half[:, 0]),
                                    flat(half[:, 1]))
    c = np.cos(yaw)[:, None, None]
    s = np.sin(yaw)[:, None, None]
    dx = xs[None, None, :] - pos[:, 0, None, None]  # (N, 1, W)
    dy = ys[None, :, None] - pos[:, 1, None, None]  # (N, H, 1)
    qx = np.abs(dx * c + dy * s)  # along the object's right axis
    qx -= half[:, 0, None, None]
    qy = np.abs(dy * c - dx * s)  # along its front axis
    qy -= half[:, 1, None, None]
    np.maximum(qx, f(0.0), out=qx)
    np.maximum(qy, f(0.0), out=qy)
    qx *= qx
    qy *= qy
    qx += qy
    return qx


def _floor_arrays(layout: Layout, *, obstacles_only: bool = False
                  ) -> tuple[list[str], np.ndarray, np.ndarray, np.ndarray]:
    """Ids, centres, headings and half extents of the floor objects.

    With ``obstacles_only``, walkable floor covers (rugs, mats) are left out.
    """
    ids = layout.ids("floor")
    if obstacles_only:
        plan = layout.plan
        ids = [i for i in ids if not plan.object(i).is_walkable]
    if not ids:
        return ids, np.zeros((0, 2)), np.zeros(0), np.zeros((0, 2))
    poses = layout.poses
    pos = np.array([[poses[i].x, poses[i].y] for i in ids], dtype=float)
    yaw = np.array([poses[i].yaw for i in ids], dtype=float)
    half = 0.5 * np.array([layout.plan.object(i).size[:2] for i in ids], dtype=float)
    return ids, pos, yaw, half


def occupancy_mask(
    layout: Layout, *, agent_radius: float = 0.2, grid: float = 0.05
) -> tuple[np.ndarray, np.ndarray]:
    """Floor cells covered by floor obstacles inflated by the agent radius.

    Walkable floor covers (rugs, mats; :attr:`SceneObject.is_walkable`) are
    no obstacle and leave no mark.

    Two layouts of the same plan share the grid, so their masks can be
    compared cell by cell (e.g. a Jaccard distance for topological diversity).

    Parameters
    ----------
    layout : Layout
    agent_radius : float
        Inflation of every footprint, metres (default 0.2).
    grid : float
        Cell size, metres (default 0.05).

    Returns
    -------
    mask : ndarray of bool, shape (H, W)
        True on floor cells whose centre is within ``agent_radius`` of a
        floor obstacle's footprint; rows run along +y, columns along +x.
        Walls are not marked.
    origin : ndarray, shape (2,)
        World position (metres) of the lower-left corner of cell ``[0, 0]``.
    """
    rg = room_grid(layout.room, grid=grid, agent_radius=agent_radius)
    _, pos, yaw, half = _floor_arrays(layout, obstacles_only=True)
    if len(pos) == 0:
        return np.zeros(rg.shape, dtype=bool), rg.origin.copy()
    d2 = _footprint_dist2(rg.xs, rg.ys, pos - rg.origin, yaw, half)
    return rg.floor & (d2.min(0) <= np.float32(agent_radius) ** 2), rg.origin.copy()
