"""The V loop: generate until ``n`` scenes pass the checks AND a plausibility judge.

The method's validation stage (paper §III-C) is a two-stage filter: every
sample first meets the cheap deterministic checks (collisions, room bounds,
doors, free floor, paths; :func:`forcelayout.validate.check_layout`) and the
distinctness test of :func:`forcelayout.generate`; only the survivors go to
the expensive judge. The loop stops once ``n`` scenes are accepted or the
sample budget is spent, and records for every sample what happened to it.

A **judge** is any callable ``judge(layout) -> verdict``: a vision-language
model (:class:`forcelayout.validate.vlm.VLMJudge`, extra ``vlm``), a
CLIP-score threshold, a hand-written rule, a person at a prompt. Its answer
may be a :class:`Verdict`, a ``bool`` or a mapping with the fields of a
verdict. A judge that raises, returns something else, or (with
``judge_timeout``) takes too long leaves the scene **unjudged**, with the
reason; the loop goes on, and stops early only after
``max_unjudged_in_a_row`` such failures in a row (an endpoint that is down).

This module needs no extra.

Examples
--------
>>> from forcelayout.validate import generate_validated
>>> def no_desk_by_the_door(layout):
...     return layout.poses["desk"].y > 1.0     # a bool is a verdict
>>> run = generate_validated("home_office", 2, 20, judge=no_desk_by_the_door)  # doctest: +SKIP
>>> run.summary()["acceptance_rate"]                                       # doctest: +SKIP
"""

from __future__ import annotations

import importlib
import threading
import time
import warnings
from collections.abc import Callable, Iterator, Mapping
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from forcelayout._text import one_line
from forcelayout.diagnose import FewLayoutsWarning, dominant_cause
from forcelayout.layout import Layout
from forcelayout.options import Options
from forcelayout.plan import Plan
from forcelayout.views import Summary

__all__ = [
    "ObjectComplaint",
    "Verdict",
    "Judge",
    "Judgement",
    "judge_layout",
    "load_judge",
    "judge_name",
    "Candidate",
    "ValidatedGeneration",
    "generate_validated",
]

#: Longest reason kept from a judge, characters, "..." included (verdicts are data from
#: outside).
MAX_REASON_CHARS = 500

#: A plausibility judge: a layout in, a verdict (:class:`Verdict`, bool or mapping) out.
Judge = Callable[[Layout], Any]


class ObjectComplaint(BaseModel):
    """What a judge finds wrong with one object of the scene."""

    model_config = ConfigDict(extra="ignore")

    object: str = Field(description="Id of the object, as labelled in the pictures.")
    complaint: str = Field(description="What is implausible about it, in one sentence.")


class Verdict(BaseModel):
    """A judge's answer: is the scene plausible, why, and which objects are wrong.

    This is also the JSON Schema a vision-language model is asked to follow.
    """

    model_config = ConfigDict(extra="ignore")

    plausible: bool = Field(description="True if a person would find this room's furniture "
                                        "arrangement functional, logical and realistic.")
    reasons: list[str] = Field(default_factory=list,
                               description="Short reasons for the verdict.")
    objects: list[ObjectComplaint] = Field(
        default_factory=list, description="Objects that are implausibly placed; empty if none.")

    def reason(self) -> str:
        """The verdict's reasons and complaints in one line."""
        parts = [" ".join(str(r).split()) for r in self.reasons if str(r).strip()]
        parts += [f"{c.object}: {' '.join(c.complaint.split())}" for c in self.objects]
        text = "; ".join(parts) or ("plausible" if self.plausible else "the judge said no")
        return one_line(text, MAX_REASON_CHARS)


@dataclass
class Judgement:
    """The outcome of asking a judge about one scene.

    Attributes
    ----------
    status : {"plausible", "implausible", "unjudged"}
    verdict : Verdict or None
        None when unjudged.
    reason : str
        One line: the verdict's reasons, or why there is no verdict.
    seconds : float
        Wall time of the judge's call.
    """

    status: Literal["plausible", "implausible", "unjudged"]
    verdict: Verdict | None
    reason: str
    seconds: float = 0.0

    @property
    def accepted(self) -> bool:
        """True when the judge found the scene plausible."""
        return self.status == "plausible"


