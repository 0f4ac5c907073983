"""The multi-step LLM planner: a scene description in, a validated :class:`Plan` out.

Steps (paper §III-A), each one request with structured output:

1. ``room`` — room properties (floor polygon, height, doors, windows) and
   functional areas;
2. ``objects`` — objects with sizes, placement rules and pairwise relations,
   chosen only from the registry's vocabulary;
3. ``scene_graph`` — areas with their members and area rules, and support
   bonds (an object on top of another);
4. ``decor`` — secondary decorative items (off with ``decor=False``, the
   paper's −Decor condition);
5. ``self_check`` — the model lists the plan's problems (given the
   library's own report); only if it lists some, ``correction`` asks for the
   corrected plan.

Steps 4 and 5 refine a plan that is already valid: when they give nothing
usable, the plan stands as it was (said in ``Planner.unresolved``).

After each step the plan so far is validated by :class:`forcelayout.Plan`;
a reply that does not parse or fails validation is sent back with every
problem (and its JSON path) and the step is retried, up to
``max_attempts`` times. The model's output is only ever parsed as JSON data
and validated; it is never evaluated or executed.
"""

from __future__ import annotations

import difflib
import json
import logging
import re
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

from pydantic import BaseModel

from forcelayout import rules as registry
from forcelayout.autofix import autofix, resolve_id
from forcelayout.errors import PlanError
from forcelayout.llm.client import (
    ChatClient,
    LLMRequestError,
    OpenAIChatClient,
    RecordingClient,
    ReplayClient,
    call_client,
    estimate_tokens,
)
from forcelayout.llm.prompts import DEFAULT_TEMPLATES, PromptTemplates, render, vocabulary
from forcelayout.llm.prompts import vocabulary_text as _vocabulary_text
from forcelayout.llm.steps import (
    CheckIssues,
    DecorStep,
    ObjectsStep,
    PlanDraft,
    ReplyError,
    RoomStep,
    RuleDraft,
    SceneGraphStep,
    SelfCheckStep,
    close_cut_reply,
    parse_reply,
    schema_for,
    shape_of,
)
from forcelayout.plan import Plan
from forcelayout.relax import relax
from forcelayout.rules import RuleInfo, is_registered
from forcelayout.sanity import (
    ROOM_FURNITURE,
    Finding,
    article,
    category_key,
    plan_findings,
    room_kind,
    usual_size,
)

__all__ = ["Planner", "PlanningError", "Attempt", "plan_from_prompt", "make_client", "STEPS"]

log = logging.getLogger("forcelayout.llm")

#: The planning steps in order (the ``name`` each request carries).
STEPS = ("room", "objects", "scene_graph", "decor", "self_check", "correction")
#: Attempts of the self-check (a refinement: when its corrections cannot be used after
#: these, the plan stands as before the check).
SELF_CHECK_ATTEMPTS = 2
#: Most attempts per step a planner may be configured with.
MAX_ATTEMPTS_CAP = 20

M = TypeVar("M", bound=BaseModel)
Draft = dict[str, Any]


@dataclass(frozen=True)
class Attempt:
    """One failed attempt of a planning step.

    Attributes
    ----------
    step : str
        The step's name (see :data:`STEPS`).
    number : int
        1 for the first attempt of the step.
    reason : str
        Why it failed: the request error, or every problem of the reply.
    """

    step: str
    number: int
    reason: str

    def __str__(self) -> str:
        return f"{self.step} attempt {self.number}: {self.reason}"


class PlanningError(RuntimeError):
    """Planning failed: a step got no usable reply within its attempts.

    Attributes
    ----------
    step : str
        The step that failed.
    attempts : list of Attempt
        Every failed attempt of the run, in order, each with its reason.
    """

    def __init__(self, step: str, attempts: Sequence[Attempt], *, note: str = ""):
        self.step = step
        self.attempts = list(attempts)
        mine = [a for a in self.attempts if a.step == step]
        head = (f"planning step {step!r} failed after {len(mine)} attempt"
                f"{'s' if len(mine) != 1 else ''}{note}:")
        lines = [head, *(f"  {a.number}. {a.reason}" for a in mine)]
        super().__init__("\n".join(lines))


class _Problems(Exception):
    def __init__(self, problems: list[str]):
        self.problems = problems
        super().__init__("; ".join(problems))


def _slug(text: str, fallback: str = "plan") -> str:
    s = re.sub(r"[^A-Za-z0-9_\-]+", "_", text.strip().lower()).strip("_-")
    return s[:60] or fallback


def _did_you_mean(name: str, options: Sequence[str]) -> str:
    close = difflib.get_close_matches(name, list(options), n=1, cutoff=0.5)
    return f" Did you mean {close[0]!r}?" if close else ""


_PATH = re.compile(r"^(objects|rules)\[(\d+)\](.*)$", re.DOTALL)


