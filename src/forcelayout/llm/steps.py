"""The structured replies of the planning steps, as pydantic models.

Each step of the planner asks for one JSON object following one of these
models' JSON Schema; the reply is parsed with :func:`parse_reply` and turned
into part of a :class:`forcelayout.Plan`. The models are deliberately plain
(lists instead of tuples, few constraints) so that any structured-output
backend accepts their schema; the plan's own validation is the real check.
Rule names are restricted to the registry's vocabulary by an ``enum`` added
to the schema at request time (see :func:`schema_for`).
"""

from __future__ import annotations

import copy
import json
import re
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, ValidationError

__all__ = [
    "OpeningDraft",
    "WindowDraft",
    "RoomDraft",
    "AreaDraft",
    "ObjectDraft",
    "RuleDraft",
    "AreaRuleDraft",
    "RoomStep",
    "ObjectsStep",
    "GraphArea",
    "SupportEdge",
    "SceneGraphStep",
    "DecorStep",
    "PlanDraft",
    "SelfCheckStep",
    "CheckIssues",
    "MAX_ISSUES",
    "PromptList",
    "ReplyError",
    "parse_reply",
    "close_cut_reply",
    "schema_for",
    "shape_of",
    "MAX_REPLY_CHARS",
    "MAX_OBJECTS",
]

#: Longest reply text parsed, characters; longer replies are rejected.
MAX_REPLY_CHARS = 200_000
#: Most objects one step may add (a room plan has up to about 22; the bound is also in
#: the JSON Schema, so a server that turns the schema into a grammar stops a runaway list).
MAX_OBJECTS = 24
#: Most rules (and area memberships, support bonds) one step may add.
MAX_RULES = 40


class _Draft(BaseModel):
    model_config = ConfigDict(extra="ignore")


class OpeningDraft(_Draft):
    """A door on a wall."""

    wall: int = Field(description="Index i of the wall polygon[i] -> polygon[i+1].")
    offset: float = Field(description="Distance of the door's centre from polygon[i], m.")
    width: float = Field(0.9, description="Width along the wall, m.")


class WindowDraft(OpeningDraft):
    """A window on a wall."""

    width: float = Field(1.2, description="Width along the wall, m.")
    sill: float = Field(0.9, description="Height of the bottom edge above the floor, m.")
    height: float = Field(1.2, description="Window height, m.")


class RoomDraft(_Draft):
    """The room's floor polygon, height, doors and windows."""

    polygon: list[list[float]] = Field(
        description="Floor corners [x, y] in metres, in order around the room.")
    height: float = Field(2.7, description="Ceiling height, m.")
    doors: list[OpeningDraft] = Field(default_factory=list)
    windows: list[WindowDraft] = Field(default_factory=list)


class AreaDraft(_Draft):
    """A functional area of the room (e.g. 'sleeping')."""

    name: str = Field(description="Short snake_case name, e.g. 'sleeping'.")
    description: str = ""


class RoomStep(_Draft):
    """Step 1: room properties and functional areas."""

    name: str = Field(description="Short snake_case name of the scene, e.g. 'student_bedroom'.")
    description: str = Field("", description="One sentence describing the scene.")
    shape: str = Field("", description="The room's shape in words, e.g. 'rectangular, 4 x 3.5 m'.")
    room: RoomDraft
    areas: list[AreaDraft] = Field(default_factory=list)


class ObjectDraft(_Draft):
    """One object of the scene."""

    id: str = Field(description="Unique id of letters, digits and _ , e.g. 'nightstand_1'.")
    category: str = Field(description="Object class, e.g. 'nightstand'.")
    description: str = Field("", description="Looks and material, for finding a 3D model.")
    size: list[float] = Field(min_length=3, max_length=3,
                              description="[width, depth, height] in metres; front is the "
                                          "depth side.")
    area: str | None = Field(None, description="Name of the functional area it belongs to.")
    primary: bool = Field(False, description="Main furniture that must be reachable.")


