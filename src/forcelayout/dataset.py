"""Datasets: many layouts of many plans written to a folder, resumable, byte for byte reproducible.

:func:`build_dataset` realises each plan as ``n`` valid, distinct layouts
(the layouts :func:`forcelayout.generate` would accept, in the same order)
and writes each one as soon as it is accepted. The folder::

    DIR/dataset.json                what the dataset is: plans (with hashes), n, seed,
                                    pictures, exports, options, library version
    DIR/index.jsonl                 one JSON line per finished layout
    DIR/run.log                     one JSON line per run event, with timings
    DIR/<plan>/plan.json            the plan
    DIR/<plan>/<plan>_<k>.json      layout k (:func:`layout_stem`: k zero-padded to n's width)
    DIR/<plan>/<plan>_<k>.png       its picture (or .svg; none with pictures="none")
    DIR/<plan>/<plan>_<k>.<ext>     its exports (``forcelayout.export.write_exports``)
    DIR/<plan>/summary.json         written when the plan is done: counts, failure reasons

Every file is written to a temporary name in the same folder and renamed
into place, and a layout counts as finished only once its line is in the
index, written after all its files. Layout ``k`` of a plan is the ``k``-th
accepted sample in sample order, so a run that is killed at any moment and
started again with the same arguments finishes with the same bytes as a run
that was never stopped (``run.log`` aside, which keeps the timings). The
index is rewritten in plan and layout order at the end of every run.

Pictures and exports are made where the samples run (in the workers of the
executor); the process that calls :func:`build_dataset` only decides which
samples are accepted and keeps the index.

With ``judge=`` (any plausibility judge of :mod:`forcelayout.validate.loop`,
e.g. :class:`forcelayout.validate.vlm.VLMJudge`), the layouts that pass the
checks and the distinctness test are judged, in the calling process, before
they are written: a layout the judge rejects or leaves unjudged is not
written, and counts under ``implausible`` or ``unjudged`` in its plan's
``failure_reasons``. The index line of a judged layout holds the verdict
(``"judge"``) and ``dataset.json`` names the judge, so a folder is resumed only
by the same judge; with a deterministic judge a resumed run ends with the
same bytes as one that never stopped.
"""

from __future__ import annotations

import collections
import functools
import hashlib
import json
import os
import shutil
import sys
import time
import warnings
from collections.abc import Callable, Iterable, Iterator, Sequence
from concurrent.futures import Executor, Future
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from forcelayout._atomic import TMP_MARK, atomic_path, write_text
from forcelayout.diagnose import FeasibilityWarning, dominant_cause
from forcelayout.errors import InputError
from forcelayout.layout import Layout, SampleReport
from forcelayout.options import Options
from forcelayout.plan import Plan
from forcelayout.sampling import (
    DistinctLayouts,
    executor_workers,
    iter_samples,
    plan_feasibility,
    repair_counts,
)
from forcelayout.sources import load_plan
from forcelayout.validate.loop import Judge, judge_layout, judge_name

__all__ = [
    "PICTURE_FORMATS",
    "DatasetError",
    "PlanOutcome",
    "DatasetResult",
    "plan_sources",
    "layout_stem",
    "build_dataset",
]

#: Picture formats of :func:`build_dataset` (``"none"`` draws none).
PICTURE_FORMATS = ("png", "svg", "none")

#: Written into ``dataset.json``; a folder of another format is never resumed.
FORMAT = "forcelayout-dataset/1"

MANIFEST, INDEX, RUN_LOG, SUMMARY = "dataset.json", "index.jsonl", "run.log", "summary.json"


class DatasetError(InputError, ValueError):
    """The dataset cannot be made as asked (a folder of another run, clashing plan names, ...)."""


@dataclass
class PlanOutcome:
    """How one plan of a dataset went.

    Attributes
    ----------
    name : str
        The plan's name (also its folder).
    wanted, accepted, attempted : int
        Layouts asked for, layouts finished, samples drawn (in all runs).
    resumed : int
        Layouts that were already finished when this run started.
    why : str or None
        When fewer than ``wanted`` were accepted, the dominant cause in one line.
    repaired : dict of str to int
        The finished layouts whose samples were repaired (``"layouts"``) and how many took
        each kind of repair step (:func:`forcelayout.sampling.repair_counts`), in all runs.
    """

    name: str
    wanted: int
    accepted: int = 0
    attempted: int = 0
    resumed: int = 0
    why: str | None = None
    repaired: dict[str, int] = field(default_factory=dict)