def _relabel(path: str, offsets: dict[str, tuple[int, str]]) -> str:
    """Map a plan path (``rules[7] (near)``) to the reply's (``rules[2] (near)``)."""
    m = _PATH.match(path)
    if not m or m.group(1) not in offsets:
        return path
    off, label = offsets[m.group(1)]
    k = int(m.group(2))
    if k < off:
        return f"plan {path} (from an earlier step)"
    return f"{label}[{k - off}]{m.group(3)}"


_CLI_HINT = re.compile(r"\s*Run `forcelayout rules`.*$", re.DOTALL)


def _for_model(message: str) -> str:
    """A plan problem's message as advice to the model (no command-line hints)."""
    return _CLI_HINT.sub(" Use only the listed rules.", message)


def _validate(draft: Draft, offsets: dict[str, tuple[int, str]] | None = None) -> Plan:
    try:
        return Plan.from_dict(draft)
    except PlanError as e:
        raise _Problems([f"{_relabel(p.path, offsets or {})}: {_for_model(p.message)}"
                         for p in e.problems]) from None


def _room_dict(room: Any) -> dict[str, Any]:
    return {"polygon": room.polygon, "height": room.height,
            "doors": [d.model_dump() for d in room.doors],
            "windows": [w.model_dump() for w in room.windows]}


def _object_dict(o: Any, *, decor: bool) -> dict[str, Any]:
    return {"id": o.id, "category": o.category, "description": o.description,
            "size": o.size, "area": o.area or None, "primary": bool(o.primary), "decor": decor}


def _rule_dict(r: RuleDraft) -> dict[str, Any]:
    # the keys in the order of the step schemas: a server that enforces a schema's order
    # (llama.cpp's grammars do) would not let a model copying a plan write a target after
    # the params
    out: dict[str, Any] = {"rule": r.rule, "object": r.object}
    if r.target:
        out["target"] = r.target
    out["params"] = dict(r.params)
    return out


