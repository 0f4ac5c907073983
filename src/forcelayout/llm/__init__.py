"""L stage: plan scenes from text with a language model (needs ``forcelayout[llm]``).

A multi-step planner (room and areas -> objects with rules from the
registry's vocabulary -> scene graph -> decorative items -> self-check) with
structured output, validation of every step by :class:`forcelayout.Plan`
and retries that feed the problems back. It talks to any OpenAI-compatible
server (OpenAI, vLLM, Ollama, LM Studio, ...) through a small
:class:`ChatClient` protocol; runs can be recorded to JSONL and replayed
without a server.

Examples
--------
>>> from forcelayout.llm import plan_from_prompt
>>> plan = plan_from_prompt("a student's bedroom")           # doctest: +SKIP
>>> plan = plan_from_prompt("a student's bedroom", replay="run.jsonl")  # doctest: +SKIP

Importing this module without the ``openai`` package raises an ImportError
that says ``pip install "forcelayout[llm]"``; ``openai`` itself is imported
when an :class:`OpenAIChatClient` is made (replaying a recording never needs it).
"""

from forcelayout._optional import require_optional

require_optional("openai", "llm")

from forcelayout.llm.client import (  # noqa: E402
    DEFAULT_MODEL,
    ChatClient,
    LLMRequestError,
    OpenAIChatClient,
    RecordingClient,
    ReplayClient,
    ReplayError,
)
from forcelayout.llm.diversity import expand_prompts, plan_variants  # noqa: E402
from forcelayout.llm.planner import (  # noqa: E402
    STEPS,
    Attempt,
    Planner,
    PlanningError,
    make_client,
    plan_from_prompt,
)
from forcelayout.llm.prompts import (  # noqa: E402
    DEFAULT_TEMPLATES,
    PromptTemplates,
    vocabulary_text,
)
from forcelayout.llm.steps import ReplyError, parse_reply  # noqa: E402

__all__ = [
    "Planner",
    "PlanningError",
    "Attempt",
    "plan_from_prompt",
    "make_client",
    "expand_prompts",
    "plan_variants",
    "ChatClient",
    "OpenAIChatClient",
    "RecordingClient",
    "ReplayClient",
    "LLMRequestError",
    "ReplayError",
    "PromptTemplates",
    "DEFAULT_TEMPLATES",
    "vocabulary_text",
    "parse_reply",
    "ReplyError",
    "STEPS",
    "DEFAULT_MODEL",
]
