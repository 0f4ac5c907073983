"""Semantic diversity (paper Fig. 4b): one room type, many distinct descriptions and plans.

:func:`expand_prompts` asks the model for ``k`` distinct descriptive prompts
for a high-level room type ("living room" -> "a modern and cosy living room
with a reading corner", ...); :func:`plan_variants` plans each of them, so
layouts differ in their semantics as well as in their geometry.
"""

from __future__ import annotations

import json
import logging
from typing import Any

from forcelayout.llm.client import ChatClient, LLMRequestError
from forcelayout.llm.planner import Attempt, Planner, PlanningError
from forcelayout.llm.prompts import (
    DEFAULT_TEMPLATES,
    PromptTemplates,
    render,
    vocabulary,
    vocabulary_text,
)
from forcelayout.llm.steps import PromptList, ReplyError, parse_reply, schema_for, shape_of
from forcelayout.plan import Plan

__all__ = ["expand_prompts", "plan_variants", "MAX_VARIANTS"]

log = logging.getLogger("forcelayout.llm")

#: Most descriptions one call may ask for.
MAX_VARIANTS = 100


def expand_prompts(
    room_type: str, k: int, client: ChatClient, *,
    templates: PromptTemplates | None = None, max_attempts: int = 3,
) -> list[str]:
    """Expand a room type into ``k`` distinct descriptive prompts.

    Parameters
    ----------
    room_type : str
        A high-level type such as ``"bedroom"`` or ``"living room"``.
    k : int
        Number of descriptions wanted (1 to 100).
    client : ChatClient
        The model to ask.
    templates : PromptTemplates, optional
        Uses its ``system`` and ``expand`` templates.
    max_attempts : int, default 3
        Attempts before :class:`PlanningError`; a reply with fewer than ``k``
        distinct descriptions is sent back and retried.

    Returns
    -------
    list of str
        ``k`` descriptions, distinct ignoring case and spacing.
    """
    if not 1 <= int(k) <= MAX_VARIANTS:
        raise ValueError(f"k={k!r}; ask for 1 to {MAX_VARIANTS} descriptions")
    templates = templates or DEFAULT_TEMPLATES
    schema = schema_for(PromptList)
    # the system message is the planner's (vocabulary included), so a server's prompt cache
    # serves the planning requests that usually follow
    values = {"room_type": " ".join(room_type.split()), "k": int(k), "prompt": room_type,
              "vocabulary": vocabulary_text(vocabulary())}
    base = [{"role": "system", "content": render(templates, "system", **values)},
            {"role": "user", "content": render(templates, "expand", **values,
                                               schema=json.dumps(schema),
                                               shape=shape_of(schema))}]
    messages = base
    attempts: list[Attempt] = []
    for number in range(1, int(max_attempts) + 1):
        try:
            reply = client.complete(messages, schema=schema, name="expand")
        except LLMRequestError as e:
            attempts.append(Attempt("expand", number, f"request failed: {e}"))
            if not e.retryable:
                break
            continue
        try:
            got = parse_reply(reply, PromptList).prompts
            distinct = list({" ".join(p.split()).lower(): " ".join(p.split())
                             for p in got if p.strip()}.values())
            if len(distinct) < k:
                raise ReplyError([f"prompts: {len(distinct)} distinct descriptions, {k} needed; "
                                  f"give {k} different ones"])
        except ReplyError as e:
            attempts.append(Attempt("expand", number, "; ".join(e.problems)))
            messages = [*base, {"role": "assistant", "content": reply},
                        {"role": "user", "content": render(
                            templates, "repair", **values,
                            problems="\n".join(f"- {p}" for p in e.problems))}]
            continue
        return distinct[:k]
    raise PlanningError("expand", attempts)


def plan_variants(
    room_type: str, k: int, client: ChatClient, *, skip_failures: bool = True,
    **planner_kwargs: Any,
) -> list[tuple[str, Plan]]:
    """Expand ``room_type`` into ``k`` descriptions and plan each one.

    Parameters
    ----------
    room_type : str
        A high-level type such as ``"living room"``.
    k : int
        Number of descriptions (1 to 100).
    client : ChatClient
        The model to ask.
    skip_failures : bool, default True
        Leave out descriptions whose planning failed (logged); if False the
        first :class:`PlanningError` is raised.
    **planner_kwargs
        Passed to :class:`Planner` (``decor``, ``self_check``, ``templates``, ...).

    Returns
    -------
    list of (str, Plan)
        Each description with its plan, in the order the model gave them.
    """
    planner = Planner(client, **planner_kwargs)
    prompts = expand_prompts(room_type, k, client, templates=planner.templates,
                             max_attempts=planner.max_attempts)
    out = []
    for prompt in prompts:
        try:
            out.append((prompt, planner.plan(prompt)))
        except PlanningError as e:
            if not skip_failures:
                raise
            log.warning("left out %r: %s", prompt, e)
    return out