class Planner:
    """Plan scenes from text with a language model, step by step.

    Parameters
    ----------
    client : ChatClient
        The model to ask (e.g. :class:`OpenAIChatClient`, :class:`ReplayClient`).
    templates : PromptTemplates, optional
        Prompt templates; :data:`DEFAULT_TEMPLATES` if None.
    decor : bool, default True
        Run step 4 (secondary decorative items); False gives the −Decor plans.
    self_check : bool, default True
        Run step 5: the model lists the plan's problems (a short reply) and,
        only if it lists some, gives the corrected plan. Corrections are kept
        only if they validate within
        :data:`SELF_CHECK_ATTEMPTS` attempts; else the plan stands as before
        the check (a warning, and a line in :attr:`unresolved`).
    max_attempts : int, default 3
        Attempts per step before :class:`PlanningError` (1 to 20).
    rules : str, default "*"
        Shell pattern of the rule names offered (registered rules of kind
        unary, binary or surface, including plugins).
    step_timeout : float, optional
        Seconds one step may take, all its requests and repairs included
        (each request gets what is left; the SDK makes no retries of its own).
        Default: the client's ``timeout`` attribute, else no limit.
    relax : bool, default True
        Try the finished plan (:func:`forcelayout.relax.relax`: a few trial
        samples) and drop the floor rules that keep it from yielding layouts;
        each rule dropped is a line of :attr:`fixes` (``trial: ...``).
    detail : bool, default False
        Show each rule's whole docstring in the prompts; by default only its
        summary, parameters and one example (prompts about half as long).
    feasibility : bool, default True
        Feed the library's findings (:func:`forcelayout.sanity.plan_findings`
        and infeasible verdicts of :func:`forcelayout.diagnose.feasibility`)
        back to the model like schema errors. A step whose attempts run out
        with only such findings left keeps its best reply (logged at WARNING).

    Examples
    --------
    >>> from forcelayout.llm import Planner, OpenAIChatClient   # doctest: +SKIP
    >>> planner = Planner(OpenAIChatClient(base_url="http://localhost:11434/v1",
    ...                                    model="qwen2.5:14b"))  # doctest: +SKIP
    >>> plan = planner.plan("a student's bedroom")              # doctest: +SKIP
    """

    def __init__(
        self, client: ChatClient, *, templates: PromptTemplates | None = None,
        decor: bool = True, self_check: bool = True, max_attempts: int = 3, rules: str = "*",
        step_timeout: float | None = None, feasibility: bool = True, detail: bool = False,
        relax: bool = True,
    ):
        if not 1 <= int(max_attempts) <= MAX_ATTEMPTS_CAP:
            raise ValueError(f"max_attempts={max_attempts!r}; give 1 to {MAX_ATTEMPTS_CAP}")
        if not callable(getattr(client, "complete", None)):
            raise TypeError(f"client {client!r} has no complete(messages, schema=, name=) method")
        self.client = client
        self.templates = templates or DEFAULT_TEMPLATES
        self.decor = bool(decor)
        self.self_check = bool(self_check)
        self.max_attempts = int(max_attempts)
        self.rules = rules
        if step_timeout is None:
            inner = getattr(client, "inner", client)
            t = getattr(inner, "timeout", None)
            step_timeout = float(t) if isinstance(t, int | float) else None
        if step_timeout is not None and not step_timeout > 0:
            raise ValueError(f"step_timeout={step_timeout!r}; give a positive number of seconds")
        self.step_timeout = step_timeout
        self.feasibility = bool(feasibility)
        self.detail = bool(detail)
        self.relax = bool(relax)
        #: Failed attempts of the last :meth:`plan` call (empty if all went first time).
        self.failed_attempts: list[Attempt] = []
        #: What the last :meth:`plan` call fixed without asking the model, one line each.
        self.fixes: list[str] = []
        #: Findings the model left unfixed in the last :meth:`plan` call (the plan has them).
        self.unresolved: list[str] = []
        #: Requests sent in the last :meth:`plan` call.
        self.requests = 0
        self._current: Draft | None = None

    def __repr__(self) -> str:
        return (f"Planner({self.client!r}, decor={self.decor}, self_check={self.self_check}, "
                f"max_attempts={self.max_attempts})")

    # -- vocabulary -------------------------------------------------------------------
    def vocabulary(self) -> list[RuleInfo]:
        """The rules offered to the model (read from the registry on each call)."""
        return vocabulary(self.rules)

    def vocabulary_text(self) -> str:
        """The vocabulary as it appears in the prompts."""
        return _vocabulary_text(self.vocabulary(), detail=self.detail)

    # -- planning ---------------------------------------------------------------------
    def plan(self, prompt: str) -> Plan:
        """Plan a scene from a description.

        Parameters
        ----------
        prompt : str
            The scene in words, e.g. ``"a student's bedroom"``.

        Returns
        -------
        Plan
            A plan that passed the core validation.

        Raises
        ------
        PlanningError
            If the room, objects or scene graph step got no usable reply within
            ``max_attempts`` (or the server refuses requests); it carries every
            failed attempt with its reason.
        """
        prompt = " ".join(str(prompt).split())
        if not prompt:
            raise ValueError("the scene description is empty; describe the room, e.g. "
                             "\"a student's bedroom\"")
        self.failed_attempts = []
        self.fixes = []
        self.unresolved = []
        self.requests = 0
        self._current: Draft | None = None
        infos = self.vocabulary()
        if not infos:
            raise ValueError(f"no registered rule matches rules={self.rules!r}")
        kinds = {i.name: i.kind for i in infos}
        values = {"prompt": prompt, "vocabulary": _vocabulary_text(infos, detail=self.detail)}
        names = sorted(kinds)

        draft = self._run("room", RoomStep, values, None,
                          lambda r: self._apply_room(r, prompt))
        draft = self._run("objects", ObjectsStep, values, names,
                          lambda r: self._apply_objects(r, draft, kinds))
        unary = [i for i in infos if i.kind == "unary"]
        draft = self._run("scene_graph", SceneGraphStep, values,
                          [i.name for i in unary] or names,
                          lambda r: self._apply_graph(r, draft, kinds))
        # decor and the self-check refine a plan that is already valid: neither may make the
        # plan fail; what they could not do is said, and the plan stands as it was
        if self.decor:
            draft = self._refine("decor", "its items could not be used",
                                 "decor: items dropped", draft,
                                 lambda d: self._run("decor", DecorStep, values, names,
                                                     lambda r: self._apply_decor(r, d, kinds)))
        if self.self_check:
            draft = self._refine("self_check", "its corrections could not be used",
                                 "self_check: corrections dropped", draft,
                                 lambda d: self._check(d, values, names, kinds))
        plan = Plan.from_dict(draft)
        if self.relax:
            t = time.monotonic()
            plan, notes = relax(plan)
            for n in notes:
                log.info("trial runs: %s", n)
            self.fixes.extend(f"trial: {n}" for n in notes)
            log.info("trial runs of the plan took %.1f s", time.monotonic() - t)
        log.info("planned %r: %d objects, %d rules; %d requests, %d repairs, %d fixes without "
                 "asking", plan.name, len(plan.objects), len(plan.rules), self.requests,
                 len(self.failed_attempts), len(self.fixes))
        return plan

    def _refine(self, step: str, what: str, label: str, draft: Draft,
                run: Callable[[Draft], Draft]) -> Draft:
        """``run(draft)``, or ``draft`` itself when the step gives nothing usable."""
        try:
            return run(draft)
        except PlanningError as e:
            cause = e.__cause__
            if isinstance(cause, LLMRequestError) and not cause.retryable:
                raise  # the server refuses every request: later steps would fail the same way
            reason = e.attempts[-1].reason if e.attempts else str(e)
            log.warning("step %r: %s; the plan stands as before the step (last problem: %s)",
                        step, what, reason)
            self.unresolved.append(f"{label} ({reason})")
            self._current = draft
            return draft

    def _check(self, draft: Draft, values: dict[str, Any], names: list[str],
               kinds: dict[str, str]) -> Draft:
        """Step 5: ask for the plan's problems; only if there are some, for the corrections."""
        attempts = min(self.max_attempts, SELF_CHECK_ATTEMPTS)
        found: list[str] = []

        def listed(r: SelfCheckStep) -> Draft:
            found[:] = []
            for issue in (" ".join(i.split()) for i in r.issues if i.strip()):
                if _NO_PROBLEM.match(issue):  # "no problems found" is not a problem
                    continue
                has = _claimed_missing(issue, draft)
                extra = _unasked(issue, values["prompt"]) if has is None else None
                if has is not None:
                    self._note("self_check", f"dropped the issue {issue!r}: the plan has {has}")
                elif extra is not None:
                    self._note("self_check", f"dropped the issue {issue!r}: the description "
                                             f"does not ask for {extra}")
                else:
                    found.append(issue)
            if r.plan is not None and found:  # the corrected plan came at once
                return self._apply_check(r, draft, kinds)
            if r.plan is not None:
                log.info("step 'self_check': no problems listed; the plan it repeated is not "
                         "used")
            return draft

        checked = self._run("self_check", SelfCheckStep,
                            {**values, "report": self._report(draft)}, names, listed,
                            attempts=attempts, schema_model=CheckIssues)
        if not found or checked is not draft:
            return checked
        log.info("step 'self_check' found: %s", "; ".join(found))
        return self._run("correction", SelfCheckStep,
                         {**values, "issues": "\n".join(f"- {i}" for i in found)}, names,
                         lambda r: self._apply_check(r, draft, kinds), attempts=attempts)

    def _report(self, draft: Draft) -> str:
        """The library's findings about a draft, as text for the self-check prompt."""
        try:
            plan = Plan.from_dict(draft)
        except PlanError as e:  # cannot happen after the steps; said plainly if it does
            return "\n".join(f"- {p}" for p in e.problems)
        from forcelayout.diagnose import feasibility

        notes = feasibility(plan).notes
        return "\n".join(f"- {n}" for n in notes) if notes else "- no problems found"

    def _run(self, step: str, model: type[M], values: dict[str, Any],
             rule_names: list[str] | None, apply: Callable[[M], Draft], *,
             attempts: int | None = None, schema_model: type[BaseModel] | None = None
             ) -> Draft:
        # the schema asked for may be a part of what the reply is read as (the self-check
        # asks for its issues only and still takes a corrected plan given at once)
        schema = schema_for(schema_model or model, rule_names)
        current = self._current
        text = render(self.templates, {"room": "room", "objects": "objects",
                                       "scene_graph": "graph", "decor": "decor",
                                       "self_check": "check", "correction": "correct"}[step],
                      **{"report": "", "issues": "", **values},
                      schema=json.dumps(schema, separators=(",", ":")), shape=shape_of(schema),
                      plan=json.dumps(current, separators=(",", ":")) if current else "{}")
        base = [{"role": "system", "content": render(self.templates, "system", **values)},
                {"role": "user", "content": text}]
        messages = base
        t0 = time.monotonic()
        budget = self.step_timeout
        seen: dict[str, int] = {}
        best: tuple[int, Draft, list[str], list[str]] | None = None
        note = ""
        for number in range(1, (attempts or self.max_attempts) + 1):
            left = None if budget is None else budget - (time.monotonic() - t0)
            if left is not None and left <= 0.05:
                note = f" (the step's time budget of {budget:g} s is used up)"
                break
            log.info("step %r attempt %d: sending %d messages, about %d tokens", step, number,
                     len(messages), estimate_tokens(messages))
            t = time.monotonic()
            self.requests += 1
            try:
                reply = call_client(self.client, messages, schema=schema, name=step,
                                    timeout=left)
            except LLMRequestError as e:
                self._fail(step, number, f"request failed after {time.monotonic() - t:.1f} s: "
                           f"{e}")
                if not e.retryable:
                    raise PlanningError(step, self.failed_attempts,
                                        note=" (the error is not worth retrying)") from e
                continue
            log.info("step %r attempt %d: reply of %d characters after %.1f s", step, number,
                     len(reply), time.monotonic() - t)
            key = " ".join(reply.split())
            repeats = seen.get(key, 0)
            seen[key] = repeats + 1
            fixes_before = len(self.fixes)
            usable = False
            try:
                draft = apply(self._parse(step, reply, model))
            except (ReplyError, _Problems) as e:
                problems = list(e.problems)
                del self.fixes[fixes_before:]
            else:
                usable = True
                problems = self._findings(step, draft) if self.feasibility else []
                if not problems:
                    log.info("step %r: done after %d attempt%s in %.1f s", step, number,
                             "s" if number > 1 else "", time.monotonic() - t0)
                    self._current = draft
                    return draft
                if best is None or len(problems) < len(best[2]):
                    best = (number, draft, problems, self.fixes[fixes_before:])
                del self.fixes[fixes_before:]
            self._fail(step, number, "; ".join(problems))
            if repeats >= 2:
                note = " (the model sent the same reply three times)"
                break
            if repeats and usable:  # a usable reply sent again: the model stands by it
                log.info("step %r: the model sent the same usable reply again; keeping it",
                         step)
                break
            repair = render(self.templates, "repair", **values,
                            problems="\n".join(f"- {p}" for p in problems))
            if repeats:  # the same reply again: start afresh instead of repeating the exchange
                log.info("step %r: the model repeated a reply; asking afresh with the problems",
                         step)
                messages = [*base[:-1], {"role": "user", "content": text + "\n\n" + repair
                                         .replace("Your reply could not be used:",
                                                  "Earlier answers were rejected for:")}]
            else:
                messages = [*base, {"role": "assistant", "content": reply},
                            {"role": "user", "content": repair}]
        if best is not None:
            number, draft, problems, fixes = best
            self.fixes.extend(fixes)
            draft, problems = self._usual_sizes(step, draft, problems)
            if problems:
                log.warning("step %r: kept attempt %d with problems the model did not fix: %s",
                            step, number, "; ".join(problems))
            self.unresolved.extend(problems)
            self._current = draft
            return draft
        raise PlanningError(step, self.failed_attempts, note=note)

    def _usual_sizes(self, step: str, draft: Draft, problems: list[str]
                     ) -> tuple[Draft, list[str]]:
        """Sizes far from their category's the model did not fix, brought into its usual range
        (:func:`forcelayout.sanity.usual_size`); the problems left."""
        try:
            plan = Plan.from_dict(draft)
        except PlanError:
            return draft, problems
        objects = list(draft.get("objects") or [])
        left = list(problems)
        for f in plan_findings(plan):
            m = re.fullmatch(r"objects\[(\d+)\]\.size", f.path)
            if m is None or str(f) not in left or int(m.group(1)) >= len(objects):
                continue
            k = int(m.group(1))
            o = objects[k]
            size = usual_size(str(o.get("category", "")), o.get("size") or [])
            if size is None:
                continue
            self._note(step, f"objects[{k}].size: {o.get('id')!r} was "
                             f"{' x '.join(f'{x:g}' for x in o['size'])} m after every attempt; "
                             f"set to {' x '.join(f'{x:g}' for x in size)} m, the nearest usual "
                             f"size of its category")
            objects[k] = {**o, "size": size}
            left.remove(str(f))
        return ({**draft, "objects": objects} if len(left) < len(problems) else draft), left

    def _parse(self, step: str, reply: str, model: type[M]) -> M:
        """Parse a reply; one cut off at the token limit is read up to its last whole item."""
        try:
            return parse_reply(reply, model)
        except ReplyError as first:
            # a corrected plan cut off would lose the rest of the plan: not for the correction
            closed = close_cut_reply(reply) if step != "correction" else None
            if closed is None:
                raise
            try:
                parsed = parse_reply(closed, model)
            except ReplyError:
                raise first from None
            self._note(step, f"the reply broke off after {len(reply)} characters (the "
                       "server's token limit?); read up to its last whole list item")
            return parsed

    def _findings(self, step: str, draft: Draft) -> list[str]:
        """The library's findings about what this step added, as problems for the model."""
        if step == "room":
            draft = {**draft, "objects": [{"id": "probe", "category": "probe",
                                           "size": [0.01, 0.01, 0.01]}]}
        try:
            plan = Plan.from_dict(draft)
        except PlanError:
            return []
        prev = self._current or {}
        n_obj, n_rules = len(prev.get("objects") or []), len(prev.get("rules") or [])

        def mine(f: Finding) -> bool:
            refs = f.refs or (f.path,)
            if step == "room":
                return any(r.startswith("room") for r in refs)
            if step == "objects":
                return any(r.startswith(("objects[", "rules[")) for r in refs)
            if step == "scene_graph":
                return any(r.startswith("areas[") for r in refs)
            if step == "decor":
                for r in refs:
                    m = re.match(r"(objects|rules)\[(\d+)\]", r)
                    if m and int(m.group(2)) >= (n_obj if m.group(1) == "objects" else n_rules):
                        return True
                return False
            return True

        out = [str(f) for f in plan_findings(plan) if mine(f) and str(f) not in self.unresolved]
        if step in ("objects", "self_check", "correction"):
            from forcelayout.diagnose import feasibility

            feas = feasibility(plan)
            if not feas.ok:
                found = {str(f) for f in feas.findings}
                out += [f"objects: {n}" for n in feas.notes if n not in found and n not in out
                        and f"objects: {n}" not in self.unresolved][:3]
        return _dedupe(out)

    def _note(self, step: str, text: str) -> None:
        log.info("step %r: fixed without asking: %s", step, text)
        self.fixes.append(f"{step}: {text}")

    def _fix(self, step: str, draft: Draft) -> Draft:
        """Apply :func:`forcelayout.autofix.autofix`; log and keep what it did."""
        fixed, notes = autofix(draft)
        for n in notes:
            log.info("step %r: fixed without asking: %s", step, n)
        self.fixes.extend(f"{step}: {n}" for n in notes)
        return fixed

    def _fail(self, step: str, number: int, reason: str) -> None:
        log.info("step %r attempt %d needs a repair: %s", step, number, reason)
        self.failed_attempts.append(Attempt(step, number, reason))

    # -- steps --------------------------------------------------------------------------
    def _apply_room(self, r: RoomStep, prompt: str) -> Draft:
        problems = []
        seen: set[str] = set()
        for k, a in enumerate(r.areas):
            if a.name in seen:
                problems.append(f"areas[{k}].name: area {a.name!r} appears twice")
            seen.add(a.name)
        draft: Draft = {"name": _slug(r.name), "description": r.description or prompt,
                        "room": _room_dict(r.room),
                        "areas": [{"name": a.name, "description": a.description}
                                  for a in r.areas],
                        "objects": [], "rules": []}
        draft = self._fix("room", draft)
        probe = {**draft, "objects": [{"id": "probe", "category": "probe",
                                       "size": [0.01, 0.01, 0.01]}]}
        try:
            _validate(probe)
        except _Problems as e:
            problems.extend(e.problems)
        if problems:
            raise _Problems(problems)
        return draft

    @staticmethod
    def _vocab_problems(rules: Sequence[RuleDraft], kinds: dict[str, str], label: str,
                        allowed: tuple[str, ...] = ("unary", "binary", "surface")) -> list[str]:
        out = []
        for k, r in enumerate(rules):
            kind = kinds.get(r.rule)
            if kind is None:
                if is_registered(r.rule):  # unregistered names are reported by the plan
                    out.append(f"{label}[{k}] ({r.rule}): {r.rule!r} is not one of the rules "
                               f"offered.{_did_you_mean(r.rule, sorted(kinds))} Use only the "
                               "listed rules")
            elif kind not in allowed:
                out.append(f"{label}[{k}] ({r.rule}): a {kind} rule cannot be used here; "
                           f"use a {' or '.join(allowed)} rule")
        return out

    def _apply_objects(self, r: ObjectsStep, draft: Draft, kinds: dict[str, str]) -> Draft:
        problems = self._vocab_problems(r.rules, kinds, "rules")
        new = self._fix("objects", {
            **draft, "objects": [_object_dict(o, decor=False) for o in r.objects],
            "rules": [_rule_dict(x) for x in r.rules]})
        try:
            _validate(new)
        except _Problems as e:
            problems.extend(p for p in e.problems if p not in problems)
        if problems:
            raise _Problems(_dedupe(problems))
        return new

    def _apply_graph(self, r: SceneGraphStep, draft: Draft, kinds: dict[str, str]) -> Draft:
        ids = [o["id"] for o in draft["objects"]]
        by_cat: dict[str, list[str]] = {}
        for o in draft["objects"]:
            by_cat.setdefault(o["category"], []).append(o["id"])

        def known(oid: str, path: str, what: str) -> str | None:
            """The object ``oid`` means (a near miss mapped), or None (noted: dropped)."""
            new = resolve_id(oid, ids, by_cat)
            if new in ids:
                if new != oid:
                    self._note("scene_graph", f"{path}: {oid!r} read as {new!r}")
                return new
            self._note("scene_graph", f"{path}: dropped {what} naming {oid!r}, which is no "
                       "object of the plan")
            return None

        problems: list[str] = []
        member: dict[str, str] = {}
        names: set[str] = set()
        for i, a in enumerate(r.areas):
            if a.name in names:
                problems.append(f"areas[{i}].name: area {a.name!r} appears twice")
            names.add(a.name)
            for j, raw in enumerate(a.objects):
                oid = known(raw, f"areas[{i}].objects[{j}]", "the membership")
                if oid is None:
                    continue
                if oid in member:
                    if member[oid] != a.name:
                        self._note("scene_graph", f"areas[{i}].objects[{j}]: {oid!r} left in "
                                   f"area {member[oid]!r} only (an object belongs to one area)")
                else:
                    member[oid] = a.name
            for j, ar in enumerate(a.rules):
                kind = kinds.get(ar.rule)
                if kind != "unary":
                    what = "unknown rule" if kind is None else f"a {kind} rule"
                    problems.append(f"areas[{i}].rules[{j}] ({ar.rule}): {what}; area rules "
                                    "must be unary rules from the list"
                                    f"{_did_you_mean(ar.rule, sorted(kinds))}")
        support: list[tuple[str, str]] = []
        for k, e in enumerate(r.support):
            child = known(e.object, f"support[{k}].object", "the support bond")
            parent = None if child is None else known(e.parent, f"support[{k}].parent",
                                                      "the support bond")
            if child is None or parent is None:
                continue
            if child == parent:
                self._note("scene_graph", f"support[{k}]: dropped, {child!r} cannot rest on "
                           "itself")
                continue
            support.append((child, parent))
        if problems:
            raise _Problems(problems)
        areas = [{"name": a.name, "description": a.description,
                  "rules": [{"rule": ar.rule, "params": dict(ar.params)} for ar in a.rules]}
                 for a in r.areas] or draft["areas"]
        area_names = {a["name"] for a in areas}
        objects = []
        for o in draft["objects"]:
            area = member.get(o["id"], o["area"])
            objects.append({**o, "area": area if area in area_names else None})
        rules = list(draft["rules"])
        n_rules = len(rules)
        # the rule that rests an object on its parent's top, as the registry declares it
        top = next((n for n in sorted(kinds) if registry.get_rule(n).surface == "top"), None)
        have = {(x["object"], x.get("target")) for x in rules if x["rule"] == top}
        if top is not None:
            rules += [{"rule": top, "object": child, "target": parent, "params": {}}
                      for child, parent in dict.fromkeys(support) if (child, parent) not in have]
        elif support:
            raise _Problems(["support: no rule in the vocabulary rests an object on another's "
                             "top; give no support bonds"])
        new = self._fix("scene_graph", {**draft, "areas": areas, "objects": objects,
                                         "rules": rules})
        _validate(new, {"rules": (n_rules, "support"), "objects": (len(objects), "objects")})
        return new

    def _apply_decor(self, r: DecorStep, draft: Draft, kinds: dict[str, str]) -> Draft:
        problems = self._vocab_problems(r.rules, kinds, "rules")
        n_obj, n_rules = len(draft["objects"]), len(draft["rules"])
        new = self._fix("decor", {
            **draft,
            "objects": draft["objects"] + [_object_dict(o, decor=True) for o in r.objects],
            "rules": draft["rules"] + [_rule_dict(x) for x in r.rules]})
        try:
            _validate(new, {"objects": (n_obj, "objects"), "rules": (n_rules, "rules")})
        except _Problems as e:
            problems.extend(e.problems)
        if problems:
            raise _Problems(_dedupe(problems))
        return new

    def _apply_check(self, r: SelfCheckStep, draft: Draft, kinds: dict[str, str]) -> Draft:
        if r.plan is None:
            return draft
        p: PlanDraft = r.plan
        problems = [f"plan.{x}" for x in self._vocab_problems(p.rules, kinds, "rules")]
        if not self.decor and any(o.decor for o in p.objects):
            problems.append("plan.objects: this plan is planned without decorative items; "
                            "remove the objects with decor=true")
        new: Draft = {
            "name": _slug(p.name, draft["name"]), "description": p.description
            or draft["description"], "room": _room_dict(p.room),
            "areas": [{"name": a.name, "description": a.description,
                       "rules": [{"rule": x.rule, "params": dict(x.params)} for x in a.rules]}
                      for a in p.areas],
            "objects": [_object_dict(o, decor=o.decor) for o in p.objects],
            "rules": [_rule_dict(x) for x in p.rules]}
        new = self._fix("self_check", new)
        try:
            Plan.from_dict(new)
        except PlanError as e:
            problems.extend(f"plan.{q.path}: {_for_model(q.message)}" for q in e.problems)
        if problems:
            raise _Problems(_dedupe(problems))
        return new