def _as_verdict(value: Any) -> Verdict:
    if isinstance(value, Verdict):
        return value
    if isinstance(value, bool | np.bool_):
        return Verdict(plausible=bool(value))
    if isinstance(value, Mapping):
        try:
            return Verdict.model_validate(dict(value))
        except ValidationError as e:
            problems = "; ".join(f"{'.'.join(map(str, err['loc'])) or '(verdict)'}: "
                                 f"{err['msg']}" for err in e.errors())
            raise TypeError(f"the judge's answer is not a verdict: {problems}") from None
    raise TypeError(f"the judge returned {type(value).__name__}, not a verdict (give a Verdict, "
                    "a bool or a dict with 'plausible')")


def _call(judge: Judge, layout: Layout, timeout: float | None) -> Any:
    if timeout is None:
        return judge(layout)
    box: dict[str, Any] = {}

    def run() -> None:
        try:
            box["value"] = judge(layout)
        except BaseException as e:  # handed to the caller's thread
            box["error"] = e

    worker = threading.Thread(target=run, name="forcelayout-judge", daemon=True)
    worker.start()
    worker.join(timeout)
    if worker.is_alive():  # left to finish on its own; its answer is ignored
        raise TimeoutError(f"no verdict within {timeout:g} s")
    if "error" in box:
        raise box["error"]
    return box.get("value")


def judge_layout(judge: Judge, layout: Layout, *, timeout: float | None = None) -> Judgement:
    """Ask ``judge`` about ``layout``; never raises for a failing judge.

    Parameters
    ----------
    judge : callable
        ``judge(layout)`` returning a :class:`Verdict`, a bool or a mapping.
    layout : Layout
    timeout : float, optional
        Seconds to wait for the answer; the call runs in a helper thread,
        which is left behind (not killed) when it takes longer. A VLM judge
        has its own request timeout, so it needs none.

    Returns
    -------
    Judgement
        ``"unjudged"`` with the reason when the judge raised (any
        ``Exception``), returned no verdict, or timed out.
    """
    t0 = time.perf_counter()
    try:
        verdict = _as_verdict(_call(judge, layout, timeout))
    except Exception as e:  # the judge's failure is recorded, never raised
        message = str(e) or type(e).__name__
        if not isinstance(e, TimeoutError | TypeError):
            message = f"{type(e).__name__}: {message}"
        return Judgement("unjudged", None, one_line(str(message), MAX_REASON_CHARS),
                         time.perf_counter() - t0)
    status: Literal["plausible", "implausible"] = (
        "plausible" if verdict.plausible else "implausible")
    return Judgement(status, verdict, verdict.reason(), time.perf_counter() - t0)


def judge_name(judge: Judge) -> str:
    """A stable name of a judge, for manifests and summaries.

    The judge's ``name`` attribute when it has one (a :class:`VLMJudge` says
    ``"vlm:<model>"``), else ``module:qualname`` of the function or class.
    """
    name = getattr(judge, "name", None)
    if isinstance(name, str) and name:
        return name
    target = judge if hasattr(judge, "__qualname__") else type(judge)
    return f"{getattr(target, '__module__', '?')}:{getattr(target, '__qualname__', '?')}"


def load_judge(spec: str) -> Judge:
    """The judge named by ``"module:attribute"`` (a class is instantiated without arguments).

    Parameters
    ----------
    spec : str
        E.g. ``"mypkg.judges:clip_judge"``.

    Raises
    ------
    ValueError
        When ``spec`` is not ``module:attribute``, the module or attribute
        does not exist, or it is not callable.
    """
    module, sep, attr = spec.partition(":")
    if not sep or not module or not attr:
        raise ValueError(f"judge {spec!r}: give 'module:callable', e.g. 'mypkg.judges:clip_judge'")
    try:
        obj: Any = importlib.import_module(module)
    except ImportError as e:
        raise ValueError(f"judge {spec!r}: cannot import module {module!r} ({e})") from None
    for part in attr.split("."):
        if not hasattr(obj, part):
            raise ValueError(f"judge {spec!r}: module {module!r} has no {attr!r}")
        obj = getattr(obj, part)
    if isinstance(obj, type):
        obj = obj()
    if not callable(obj):
        raise ValueError(f"judge {spec!r} is not callable")
    return obj


