"""Stage P of the method: realise a plan's objects as poses from one random generator.

:func:`realise` is what :func:`forcelayout.solve` runs for each sample. It
places the floor objects (one force-directed simulation, or the hierarchical
path of :mod:`forcelayout.hierarchy` with ``Options(hierarchy=True)``), then
the objects on tops, walls and the ceiling (:mod:`forcelayout.surfaces`).
An object that cannot be placed is listed in :attr:`Placement.missing` with
the reason, never dropped silently.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from forcelayout.batching import SampleTask, SimRequest, drive
from forcelayout.forces import ForceModel
from forcelayout.hierarchy import sample_floor, scene_graph
from forcelayout.initial import Starts
from forcelayout.layout import Pose
from forcelayout.options import Options
from forcelayout.plan import Plan
from forcelayout.repair import closing, repair_task, repairing
from forcelayout.solver import SimulationResult
from forcelayout.surfaces import check_surfaces, place_surfaces_batch
from forcelayout.verdict import FloorVerdict, JudgeRequest, allowed_misses

__all__ = ["Placement", "realise", "realise_batch", "prepare", "SETTLE_STARTS", "SETTLE_MIN_STEPS",
           "START_RULE_SATISFACTION"]


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
    repairs : list of str
        What each repair round of the floor did (empty when none was needed).
    """

    poses: dict[str, Pose]
    steps: int = 0
    converged: bool = True
    missing: list[str] = field(default_factory=list)
    stages: dict[str, float] = field(default_factory=dict)
    repairs: list[str] = field(default_factory=list)


#: Starts that pass and are settled, at most, before the full simulation runs from the first.
SETTLE_STARTS = 3

#: Most starts a sample draws at once once its first two failed (``Starts(ahead=...)``).
START_AHEAD = 8

#: Share of its rules a start must meet to be settled as drawn, at the least (a stricter
#: ``Options.min_rule_satisfaction`` asks for more).
START_RULE_SATISFACTION = 0.95

#: Fewest steps of settling a start that passes (then it stops once at rest).
SETTLE_MIN_STEPS = 10

_PREPARED: dict[int, Plan] = {}


def prepare(plan: Plan) -> None:
    """Checks that need the whole plan, run once per plan object before any simulation.

    Raises
    ------
    PlanError
        A wall object wider than every free wall stretch or outside its
        height band (:func:`forcelayout.surfaces.check_surfaces`), or a cycle
        of bonds (:func:`forcelayout.hierarchy.scene_graph`).
    """
    if _PREPARED.get(id(plan)) is plan:
        return
    check_surfaces(plan)
    scene_graph(plan)
    if len(_PREPARED) > 64:
        _PREPARED.clear()
    _PREPARED[id(plan)] = plan


def _settle(model: ForceModel, quiet: ForceModel, pos: np.ndarray, yaw: np.ndarray,
            opts: Options, misses: int) -> SampleTask[tuple[SimulationResult, bool]]:
    """Settle a start that passes by the rules and the physical terms alone.

    At most ``SolverConfig.settle_steps`` steps of ``quiet``
    (:meth:`ForceModel.settling`: without the walking-room and access terms,
    doors keeping only their swing squares clear; the bindings the start
    leaves unmet muted, :meth:`ForceModel.muting`): they square the objects up
    and press them to their walls, where the walking-room and access terms of
    the full simulation would rearrange an arrangement that needs no
    rearranging. A start that is already at rest stops after
    ``SETTLE_MIN_STEPS`` (the rule forces are strongest at the first steps of
    the annealing, so rest then is rest). A floor still moving that does not
    pass yet (chairs still sliding into place) settles as many steps again;
    one that passes is kept as it is, not polished further. Returns the
    result and whether it still passes (with at most ``misses`` bindings
    unmet).
    """
    cfg = opts.solver
    settle = replace(cfg, max_steps=cfg.settle_steps,
                     min_steps=min(cfg.min_steps, SETTLE_MIN_STEPS, cfg.settle_steps))
    res = yield SimRequest(quiet, pos, yaw, settle)
    ok = (yield JudgeRequest(model, res.pos, res.yaw, opts.check_kwargs)).passes(misses)
    if not ok and not res.converged:
        more = yield SimRequest(quiet, res.pos, res.yaw, settle)
        res = replace(more, steps=res.steps + more.steps)
        ok = (yield JudgeRequest(model, res.pos, res.yaw, opts.check_kwargs)).passes(misses)
    return res, ok


