"""The scene plan: a room, its objects and the rules that place them.

A plan is plain JSON, validated by pydantic models. Everything that would
make a simulation fail is reported before any simulation, all problems at
once, each with the JSON path of its field::

    rules[4] (facing): unknown object 'chiar'. Did you mean 'chair'?

Conventions: metres; wall ``i`` runs from ``polygon[i]`` to ``polygon[i+1]``;
an opening's ``offset`` is the distance of its centre from ``polygon[i]``;
an object's ``size`` is ``[width (local x), depth (local y), height]`` and
local +y is its front.

Examples
--------
>>> from forcelayout import Plan
>>> plan = Plan.model_validate({
...     "name": "tiny",
...     "room": {"polygon": [[0, 0], [3, 0], [3, 3], [0, 3]]},
...     "objects": [{"id": "bed", "category": "bed", "size": [1.4, 2.0, 0.5]}],
...     "rules": [{"rule": "at_wall", "object": "bed"}],
... })
>>> plan.object("bed").size
(1.4, 2.0, 0.5)
"""

from __future__ import annotations

import difflib
import json
import math
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Annotated, Any, Literal, get_args

import numpy as np
import shapely
from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    SerializerFunctionWrapHandler,
    ValidationError,
    field_validator,
    model_serializer,
    model_validator,
)

from forcelayout import rules as registry
from forcelayout.errors import PlanError, Problem

__all__ = [
    "Door",
    "Window",
    "Room",
    "SceneObject",
    "ObjectAccess",
    "RuleSpec",
    "AreaRule",
    "Area",
    "Plan",
    "MAX_FLOOR_FILL",
    "PHYSICAL_TERMS",
    "WALKABLE_CATEGORIES",
    "WALKABLE_HEIGHT",
]

#: Names of the always-on terms whose strength ``Plan.weights`` may scale.
PHYSICAL_TERMS = frozenset({"repulsion", "passage", "boundary", "alignment", "door", "window",
                            "access"})
#: Largest fraction of the floor the floor objects' footprints may cover.
MAX_FLOOR_FILL = 0.6

#: A size this large (metres) in a plan most likely was given in centimetres or millimetres.
_UNIT_SLIP = 20.0
#: No room is this many metres across (the free-space grid of a larger one is too big):
#: a room's coordinates past it are taken for centimetres or millimetres.
_ROOM_UNIT_SLIP = 100.0
#: Categories (or words of a category) that are walkable floor covers by default.
WALKABLE_CATEGORIES = frozenset({"rug", "carpet", "mat", "doormat", "runner"})
#: Objects at most this high (metres) are walkable floor covers by default.
WALKABLE_HEIGHT = 0.05

Metres = Annotated[float, Field(allow_inf_nan=False)]
PositiveMetres = Annotated[float, Field(gt=0, allow_inf_nan=False)]


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", populate_by_name=True)


class _Opening(_Model):
    wall: int = Field(ge=0, description="Index i of the wall polygon[i] -> polygon[i+1].")
    offset: Metres = Field(ge=0, description="Distance of the opening's centre from polygon[i], m.")
    width: PositiveMetres = Field(description="Opening width along the wall, m.")


class Door(_Opening):
    """A door on a wall; its swing square (width x width) inside the room is kept clear."""

    width: PositiveMetres = Field(0.9, description="Door width along the wall, m.")
    height: PositiveMetres = Field(2.05, description="Door height, m.")


class Window(_Opening):
    """A window on a wall, between ``sill`` and ``sill + height`` above the floor."""

    width: PositiveMetres = Field(1.2, description="Window width along the wall, m.")
    sill: Metres = Field(0.9, ge=0, description="Height of the window's bottom edge, m.")
    height: PositiveMetres = Field(1.2, description="Window height, m.")
    clearance: Metres = Field(0.5, ge=0, description=(
        "Depth in metres of the zone in front of the window (window width x clearance, "
        "inside the room) kept free of floor objects taller than the sill; 0 turns it off."))


class Room(_Model):
    """The room: a simple floor polygon (any shape), a height, doors and windows."""

    polygon: list[tuple[Metres, Metres]] = Field(
        min_length=3, description="Floor polygon vertices [x, y] in metres, either orientation."
    )
    height: PositiveMetres = Field(2.7, description="Ceiling height, m.")
    doors: list[Door] = Field(default_factory=list)
    windows: list[Window] = Field(default_factory=list)

    @property
    def shape(self) -> shapely.Polygon:
        """The floor as a shapely polygon."""
        return shapely.Polygon(self.polygon)

    def wall_length(self, i: int) -> float:
        """Length of wall ``i`` in metres."""
        a = self.polygon[i]
        b = self.polygon[(i + 1) % len(self.polygon)]
        return math.hypot(b[0] - a[0], b[1] - a[1])


