"""One plan → many layouts: seeded samples, checks, and any executor.

:func:`solve` realises a plan once from a seed. :func:`generate` draws
samples until ``n`` valid, distinct layouts are accepted or the attempt
budget is spent, on any :class:`concurrent.futures.Executor` (a process
pool on one machine, ``distributed.Client.get_executor()`` on a Dask
cluster, Ray's executor, ...). Sample ``k`` of a run with seed ``s`` always
uses the seed sequence ``(s, k)``, and samples are accepted in index order,
so the result does not depend on the executor or the number of workers.
"""

from __future__ import annotations

import collections
import itertools
import math
import signal
import time
import warnings
from collections.abc import Callable, Iterable, Iterator, Sequence
from concurrent.futures import Executor, ProcessPoolExecutor
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from forcelayout._heap import older_objects_frozen
from forcelayout.diagnose import (
    EmptyGenerationError,
    Feasibility,
    FeasibilityWarning,
    FewLayoutsWarning,
    dominant_cause,
    feasibility,
    missed_rules,
)
from forcelayout.errors import PlanError
from forcelayout.layout import Layout, SampleReport
from forcelayout.metrics.sets import still_objects
from forcelayout.options import Options
from forcelayout.plan import Plan
from forcelayout.sources import load_plan
from forcelayout.views import Summary

__all__ = [
    "Options",
    "Generation",
    "DistinctLayouts",
    "solve",
    "solve_many",
    "generate",
    "iter_samples",
    "executor_workers",
    "repair_counts",
    "process_pool",
    "stop_executor",
    "plan_feasibility",
    "sample_seed",
]


def sample_seed(seed: int, index: int) -> int:
    """The seed of sample ``index`` of a run seeded with ``seed`` (a 63-bit int)."""
    ss = np.random.SeedSequence([int(seed) & 0xFFFFFFFFFFFFFFFF, int(index)])
    return int(ss.generate_state(1, dtype=np.uint64)[0] >> np.uint64(1))


def _plan_for(plan: Plan, opts: Options) -> Plan:
    if opts.decor:
        return plan
    from forcelayout.ablation import without_decor

    return without_decor(plan)


def solve(
    plan: Plan | str | dict[str, Any],
    seed: int = 0,
    *,
    options: Options | None = None,
    **kwargs: Any,
) -> Layout:
    """Realise a plan once.

    Parameters
    ----------
    plan : Plan, path, JSON text, dict or bundled plan name
    seed : int
        Same plan + seed gives the same layout, bit for bit, on one machine.
    options : Options, optional
        Or give its fields as keyword arguments (``relations=False``, ...).

    Returns
    -------
    Layout
        Its ``report`` says whether it passed the checks and, if not, why.
    """
    opts = _options(options, kwargs, "solve", ("seed", "options"))
    if not isinstance(seed, int | np.integer) or seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
    plan = _plan_for(load_plan(plan), opts)
    return _solve_many(plan, [int(seed)], opts)[0]


def solve_many(
    plan: Plan | str | dict[str, Any],
    seeds: Sequence[int],
    *,
    options: Options | None = None,
    **kwargs: Any,
) -> list[Layout]:
    """Realise a plan once per seed, the samples simulated together (the batched engine).

    Layout ``k`` is :func:`solve` of ``seeds[k]``, bit for bit; the floor
    simulations of all seeds run as batches, which takes less time per
    sample than one :func:`solve` call per seed. ``Options.batch`` does not
    apply here: every seed given is one batch.

    Parameters
    ----------
    plan : Plan, path, JSON text, dict or bundled plan name
    seeds : sequence of int
    options : Options, optional
        Or give its fields as keyword arguments.

    Returns
    -------
    list of Layout
        One per seed, in order, each with its ``report``.
    """
    opts = _options(options, kwargs, "solve_many", ("seeds", "options"))
    seeds = [int(s) for s in seeds]
    bad = [s for s in seeds if s < 0]
    if bad:
        raise ValueError(f"seeds must be non-negative integers, got {bad[0]!r}")
    plan = _plan_for(load_plan(plan), opts)
    return _solve_many(plan, seeds, opts)