@dataclass
class DatasetResult:
    """The outcome of :func:`build_dataset`.

    Attributes
    ----------
    out : Path
        The dataset's folder.
    plans : list of PlanOutcome
        One per plan, in the order given.
    seconds : float
        Wall time of this run.
    """

    out: Path
    plans: list[PlanOutcome] = field(default_factory=list)
    seconds: float = 0.0

    @property
    def accepted(self) -> int:
        """Layouts finished, over all plans."""
        return sum(p.accepted for p in self.plans)

    @property
    def wanted(self) -> int:
        """Layouts asked for, over all plans."""
        return sum(p.wanted for p in self.plans)

    @property
    def resumed(self) -> int:
        """Layouts that were already finished when this run started."""
        return sum(p.resumed for p in self.plans)

    @property
    def complete(self) -> bool:
        """True when every plan has all the layouts asked for."""
        return all(p.accepted >= p.wanted for p in self.plans)


# ----------------------------------------------------------------------------- sources


def plan_sources(sources: Iterable[Plan | str | Path | dict[str, Any]]) -> list[Plan]:
    """The plans named by ``sources``: plans, plan files, folders of plan files, bundled names.

    A folder stands for the ``*.json`` files directly in it, in name order.

    Raises
    ------
    DatasetError
        When no plan is given, a folder holds no plan file, or two plans share
        a name (each plan's layouts go to a folder of its name).
    """
    plans: list[Plan] = []
    origin: dict[str, str] = {}
    for source in sources:
        if isinstance(source, str | Path) and Path(source).is_dir():
            files = sorted(Path(source).glob("*.json"))
            if not files:
                raise DatasetError(f"folder {str(source)!r} holds no plan file (*.json)")
            items: list[tuple[str, Any]] = [(str(f), f) for f in files]
        else:
            label = source.name if isinstance(source, Plan) else (
                "a dict" if isinstance(source, dict) else str(source))
            items = [(label, source)]
        for label, item in items:
            plan = load_plan(item)
            if plan.name in origin:
                raise DatasetError(
                    f"two plans are named {plan.name!r} ({origin[plan.name]} and {label}); "
                    "each plan's layouts go to a folder of its name: give one a different "
                    "\"name\"")
            origin[plan.name] = label
            plans.append(plan)
    if not plans:
        raise DatasetError("no plan given: name plan files, folders of plans or bundled plans")
    return plans


# ----------------------------------------------------------------------------- files


def _json(data: Any) -> str:
    return json.dumps(data, indent=2, sort_keys=True) + "\n"


def layout_stem(plan_name: str, k: int, n: int) -> str:
    """The file name, without suffix, of layout ``k`` of ``n`` of a plan in a dataset.

    ``k`` is zero-padded to the width of ``n - 1`` (at least 3 digits), so the
    names of one run sort in layout order.

    Examples
    --------
    >>> layout_stem("bedroom", 7, 1000), layout_stem("bedroom", 7, 1001)
    ('bedroom_007', 'bedroom_0007')
    """
    return f"{plan_name}_{k:0{max(3, len(str(max(n - 1, 0))))}d}"


def _plan_hash(plan: Plan) -> str:
    return hashlib.sha256(plan.to_json().encode("utf-8")).hexdigest()


@dataclass(frozen=True)
class _Files:
    """What is written for each layout besides its JSON (sent to the workers)."""

    pictures: str = "png"
    exports: tuple[str, ...] = ()
    movable: tuple[str, ...] = ()
    assets: str | None = None  # an asset library folder: exports place its meshes


@functools.lru_cache(maxsize=4)
def _asset_library(folder: str) -> Any:
    from forcelayout.grounding import AssetLibrary

    return AssetLibrary.load(folder)


def _write_layout(layout: Layout, folder: str, stem: str, what: _Files) -> dict[str, Any]:
    """Write one layout's files (runs in a worker); returns its index entry's file part."""
    from forcelayout.validate import check_layout

    where = Path(folder)
    files: list[str] = []
    if what.pictures != "none":
        pic = where / f"{stem}.{what.pictures}"
        with atomic_path(pic) as tmp:
            layout.picture(tmp)
        files.append(pic.name)
    if what.exports:
        from forcelayout.export import write_exports

        meshes = None
        if what.assets is not None:
            from forcelayout.grounding import scene_assets

            meshes = scene_assets(layout.plan, _asset_library(what.assets))
        written = write_exports(layout, where / stem, what.exports, movable=what.movable,
                                assets=meshes)
        files.extend(Path(p).name for p in written)
    main = where / f"{stem}.json"
    write_text(main, layout.to_json())
    files.insert(0, main.name)
    report = check_layout(layout)
    return {"files": files,
            "checks": {"passed": report.ok, "free_fraction": round(report.free_fraction, 4),
                       "navigable_fraction": round(report.navigable_fraction, 4)}}


