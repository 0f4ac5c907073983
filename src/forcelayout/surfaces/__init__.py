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
from collections.abc import Sequence

import numpy as np

from forcelayout.batching import SampleTask, drive
from forcelayout.bindings import CompiledPlan, compile_plan
from forcelayout.layout import Pose
from forcelayout.options import SolverConfig
from forcelayout.plan import Plan
from forcelayout.surfaces.ceiling import place_on_ceiling
from forcelayout.surfaces.check import check_surfaces
from forcelayout.surfaces.plane import AnchorTerm, SurfacePlacement
from forcelayout.surfaces.tops import place_on_tops
from forcelayout.surfaces.walls import (
    EYE_LEVEL,
    REACH,
    free_wall_stretches,
    place_on_walls,
    wall_pose,
)

__all__ = [
    "EYE_LEVEL",
    "AnchorTerm",
    "SurfacePlacement",
    "check_surfaces",
    "free_wall_stretches",
    "place_surfaces",
    "place_surfaces_batch",
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
    reach: float = REACH,
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
    return place_surfaces_batch(plan, [floor], [rng], relations=relations, solver=solver,
                                reach=reach)[0]


def surface_task(
    plan: Plan,
    floor: dict[str, Pose],
    rng: np.random.Generator,
    *,
    relations: bool = True,
    solver: SolverConfig | None = None,
    reach: float = REACH,
    models: dict | None = None,
) -> SampleTask[SurfacePlacement]:
    """:func:`place_surfaces` as a sample task (:mod:`forcelayout.batching`).

    Every plane's simulation is a request: samples driven together that
    share one ``models`` dict (the planes' force models: a top, a wall with
    the same objects, the ceiling) simulate each plane as one batch, each
    sample with its own spots and obstacles. The result is the one
    :func:`place_surfaces` gives, bit for bit. ``stages`` holds the seconds
    the task itself spent on each stage (not the batched simulations);
    :func:`place_surfaces_batch` times whole stages.
    """
    cp = compile_plan(plan)
    cfg = solver or SolverConfig()
    out = SurfacePlacement(dict(floor))
    models = {} if models is None else models
    for name, stage in _stages(cp, out, rng, relations, cfg, reach, models):
        yield from _timed(stage, out.stages, name)
    _finish(plan, out)
    return out


def place_surfaces_batch(
    plan: Plan,
    floors: Sequence[dict[str, Pose]],
    rngs: Sequence[np.random.Generator],
    *,
    relations: bool = True,
    solver: SolverConfig | None = None,
    reach: float = REACH,
) -> list[SurfacePlacement]:
    """:func:`place_surfaces` for many samples of one plan, each plane simulated as a batch.

    The stages run one after the other for all samples (tops, then walls,
    then the ceiling), so each batch holds every sample that reached it.
    Sample ``k`` draws only from ``rngs[k]``: its placement is the one
    :func:`place_surfaces` gives it alone. Each placement's ``stages`` is the
    batch's time on each stage shared equally among its samples.
    """
    cp = compile_plan(plan)
    cfg = solver or SolverConfig()
    outs = [SurfacePlacement(dict(floor)) for floor in floors]
    models: dict = {}
    stages = [_stages(cp, out, rng, relations, cfg, reach, models)
              for out, rng in zip(outs, rngs, strict=True)]
    for k, name in enumerate(_STAGES):
        t = time.perf_counter()
        drive([s[k][1] for s in stages])
        share = (time.perf_counter() - t) / max(len(outs), 1)
        for out in outs:
            out.stages[name] = share
    for out in outs:
        _finish(plan, out)
    return outs


_STAGES = ("tops", "walls", "ceiling")


def _stages(cp: CompiledPlan, out: SurfacePlacement, rng: np.random.Generator, relations: bool,
            cfg: SolverConfig, reach: float, models: dict
            ) -> list[tuple[str, SampleTask[None]]]:
    """The three stages of one sample as tasks, in order (each starts when driven)."""
    return [("tops", place_on_tops(cp, out.poses, rng, relations, cfg, out, models)),
            ("walls", place_on_walls(cp, out.poses, rng, relations, cfg, reach, out, models)),
            ("ceiling", place_on_ceiling(cp, out.poses, rng, relations, cfg, out, models))]


def _timed(task: SampleTask[None], stages: dict[str, float], name: str) -> SampleTask[None]:
    """``task``, adding the seconds it runs between requests to ``stages[name]``."""
    spent = 0.0
    answer = None
    try:
        while True:
            t = time.perf_counter()
            try:
                request = task.send(answer)
            finally:
                spent += time.perf_counter() - t
            answer = yield request
    except StopIteration:
        pass
    finally:
        stages[name] = stages.get(name, 0.0) + spent


def _finish(plan: Plan, out: SurfacePlacement) -> None:
    """Name every object no stage placed that no stage reported missing."""
    placed = set(out.poses)
    reasons = {m.split(":")[0] for m in out.missing}
    for o in plan.objects:
        if o.id not in placed and o.id not in reasons:
            out.missing.append(f"{o.id}: placed by {plan.surface_of(o.id)!r}, which no stage "
                               "placed")