@dataclass
class _Models:
    """The floor's force models, shared by the samples of a batch (so they batch)."""

    full: ForceModel
    quiet: ForceModel  # for settling a start that passes (ForceModel.settling)
    placer: object  # the start poses' candidate drawer (initial.Starts.placer_of)
    muted: dict[frozenset[int], ForceModel] = field(default_factory=dict)
    walking: ForceModel | None = None  # for repair rounds (repair.repairing), when needed
    closer: ForceModel | None = None  # for repair rounds short of floor (repair.closing)

    def repairing(self) -> ForceModel:
        """The model of repair rounds, built once for the batch (so its rounds batch)."""
        if self.walking is None:
            self.walking = repairing(self.full)
        return self.walking

    def closing(self, radius: float) -> ForceModel:
        """The model of repair rounds short of free floor, built once for the batch."""
        if self.closer is None:
            self.closer = closing(self.full, radius)
        return self.closer

    def settling(self, missed: set[int]) -> ForceModel:
        """The settling model for a start that passes with the bindings at ``missed``
        (``FloorVerdict.missed``) unmet: those muted (shared by the samples that leave the
        same ones unmet, so they batch)."""
        off = frozenset(missed)
        if not off:
            return self.quiet
        out = self.muted.get(off)
        if out is None:
            out = self.muted[off] = self.quiet.muting(off)
        return out

    @classmethod
    def of(cls, plan: Plan, opts: Options) -> _Models:
        full = ForceModel(plan, relations=opts.relations)
        placer = Starts.placer_of(full) if full.n else None
        return cls(full, full.settling(), placer)


def _flat_floor(plan: Plan, rng: np.random.Generator, opts: Options, models: _Models
                ) -> SampleTask[tuple[dict[str, Pose], int, bool, list[str]]]:
    model = models.full
    # a start may leave unmet as many bindings as the sample's acceptance allows, but
    # never more than the default acceptance does: a run that accepts any sample
    # (min_rule_satisfaction=0) still gets starts that meet its rules
    misses = allowed_misses(len(model.compiled.bindings),
                            max(opts.min_rule_satisfaction, START_RULE_SATISFACTION))
    steps, best = 0, None
    for attempt in range(opts.floor_attempts):
        res, notes, verdict = yield from _floor_attempt(model, rng, opts, models, misses)
        steps += res.steps
        if attempt:  # the report says which attempt made the layout
            notes = [f"started over ({attempt + 1} of {opts.floor_attempts})", *notes]
        if best is None or verdict is None or verdict.better_than(best[2], misses):
            best = (res, notes, verdict)
        if verdict is None or verdict.passes(misses):
            break
    res, notes, _ = best
    poses = {oid: Pose(float(p[0]), float(p[1]), float(y))
             for oid, p, y in zip(model.ids, res.pos, res.yaw, strict=True)}
    return poses, steps, res.converged, notes