def _clear(out: Path) -> None:
    for child in out.iterdir():
        if child.is_dir() and not child.is_symlink():
            shutil.rmtree(child)
        else:
            child.unlink()


def _read_index(out: Path) -> list[dict[str, Any]]:
    """The finished layouts' index lines (a torn last line, from a kill, is left out)."""
    path = out / INDEX
    if not path.exists():
        return []
    entries = []
    for line in path.read_text(encoding="utf-8").splitlines():
        try:
            entry = json.loads(line)
        except json.JSONDecodeError:
            continue
        if isinstance(entry, dict) and {"plan", "layout", "sample"} <= set(entry):
            entries.append(entry)
    return entries


class _Log:
    """``run.log``: one JSON line per event, with timings (not part of the dataset proper)."""

    def __init__(self, path: Path):
        self.path = path
        self.t0 = time.perf_counter()

    def __call__(self, event: str, **data: Any) -> None:
        data = {"event": event, "time": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
                "elapsed_s": round(time.perf_counter() - self.t0, 3), **data}
        with self.path.open("a", encoding="utf-8") as f:
            f.write(json.dumps(data) + "\n")


# ----------------------------------------------------------------------------- the run


def _manifest(plans: list[Plan], n: int, seed: int, budget: int, pictures: str,
              exports: tuple[str, ...], movable: tuple[str, ...], opts: Options,
              distinct_tol: float, judge: str | None = None) -> dict[str, Any]:
    from forcelayout import __version__

    extra = {"judge": judge} if judge is not None else {}  # absent: folders of earlier runs
    return {**extra,
        "format": FORMAT,
        "forcelayout": __version__,
        "n": n,
        "seed": seed,
        "max_attempts": budget,
        "distinct_tol": distinct_tol,
        "pictures": pictures,
        "exports": list(exports),
        "movable": list(movable),
        "options": json.loads(json.dumps(asdict(opts), default=str)),
        "plans": [{"name": p.name, "sha256": _plan_hash(p)} for p in plans],
    }


def _differences(old: dict[str, Any], new: dict[str, Any]) -> list[str]:
    keys = sorted(set(old) | set(new))
    out = []
    for k in keys:
        if old.get(k) != new.get(k):
            if k == "plans":
                out.append("plans (names or contents)")
            else:
                out.append(f"{k} ({old.get(k)!r} there, {new.get(k)!r} now)")
    return out


def _prepare_folder(out: Path, manifest: dict[str, Any], overwrite: bool) -> None:
    """Refuse a folder holding another run's files; clear it with ``overwrite``."""
    if out.exists() and not out.is_dir():
        raise DatasetError(f"--out {str(out)!r} is a file, not a folder")
    out.mkdir(parents=True, exist_ok=True)
    if not any(out.iterdir()):
        return
    if overwrite:
        _clear(out)
        return
    try:
        old = json.loads((out / MANIFEST).read_text(encoding="utf-8"))
    except (OSError, json.JSONDecodeError):
        old = None
    if not isinstance(old, dict) or old.get("format") != FORMAT:
        raise DatasetError(f"folder {str(out)!r} holds files that are not a forcelayout dataset; "
                           "give an empty or new folder, or --overwrite to empty it first")
    diff = _differences(old, manifest)
    if diff:
        raise DatasetError(f"folder {str(out)!r} holds another dataset (differs in "
                           f"{'; '.join(diff)}); run the same command as before to resume it, "
                           "or give --overwrite to replace it")