# ----------------------------------------------------------------------------- the loop

#: What happened to a sample in the V loop.
Status = Literal["accepted", "invalid", "duplicate", "implausible", "unjudged"]


@dataclass
class Candidate:
    """One sample of a V loop and what happened to it.

    Attributes
    ----------
    index : int
        Sample index in the run (its seed is ``sample_seed(seed, index)``).
    layout : Layout
    status : {"accepted", "invalid", "duplicate", "implausible", "unjudged"}
        ``invalid``: failed the deterministic checks; ``duplicate``: too
        close to an accepted layout; ``implausible``: the judge said no;
        ``unjudged``: the judge gave no verdict.
    reason : str or None
        Why it was not accepted, one line.
    verdict : Verdict or None
        The judge's verdict, when it gave one.
    judge_seconds : float
        Time the judge took on it (0 when not judged).
    """

    index: int
    layout: Layout
    status: Status
    reason: str | None = None
    verdict: Verdict | None = None
    judge_seconds: float = 0.0


@dataclass
class ValidatedGeneration:
    """The outcome of :func:`generate_validated`.

    Iterating, ``len()`` and indexing go over the accepted layouts.

    Attributes
    ----------
    plan : Plan
    seed : int
    wanted : int
    layouts : list of Layout
        Accepted layouts (valid, distinct, plausible), in sample order.
    candidates : list of Candidate
        Every sample drawn, in sample order.
    seconds : float
        Wall time of the run.
    judge : str
        :func:`judge_name` of the judge.
    why : str or None
        When fewer than ``wanted`` were accepted, the dominant cause in one line.
    """

    plan: Plan
    seed: int
    wanted: int
    layouts: list[Layout] = field(default_factory=list)
    candidates: list[Candidate] = field(default_factory=list)
    seconds: float = 0.0
    judge: str = ""
    why: str | None = None

    def __iter__(self) -> Iterator[Layout]:
        return iter(self.layouts)

    def __len__(self) -> int:
        return len(self.layouts)

    def __getitem__(self, k: int) -> Layout:
        return self.layouts[k]

    def _count(self, *statuses: str) -> int:
        return sum(c.status in statuses for c in self.candidates)

    @property
    def attempted(self) -> int:
        """Samples drawn."""
        return len(self.candidates)

    @property
    def valid(self) -> int:
        """Samples that passed the deterministic checks."""
        return self.attempted - self._count("invalid")

    @property
    def judged(self) -> int:
        """Samples the judge gave a verdict on (accepted or implausible)."""
        return self._count("accepted", "implausible")

    @property
    def unjudged(self) -> int:
        """Samples sent to the judge that got no verdict."""
        return self._count("unjudged")

    @property
    def acceptance_rate(self) -> float:
        """Accepted / judged: the judge's acceptance rate (the paper's "Plausibility (VLM)")."""
        return len(self.layouts) / self.judged if self.judged else float("nan")

    @property
    def validity_rate(self) -> float:
        """Samples passing the checks / samples drawn (the paper's "Validity")."""
        return self.valid / self.attempted if self.attempted else float("nan")

    @property
    def judge_seconds(self) -> float:
        """Time spent in the judge, over all samples."""
        return float(sum(c.judge_seconds for c in self.candidates))

    @property
    def seconds_per_accepted(self) -> float:
        """Wall time per accepted scene (``inf`` when none was accepted)."""
        return self.seconds / len(self.layouts) if self.layouts else float("inf")

    @property
    def verdicts(self) -> list[Verdict]:
        """The judge's verdicts on the accepted layouts, in order."""
        return [c.verdict for c in self.candidates if c.status == "accepted" and c.verdict]

    @property
    def rejections(self) -> list[Candidate]:
        """The samples that were not accepted, each with its status and reason."""
        return [c for c in self.candidates if c.status != "accepted"]

    def summary(self) -> Summary:
        """Counts, rates, timing and the reasons samples were turned down.

        ``rejection_reasons`` counts statuses (``invalid``, ``duplicate``,
        ``implausible``, ``unjudged``); ``failure_reasons`` counts the
        checks and the judge's verdicts as in :meth:`Generation.summary
        <forcelayout.Generation.summary>`.
        """
        statuses: dict[str, int] = {}
        reasons: dict[str, int] = {}
        for c in self.rejections:
            statuses[c.status] = statuses.get(c.status, 0) + 1
            for f in dict.fromkeys(f.split(":")[0] for f in c.layout.report.failures):
                reasons[f] = reasons.get(f, 0) + 1
        return Summary({
            "plan": self.plan.name,
            "seed": self.seed,
            "judge": self.judge,
            "wanted": self.wanted,
            "accepted": len(self.layouts),
            "attempted": self.attempted,
            "valid": self.valid,
            "judged": self.judged,
            "unjudged": self.unjudged,
            "validity_rate": self.validity_rate,
            "acceptance_rate": self.acceptance_rate,
            "seconds": self.seconds,
            "judge_seconds": self.judge_seconds,
            "seconds_per_accepted": self.seconds_per_accepted,
            "why": self.why,
            "rejection_reasons": dict(sorted(statuses.items(), key=lambda kv: -kv[1])),
            "failure_reasons": dict(sorted(reasons.items(), key=lambda kv: -kv[1])),
        })

    def __repr__(self) -> str:
        return (f"<ValidatedGeneration plan={self.plan.name!r} accepted={len(self)}/{self.wanted}"
                f" attempted={self.attempted} judged={self.judged} unjudged={self.unjudged} "
                f"seconds={self.seconds:.2f}>")


