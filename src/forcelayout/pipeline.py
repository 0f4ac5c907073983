"""Stage P of the method: realise a plan's objects as poses from one random generator.

:func:`realise` is what :func:`forcelayout.solve` runs for each sample. It
places the floor objects with one force-directed simulation; objects placed
by surface rules (``on_top``, ``on_wall``, ``on_ceiling``) are listed as
missing with a reason until a surface stage places them.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from forcelayout.forces import ForceModel
from forcelayout.layout import Pose
from forcelayout.plan import Plan
from forcelayout.solver import simulate

if TYPE_CHECKING:
    from forcelayout.sampling import Options

__all__ = ["Placement", "realise", "initial_poses"]


@dataclass
class Placement:
    """Poses from one realisation and how it went.

    Attributes
    ----------
    poses : dict of str to Pose
    steps : int
        Simulation steps over all stages.
    converged : bool
        Whether every simulation settled before its step cap.
    missing : list of str
        ``"<id>: <reason>"`` for each object of the plan that was not placed.
    stages : dict of str to float
        Seconds spent per stage.
    """

    poses: dict[str, Pose]
    steps: int = 0
    converged: bool = True
    missing: list[str] = field(default_factory=list)
    stages: dict[str, float] = field(default_factory=dict)


def initial_poses(
    model: ForceModel, rng: np.random.Generator, *, tries: int = 40
) -> tuple[np.ndarray, np.ndarray]:
    """Random start poses inside the room, avoiding overlaps where possible.

    Objects are placed largest first at uniformly random positions and
    headings; each gets at most ``tries`` draws, keeping the draw with the
    least overlap (so this never loops forever on a crowded plan).
    """
    room = model.room
    n = model.n
    pos = np.zeros((n, 2))
    yaw = rng.uniform(-np.pi, np.pi, n)
    lo, hi = room.bounds[:2], room.bounds[2:]
    order = np.argsort(-(model.size[:, 0] * model.size[:, 1]), kind="stable")
    placed: list[int] = []
    for r in order:
        best, best_score = None, -np.inf
        for _ in range(tries):
            p = rng.uniform(lo, hi)
            st = model.state(np.vstack([pos, p[None]]), np.append(yaw, yaw[r]))
            st.size = np.vstack([model.size, model.size[r:r + 1]])
            c = st.corners[-1]
            if not room.contains(np.vstack([c, p[None]])).all():
                continue
            d, _ = room.wall_distance(c)
            score = min(float(d.min()), 0.3)
            if placed:
                sep = st.separation(np.full(len(placed), n), np.array(placed))
                score = min(score, float(sep.min()))
            if score > best_score:
                best, best_score = p, score
            if score >= 0.05:
                break
        pos[r] = best if best is not None else room.centroid
        placed.append(int(r))
    return pos, yaw


def realise(plan: Plan, rng: np.random.Generator, opts: Options) -> Placement:
    """Place the plan's objects: floor objects by one annealed simulation."""
    t0 = time.perf_counter()
    model = ForceModel(plan, relations=opts.relations)
    pos0, yaw0 = initial_poses(model, rng)
    res = simulate(model, pos0, yaw0, opts.solver)
    poses = {oid: Pose(float(p[0]), float(p[1]), float(y))
             for oid, p, y in zip(model.ids, res.pos, res.yaw, strict=True)}
    missing = [f"{o.id}: placed by {plan.surface_of(o.id)!r}, which is not placed by this "
               "stage" for o in plan.objects if o.id not in poses]
    return Placement(poses, res.steps, res.converged, missing,
                     {"floor": time.perf_counter() - t0})