def build_dataset(
    sources: Sequence[Plan | str | Path | dict[str, Any]] | Plan | str | Path,
    n: int,
    out: str | Path,
    *,
    seed: int = 0,
    executor: Executor | None = None,
    pictures: str = "png",
    exports: Sequence[str] = (),
    movable: Sequence[str] = (),
    max_attempts: int | None = None,
    distinct_tol: float = 0.05,
    overwrite: bool = False,
    options: Options | None = None,
    prompts: dict[str, str] | None = None,
    assets: str | Path | None = None,
    progress: bool | Callable[[int, int], Any] = False,
    judge: Judge | None = None,
    judge_timeout: float | None = None,
) -> DatasetResult:
    """Write ``n`` valid, distinct layouts of every plan to ``out``, resuming a killed run.

    Parameters
    ----------
    sources : plan, plan file, folder of plan files, bundled name, or a list of them
        See :func:`plan_sources`.
    n : int
        Layouts per plan.
    out : str or Path
        The dataset's folder: new, empty, or holding a run of the same
        arguments (which is resumed).
    seed : int
        Seed of the run; a plan's sample ``k`` uses ``sample_seed(seed, k)``.
    executor : concurrent.futures.Executor, optional
        Where samples run and files are written (``ProcessPoolExecutor``,
        ``distributed.Client(...).get_executor()``, ...); this process when
        omitted. The dataset does not depend on it.
    pictures : {"png", "svg", "none"}
        A top-down picture per layout.
    exports : sequence of str
        3D formats per layout (``forcelayout.export.EXPORT_FORMATS``: glb, usd,
        mjcf, habitat); needs the ``export`` extra.
    movable : sequence of str
        Categories exported as movable bodies (USD rigid bodies, MJCF free
        joints, Habitat ``DYNAMIC``).
    max_attempts : int, optional
        Sample budget per plan; default ``max(4 n, n + 20)``.
    distinct_tol : float
        As in :func:`forcelayout.generate`.
    overwrite : bool
        Empty ``out`` first if it holds anything.
    options : Options, optional
        How samples are made and judged.
    prompts : dict of str to str, optional
        For plans made from a description: plan name -> the description,
        kept in ``dataset.json`` so a resumed run can reuse the plan.
    assets : str or Path, optional
        An asset library folder (``forcelayout.grounding``, extra
        ``grounding``): the exports place its meshes for the plans' grounded
        objects (see :func:`forcelayout.grounding.ground_plan`).
    progress : bool or callable
        ``True`` shows a progress bar moving per finished layout; a callable
        is called ``progress(finished, total)`` after each one.
    judge : callable, optional
        A plausibility judge (``judge(layout)`` -> ``Verdict``, bool or
        mapping; see :mod:`forcelayout.validate.loop`) asked, in this
        process, about each layout that passes the checks and the
        distinctness test, before it is written. Rejected and unjudged
        layouts are not written; their reasons count in ``summary.json``.
        :func:`~forcelayout.validate.loop.judge_name` of it is kept in
        ``dataset.json``.
    judge_timeout : float, optional
        Seconds to wait for each verdict (see
        :func:`~forcelayout.validate.loop.judge_layout`).

    Returns
    -------
    DatasetResult

    Raises
    ------
    DatasetError
        Before any sample runs: a folder of another run (without
        ``overwrite``), clashing plan names, a bad format name or count.
    KeyboardInterrupt
        Passed on after the finished layouts are safely in the index; running
        the same call again resumes.

    Warns
    -----
    FeasibilityWarning
        Before sampling, for each plan that looks infeasible (sampling goes on).
    """
    if isinstance(n, bool) or not isinstance(n, int) or n < 0:
        raise DatasetError(f"n must be a whole number >= 0, got {n!r}")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise DatasetError(f"seed must be a whole number >= 0, got {seed!r}")
    if pictures not in PICTURE_FORMATS:
        raise DatasetError(f"pictures must be one of {list(PICTURE_FORMATS)}, got {pictures!r}")
    if judge is not None and not callable(judge):
        raise DatasetError(f"judge must be callable (layout -> verdict), got "
                           f"{type(judge).__name__}")
    if judge_timeout is not None and not judge_timeout > 0:
        raise DatasetError(f"judge_timeout must be a positive number of seconds, got "
                           f"{judge_timeout!r}")
    exports = tuple(dict.fromkeys(exports))
    if exports:
        from forcelayout.export import EXPORT_FORMATS  # ImportError names the extra

        bad = [f for f in exports if f not in EXPORT_FORMATS]
        if bad:
            raise DatasetError(f"unknown export format(s) {bad}; choose from "
                               f"{list(EXPORT_FORMATS)}")
    if isinstance(sources, Plan | str | Path | dict):
        sources = [sources]
    plans = plan_sources(sources)
    from forcelayout.pipeline import prepare

    opts = options or Options()
    for plan in plans:
        prepare(plan)  # plan-level problems surface before any sample runs
        feas = plan_feasibility(plan, opts)
        if not feas.ok:
            warnings.warn(FeasibilityWarning.of(plan.name, feas), stacklevel=2)
    budget = max(4 * n, n + 20) if max_attempts is None else int(max_attempts)
    if budget < 0:
        raise DatasetError(f"max_attempts must be >= 0, got {max_attempts}")
    movable = tuple(movable)
    out = Path(out)
    what = _Files(pictures, exports, movable, None if assets is None else str(Path(assets)))
    manifest = _manifest(plans, n, seed, budget, pictures, exports, movable, opts, distinct_tol,
                         judge_name(judge) if judge is not None else None)
    if assets is not None:  # the library's metadata, not its path: the folder may move
        from forcelayout.grounding import METADATA_FILE

        manifest["assets"] = hashlib.sha256(
            (Path(assets) / METADATA_FILE).read_bytes()).hexdigest()
    for entry in manifest["plans"]:
        if prompts and entry["name"] in prompts:
            entry["prompt"] = prompts[entry["name"]]
    _prepare_folder(out, manifest, overwrite)
    write_text(out / MANIFEST, _json(manifest))
    for stray in list(out.glob(f"**/.*{TMP_MARK}*")):  # half-written files of a killed run
        if stray.is_dir():
            shutil.rmtree(stray, ignore_errors=True)
        else:
            stray.unlink(missing_ok=True)

    done = collections.defaultdict(dict)
    for entry in _read_index(out):
        done[entry["plan"]][entry["layout"]] = entry
    result = DatasetResult(out)
    log = _Log(out / RUN_LOG)
    log("start", plans=[p.name for p in plans], n=n, seed=seed,
        workers=executor_workers(executor), resumed=sum(len(v) for v in done.values()))
    total = n * len(plans)
    finished = sum(min(len(done[p.name]), n) for p in plans)
    bar, tell = _progress(progress, total, finished)
    t0 = time.perf_counter()
    try:
        for plan in plans:
            outcome = _run_plan(plan, n, out, seed, budget, what,
                                opts, distinct_tol, executor, done[plan.name], tell, log,
                                judge, judge_timeout)
            result.plans.append(outcome)
        write_text(out / INDEX, "".join(
            json.dumps(e, sort_keys=True) + "\n"
            for p in plans for _, e in sorted(done[p.name].items())))
    except KeyboardInterrupt:
        log("interrupted", finished=sum(len(v) for v in done.values()))
        raise
    finally:
        if bar is not None:
            bar.close()
    result.seconds = time.perf_counter() - t0
    log("end", accepted=result.accepted, wanted=result.wanted, seconds=round(result.seconds, 3))
    return result