class ObjectAccess(_Model):
    """Free floor a person needs beside an object to use it.

    ``sides`` are sides of the footprint in the object's frame (``"front"``
    is local +y); a person uses one of them (either long side of a bed).
    """

    sides: list[Literal["front", "back", "left", "right"]] = Field(
        min_length=1, description="Sides that need free floor, e.g. ['front'].")
    depth: PositiveMetres = Field(0.6, description="Depth of the free floor, m.")
    doors: bool = Field(False, description=(
        "Doors or drawers open into the free floor: only an object a rule stands beside "
        "it (next_to) may stand there, not one a rule puts in front of it or near it."))


class SceneObject(_Model):
    """One object of the plan (furniture, decor, fixtures)."""

    id: str = Field(min_length=1, pattern=r"^[A-Za-z0-9_.\-]+$",
                    description="Unique id, e.g. 'nightstand_1'.")
    category: str = Field(min_length=1, description="Object class, e.g. 'nightstand'.")
    description: str = Field("", description="Free text used for asset retrieval.")
    size: tuple[PositiveMetres, PositiveMetres, PositiveMetres] = Field(
        description="[width (local x), depth (local y, front is +y), height] in metres."
    )
    area: str | None = Field(None, description="Functional area this object belongs to.")
    primary: bool = Field(False, description="Primary objects must be reachable from a door.")
    decor: bool = Field(False, description="Secondary (decorative) item; dropped by no_decor.")
    walkable: bool | None = Field(None, description=(
        "A floor cover people walk on (rug, mat): no obstacle for collisions or navigation, "
        "furniture may stand on it, it must still lie inside the room. None = the default: "
        "true for the categories rug, carpet, mat, doormat and runner (any case, also as a "
        "word of the category, e.g. 'bath_mat', 'area rug') and for objects at most 0.05 m "
        "high; false otherwise."))
    access: ObjectAccess | Literal[False] | None = Field(None, description=(
        "Free floor kept clear beside the object so a person can use it: None = the default "
        "of its category (front of a wardrobe, desk, sofa, fridge; a long side of a bed; "
        "see forcelayout.access), also true; false = none."))
    asset: str | None = Field(None, min_length=1, description=(
        "Id of the asset (mesh) this object was grounded to, in an asset library's "
        "assets.json (see forcelayout.grounding); None = a box."))
    footprint: list[tuple[Metres, Metres]] | None = Field(None, min_length=3, max_length=16,
                                                          description=(
        "Convex footprint polygon [[x, y], ...] in the object's frame (metres, front +y, "
        "inside the size's [w, d] box), used as the object's Box2D fixture instead of the "
        "rectangle; None = the rectangle. Checks and pictures still use the rectangle."))

    @field_validator("access", mode="before")
    @classmethod
    def _one_access(cls, v: Any) -> Any:
        """One clear message for a bad ``access`` (not one per form it may take); ``true``
        is the category's default, as ``null``."""
        shape = ('access is {"sides": ["front", ...], "depth": metres}, false for none, or '
                 'true or null for the default of its category')
        if v is None or v is False or isinstance(v, ObjectAccess):
            return v
        if v is True:
            return None
        if isinstance(v, dict):
            try:
                return ObjectAccess.model_validate(v)
            except ValidationError as e:
                errs = e.errors()
                what = "; ".join(f"{'.'.join(map(str, err['loc']))}: {err['msg']}"
                                 for err in errs)
                if len(errs) > 1:  # one problem of the plan, said as one
                    what = f"{len(errs)} mistakes in it: {what}"
                raise ValueError(f"{what} ({shape})") from None
        raise ValueError(f"{shape}; got {v!r}")

    @field_validator("footprint")
    @classmethod
    def _convex_footprint(cls, v: list[tuple[float, float]] | None
                          ) -> list[tuple[float, float]] | None:
        if v is None:
            return v
        hull = shapely.MultiPoint(v).convex_hull
        if hull.geom_type != "Polygon" or hull.area <= 1e-9:
            raise ValueError("the footprint needs at least 3 corners enclosing a non-zero area")
        if abs(hull.area - shapely.Polygon(v).area) > 1e-6 * max(hull.area, 1.0) \
                or not shapely.Polygon(v).is_valid:
            raise ValueError("the footprint must be a convex polygon with its corners in order")
        return v

    @model_validator(mode="after")
    def _footprint_in_box(self) -> SceneObject:
        if self.footprint is not None:
            w, d = self.size[0] / 2 + 1e-6, self.size[1] / 2 + 1e-6
            if any(abs(x) > w or abs(y) > d for x, y in self.footprint):
                raise ValueError(f"the footprint of {self.id!r} leaves its size's "
                                 f"{self.size[0]:g} x {self.size[1]:g} m box centred on 0")
        return self

    @model_serializer(mode="wrap")
    def _drop_unset_grounding(self, handler: SerializerFunctionWrapHandler) -> dict[str, Any]:
        # plans without assets keep the JSON (and the hash) they had before these fields
        data = handler(self)
        for key in ("asset", "footprint"):
            if key in data and data[key] is None:
                del data[key]
        return data

    @property
    def is_walkable(self) -> bool:
        """Whether the object is a walkable floor cover (``walkable``, or its default)."""
        if self.walkable is not None:
            return self.walkable
        if self.size[2] <= WALKABLE_HEIGHT + 1e-9:
            return True
        words = re.split(r"[^a-z0-9]+", self.category.lower())
        return any(w in WALKABLE_CATEGORIES or (w.endswith("s") and w[:-1] in WALKABLE_CATEGORIES)
                   for w in words)


