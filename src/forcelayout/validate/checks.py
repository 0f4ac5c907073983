"""Deterministic checks of a finished layout (stage V of the method).

:func:`check_layout` runs, in order:

``collision``
    No two floor objects' footprints overlap by more than ``max_overlap`` m².
    Walkable floor covers (rugs, mats; :attr:`SceneObject.is_walkable`) are
    no obstacle: furniture may stand on them and they may overlap each other.
``outside``
    No floor object's footprint, walkable ones included, lies outside the
    floor polygon by more than ``max_overlap`` m².
``door``
    No floor object (walkable ones excepted) covers more than
    ``max_overlap`` m² of the square of door width in front of any door (its
    swing area).
``window``
    No floor object taller than a window's sill (walkable ones excepted)
    covers more than ``max_overlap`` m² of the window's clearance zone: the
    window's width, :attr:`Window.clearance` metres deep into the room.
``surface``
    Objects off the floor rest where they say: on top of a placed parent and
    inside its top; on an existing wall, within its ends, below the ceiling;
    on the ceiling above the floor.
``navigable``
    Floor objects (walkable ones excepted) inflated by the agent radius leave
    at least ``min_free_fraction`` of the floor free; the walls are not
    inflated (DESIGN.md's definition). The share with a wall band of the agent
    radius taken out as well is reported as ``navigable_fraction``.
``reachable``
    Every primary floor object has a free cell within ``agent_radius + reach``
    of its footprint (the agent's body comes within ``reach`` of it) that is
    4-connected through cells free for the agent's centre (at least the agent
    radius from furniture *and* from solid walls) to the cells just inside
    each door, and every door is so connected to the first (an agent walks
    through a room with two doors). A room without doors is checked from its
    largest free region instead. A failure names the objects that block the
    cheapest way in.

Each failure is a line ``"<check>: <reason naming the objects>"``.
"""

from __future__ import annotations

import contextvars
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely

from forcelayout.geometry import (
    RoomGeometry,
    corners_from_axes,
    front_vectors,
    obb_separation,
    right_vectors,
    separation_matrix,
)
from forcelayout.validate.occupancy import _floor_arrays, _footprint_dist2, room_grid

if TYPE_CHECKING:
    from forcelayout.layout import Layout
    from forcelayout.plan import Room

__all__ = ["CheckReport", "check_layout", "check_floors", "check_parameters", "CHECKS",
           "window_zones"]

#: Names of the checks, in the order they run.
CHECKS = ("collision", "outside", "door", "window", "access", "surface", "navigable",
          "reachable")

