"""Surface placement (paper §III-B-4): objects on tops, on walls and on the ceiling.

Every surface is a 2D plane solved with the same annealed simulation as the
floor (:func:`forcelayout.solver.simulate`); where a rule puts its object is
what its class declares as ``surface`` (``"top"``, ``"wall"``,
``"ceiling"``), so a plugin rule is placed like a built-in one:

* :mod:`~forcelayout.surfaces.tops` — a parent's top is a rectangle "room"
  in the parent's frame; the children are simulated there and carried to
  the room;
* :mod:`~forcelayout.surfaces.walls` — a wall unfolded into a rectangle of
  wall length x room height, with doors, windows and nearby furniture as
  obstacles; objects settle towards eye level (and over their target);
* :mod:`~forcelayout.surfaces.ceiling` — the floor polygon seen from below;
* :mod:`~forcelayout.surfaces.check` — what can be known before simulating.

An object that cannot be placed is reported as missing with the reason.
"""

from __future__ import annotations

import time

import numpy as np

from forcelayout.batching import SampleTask, drive
from forcelayout.bindings import compile_plan
from forcelayout.layout import Pose
from forcelayout.options import SolverConfig
from forcelayout.plan import Plan
from forcelayout.surfaces.ceiling import place_on_ceiling
from forcelayout.surfaces.check import check_surfaces
from forcelayout.surfaces.plane import AnchorTerm, SurfacePlacement
from forcelayout.surfaces.tops import place_on_tops
from forcelayout.surfaces.walls import EYE_LEVEL, free_wall_stretches, place_on_walls, wall_pose

__all__ = [
    "EYE_LEVEL",
    "AnchorTerm",
    "SurfacePlacement",
    "check_surfaces",
    "free_wall_stretches",
    "place_surfaces",
    "surface_task",
    "wall_pose",
]


def place_surfaces(
    plan: Plan,
    floor: dict[str, Pose],
    rng: np.random.Generator,
    *,
    relations: bool = True,
    solver: SolverConfig | None = None,
    reach: float = 0.3,
) -> SurfacePlacement:
    """Place every off-floor object of the plan, given the floor objects' poses.

    Parameters
    ----------
    plan : Plan
    floor : dict of str to Pose
        Poses of the floor objects (not modified).
    rng : numpy.random.Generator
        Source of all randomness of this stage.
    relations : bool
        ``False`` zeroes the object-object rules on surfaces too.
    solver : SolverConfig, optional
        Base simulation parameters; surface planes use at most 120 steps.
    reach : float
        Floor objects closer than this to a wall (metres) are obstacles on it.

    Returns
    -------
    SurfacePlacement
        All poses; objects that could not be placed are in ``missing``.
    """
    return drive([surface_task(plan, floor, rng, relations=relations, solver=solver,
                               reach=reach)])[0]


def surface_task(
    plan: Plan,
    floor: dict[str, Pose],
    rng: np.random.Generator,
    *,
    relations: bool = True,
    solver: SolverConfig | None = None,
    reach: float = 0.3,
    models: dict | None = None,
) -> SampleTask[SurfacePlacement]:
    """:func:`place_surfaces` as a sample task (:mod:`forcelayout.batching`).

    The simulations of the tops are requests: samples driven together that
    share one ``models`` dict (the tops' force models, the same for every
    sample of a plan) simulate each top as one batch. The result is the one
    :func:`place_surfaces` gives, bit for bit.
    """
    cp = compile_plan(plan)
    cfg = solver or SolverConfig()
    out = SurfacePlacement(dict(floor))
    t = time.perf_counter()
    yield from place_on_tops(cp, out.poses, rng, relations, cfg, out, models)
    t1 = time.perf_counter()
    place_on_walls(cp, out.poses, rng, relations, cfg, reach, out)
    t2 = time.perf_counter()
    place_on_ceiling(cp, out.poses, rng, relations, cfg, out)
    t3 = time.perf_counter()
    out.stages = {"tops": t1 - t, "walls": t2 - t1, "ceiling": t3 - t2}
    placed = set(out.poses)
    reasons = {m.split(":")[0] for m in out.missing}
    for o in plan.objects:
        if o.id not in placed and o.id not in reasons:
            out.missing.append(f"{o.id}: placed by {plan.surface_of(o.id)!r}, which no stage "
                               "placed")
    return out