class RuleSpec(_Model):
    """One rule binding: ``rule`` applied to ``object`` (and ``target``)."""

    rule: str = Field(min_length=1, description="Registered rule name, e.g. 'next_to'.")
    object: str = Field(min_length=1, description="Id of the object the rule places.")
    target: str | None = Field(None, description="Id of the other object (binary rules).")
    params: dict[str, Any] = Field(default_factory=dict, description="Rule parameters.")
    weight: float | None = Field(None, ge=0, allow_inf_nan=False,
                                 description="Strength multiplier; None uses the default.")
    bond: bool | None = Field(None, description=(
        "Strong parent->child dependency in the scene graph; None = the default "
        "(next_to, in_front_of and around between floor objects of one area)."))
    required: bool = Field(False, description=(
        "Every layout must meet this rule, whatever share of the rules the acceptance "
        "lets go unmet (min_rule_satisfaction, --min-rules)."))

    @property
    def label(self) -> str:
        """The binding as reports name it: ``near(sofa, tv)``, ``at_wall(bed)``."""
        return _binding_label(self.rule, self.object, self.target)


def _binding_label(rule: str, obj: str, target: str | None) -> str:
    """A rule binding as reports name it: ``near(sofa, tv)``, ``at_wall(bed)``."""
    return f"{rule}({obj}{', ' + target if target else ''})"


class AreaRule(_Model):
    """A rule for a whole functional area (e.g. the sleeping area at a wall)."""

    rule: str = Field(min_length=1)
    target: str | None = None
    params: dict[str, Any] = Field(default_factory=dict)
    weight: float | None = Field(None, ge=0, allow_inf_nan=False)


class Area(_Model):
    """A functional area (e.g. 'sleeping') grouping objects that are placed together."""

    name: str = Field(min_length=1)
    description: str = ""
    rules: list[AreaRule] = Field(default_factory=list)