class RuleDraft(_Draft):
    """One placement rule or relation from the vocabulary."""

    rule: str = Field(description="Rule name from the vocabulary.")
    object: str = Field(description="Id of the object the rule places.")
    target: str | None = Field(None, description="Id of the other object, for relations.")
    params: dict[str, Any] = Field(default_factory=dict,
                                   description="Optional rule parameters (see vocabulary).")


class ObjectsStep(_Draft):
    """Step 2: the objects with sizes, and their placement rules and relations."""

    objects: list[ObjectDraft] = Field(min_length=1, max_length=MAX_OBJECTS)
    rules: list[RuleDraft] = Field(default_factory=list, max_length=MAX_RULES)


class AreaRuleDraft(_Draft):
    """A placement rule for a whole functional area (unary rules only)."""

    rule: str
    params: dict[str, Any] = Field(default_factory=dict)


class GraphArea(_Draft):
    """A node of the scene graph: an area with its member objects."""

    name: str
    description: str = ""
    rules: list[AreaRuleDraft] = Field(default_factory=list, max_length=MAX_RULES)
    objects: list[str] = Field(default_factory=list, max_length=MAX_OBJECTS,
                               description="Ids of the area's objects.")


class SupportEdge(_Draft):
    """A parent-child bond: ``object`` rests on top of ``parent``."""

    object: str
    parent: str


class SceneGraphStep(_Draft):
    """Step 3: the scene graph: areas -> objects, and objects resting on others."""

    areas: list[GraphArea] = Field(default_factory=list)
    support: list[SupportEdge] = Field(default_factory=list, max_length=MAX_RULES)


class DecorStep(_Draft):
    """Step 4: secondary decorative items and their rules."""

    objects: list[ObjectDraft] = Field(default_factory=list, max_length=MAX_OBJECTS)
    rules: list[RuleDraft] = Field(default_factory=list, max_length=MAX_RULES)


class PlanObjectDraft(ObjectDraft):
    """An object of a whole plan, with its decor flag."""

    decor: bool = False


class PlanAreaDraft(AreaDraft):
    """A functional area of a whole plan, with its area rules."""

    rules: list[AreaRuleDraft] = Field(default_factory=list, max_length=MAX_RULES)


class PlanDraft(_Draft):
    """A whole plan (the self-check step's corrected version)."""

    name: str
    description: str = ""
    room: RoomDraft
    areas: list[PlanAreaDraft] = Field(default_factory=list)
    objects: list[PlanObjectDraft] = Field(min_length=1, max_length=3 * MAX_OBJECTS)
    rules: list[RuleDraft] = Field(default_factory=list, max_length=3 * MAX_RULES)


class SelfCheckStep(_Draft):
    """Step 5: the model's own check; ``plan`` is the corrected plan, or null if none needed."""

    issues: list[str] = Field(default_factory=list,
                              description="Logical problems found; empty if none.")
    plan: PlanDraft | None = Field(None, description="The corrected plan, or null.")


#: Most issues one self-check reply lists.
MAX_ISSUES = 8


class CheckIssues(_Draft):
    """Step 5, first request: only the problems the model finds (no plan), so a plan without
    problems costs a reply of a few tokens; a second request asks for the corrections."""

    issues: list[str] = Field(default_factory=list, max_length=MAX_ISSUES,
                              description="Problems found, each one short sentence; empty if "
                                          "none.")


class PromptList(_Draft):
    """Distinct descriptive prompts for one room type."""

    prompts: list[str] = Field(min_length=1)


class ReplyError(ValueError):
    """A reply that is not the JSON object the step asked for.

    Attributes
    ----------
    problems : list of str
        What is wrong, each starting with the JSON path in the reply.
    """

    def __init__(self, problems: list[str]):
        self.problems = list(problems)
        super().__init__("; ".join(self.problems))


_FENCE = re.compile(r"```(?:json|JSON)?\s*\n?(.*?)```", re.DOTALL)


def _loc(loc: tuple[Any, ...]) -> str:
    out = ""
    for part in loc:
        out += f"[{part}]" if isinstance(part, int) else ("." if out else "") + str(part)
    return out or "(reply)"


