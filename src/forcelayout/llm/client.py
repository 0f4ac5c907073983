"""Chat clients the planner talks to: any OpenAI-compatible server, recordings, replays.

The planner depends only on the small :class:`ChatClient` protocol: one
method that sends chat messages (and, optionally, the JSON Schema the reply
must follow) and returns the reply's text. :class:`OpenAIChatClient`
implements it over the ``openai`` SDK's chat-completions API, which OpenAI,
vLLM, Ollama, LM Studio, llama.cpp and many other servers speak.
:class:`RecordingClient` writes every request and reply to a JSONL file and
:class:`ReplayClient` answers from such a file, so a notebook reruns without a
server and a paper's plans can be shared.

API keys are read from arguments or the environment, sent only to the server,
and never written to recordings, logs, error messages or reprs.
"""

from __future__ import annotations

import json
import logging
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Literal, Protocol, runtime_checkable

from forcelayout._optional import import_optional

openai = import_optional("openai", "llm")

__all__ = [
    "ChatClient",
    "Message",
    "LLMRequestError",
    "ReplayError",
    "OpenAIChatClient",
    "RecordingClient",
    "ReplayClient",
    "DEFAULT_MODEL",
    "RECORDING_VERSION",
]

log = logging.getLogger("forcelayout.llm")

#: A chat message: ``{"role": "system" | "user" | "assistant", "content": str}``.
Message = Mapping[str, str]
#: Model used when neither an argument nor ``FORCELAYOUT_LLM_MODEL`` names one
#: (the model of the method paper).
DEFAULT_MODEL = "gpt-4o-2024-08-06"
#: Version tag written on every line of a recording.
RECORDING_VERSION = 1
_MAX_ERROR_CHARS = 300


class LLMRequestError(RuntimeError):
    """A request to the language model failed (timeout, HTTP error, no connection).

    Attributes
    ----------
    retryable : bool
        True for failures worth retrying: timeouts, lost connections, HTTP 429
        and 5xx. False for e.g. a wrong API key or an unknown model.
    """

    def __init__(self, message: str, *, retryable: bool = True):
        super().__init__(message)
        self.retryable = retryable


class ReplayError(RuntimeError):
    """A replayed run asked for something its recording does not hold."""


@runtime_checkable
class ChatClient(Protocol):
    """What the planner needs from a language model: one chat completion.

    Implementations send ``messages`` and return the assistant reply's text.
    ``schema`` is the JSON Schema the reply must follow and ``name`` names
    it (and the planning step); a client may use them for structured output
    or ignore them (the planner parses and validates every reply anyway).
    Transport failures raise :class:`LLMRequestError`.
    """

    def complete(
        self, messages: Sequence[Message], *, schema: dict[str, Any] | None = None,
        name: str = "reply",
    ) -> str:
        """Send ``messages``; return the reply text."""
        ...


def _redact(text: str, secret: str | None) -> str:
    if secret and len(secret) >= 4:
        text = text.replace(secret, "***")
    return text[:_MAX_ERROR_CHARS] + ("..." if len(text) > _MAX_ERROR_CHARS else "")