class Plan(_Model):
    """A declarative scene plan: room, objects, rules and functional areas.

    Validation checks everything a simulation needs, and reports all
    problems at once with their JSON paths (see :class:`PlanError`).
    """

    name: str = Field("plan", min_length=1)
    description: str = ""
    room: Room
    objects: list[SceneObject] = Field(min_length=1)
    rules: list[RuleSpec] = Field(default_factory=list)
    areas: list[Area] = Field(default_factory=list)
    weights: dict[str, Annotated[float, Field(ge=0, allow_inf_nan=False)]] = Field(
        default_factory=dict,
        description="Per-rule-name weight overrides for this plan, e.g. {'near': 0.5}.",
    )

    @field_validator("objects")
    @classmethod
    def _unique_ids(cls, v: list[SceneObject]) -> list[SceneObject]:
        seen: set[str] = set()
        for o in v:
            if o.id in seen:
                raise ValueError(f"object id {o.id!r} appears twice; ids must be unique")
            seen.add(o.id)
        return v

    @model_validator(mode="after")
    def _check(self) -> Plan:
        problems = list(_semantic_problems(self))
        if problems:
            raise PlanError(problems)
        return self

    # -- access -----------------------------------------------------------------
    def object(self, object_id: str) -> SceneObject:
        """The object with id ``object_id``."""
        for o in self.objects:
            if o.id == object_id:
                return o
        raise KeyError(object_id)

    @property
    def ids(self) -> list[str]:
        """Object ids in plan order."""
        return [o.id for o in self.objects]

    def surface_of(self, object_id: str) -> str:
        """Where an object rests: ``"floor"``, or the name of the rule that takes it off it.

        A rule takes its object off the floor when its class declares a
        ``surface`` other than ``"floor"`` (see :class:`forcelayout.rules.Rule`).
        """
        for r in self.rules:
            if r.object == object_id and _off_floor(r.rule):
                return r.rule
        return "floor"

    def floor_objects(self) -> list[SceneObject]:
        """Objects that stand on the floor (no off-floor rule binds them)."""
        off = {r.object for r in self.rules if _off_floor(r.rule)}
        return [o for o in self.objects if o.id not in off]

    # -- I/O --------------------------------------------------------------------
    @classmethod
    def from_json(cls, text: str | bytes) -> Plan:
        """Parse and validate a plan from JSON text; raises :class:`PlanError`."""
        try:
            return cls.model_validate_json(text)
        except ValidationError as e:
            if any(err["type"] == "json_invalid" for err in e.errors()):
                raise PlanError([_json_problem(text)]) from None
            raise _plan_error(e) from None

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> Plan:
        """Validate a plan from a dict; raises :class:`PlanError`."""
        try:
            return cls.model_validate(data)
        except ValidationError as e:
            raise _plan_error(e) from None

    @classmethod
    def load(cls, path: str | Path) -> Plan:
        """Read and validate a plan JSON file; raises :class:`PlanError`."""
        return cls.from_json(Path(path).read_text(encoding="utf-8"))

    def to_json(self, *, indent: int | None = 2) -> str:
        """The plan as JSON text (round-trips through :meth:`from_json`)."""
        return self.model_dump_json(indent=indent, exclude_defaults=False)

    def save(self, path: str | Path) -> Path:
        """Write the plan as JSON to ``path``."""
        path = Path(path)
        path.write_text(self.to_json(), encoding="utf-8")
        return path

    @classmethod
    def json_schema(cls) -> dict[str, Any]:
        """JSON Schema of the plan, e.g. for an LLM's structured output."""
        return cls.model_json_schema()


# -- validation ------------------------------------------------------------------


def _fmt_loc(loc: tuple[Any, ...]) -> str:
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += ("." if out else "") + str(part)
    return out


def _json_problem(text: str | bytes) -> Problem:
    """Where JSON text that does not parse goes wrong, with the line it is on."""
    if isinstance(text, bytes):
        text = text.decode("utf-8", errors="replace")
    try:
        json.loads(text)
    except json.JSONDecodeError as e:
        lines = text.splitlines()  # a text cut short fails past its last line
        line = lines[e.lineno - 1] if e.lineno <= len(lines) else ""
        if len(line.strip()) <= 80:
            shown = line.strip()
        else:  # the 80 characters about the column, on a long line (JSON on one line)
            start = max(0, min(e.colno - 41, len(line) - 77))
            shown = (("..." if start else "") + line[start:start + 77].strip()
                     + ("..." if start + 77 < len(line) else ""))
        where = f"the line reads: {shown}" if line.strip() else "the text ends there"
        # "Unterminated string starting at": the message ends where its position was
        msg = f"{e.msg} line {e.lineno}, column {e.colno}" if e.msg.endswith(" at") else e.msg
        return Problem(f"line {e.lineno}, column {e.colno}",
                       f"not valid JSON: {msg} (a doubled or trailing comma, or a missing "
                       f"quote or bracket?); {where}")
    return Problem("(the text)", "not valid JSON")


def _plan_error(e: ValidationError) -> PlanError:
    problems: list[Problem] = []
    for err in e.errors():
        ctx_err = (err.get("ctx") or {}).get("error")
        if isinstance(ctx_err, PlanError):
            problems.extend(ctx_err.problems)
            continue
        msg = err["msg"].removeprefix("Value error, ")
        if err["type"] == "extra_forbidden":
            msg = "unknown field; remove it or check its spelling"
            fields = _fields_at(err["loc"][:-1])
            if fields and isinstance(err["loc"][-1], str):
                msg += _did_you_mean(err["loc"][-1], fields).replace(" Did", ". Did", 1)
        elif err["type"] == "missing":
            msg = "required field is missing"
        elif err["type"] in ("model_type", "dict_type") and not err["loc"]:  # the whole plan
            kind = type(err.get("input")).__name__
            msg = (f"a plan is one JSON object (with room, objects and rules), not a {kind}; "
                   "give one plan per file")
        msg = _unit_hint(err, msg)
        loc = err["loc"]
        if loc[:1] == ("objects",) and "size" in loc[2:]:  # a size of the wrong length or kind
            msg += "; size is [width, depth, height] in metres"
        problems.append(Problem(_fmt_loc(loc), msg))
    return PlanError(problems)