def _json_in(body: str) -> Any:
    """The JSON value of a reply: as is, else inside a code fence, else from { to }."""
    candidates = [body]
    fence = _FENCE.search(body)
    if fence:
        candidates.append(fence.group(1).strip())
    start, end = body.find("{"), body.rfind("}")
    if start >= 0 and end > start:
        candidates.append(body[start:end + 1])
    if len(candidates) == 1 and not body.startswith(("{", "[")):
        raise ReplyError(["(reply): no JSON object found; answer with one JSON object "
                          "only, no prose"])
    errors: list[json.JSONDecodeError] = []
    for candidate in candidates:
        try:
            return json.loads(candidate)
        except json.JSONDecodeError as e:
            errors.append(e)
    last = errors[-1]  # the most specific candidate: the fence's or the braces' content
    whole = errors[0]  # the reply as a whole: does it end before its JSON does?
    cut = whole.pos >= len(whole.doc.rstrip()) and \
        whole.msg.startswith(("Expecting", "Unterminated"))
    raise ReplyError([f"(reply): not valid JSON: {last.msg} at line {last.lineno} column "
                      f"{last.colno}"] + (["(reply): it breaks off before its end (the "
                                           "server's token limit?); answer shorter: compact "
                                           "JSON without indentation, fewer rules"] if cut
                                          else []))


def close_cut_reply(text: str) -> str | None:
    """Close a JSON reply that broke off (at the server's token limit) after its last whole
    list item.

    A reply cut off inside a long list (the 30th rule of an object step) is
    read up to the last object (or list) item of a list that was complete,
    and every open list and object is closed. Only a reply that is a valid start of one JSON object
    is closed.

    Parameters
    ----------
    text : str
        The reply.

    Returns
    -------
    str or None
        The closed JSON text, or None if the reply is complete, is not one
        JSON object cut off, or has no whole list item to keep.

    Examples
    --------
    >>> close_cut_reply('{"objects": [{"id": "bed"}, {"id": "des')
    '{"objects": [{"id": "bed"}]}'
    """
    body = text.strip()
    start = body.find("{")
    if start < 0:
        return None
    body = body[start:]
    stack: list[str] = []
    cut: tuple[int, str] | None = None  # (end of the last whole list item, closers then)
    in_str = escape = False
    for i, ch in enumerate(body):
        if in_str:
            if escape:
                escape = False
            elif ch == "\\":
                escape = True
            elif ch == '"':
                in_str = False
            continue
        if ch == '"':
            in_str = True
        elif ch in "[{":
            stack.append("]" if ch == "[" else "}")
        elif ch in "]}":
            if not stack or stack.pop() != ch:
                return None
            if not stack:  # the object closed: the reply is whole (or has trailing text)
                return None
            if stack[-1] == "]":  # a whole object or list item of a list
                cut = (i + 1, "".join(reversed(stack)))
    if not stack or cut is None:
        return None
    closed = body[:cut[0]] + cut[1]
    try:
        json.loads(closed)
    except json.JSONDecodeError:
        return None
    return closed


def parse_reply(text: str, model: type[_Draft]) -> Any:
    """Parse a reply as JSON (cutting out code fences and prose) and validate it.

    The text is only ever parsed as JSON data, never evaluated.

    Parameters
    ----------
    text : str
        The reply.
    model : pydantic model class
        The step's model.

    Returns
    -------
    model instance

    Raises
    ------
    ReplyError
        If the text holds no JSON object or it does not match the model.
    """
    if len(text) > MAX_REPLY_CHARS:
        raise ReplyError([f"(reply): {len(text)} characters is longer than the limit of "
                          f"{MAX_REPLY_CHARS}; answer with the JSON object only"])
    data = _json_in(text.strip())
    if not isinstance(data, dict):
        raise ReplyError([f"(reply): expected a JSON object, got {type(data).__name__}"])
    if "$defs" in data or "$schema" in data or (data.get("type") == "object"
                                                 and isinstance(data.get("properties"), dict)):
        raise ReplyError(["(reply): this is the JSON Schema itself, not an answer; answer with "
                          "one JSON object that follows the schema, with the values filled "
                          f"in (its fields: {', '.join(model.model_fields)})"])
    try:
        return model.model_validate(data)
    except ValidationError as e:
        raise ReplyError([f"{_loc(err['loc'])}: {err['msg']}" for err in e.errors()]) from None