_SURFACE_TOL = 0.01  # metres of slack for objects on walls
_BLOCKED_COST = 100.0  # cost of a blocked cell against a free one when naming blockers


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
        Share of the floor cells farther than the agent radius from every
        floor obstacle (walkable covers are none), in [0, 1]; the walls are not
        inflated. The ``navigable`` check compares it with
        ``min_free_fraction``.
    navigable_fraction : float
        Share of the floor cells where the agent's centre fits: farther than
        the agent radius from every floor obstacle and at least the agent
        radius from every solid wall, in [0, 1] (never more than
        ``free_fraction``). Reported only, unless ``check_layout(...,
        wall_band=True)``.
    unreachable : list of str
        Ids of primary objects not reachable from every door.
    blocked_by : dict of str to list of str
        For each unreachable primary object, the floor objects in the way of
        the cheapest path to it (from the first door that cannot reach it),
        nearest the door first; empty when only the walls are in the way. A
        door the first door cannot reach (``"door 1"``) is listed the same way.
    free_mask : ndarray of bool, shape (H, W), optional
        Cells free for the agent's centre (furniture and wall band taken out;
        what ``reachable`` walks on). Rows along +y, columns along +x.
    origin : ndarray, shape (2,), optional
        World position of the lower-left corner of cell ``[0, 0]``, metres.
    grid : float
        Cell size, metres.
    """

    ok: bool
    failures: list[str] = field(default_factory=list)
    free_fraction: float = 1.0
    navigable_fraction: float = 1.0
    unreachable: list[str] = field(default_factory=list)
    blocked_by: dict[str, list[str]] = field(default_factory=dict)
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
        head = (f"{'ok' if self.ok else 'FAILED'}: {self.free_fraction:.0%} of the floor free "
                f"({self.navigable_fraction:.0%} with the wall band)")
        return "\n".join([head, *(f"  {f}" for f in self.failures)])


def _area(a: float) -> str:
    return f"{a:.2f}" if a >= 0.01 else f"{a:.2g}"


def _area_over(a: float, limit: float) -> str:
    """An area above ``limit``, m², with enough digits to read above it."""
    for digits in range(2, 7):
        shown = f"{a:.{digits}f}"
        if float(shown) > limit:
            return shown
    return f"{a:.6g}"


def _percents(value: float, need: float) -> tuple[str, str]:
    """``value`` and ``need`` as percentages, with enough digits to show ``value < need``."""
    shown_need = f"{100 * need:.6g}"
    for digits in range(5):
        shown = f"{100 * value:.{digits}f}"
        if float(shown) < float(shown_need):
            return shown, shown_need
    return f"{100 * value:.6g}", shown_need


def _polygons(corners: np.ndarray) -> np.ndarray:
    if len(corners) == 0:
        return np.empty(0, dtype=object)
    return shapely.polygons(corners)


def _check_positive(name: str, value: float, *, allow_zero: bool = True) -> None:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.number)):
        need = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"check_layout: {name} must be a finite number {need}, got {value!r}")
    ok = np.isfinite(value) and (value >= 0 if allow_zero else value > 0)
    if not ok:
        need = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"check_layout: {name} must be a finite number {need}, got {value!r}")


#: The check parameters that are numbers, and whether 0 is allowed.
_NUMBERS = {"agent_radius": True, "grid": False, "reach": True, "max_overlap": True,
            "max_access_overlap": True, "access_width": False}
#: The check parameters that are switches.
_FLAGS = ("door_clearance", "window_clearance", "wall_band", "access_clearance")


def check_parameters(**given: Any) -> None:
    """Refuse a parameter of :func:`check_layout` out of range or of the wrong type (a
    ValueError naming it), as the checks and ``Options.check_kwargs`` do before any
    sampling. Only the parameters given are judged (their defaults are valid)."""
    for name, value in given.items():
        if name in _NUMBERS:
            _check_positive(name, value, allow_zero=_NUMBERS[name])
        elif name in _FLAGS:
            if not isinstance(value, (bool, np.bool_)):
                raise ValueError(f"check_layout: {name} must be True or False, got {value!r}")
        elif name == "min_free_fraction":
            if isinstance(value, bool) or not isinstance(value, (int, float, np.number)) \
                    or not 0.0 <= value <= 1.0:
                raise ValueError(f"check_layout: min_free_fraction must lie in [0, 1], "
                                 f"got {value!r}")
        else:
            raise ValueError(f"check_layout: unknown check parameter {name!r}")


def check_layout(
    layout: Layout,
    *,
    agent_radius: float = 0.2,
    grid: float = 0.05,
    min_free_fraction: float = 0.3,
    reach: float = 0.25,
    max_overlap: float = 1e-4,
    door_clearance: bool = True,
    window_clearance: bool = True,
    wall_band: bool = False,
    access_clearance: bool = False,
    max_access_overlap: float = 0.1,
    access_width: float = 0.6,
) -> CheckReport:
    """Run the deterministic checks on a layout.

    Parameters
    ----------
    layout : Layout
        Poses per object; objects whose surface is ``"floor"`` are obstacles,
        except walkable floor covers (:attr:`SceneObject.is_walkable`).
    agent_radius : float
        Radius of the disc-shaped agent, metres (default 0.2).
    grid : float
        Cell size of the floor grid used by ``navigable`` and ``reachable``,
        metres (default 0.05).
    min_free_fraction : float
        Smallest fraction of the floor that must stay free of floor obstacles
        inflated by the agent radius, in [0, 1] (default 0.3).
    reach : float
        How close, in metres, the agent's body must get to each primary
        object (default 0.25).
    max_overlap : float
        Overlap area tolerated by ``collision``, ``outside``, ``door``,
        ``window`` and on-top placement, m² (default 1e-4).
    door_clearance : bool
        Run the ``door`` check (default True).
    window_clearance : bool
        Run the ``window`` check (default True).
    wall_band : bool
        Let ``navigable`` compare the share of the floor free for the agent's
        centre *with* a wall band of the agent radius taken out
        (``navigable_fraction``) instead of ``free_fraction`` (default False,
        as DESIGN.md defines the check).
    access_clearance : bool
        Run the ``access`` check (default False): every object with access
        zones (:mod:`forcelayout.access`: the front of a wardrobe, desk,
        counter or fridge, a long side of a bed) keeps at least one of them
        free. A zone is free when some stretch of it ``access_width`` wide
        (the whole side if it is narrower), as deep as the zone, has at most
        ``max_access_overlap`` and at most a third of its area covered by
        solid objects that no rule relates
        to its owner or lying off the floor: a nightstand at the head of a
        bed leaves the rest of that side to get in from. The simulation keeps
        the whole zones free by a force and by start poses; this check makes
        it a requirement.
    max_access_overlap : float
        Area of a stretch of an access zone, m², that may be covered or off
        the floor before it counts as blocked (default 0.1); never more than
        a third of the stretch (0.045 m² of the 0.45 x 0.3 m zone behind a
        chair).
    access_width : float
        Width of the free stretch a person needs along a side, metres
        (default 0.6).

    Returns
    -------
    CheckReport
        ``ok``, the failure lines, the free and navigable fractions,
        unreachable primary objects with what blocks them, and the free-cell
        mask.

    Examples
    --------
    >>> report = layout.check()                    # doctest: +SKIP
    >>> report.ok, report.failures                 # doctest: +SKIP
    (False, ["door: 'wardrobe' blocks the swing area of door 0"])
    """
    return check_floors([layout], agent_radius=agent_radius, grid=grid,
                        min_free_fraction=min_free_fraction, reach=reach,
                        max_overlap=max_overlap, door_clearance=door_clearance,
                        window_clearance=window_clearance, wall_band=wall_band,
                        access_clearance=access_clearance,
                        max_access_overlap=max_access_overlap, access_width=access_width)[0]


def check_floors(
    layouts: Sequence[Layout],
    *,
    agent_radius: float = 0.2,
    grid: float = 0.05,
    min_free_fraction: float = 0.3,
    reach: float = 0.25,
    max_overlap: float = 1e-4,
    door_clearance: bool = True,
    window_clearance: bool = True,
    wall_band: bool = False,
    access_clearance: bool = False,
    max_access_overlap: float = 0.1,
    access_width: float = 0.6,
    name_blockers: bool = True,
) -> list[CheckReport]:
    """:func:`check_layout` for many layouts, the checks of their floors run together.

    Layouts of one plan with the same floor objects share each step of the
    floor checks (one array with a leading layout axis); each report is the
    one :func:`check_layout` gives that layout alone. Parameters as for
    :func:`check_layout`; ``name_blockers=False`` leaves out what blocks the
    way to an unreachable object (``blocked_by`` empty, the failure lines
    without "blocked by"): the same failures, counted as many, for less
    (a path search per unreachable object and door).

    Returns
    -------
    list of CheckReport
        One per layout, in order.
    """
    args = (agent_radius, grid, min_free_fraction, reach, max_overlap, door_clearance,
            window_clearance, wall_band, access_clearance, max_access_overlap, access_width,
            bool(name_blockers))
    check_parameters(agent_radius=agent_radius, grid=grid, min_free_fraction=min_free_fraction,
                     reach=reach, max_overlap=max_overlap, door_clearance=door_clearance,
                     window_clearance=window_clearance, wall_band=wall_band,
                     access_clearance=access_clearance, max_access_overlap=max_access_overlap,
                     access_width=access_width)
    kept = _FLOOR_CHECKS.get()
    floors: list[tuple | None] = []
    todo: dict[tuple, list[int]] = {}  # layouts whose floors are checked together
    arrays = []
    for k, layout in enumerate(layouts):
        ids, pos, yaw, half = _floor_arrays(layout)
        key = (id(layout.plan), tuple(ids), pos.tobytes(), yaw.tobytes(), half.tobytes(),
               *args)
        hit = None if kept is None else kept.get(key)
        floors.append(hit[1] if hit is not None and hit[0] is layout.plan else None)
        arrays.append((key, ids, pos, yaw, half))
        if floors[-1] is None:
            todo.setdefault((id(layout.plan), tuple(ids), half.tobytes()), []).append(k)
    for ks in todo.values():
        _, ids, _, _, half = arrays[ks[0]]
        done = _floor_checks(layouts[ks[0]], ids, np.stack([arrays[k][2] for k in ks]),
                             np.stack([arrays[k][3] for k in ks]), half, *args)
        for k, floor in zip(ks, done, strict=True):
            floors[k] = floor
            if kept is not None:
                if len(kept) >= _FLOOR_CHECKS_KEPT:
                    kept.pop(next(iter(kept)))
                kept[arrays[k][0]] = (layouts[k].plan, floor)
    out = []
    for layout, floor in zip(layouts, floors, strict=True):
        before, after, free_fraction, navigable_fraction, unreachable, blocked_by, free, \
            origin = floor
        failures = before + _surfaces(layout, max_overlap) + after
        out.append(CheckReport(ok=not failures, failures=failures, free_fraction=free_fraction,
                               navigable_fraction=navigable_fraction,
                               unreachable=list(unreachable),
                               blocked_by={k: list(v) for k, v in blocked_by.items()},
                               free_mask=free.copy(), origin=origin.copy(), grid=float(grid)))
    return out


#: Within :func:`reusing_floor_checks`: the floor checks of recent layouts, key -> (plan,
#: results), oldest out first. A floor judged after settling is judged again with its objects
#: on tops, walls and the ceiling; its floor checks are then not run twice.
_FLOOR_CHECKS: contextvars.ContextVar[dict | None] = contextvars.ContextVar(
    "forcelayout_floor_checks", default=None)
_FLOOR_CHECKS_KEPT = 256


@contextmanager
def reusing_floor_checks() -> Iterator[None]:
    """Within the block, :func:`check_layout` reuses the checks of a floor it has checked.

    Two layouts with the same plan object, the same floor poses (bit for bit)
    and the same thresholds share every check but ``surfaces``. The samples
    of a batch run in such a block (the plan does not change there); outside
    one, nothing is reused.
    """
    token = _FLOOR_CHECKS.set({})
    try:
        yield
    finally:
        _FLOOR_CHECKS.reset(token)


#: Bytes of footprint distances (float32, floors x objects x cells) computed at once.
_DIST_BYTES = 32 * 2**20


def _floor_checks(layout: Layout, ids: list[str], pos: np.ndarray, yaw: np.ndarray,
                  half: np.ndarray, agent_radius: float, grid: float,
                  min_free_fraction: float, reach: float, max_overlap: float,
                  door_clearance: bool, window_clearance: bool, wall_band: bool,
                  access_clearance: bool, max_access_overlap: float,
                  access_width: float, name_blockers: bool = True) -> list[tuple]:
    """Every check of the floor objects alone (all but ``surfaces``) of B floors of
    ``layout``'s plan with the same objects ``ids`` at poses (B, N, 2) and (B, N), checked
    together: per floor, the failures before and after where ``surfaces`` goes, the
    fractions, the unreachable objects, what blocks them, the free mask and its origin."""
    room = layout.room
    plan = layout.plan
    nb = len(yaw)
    height = np.array([plan.object(i).size[2] for i in ids], dtype=float)
    walk, solid, boxes, corners, polys = _floor_boxes(plan, ids, pos, yaw, half)
    halves = boxes[3]

    before: list[list[str]] = [[] for _ in range(nb)]
    for b, lines in enumerate(_collisions(ids, boxes, polys, solid, max_overlap)):
        before[b] += lines
    for b, lines in enumerate(_outside(ids, corners, polys, room, max_overlap)):
        before[b] += lines
    if door_clearance:
        for b, lines in enumerate(_doors(ids, boxes, polys, solid, room, max_overlap)):
            before[b] += lines
    if window_clearance:
        for b, lines in enumerate(_windows(ids, boxes, polys, solid, height, layout,
                                           max_overlap)):
            before[b] += lines
    if access_clearance:
        for b, lines in enumerate(_access(ids, boxes, polys, solid, walk, layout,
                                          max_access_overlap, access_width)):
            before[b] += lines
    rg = room_grid(room, grid=grid, agent_radius=agent_radius)
    r2 = np.float32(agent_radius) ** 2
    n_floor = max(rg.n_floor, 1)
    prim = [k for k, oid in enumerate(ids) if plan.object(oid).primary]
    # the footprint distances needed: the obstacles' (first), then walkable primary objects'
    rows = np.concatenate([solid, [k for k in prim if walk[k]]]).astype(int)
    ns = len(solid)
    out = []
    chunk = max(1, _DIST_BYTES // max(4 * len(rows) * rg.floor.size, 1))
    for c0 in range(0, nb, chunk):  # footprint distances of a few floors at a time
        bs = slice(c0, min(nb, c0 + chunk))
        if len(rows):
            dist2 = _footprint_dist2(rg.xs, rg.ys, (pos[bs][:, rows] - rg.origin).reshape(-1, 2),
                                     yaw[bs][:, rows].reshape(-1),
                                     halves[bs][:, rows].reshape(-1, 2))
            dist2 = dist2.reshape(-1, len(rows), *rg.shape)
        else:
            dist2 = np.zeros((len(pos[bs]), 0, *rg.shape), dtype=np.float32)
        if ns:
            clear = dist2[:, :ns].min(1) > r2  # (b, H, W)
        else:
            clear = np.ones((len(dist2), *rg.shape), dtype=bool)
        free = rg.wall_free & clear
        # free regions, each floor's numbered on their own (no cell links two floors)
        labels, _ = _label(free) if prim or len(rg.door_seeds) > 1 else (None, 0)
        reached = None  # (b, P, D): whether each primary object is reached from each door
        if prim and len(rg.door_seeds):
            at = {int(k): i for i, k in enumerate(rows)}
            reached = _reached_from_doors(labels, dist2[:, [at[k] for k in prim]],
                                          rg.door_seeds, np.float32(agent_radius + reach) ** 2)
        for m, b in enumerate(range(nb)[bs]):
            after: list[str] = []
            free_fraction = float((rg.floor & clear[m]).sum()) / n_floor
            navigable_fraction = float(free[m].sum()) / n_floor
            judged = navigable_fraction if wall_band else free_fraction
            if judged < min_free_fraction:
                shown, need = _percents(judged, min_free_fraction)
                where = "for the centre of" if wall_band else "for"
                after.append(f"navigable: only {shown}% of the floor is free {where} an agent "
                             f"of radius {agent_radius:g} m (need {need}%)")
            unreachable, blocked_by, reach_fail = _reachable(
                ids, prim, solid, rows, dist2[m], r2, free[m],
                None if labels is None else labels[m], rg, agent_radius + reach,
                None if reached is None else reached[m], name_blockers)
            after += reach_fail
            out.append((before[b], after, free_fraction, navigable_fraction, unreachable,
                        blocked_by, free[m], rg.origin.copy()))
    return out


def _floor_boxes(plan, ids: list[str], pos: np.ndarray, yaw: np.ndarray, half: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray, tuple[np.ndarray, ...], np.ndarray,
                            _Footprints]:
    """The footprints of B floors of objects ``ids`` at poses (B, N, 2) and (B, N): which
    rows are walkable covers, the solid rows (floor obstacles), the boxes ``(pos, right,
    front, half)`` (B, N, 2) each, their corners (B, N, 4, 2) and their polygons."""
    nb, n = yaw.shape
    walk = np.array([plan.object(i).is_walkable for i in ids], dtype=bool)
    right, front = right_vectors(yaw), front_vectors(yaw)  # (B, N, 2)
    halves = np.broadcast_to(half, (nb, n, 2))
    corners = corners_from_axes(pos.reshape(-1, 2), right.reshape(-1, 2),
                                front.reshape(-1, 2), halves.reshape(-1, 2)).reshape(nb, n, 4, 2)
    return walk, np.nonzero(~walk)[0], (pos, right, front, halves), corners, \
        _Footprints(corners)


#: 4-connected within each floor of a stack (B, H, W), never from one floor to the next.
_IN_PLANE = np.array([np.zeros((3, 3)), [[0, 1, 0], [1, 1, 1], [0, 1, 0]], np.zeros((3, 3))],
                     dtype=bool)


def _label(free: np.ndarray) -> tuple[np.ndarray, int]:
    """:func:`scipy.ndimage.label` of a stack of floors, each numbered on its own (4-connected
    within a floor); scipy.ndimage is imported when first needed (a third of a second
    that every command line call had paid)."""
    from scipy import ndimage

    return ndimage.label(free, structure=_IN_PLANE)


class _Footprints:
    """The shapely polygons of footprints (B, N, 4, 2), made when first asked for."""

    def __init__(self, corners: np.ndarray):
        self.corners = corners
        self._made: dict[tuple[int, int], object] = {}

    def __call__(self, b: int, ks: np.ndarray) -> np.ndarray:
        """Polygons of footprints ``ks`` of floor ``b``."""
        out = np.empty(len(ks), dtype=object)
        for m, k in enumerate(ks.tolist()):
            poly = self._made.get((b, k))
            if poly is None:
                poly = self._made[(b, k)] = shapely.polygons(self.corners[b, k])
            out[m] = poly
        return out


def _collisions(ids: list[str], boxes: tuple[np.ndarray, ...], polys: _Footprints,
                solid: np.ndarray, max_overlap: float) -> list[list[str]]:
    pos, right, front, half = boxes
    nb = len(pos)
    if len(solid) < 2:
        return [[] for _ in range(nb)]
    sep = separation_matrix(pos[:, solid], right[:, solid], front[:, solid], half[:, solid])
    out = []
    for b in range(nb):
        i, j = np.nonzero(np.triu(sep[b] < 0.0, k=1))
        if len(i) == 0:
            out.append([])
            continue
        i, j = solid[i], solid[j]
        area = shapely.area(shapely.intersection(polys(b, i), polys(b, j)))
        bad = area > max_overlap
        out.append([f"collision: {ids[a]!r} and {ids[c]!r} overlap by {_area(s)} m²"
                    for a, c, s in zip(i[bad], j[bad], area[bad], strict=True)])
    return out


def _outside(ids: list[str], corners: np.ndarray, polys: _Footprints, room,
             max_overlap: float) -> list[list[str]]:
    nb, n = corners.shape[:2]
    if not ids:
        return [[] for _ in range(nb)]
    # certainly inside: the exact area is computed only for the others
    sure = room.contains_boxes(corners)
    out = []
    for b in range(nb):
        cand = np.nonzero(~sure[b])[0]
        if len(cand) == 0:
            out.append([])
            continue
        area = shapely.area(shapely.difference(polys(b, cand), room.shape))
        bad = area > max_overlap
        out.append([f"outside: {ids[k]!r} pokes {_area(a)} m² out of the room"
                    for k, a in zip(cand[bad], area[bad], strict=True)])
    return out


def _zone_overlaps(boxes: tuple[np.ndarray, ...], polys: _Footprints, cand: np.ndarray,
                   zones: tuple[np.ndarray, ...], max_overlap: float
                   ) -> list[list[tuple[int, int]]]:
    """Per floor, the (object, zone) pairs whose footprint covers more than ``max_overlap``
    of the zone."""
    pos, right, front, half = boxes
    nb = len(pos)
    zc, zr, zf, zh = zones
    if len(cand) == 0 or len(zc) == 0:
        return [[] for _ in range(nb)]
    n = len(cand)

    def both(a: np.ndarray, z: np.ndarray) -> np.ndarray:  # the candidates, then the zones
        return np.concatenate([a[:, cand], np.broadcast_to(z, (nb, *z.shape))], axis=1)

    sep = separation_matrix(both(pos, zc), both(right, zr), both(front, zf),
                            both(half, zh))[:, :n, n:]
    out: list[list[tuple[int, int]]] = []
    squares = None
    for b in range(nb):
        k, z = np.nonzero(sep[b] < 0.0)
        if len(k) == 0:
            out.append([])
            continue
        if squares is None:
            squares = _polygons(corners_from_axes(zc, zr, zf, zh))
        area = shapely.area(shapely.intersection(polys(b, cand[k]), squares[z]))
        bad = area > max_overlap
        out.append([(int(cand[a]), int(c)) for a, c in zip(k[bad], z[bad], strict=True)])
    return out


def _doors(ids: list[str], boxes: tuple[np.ndarray, ...], polys: _Footprints,
           solid: np.ndarray, room, max_overlap: float) -> list[list[str]]:
    if len(room.doors) == 0:
        return [[] for _ in range(len(boxes[0]))]
    hits = _zone_overlaps(boxes, polys, solid, room.door_squares, max_overlap)
    return [[f"door: {ids[a]!r} blocks the swing area of door {b}" for a, b in h]
            for h in hits]


def window_zones(room: Room) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                                      np.ndarray]:
    """Each window's clearance zone as a box, and the window's sill height.

    The zone is what the ``window`` check keeps free of floor objects taller
    than the sill: the window's width along its wall, ``Window.clearance``
    metres deep into the room.

    Parameters
    ----------
    room : Room
        The plan's room (``plan.room``).

    Returns
    -------
    centre, right, front, half : ndarray, shapes (K, 2)
        Centre, unit axes (``right`` along the wall, ``front`` into the room)
        and half extents (half width, half depth) of each zone, metres.
    sill : ndarray, shape (K,)
        Sill height of each window above the floor, metres.

    Raises
    ------
    TypeError
        For a :class:`~forcelayout.geometry.RoomGeometry` (``layout.room``), which
        holds no sills: pass ``layout.plan.room``.
    """
    if isinstance(room, RoomGeometry):
        raise TypeError("window_zones takes the plan's room (layout.plan.room), with the "
                        "windows' sills and clearances, not its geometry (layout.room)")
    return _window_zones(RoomGeometry.from_room(room), room.windows)


def _window_zones(geom: RoomGeometry, specs: list) -> tuple[np.ndarray, ...]:
    w = geom.windows
    depth = np.array([o.clearance for o in specs], dtype=float).reshape(-1)
    sill = np.array([o.sill for o in specs], dtype=float).reshape(-1)
    centre, half = w.zones(depth)
    return centre.reshape(-1, 2), w.tangent.copy(), w.normal.copy(), half.reshape(-1, 2), sill


def _windows(ids: list[str], boxes: tuple[np.ndarray, ...], polys: _Footprints,
             solid: np.ndarray, height: np.ndarray, layout: Layout, max_overlap: float
             ) -> list[list[str]]:
    nb = len(boxes[0])
    out: list[list[str]] = [[] for _ in range(nb)]
    if not len(layout.plan.room.windows) or not len(solid):
        return out
    zc, zr, zf, zh, sill = _window_zones(layout.room, layout.plan.room.windows)
    for k in np.nonzero(zh[:, 1] > 0)[0]:  # a zone of depth 0 is switched off
        tall = solid[height[solid] > sill[k] + 1e-9]
        zone = (zc[k:k + 1], zr[k:k + 1], zf[k:k + 1], zh[k:k + 1])
        for b, hits in enumerate(_zone_overlaps(boxes, polys, tall, zone, max_overlap)):
            out[b] += [f"window: {ids[a]!r} ({height[a]:.2f} m tall) stands in front of "
                       f"window {k} (sill {sill[k]:.2f} m)" for a, _ in hits]
    return out


#: Step of the stretches of an access zone the check tries along its side, metres.
_ACCESS_STEP = 0.05

#: Largest share of a stretch of an access zone that may be covered or off the floor, on
#: top of ``max_access_overlap`` (m²): the cap of small zones (behind a chair, 0.135 m²).
_ACCESS_SHARE = 1.0 / 3.0


def _stretch_width(half: np.ndarray, width: float) -> float:
    """How wide the stretches of a zone of half extents ``half`` are: ``width``, or the
    zone's side if narrower."""
    return min(width, 2.0 * float(half[0]))


