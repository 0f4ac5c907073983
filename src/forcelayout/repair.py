"""Repair before reject: move only the objects at fault, then resettle briefly.

A floor simulation that ends with a failed check or an unmet rule is not
thrown away at once. :func:`repair_floor` judges the floor (the
deterministic checks on the floor objects, and every floor binding by its
rule's own check), names the objects at fault — those blocking the path to
an unreachable object (:attr:`CheckReport.blocked_by`), those named by a
collision, door or window failure, those leaving slivers of floor no agent
fits through, the objects of unmet bindings and those holding the floor by
the opening an unmet ``near_window`` or ``near_door`` wants — and runs a short
simulation in which only they move (with their children), with the rules
at full strength and a walkway term that asks them to leave an agent's
width to their neighbours or to touch them; where the floor is short of
free space and every object reachable, a pull that closes the slivers
instead (:func:`closing`). The result is kept only if it is nearer
acceptance (:meth:`~forcelayout.verdict.FloorVerdict.better_than`); at most
``rounds`` rounds, each capped in steps. The sample's report lists what
each round did.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from forcelayout.batching import SampleTask, SimRequest, drive
from forcelayout.forces import ClosingTerm, ForceModel, PassageTerm
from forcelayout.initial import RelocateRequest, Starts, _movers
from forcelayout.options import SolverConfig
from forcelayout.rules.shaping import CAP
from forcelayout.verdict import FloorVerdict, JudgeRequest

__all__ = ["repair_floor", "repair_task", "repairing", "closing"]

#: Candidates and spread of the new spots a repair draws (as start poses draw them).
_TRIES, _SPREAD = 16, 0.3


def repair_floor(model: ForceModel, pos: np.ndarray, yaw: np.ndarray, config: SolverConfig,
                 *, rounds: int = 2, steps: int = 80, check_kwargs: dict | None = None,
                 verdict: FloorVerdict | None = None, rng: np.random.Generator | None = None
                 ) -> tuple[np.ndarray, np.ndarray, int, list[str]]:
    """Repair a settled floor arrangement by moving only the objects at fault.

    Round 1 resettles the objects at fault where they are, with their children
    (the objects that start beside them: the rug under a beanbag, the chair at
    a desk); later rounds (given ``rng``) first move them to new spots drawn as
    start poses are (:func:`forcelayout.initial.relocate`: another wall,
    another corner, the other side of their parent), with their parents every
    other round (rounds 3, 5, ...), then resettle them. A round simulates
    :func:`repairing`'s model, or :func:`closing`'s where the floor is short of
    free space and nothing is unreachable. Three rounds in a row that do not
    help end the repair. One sample of :func:`repair_task` (the batched
    engine's form).

    Parameters
    ----------
    model : ForceModel
    pos, yaw : ndarray
        The settled poses.
    config : SolverConfig
        Base settings; each round runs at most ``steps`` steps.
    rounds : int
        Largest number of repair rounds.
    steps : int
        Step cap of one round.
    check_kwargs : dict, optional
        Thresholds of the checks.
    verdict : FloorVerdict, optional
        The verdict on ``pos, yaw`` if already known.
    rng : numpy.random.Generator, optional
        Source of the new spots; without it every round resettles in place.

    Returns
    -------
    pos, yaw : ndarray
        The best arrangement found (the input if no round improved it).
    steps : int
        Simulation steps spent.
    repairs : list of str
        One line per round that improved the arrangement, naming the moved
        objects and the failures before and after.
    """
    return drive([repair_task(model, pos, yaw, config, rounds=rounds, steps=steps,
                              check_kwargs=check_kwargs, verdict=verdict, rng=rng)])[0]


def repairing(model: ForceModel) -> ForceModel:
    """The model a repair round simulates: ``model`` with walking room (an agent's width
    and a little more, not annealed) between every two solid objects no rule relates.

    Only the objects at fault move in a round, so of those pairs only the ones
    with a moving object act: it keeps that width to its neighbours or touches
    them. Build it once per model and pass it to :func:`repair_task`: the
    rounds of the samples of a batch then simulate together.
    """
    out = model.leaving_out()
    out.add_term(_walkway(model))
    return out


def closing(model: ForceModel, radius: float = 0.2) -> ForceModel:
    """The model a repair round of an arrangement short of free floor simulates:
    ``model`` with a pull that closes the slivers of floor too narrow for an agent of
    ``radius`` (:class:`~forcelayout.forces.ClosingTerm`) between every two solid
    objects and between each and the walls.

    Such gaps are lost to the agent whole; closing them is what frees floor.
    The walking-room term, which asks the same gaps to open, is left out.
    Build it once per model, as :func:`repairing`.
    """
    n = model.n
    pi, pj = (a.astype(int) for a in np.triu_indices(n, k=1))
    solid = ~np.asarray(model.walkable, dtype=bool)
    keep = solid[pi] & solid[pj]
    out = model.leaving_out(PassageTerm)
    out.add_term(ClosingTerm(pi[keep], pj[keep], solid, radius, _CLOSING))
    return out


#: Strength of the pull closing slivers in a repair round: less than half a rule's
#: full pull (``rules.shaping.CAP``), so it closes a gap no rule holds open.
_CLOSING = 0.4 * CAP


def repair_task(model: ForceModel, pos: np.ndarray, yaw: np.ndarray, config: SolverConfig,
                *, rounds: int = 2, steps: int = 80, check_kwargs: dict | None = None,
                verdict: FloorVerdict | None = None, rng: np.random.Generator | None = None,
                placer=None, walking: ForceModel | None = None,
                closer: ForceModel | None = None, misses: int = 0
                ) -> SampleTask[tuple[np.ndarray, np.ndarray, int, list[str]]]:
    """:func:`repair_floor` as a sample task (:mod:`forcelayout.batching`): it asks for
    each verdict with a :class:`~forcelayout.verdict.JudgeRequest`, for each new spot
    with a :class:`~forcelayout.initial.RelocateRequest` and for each round's
    simulation with a :class:`~forcelayout.batching.SimRequest` (its own fixed rows),
    so the repairs of a batch's samples run together. Give the samples of a batch the
    same ``placer`` (:meth:`Starts.placer_of`), ``walking`` (:func:`repairing`) and
    ``closer`` (:func:`closing`). A round is kept where it is nearer acceptance
    (:meth:`FloorVerdict.better_than`), the sample allowed ``misses`` unmet bindings."""
    if verdict is None:
        verdict = yield JudgeRequest(model, pos, yaw, check_kwargs)
    spent, notes = 0, []
    cfg = replace(config, max_steps=max(1, min(config.max_steps, steps)),
                  min_steps=min(config.min_steps, 20))
    idle = 0  # rounds in a row that did not help
    for k in range(max(0, rounds)):
        if verdict.ok or not verdict.at_fault or idle >= 3:
            break
        if placer is None:
            placer = Starts.placer_of(model)
        if walking is None:
            walking = repairing(model)
        movers = np.zeros(model.n, dtype=bool)
        movers[sorted(verdict.at_fault)] = True
        # an object moves with the objects that start beside it (its children: the rug
        # under it, the chair in front of it); moved elsewhere, every other round with
        # its parent too
        movers = _movers(placer.parent, movers, with_parents=k > 0 and k % 2 == 0)
        start_pos, start_yaw, how = pos, yaw, "resettled"
        if k > 0 and rng is not None:
            start_pos, start_yaw = yield RelocateRequest(
                placer, rng, tuple(np.flatnonzero(movers).tolist()), pos, yaw, _TRIES,
                _SPREAD)
            how = "moved elsewhere"
        short = any(f.startswith("navigable:") for f in verdict.failures) and not any(
            f.startswith("reachable:") for f in verdict.failures)
        if short and closer is None:
            closer = closing(model, float((check_kwargs or {}).get("agent_radius", 0.2)))
        res = yield SimRequest(closer if short else walking, start_pos, start_yaw, cfg,
                               fixed=~movers)
        spent += res.steps
        after = yield JudgeRequest(model, res.pos, res.yaw, check_kwargs)
        if not after.better_than(verdict, misses):
            idle += 1
            continue
        idle = 0
        moved = ", ".join(model.ids[r] for r in np.flatnonzero(movers))
        more = ""
        if len(after.failures) == len(verdict.failures) and \
                after.rejecting(misses) == verdict.rejecting(misses):
            more = f" ({verdict.free:.0%} -> {after.free:.0%} of the floor free)"
        elif len(after.failures) >= len(verdict.failures):  # traded for unmet rules
            unmet = ", ".join(sorted(set(after.failures) - set(verdict.failures)))
            more = f" (left unmet, as the sample allows: {unmet})"
        notes.append(f"{how} {moved}: {len(verdict.failures)} -> {len(after.failures)} "
                     f"failures{more}")
        pos, yaw, verdict = res.pos, res.yaw, after
    return pos, yaw, spent, notes


def _walkway(model: ForceModel) -> PassageTerm:
    """Walking room (an agent's width and a little more) between every two solid objects
    no rule relates.

    Not annealed: it holds through the short repair simulation.
    """
    n = model.n
    pi, pj = (a.astype(int) for a in np.triu_indices(n, k=1))
    solid = ~model.walkable
    keep = solid[pi] & solid[pj] & ~model.related[pi, pj]
    w = replace(model.physical_weights, passage=2.0, passage_range=0.5)
    term = PassageTerm(pi[keep], pj[keep], w)
    term.annealed = False
    return term