_NO_PROBLEM = re.compile(r"^\W*(?:-\s*)?(?:no (?:problems?|issues?)(?: (?:were |was )?found)?|"
                         r"none|nothing(?: is)? missing|n/?a|ok|the plan is (?:fine|ok|"
                         r"correct|complete))\W*$", re.IGNORECASE)
_ABSENT = re.compile(r"\b(?:lacks?|lacking|is missing|are missing|missing|has no|have no|"
                     r"there is no|there are no|without)\b\s+(.+)", re.IGNORECASE)
_MORE = re.compile(r"\b(?:second|third|another|more|two|three|four|five|six|extra|"
                   r"additional|enough|\d+)\b", re.IGNORECASE)


def _claimed_missing(issue: str, draft: Draft) -> str | None:
    """If ``issue`` says the plan lacks an object it has, what it has (``'nightstand_3'``, ``a
    coffee table``); else None.

    Only plain claims of absence are checked ("the plan lacks a bed"); one asking for more
    of a kind ("a second bed", "two chairs") is left to the model.
    """
    m = _ABSENT.search(issue)
    if m is None:
        return None
    phrase = re.split(r"[.;,]| for | to | in | near | by | and ", m.group(1))[0]
    words = _words(phrase)
    while words and words[0] in ("a", "an", "the", "any"):
        words = words[1:]
    for o in draft.get("objects") or []:  # an id: "the nightstand 3" for nightstand_3
        if "_".join(words) == str(o.get("id", "")).lower() and o.get("category"):
            return repr(str(o.get("id")))
    if _MORE.search(phrase):
        return None
    key = category_key(phrase)
    if key is None:
        return None
    for o in draft.get("objects") or []:
        if key in (category_key(str(o.get("category", ""))), category_key(str(o.get("id", "")))):
            return f"{article(key)} {key.replace('_', ' ')}"
    return None


