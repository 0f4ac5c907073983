"""A floor arrangement's verdict: the failed checks, the unmet rules, and who is at fault.

Start poses (:mod:`forcelayout.initial`), settling and repair
(:mod:`forcelayout.repair`) all judge a floor the same way:
:func:`judge_floor` runs the deterministic checks on the floor objects and
every floor binding's own check, and names the objects to move.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

from forcelayout.bindings import Binding
from forcelayout.forces import ForceModel
from forcelayout.layout import Layout, Pose
from forcelayout.rules.base import State
from forcelayout.rules.physical import wall_gaps
from forcelayout.surfaces.walls import unhung, unreached, unseen
from forcelayout.validate.checks import check_floors

__all__ = ["FloorVerdict", "JudgeRequest", "judge_floor", "judge_floors", "allowed_misses"]

_QUOTED = re.compile(r"'([^']+)'")


@dataclass
class FloorVerdict:
    """How a floor arrangement fares, and which objects are at fault.

    Attributes
    ----------
    failures : list of str
        Failed checks (``"<check>: ..."``) and unmet bindings (``"rule(object, target)"``).
    at_fault : set of int
        Rows of the objects to move.
    missed : set of int
        Positions of the unmet bindings in the model's ``bindings``, and
        ``-1 - index`` of a wall binding (its ``Binding.index``) the wall stage
        will leave unmet (a shelf that finds no wall within its ``max_gap``
        above its desk); each is one of ``failures`` (the rest are failed
        checks).
    free : float
        Share of the floor free for the agent, as the ``navigable`` check
        judges it (1 where the checks did not run).
    required : set of int
        Those of ``missed`` that the plan requires (``RuleSpec.required``): no share
        of the rules lets them go unmet.
    """

    failures: list[str] = field(default_factory=list)
    at_fault: set[int] = field(default_factory=set)
    missed: set[int] = field(default_factory=set)
    free: float = 1.0
    required: set[int] = field(default_factory=set)

    def _miss(self, binding: Binding, key: int) -> None:
        """Record ``binding`` unmet under ``key`` (its position in the model's
        ``bindings``, or ``-1 - index`` for a rule judged off the floor simulation): one
        more failure, among ``missed``, and among ``required`` where the plan requires it."""
        self.failures.append(str(binding))
        self.missed.add(key)
        if binding.required:
            self.required.add(key)

    def better_than(self, other: FloorVerdict, misses: int = 0) -> bool:
        """Whether this arrangement is nearer acceptance than ``other``.

        Fewer of the failures that reject a sample (failed checks, and unmet bindings
        beyond the ``misses`` it may leave unmet: a door kept clear at the price of one
        rule left unmet, as the sample allows, is nearer); as many, fewer failures; as
        many again, clearly more free floor where too little is free and the other
        failures the same (a step towards the ``navigable`` check that does not yet
        pass it)."""
        if self.rejecting(misses) != other.rejecting(misses):
            return self.rejecting(misses) < other.rejecting(misses)
        if len(self.failures) != len(other.failures):
            return len(self.failures) < len(other.failures)

        def rest(v: FloorVerdict) -> list[str]:
            return sorted(f for f in v.failures if not f.startswith("navigable:"))

        short = any(f.startswith("navigable:") for f in other.failures)
        return short and rest(self) == rest(other) and self.free > other.free + 0.005

    def rejecting(self, misses: int = 0) -> int:
        """How many failures reject the arrangement: failed checks, the unmet bindings
        the plan requires, and the other unmet bindings beyond ``misses``."""
        needed = len(self.required)
        return len(self.failures) - self.unmet + needed + max(0, self.unmet - needed - misses)

    @property
    def unmet(self) -> int:
        """How many of ``failures`` are unmet bindings."""
        return len(self.missed)

    @property
    def ok(self) -> bool:
        """Whether nothing failed."""
        return not self.failures

    def passes(self, misses: int = 0) -> bool:
        """Whether every check passed and at most ``misses`` bindings are unmet.

        A sample is accepted when it meets a share of its rules
        (``Options.min_rule_satisfaction``) and every rule the plan requires;
        ``misses`` is how many of the plan's bindings that share leaves unmet
        (see :func:`allowed_misses`).
        """
        return len(self.failures) - self.unmet == 0 and not self.required \
            and self.unmet <= misses


def allowed_misses(n_bindings: int, min_rule_satisfaction: float) -> int:
    """How many of ``n_bindings`` may be unmet while at least ``min_rule_satisfaction`` are met.

    >>> allowed_misses(20, 0.95), allowed_misses(19, 0.95), allowed_misses(40, 1.0)
    (1, 0, 0)
    """
    if n_bindings <= 0:
        return 0
    return max(0, int(np.floor(n_bindings * (1.0 - min_rule_satisfaction) + 1e-9)))


def judge_floor(model: ForceModel, pos: np.ndarray, yaw: np.ndarray,
                check_kwargs: dict | None = None, *, checks: bool = True,
                walls: bool = True) -> FloorVerdict:
    """Check a floor arrangement and name the objects at fault.

    Parameters
    ----------
    model : ForceModel
        The floor simulation's model (rows are the plan's floor objects).
    pos : ndarray, shape (N, 2)
    yaw : ndarray, shape (N,)
    check_kwargs : dict, optional
        Thresholds for :func:`forcelayout.validate.check_layout`.
    checks : bool
        Run the deterministic checks (default); ``False`` judges the rules
        alone (rows that are not objects of the plan, e.g. an area's
        rectangle, cannot be checked).
    walls : bool
        On a floor that passes every check, judge whether each wall object
        finds a free stretch of wall (:func:`forcelayout.surfaces.walls.unhung`:
        ``walls: ...`` failures, the floor objects in the way at fault), as
        the wall stage will look for one (default); start poses are judged
        without (the simulation still moves what stands under a window).

    Returns
    -------
    FloorVerdict
    """
    return judge_floors(model, np.asarray(pos)[None], np.asarray(yaw)[None], check_kwargs,
                        checks=checks, walls=walls)[0]


def judge_floors(model: ForceModel, pos: np.ndarray, yaw: np.ndarray,
                 check_kwargs: dict | None = None, *, checks: bool = True,
                 blockers: bool = True, walls: bool = True) -> list[FloorVerdict]:
    """:func:`judge_floor` for B arrangements of one model, poses (B, N, 2) and (B, N).

    The checks run for all of them at once
    (:func:`forcelayout.validate.checks.check_floors`) and so do the rules (one
    stacked state; a rule that is not ``batched`` once per arrangement); each
    verdict is the one :func:`judge_floor` gives that arrangement alone.
    ``blockers=False`` leaves out the objects that block the way to an unreachable
    object (from the failures' text and from ``at_fault``): the same failures, as
    many, where only their count matters (choosing among starts).
    """
    pos = np.asarray(pos, dtype=float)
    yaw = np.asarray(yaw, dtype=float)
    nb = len(pos)
    row = {oid: r for r, oid in enumerate(model.ids)}
    out = [FloorVerdict() for _ in range(nb)]
    if checks:
        layouts = [Layout(model.plan, {oid: Pose(float(a[0]), float(a[1]), float(t))
                                       for oid, a, t in zip(model.ids, p, y, strict=True)})
                   for p, y in zip(pos, yaw, strict=True)]
        reports = check_floors(layouts, name_blockers=blockers, **(check_kwargs or {}))
        for v, report in zip(out, reports, strict=True):
            v.failures += report.failures
            for fail in report.failures:
                check = fail.split(":", 1)[0]
                if check in ("collision", "door", "window", "outside", "access"):
                    v.at_fault.update(row[n] for n in _QUOTED.findall(fail) if n in row)
            for blockers in report.blocked_by.values():
                v.at_fault.update(row[n] for n in blockers if n in row)
        # the wall objects that would find no wall to hang on, judged on the floors that
        # pass every check (where a sample would go on to the walls and fail with them
        # missing: a painting above a sofa that stands under a window)
        clean = [b for b, report in enumerate(reports) if walls and not report.failures]
        if clean:
            for b, missing in zip(clean, unhung(model.compiled, list(model.ids), pos[clean],
                                                yaw[clean]), strict=True):
                v = out[b]
                for wall_binding, near, higher in missing:
                    oid, target = wall_binding.object, wall_binding.target
                    if higher:  # the wall stage hangs it higher, its rule unmet
                        v._miss(wall_binding, -1 - wall_binding.index)
                        v.at_fault.add(row[target])
                    elif target is not None:
                        v.failures.append(f"walls: no room for {oid!r} on the wall above "
                                          f"{target!r} (doors, windows or furniture there)")
                        v.at_fault.add(row[target])
                    else:
                        v.failures.append(f"walls: no free stretch of wall for {oid!r} "
                                          "(doors, windows and the furniture by the walls "
                                          "block it)")
                        v.at_fault.update(row[n] for n in near)
        # the rules turning a floor object towards a wall object that its spot leaves
        # unmet, on every floor that passes every check, its start too (a dresser with its
        # mirror on the wall the bed looks at for its TV; two beds facing one TV from
        # different walls)
        clean = [b for b, report in enumerate(reports) if not report.failures]
        if clean:
            for b, missing in zip(clean, unseen(model.compiled, list(model.ids), pos[clean],
                                                yaw[clean]), strict=True):
                v = out[b]
                for view, near in missing:
                    v._miss(view, -1 - view.index)
                    # the objects in the way there, else every object turned to that wall
                    # object (moving the second bed alone set it beside the first, each time)
                    v.at_fault.update([row[n] for n in near] or [
                        row[o.object] for o in model.wall_views if o.target == view.target])
        # the floor objects tied by a close rule to a wall object hung on one wall the plan
        # names, out of reach of that wall (a teacher's desk near the whiteboard)
        for v, far in zip(out, unreached(model.compiled, list(model.ids), pos, yaw),
                          strict=True):
            for tie in far:
                v._miss(tie.binding, -1 - tie.binding.index)
                v.at_fault.add(row[tie.floor])
        radius = float((check_kwargs or {}).get("agent_radius", 0.2))
        band = bool((check_kwargs or {}).get("wall_band", False))
        short = []  # the floors with too little free floor
        for b, (v, report) in enumerate(zip(out, reports, strict=True)):
            v.free = report.navigable_fraction if band else report.free_fraction
            if any(f.startswith("navigable:") for f in report.failures):
                short.append(b)
        if short:
            for b, rows in zip(short, _slivers(model, pos[short], yaw[short], radius),
                               strict=True):
                out[b].at_fault.update(rows)
    if nb == 1:
        met = {k: np.array([ok]) for k, ok in
               model.satisfied(model.state(pos[0], yaw[0])).items()}
    else:
        stacked = model.stacked(nb)
        met = stacked.satisfied(stacked.state(pos.reshape(-1, 2), yaw.reshape(-1)))
    for k, ok in met.items():
        if ok.all():
            continue
        b = model.bindings[k]
        for s in np.flatnonzero(~ok):
            v = out[s]
            v._miss(b, k)
            v.at_fault.add(row[b.object])
            v.at_fault.update(_holding(model, pos[s], b))
    return out


def _holding(model: ForceModel, pos: np.ndarray, binding: Binding) -> list[int]:
    """Rows of the solid floor objects that hold the floor an unmet binding's object wants
    by a door or a window (its rule's start place, within its reach): those not wanted
    there by a rule of their own. A desk kept from the window by a bed that stands under
    it fails with the bed."""
    hint = binding.rule.start
    if hint is None or hint.place not in ("window", "door") or hint.reach is None:
        return []
    openings = model.room.windows if hint.place == "window" else model.room.doors
    pick = int(getattr(binding.params, hint.which, -1)) if hint.which else -1
    centres = openings.centres(pick)
    if not len(centres):
        return []
    reach = float(getattr(binding.params, hint.reach))
    solid = ~np.asarray(model.walkable, dtype=bool)
    near = np.linalg.norm(pos[:, None] - centres[None], axis=2).min(axis=1) < reach
    return np.flatnonzero(near & solid & ~model.wanted_at(hint.place)).tolist()


def _slivers(model: ForceModel, pos: np.ndarray, yaw: np.ndarray, radius: float
             ) -> list[list[int]]:
    """For each of K floors (poses (K, N, 2) and (K, N)), the rows of the solid floor
    objects that leave a sliver of floor too narrow for the agent (a gap of 3 cm up to
    its width) to a wall or to another solid object, or that touch nothing (free floor
    lost all round): too little free floor is mended by closing such gaps, widening them
    into walkways, or moving a lone object."""
    k, n = yaw.shape
    solid = ~np.asarray(model.walkable, dtype=bool)
    if solid.sum() == 0:
        return [[] for _ in range(k)]
    st = State(pos.reshape(k * n, 2), yaw.reshape(k * n), np.tile(model.size, (k, 1)),
               model.room, samples=k)
    wall_gap = wall_gaps(st).reshape(k, n, -1)  # (K, N, W)
    sep = st.sample_separations.copy()  # (K, N, N): each floor's own pairs
    sep[:, np.arange(n), np.arange(n)] = np.inf
    sep[:, :, ~solid] = np.inf
    lo, hi = 0.03, 2.0 * radius
    narrow = ((wall_gap > lo) & (wall_gap < hi)).any(axis=2) | \
        ((sep > lo) & (sep < hi)).any(axis=2)
    alone = (wall_gap > lo).all(axis=2) & (sep > lo).all(axis=2)  # touching nothing
    return [np.flatnonzero(row).tolist() for row in (narrow | alone) & solid]


@dataclass
class JudgeRequest:
    """A sample's ask for the verdict on a floor arrangement (:func:`judge_floor`),
    batched by :func:`forcelayout.batching.drive` with the asks of other samples of the
    same model (:func:`judge_floors`).

    Attributes
    ----------
    model : ForceModel
    pos : ndarray, shape (N, 2) or (M, N, 2)
    yaw : ndarray, shape (N,) or (M, N)
        One arrangement, answered with its verdict, or M, answered with a list of M.
    check_kwargs : dict, optional
    checks, walls : bool
        As for :func:`judge_floor`.
    blockers : bool
        As for :func:`judge_floors`.
    """

    model: ForceModel
    pos: np.ndarray
    yaw: np.ndarray
    check_kwargs: dict | None = None
    checks: bool = True
    blockers: bool = True
    walls: bool = True

    def key(self) -> tuple:
        """Requests with equal keys are judged as one batch."""
        kw = None if self.check_kwargs is None else tuple(sorted(self.check_kwargs.items()))
        return (id(self.model), kw, self.checks, self.blockers, self.walls)

    @staticmethod
    def run(requests: list[JudgeRequest]) -> list[FloorVerdict | list[FloorVerdict]]:
        """The verdicts of requests with the same key, judged together."""
        first = requests[0]
        n = first.model.n
        many = [q.pos.ndim == 3 for q in requests]
        pos = np.concatenate([q.pos.reshape(-1, n, 2) for q in requests])
        yaw = np.concatenate([q.yaw.reshape(-1, n) for q in requests])
        verdicts = judge_floors(first.model, pos, yaw, first.check_kwargs, checks=first.checks,
                                blockers=first.blockers, walls=first.walls)
        out: list[FloorVerdict | list[FloorVerdict]] = []
        at = 0
        for q, m in zip(requests, many, strict=True):
            k = len(q.pos) if m else 1
            out.append(verdicts[at: at + k] if m else verdicts[at])
            at += k
        return out
