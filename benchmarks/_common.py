"""Shared helpers of the evaluation scripts (paper_tables.py, scaling.py).

Not part of the library: plain functions that draw timed samples (in this
process or a process pool), summarise them with :mod:`forcelayout.metrics`,
and write JSON, Markdown and PNG.
"""

from __future__ import annotations

import json
import math
import os
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import Executor, ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

import forcelayout as fl
from forcelayout import baselines, metrics
from forcelayout.sampling import sample_seed

#: Conditions of the paper's Tables I and II.
CONDITIONS = ("Full", "-Relations", "-Decor", "Random")

#: A sample that passes the checks and meets at least this fraction of its rules is "good".
GOOD_RULES = 0.95


@dataclass
class Sample:
    """One raw sample: its layout, whether it is valid, its rules and its CPU time."""

    layout: fl.Layout
    valid: bool
    rule_satisfaction: float
    cpu_seconds: float
    failures: list[str] = field(default_factory=list)

    @property
    def good(self) -> bool:
        """Valid and meeting at least :data:`GOOD_RULES` of its rules."""
        return self.valid and self.rule_satisfaction >= GOOD_RULES


def raw_samples(plan: fl.Plan, seed: int, count: int, batch: int
                ) -> Iterator[tuple[fl.Layout, float]]:
    """Samples ``0 .. count - 1`` of a run with ``seed``, ``batch`` at a time, and CPU seconds.

    Each batch is one :func:`forcelayout.sampling.solve_many` call (the
    batched engine, as :func:`forcelayout.generate` runs a long run); each
    layout comes with its share of its batch's CPU time. On a version of
    the library without ``solve_many`` (an A/B run against an older commit)
    every sample is one :func:`forcelayout.solve`.
    """
    many = getattr(fl.sampling, "solve_many", None)
    for first in range(0, count, batch if many is not None else 1):
        seeds = [sample_seed(seed, k) for k in range(first, min(count, first + batch))]
        t0 = time.process_time()
        layouts = many(plan, seeds) if many is not None else [fl.solve(plan, seeds[0])]
        share = (time.process_time() - t0) / len(layouts)
        for lay in layouts:
            yield lay, share


def draw(plan: fl.Plan, condition: str, seed: int) -> Sample:
    """Draw one raw sample of ``plan`` under ``condition``, timing it in CPU seconds.

    Full, −Relations and −Decor use :func:`forcelayout.solve` (which runs the
    deterministic checks); Random uses :func:`forcelayout.baselines.random_layout`
    judged by :func:`forcelayout.validate.check_layout`. A sample that raises
    counts as invalid, with the error as its failure.
    """
    if condition not in CONDITIONS:
        raise ValueError(f"unknown condition {condition!r}; use one of {CONDITIONS}")
    t0 = time.process_time()
    try:
        if condition == "Random":
            from forcelayout.validate import check_layout

            lay = baselines.random_layout(plan, seed)
            failures = list(check_layout(lay).failures)
            lay.report.valid = not failures
            lay.report.failures = failures
            lay.report.rule_satisfaction = lay.rule_satisfaction
        else:
            opts = {"Full": {}, "-Relations": {"relations": False},
                    "-Decor": {"decor": False}}[condition]
            # validity here is the deterministic checks alone (as in the paper);
            # rule satisfaction is measured apart and combined into "good"
            lay = fl.solve(plan, seed, min_rule_satisfaction=0.0, **opts)
    except Exception as e:  # a failing sample is data, not a crash of the benchmark
        cpu = time.process_time() - t0
        return Sample(fl.Layout(plan, {}, seed), False, 0.0, cpu,
                      [f"error: {type(e).__name__}: {e}"])
    cpu = time.process_time() - t0
    rep = lay.report
    return Sample(lay, bool(rep.valid), float(rep.rule_satisfaction), cpu, list(rep.failures))


def draw_many(plan_source: str, condition: str, n: int, seed: int) -> tuple[str, str, list[Sample]]:
    """Draw samples ``0..n-1`` (seeds ``sample_seed(seed, k)``) of one plan and condition."""
    plan = fl.load_plan(plan_source)
    draw(plan, condition, 2**62)  # warm imports and caches outside the measured samples
    return plan_source, condition, [draw(plan, condition, sample_seed(seed, k)) for k in range(n)]


def run_tasks(fn: Callable[..., Any], tasks: Sequence[tuple[Any, ...]], jobs: int) -> list[Any]:
    """Run ``fn(*task)`` for every task, in a process pool when ``jobs > 1``, in order."""
    if jobs <= 1:
        return [fn(*t) for t in tasks]
    ex: Executor
    with ProcessPoolExecutor(max_workers=jobs) as ex:
        futures = [ex.submit(fn, *t) for t in tasks]
        return [f.result() for f in futures]


def default_jobs() -> int:
    """Worker processes: the cores available to this process, at most 2."""
    try:
        n = len(os.sched_getaffinity(0))
    except AttributeError:
        n = os.cpu_count() or 1
    return max(1, min(2, n))


def ci(values: Any, *, within: bool, resamples: int, seed: int, scale: float = 1.0
       ) -> dict[str, Any]:
    """Bootstrap CI (resampling plans) as a JSON dict, values multiplied by ``scale``."""
    c = metrics.bootstrap_ci(values, n_resamples=resamples, seed=seed, resample_within=within)
    d = c.to_dict()
    for k in ("estimate", "low", "high"):
        if d[k] is not None:
            d[k] = round(float(d[k]) * scale, 4)
    return d


def jsonable(x: Any) -> Any:
    """Replace NaN/inf floats by None, recursively, so ``json.dumps`` gives valid JSON."""
    if isinstance(x, float | np.floating):
        return float(x) if math.isfinite(x) else None
    if isinstance(x, dict):
        return {k: jsonable(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [jsonable(v) for v in x]
    if isinstance(x, np.integer):
        return int(x)
    return x


def dump(result: dict[str, Any], out: str | None) -> None:
    """Print the result as JSON (and write it to ``out`` if given)."""
    text = json.dumps(jsonable(result), indent=2, allow_nan=False)
    print(text)
    if out:
        Path(out).write_text(text + "\n", encoding="utf-8")


def fmt(c: dict[str, Any] | None, digits: int = 2) -> str:
    """``estimate [low, high]`` of a CI dict, or ``–`` when missing."""
    if not c or c.get("estimate") is None:
        return "–"
    lo, hi = c.get("low"), c.get("high")
    if lo is None or hi is None:
        return f"{c['estimate']:.{digits}f}"
    return f"{c['estimate']:.{digits}f} [{lo:.{digits}f}, {hi:.{digits}f}]"


def new_figure(width: float, height: float) -> Any:
    """A matplotlib Figure on the Agg canvas (no display, no pyplot state)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=110)
    FigureCanvasAgg(fig)
    return fig