def _stretches(centre: np.ndarray, lateral: np.ndarray, out: np.ndarray, half: np.ndarray,
               width: float) -> np.ndarray:
    """Polygons of the stretches of one zone ``width`` wide (the zone if narrower), side
    by side every :data:`_ACCESS_STEP` metres from one end of the zone to the other."""
    w = _stretch_width(half, width)
    slack = 2.0 * float(half[0]) - w
    u = np.linspace(-0.5 * slack, 0.5 * slack, int(np.ceil(slack / _ACCESS_STEP)) + 1)
    k = len(u)
    corners = corners_from_axes(centre + u[:, None] * lateral, np.broadcast_to(lateral, (k, 2)),
                                np.broadcast_to(out, (k, 2)),
                                np.broadcast_to([0.5 * w, half[1]], (k, 2)))
    return _polygons(corners)


def _access(ids: list[str], boxes: tuple[np.ndarray, ...], polys: _Footprints,
            solid: np.ndarray, walk: np.ndarray, layout: Layout, limit: float, width: float
            ) -> list[list[str]]:
    """Per floor, a line for each object with every access zone blocked, saying by what:
    a zone is free when one stretch of it ``width`` wide has at most ``limit`` m² covered
    or off the floor."""
    found = _zone_states(ids, boxes, polys, solid, walk, layout, limit, width)
    if found is None:
        return [[] for _ in range(len(boxes[0]))]
    zones, states = found
    o = zones.owner
    out = []
    for blocked, why, _ in states:
        lines = []
        for u in dict.fromkeys(o.tolist()):
            mine = np.flatnonzero(o == u).tolist()
            if blocked[mine].all():
                sides = "; ".join(f"{zones.sides[zz]} ({zones.depth[zz]:.2f} m deep) blocked "
                                  f"by {_covering(why[zz], limit)}" for zz in mine)
                lines.append(f"access: {ids[u]!r} has no free side to be used from ({sides})")
        out.append(lines)
    return out


