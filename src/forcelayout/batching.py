"""The batched engine: samples as coroutines whose simulations run together.

Each sample of a run is written as ordinary sequential code, a generator
that ``yield``\\ s a :class:`SimRequest` wherever it needs a simulation and
receives the :class:`~forcelayout.solver.SimulationResult` back (drawing
start poses, judging and repairing in between). :func:`drive` runs many
such samples side by side: at each round it gathers the requests of every
sample still running, groups those of the same force model and solver
settings, and runs each group as one :func:`~forcelayout.solver.simulate_batch`
(the rule and physical terms computed once per step for the whole group).

A sample's result depends on its own random generator and requests only,
and :func:`~forcelayout.solver.simulate_batch` gives each sample what it
would get alone, so a sample's layout is the same, bit for bit, whatever
batch it ran in.
"""

from __future__ import annotations

from collections.abc import Generator, Sequence
from dataclasses import dataclass
from typing import Any, TypeVar

import numpy as np

from forcelayout.forces import ForceModel
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
    """

    model: ForceModel
    pos: np.ndarray
    yaw: np.ndarray
    config: SolverConfig


#: A sample written as a generator: yields requests, receives results, returns its outcome.
SampleTask = Generator[SimRequest, SimulationResult, T]


def drive(tasks: Sequence[SampleTask[T]]) -> list[T]:
    """Run sample tasks side by side, batching their simulations.

    Parameters
    ----------
    tasks : sequence of generator
        Each yields :class:`SimRequest` and is sent the result of each;
        what it returns is its outcome.

    Returns
    -------
    list
        The tasks' outcomes, in order.
    """
    outcomes: list[Any] = [None] * len(tasks)
    pending: dict[int, SimRequest] = {}

    def advance(k: int, result: SimulationResult | None) -> None:
        try:
            pending[k] = tasks[k].send(result)  # type: ignore[arg-type]
        except StopIteration as stop:
            outcomes[k] = stop.value

    for k in range(len(tasks)):
        advance(k, None)
    while pending:
        groups: dict[tuple[int, SolverConfig], list[int]] = {}
        for k, req in pending.items():
            groups.setdefault((id(req.model), req.config), []).append(k)
        asked, pending = pending, {}
        for ks in groups.values():
            reqs = [asked[k] for k in ks]
            results = simulate_batch(reqs[0].model, np.stack([r.pos for r in reqs]),
                                     np.stack([r.yaw for r in reqs]), reqs[0].config)
            for k, res in zip(ks, results, strict=True):
                advance(k, res)
    return outcomes
