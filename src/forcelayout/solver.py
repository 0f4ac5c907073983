"""The Box2D world and the annealed step loop (the only module that imports Box2D).

The world is top-down with zero gravity. Every simulated object is a dynamic
rigid body whose fixture is its footprint rectangle; the room (any simple
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
from Box2D import b2ChainShape, b2PolygonShape, b2World

from forcelayout.forces import ForceModel
from forcelayout.geometry import RoomGeometry

__all__ = ["SolverConfig", "SimulationResult", "simulate", "temperature"]


@dataclass(frozen=True)
class SolverConfig:
    """Parameters of the annealed simulation.

    Attributes
    ----------
    k : float
        Cooling rate of ``T(t) = 1 / (1 + k t)`` (paper: 0.02).
    dt : float
        Box2D time step, seconds.
    mobility : float
        Velocity per unit force, m/s per N (overdamped motion).
    angular_mobility : float
        Angular velocity per unit torque, rad/s per N·m.
    max_speed : float
        Speed cap, m/s.
    max_turn : float
        Angular speed cap, rad/s.
    min_steps, max_steps : int
        The loop runs at least ``min_steps`` and at most ``max_steps`` steps.
    tol_pos : float
        Convergence threshold on per-step displacement, metres.
    tol_yaw : float
        Convergence threshold on per-step rotation, radians.
    patience : int
        Consecutive quiet steps that mean convergence.
    velocity_iterations, position_iterations : int
        Box2D solver iterations.
    semantic_interval : int
        The rule forces are recomputed every this many steps and held in
        between (multiple time stepping: the slow, soft semantic terms are
        sampled less often than the stiff physical ones, which are computed
        every step). 1 recomputes everything every step.
    """

    k: float = 0.02
    dt: float = 1.0 / 30.0
    mobility: float = 1.0
    angular_mobility: float = 4.0
    max_speed: float = 1.0
    max_turn: float = 3.0
    min_steps: int = 40
    max_steps: int = 400
    tol_pos: float = 2e-3
    tol_yaw: float = 4e-3
    patience: int = 8
    velocity_iterations: int = 6
    position_iterations: int = 3
    semantic_interval: int = 2

    def __post_init__(self) -> None:
        if self.max_steps < 1 or self.min_steps < 0 or self.patience < 1:
            raise ValueError("SolverConfig: max_steps >= 1, min_steps >= 0 and patience >= 1")
        if not (self.k >= 0 and self.dt > 0 and self.mobility > 0):
            raise ValueError("SolverConfig: k >= 0, dt > 0 and mobility > 0")
        if self.semantic_interval < 1:
            raise ValueError("SolverConfig: semantic_interval >= 1")


def temperature(step: int | np.ndarray, k: float = 0.02) -> np.ndarray | float:
    """Annealing temperature ``T(t) = 1 / (1 + k t)`` (paper eq. 4)."""
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


def _world(room: RoomGeometry, obstacles: list[np.ndarray] | None = None) -> b2World:
    world = b2World(gravity=(0.0, 0.0), doSleep=False)
    walls = world.CreateStaticBody()
    verts = [tuple(map(float, v)) for v in room.polygon]
    walls.CreateFixture(shape=b2ChainShape(vertices_loop=verts), friction=0.0)
    for poly in obstacles or []:
        walls.CreateFixture(shape=b2PolygonShape(vertices=[tuple(map(float, v)) for v in poly]),
                            friction=0.0)
    return world


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
    for r in range(n):
        hw, hd = (float(v) for v in model.size[r, :2] * 0.5)
        kw = dict(position=(float(pos[r, 0]), float(pos[r, 1])), angle=float(yaw[r]),
                  fixedRotation=False, bullet=False)
        b = world.CreateStaticBody(**kw) if fixed[r] else world.CreateDynamicBody(**kw)
        b.CreatePolygonFixture(box=(hw, hd), density=1.0, friction=0.0, restitution=0.0)
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
            fs, ts = model.semantic(state, 1.0 / (1.0 + k * t))
        fp, tp = model.physical(state)
        f, tau = fs + fp, ts + tp
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