def _zone_states(ids: list[str], boxes: tuple[np.ndarray, ...], polys: _Footprints,
                 solid: np.ndarray, walk: np.ndarray, layout: Layout, limit: float,
                 width: float) -> tuple[Any, list[tuple[np.ndarray, list, np.ndarray]]] | None:
    """The access zones of the floor rows ``ids`` (an :class:`~forcelayout.access.AccessZones`,
    None for none) and per floor: which zones are blocked (Z,), what covers each
    (``[(m², what), ...]``, ``what`` an object's id or None for the wall) and the zones'
    corners (Z, 4, 2)."""
    from forcelayout.access import access_zones, related_pairs, zone_boxes
    from forcelayout.bindings import compile_plan

    pos, right, front, half = boxes
    nb = len(pos)
    plan = layout.plan
    bindings = compile_plan(plan).bindings
    objects = {o.id: o for o in plan.objects}
    zones = access_zones(objects, ids, bindings, walk, related_pairs(ids, bindings, objects))
    if zones is None:
        return None
    o = zones.owner
    zc, zo, zl, zh = zone_boxes(pos[:, o], right[:, o], front[:, o], half[:, o],
                                zones.direction, zones.depth)  # (B, Z, 2)
    nz = len(o)
    corners = corners_from_axes(zc.reshape(-1, 2), zl.reshape(-1, 2), zo.reshape(-1, 2),
                                zh.reshape(-1, 2)).reshape(nb, nz, 4, 2)
    on_floor = layout.room.contains_boxes(corners)  # (B, Z): certainly on the floor
    sep = obb_separation(pos[:, None, solid] - zc[:, :, None], zl[:, :, None],
                         zo[:, :, None], zh[:, :, None], right[:, None, solid],
                         front[:, None, solid], half[:, None, solid])  # (B, Z, S)
    near = (sep < 0.0) & ~zones.exempt[:, solid][None]
    out = []
    for b in range(nb):
        squares = _polygons(corners[b])
        # per zone, what covers it (area, what) and the parts of it covered or off the floor
        why: list[list[tuple[float, str | None]]] = [[] for _ in range(nz)]
        parts: list[list[Any]] = [[] for _ in range(nz)]
        z, s = np.nonzero(near[b])
        if len(z):
            cut = shapely.intersection(polys(b, solid[s]), squares[z])
            for zz, ss, a, g in zip(z.tolist(), s.tolist(), shapely.area(cut).tolist(), cut,
                                    strict=True):
                if a > 0.0:
                    why[zz].append((a, ids[solid[ss]]))
                    parts[zz].append(g)
        for zz in np.flatnonzero(~on_floor[b]).tolist():
            g = shapely.difference(squares[zz], layout.room.shape)
            a = float(shapely.area(g))
            if a > 0.0:
                why[zz].append((a, None))
                parts[zz].append(g)
        blocked = np.zeros(nz, dtype=bool)
        for zz in range(nz):
            # at most ``limit``, and at most a third of a stretch: 0.1 m² is three
            # quarters of the zone behind a chair
            most = min(limit, _ACCESS_SHARE * _stretch_width(zh[b, zz], width)
                       * 2.0 * float(zh[b, zz, 1]))
            if sum(a for a, _ in why[zz]) <= most:
                continue  # the whole zone is free enough
            taken = shapely.union_all(parts[zz])
            stretches = _stretches(zc[b, zz], zl[b, zz], zo[b, zz], zh[b, zz], width)
            blocked[zz] = bool(shapely.area(shapely.intersection(taken, stretches)).min()
                               > most)
        out.append((blocked, why, corners[b]))
    return zones, out