class OpenAIChatClient:
    """A :class:`ChatClient` over the ``openai`` SDK's chat-completions API.

    Works with every server that speaks that API: OpenAI, vLLM
    (``http://localhost:8000/v1``), Ollama (``http://localhost:11434/v1``),
    LM Studio (``http://localhost:1234/v1``), llama.cpp and others.

    Parameters
    ----------
    base_url : str, optional
        Server URL ending in ``/v1``; default ``$OPENAI_BASE_URL``, else OpenAI.
    model : str, optional
        Model name; default ``$FORCELAYOUT_LLM_MODEL``, else :data:`DEFAULT_MODEL`.
    api_key : str, optional
        Default ``$OPENAI_API_KEY``. Local servers that need no key get a
        placeholder. Never logged, recorded or shown.
    timeout : float, default 60
        Seconds to wait for one reply.
    max_retries : int, default 2
        Retries the SDK itself makes on connection errors, 429 and 5xx, with
        back-off (the planner retries failed steps on top of this).
    temperature : float, optional
        Sampling temperature; the server's default when None.
    seed : int, optional
        Sampling seed, for servers that honour it.
    structured : {"auto", "json_schema", "none"}, default "auto"
        How to ask for JSON: ``"json_schema"`` sends the schema as
        ``response_format`` (structured output); ``"none"`` relies on the
        prompt (the reply's JSON is cut out of the text); ``"auto"`` tries
        structured output and falls back to ``"none"`` for the rest of the
        session if the server rejects it.
    max_tokens : int, optional
        Cap on the reply's length in tokens.
    """

    def __init__(
        self, *, base_url: str | None = None, model: str | None = None,
        api_key: str | None = None, timeout: float = 60.0, max_retries: int = 2,
        temperature: float | None = None, seed: int | None = None,
        structured: Literal["auto", "json_schema", "none"] = "auto",
        max_tokens: int | None = None,
    ):
        if structured not in ("auto", "json_schema", "none"):
            raise ValueError(f"structured={structured!r}; use 'auto', 'json_schema' or 'none'")
        if timeout <= 0:
            raise ValueError(f"timeout={timeout!r} s; give a positive number of seconds")
        self.base_url = base_url or os.environ.get("OPENAI_BASE_URL") or None
        self.model = model or os.environ.get("FORCELAYOUT_LLM_MODEL") or DEFAULT_MODEL
        key = api_key or os.environ.get("OPENAI_API_KEY")
        if not key:
            if self.base_url is None:
                raise LLMRequestError(
                    "no API key: set OPENAI_API_KEY (or pass api_key=...), or point base_url / "
                    "OPENAI_BASE_URL at a local OpenAI-compatible server such as vLLM or Ollama",
                    retryable=False)
            key = "not-needed"  # local servers ignore it; the SDK requires one
        self.__key = key
        self.timeout = float(timeout)
        self.temperature = temperature
        self.seed = seed
        self.max_tokens = max_tokens
        self.structured = structured
        self._sdk = openai.OpenAI(base_url=self.base_url, api_key=key, timeout=self.timeout,
                                  max_retries=int(max_retries))

    def __repr__(self) -> str:
        return (f"OpenAIChatClient(base_url={self.base_url!r}, model={self.model!r}, "
                f"timeout={self.timeout:g}, structured={self.structured!r})")

    def complete(
        self, messages: Sequence[Message], *, schema: dict[str, Any] | None = None,
        name: str = "reply",
    ) -> str:
        """Send ``messages`` to the server; return the reply text.

        Raises
        ------
        LLMRequestError
            On timeout, lost connection, or an HTTP error status.
        """
        kwargs: dict[str, Any] = {"model": self.model,
                                  "messages": [dict(m) for m in messages]}
        if self.temperature is not None:
            kwargs["temperature"] = self.temperature
        if self.seed is not None:
            kwargs["seed"] = self.seed
        if self.max_tokens is not None:
            kwargs["max_tokens"] = self.max_tokens
        if schema is not None and self.structured in ("auto", "json_schema"):
            fmt = {"type": "json_schema",
                   "json_schema": {"name": name, "schema": schema, "strict": False}}
            try:
                return self._send({**kwargs, "response_format": fmt})
            except LLMRequestError as e:
                if self.structured != "auto" or getattr(e, "status", None) not in (400, 422):
                    raise
                log.info("server rejected structured output (%s); asking for JSON in text", e)
                self.structured = "none"
        return self._send(kwargs)

    def _send(self, kwargs: dict[str, Any]) -> str:
        try:
            resp = self._sdk.chat.completions.create(**kwargs)
        except openai.APITimeoutError:
            raise LLMRequestError(f"no reply within {self.timeout:g} s from "
                                  f"{self._where()}; raise timeout= or use a faster model"
                                  ) from None
        except openai.APIConnectionError as e:
            raise LLMRequestError(f"could not reach {self._where()}: "
                                  f"{_redact(str(e), self.__key)}") from None
        except openai.APIStatusError as e:
            status = int(e.status_code)
            err = LLMRequestError(
                f"{self._where()} answered HTTP {status}: {_redact(str(e.message), self.__key)}",
                retryable=status == 429 or status >= 500)
            err.status = status  # type: ignore[attr-defined]
            raise err from None
        if not resp.choices:
            raise LLMRequestError(f"{self._where()} sent a reply without choices")
        choice = resp.choices[0]
        content = choice.message.content or ""
        if choice.finish_reason == "length":
            log.warning("the reply was cut off at the token limit; it may not parse")
        return content

    def _where(self) -> str:
        return f"the server at {self.base_url or 'api.openai.com'} (model {self.model!r})"


