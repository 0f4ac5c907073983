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
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Literal, Protocol, runtime_checkable

from forcelayout._optional import import_optional
from forcelayout._text import one_line

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
    "STRUCTURED_MODES",
    "estimate_tokens",
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


#: The structured-output modes, most specific first.
STRUCTURED_MODES = ("auto", "json_schema", "json_object", "none")
Structured = Literal["auto", "json_schema", "json_object", "none"]
_NEXT_MODE = {"json_schema": "json_object", "json_object": "none"}
_MODE_TEXT = {"json_object": "response_format json_object with the schema",
              "none": "no response_format (JSON asked for in the prompt)"}
_CONTEXT = re.compile(
    r"context (length|window|size)|maximum context|n_ctx|exceeds? (the )?(available )?context"
    r"|too many tokens|prompt is too long|max_model_len|input is too long", re.IGNORECASE)
_FORMAT_WORDS = re.compile(r"response_format|json_schema|json_object|schema|grammar|"
                           r"format|structured", re.IGNORECASE)
#: Characters per token assumed when a server does not say how long a request was.
CHARS_PER_TOKEN = 4


def _format(mode: str, name: str, schema: dict[str, Any]) -> dict[str, Any]:
    if mode == "json_schema":
        return {"type": "json_schema",
                "json_schema": {"name": name, "schema": schema, "strict": False}}
    return {"type": "json_object", "schema": schema}


def _rejects_format(e: LLMRequestError) -> bool:
    """Whether a failed structured request means "this format is not supported here"."""
    if getattr(e, "kind", None) == "context":
        return False
    status = getattr(e, "status", None)
    if status in (400, 415, 422):
        return True
    if status in (500, 501):
        return bool(_FORMAT_WORDS.search(getattr(e, "detail", "") or str(e)))
    return False