def schema_for(model: type[_Draft], rule_names: list[str] | None = None) -> dict[str, Any]:
    """JSON Schema of a step model, with rule names limited to ``rule_names``.

    Parameters
    ----------
    model : pydantic model class
        The step's model.
    rule_names : list of str, optional
        Allowed values of every ``rule`` field (an ``enum``); no limit if None.
    """
    schema = copy.deepcopy(model.model_json_schema())
    if rule_names:
        for name in ("RuleDraft", "AreaRuleDraft"):
            prop = schema.get("$defs", {}).get(name, {}).get("properties", {}).get("rule")
            if prop is not None:
                prop["enum"] = list(rule_names)
    return schema


def shape_of(schema: dict[str, Any]) -> str:
    """A short outline of a JSON Schema's object: its keys, their types and meanings.

    What a prompt shows instead of the schema itself: a third of its length, which a small
    model on a CPU reads in a third of the time, while the server is still given the whole
    schema to enforce.

    Parameters
    ----------
    schema : dict
        A step's JSON Schema (:func:`schema_for`).

    Returns
    -------
    str
        One line per key, nested lists and objects indented.

    Examples
    --------
    >>> print(shape_of(schema_for(SupportEdge)))
    - object: string
    - parent: string
    """
    defs = schema.get("$defs", {})
    lines: list[str] = []
    _outline(schema, defs, lines, "")
    return "\n".join(lines)


def _resolve(node: dict[str, Any], defs: dict[str, Any]) -> dict[str, Any]:
    ref = node.get("$ref")
    return defs.get(ref.rsplit("/", 1)[-1], {}) if isinstance(ref, str) else node


def _type(node: dict[str, Any], defs: dict[str, Any]) -> tuple[str, dict[str, Any] | None]:
    """The type's words, and the object (or object of a list) whose keys follow, if any."""
    node = _resolve(node, defs)
    if "anyOf" in node:
        kinds = [k for k in node["anyOf"] if k.get("type") != "null"]
        words, inner = _type(kinds[0], defs) if kinds else ("null", None)
        return (f"{words} or null" if len(kinds) < len(node["anyOf"]) else words), inner
    if "enum" in node:
        if len(node["enum"]) > 6:
            return "a rule name of the system message", None
        return "one of " + ", ".join(json.dumps(v) for v in node["enum"]), None
    kind = node.get("type")
    if kind == "array":
        items = _resolve(node.get("items", {}), defs)
        lo, hi = node.get("minItems"), node.get("maxItems")
        if lo is not None and lo == hi and items.get("type") in ("number", "integer"):
            return "[" + ", ".join([items["type"]] * lo) + "]", None
        count = (f"{lo}-{hi} " if lo and hi else f"up to {hi} " if hi else
                 f"at least {lo} " if lo else "")
        if "properties" in items:
            return f"list of {count}objects", items
        words, _ = _type(items, defs)
        return f"list of {count}{words}", None
    if "properties" in node:
        return "object", node
    return str(kind or "any"), None


def _outline(node: dict[str, Any], defs: dict[str, Any], lines: list[str], pad: str) -> None:
    node = _resolve(node, defs)
    required = set(node.get("required", []))
    for key, prop in node.get("properties", {}).items():
        words, inner = _type(prop, defs)
        what = _resolve(prop, defs).get("description") or prop.get("description")
        name = key if key in required else f"{key} (optional)"
        lines.append(f"{pad}- {name}: {words}" + (f" — {what.rstrip('.')}" if what else "")
                     + (", with keys:" if inner is not None else ""))
        if inner is not None:
            _outline(inner, defs, lines, pad + "  ")