def _progress(progress: bool | Callable[[int, int], Any], total: int,
              finished: int) -> tuple[Any, Callable[[], None]]:
    count = [finished]
    if callable(progress):
        def tell() -> None:
            count[0] += 1
            progress(count[0], total)
        return None, tell
    if not progress:
        return None, lambda: None
    from tqdm.auto import tqdm

    bar = tqdm(total=total, initial=finished, unit="layout", file=sys.stderr)
    return bar, lambda: bar.update(1)


def _run_plan(plan: Plan, n: int, out: Path, seed: int, budget: int, what: _Files,
              opts: Options, distinct_tol: float, executor: Executor | None,
              done: dict[int, dict[str, Any]], tell: Callable[[], None],
              log: Callable[..., None], judge: Judge | None = None,
              judge_timeout: float | None = None) -> PlanOutcome:
    folder = out / plan.name
    folder.mkdir(exist_ok=True)
    outcome = PlanOutcome(plan.name, n)
    summary_path = folder / SUMMARY
    # layouts count as finished in order: a gap (a torn index) starts the plan again there
    k = 0
    while k in done and k < n:
        k += 1
    for extra in [j for j in done if j >= k]:
        del done[extra]
    outcome.resumed = k
    if summary_path.exists() and k >= min(n, _summary_accepted(summary_path)):
        outcome.accepted = k
        finished = json.loads(summary_path.read_text(encoding="utf-8"))
        outcome.attempted = finished["attempted"]
        outcome.repaired = finished.get("repaired", {})
        return outcome
    write_text(folder / "plan.json", plan.to_json())
    t0 = time.perf_counter()
    seen = DistinctLayouts(distinct_tol)
    for j in range(k):
        seen.add_if_new(Layout.load(folder / done[j]["files"][0], plan))
    start = done[k - 1]["sample"] + 1 if k else 0
    reports: list[SampleReport] = []  # this run's samples after the last accepted one
    drawn = 0
    writing: collections.deque[tuple[int, int, Layout, dict, Future | dict, dict | None]] = \
        collections.deque()

    def commit(block: bool) -> None:
        while writing and (block or not isinstance(writing[0][4], Future)
                           or writing[0][4].done()):
            j, sample, lay, rejected, job, verdict = writing.popleft()
            written = job.result() if isinstance(job, Future) else job
            entry = {"plan": plan.name, "layout": j, "sample": sample, "seed": lay.seed,
                     "rule_satisfaction": round(lay.rule_satisfaction, 6),
                     "rejected_before": rejected, **written}
            if lay.report.repairs:  # how the sample was repaired before it passed
                entry["repairs"] = list(lay.report.repairs)
            if verdict is not None:
                entry["judge"] = verdict
            with (out / INDEX).open("a", encoding="utf-8") as f:
                f.write(json.dumps(entry, sort_keys=True) + "\n")
                f.flush()
                os.fsync(f.fileno())
            done[j] = entry
            tell()

    samples: Iterator[tuple[int, Layout]] = iter_samples(
        plan, seed, start=start, stop=budget if k < n else start, executor=executor,
        options=opts, expect=n - k)
    try:
        for sample, lay in samples:
            drawn += 1
            if lay.report.valid and seen.is_new(lay):
                verdict = None
                if judge is not None:
                    judged = judge_layout(judge, lay, timeout=judge_timeout)
                    if not judged.accepted:
                        lay.report.failures.append(f"{judged.status}: {judged.reason}")
                        reports.append(lay.report)
                        continue
                    verdict = judged.verdict.model_dump(mode="json") \
                        if judged.verdict is not None else None
                seen.add(lay)
                stem = layout_stem(plan.name, k, n)
                if executor is None:
                    job: Future | dict = _write_layout(lay, str(folder), stem, what)
                else:
                    job = executor.submit(_write_layout, lay, str(folder), stem, what)
                writing.append((k, sample, lay, _reasons(reports), job, verdict))
                reports = []
                k += 1
                commit(block=False)
                if k >= n:
                    break
            else:
                if lay.report.valid:
                    lay.report.failures.append(DistinctLayouts.FAILURE)
                reports.append(lay.report)
        commit(block=True)
    finally:
        samples.close()
        for *_, job, _verdict in writing:
            if isinstance(job, Future):
                job.cancel()
    outcome.accepted = k
    outcome.attempted = start + drawn  # samples of earlier runs up to the last finished layout
    reasons: dict[str, int] = _reasons(reports)
    for entry in done.values():
        for key, count in entry.get("rejected_before", {}).items():
            reasons[key] = reasons.get(key, 0) + count
    if k < n:  # the samples after the last accepted layout, all drawn in this run
        outcome.why = dominant_cause(reports) or "the sample budget ran out"
    summary = {
        "plan": plan.name, "wanted": n, "accepted": k, "attempted": outcome.attempted,
        "why": outcome.why, "failure_reasons": dict(sorted(reasons.items())),
        # the accepted layouts that were repaired, and how
        "repaired": repair_counts((e.get("repairs", ()) for e in done.values()), "layouts"),
    }
    outcome.repaired = summary["repaired"]
    if judge is not None:
        summary["judge"] = judge_name(judge)
    write_text(summary_path, _json(summary))
    log("plan", plan=plan.name, accepted=k, wanted=n, attempted=outcome.attempted,
        resumed=outcome.resumed, seconds=round(time.perf_counter() - t0, 3), why=outcome.why)
    return outcome


def _reasons(reports: list[SampleReport]) -> dict[str, int]:
    """How many of ``reports`` failed each check (the part of a failure before its colon)."""
    counts: dict[str, int] = {}
    for r in reports:
        for key in dict.fromkeys(f.split(":")[0] for f in r.failures):
            counts[key] = counts.get(key, 0) + 1
    return dict(sorted(counts.items()))


def _summary_accepted(path: Path) -> int:
    try:
        return int(json.loads(path.read_text(encoding="utf-8"))["accepted"])
    except (OSError, ValueError, KeyError, TypeError):
        return sys.maxsize
