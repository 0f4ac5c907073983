"""A real HTTP server on 127.0.0.1 that speaks the chat-completions protocol.

The ``openai`` SDK talks to it unchanged. It answers each request with the
next scripted reply, so tests can send malformed JSON, unknown rules, plans
that cannot fit, slow replies (timeouts) and HTTP errors. It is bounded: a
request cap, an interruptible delay with a ceiling, and ``close()`` (the
fixture's teardown) stops it.

Scripted reply items:

* ``str`` — the assistant message content;
* ``{"content": str, "delay": s}`` — reply after ``delay`` seconds;
* ``{"status": int, "message": str}`` — an HTTP error with an OpenAI-style body;
* ``{"refusal": str}`` — a refusal as OpenAI sends one: ``content`` null,
  the text in ``refusal``.

Messages may carry images as OpenAI's vision API does (``content`` a list of
``{"type": "text", "text": ...}`` and ``{"type": "image_url", "image_url":
{"url": "data:image/png;base64,..."}}`` parts); a malformed part gets HTTP
400 like a real server, and :meth:`FakeChatServer.images` decodes them.

Run as a script to rewrite the example recording from scripted replies::

    python tests/fake_openai.py examples/data/llm_bedroom.jsonl
"""

from __future__ import annotations

import base64
import binascii
import json
import threading
from collections.abc import Sequence
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any

MAX_REQUESTS = 200
MAX_DELAY = 5.0