#: Units a number in a plan may be written with by mistake, and their factor to the plan's
#: units (metres, degrees).
_UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001, "deg": 1.0, "°": 1.0}
_WITH_UNIT = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+))\s*([a-zA-Z°]+)\s*$")


def _unit_hint(err: Any, msg: str) -> str:
    """``msg``, for a number written as text with its unit (``"0.2m"``), said plainly: write
    the number alone, in metres or degrees."""
    if err["type"] not in ("float_parsing", "int_parsing") or not isinstance(err.get("input"),
                                                                             str):
        return msg
    m = _WITH_UNIT.match(err["input"])
    if m is None or m.group(2).lower() not in _UNITS:
        return (f"{err['input']!r} is not a number; give one, without quotes (lengths in "
                "metres, angles in degrees)")
    value = float(m.group(1)) * _UNITS[m.group(2).lower()]
    return (f"{err['input']!r} is not a number; write it without its unit: {value:g} "
            "(lengths are in metres, angles in degrees)")


def _fields_at(loc: tuple) -> list[str]:
    """The field names of the model at ``loc`` in a plan (``("rules", 2)``: a rule's), or
    none where the path leads to no model."""
    model: Any = Plan
    for part in loc:
        if isinstance(part, int):
            continue
        field = getattr(model, "model_fields", {}).get(part)
        if field is None:
            return []
        kinds = [field.annotation]
        model = None
        while kinds:  # the model in list[...], X | None, Annotated[...]
            t = kinds.pop()
            if isinstance(t, type) and issubclass(t, BaseModel):
                model = t
                break
            kinds.extend(get_args(t))
        if model is None:
            return []
    return [f.alias or name for name, f in model.model_fields.items()]


def _did_you_mean(name: str, options: list[str]) -> str:
    """`` Did you mean 'x'?`` for the closest option, or for each of up to three that are
    as close (``nightstand_1`` for ``nightstand_l`` and ``nightstand_r``); "" for none."""
    close = difflib.get_close_matches(name, options, n=3, cutoff=0.6)
    if not close:
        return ""

    def ratio(option: str) -> float:
        return difflib.SequenceMatcher(None, name, option).ratio()

    best = ratio(close[0])
    tied = sorted(c for c in close if ratio(c) >= best - 1e-9)
    return f" Did you mean {' or '.join(repr(c) for c in tied)}?"


def _which_id(name: str, ids: list[str]) -> str:
    """The hint for an unknown object id: the closest id, else the ids there are."""
    close = _did_you_mean(name, ids)
    if close or not ids:
        return close
    more = len(ids) - 12
    shown = ", ".join(repr(i) for i in ids[:12]) + (f" and {more} more" if more > 0 else "")
    return f" The plan's objects are {shown}."


def _room_feature(rule: str, target: str, obj: str) -> str:
    """The hint for a target naming a window or a door: the rule meant for it."""
    from forcelayout.autofix import room_feature_hint  # the autofix reads plans: when needed

    return room_feature_hint(rule, target, obj)


def _rule_meant(name: str) -> str:
    """The hint for an unknown rule name: the rule it is an alias of (``beside`` is
    ``next_to``), else the closest registered name."""
    from forcelayout.autofix import rule_aliases  # the autofix reads plans: when needed

    meant = rule_aliases().get(name.strip().lower().replace(" ", "_").replace("-", "_"))
    if meant is not None:
        return f" {name!r} means {meant!r} here: write {meant!r}."
    return _did_you_mean(name, registry.available_rules())


def _off_floor(name: str) -> bool:
    """Whether the registered rule ``name`` places its object off the floor."""
    return registry.is_registered(name) and registry.get_rule(name).surface != "floor"


