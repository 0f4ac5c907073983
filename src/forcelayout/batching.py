"""The batched engine: samples as coroutines whose simulations run together.

Each sample of a run is written as ordinary sequential code, a generator
that ``yield``\\ s a request wherever it needs expensive, batchable work and
receives the answer back: a :class:`SimRequest` for a simulation (answered
with its :class:`~forcelayout.solver.SimulationResult`), a
:class:`forcelayout.initial.ProposeRequest` for a set of start poses, a
:class:`forcelayout.initial.RelocateRequest` to draw some objects again.
:func:`drive` runs many such samples side by side: at each round it gathers
the requests of every sample still running, groups those of the same kind
and ``key()`` (the same force model and solver settings; the same model's
candidate drawer) and answers each group with one call of the kind's
``run(requests)``: one :func:`~forcelayout.solver.simulate_batch` (the rule
and physical terms computed once per step for the whole group), or start
poses placed for the whole group object by object.

A sample's result depends on its own random generator and requests only,
and :func:`~forcelayout.solver.simulate_batch` gives each sample what it
would get alone, so a sample's layout is the same, bit for bit, whatever
batch it ran in.
"""

from __future__ import annotations

from collections.abc import Generator, Hashable, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar, TypeVar

import numpy as np

from forcelayout.forces import ForceModel, ForceTerm
from forcelayout.options import SolverConfig
from forcelayout.solver import SimulationResult, simulate_batch

__all__ = ["SimRequest", "SampleTask", "drive"]

T = TypeVar("T")


@dataclass
class SimRequest:
    """One simulation a sample asks for.

    Attributes
    ----------
    model : ForceModel
        Requests of the same model object (and settings) run as one batch.
    pos : ndarray, shape (N, 2)
    yaw : ndarray, shape (N,)
        Start poses.
    config : SolverConfig
    fixed : ndarray of bool, shape (N,), optional
        Rows that do not move in this sample (they still push and pull).
    obstacles : list of ndarray, optional
        This sample's static convex obstacles (a wall's door and furniture).
    terms : tuple of ForceTerm
        This sample's own extra terms, after the model's (its anchors); the
        requests of one batch have terms of the same classes, in order.
    """

    model: ForceModel
    pos: np.ndarray
    yaw: np.ndarray
    config: SolverConfig
    fixed: np.ndarray | None = None
    obstacles: list[np.ndarray] | None = None
    terms: tuple[ForceTerm, ...] = ()

    #: Answered only in a round where every pending request waits too: samples still
    #: drawing or fixing starts join the batch instead of forming smaller ones later.
    wait: ClassVar[bool] = True

    def key(self) -> Hashable:
        """Requests with equal keys run as one batch."""
        return (id(self.model), self.config, tuple(type(t) for t in self.terms))

    @staticmethod
    def run(requests: list[SimRequest]) -> list[SimulationResult]:
        """One :func:`~forcelayout.solver.simulate_batch` of requests with the same key."""
        first = requests[0]
        fixed = None
        if any(r.fixed is not None for r in requests):
            none = np.zeros(first.model.n, dtype=bool)
            fixed = np.stack([none if r.fixed is None else np.asarray(r.fixed, dtype=bool)
                              for r in requests])
        obstacles = None
        if any(r.obstacles for r in requests):
            obstacles = [list(r.obstacles or []) for r in requests]
        terms = [r.terms for r in requests] if first.terms else None
        return simulate_batch(first.model, np.stack([r.pos for r in requests]),
                              np.stack([r.yaw for r in requests]), first.config, fixed=fixed,
                              sample_obstacles=obstacles, sample_terms=terms)


#: A sample written as a generator: yields requests, receives answers, returns its outcome.
SampleTask = Generator[Any, Any, T]


def drive(tasks: Sequence[SampleTask[T]]) -> list[T]:
    """Run sample tasks side by side, batching their simulations.

    Parameters
    ----------
    tasks : sequence of generator
        Each yields requests (objects with ``key()`` and a static
        ``run(requests) -> answers``, such as :class:`SimRequest`) and is
        sent the answer to each; what it returns is its outcome. A request
        whose class sets ``wait = True`` (a simulation) is answered only in
        a round where every pending request waits: the samples still
        drawing or fixing their starts join its batch rather than forming a
        smaller one a round later. The order of answers changes no outcome.

    Returns
    -------
    list
        The tasks' outcomes, in order.
    """
    outcomes: list[Any] = [None] * len(tasks)
    pending: dict[int, Any] = {}

    def advance(k: int, answer: Any) -> None:
        try:
            pending[k] = tasks[k].send(answer)
        except StopIteration as stop:
            outcomes[k] = stop.value

    for k in range(len(tasks)):
        advance(k, None)
    while pending:
        # requests that wait (simulations) are answered once nothing else is pending
        ready = {k: req for k, req in pending.items() if not getattr(req, "wait", False)}
        asked = ready or pending
        groups: dict[tuple[type, Hashable], list[int]] = {}
        for k, req in asked.items():
            groups.setdefault((type(req), req.key()), []).append(k)
        pending = {k: req for k, req in pending.items() if k not in asked}
        for (kind, _), ks in groups.items():
            answers = kind.run([asked[k] for k in ks])
            for k, answer in zip(ks, answers, strict=True):
                advance(k, answer)
    return outcomes