class FakeChatServer:
    """Scripted chat-completions server on ``127.0.0.1`` (a free port).

    Parameters
    ----------
    replies : sequence
        Scripted replies, one per request, in order (see module docstring).
    json_schema, json_object : bool or (int, str), default True
        Whether ``response_format`` of that type is accepted. False: such
        requests get HTTP 400 without using a scripted reply (a server without
        that kind of structured output); ``(status, message)``: that error
        (e.g. llama-cpp-python's HTTP 500 for ``json_schema``).
    echo_schema : bool, default False
        Answer a request without ``response_format`` with the JSON Schema
        its prompt ends with, else the room step's (what small models do when
        nothing constrains them), using no scripted reply.
    context : int, optional
        The context length in tokens (characters / 4): a longer request gets
        HTTP 400 "maximum context length is N tokens" without using a reply.
    """

    def __init__(self, replies: Sequence[Any], *, json_schema: Any = True,
                 json_object: Any = True, echo_schema: bool = False,
                 context: int | None = None):
        self.replies = list(replies)
        self.json_schema = json_schema
        self.json_object = json_object
        self.echo_schema = echo_schema
        self.context = context
        self.requests: list[dict[str, Any]] = []
        #: ``response_format`` types refused, in order (requests that used no script item).
        self.rejected: list[str] = []
        self.headers: list[dict[str, str]] = []
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._httpd = ThreadingHTTPServer(("127.0.0.1", 0), self._handler())
        self._httpd.daemon_threads = True
        self._thread = threading.Thread(target=self._httpd.serve_forever,
                                        kwargs={"poll_interval": 0.05}, daemon=True)
        self._thread.start()

    @property
    def url(self) -> str:
        """Base URL for the SDK, ending in ``/v1``."""
        return f"http://127.0.0.1:{self._httpd.server_address[1]}/v1"

    @property
    def remaining(self) -> int:
        """Scripted replies not used yet."""
        return len(self.replies)

    def close(self) -> None:
        """Stop serving (interrupts pending delays)."""
        self._stop.set()
        self._httpd.shutdown()
        self._httpd.server_close()
        self._thread.join(timeout=5)

    def __enter__(self) -> FakeChatServer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def user_messages(self) -> list[str]:
        """The last message of every request received, in order."""
        return [r["messages"][-1]["content"] for r in self.requests]

    def images(self, k: int = -1) -> list[bytes]:
        """The images of request ``k`` (default the last), decoded, in message order."""
        out = []
        for m in self.requests[k]["messages"]:
            if isinstance(m.get("content"), list):
                for part in m["content"]:
                    if part.get("type") == "image_url":
                        url = part["image_url"]["url"]
                        out.append(base64.b64decode(url.partition("base64,")[2]))
        return out

    def _next(self, body: dict[str, Any]) -> Any:
        with self._lock:
            if len(self.requests) + len(self.rejected) >= MAX_REQUESTS:
                return {"status": 503, "message": "request cap of the fake server reached"}
            bad = _bad_content(body)
            if bad:
                return {"status": 400, "message": bad}
            fmt = (body.get("response_format") or {}).get("type")
            accept = {"json_schema": self.json_schema, "json_object": self.json_object}.get(fmt,
                                                                                         True)
            if accept is not True:
                self.rejected.append(fmt)
                status, message = accept if isinstance(accept, tuple) else (
                    400, f"response_format {fmt} not supported")
                return {"status": status, "message": message}
            if self.context is not None:
                tokens = sum(len(m.get("content") or "") for m in body["messages"]) // 4
                if tokens > self.context:
                    self.rejected.append(f"context:{fmt}")
                    return {"status": 400, "message": (
                        f"This model's maximum context length is {self.context} tokens. However, "
                        f"you requested {tokens + 512} tokens ({tokens} in the messages, 512 in "
                        "the completion). Please reduce the length of the messages.")}
            self.requests.append(body)
            if self.echo_schema and fmt is None:
                text = body["messages"][-1]["content"]
                if "schema:\n" in text:
                    return text.rsplit("schema:\n", 1)[1]
                from forcelayout.llm.steps import RoomStep, schema_for

                return json.dumps(schema_for(RoomStep))
            if not self.replies:
                return {"status": 500, "message": "the fake server's script is exhausted"}
            return self.replies.pop(0)

    def _handler(self) -> type[BaseHTTPRequestHandler]:
        server = self

        class Handler(BaseHTTPRequestHandler):
            def log_message(self, *args: object) -> None:  # keep test output clean
                pass

            def _send(self, status: int, payload: dict[str, Any]) -> None:
                data = json.dumps(payload).encode()
                try:
                    self.send_response(status)
                    self.send_header("Content-Type", "application/json")
                    self.send_header("Content-Length", str(len(data)))
                    self.end_headers()
                    self.wfile.write(data)
                except (BrokenPipeError, ConnectionResetError):
                    pass  # the client gave up (timeout)

            def do_POST(self) -> None:  # noqa: N802 (http.server API)
                if self.path.rstrip("/") not in ("/v1/chat/completions", "/chat/completions"):
                    self._send(404, {"error": {"message": f"no route {self.path}"}})
                    return
                length = int(self.headers.get("Content-Length") or 0)
                try:
                    body = json.loads(self.rfile.read(length) or b"{}")
                except json.JSONDecodeError:
                    self._send(400, {"error": {"message": "request body is not JSON"}})
                    return
                with server._lock:
                    server.headers.append(dict(self.headers))
                item = server._next(body)
                if isinstance(item, str):
                    item = {"content": item}
                if "status" in item:
                    self._send(int(item["status"]), {"error": {
                        "message": item.get("message", "scripted error"), "type": "server_error",
                        "code": None}})
                    return
                delay = min(float(item.get("delay", 0.0)), MAX_DELAY)
                if delay and server._stop.wait(delay):
                    return
                message = {"role": "assistant", "content": item.get("content")}
                if "refusal" in item:
                    message["refusal"] = item["refusal"]
                self._send(200, {
                    "id": f"chatcmpl-fake-{len(server.requests)}", "object": "chat.completion",
                    "created": 0, "model": body.get("model", "fake"),
                    "choices": [{"index": 0, "finish_reason": "stop", "logprobs": None,
                                 "message": message}],
                    "usage": {"prompt_tokens": 0, "completion_tokens": 0, "total_tokens": 0}})

        return Handler


def _bad_content(body: dict[str, Any]) -> str | None:
    """What is wrong with the request's message contents (text or vision parts), or None."""
    for i, m in enumerate(body.get("messages") or []):
        content = m.get("content")
        if isinstance(content, str) or content is None:
            continue
        if not isinstance(content, list):
            return f"messages[{i}].content must be a string or a list of parts"
        for j, part in enumerate(content):
            kind = part.get("type") if isinstance(part, dict) else None
            if kind == "text" and isinstance(part.get("text"), str):
                continue
            if kind == "image_url":
                url = (part.get("image_url") or {}).get("url", "")
                head, _, data = url.partition(";base64,")
                if head.startswith("data:image/") and data:
                    try:
                        base64.b64decode(data, validate=True)
                        continue
                    except (binascii.Error, ValueError):
                        pass
                return f"messages[{i}].content[{j}]: image_url needs a base64 data URL"
            return f"messages[{i}].content[{j}]: unknown content part {kind!r}"
    return None