def estimate_tokens(messages: Sequence[Message]) -> int:
    """A rough token count of chat messages (characters / 4, plus a few per message)."""
    return sum(len(str(m.get("content", ""))) // CHARS_PER_TOKEN + 4 for m in messages)


def _context_message(where: str, detail: str, kwargs: dict[str, Any]) -> str:
    ctx = re.search(r"(?:context (?:length|window|size)(?: is| of)?|n_ctx[ =:]*|max_model_len"
                    r"[ =:]*)\D{0,20}?(\d{3,7})", detail, re.IGNORECASE)
    asked = re.search(r"(?:requested|you requested|request has|prompt has|n_prompt_tokens"
                      r"\W*)\D{0,20}?(\d{3,7})", detail, re.IGNORECASE)
    need = estimate_tokens(kwargs["messages"]) + int(kwargs.get("max_tokens") or 2048)
    have = f"its context of {ctx.group(1)} tokens" if ctx else "its context"
    size = f"{asked.group(1)} tokens" if asked else f"about {need} tokens"
    return (f"the request does not fit the context of {where}: it needs {size} (prompt and "
            f"reply), more than {have}. Start the server with a context of at least 8192 "
            "tokens, 16384 to be safe: llama-cpp-python --n_ctx 16384, llama-server -c 16384, "
            "Ollama OLLAMA_CONTEXT_LENGTH=16384 (or num_ctx), vLLM --max-model-len 16384, "
            f"LM Studio's context length setting (server said: {one_line(detail, 160)})")


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
    A client whose ``complete`` also takes ``timeout=`` is given what is left
    of the step's time budget. Transport failures raise :class:`LLMRequestError`.
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
        back-off, when :meth:`complete` is called without ``timeout``. The
        planner passes a ``timeout`` (what is left of its step's budget) and
        then the SDK makes no retries of its own: the planner's attempts are
        the retries, each listed in its errors.
    temperature : float, optional
        Sampling temperature; the server's default when None.
    seed : int, optional
        Sampling seed, for servers that honour it.
    structured : {"auto", "json_schema", "json_object", "none"}, default "auto"
        How to ask for JSON: ``"json_schema"`` sends the schema as
        ``response_format`` of type ``json_schema`` (OpenAI, vLLM, Ollama, LM
        Studio, llama.cpp's ``llama-server``); ``"json_object"`` sends type
        ``json_object`` with the schema beside it (llama-cpp-python and
        llama.cpp turn it into a grammar); ``"none"`` relies on the prompt
        (the reply's JSON is cut out of the text). ``"auto"`` negotiates:
        json_schema, then json_object, then none, moving down on any
        rejection (HTTP 400 or 422, or a 5xx whose message is about the
        format or the schema) — logged once per server at WARNING — and
        keeping what worked for the rest of the session.
    max_tokens : int, optional
        Cap on the reply's length in tokens.
    """

    def __init__(
        self, *, base_url: str | None = None, model: str | None = None,
        api_key: str | None = None, timeout: float = 60.0, max_retries: int = 2,
        temperature: float | None = None, seed: int | None = None,
        structured: Structured = "auto",
        max_tokens: int | None = None,
    ):
        if structured not in STRUCTURED_MODES:
            raise ValueError(f"structured={structured!r}; use one of "
                             f"{', '.join(repr(m) for m in STRUCTURED_MODES)}")
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
        #: Structured-output mode in use: the one given, or in ``"auto"`` the
        #: one negotiated so far.
        self.mode: str = "json_schema" if structured == "auto" else structured
        self.max_retries = int(max_retries)
        self._openai = import_optional("openai", "llm")
        self._sdk = self._openai.OpenAI(base_url=self.base_url, api_key=key, timeout=self.timeout,
                                  max_retries=int(max_retries))

    def __repr__(self) -> str:
        return (f"OpenAIChatClient(base_url={self.base_url!r}, model={self.model!r}, "
                f"timeout={self.timeout:g}, structured={self.structured!r})")

    def complete(
        self, messages: Sequence[Message], *, schema: dict[str, Any] | None = None,
        name: str = "reply", timeout: float | None = None,
    ) -> str:
        """Send ``messages`` to the server; return the reply text.

        Parameters
        ----------
        timeout : float, optional
            Seconds this call may take at most (the rest of the caller's
            budget); the SDK then makes no retries of its own. Default: the
            client's ``timeout`` per request, with the SDK's ``max_retries``.

        Raises
        ------
        LLMRequestError
            On timeout, lost connection, or an HTTP error status; a request
            larger than the server's context raises one with
            ``kind == "context"`` and the size needed.
        """
        kwargs: dict[str, Any] = {"model": self.model,
                                  "messages": [dict(m) for m in messages]}
        if self.temperature is not None:
            kwargs["temperature"] = self.temperature
        if self.seed is not None:
            kwargs["seed"] = self.seed
        if self.max_tokens is not None:
            kwargs["max_tokens"] = self.max_tokens
        sdk = self._sdk
        if timeout is not None:
            sdk = self._sdk.with_options(timeout=max(0.1, min(float(timeout), self.timeout)),
                                         max_retries=0)
        while schema is not None and self.mode != "none":
            try:
                return self._send(sdk, {**kwargs, "response_format": _format(self.mode, name,
                                                                           schema)})
            except LLMRequestError as e:
                if self.structured != "auto" or not _rejects_format(e):
                    raise
                lower = _NEXT_MODE[self.mode]
                log.warning("the server at %s rejected response_format %r (%s); asking with %s "
                            "for the rest of the session (set structured= / --structured to "
                            "skip this)", self.base_url or "api.openai.com", self.mode,
                            one_line(str(e), 160), _MODE_TEXT[lower])
                self.mode = lower
        return self._send(sdk, kwargs)

    def _send(self, sdk: Any, kwargs: dict[str, Any]) -> str:
        openai = self._openai
        try:
            resp = sdk.chat.completions.create(**kwargs)
        except openai.APITimeoutError:
            raise LLMRequestError(f"no reply within {float(sdk.timeout):.3g} s from "
                                  f"{self._where()}; raise --llm-timeout (timeout= in Python) "
                                  "or use a faster model") from None
        except openai.APIConnectionError as e:
            raise LLMRequestError(f"could not reach {self._where()}: "
                                  f"{_redact(str(e), self.__key)}") from None
        except openai.APIStatusError as e:
            status = int(e.status_code)
            text = _redact(str(e.message), self.__key)
            if _CONTEXT.search(str(e.message)):
                err = LLMRequestError(_context_message(self._where(), str(e.message), kwargs),
                                      retryable=False)
                err.kind = "context"  # type: ignore[attr-defined]
            else:
                err = LLMRequestError(f"{self._where()} answered HTTP {status}: {text}",
                                      retryable=status == 429 or status >= 500)
            err.status = status  # type: ignore[attr-defined]
            err.detail = str(e.message)  # type: ignore[attr-defined]
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
        name: str = "reply", timeout: float | None = None,
    ) -> str:
        """Forward to the inner client and append the exchange to the file."""
        entry: dict[str, Any] = {"v": RECORDING_VERSION, "name": name,
                                 "model": getattr(self.inner, "model", None),
                                 "messages": [dict(m) for m in messages]}
        try:
            reply = call_client(self.inner, messages, schema=schema, name=name,
                                timeout=timeout)
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
        name: str = "reply", timeout: float | None = None,
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


def call_client(client: ChatClient, messages: Sequence[Message], *,
                schema: dict[str, Any] | None, name: str, timeout: float | None) -> str:
    """``client.complete(...)``, passing ``timeout`` only to clients that take it."""
    if timeout is not None and _takes_timeout(client):
        return client.complete(messages, schema=schema, name=name,  # type: ignore[call-arg]
                               timeout=timeout)
    return client.complete(messages, schema=schema, name=name)


def _takes_timeout(client: Any) -> bool:
    import inspect

    try:
        params = inspect.signature(client.complete).parameters
    except (TypeError, ValueError):
        return False
    return "timeout" in params or any(p.kind is p.VAR_KEYWORD for p in params.values())