def _overlapping_openings(room: Room, n_walls: int) -> Iterator[Problem]:
    """Openings on one wall that share a stretch of it at the same heights (two doors; a
    window reaching below a door's top): one problem for the later of each pair."""
    spans = []  # (path, wall, along from, along to, height from, height to)
    for k, d in enumerate(room.doors):
        spans.append((f"room.doors[{k}]", d.wall, d.offset - d.width / 2,
                      d.offset + d.width / 2, 0.0, d.height))
    for k, w in enumerate(room.windows):
        spans.append((f"room.windows[{k}]", w.wall, w.offset - w.width / 2,
                      w.offset + w.width / 2, w.sill, w.sill + w.height))
    for b, (path, wall, lo, hi, zlo, zhi) in enumerate(spans):
        if wall >= n_walls:
            continue  # said above
        for first, wall1, lo1, hi1, zlo1, zhi1 in spans[:b]:
            if wall1 == wall and min(hi, hi1) - max(lo, lo1) > 1e-6 \
                    and min(zhi, zhi1) - max(zlo, zlo1) > 1e-6:
                yield Problem(f"{path}.offset", f"it overlaps {first} on wall {wall} "
                              f"([{lo:.2f}, {hi:.2f}] m and [{lo1:.2f}, {hi1:.2f}] m along "
                              "it); move one along the wall or onto another wall")
                break


def _polygon_fault(polygon: list) -> str:
    """Where a floor polygon that is not simple goes wrong, as a clause for its message:
    repeated corners, or the walls (wall ``i`` runs from corner ``i`` to corner ``i + 1``)
    that cross or run back over each other."""
    v = [tuple(map(float, p)) for p in polygon]
    n = len(v)
    i = _repeated_corner(polygon)
    if i is not None:
        return (f" (corners {i} and {(i + 1) % n} are the same point {list(v[i])}: "
                f"drop one)")
    edges = [shapely.LineString([v[i], v[(i + 1) % n]]) for i in range(n)]
    for i in range(n):
        for j in range(i + 1, n):
            meet = edges[i].intersection(edges[j])
            if meet.is_empty:
                continue
            if j == i + 1 or (i == 0 and j == n - 1):  # neighbours share a corner only
                if meet.geom_type == "Point":
                    continue
                return f" (walls {i} and {j} run back over each other)"
            return f" (walls {i} and {j} cross)"
    return " (its corners lie on one line)" if shapely.Polygon(v).area <= 1e-9 else ""


def _repeated_corner(polygon: list) -> int | None:
    """The first corner of a floor polygon that the next one repeats (within 1 nm)."""
    v = np.asarray(polygon, dtype=float)
    same = np.flatnonzero(np.abs(v - np.roll(v, -1, axis=0)).max(axis=1) <= 1e-9)
    return int(same[0]) if len(same) else None


