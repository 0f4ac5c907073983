"""Validity and rule rates, throughput, and bootstrap confidence intervals.

Rates are fractions in ``[0, 1]`` over samples; throughput is layouts per
second per core; :func:`bootstrap_ci` resamples *plans* (and optionally their
samples) as the paper resamples prompts.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from forcelayout.layout import Layout, SampleReport

__all__ = [
    "validity_rate",
    "rule_satisfaction_rate",
    "throughput",
    "ConfidenceInterval",
    "bootstrap_ci",
]


def _report(item: Layout | SampleReport) -> SampleReport:
    return item.report if isinstance(item, Layout) else item


def validity_rate(items: Iterable[Layout | SampleReport | bool]) -> float:
    """Fraction of samples that passed the deterministic checks, in ``[0, 1]``.

    Items are layouts, their reports, or booleans (NaN when there are none).
    """
    flags = [bool(x) if isinstance(x, bool | np.bool_) else _report(x).valid for x in items]
    return float(np.mean(flags)) if flags else float("nan")


def rule_satisfaction_rate(items: Iterable[Layout | SampleReport | float]) -> float:
    """Mean fraction of rule bindings met over samples, in ``[0, 1]`` (NaN when empty)."""
    vals = [float(x) if isinstance(x, int | float | np.floating) else
            _report(x).rule_satisfaction for x in items]
    return float(np.mean(vals)) if vals else float("nan")


def throughput(count: int, seconds: float, *, cores: int = 1) -> float:
    """Layouts per second per core: ``count / (seconds · cores)``.

    Parameters
    ----------
    count : int
        Layouts produced (e.g. valid ones).
    seconds : float
        Wall time they took on ``cores`` cores, or CPU time with ``cores=1``.
    cores : int
    """
    if seconds < 0 or cores < 1:
        raise ValueError(f"need seconds >= 0 and cores >= 1, got {seconds}, {cores}")
    return float(count / (seconds * cores)) if seconds > 0 else float("nan")


@dataclass(frozen=True)
class ConfidenceInterval:
    """A statistic with its bootstrap confidence interval.

    Attributes
    ----------
    estimate : float
        The statistic on the original data.
    low, high : float
        Percentile interval bounds.
    level : float
        Coverage, e.g. 0.95.
    n_groups : int
        Number of plans (resampling units).
    """

    estimate: float
    low: float
    high: float
    level: float = 0.95
    n_groups: int = 0

    def to_dict(self) -> dict[str, float | int | None]:
        """Plain data; NaN becomes ``None`` so the result is valid JSON."""
        def f(v: float) -> float | None:
            return None if not np.isfinite(v) else float(v)
        return {"estimate": f(self.estimate), "low": f(self.low), "high": f(self.high),
                "level": self.level, "n_groups": self.n_groups}

    def __str__(self) -> str:
        return f"{self.estimate:.3g} [{self.low:.3g}, {self.high:.3g}]"


def bootstrap_ci(
    values_per_plan: Sequence[float] | Sequence[Sequence[float]],
    stat: Callable[..., Any] = np.mean,
    *,
    n_resamples: int = 10_000,
    seed: int | np.random.Generator = 0,
    level: float = 0.95,
    resample_within: bool = False,
) -> ConfidenceInterval:
    """Percentile bootstrap confidence interval, resampling plans with replacement.

    Parameters
    ----------
    values_per_plan : sequence of float, or sequence of sequences of float
        One value per plan, or the values of each plan's samples (pooled for
        the statistic). NaN values are dropped.
    stat : callable
        Statistic of a 1-D array; ``np.mean`` (default) and ``np.median``
        are computed for all resamples at once.
    n_resamples : int
        Bootstrap resamples (10,000 as in the paper).
    seed : int or numpy.random.Generator
    level : float
        Coverage in (0, 1).
    resample_within : bool
        Also resample each drawn plan's own values (two-stage bootstrap), so a
        handful of plans with many samples still gives an informative interval.

    Returns
    -------
    ConfidenceInterval
        NaN bounds when there are no values.
    """
    if not 0 < level < 1:
        raise ValueError(f"level must lie in (0, 1), got {level}")
    if n_resamples < 1 or n_resamples > 10_000_000:
        raise ValueError(f"n_resamples must lie in [1, 10_000_000], got {n_resamples}")
    groups = [np.atleast_1d(np.asarray(v, dtype=float)) for v in values_per_plan]
    groups = [g[np.isfinite(g)] for g in groups]
    groups = [g for g in groups if g.size]
    p = len(groups)
    if p == 0:
        nan = float("nan")
        return ConfidenceInterval(nan, nan, nan, level, 0)
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    estimate = float(stat(np.concatenate(groups)))
    lmax = max(g.size for g in groups)
    pad = np.full((p, lmax), np.nan)
    for k, g in enumerate(groups):
        pad[k, : g.size] = g
    sizes = np.array([g.size for g in groups])
    chunk = max(1, 4_000_000 // (p * lmax))  # resamples per block, bounding memory
    blocks = []
    for start in range(0, n_resamples, chunk):
        r = min(chunk, n_resamples - start)
        pick = rng.integers(0, p, size=(r, p))  # plans drawn per resample
        if resample_within:
            n_pick = sizes[pick][..., None]
            col = np.minimum((rng.random((r, p, lmax)) * n_pick).astype(int), n_pick - 1)
            vals = np.where(np.arange(lmax)[None, None, :] < n_pick, pad[pick[..., None], col],
                            np.nan)
        else:
            vals = pad[pick]  # (r, P, L)
        vals = vals.reshape(r, -1)
        if stat is np.mean:
            blocks.append(np.nanmean(vals, axis=1))
        elif stat is np.median:
            blocks.append(np.nanmedian(vals, axis=1))
        else:
            blocks.append(np.array([stat(row[np.isfinite(row)]) for row in vals], dtype=float))
    stats = np.concatenate(blocks)
    alpha = (1 - level) / 2
    low, high = np.quantile(stats, [alpha, 1 - alpha])
    return ConfidenceInterval(estimate, float(low), float(high), level, p)