class RecordingClient:
    """Wrap a client and write every request and reply to a JSONL file.

    Each line holds ``{"v", "name", "model", "messages", "reply"}`` (or
    ``"error"`` instead of ``"reply"`` for a failed request) — no headers and
    no API key. :class:`ReplayClient` answers from the file.

    Parameters
    ----------
    inner : ChatClient
        The client that really answers.
    path : str or Path
        The JSONL file; truncated when the recording starts.
    """

    def __init__(self, inner: ChatClient, path: str | Path):
        self.inner = inner
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.path.write_text("", encoding="utf-8")

    def __repr__(self) -> str:
        return f"RecordingClient({self.inner!r}, path={str(self.path)!r})"

    def complete(
        self, messages: Sequence[Message], *, schema: dict[str, Any] | None = None,
        name: str = "reply",
    ) -> str:
        """Forward to the inner client and append the exchange to the file."""
        entry: dict[str, Any] = {"v": RECORDING_VERSION, "name": name,
                                 "model": getattr(self.inner, "model", None),
                                 "messages": [dict(m) for m in messages]}
        try:
            reply = self.inner.complete(messages, schema=schema, name=name)
        except LLMRequestError as e:
            entry["error"] = {"message": str(e), "retryable": e.retryable}
            self._write(entry)
            raise
        entry["reply"] = reply
        self._write(entry)
        return reply

    def _write(self, entry: dict[str, Any]) -> None:
        with self.path.open("a", encoding="utf-8") as f:
            f.write(json.dumps(entry, ensure_ascii=False) + "\n")


class ReplayClient:
    """Answer requests from a JSONL recording, in order, without any server.

    Parameters
    ----------
    path : str or Path
        A file written by :class:`RecordingClient`.
    strict : bool, default False
        Also require each request's messages to equal the recorded ones.
        By default only the step names must match, so a recording survives
        wording changes of the prompts (e.g. a newly registered rule).

    Raises
    ------
    ReplayError
        When the run asks for more requests than were recorded, or for a
        different step than the recording holds next.
    """

    def __init__(self, path: str | Path, *, strict: bool = False):
        self.path = Path(path)
        self.strict = strict
        self.model: str | None = None
        self._entries: list[dict[str, Any]] = []
        text = self.path.read_text(encoding="utf-8")
        for n, line in enumerate(text.splitlines(), start=1):
            if not line.strip():
                continue
            try:
                entry = json.loads(line)
            except json.JSONDecodeError as e:
                raise ReplayError(f"{self.path}:{n}: not a JSON line ({e.msg})") from None
            if not isinstance(entry, dict) or "name" not in entry or not (
                    "reply" in entry or "error" in entry):
                raise ReplayError(f"{self.path}:{n}: not a forcelayout LLM recording line "
                                  "(needs 'name' and 'reply' or 'error')")
            self._entries.append(entry)
        if self._entries:
            self.model = self._entries[0].get("model")
        self._next = 0

    def __repr__(self) -> str:
        return (f"ReplayClient({str(self.path)!r}, {self._next}/{len(self._entries)} "
                "replies used)")

    @property
    def remaining(self) -> int:
        """Recorded replies not used yet."""
        return len(self._entries) - self._next

    def complete(
        self, messages: Sequence[Message], *, schema: dict[str, Any] | None = None,
        name: str = "reply",
    ) -> str:
        """Return the next recorded reply (or raise the recorded error)."""
        k = self._next
        if k >= len(self._entries):
            raise ReplayError(
                f"{self.path} holds {len(self._entries)} replies but the run asked for more "
                f"(step {name!r}); the prompts, rules or validation changed since it was "
                "recorded — record the run again")
        entry = self._entries[k]
        if entry["name"] != name:
            raise ReplayError(f"{self.path} line {k + 1}: recorded step {entry['name']!r} but "
                              f"the run asks for step {name!r}; record the run again")
        if self.strict and entry.get("messages") != [dict(m) for m in messages]:
            raise ReplayError(f"{self.path} line {k + 1}: the request of step {name!r} differs "
                              "from the recorded one (strict replay)")
        self._next += 1
        if "error" in entry:
            err = entry["error"] or {}
            raise LLMRequestError(str(err.get("message", "recorded failure")),
                                  retryable=bool(err.get("retryable", True)))
        return str(entry["reply"])