def _unasked(issue: str, prompt: str) -> str | None:
    """If ``issue`` says the plan lacks something the description does not ask for, that thing
    (``'a ceiling light'``); else None.

    The check looks for furniture the description asks for: named in it (``"a kitchen with a
    table for four"`` asks for a table) or what its room type cannot do without
    (:data:`forcelayout.sanity.ROOM_FURNITURE`: a bedroom asks for a bed). Extras a model wishes
    for (a picture, a second lamp) are not problems of the plan.
    """
    m = _ABSENT.search(issue)
    if m is None:
        return None
    phrase = _PHRASE_END.split(m.group(1))[0]
    words = [w for w in _words(phrase) if w not in _FILLER and not _MORE.fullmatch(w)]
    if not words:
        return None
    asked = {_singular(w) for w in _words(prompt)}
    kind = room_kind("", prompt)
    if kind is not None:
        asked.update(ROOM_FURNITURE[kind])
    key = category_key(phrase)
    if key in asked or any(_singular(w) in asked for w in words):
        return None
    return " ".join(words)


_PHRASE_END = re.compile(r"[.;,:(]| for | to | in | near | by | and | of | with | on | that ")
_FILLER = frozenset({"a", "an", "the", "any", "some", "its", "their", "enough"})


def _words(text: str) -> list[str]:
    return [w for w in re.split(r"[^a-z0-9]+", text.lower()) if w]


