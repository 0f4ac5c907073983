"""The Box2D world and the annealed step loop (the only module that imports Box2D).

The world is top-down with zero gravity. Every simulated object is a dynamic
rigid body whose fixture is its footprint rectangle (or the convex polygon
of ``SceneObject.footprint``, e.g. a grounded mesh's outline); the room (any simple
polygon) is a static chain of walls. Each step:

1. read the poses of all bodies into numpy arrays;
2. compute the net force and torque (eqs. 2–3) with the semantic terms
   scaled by the annealing temperature ``T(t) = 1 / (1 + k t)`` (eq. 4);
3. move the bodies overdamped — velocity proportional to force (speed
   capped) — and let Box2D step, which resolves contacts so bodies never
   pass through each other or the walls;
4. stop once every object moved less than ``tol_pos`` metres and turned less
   than ``tol_yaw`` radians per step for ``patience`` steps, or at
   ``max_steps``.

Same inputs give the same result, bit for bit, on the same machine.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import shapely

from forcelayout.forces import ForceModel, ForceTerm, join_terms
from forcelayout.geometry import RoomGeometry, box_corners
from forcelayout.options import SolverConfig
from forcelayout.rules.base import State

with warnings.catch_warnings():  # Box2D's SWIG wrappers warn of their own types when loaded
    warnings.filterwarnings("ignore", r"builtin type (SwigPy\w+|swigvarlink) has no __module__",
                            DeprecationWarning)
    from Box2D import (
        b2_dynamicBody,
        b2_staticBody,
        b2BodyDef,
        b2ChainShape,
        b2FixtureDef,
        b2PolygonShape,
        b2World,
    )

__all__ = ["SolverConfig", "SimulationResult", "simulate", "simulate_batch", "temperature"]


def temperature(step: int | np.ndarray, k: float = 0.02) -> np.ndarray | float:
    """Annealing temperature ``T(t) = 1 / (1 + k t)`` (paper eq. 4).

    Parameters
    ----------
    step : int or ndarray
        Simulation step ``t`` (0 at the start).
    k : float
        Cooling rate (paper: 0.02).

    Returns
    -------
    float or ndarray
        A float for a scalar step, else an array of the steps' shape.
    """
    if isinstance(step, int | float):
        return 1.0 / (1.0 + k * step)
    return 1.0 / (1.0 + k * np.asarray(step, dtype=float))


@dataclass
class SimulationResult:
    """Final poses of one simulation.

    Attributes
    ----------
    pos : ndarray, shape (N, 2)
    yaw : ndarray, shape (N,)
        Wrapped to ``[-pi, pi)``.
    steps : int
        Steps taken.
    converged : bool
        Whether motion fell below the thresholds before ``max_steps``.
    """

    pos: np.ndarray
    yaw: np.ndarray
    steps: int
    converged: bool


#: Box2D collision categories: the room's walls, furniture, walkable floor covers.
_WALLS, _SOLID, _COVER = 0x0001, 0x0002, 0x0004
#: Force (N) and torque (N m) below which a start counts as one nothing acts on (rounding).
_STILL = 1e-9


def _world(room: RoomGeometry, obstacles: list[np.ndarray] | None = None) -> b2World:
    world = b2World(gravity=(0.0, 0.0), doSleep=False)
    walls = world.CreateStaticBody()
    verts = [tuple(map(float, v)) for v in room.polygon]
    walls.CreateFixture(shape=b2ChainShape(vertices_loop=verts), friction=0.0,
                        categoryBits=_WALLS, maskBits=_SOLID | _COVER)
    for poly in obstacles or []:
        walls.CreateFixture(shape=b2PolygonShape(vertices=[tuple(map(float, v)) for v in poly]),
                            friction=0.0, categoryBits=_WALLS, maskBits=_SOLID)
    return world


def _footprints(model: ForceModel) -> list[list[tuple[float, float]] | None]:
    """Each row's convex footprint polygon (``SceneObject.footprint``), or None for its box.

    A footprint is used only where the row is simulated at the object's own
    width and depth (the floor), not where a plane sees it otherwise.
    """
    objects = {o.id: o for o in model.plan.objects}
    out: list[list[tuple[float, float]] | None] = []
    for r, oid in enumerate(model.ids):
        o = objects.get(oid)
        fp = getattr(o, "footprint", None)
        if fp is None or not np.allclose(model.size[r, :2], o.size[:2]):
            out.append(None)
        else:
            out.append([(float(x), float(y)) for x, y in fp])
    return out


def _at_rest(model: ForceModel, state: State, f: np.ndarray, tau: np.ndarray,
             obstacles: list[np.ndarray] | None) -> bool:
    """Whether no term acts on any moving object (``f``, ``tau`` of those rows) and every
    footprint lies inside the room, clear of the obstacles.

    Bodies then keep still: their velocities are set from the forces, and the
    contact solver only moves footprints that overlap (the repulsion term,
    zero here, acts before furniture touches).
    """
    if np.abs(f).max(initial=0.0) > _STILL or np.abs(tau).max(initial=0.0) > _STILL:
        return False
    if not model.room.contains(state.corners.reshape(-1, 2)).all():
        return False
    return not obstacles or not _overlapping(state.corners, obstacles).any()


def _overlapping(corners: np.ndarray, polygons: list[np.ndarray]) -> np.ndarray:
    """Whether each footprint (corners (M, 4, 2)) overlaps each convex polygon, (M, K)."""
    bodies = shapely.polygons(corners)
    walls = np.array([shapely.Polygon(np.asarray(p, dtype=float)) for p in polygons])
    return shapely.area(shapely.intersection(bodies[:, None], walls[None])) > 1e-9


def _clear_keep_out(model: ForceModel, pos: np.ndarray, yaw: np.ndarray
                    ) -> list[list[np.ndarray]]:
    """Each sample's static keep-out polygons (:attr:`ForceModel.keep_out`): those no
    solid row overlaps at its start. A row that starts inside one is pushed out by its
    force term instead; made static, it would be thrown out through the nearest edge,
    a wall's side as readily as the room's."""
    count = len(pos)
    if not model.keep_out:
        return [[] for _ in range(count)]
    solid = ~np.asarray(model.walkable, dtype=bool)
    if not solid.any():
        return [list(model.keep_out) for _ in range(count)]
    half = model.size[solid, :2] * 0.5
    corners = box_corners(pos[:, solid].reshape(-1, 2), yaw[:, solid].reshape(-1),
                          np.tile(half, (count, 1)))
    zones = len(model.keep_out)
    hit = _overlapping(corners, model.keep_out).reshape(count, -1, zones).any(axis=1)  # (B, K)
    return [[model.keep_out[k] for k in range(zones) if not hit[b, k]] for b in range(count)]


def _add(terms: Sequence[ForceTerm], state: State, temperature: float, annealed: bool,
         f: np.ndarray, tau: np.ndarray) -> None:
    """Add the forces of the ``terms`` of this kind (annealed or not) to ``f`` and ``tau``."""
    for term in terms:
        if term.annealed == annealed:
            fk, tk = term(state, temperature)
            f += fk
            tau += tk


def _fixtures(model: ForceModel, hulls: list) -> list[b2FixtureDef]:
    """Each row's fixture definition (its footprint, density and collision layer), made once
    per simulation and used for the body of every sample (Box2D copies it)."""
    defs = []
    walkable = model.walkable
    for r in range(model.n):
        hw, hd = (float(v) for v in model.size[r, :2] * 0.5)
        shape = (b2PolygonShape(box=(hw, hd)) if hulls[r] is None
                 else b2PolygonShape(vertices=hulls[r]))
        # walls collide with everything; furniture with furniture; covers with walls only
        layer = _COVER if walkable[r] else _SOLID
        defs.append(b2FixtureDef(shape=shape, density=1.0, friction=0.0, restitution=0.0,
                                 categoryBits=layer,
                                 maskBits=_WALLS | (0 if walkable[r] else _SOLID)))
    return defs


def _bodies(world: b2World, pos: np.ndarray, yaw: np.ndarray, fixed: np.ndarray,
            fixtures: list[b2FixtureDef]) -> list:
    """One body per row in ``world``, at its pose, static where ``fixed``."""
    bodies = []
    spec = b2BodyDef()  # fixedRotation and bullet off, as by default
    for r, fixture in enumerate(fixtures):
        spec.type = b2_staticBody if fixed[r] else b2_dynamicBody
        spec.position = (float(pos[r, 0]), float(pos[r, 1]))
        spec.angle = float(yaw[r])
        body = world.CreateBody(spec)
        body.CreateFixture(fixture)
        bodies.append(body)
    return bodies


def simulate(
    model: ForceModel,
    pos: np.ndarray,
    yaw: np.ndarray,
    config: SolverConfig | None = None,
    *,
    fixed: np.ndarray | None = None,
    obstacles: list[np.ndarray] | None = None,
    callback: Callable[[int, np.ndarray, np.ndarray], None] | None = None,
) -> SimulationResult:
    """Run the annealed force-directed simulation from the given start poses.

    One sample of :func:`simulate_batch` (the same result, bit for bit, as
    the sample gets in any batch).

    Parameters
    ----------
    model : ForceModel
        The objects, their rules and the room.
    pos : ndarray, shape (N, 2)
        Start positions, metres.
    yaw : ndarray, shape (N,)
        Start headings, radians CCW.
    config : SolverConfig, optional
    fixed : ndarray of bool, shape (N,), optional
        Objects that do not move (e.g. parents already settled); they still
        push and pull the others.
    obstacles : list of ndarray, shape (K, 2), optional
        Convex polygons that are static walls (e.g. settled areas).
    callback : callable, optional
        ``callback(step, pos, yaw)`` after every step (for animations).

    Returns
    -------
    SimulationResult
    """
    n = model.n
    each = None if callback is None else (lambda step, b, p, y: callback(step, p, y))
    return simulate_batch(model, np.reshape(np.asarray(pos, dtype=float), (1, n, 2)),
                          np.reshape(np.asarray(yaw, dtype=float), (1, n)), config,
                          fixed=fixed, obstacles=obstacles, callback=each)[0]


def simulate_batch(
    model: ForceModel,
    pos: np.ndarray,
    yaw: np.ndarray,
    config: SolverConfig | None = None,
    *,
    fixed: np.ndarray | None = None,
    obstacles: list[np.ndarray] | None = None,
    sample_obstacles: Sequence[list[np.ndarray]] | None = None,
    sample_terms: Sequence[Sequence[ForceTerm]] | None = None,
    callback: Callable[[int, int, np.ndarray, np.ndarray], None] | None = None,
) -> list[SimulationResult]:
    """Simulate many samples of the same objects together, from their own start poses.

    Each sample has its own Box2D world; the force terms are computed once
    per step for all samples still moving (one stacked state, see
    :meth:`ForceModel.stacked`). A sample leaves the batch once it comes to
    rest, so a slow one holds up no other. Sample ``b``'s result is the one
    :func:`simulate` gives it alone, bit for bit, whatever else is in the batch.

    Parameters
    ----------
    model : ForceModel
    pos : ndarray, shape (B, N, 2)
    yaw : ndarray, shape (B, N)
        Start poses of the B samples.
    config : SolverConfig, optional
    fixed : ndarray of bool, shape (N,) or (B, N), optional
        As for :func:`simulate`: the same for every sample, or each sample's own.
    obstacles : optional
        As for :func:`simulate`; the same for every sample.
    sample_obstacles : sequence of lists of ndarray, optional
        Each sample's own obstacles (convex polygons), besides ``obstacles``.
    sample_terms : sequence of sequences of ForceTerm, optional
        Each sample's own extra terms, summed after the model's (a wall
        object's spring to its own spot). Term ``j`` of every sample is of one
        class; they are joined with :func:`~forcelayout.forces.join_terms`.
    callback : callable, optional
        ``callback(step, b, pos, yaw)`` after every step of each moving sample ``b``.

    Returns
    -------
    list of SimulationResult
        One per sample, in order; ``converged`` is False for a sample that
        hit ``max_steps`` (or whose poses stopped being finite).
    """
    cfg = config or SolverConfig()
    n = model.n
    pos = np.array(pos, dtype=float)
    count = len(pos)
    pos = pos.reshape(count, n, 2)
    yaw = np.array(yaw, dtype=float).reshape(count, n)
    fixed = np.zeros(n, dtype=bool) if fixed is None else np.asarray(fixed, dtype=bool)
    own = fixed.ndim == 2  # each sample's own fixed rows
    if n == 0 or count == 0:
        return [SimulationResult(pos[b], yaw[b], 0, True) for b in range(count)]
    fixtures = _fixtures(model, _footprints(model))
    keep_out = _clear_keep_out(model, pos, yaw)
    walls = [keep_out[b] + list(obstacles or [])
             + list(sample_obstacles[b] if sample_obstacles else [])
             for b in range(count)]  # each sample's static obstacles
    own_terms = [list(ts) for ts in sample_terms] if sample_terms else None
    if own_terms is not None and len({len(ts) for ts in own_terms}) > 1:
        raise ValueError("sample_terms: every sample needs the same number of terms")
    joined: dict[tuple[int, ...], list[ForceTerm]] = {}  # by the active samples
    worlds, bodies, moving = [], [], []
    for b in range(count):
        world = _world(model.room, walls[b])
        fb = fixed[b] if own else fixed
        bods = _bodies(world, pos[b], yaw[b], fb, fixtures)
        worlds.append(world)
        bodies.append(bods)
        moving.append([bd for bd, f in zip(bods, fb, strict=True) if not f])
    mv = np.flatnonzero(~fixed) if not own else None
    mvs = [np.flatnonzero(~fixed[b]) for b in range(count)] if own else None
    all_moving = not fixed.any()
    steps = np.zeros(count, dtype=int)
    converged = np.zeros(count, dtype=bool)
    quiet = np.zeros(count, dtype=int)
    fs_all = np.zeros((count, n, 2))  # the annealed terms, sampled every few steps
    ts_all = np.zeros((count, n))
    k, dt, mob, amob = cfg.k, cfg.dt, cfg.mobility, cfg.angular_mobility
    vmax, wmax = cfg.max_speed, cfg.max_turn
    vel_it, pos_it = cfg.velocity_iterations, cfg.position_iterations
    every = cfg.semantic_interval
    active = np.arange(count)
    for t in range(cfg.max_steps):
        if not len(active):
            break
        m = len(active)
        forces = model.stacked(m)
        state = forces.state(pos[active].reshape(m * n, 2), yaw[active].reshape(m * n))
        extra: list[ForceTerm] = []
        if own_terms is not None and own_terms[0]:
            key = tuple(active.tolist())
            if key not in joined:
                joined.clear()
                joined[key] = [join_terms([own_terms[b][j] for b in key])
                               for j in range(len(own_terms[0]))]
            extra = joined[key]
        if t % every == 0:
            fs, ts = forces.net(state, temperature(t, k), annealed=True)
            _add(extra, state, temperature(t, k), True, fs, ts)
            fs_all[active] = fs.reshape(m, n, 2)
            ts_all[active] = ts.reshape(m, n)
        fp, tp = forces.net(state, 1.0, annealed=False)
        _add(extra, state, 1.0, False, fp, tp)
        f = (fs_all[active] + fp.reshape(m, n, 2))
        tau = (ts_all[active] + tp.reshape(m, n))
        if t == 0:  # nothing acts and nothing overlaps: no step would move it
            moves = [slice(None) if all_moving else mvs[b] if own else mv
                     for b in active.tolist()]  # the rows of each sample that move
            rest = np.array([_at_rest(model, state.sample(c), f[c][moves[c]],
                                      tau[c][moves[c]], walls[b])
                             for c, b in enumerate(active.tolist())])
            if rest.any():
                converged[active[rest]] = True
                keep = ~rest
                active, f, tau = active[keep], f[keep], tau[keep]
                m = len(active)
                if not m:
                    break
        if not all_moving and not own:
            f, tau = f[:, mv], tau[:, mv]
        v = f * mob
        speed2 = (v * v).sum(2)
        fast = speed2 > vmax * vmax
        if fast.any():
            v[fast] *= (vmax / np.sqrt(speed2[fast]))[:, None]
        om = np.clip(tau * amob, -wmax, wmax)
        if own:  # each sample's moving rows
            vl = [v[c, mvs[b]].tolist() for c, b in enumerate(active.tolist())]
            wl = [om[c, mvs[b]].tolist() for c, b in enumerate(active.tolist())]
        else:
            vl, wl = v.tolist(), om.tolist()
        new = np.empty((m, n, 3))
        for c, b in enumerate(active.tolist()):
            for body, vel, w in zip(moving[b], vl[c], wl[c], strict=True):
                body.linearVelocity = vel
                body.angularVelocity = w
            worlds[b].Step(dt, vel_it, pos_it)
            new[c] = [(p.x, p.y, bd.angle) for bd in bodies[b] for p in (bd.position,)]
        old_pos, old_yaw = pos[active], yaw[active]
        dpos = np.abs(new[:, :, :2] - old_pos).reshape(m, -1).max(1)
        dyaw = np.abs(new[:, :, 2] - old_yaw).max(1)
        pos[active] = new[:, :, :2]
        yaw[active] = new[:, :, 2]
        steps[active] = t + 1
        if callback is not None:
            for b in active.tolist():
                callback(t + 1, b, pos[b], yaw[b])
        finite = np.isfinite(dpos) & np.isfinite(dyaw)
        still = (dpos < cfg.tol_pos) & (dyaw < cfg.tol_yaw)
        quiet[active] = np.where(still, quiet[active] + 1, 0)
        done = (t + 1 >= cfg.min_steps) & (quiet[active] >= cfg.patience) & finite
        converged[active[done]] = True
        active = active[finite & ~done]
    yaw = (yaw + np.pi) % (2 * np.pi) - np.pi
    return [SimulationResult(pos[b].copy(), yaw[b].copy(), int(steps[b]), bool(converged[b]))
            for b in range(count)]