def _solve_many(plan: Plan, seeds: list[int], opts: Options) -> list[Layout]:
    """:func:`solve` of each seed, one batch; each report's ``seconds`` is its share."""
    t0 = time.perf_counter()
    from forcelayout.pipeline import realise_batch
    from forcelayout.validate.checks import reusing_floor_checks

    layouts = []
    # a settled floor is not checked twice; the collector's passes skip older objects
    with reusing_floor_checks(), older_objects_frozen():
        placed = realise_batch(plan, [np.random.default_rng(s) for s in seeds], opts)
        for seed, p in zip(seeds, placed, strict=True):
            report = SampleReport(seed=seed, steps=p.steps, converged=p.converged,
                                  missing=p.missing, stages=p.stages, repairs=p.repairs)
            if p.missing:
                report.failures.append("missing: " + "; ".join(p.missing))
            layouts.append(Layout(plan, p.poses, seed, report))
        Layout._judge_rules_of(layouts)  # all rule reports on one stacked state
        for layout in layouts:
            _judge(layout, opts)
    share = (time.perf_counter() - t0) / max(len(seeds), 1)
    for lay in layouts:
        lay.report.seconds = share
    return layouts


#: Fewest samples a run with the default budget draws before it may give up with none
#: accepted (:attr:`Generation.stopped_early`).
_GIVE_UP_AFTER = 10

#: How a sample's failure line begins where it misses a rule the plan requires.
_REQUIRED = "rules: required by the plan"


def _judge(layout: Layout, opts: Options) -> None:
    report = layout.report
    report.rule_satisfaction = layout.rule_satisfaction
    failures: list[str] = list(report.failures)  # e.g. objects that could not be placed
    if opts.check:
        from forcelayout.validate import check_layout

        failures.extend(check_layout(layout, **opts.check_kwargs).failures)
    if report.rule_satisfaction < opts.min_rule_satisfaction:
        unmet = [r.label for r in layout.rule_report() if r.satisfied is False]  # cached
        from forcelayout.validate.checks import _percents

        shown, need = _percents(report.rule_satisfaction, opts.min_rule_satisfaction)
        failures.append(f"rules: {shown}% met, below {need}%; unmet: {', '.join(unmet)}")
    elif report.rule_satisfaction < 1.0 and (needed := layout.required_unmet):
        # whatever share the acceptance asks for
        failures.append(f"{_REQUIRED}; unmet: {', '.join(needed)}")
    report.failures = failures
    report.valid = not failures


def _options(options: Options | None, kwargs: dict[str, Any], caller: str = "",
             own: Sequence[str] = ()) -> Options:
    """``options`` with the fields given as keyword arguments (these win); an unknown name
    is refused with the closest of the Options fields and the caller's ``own`` arguments."""
    opts = options or Options()
    if kwargs:
        fields = sorted(Options.__dataclass_fields__)
        unknown = sorted(set(kwargs) - set(fields))
        if unknown:
            import difflib

            close = difflib.get_close_matches(unknown[0], [*own, *fields], n=1)
            hint = f" Did you mean {close[0]!r}?" if close else ""
            raise TypeError(f"{caller + ': ' if caller else ''}unknown keyword argument(s) "
                            f"{unknown}.{hint} Its own: {', '.join(own) or 'none'}; the "
                            f"Options fields: {', '.join(fields)}")
        opts = replace(opts, **kwargs)
    return opts


def _samples(plan: Plan, seeds: list[int], opts: Options) -> list[Layout]:
    """Samples of the given seeds as one batch; a sample that fails says why, the run goes on."""
    try:
        return _solve_many(_plan_for(plan, opts), seeds, opts)
    except (PlanError, TypeError, ValueError):
        raise
    except Exception as e:
        if len(seeds) > 1:  # find the sample at fault: the others are the same alone
            return [lay for s in seeds for lay in _samples(plan, [s], opts)]
        report = SampleReport(seed=seeds[0], valid=False, converged=False,
                              failures=[f"error: {type(e).__name__}: {e}"])
        return [Layout(plan, {}, seeds[0], report)]