def _singular(word: str) -> str:
    for end, repl in (("ies", "y"), ("ves", "f"), ("ches", "ch"), ("shes", "sh"), ("ses", "s"),
                      ("s", "")):
        if word.endswith(end) and len(word) > len(end) + 2:
            return word[: -len(end)] + repl
    return word


def _dedupe(items: list[str]) -> list[str]:
    return list(dict.fromkeys(items))


def make_client(
    *, record: str | Path | None = None, replay: str | Path | None = None,
    **client_kwargs: Any,
) -> ChatClient:
    """A chat client from options: a replay, or a server (optionally recorded).

    Parameters
    ----------
    record : path, optional
        Write every request and reply to this JSONL file.
    replay : path, optional
        Answer from this recording instead of a server (``client_kwargs``
        other than ``strict`` are then ignored).
    **client_kwargs
        Passed to :class:`OpenAIChatClient` (``base_url``, ``model``,
        ``api_key``, ``timeout``, ``temperature``, ``seed``, ...).
    """
    client: ChatClient
    if replay is not None:
        client = ReplayClient(replay, strict=bool(client_kwargs.get("strict", False)))
    else:
        client_kwargs.pop("strict", None)
        client = OpenAIChatClient(**client_kwargs)
    if record is not None:
        client = RecordingClient(client, record)
    return client