def generate_validated(
    plan: Plan | str | dict[str, Any],
    n_accepted: int,
    max_attempts: int | None = None,
    *,
    judge: Judge,
    seed: int = 0,
    executor: Executor | None = None,
    distinct_tol: float = 0.05,
    judge_timeout: float | None = None,
    max_unjudged_in_a_row: int | None = 5,
    on_layout: Callable[[Layout, Verdict], Any] | None = None,
    progress: bool = False,
    options: Options | None = None,
    **kwargs: Any,
) -> ValidatedGeneration:
    """The V loop: samples until ``n_accepted`` pass the checks and the judge, or the budget ends.

    Samples are drawn as by :func:`forcelayout.generate` (sample ``k`` from
    ``sample_seed(seed, k)``, on any executor, in index order); each one
    that passes the deterministic checks and is not within ``distinct_tol``
    of an accepted layout goes to ``judge``, in this process, one at a time.
    With a deterministic judge the result does not depend on the executor.

    Parameters
    ----------
    plan : Plan, path, JSON text, dict or bundled plan name
    n_accepted : int
        Scenes wanted.
    max_attempts : int, optional
        Sample budget (samples drawn, judged or not); default
        ``max(4 n, n + 20)``.
    judge : callable
        ``judge(layout)`` -> :class:`Verdict`, bool or mapping (see the module).
    seed : int
    executor : concurrent.futures.Executor, optional
        Where samples are simulated (the judge always runs here).
    distinct_tol : float
        As in :func:`forcelayout.generate`; only accepted layouts count.
    judge_timeout : float, optional
        Seconds to wait for each verdict (see :func:`judge_layout`).
    max_unjudged_in_a_row : int or None
        Stop early after this many scenes in a row got no verdict (the
        judge's endpoint is down); None never stops early.
    on_layout : callable, optional
        Called ``on_layout(layout, verdict)`` with each accepted scene as
        soon as it is accepted.
    progress : bool
        Show a progress bar over accepted scenes (tqdm).
    options : Options, optional
        Or its fields as keyword arguments.

    Returns
    -------
    ValidatedGeneration
        Accepted layouts, every sample's :class:`Candidate`, acceptance
        rate, seconds per accepted scene and :meth:`~ValidatedGeneration.summary`.

    Warns
    -----
    FewLayoutsWarning
        When fewer than ``n_accepted`` scenes were accepted.
    """
    from forcelayout.pipeline import prepare
    from forcelayout.sampling import DistinctLayouts, _options, iter_samples
    from forcelayout.sources import load_plan

    if isinstance(n_accepted, bool) or not isinstance(n_accepted, int | np.integer) \
            or n_accepted < 0:
        raise ValueError(f"n_accepted must be a whole number >= 0, got {n_accepted!r}")
    if max_attempts is not None and (isinstance(max_attempts, bool) or not isinstance(
            max_attempts, int | np.integer) or max_attempts < 0):
        raise ValueError(f"max_attempts must be a whole number >= 0, got {max_attempts!r}")
    if not callable(judge):
        raise TypeError(f"judge must be callable (layout -> verdict), got {type(judge).__name__}")
    if judge_timeout is not None and not judge_timeout > 0:
        raise ValueError(f"judge_timeout must be a positive number of seconds, got "
                         f"{judge_timeout!r}")
    opts = _options(options, kwargs)
    plan = load_plan(plan)
    prepare(plan)  # plan-level problems surface before any sample runs
    n = int(n_accepted)
    budget = max(4 * n, n + 20) if max_attempts is None else int(max_attempts)
    result = ValidatedGeneration(plan, int(seed), n, judge=judge_name(judge))
    seen = DistinctLayouts(distinct_tol)
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=n, desc=f"{plan.name} (judged)", unit="scene")
    t0 = time.perf_counter()
    failing_in_a_row = 0
    samples = iter_samples(plan, seed, stop=budget if n > 0 else 0, executor=executor,
                           options=opts, expect=n)
    try:
        for k, lay in samples:
            report = lay.report
            if not report.valid:
                reason = "; ".join(report.failures) or "failed the checks"
                result.candidates.append(Candidate(k, lay, "invalid",
                                                  one_line(str(reason), MAX_REASON_CHARS)))
                continue
            if not seen.is_new(lay):
                report.failures.append(DistinctLayouts.FAILURE)
                result.candidates.append(Candidate(k, lay, "duplicate", report.failures[-1]))
                continue
            j = judge_layout(judge, lay, timeout=judge_timeout)
            if j.accepted:
                failing_in_a_row = 0
                seen.add(lay)
                result.layouts.append(lay)
                result.candidates.append(Candidate(k, lay, "accepted", None, j.verdict,
                                                   j.seconds))
                if on_layout is not None:
                    on_layout(lay, j.verdict)  # type: ignore[arg-type]
                if bar is not None:
                    bar.update(1)
                if len(result.layouts) >= n:
                    break
                continue
            report.failures.append(f"{j.status}: {j.reason}")
            result.candidates.append(Candidate(k, lay, j.status, j.reason, j.verdict,
                                               j.seconds))
            if j.status == "unjudged":
                failing_in_a_row += 1
                if max_unjudged_in_a_row is not None and failing_in_a_row >= \
                        max_unjudged_in_a_row:
                    result.why = (f"the judge gave no verdict {failing_in_a_row} times in a "
                                  f"row (last: {j.reason}); stopped early")
                    break
            else:
                failing_in_a_row = 0
    finally:
        samples.close()
        if bar is not None:
            bar.close()
    result.seconds = time.perf_counter() - t0
    if len(result.layouts) < n:
        if result.why is None:
            tail = [c.layout.report for c in result.candidates]
            result.why = (dominant_cause(tail) if tail else None) or \
                f"the budget of {budget} samples ran out"
        warnings.warn(FewLayoutsWarning(
            f"only {len(result.layouts)} of {n} scenes of plan {plan.name!r} passed the checks "
            f"and the judge in {result.attempted} samples: {result.why}",
            accepted=len(result.layouts), wanted=n, attempted=result.attempted, why=result.why),
            stacklevel=2)
    return result