def zone_states(layout: Layout, *, max_access_overlap: float = 0.1, access_width: float = 0.6
                ) -> list[tuple[str, str, float, np.ndarray, bool, list[tuple[str, float]]]]:
    """The ``access`` check's verdict on each access zone of a layout's floor objects.

    Backs :func:`forcelayout.access.zone_states` (which documents it).
    """
    check_parameters(max_access_overlap=max_access_overlap, access_width=access_width)
    ids, pos, yaw, half = _floor_arrays(layout)
    if not ids:
        return []
    walk, solid, boxes, _, polys = _floor_boxes(layout.plan, ids, pos[None], yaw[None], half)
    found = _zone_states(ids, boxes, polys, solid, walk, layout, max_access_overlap,
                         access_width)
    if found is None:
        return []
    zones, [(blocked, why, zc)] = found
    out = []
    for zz, r in enumerate(zones.owner.tolist()):
        cover = sorted((("wall" if w is None else w, a) for a, w in why[zz]),
                       key=lambda t: -t[1])
        out.append((ids[r], zones.sides[zz], float(zones.depth[zz]), zc[zz].copy(),
                    not bool(blocked[zz]), cover))
    return out


def _covering(why: list[tuple[float, str | None]], limit: float) -> str:
    """What covers an access zone, largest first: ``'bed' (0.31 m²)``, ``the wall (0.19 m²
    off the floor)``."""
    why = sorted(why, key=lambda t: -t[0])
    why = [t for t in why if t[0] >= 0.01] or why[:1]  # not the slivers
    return ", ".join(f"{'the wall' if what is None else repr(what)} "
                     f"({_area_over(a, limit) if a > limit else _area(a)} m²"
                     f"{' off the floor' if what is None else ''})" for a, what in why)


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
            c = layout.corners(oid)
            if room.contains_boxes(c):
                continue
            a = shapely.area(shapely.difference(shapely.Polygon(c), room.shape))
            if a > max_overlap:
                out.append(f"surface: {oid!r} on the ceiling pokes {_area(a)} m² out of the room")
        elif surf.startswith("wall:"):
            out += _wall_surface(oid, p, plan.object(oid).size, surf, room)
        elif surf in poses:
            c = layout.corners(oid)
            top = layout.corners(surf)
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