def _floor_attempt(model: ForceModel, rng: np.random.Generator, opts: Options,
                   models: _Models, misses: int
                   ) -> SampleTask[tuple[SimulationResult, list[str], FloorVerdict | None]]:
    """One attempt at a sample's floor: starts drawn until one passes and settles, else the
    full simulation of the start nearest passing, then its repair rounds. Returns the
    result (its poses, steps and whether it converged), the repair notes and the floor's
    verdict (None where a start passed and settled, and where no attempt follows)."""
    settle = opts.solver.settle_steps > 0 and opts.relations and model.n > 0
    steps, settled, start, fewest, tried = 0, None, None, np.inf, 0
    starts = Starts(model, rng, placer=models.placer, misses=misses, ahead=START_AHEAD,
                    restarts=opts.starts)
    while True:
        got = yield from starts.next()
        if got is None:
            break
        pos0, yaw0, verdict = got
        if len(verdict.failures) < fewest:  # the first start with the fewest failures
            start, fewest = (pos0, yaw0), len(verdict.failures)
        if not verdict.passes(misses):
            continue
        if not settle:
            break
        quiet = models.settling(verdict.missed)
        res, ok = yield from _settle(model, quiet, pos0, yaw0, opts, misses)
        steps += res.steps
        if ok:
            settled = res
            break
        tried += 1
        if tried >= SETTLE_STARTS:
            break
    if settled is not None:
        return replace(settled, steps=steps), [], None
    repairs: list[str] = []
    res = yield SimRequest(model, start[0], start[1], opts.solver)
    steps += res.steps
    pos, yaw = res.pos, res.yaw
    if opts.repair > 0 and model.n:
        pos, yaw, extra, repairs = yield from repair_task(
            model, pos, yaw, opts.solver, rounds=opts.repair,
            check_kwargs=opts.check_kwargs, rng=rng, placer=models.placer,
            walking=models.repairing(), misses=misses,
            closer=models.closing(float(opts.check_kwargs.get("agent_radius", 0.2))))
        steps += extra
        yaw = (yaw + np.pi) % (2 * np.pi) - np.pi
    verdict = None
    if opts.floor_attempts > 1 and model.n:  # whether to start over, and which attempt is
        # nearer passing (neither asks what blocks the way to an unreachable object)
        verdict = yield JudgeRequest(model, pos, yaw, opts.check_kwargs, blockers=False)
    return replace(res, pos=pos, yaw=yaw, steps=steps), repairs, verdict


def realise(plan: Plan, rng: np.random.Generator, opts: Options) -> Placement:
    """Place every object of the plan: the floor, then tops, walls and the ceiling.

    With ``opts.hierarchy`` the floor comes from the hierarchical path
    (:func:`forcelayout.hierarchy.sample_floor`: area variants assembled by a
    room-level simulation, then settled together); otherwise from one
    annealed simulation of all floor objects. The surface stage
    (:func:`forcelayout.surfaces.place_surfaces`) then places the ``on_top``,
    wall and ceiling objects. The same as one sample of :func:`realise_batch`.

    Returns
    -------
    Placement
        Poses of all placed objects; ``missing`` names every object of the
        plan left without a pose, with the reason. ``stages`` holds seconds
        per stage (``"floor"``, ``"tops"``, ``"walls"``, ``"ceiling"``, and
        on the hierarchical path ``"variants"`` and ``"assembly"``).
    """
    return realise_batch(plan, [rng], opts)[0]


def realise_batch(plan: Plan, rngs: Sequence[np.random.Generator], opts: Options
                  ) -> list[Placement]:
    """:func:`realise` for many samples of one plan, their floors simulated together.

    Sample ``k`` draws only from ``rngs[k]``, and the floor simulations of
    all samples (on the flat path) and their surface planes' simulations
    run as batches (:mod:`forcelayout.batching`), so each placement is the
    one :func:`realise` gives that generator alone. Each stage's time (on
    the flat path) is the batch's time on it shared equally among its
    samples.
    """
    prepare(plan)
    count = max(len(rngs), 1)
    t0 = time.perf_counter()
    if opts.hierarchy:  # area variants assembled in the room, one sample at a time
        floors = [(*sample_floor(plan, rng, opts), []) for rng in rngs]
    else:
        models = _Models.of(plan, opts)
        flat = drive([_flat_floor(plan, rng, opts, models) for rng in rngs])
        share = (time.perf_counter() - t0) / count
        floors = [(poses, steps, converged, {"floor": share}, repairs)
                  for poses, steps, converged, repairs in flat]
    surfs = place_surfaces_batch(plan, [floor[0] for floor in floors], rngs,
                                 relations=opts.relations, solver=opts.solver)
    out = []
    for (_, steps, converged, stages, repairs), surf in zip(floors, surfs, strict=True):
        stages = {**stages, **surf.stages}
        out.append(Placement(surf.poses, steps + surf.steps, converged and surf.converged,
                             surf.missing, stages, repairs))
    return out