def _chunks(indices: Iterator[int], largest: int, expect: int = 0, parts: int = 1
            ) -> Iterator[list[int]]:
    """Consecutive runs of sample indices: the ``expect`` samples a caller expects to use in
    at least ``parts`` near-equal runs of at most ``largest``; then runs 1, 2, 4, ... long
    up to ``largest``.

    A run that stops early (``n`` layouts accepted) computes few samples it
    throws away; a long one soon runs full batches.
    """
    if expect > 0:
        count = max(parts, -(-expect // largest))
        base, extra = divmod(expect, count)
        for k in range(count):
            chunk = list(itertools.islice(indices, base + (k < extra)))
            if not chunk:
                return
            yield chunk
    size = 1
    while True:
        chunk = list(itertools.islice(indices, size))
        if not chunk:
            return
        yield chunk
        size = min(2 * size, largest)


@dataclass
class Generation:
    """The outcome of :func:`generate`: accepted layouts and every sample's report.

    Iterating, ``len()`` and indexing go over the accepted layouts. Indexing
    an empty one raises :class:`~forcelayout.diagnose.EmptyGenerationError`
    (an ``IndexError``) saying why it is empty.

    Attributes
    ----------
    layouts : list of Layout
        Valid, distinct layouts in sample order.
    reports : list of SampleReport
        One per attempted sample (accepted or not), in sample order.
    seconds : float
        Wall time of the whole run, from the call on: loading and preparing the plan
        included (in a new process, the first run also loads the parts of the library it
        uses, about a second).
    wanted : int or None
        The ``n`` asked for.
    feasibility : Feasibility or None
        The plan's :func:`~forcelayout.diagnose.feasibility` estimate, made
        once before sampling.
    why : str or None
        When fewer than ``wanted`` layouts were accepted, the dominant cause
        in one line (:func:`~forcelayout.diagnose.dominant_cause` of the
        reports); ``None`` otherwise.
    stopped_early : int or None
        The sample budget a run stopped short of, where it gave up early: no
        layout accepted after a quarter of its default budget (10 samples at
        least) while the plan looked infeasible before sampling, or while one
        rule failed nearly every sample (:meth:`hint` names it); ``None``
        otherwise. A run given ``max_attempts`` draws them all.
    """

    plan: Plan
    seed: int
    layouts: list[Layout]
    reports: list[SampleReport]
    seconds: float
    wanted: int | None = None
    feasibility: Feasibility | None = None
    why: str | None = None
    stopped_early: int | None = None

    def __iter__(self) -> Iterator[Layout]:
        return iter(self.layouts)

    def __len__(self) -> int:
        return len(self.layouts)

    def __getitem__(self, k: int) -> Layout:
        if not self.layouts and not isinstance(k, slice):
            raise EmptyGenerationError(self._empty_message())
        return self.layouts[k]

    def _empty_message(self) -> str:
        head = f"no layout of plan {self.plan.name!r} was accepted"
        if self.wanted == 0:
            return f"{head}: none was asked for (n=0)"
        text = f"{head} in {self.attempted} samples: {self._cause()}"
        if self.feasibility is not None and not self.feasibility.ok:
            text += (" (before sampling the plan looked infeasible: "
                     f"{self.feasibility.infeasible_notes[0]})")
        return text

    def _cause(self) -> str:
        """The one-line reason for too few layouts (``why`` when set)."""
        if self.why:
            return self.why
        if not self.reports:
            return "no sample was drawn (max_attempts=0)"
        return (dominant_cause(self.reports)
                or f"the budget of {self.attempted} samples ran out before any failed")

    def hint(self, *, cli: bool = False) -> str | None:
        """One line: how many layouts came of how many samples, why, and what to try.

        ``None`` when ``wanted`` layouts were accepted. ``cli=True`` names the
        command line's ``--max-attempts`` instead of ``max_attempts=``.
        """
        if self.wanted is None or len(self.layouts) >= self.wanted:
            return None
        k, n, tried = len(self.layouts), self.wanted, self.attempted

        def attempts(total: int) -> str:
            return f"--max-attempts {total}" if cli else f"max_attempts={total}"

        raised = [r for r in self.rejected if any(f.startswith("error:") for f in r.failures)]
        if tried == 0:
            todo = f"allow samples with {attempts(max(4 * n, n + 20))}"
        elif len(raised) > 0.5 * len(self.rejected):
            # an exception is a fault of the code, not of the plan: no sample mends it
            seed = raised[0].seed
            show = ("run again as forcelayout --debug generate ... for its traceback" if cli else
                    f"forcelayout.solve(plan, {seed}) raises it with its traceback")
            todo = (f"{len(raised)} of {tried} samples raised an exception in the library or "
                    f"a plugin rule, which neither a looser plan nor more samples mend: {show}")
        elif self.feasibility is not None and not self.feasibility.ok:
            first = self.feasibility.infeasible_notes[0]
            if first in {str(f) for f in self.feasibility.findings}:  # a rule that cannot
                # be met, with its fix: that, not more samples or less furniture
                todo = f"before sampling the plan looked infeasible: {first}"
            else:
                todo = ("the plan looked infeasible before sampling; loosen it (fewer or "
                        "smaller objects, a larger room, fewer wall rules) rather than "
                        "drawing more samples")
        elif k < 0.1 * tried and (crowded := self._crowded()) is not None:
            # samples do not mend a room too full to walk through
            more = tried + math.ceil((n - k) * tried / k * 1.2) if k else 4 * tried
            todo = (f"before sampling the plan looked tight ({crowded}): fewer or smaller "
                    f"objects or a larger room will do more than samples (or try "
                    f"{attempts(more)})")
        elif k < 0.1 * tried and (never := self._never_met()) is not None:
            # one rule missed by nearly every sample: likely impossible as written, which a
            # lower share only hides
            rule, m, of, required = never
            short = None if required else self._short_of_rules(n - k)
            todo = (f"{rule} was unmet in {m} of the {of} samples that failed for their "
                    "rules, so it may be impossible as written, or at odds with another rule "
                    "(its distance or angle, a wall or opening that pins one of its "
                    "objects): loosen or remove it")
            if required:
                todo += " (the plan requires it)"
            elif short is not None:
                flag = (f"--min-rules {short[1]:.2f}" if cli
                        else f"min_rule_satisfaction={short[1]:.2f}")
                todo += f"; {flag} accepts layouts that leave it unmet"
        elif k < 0.1 * tried and (short := self._short_of_rules(n - k)) is not None:
            # samples that pass every check but a rule or two: a lower share of rules met
            # takes them, where more samples seldom meet every rule
            count, share = short
            flag = f"--min-rules {share:.2f}" if cli else f"min_rule_satisfaction={share:.2f}"
            todo = (f"{count} of {tried} samples passed every check and met {share:.0%} of "
                    f"the rules or more: {flag} accepts such samples; or loosen the rule "
                    "named, since more samples seldom meet them all")
        elif k > 0 and (dup := self._duplicates()) >= max(0.5 * tried, 4 * k):
            # most valid samples repeat the few layouts the plan allows: more samples repeat
            # them again
            todo = (f"{dup} of {tried} samples repeat one of the {k} accepted, so the plan "
                    f"seems to allow about {k} distinct layouts: loosen it (fewer wall or "
                    "corner rules, a larger room) for more"
                    + ("" if cli else ", or lower distinct_tol") + ", not more samples")
        elif k > 0:
            more = tried + math.ceil((n - k) * tried / k * 1.2)
            todo = f"try {attempts(more)} (about {k / tried:.0%} of samples are accepted)"
        else:
            todo = f"loosen the plan, or try {attempts(4 * tried)} for a rare success"
        if self.stopped_early is not None:
            todo += (f" (stopped after {tried} of {self.stopped_early} samples, none accepted: "
                     f"{attempts(self.stopped_early)} draws them all)")
        line = (f"only {k} of {n} layouts of plan {self.plan.name!r} from {tried} samples: "
                f"{self._cause()}; {todo}")
        return " ".join(line.split())  # one line whatever the failure messages hold

    def _duplicates(self) -> int:
        """How many samples were valid but repeated an accepted layout."""
        return sum(DistinctLayouts.FAILURE in r.failures for r in self.rejected)

    def _short_of_rules(self, wanted: int) -> tuple[int, float] | None:
        """How many rejected samples failed for their rules alone, and the share of rules
        (rounded down to a hundredth) that ``wanted`` of them, or all if fewer, meet; None
        unless at least half the samples failed so, meeting half their rules or more."""
        sats = sorted((r.rule_satisfaction for r in self.rejected
                       if r.failures and not r.missing
                       and all(f.startswith("rules:") and not f.startswith(_REQUIRED)
                               for f in r.failures)), reverse=True)
        if not sats or len(sats) < 0.5 * self.attempted:
            return None
        share = math.floor(sats[min(wanted, len(sats)) - 1] * 100 + 1e-9) / 100
        if share < 0.5:
            return None
        return sum(s >= share for s in sats), share

    def _never_met(self) -> tuple[str, int, int, bool] | None:
        """The rule binding missed most often by the samples that failed for their rules,
        how many missed it, how many so failed, and whether the plan requires it; where it
        is at least 10 and 90 % of them, else None."""
        lines = [[f for f in r.failures if f.startswith("rules:")] for r in self.rejected]
        missed = [missed_rules(ls) for ls in lines if ls]
        counts = collections.Counter(b for m in missed for b in m)
        if not counts:
            return None
        rule, m = counts.most_common(1)[0]
        if m < max(10, 0.9 * len(missed)):
            return None
        return rule, m, len(missed), rule in {s.label for s in self.plan.rules if s.required}

    def _hopeless(self) -> bool:
        """Whether a run with nothing accepted yet may give up: the plan looked infeasible
        before sampling, or tight on free floor with nine in ten samples short of it
        (:meth:`_crowded`), or nine in ten samples failed for their rules, one rule among
        them nearly every time (:meth:`_never_met`)."""
        if self.layouts:
            return False
        if self.feasibility is not None and self.feasibility.verdict == "infeasible":
            return True
        short = self._failing("navigable")
        if short >= 0.9 * len(self.reports) and self._crowded() is not None:
            return True
        ruled = self._failing("rules")
        return ruled >= 0.9 * len(self.reports) and self._never_met() is not None

    def _failing(self, check: str) -> int:
        """How many samples failed ``check`` (the word their failure lines begin with)."""
        return sum(any(f.startswith(check + ":") for f in r.failures) for r in self.reports)

    def _crowded(self) -> str | None:
        """The feasibility note on too little free floor, where most samples failed the
        ``navigable`` check and the estimate had found the plan tight there."""
        feas = self.feasibility
        if feas is None or feas.verdict != "tight" or not self.reports:
            return None
        short = self._failing("navigable")
        if short <= 0.5 * len(self.reports):
            return None
        return next((note for note in feas.notes if "of the floor free" in note), None)

    @property
    def attempted(self) -> int:
        """Number of samples drawn."""
        return len(self.reports)

    @property
    def rejected(self) -> list[SampleReport]:
        """Reports of the samples that were not accepted."""
        accepted = {lay.report.seed for lay in self.layouts}
        return [r for r in self.reports if r.seed not in accepted]

    def summary(self) -> Summary:
        """Counts, rates, timing and the most common failure reasons (``failure_reasons``:
        how many rejected samples failed each check or rule, a sample once under each);
        ``repaired``: how many samples drawn were repaired, and how many by each kind of
        step (``"resettled"``, ``"moved elsewhere"``, ``"started over"``; a sample once
        under each, :attr:`SampleReport.repairs`);
        ``still_objects``: floor objects in the same spot in every accepted layout (of
        five or more; :func:`forcelayout.metrics.still_objects`).

        Returns
        -------
        Summary
            A ``dict`` (JSON-ready, as before) whose ``str()`` is an aligned
            table and which Jupyter shows as an HTML table.
        """
        reasons: dict[str, int] = {}
        for r in self.rejected:
            # a valid sample beyond the n wanted (drawn in the same wave) failed nothing;
            # a sample counts once under each reason, however many lines it failed by
            for key in dict.fromkeys(f.split(":")[0] for f in r.failures
                                     or ["surplus: valid, beyond the layouts wanted"]):
                reasons[key] = reasons.get(key, 0) + 1
        valid = sum(r.valid for r in self.reports)
        return Summary({
            "plan": self.plan.name,
            "seed": self.seed,
            "wanted": self.wanted,
            "accepted": len(self.layouts),
            "attempted": self.attempted,
            "feasibility": self.feasibility.verdict if self.feasibility is not None else None,
            "feasibility_notes": list(self.feasibility.notes) if self.feasibility is not None
            else [],
            "why": self.why,
            "valid_fraction": valid / max(self.attempted, 1),
            "mean_rule_satisfaction": float(np.mean([r.rule_satisfaction for r in self.reports]))
            if self.reports else 0.0,
            "seconds": self.seconds,
            "layouts_per_second": len(self.layouts) / self.seconds if self.seconds else 0.0,
            "median_steps": float(np.median([r.steps for r in self.reports])) if self.reports
            else 0.0,
            "failure_reasons": dict(sorted(reasons.items(), key=lambda kv: -kv[1])),
            "repaired": repair_counts(r.repairs for r in self.reports),
            # floor objects the plan leaves one spot: the same pose in every layout
            "still_objects": still_objects(self.layouts),
        })

    def _repr_html_(self) -> str:
        """Jupyter's view: thumbnails of the first layouts and the summary table."""
        from forcelayout.views import generation_html

        return generation_html(self)

    def __repr__(self) -> str:
        of = f"/{self.wanted}" if self.wanted is not None else ""
        return (f"<Generation plan={self.plan.name!r} seed={self.seed} layouts={len(self)}{of} "
                f"attempted={self.attempted} seconds={self.seconds:.2f}>")


class DistinctLayouts:
    """Accepted layouts, indexed so a new one is compared only with its near neighbours.

    Two layouts of the same objects are duplicates when every object's centre
    lies within ``tol`` metres (on each axis) of its place in the other. The
    index keys each layout by the grid cell (size ``tol``) of its first few
    coordinates; a duplicate can only sit in a neighbouring cell, so checking
    one layout costs a fixed number of look-ups instead of a pass over all the
    accepted ones (near-linear time for a whole run).

    Parameters
    ----------
    tol : float
        Largest per-axis distance, metres, at which two layouts are the same;
        0 accepts everything.
    dims : int
        How many coordinates key the index.

    Examples
    --------
    >>> import forcelayout as fl
    >>> seen = fl.sampling.DistinctLayouts(0.05)
    >>> lay = fl.solve("bedroom", 0)
    >>> seen.add_if_new(lay), seen.add_if_new(lay)
    (True, False)
    """

    #: The failure a sample that duplicates an accepted layout is given.
    FAILURE = "duplicate: within distinct_tol of an accepted layout"

    def __init__(self, tol: float, dims: int = 4):
        self.tol, self.dims = float(tol), int(dims)
        self._cells: dict[tuple, list[np.ndarray]] = {}

    def _key(self, layout: Layout) -> tuple[tuple, np.ndarray, np.ndarray]:
        ids = tuple(layout.ids())
        v = np.array([[layout.poses[i].x, layout.poses[i].y] for i in ids]).ravel()
        k = min(self.dims, v.size)
        return ids, v, np.floor(v[:k] / self.tol).astype(int)

    def is_new(self, layout: Layout) -> bool:
        """Whether ``layout`` is no duplicate of an indexed one (it is not indexed).

        With :meth:`add`, this lets a caller test a layout, run a further
        test on it (e.g. a plausibility judge) and index only the ones it keeps.
        """
        if self.tol <= 0:
            return True
        ids, v, key = self._key(layout)
        for off in itertools.product((-1, 0, 1), repeat=key.size):
            for w in self._cells.get((ids, *(key + np.array(off, dtype=int)).tolist()), ()):
                if np.abs(v - w).max() < self.tol:
                    return False
        return True

    def add(self, layout: Layout) -> None:
        """Index ``layout`` (whether or not it is a duplicate)."""
        if self.tol <= 0:
            return
        ids, v, key = self._key(layout)
        self._cells.setdefault((ids, *key.tolist()), []).append(v)

    def add_if_new(self, layout: Layout) -> bool:
        """Index ``layout`` and return True, or return False for a duplicate."""
        if not self.is_new(layout):
            return False
        self.add(layout)
        return True


def executor_workers(executor: Executor | None) -> int:
    """How many samples ``executor`` runs at once (1 for none; a guess for unknown kinds).

    Knows ``ProcessPoolExecutor``/``ThreadPoolExecutor`` and Dask's
    ``Client.get_executor()``; any other executor may say so with a
    ``max_workers`` attribute.
    """
    if executor is None:
        return 1
    for name in ("max_workers", "_max_workers"):
        value = getattr(executor, name, None)
        if isinstance(value, int) and value > 0:
            return value
    client = getattr(executor, "_client", None)  # distributed.client.ClientExecutor
    if client is not None:
        try:
            return max(1, sum(client.nthreads().values()))
        except Exception:  # a client that cannot say: a modest guess
            return 4
    return 4


def _leave_interrupts_to_the_parent() -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)


class _Pool(ProcessPoolExecutor):
    """A process pool that can be stopped at once (see :func:`process_pool`)."""

    def stop_now(self) -> None:
        """Cancel the samples not started and end the workers now, not after their batch.

        What Ctrl-C asks for: a worker that ignores it would otherwise finish
        its batch first, and an interrupt that lands while the pool shuts
        down can leave idle workers waiting for work that never comes.
        """
        workers = list((getattr(self, "_processes", None) or {}).values())
        super().shutdown(wait=False, cancel_futures=True)
        for w in workers:
            if w.is_alive():
                w.terminate()
        for w in workers:
            w.join(5)

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        """As ``ProcessPoolExecutor.shutdown``; Ctrl-C while it waits stops the pool now."""
        try:
            super().shutdown(wait=wait, cancel_futures=cancel_futures)
        except KeyboardInterrupt:
            self.stop_now()
            raise


def process_pool(max_workers: int | None = None) -> ProcessPoolExecutor:
    """A process pool whose workers leave Ctrl-C to the parent process.

    Ctrl-C in a terminal interrupts every process of the foreground group;
    the workers of this pool ignore it, so only the parent stops (and can
    keep what is finished and say so) instead of each worker printing a
    traceback. Its ``stop_now()`` cancels what has not started and ends the
    workers at once (the command line calls it on Ctrl-C).

    Parameters
    ----------
    max_workers : int, optional
        Processes (default: one per core).
    """
    return _Pool(max_workers, initializer=_leave_interrupts_to_the_parent)


def stop_executor(executor: Executor) -> None:
    """Stop an executor after Ctrl-C: at once for :func:`process_pool`'s, else cancel
    what has not started and leave the rest to finish."""
    stop = getattr(executor, "stop_now", None)
    if callable(stop):
        stop()
    else:
        executor.shutdown(wait=False, cancel_futures=True)


def iter_samples(
    plan: Plan | str | dict[str, Any],
    seed: int = 0,
    *,
    start: int = 0,
    stop: int | None = None,
    executor: Executor | None = None,
    options: Options | None = None,
    ahead: int | None = None,
    expect: int | None = None,
) -> Iterator[tuple[int, Layout]]:
    """Samples ``start, start + 1, ...`` of a run, judged, in index order.

    Sample ``k`` is :func:`solve` of the plan with :func:`sample_seed(seed, k)
    <sample_seed>`, so what this yields does not depend on the executor. On
    an executor, up to ``ahead`` samples run at once and each is yielded as
    soon as it and every sample before it are done; closing the iterator (or
    leaving a ``for`` loop over it) cancels the samples not yet started.

    Parameters
    ----------
    plan : Plan, path, JSON text, dict or bundled plan name
    seed : int
        Seed of the run.
    start, stop : int
        First sample index, and one past the last (``None``: no end).
    executor : concurrent.futures.Executor, optional
        Where samples run; in this process when omitted.
    options : Options, optional
    ahead : int, optional
        Samples in flight on the executor (a batch in flight counts its
        samples); by default two batches per worker.
    expect : int, optional
        How many samples the caller expects to use (``generate`` passes the
        layouts it wants): those come in batches of near-equal size, at least
        one per worker, at most ``options.batch`` each; the samples after
        them in batches of 1, 2, 4, ... (without ``expect``, from the start),
        so a run that has what it wants when the expected samples are done
        leaves few samples running. What is yielded does not depend on it.

    Yields
    ------
    (int, Layout)
        The sample index and its layout; ``layout.report`` says whether it
        passed and, if not, why.
    """
    opts = options or Options()
    plan = load_plan(plan)
    indices = itertools.count(start) if stop is None else iter(range(start, stop))
    workers = executor_workers(executor)
    chunks = _chunks(indices, opts.batch, max(0, int(expect or 0)), workers)

    def seeds(chunk: list[int]) -> list[int]:
        return [sample_seed(seed, k) for k in chunk]

    if executor is None:
        for chunk in chunks:
            yield from zip(chunk, _samples(plan, seeds(chunk), opts), strict=True)
        return
    # by default two batches per worker: one running, one waiting
    most = 2 * workers if ahead is None else None  # batches in flight
    ahead = None if ahead is None else max(1, int(ahead))  # or samples in flight
    pending: collections.deque = collections.deque()
    in_flight = 0

    def room() -> bool:
        return len(pending) < most if most is not None else in_flight < ahead

    try:
        for chunk in chunks:
            pending.append((chunk, executor.submit(_samples, plan, seeds(chunk), opts)))
            in_flight += len(chunk)
            if not room():
                break
        while pending:
            chunk, future = pending.popleft()
            layouts = future.result()
            in_flight -= len(chunk)
            while room():
                nxt = next(chunks, None)
                if nxt is None:
                    break
                pending.append((nxt, executor.submit(_samples, plan, seeds(nxt), opts)))
                in_flight += len(nxt)
            yield from zip(chunk, layouts, strict=True)
    finally:
        for _, future in pending:
            future.cancel()


def generate(
    plan: Plan | str | dict[str, Any],
    n: int,
    *,
    seed: int = 0,
    executor: Executor | None = None,
    max_attempts: int | None = None,
    distinct_tol: float = 0.05,
    progress: bool = False,
    on_layout: Callable[[Layout], Any] | None = None,
    options: Options | None = None,
    **kwargs: Any,
) -> Generation:
    """Realise one plan as ``n`` valid, distinct layouts.

    Parameters
    ----------
    plan : Plan, path, JSON text, dict or bundled plan name
    n : int
        Layouts wanted.
    seed : int
        Seed of the run; sample ``k`` uses :func:`sample_seed(seed, k) <sample_seed>`.
    executor : concurrent.futures.Executor, optional
        Where samples run (``ProcessPoolExecutor``, a Dask or Ray executor);
        in this process when omitted. The result is the same either way.
    max_attempts : int, optional
        Sample budget; defaults to ``max(4 n, n + 20)``. The run stops early
        once ``n`` layouts are accepted.
    distinct_tol : float
        A valid sample whose every object lies within this many metres of an
        accepted layout's is a duplicate and is not accepted.
    progress : bool
        Show a progress bar (tqdm).
    on_layout : callable, optional
        Called with each accepted layout as soon as it is accepted (in
        order), e.g. to write it to disk while the run goes on.
    options : Options, optional
        Or its fields as keyword arguments (``relations=False``, ...); given
        both, the keyword arguments replace those fields of ``options``.

    Returns
    -------
    Generation
        ``len(result) <= n``; ``result.rejected`` says why the others failed,
        ``result.why`` the dominant cause in one line.

    Warns
    -----
    FeasibilityWarning
        Before sampling, when :func:`forcelayout.diagnose.feasibility` finds
        the plan infeasible (sampling goes on; ``result.feasibility`` keeps
        the estimate).
    FewLayoutsWarning
        After the run, when fewer than ``n`` layouts were accepted: accepted
        of attempted, the dominant cause and what to try.
    """
    if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 0:
        raise ValueError(f"n must be a whole number >= 0, got {n!r}")
    t0 = time.perf_counter()  # the run's seconds count its set-up (loading, preparing the plan)
    opts = _options(options, kwargs, "generate",
                    ("seed", "executor", "max_attempts", "distinct_tol", "progress", "on_layout",
                     "options"))
    plan = load_plan(plan)
    from forcelayout.pipeline import prepare

    prepare(plan)  # plan-level problems surface before any sample runs
    if max_attempts is not None and (isinstance(max_attempts, bool)
                                     or not isinstance(max_attempts, int | np.integer)):
        raise ValueError(f"max_attempts must be a whole number >= 0, got {max_attempts!r}")
    budget = max(4 * n, n + 20) if max_attempts is None else int(max_attempts)
    if budget < 0:
        raise ValueError(f"max_attempts must be >= 0, got {max_attempts}")
    feas = plan_feasibility(plan, opts)
    if not feas.ok:
        warnings.warn(FeasibilityWarning.of(plan.name, feas), stacklevel=2)
    accepted: list[Layout] = []
    reports: list[SampleReport] = []
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=n, desc=f"{plan.name}", unit="layout")
    seen = DistinctLayouts(distinct_tol)
    samples = iter_samples(plan, seed, stop=budget if n > 0 else 0, executor=executor,
                           options=opts, expect=n)
    # with the default budget, a run that has accepted nothing after a quarter of it gives
    # up where more samples are unlikely to help (an impossible rule, an infeasible plan)
    give_up = max(_GIVE_UP_AFTER, budget // 4) if max_attempts is None else None
    stopped = None
    try:
        for _, lay in samples:
            reports.append(lay.report)
            if not lay.report.valid:
                if give_up is not None and not accepted and len(reports) >= give_up \
                        and len(reports) < budget and Generation(
                            plan, int(seed), [], reports, 0.0, wanted=n,
                            feasibility=feas)._hopeless():
                    stopped = budget
                    break
                continue
            if seen.add_if_new(lay):
                accepted.append(lay)
                if on_layout is not None:
                    on_layout(lay)
                if bar is not None:
                    bar.update(1)
                if len(accepted) >= n:
                    break
            else:
                lay.report.failures.append(DistinctLayouts.FAILURE)
    finally:
        samples.close()  # samples still running are cancelled, not waited for
        if bar is not None:
            bar.close()
    result = Generation(plan, int(seed), accepted, reports, time.perf_counter() - t0,
                        wanted=n, feasibility=feas, stopped_early=stopped)
    if len(accepted) < n:
        result.why = result._cause()
        warnings.warn(FewLayoutsWarning(result.hint() or result.why, accepted=len(accepted),
                                        wanted=n, attempted=len(reports), why=result.why),
                      stacklevel=2)
    return result


def plan_feasibility(plan: Plan, opts: Options | None = None) -> Feasibility:
    """:func:`~forcelayout.diagnose.feasibility` of the plan as ``opts`` sample and judge it.

    Uses the thresholds the checks will use (``opts.check_kwargs``), no free
    floor when the checks are off, and the plan without decor when
    ``opts.decor`` is False.
    """
    opts = opts or Options()
    kw = {k: opts.check_kwargs[k] for k in ("agent_radius", "min_free_fraction")
          if k in opts.check_kwargs}
    if not opts.check:  # no navigability check: the free floor asks for nothing
        kw["min_free_fraction"] = 0.0
    access = bool(opts.check and opts.check_kwargs.get("access_clearance", False))
    return feasibility(_plan_for(plan, opts), access=access, **kw)


_REPAIR_KINDS = ("resettled", "moved elsewhere", "started over")


def repair_counts(repairs: Iterable[Sequence[str]], key: str = "samples") -> dict[str, int]:
    """How many of the samples whose repair notes (:attr:`SampleReport.repairs`) are given
    were repaired (under ``key``), and how many took each kind of repair step
    (``"resettled"``, ``"moved elsewhere"``, ``"started over"``), a sample once under each.
    """
    notes = [list(r) for r in repairs]
    out = {key: sum(bool(r) for r in notes)}
    for kind in _REPAIR_KINDS:
        out[kind] = sum(any(note.startswith(kind) for note in r) for r in notes)
    return out