def _reached_from_doors(labels: np.ndarray, dist2: np.ndarray, seeds: np.ndarray,
                        near2: np.float32) -> np.ndarray:
    """Whether the agent gets within reach of each object from each door, on B floors at
    once: ``labels`` (B, H, W) numbers the free regions (no number shared by two floors),
    ``dist2`` (B, P, H, W) the objects' footprint distances, ``seeds`` (D, H, W) the cells
    inside each door, ``near2`` the reach squared. Shape (B, P, D)."""
    door_has = np.zeros((len(seeds), int(labels.max()) + 1), dtype=bool)  # (D, regions + 1)
    for d, seed in enumerate(seeds):
        door_has[d, labels[:, seed].ravel()] = True
    door_has[:, 0] = False  # not a free region
    within = dist2 <= near2  # (B, P, H, W): the cells within reach of each object
    out = np.empty((*dist2.shape[:2], len(seeds)), dtype=bool)
    for d in range(len(seeds)):
        cells = door_has[d][labels]  # (B, H, W): the cells of the regions the door opens on
        out[..., d] = (within & cells[:, None]).any(axis=(-2, -1))
    return out


def _reachable(ids: list[str], prim: list[int], solid: np.ndarray, rows: np.ndarray,
               dist2: np.ndarray, r2: np.float32, free: np.ndarray, labels: np.ndarray | None,
               rg, near: float, reached: np.ndarray | None = None, name: bool = True
               ) -> tuple[list[str], dict[str, list[str]], list[str]]:
    """Whether the agent gets within ``near`` of each primary object (rows ``prim``) from a
    door; ``dist2`` holds the footprint distances of ``rows`` (the obstacles ``solid``
    first); ``labels`` numbers the free regions of this floor (in a stack of floors, after
    those of the floors before it: the numbers name regions, in the order a label of this
    floor alone would number them); ``reached`` (P, D), where given, is whether each is
    reached from each door (:func:`_reached_from_doors`)."""
    seeds = rg.door_seeds
    doors = _doors_apart(seeds, free, labels) if len(seeds) > 1 else []
    if not doors and (not prim or (reached is not None and reached.all())):
        return [], {}, []
    n = int(labels.max())
    if len(seeds):
        sources = list(seeds)
        names = [f"door {k}" for k in range(len(seeds))]
    else:  # no door: from the largest free region
        sources = [np.zeros(free.shape, dtype=bool)]
        if n:
            sizes = np.bincount(labels.ravel(), minlength=n + 1)
            sizes[0] = 0
            sources = [labels == int(sizes.argmax())]
        names = ["the largest free region"]
    at = {int(k): i for i, k in enumerate(rows)}
    near_cells = dist2[[at[k] for k in prim]] <= np.float32(near) ** 2  # (P, H, W)
    if reached is None:
        # the free regions each source holds, and those each primary object can be reached
        # in: (sources, n + 1) and (P, n + 1) bool
        table = np.zeros((len(sources), n + 1), dtype=bool)
        for k, source in enumerate(sources):
            table[k, labels[source & free]] = True
        row, y, x = np.nonzero(near_cells & free)
        touches = np.zeros((len(prim), n + 1), dtype=bool)
        touches[row, labels[y, x]] = True
        table[:, 0] = touches[:, 0] = False
        reached = (touches[:, None, :] & table[None]).any(-1)  # (P, sources)
    unreachable: list[str] = []
    blocked_by: dict[str, list[str]] = {}
    failures: list[str] = []
    paths: _PathFinder | None = None

    def cut_off(key: str, what: str, d: int, target: np.ndarray, skip: int = -1) -> str:
        # the failure line for ``what`` (an object's quoted id, a door) not reached from
        # source ``d``; with ``name``, what blocks the cheapest way to ``target`` (but row
        # ``skip``), kept in ``blocked_by[key]``
        line = f"reachable: {what} cannot be reached from {names[d]}"
        if not name:
            return line
        nonlocal paths
        if paths is None:  # one path search per source, over the cells obstacles take
            paths = _PathFinder(rg.floor, free, dist2[:len(solid)] <= r2)
        who = [ids[solid[s]] for s in paths.blockers(d, sources[d], target) if solid[s] != skip]
        blocked_by.setdefault(key, who)
        return line + (f" (blocked by {', '.join(repr(b) for b in who)})" if who
                       else " (the walls leave no way through)")

    for row, k in enumerate(prim):
        ok = reached[row]
        if ok.all():
            continue
        unreachable.append(ids[k])
        failures += [cut_off(ids[k], repr(ids[k]), int(d), near_cells[row], k)
                     for d in np.nonzero(~ok)[0]]
    # a door the first cannot reach: the room cannot be walked through
    failures += [cut_off(names[d], names[d], 0, seeds[d]) for d in doors]
    return unreachable, blocked_by, failures