# -- scripted replies of a small bedroom -------------------------------------------------

ROOM = {
    "name": "student_bedroom", "description": "A student's bedroom with a desk by the window.",
    "shape": "rectangular, 4 x 3.5 m",
    "room": {"polygon": [[0, 0], [4, 0], [4, 3.5], [0, 3.5]], "height": 2.7,
             "doors": [{"wall": 0, "offset": 1.0, "width": 0.9}],
             "windows": [{"wall": 2, "offset": 2.0, "width": 1.2, "sill": 0.9,
                          "height": 1.2}]},
    "areas": [{"name": "sleeping", "description": "bed and nightstand"},
              {"name": "work", "description": "desk and chair by the window"}],
}
OBJECTS = {
    "objects": [
        {"id": "bed", "category": "bed", "description": "single bed with a wooden frame",
         "size": [1.0, 2.0, 0.5], "area": "sleeping", "primary": True},
        {"id": "nightstand_1", "category": "nightstand", "description": "small nightstand",
         "size": [0.45, 0.4, 0.5], "area": "sleeping", "primary": False},
        {"id": "desk", "category": "desk", "description": "study desk",
         "size": [1.2, 0.6, 0.75], "area": "work", "primary": True},
        {"id": "desk_chair", "category": "chair", "description": "swivel chair",
         "size": [0.5, 0.5, 0.9], "area": "work", "primary": False},
    ],
    "rules": [
        {"rule": "at_wall", "object": "bed"},
        {"rule": "next_to", "object": "nightstand_1", "target": "bed"},
        {"rule": "at_wall", "object": "desk"},
        {"rule": "next_to", "object": "desk_chair", "target": "desk"},
    ],
}
GRAPH = {
    "areas": [{"name": "sleeping", "description": "bed and nightstand",
               "rules": [{"rule": "at_wall"}], "objects": ["bed", "nightstand_1"]},
              {"name": "work", "description": "desk and chair",
               "rules": [], "objects": ["desk", "desk_chair"]}],
    "support": [],
}
DECOR = {
    "objects": [{"id": "plant", "category": "plant", "description": "potted plant",
                 "size": [0.35, 0.35, 0.9], "area": "work"}],
    "rules": [{"rule": "next_to", "object": "plant", "target": "desk"}],
}
CHECK_OK = {"issues": [], "plan": None}


def bedroom_script(*, decor: bool = True, check: bool = True) -> list[str]:
    """Good replies for the five steps of planning the small bedroom."""
    out = [json.dumps(ROOM), json.dumps(OBJECTS), json.dumps(GRAPH)]
    if decor:
        out.append(json.dumps(DECOR))
    if check:
        out.append(json.dumps(CHECK_OK))
    return out


def with_unknown_rule() -> str:
    """The objects step naming a rule that is not in the vocabulary ('hovers_over')."""
    bad = json.loads(json.dumps(OBJECTS))
    bad["rules"][1]["rule"] = "hovers_over"
    return json.dumps(bad)


def _record_example(path: str) -> None:
    """Write the example recording: a scripted run, one unknown rule repaired on the way."""
    from forcelayout.llm import Planner, make_client

    script = bedroom_script()
    script.insert(1, "Sure! ```json\n" + with_unknown_rule() + "\n```")
    with FakeChatServer(script) as srv:
        client = make_client(record=path, base_url=srv.url, model="scripted-fake-server",
                             api_key="not-a-key", timeout=5.0, max_retries=0)
        plan = Planner(client).plan("a student's bedroom")
    print(f"recorded {path}: {plan.name}, {len(plan.objects)} objects")


if __name__ == "__main__":
    import sys

    _record_example(sys.argv[1] if len(sys.argv) > 1 else "examples/data/llm_bedroom.jsonl")