def _semantic_problems(plan: Plan) -> Iterator[Problem]:
    room = plan.room
    poly = room.shape
    # room polygon
    if not poly.is_valid or not shapely.is_simple(poly.exterior) or poly.area <= 1e-9 \
            or _repeated_corner(room.polygon) is not None:
        yield Problem("room.polygon", "the floor polygon must be simple (no self-intersections, "
                      "no repeated vertices) with non-zero area; list its corners in order"
                      + _polygon_fault(room.polygon))
        return
    x0, y0, x1, y1 = poly.bounds
    if max(x1 - x0, y1 - y0) > _ROOM_UNIT_SLIP:  # no room is 100 m across: a unit slip
        yield Problem("room.polygon", f"the room is {x1 - x0:g} x {y1 - y0:g} m; coordinates "
                      "and sizes are in metres (this looks like centimetres or millimetres: "
                      "divide them by 100 or 1000)")
    n_walls = len(room.polygon)
    for kind, openings in (("doors", room.doors), ("windows", room.windows)):
        for k, o in enumerate(openings):
            path = f"room.{kind}[{k}]"
            if o.wall >= n_walls:
                yield Problem(f"{path}.wall", f"wall {o.wall} does not exist; the polygon has "
                              f"walls 0..{n_walls - 1}")
                continue
            length = room.wall_length(o.wall)
            if o.width > length + 1e-9:
                yield Problem(f"{path}.width", f"{o.width:g} m is wider than wall {o.wall} "
                              f"({length:.2f} m); use a narrower opening or another wall")
            elif o.offset - o.width / 2 < -1e-9 or o.offset + o.width / 2 > length + 1e-9:
                yield Problem(f"{path}.offset", f"the opening [{o.offset - o.width / 2:.2f}, "
                              f"{o.offset + o.width / 2:.2f}] m leaves wall {o.wall} "
                              f"(0..{length:.2f} m); offset is the centre's distance from "
                              f"polygon[{o.wall}] and must lie in [{o.width / 2:.2f}, "
                              f"{length - o.width / 2:.2f}] m for a {o.width:g} m "
                              f"{kind[:-1]} on this wall")
            if kind == "windows" and o.sill + o.height > room.height + 1e-9:  # type: ignore[union-attr]
                yield Problem(f"{path}.height", "the window reaches above the ceiling")
    yield from _overlapping_openings(room, n_walls)
    # objects that cannot fit
    minx, miny, maxx, maxy = poly.bounds
    rect = poly.minimum_rotated_rectangle
    rx, ry = rect.exterior.xy
    sides = sorted({math.hypot(rx[1] - rx[0], ry[1] - ry[0]),
                    math.hypot(rx[2] - rx[1], ry[2] - ry[1])})
    short_side, long_side = sides[0], sides[-1]
    off_floor = {r.object for r in plan.rules if _off_floor(r.rule)}
    floor_area = 0.0
    footprints: list[tuple[float, str]] = []
    for k, o in enumerate(plan.objects):
        w, d, h = o.size
        # no furniture is 20 m in any direction: most likely centimetres or millimetres
        units = ("; sizes are in metres (this looks like centimetres or millimetres)"
                 if max(o.size) >= _UNIT_SLIP else "")
        if min(w, d) > short_side + 1e-9 or max(w, d) > long_side + 1e-9 or w * d > poly.area:
            yield Problem(f"objects[{k}].size", f"{o.id!r} ({w:g} x {d:g} m) is larger than the "
                          f"room ({short_side:.2f} x {long_side:.2f} m at its narrowest "
                          "and longest); shrink it or the plan"
                          + units)
        if h > room.height + 1e-9:
            yield Problem(f"objects[{k}].size", f"{o.id!r} is {h:g} m tall but the ceiling is at "
                          f"{room.height:g} m" + units)
        if o.id not in off_floor and not o.is_walkable:  # furniture stands on covers
            floor_area += w * d
            footprints.append((w * d, o.id))
    if floor_area > MAX_FLOOR_FILL * poly.area:
        largest = ", ".join(f"{oid!r} {a:.1f} m²" for a, oid in sorted(
            footprints, key=lambda t: -t[0])[:3])
        yield Problem("objects", f"the floor objects cover {floor_area:.1f} m² of a "
                      f"{poly.area:.1f} m² room (more than {MAX_FLOOR_FILL:.0%}); no valid layout "
                      f"can leave room to walk; remove objects or enlarge the room (the largest: "
                      f"{largest})")
    # rules
    ids = plan.ids
    areas = {a.name for a in plan.areas}
    for k, r in enumerate(plan.rules):
        path = f"rules[{k}] ({r.rule})"
        if not registry.is_registered(r.rule):
            hint = _rule_meant(r.rule)
            yield Problem(path, f"unknown rule {r.rule!r}.{hint} Run `forcelayout rules` for the "
                          "vocabulary or register a plugin")
            continue
        rule = registry.get_rule(r.rule)
        if r.object not in ids:
            yield Problem(f"{path}.object",
                          f"unknown object {r.object!r}.{_which_id(r.object, ids)}")
        if rule.target == "required" and r.target is None:
            yield Problem(f"{path}.target", f"{r.rule!r} relates two objects; give a target id")
        elif rule.target == "none" and r.target is not None:
            yield Problem(f"{path}.target", f"{r.rule!r} takes no target (it relates "
                          f"{r.object!r} to the room); remove 'target'")
        elif r.target is not None and r.target not in ids and r.target not in areas:
            hint = (_did_you_mean(r.target, ids) or _room_feature(r.rule, r.target, r.object)
                    or _which_id(r.target, ids))
            yield Problem(f"{path}.target", f"unknown object {r.target!r}.{hint}")
        elif r.target is not None and r.target == r.object:
            yield Problem(f"{path}.target", "an object cannot be related to itself")
        try:
            params = rule.Params.model_validate(r.params)
        except ValidationError as e:
            fields = sorted(rule.Params.model_fields)
            for err in e.errors():
                if err["type"] == "extra_forbidden":  # a misspelt or foreign parameter
                    name = str(err["loc"][-1])
                    message = (f"{r.rule!r} has no parameter {name!r}."
                               f"{_did_you_mean(name, fields)} It takes {fields}")
                elif not err["loc"] and "error" in err.get("ctx", {}):
                    # the rule's own check of its params together (max_gap below clearance):
                    # its message names the params and the fix
                    yield Problem(f"{path}.params", str(err["ctx"]["error"]))
                    continue
                else:
                    message = f"{_unit_hint(err, err['msg'])}; {r.rule!r} takes {fields}"
                yield Problem(f"{path}.params.{_fmt_loc(err['loc'])}", message)
        else:
            yield from _opening_pick(room, rule, params, path)
        hint = rule.start
        if hint is not None and hint.place == "beneath" and r.object in ids \
                and not plan.object(r.object).is_walkable:
            yield Problem(f"{path}.object", f"{r.object!r} is solid, so it cannot lie under "
                          f"{r.target!r} (solid footprints never overlap); {r.rule!r} is for "
                          "walkable floor covers (rugs, mats: set \"walkable\": true), or "
                          f"place {r.object!r} beside its target (next_to, in_front_of)")
    for name in plan.weights:
        if not registry.is_registered(name) and name not in PHYSICAL_TERMS:
            yield Problem(f"weights.{name}", f"unknown rule {name!r}."
                          f"{_did_you_mean(name, registry.available_rules())}")
    for k, o in enumerate(plan.objects):
        if o.area is not None and plan.areas and o.area not in areas:
            yield Problem(f"objects[{k}].area", f"unknown area {o.area!r}; declare it in 'areas'."
                          f"{_did_you_mean(o.area, sorted(areas))}")
    yield from _surface_problems(plan)