def _doors_apart(seeds: np.ndarray, free: np.ndarray, labels: np.ndarray) -> list[int]:
    """The doors (1, 2, ...) whose cells just inside share no free region with the first
    door's: ``seeds`` (D, H, W), ``labels`` numbering the regions of ``free``."""
    first = set(np.unique(labels[seeds[0] & free]).tolist()) - {0}
    return [d for d in range(1, len(seeds))
            if not first & set(np.unique(labels[seeds[d] & free]).tolist())]


class _PathFinder:
    """Cheapest 4-connected paths over the floor cells, where blocked cells cost much more.

    A free cell costs 1 to enter; a floor cell not free for the agent's centre
    (near furniture or in the wall band) costs 1 + ``_BLOCKED_COST``. The
    cheapest path from a door to an object crosses the thinnest obstruction;
    the furniture around its blocked cells is what stands in the way.
    """

    def __init__(self, floor: np.ndarray, free: np.ndarray, blocked: np.ndarray):
        self.blocked = blocked.reshape(len(blocked), -1)
        cells, index, indices, indptr = _grid_graph(floor)
        self.cells, self.index = cells, index
        cost = np.where(free.ravel()[cells], 1.0, 1.0 + _BLOCKED_COST)
        m = len(cells)
        from scipy import sparse  # imported when first needed, as scipy.ndimage in _label

        self.graph = sparse.csr_matrix((cost[indices], indices, indptr), shape=(m, m))
        self._runs: dict[int, tuple[np.ndarray, list[int]]] = {}

    def blockers(self, key: int, source: np.ndarray, target: np.ndarray) -> list[int]:
        """Rows of ``blocked`` crossed by the cheapest path from ``source`` to ``target``.

        In path order from ``source``; ``key`` names the source (runs from one
        source are shared between targets).
        """
        src = self.index[np.flatnonzero(source.ravel())]
        src = src[src >= 0]
        dst = self.index[np.flatnonzero(target.ravel())]
        dst = dst[dst >= 0]
        if len(src) == 0 or len(dst) == 0:
            return []
        if key not in self._runs:
            from scipy.sparse import csgraph

            dist, pred = csgraph.dijkstra(self.graph, indices=src, min_only=True,
                                          return_predecessors=True)[:2]
            # the chain of predecessors is followed on Python ints
            self._runs[key] = dist, pred.tolist()
        dist, back = self._runs[key]
        end = dst[np.argmin(dist[dst])]
        if not np.isfinite(dist[end]):
            return []
        path = [node := int(end)]
        grow = path.append
        for _ in range(len(back)):  # a chain of predecessors is at most every node long
            node = back[node]
            if node < 0:
                break
            grow(node)
        cells = self.cells[np.array(path[::-1])]
        hits = self.blocked[:, cells]  # (S, L)
        crossed = np.nonzero(hits.any(1))[0]
        first = hits[crossed].argmax(1)
        return [int(c) for c in crossed[np.argsort(first, kind="stable")]]