def plan_from_prompt(
    prompt: str, *, decor: bool = True, self_check: bool = True, max_attempts: int = 3,
    templates: PromptTemplates | None = None, record: str | Path | None = None,
    replay: str | Path | None = None, **client_kwargs: Any,
) -> Plan:
    """Plan a scene from a description in one call.

    Parameters
    ----------
    prompt : str
        The scene in words, e.g. ``"a student's bedroom"``.
    decor, self_check, max_attempts, templates
        See :class:`Planner`.
    record, replay, **client_kwargs
        See :func:`make_client` (server URL, model, API key, timeout, ...;
        by default from ``OPENAI_BASE_URL``, ``FORCELAYOUT_LLM_MODEL``,
        ``OPENAI_API_KEY``).

    Returns
    -------
    Plan

    Examples
    --------
    >>> from forcelayout.llm import plan_from_prompt
    >>> plan = plan_from_prompt("a student's bedroom", base_url="http://localhost:8000/v1",
    ...                         model="Qwen/Qwen2.5-14B-Instruct")   # doctest: +SKIP
    """
    client = make_client(record=record, replay=replay, **client_kwargs)
    planner = Planner(client, templates=templates, decor=decor, self_check=self_check,
                      max_attempts=max_attempts)
    return planner.plan(prompt)