def _opening_pick(room: Room, rule: type, params: BaseModel, path: str) -> Iterator[Problem]:
    """A binding that picks one door or window (``StartHint.which``) by an index the
    room has no opening for."""
    hint = rule.start
    if hint is None or hint.which is None:
        return
    k = int(getattr(params, hint.which))
    kind = f"{hint.place}s"
    have = len(getattr(room, kind))
    if k >= have:
        has = (f"has no {kind}" if have == 0 else
               f"has {have} {kind[:-1] if have == 1 else kind} (index "
               f"{', '.join(map(str, range(have)))})")
        yield Problem(f"{path}.params.{hint.which}",
                      f"there is no {kind[:-1]} {k}: the room {has}; give the index of one "
                      f"in room.{kind} (0 is the first), or -1 for the nearest")


def _surface_problems(plan: Plan) -> Iterator[Problem]:
    parents: dict[str, str] = {}
    placed: dict[str, int] = {}
    rule_of = {r.rule: registry.get_rule(r.rule) for r in plan.rules
               if registry.is_registered(r.rule)}
    for k, r in enumerate(plan.rules):
        if r.rule not in rule_of or rule_of[r.rule].surface == "floor":
            continue
        if r.object in placed:
            yield Problem(f"rules[{k}] ({r.rule})", f"{r.object!r} is already placed off the floor "
                          f"by rules[{placed[r.object]}]; an object rests on one surface")
            continue
        placed[r.object] = k
        if rule_of[r.rule].surface == "top" and r.target is not None:
            parents[r.object] = r.target
    ids = {o.id: o for o in plan.objects}
    for k, r in enumerate(plan.rules):
        if r.object in parents and placed.get(r.object) == k and r.target in ids \
                and r.object in ids:
            cw, cd, _ = ids[r.object].size
            pw, pd, _ = ids[r.target].size
            if min(cw, cd) > min(pw, pd) + 1e-9 or max(cw, cd) > max(pw, pd) + 1e-9:
                yield Problem(f"rules[{k}] ({r.rule})", f"{r.object!r} ({cw:g} x {cd:g} m) does "
                              f"not fit on top of {r.target!r} ({pw:g} x {pd:g} m)")
    # cycles in on_top
    for start in parents:
        seen = [start]
        cur = start
        for _ in range(len(parents) + 1):
            cur = parents.get(cur)  # type: ignore[assignment]
            if cur is None:
                break
            if cur == start:
                chain = " -> ".join([*seen, start])
                yield Problem("rules", f"cycle of objects resting on each other {chain}; an "
                              "object cannot rest on itself")
                break
            seen.append(cur)
        if cur == start:
            break


def footprint_area(plan: Plan) -> float:
    """Total footprint of the floor objects, square metres."""
    return float(sum(o.size[0] * o.size[1] for o in plan.floor_objects()))


def object_sizes(plan: Plan) -> np.ndarray:
    """Sizes of all objects, shape (N, 3), in plan order."""
    return np.array([o.size for o in plan.objects], dtype=float)