_GRAPHS: dict[int, tuple[np.ndarray, tuple[np.ndarray, ...]]] = {}


def _grid_graph(floor: np.ndarray) -> tuple[np.ndarray, ...]:
    """The 4-neighbour graph of a room grid's floor cells, in CSR form (cached per grid).

    Returns the flat indices of the floor cells, the node of each grid cell
    (-1 off the floor), and the CSR ``indices`` and ``indptr`` arrays.
    """
    hit = _GRAPHS.get(id(floor))
    if hit is not None and hit[0] is floor:
        return hit[1]
    h, w = floor.shape
    cells = np.flatnonzero(floor)
    index = np.full(floor.size, -1, dtype=np.int64)
    index[cells] = np.arange(len(cells))
    g = index.reshape(h, w)
    src, dst = [], []
    for a, b in ((g[:, :-1], g[:, 1:]), (g[:-1, :], g[1:, :])):
        both = (a >= 0) & (b >= 0)
        src += [a[both], b[both]]
        dst += [b[both], a[both]]
    s, t = np.concatenate(src), np.concatenate(dst)
    order = np.lexsort((t, s))
    s, t = s[order], t[order]
    indptr = np.zeros(len(cells) + 1, dtype=np.int64)
    np.add.at(indptr, s + 1, 1)
    out = (cells, index, t, np.cumsum(indptr))
    if len(_GRAPHS) >= 64:
        _GRAPHS.clear()
    _GRAPHS[id(floor)] = (floor, out)
    return out
