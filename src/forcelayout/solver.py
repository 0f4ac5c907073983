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

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import shapely
from Box2D import b2ChainShape, b2PolygonShape, b2World

from forcelayout.forces import ForceModel
from forcelayout.geometry import RoomGeometry
from forcelayout.options import SolverConfig
from forcelayout.rules.base import State

__all__ = ["SolverConfig", "SimulationResult", "simulate", "temperature"]


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
    """Whether no term acts on any object and every footprint lies inside the room, clear of
    the obstacles.

    Bodies then keep still: their velocities are set from the forces, and the
    contact solver only moves footprints that overlap (the repulsion term,
    zero here, acts before furniture touches).
    """
    if np.abs(f).max() > _STILL or np.abs(tau).max() > _STILL:
        return False
    if not model.room.contains(state.corners.reshape(-1, 2)).all():
        return False
    if not obstacles:
        return True
    bodies = shapely.polygons(state.corners)
    walls = np.array([shapely.Polygon(np.asarray(o, dtype=float)) for o in obstacles])
    return not (shapely.area(shapely.intersection(bodies[:, None], walls[None])) > 1e-9).any()


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
    cfg = config or SolverConfig()
    n = model.n
    pos = np.array(pos, dtype=float).reshape(n, 2)
    yaw = np.array(yaw, dtype=float).reshape(n)
    fixed = np.zeros(n, dtype=bool) if fixed is None else np.asarray(fixed, dtype=bool)
    if n == 0:
        return SimulationResult(pos, yaw, 0, True)
    world = _world(model.room, obstacles)
    bodies = []
    walkable = model.walkable
    hulls = _footprints(model)
    for r in range(n):
        hw, hd = (float(v) for v in model.size[r, :2] * 0.5)
        kw = dict(position=(float(pos[r, 0]), float(pos[r, 1])), angle=float(yaw[r]),
                  fixedRotation=False, bullet=False)
        b = world.CreateStaticBody(**kw) if fixed[r] else world.CreateDynamicBody(**kw)
        # walls collide with everything; furniture with furniture; covers with walls only
        layer = _COVER if walkable[r] else _SOLID
        shape = {"box": (hw, hd)} if hulls[r] is None else {"vertices": hulls[r]}
        b.CreatePolygonFixture(**shape, density=1.0, friction=0.0, restitution=0.0,
                               categoryBits=layer, maskBits=_WALLS | (0 if walkable[r] else _SOLID))
        bodies.append(b)
    moving = [b for b, f in zip(bodies, fixed, strict=True) if not f]
    mv = np.flatnonzero(~fixed)
    all_moving = len(mv) == n
    quiet = 0
    steps = 0
    converged = False
    k, dt, mob, amob = cfg.k, cfg.dt, cfg.mobility, cfg.angular_mobility
    vmax, wmax = cfg.max_speed, cfg.max_turn
    vel_it, pos_it = cfg.velocity_iterations, cfg.position_iterations
    every = cfg.semantic_interval
    state = model.state(pos, yaw)
    for t in range(cfg.max_steps):
        if t % every == 0:
            fs, ts = model.net(state, temperature(t, k), annealed=True)
        fp, tp = model.net(state, 1.0, annealed=False)
        f, tau = fs + fp, ts + tp
        if t == 0 and _at_rest(model, state, f, tau, obstacles):
            converged = True  # nothing acts and nothing overlaps: no step would move it
            break
        if not all_moving:
            f, tau = f[mv], tau[mv]
        v = f * mob
        speed2 = (v * v).sum(1)
        fast = speed2 > vmax * vmax
        if fast.any():
            v[fast] *= (vmax / np.sqrt(speed2[fast]))[:, None]
        om = np.clip(tau * amob, -wmax, wmax)
        for body, vel, w in zip(moving, v.tolist(), om.tolist(), strict=True):
            body.linearVelocity = vel
            body.angularVelocity = w
        world.Step(dt, vel_it, pos_it)
        new = np.array([(p.x, p.y, bd.angle) for bd in bodies for p in (bd.position,)])
        dpos = np.abs(new[:, :2] - pos).max()
        dyaw = np.abs(new[:, 2] - yaw).max()
        pos, yaw = new[:, :2], new[:, 2]
        state = model.state(pos, yaw)
        steps = t + 1
        if callback is not None:
            callback(steps, pos, yaw)
        if not (np.isfinite(dpos) and np.isfinite(dyaw)):
            break
        quiet = quiet + 1 if (dpos < cfg.tol_pos and dyaw < cfg.tol_yaw) else 0
        if steps >= cfg.min_steps and quiet >= cfg.patience:
            converged = True
            break
    yaw = (yaw + np.pi) % (2 * np.pi) - np.pi
    return SimulationResult(pos, yaw, steps, converged)
