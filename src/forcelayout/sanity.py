"""Plan findings beyond validity: impossible and implausible plans, each with its field and fix.

A plan can pass :class:`forcelayout.Plan` validation and still be
impossible (five objects tucked into the corners of a four-corner room, an
object both ``next_to`` and ``far_from`` the same target) or absurd (a bed
0.5 m wide, a window listed as furniture, a 14 x 5 m bedroom).
:func:`plan_findings` finds such plans from the plan alone, in milliseconds;
:func:`forcelayout.diagnose.feasibility`, ``forcelayout validate`` and
``forcelayout generate`` report them, and the LLM planner feeds them back to
the model like schema errors.

Each :class:`Finding` is one line: the JSON path of the field, what is
wrong, and the fix.

Examples
--------
>>> from forcelayout import Plan
>>> from forcelayout.sanity import plan_findings
>>> room = {"polygon": [[0, 0], [4, 0], [4, 3], [0, 3]]}
>>> plan = Plan.from_dict({"name": "bedroom", "room": room,
...     "objects": [{"id": "bed", "category": "bed", "size": [0.5, 2.0, 0.5]}]})
>>> f = plan_findings(plan)[0]
>>> f.path, f.severity
('objects[0].size', 'implausible')
>>> f.message
"'bed' (category 'bed') is 0.5 x 2 m; a bed is usually 0.8-2.2 x 1.8-2.4 m (height 0.25-1.4 m)"
"""

from __future__ import annotations

import math
import re
from collections import defaultdict
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Any, Literal

import numpy as np
import shapely
from pydantic import ValidationError

from forcelayout import geometry as geo
from forcelayout import rules as registry
from forcelayout.errors import UnknownRuleError
from forcelayout.plan import Plan, Room, RuleSpec
from forcelayout.rules import Rule
from forcelayout.rules.base import ParamArrays, State

__all__ = ["Finding", "plan_findings", "OutOfReach", "out_of_reach", "off_the_walls",
           "facing_apart", "PAIR_STEP",
           "gap_band", "SPOT_STEP", "CATEGORY_SIZES", "ROOM_AREAS", "ROOM_FURNITURE",
           "OPENING_WORDS", "names_the_room", "category_key", "convex_corners", "room_kind",
           "usual_size", "Severity", "MAX_TARGETS", "CONTACT_GAP"]

Severity = Literal["infeasible", "implausible"]

#: Usual (short side, long side, height) ranges of a footprint in metres, by category.
CATEGORY_SIZES: dict[str, tuple[tuple[float, float], tuple[float, float], tuple[float, float]]] = {
    "bed": ((0.8, 2.2), (1.8, 2.4), (0.25, 1.4)),
    "bunk_bed": ((0.8, 1.6), (1.8, 2.2), (1.3, 2.0)),
    "crib": ((0.55, 0.8), (0.95, 1.45), (0.75, 1.15)),
    "sofa": ((0.7, 1.2), (1.2, 3.5), (0.6, 1.1)),
    "armchair": ((0.6, 1.0), (0.6, 1.1), (0.6, 1.2)),
    "chair": ((0.35, 0.75), (0.4, 0.8), (0.65, 1.3)),
    "stool": ((0.25, 0.5), (0.25, 0.5), (0.4, 0.85)),
    "bench": ((0.3, 0.6), (0.8, 2.0), (0.4, 0.6)),
    "desk": ((0.45, 0.9), (0.8, 2.0), (0.65, 0.8)),
    "table": ((0.5, 1.2), (0.5, 2.6), (0.4, 0.8)),
    "dining_table": ((0.7, 1.2), (0.75, 2.6), (0.7, 0.8)),
    "coffee_table": ((0.4, 0.9), (0.45, 1.5), (0.25, 0.55)),
    "side_table": ((0.3, 0.65), (0.3, 0.7), (0.4, 0.75)),
    "nightstand": ((0.3, 0.6), (0.3, 0.7), (0.35, 0.8)),
    "wardrobe": ((0.45, 0.75), (0.6, 3.0), (1.6, 2.6)),
    "dresser": ((0.35, 0.65), (0.6, 1.9), (0.6, 1.5)),
    "bookshelf": ((0.2, 0.5), (0.4, 2.2), (0.7, 2.5)),
    "cabinet": ((0.3, 0.75), (0.35, 2.5), (0.4, 2.4)),
    "tv_stand": ((0.3, 0.6), (0.8, 2.4), (0.3, 0.75)),
    "tv": ((0.03, 0.45), (0.6, 2.2), (0.35, 1.3)),
    "fridge": ((0.5, 0.8), (0.5, 1.0), (0.8, 2.1)),
    "stove": ((0.5, 0.75), (0.5, 1.0), (0.8, 1.0)),
    "dishwasher": ((0.45, 0.65), (0.5, 0.7), (0.8, 0.9)),
    "washing_machine": ((0.5, 0.7), (0.55, 0.7), (0.8, 0.95)),
    "counter": ((0.5, 0.75), (0.6, 4.5), (0.85, 0.95)),
    "toilet": ((0.35, 0.5), (0.5, 0.8), (0.65, 0.9)),
    "bathtub": ((0.65, 0.95), (1.4, 1.9), (0.4, 0.7)),
    "piano": ((0.5, 1.6), (1.2, 2.8), (0.95, 1.5)),
}
_SYNONYMS = {
    "couch": "sofa", "settee": "sofa", "loveseat": "sofa", "sectional": "sofa",
    "bedside_table": "nightstand", "night_stand": "nightstand", "night_table": "nightstand",
    "bedside": "nightstand", "bookcase": "bookshelf", "book_shelf": "bookshelf",
    "closet": "wardrobe", "armoire": "wardrobe", "chest_of_drawers": "dresser",
    "drawers": "dresser", "refrigerator": "fridge", "cooker": "stove", "oven": "stove",
    "range": "stove", "hob": "stove", "television": "tv", "tv_unit": "tv_stand",
    "tv_cabinet": "tv_stand", "media_console": "tv_stand", "end_table": "side_table",
    "kitchen_table": "dining_table", "bunkbed": "bunk_bed", "cot": "crib",
    "bath": "bathtub", "tub": "bathtub", "washer": "washing_machine",
    "worktop": "counter", "countertop": "counter", "kitchen_counter": "counter",
}
#: Category words that name a door or a window (they belong in ``room.doors`` / ``room.windows``).
OPENING_WORDS = frozenset({"door", "doors", "doorway", "window", "windows", "skylight",
                           "entrance", "opening"})
_STRUCTURE_WORDS = frozenset({"room", "rooms", "floor", "wall", "walls", "ceiling"})


def names_the_room(category: str) -> bool:
    """Whether a category names the room itself or a part of it (``"room"``, ``"bathroom"``,
    ``"wall"``), not furniture: such an "object" belongs in the plan's ``room``.

    Examples
    --------
    >>> names_the_room("bathroom"), names_the_room("wall"), names_the_room("wall_shelf")
    (True, True, False)
    >>> names_the_room("bath")   # a bathtub
    False
    """
    words = _tokens(category)
    if not words or category_key(category) is not None:
        return False
    return (words[-1] in _STRUCTURE_WORDS or words[-1].endswith("room")
            or "_".join(words) in {k.replace(" ", "_") for k in ROOM_AREAS})


#: Usual floor area (m²) by room type, and the words that name it.
ROOM_AREAS: dict[str, tuple[tuple[str, ...], tuple[float, float]]] = {
    "bathroom": (("bathroom", "bath", "toilet", "wc", "washroom"), (2.0, 16.0)),
    "kids room": (("kid", "kids", "child", "children", "nursery", "playroom"), (6.0, 30.0)),
    "bedroom": (("bedroom", "bed", "dorm", "guest"), (6.0, 35.0)),
    "kitchen": (("kitchen", "kitchenette"), (4.0, 35.0)),
    "dining room": (("dining",), (7.0, 40.0)),
    "office": (("office", "study", "workroom"), (4.0, 30.0)),
    "living room": (("living", "lounge", "family", "sitting"), (9.0, 60.0)),
    "studio": (("studio", "apartment", "loft"), (14.0, 70.0)),
}
#: The furniture each room type of :data:`ROOM_AREAS` cannot do without (a bedroom asks for a
#: bed without naming it).
ROOM_FURNITURE: dict[str, tuple[str, ...]] = {
    "bathroom": ("toilet", "sink"),
    "kids room": ("bed",),
    "bedroom": ("bed",),
    "kitchen": ("counter", "stove", "fridge", "sink"),
    "dining room": ("dining_table", "table", "chair"),
    "office": ("desk", "chair"),
    "living room": ("sofa",),
    "studio": ("bed", "sofa"),
}
_SIZE_SLACK = 1.5      # a size is "far" from its range beyond this factor
AREA_SLACK = 1.3      # a floor area is "far" from its room type's range beyond this
_MAX_ASPECT = 2.5      # longer side / shorter side of an ordinary room
#: Distinct targets of one positional relation (``left_of``, ``around``, ...) per object.
MAX_TARGETS = 2
#: Step of the sweep over the spots of an object bound near a door, a window or a wall,
#: metres.
SPOT_STEP = 0.05
#: A spot this close to a clearance zone or past the floor's edge still counts as clear
#: (the checks tolerate a sliver of overlap), metres.
_SPOT_SLACK = 0.02
#: Spots judged for clearance at a time (the sweep stops at the first clear one).
_SPOT_CHUNK = 256
#: Reaches tried, as multiples of the rule's own, to say which one would leave a spot.
_REACH_FACTORS = (1.25, 1.5, 2.0, 3.0)



@dataclass(frozen=True)
class Finding:
    """One thing wrong with a plan that validation lets through.

    Attributes
    ----------
    path : str
        JSON path of the field, e.g. ``"objects[2].size"`` or ``"rules[4] (in_corner)"``.
    message : str
        What is wrong, in one sentence.
    fix : str
        What to change.
    severity : {"infeasible", "implausible"}
        ``"infeasible"``: no layout can meet the plan; ``"implausible"``:
        layouts exist but the plan is likely not what was meant.
    refs : tuple of str
        Every path the finding involves (for a finding about several rules).
    """

    path: str
    message: str
    fix: str
    severity: Severity = "implausible"
    refs: tuple[str, ...] = ()

    def __str__(self) -> str:
        return f"{self.path}: {self.message}; {self.fix}"


def _tokens(text: str) -> list[str]:
    return [t for t in re.split(r"[^a-z0-9]+", text.lower()) if t and not t.isdigit()]


def category_key(category: str) -> str | None:
    """The :data:`CATEGORY_SIZES` key a category (or an id) names, or None.

    Tries the whole name, its last two words and its last word, each also
    through a table of synonyms (``"bedside table"`` -> ``"nightstand"``).
    """
    words = _tokens(category)
    if not words:
        return None
    candidates = ["_".join(words), "".join(words)]
    if len(words) >= 2:
        candidates.append("_".join(words[-2:]))
    candidates.append(words[-1])
    if words[-1].endswith("s"):
        candidates.append(words[-1][:-1])
    for c in candidates:
        c = _SYNONYMS.get(c, c)
        if c in CATEGORY_SIZES:
            return c
    return None


def article(noun: str) -> str:
    """``"an"`` before a vowel, else ``"a"`` (``"an office"``, ``"a bedroom"``)."""
    return "an" if noun[:1].lower() in "aeiou" else "a"


def room_kind(name: str, description: str = "") -> str | None:
    """The :data:`ROOM_AREAS` room type a plan's name (else its description) names, or None.

    Examples
    --------
    >>> room_kind("student_bedroom"), room_kind("den", "a small home office")
    ('bedroom', 'office')
    """
    for text in (name, description):
        words = set(_tokens(text or ""))
        kind = next((k for k, (keys, _) in ROOM_AREAS.items() if words & set(keys)), None)
        if kind is not None:
            return kind
    return None


def usual_size(category: str, size: Sequence[float]) -> list[float] | None:
    """``size`` brought into the usual ranges of its category, or None for a category
    :data:`CATEGORY_SIZES` does not know.

    The shorter and the longer side of the footprint and the height are each clamped into
    the category's range; the side that was the width stays the width.

    Examples
    --------
    >>> usual_size("sofa", [2.0, 1.8, 0.8])
    [2.0, 1.2, 0.8]
    >>> usual_size("spaceship", [9, 9, 9]) is None
    True
    """
    key = category_key(category)
    if key is None:
        return None
    (s_lo, s_hi), (l_lo, l_hi), (h_lo, h_hi) = CATEGORY_SIZES[key]
    w, d, h = (float(x) for x in size[:3])
    short, long_ = sorted((w, d))
    short, long_ = min(max(short, s_lo), s_hi), min(max(long_, l_lo), l_hi)
    if short > long_:
        short, long_ = long_, short
    w, d = (short, long_) if w <= d else (long_, short)
    return [round(w, 3), round(d, 3), round(min(max(h, h_lo), h_hi), 3)]


def convex_corners(polygon: Iterable[tuple[float, float]] | Iterable[list[float]]) -> int:
    """Number of convex corners of a simple floor polygon (collinear vertices do not count)."""
    pts = [tuple(map(float, p)) for p in polygon]
    n = len(pts)
    if n < 3:
        return 0
    area2 = sum(pts[i][0] * pts[(i + 1) % n][1] - pts[(i + 1) % n][0] * pts[i][1]
                for i in range(n))
    sign = 1.0 if area2 > 0 else -1.0
    count = 0
    for i in range(n):
        (ax, ay), (bx, by), (cx, cy) = pts[i - 1], pts[i], pts[(i + 1) % n]
        cross = (bx - ax) * (cy - by) - (by - ay) * (cx - bx)
        if sign * cross > 1e-9 * max(1.0, math.hypot(bx - ax, by - ay)):
            count += 1
    return count


def _fmt(x: float) -> str:
    return f"{x:g}"


def _rng(r: tuple[float, float]) -> str:
    return f"{_fmt(r[0])}-{_fmt(r[1])}"


def _size_findings(plan: Plan) -> Iterable[Finding]:
    for k, o in enumerate(plan.objects):
        words = _tokens(o.category)
        if words and words[-1] in OPENING_WORDS:
            yield Finding(f"objects[{k}].category",
                          f"{o.id!r} is a {o.category} listed as an object",
                          "remove it and declare it in room.doors or room.windows",
                          refs=(f"objects[{k}]",))
            continue
        if names_the_room(o.category):
            yield Finding(f"objects[{k}].category",
                          f"{o.id!r} ({o.category}) is the room itself listed as an object",
                          "remove it: the room is described by 'room'",
                          refs=(f"objects[{k}]",))
            continue
        key = category_key(o.category)
        if key is None:
            continue
        (s_lo, s_hi), (l_lo, l_hi), (h_lo, h_hi) = CATEGORY_SIZES[key]
        short, long_ = sorted(o.size[:2])
        h = o.size[2]
        flat = (short < s_lo / _SIZE_SLACK or short > s_hi * _SIZE_SLACK
                or long_ < l_lo / _SIZE_SLACK or long_ > l_hi * _SIZE_SLACK)
        tall = h < h_lo / _SIZE_SLACK or h > h_hi * _SIZE_SLACK
        what = key.replace("_", " ")
        if flat:
            yield Finding(f"objects[{k}].size",
                          f"{o.id!r} (category {o.category!r}) is {_fmt(o.size[0])} x "
                          f"{_fmt(o.size[1])} m; {article(what)} {what} is usually "
                          f"{_rng((s_lo, s_hi))} x "
                          f"{_rng((l_lo, l_hi))} m (height {_rng((h_lo, h_hi))} m)",
                          "fix the size or the category", refs=(f"objects[{k}]",))
        elif tall:  # the footprint is usual: say it is the height
            yield Finding(f"objects[{k}].size[2]",
                          f"{o.id!r} (category {o.category!r}) is {_fmt(h)} m tall; "
                          f"{article(what)} {what} is usually {_rng((h_lo, h_hi))} m tall",
                          "fix the height (size[2]) or the category", refs=(f"objects[{k}]",))


def _room_findings(plan: Plan) -> Iterable[Finding]:
    floor = plan.room.shape
    rect = floor.minimum_rotated_rectangle
    xs, ys = rect.exterior.xy
    sides = sorted({math.hypot(xs[1] - xs[0], ys[1] - ys[0]),
                    math.hypot(xs[2] - xs[1], ys[2] - ys[1])})
    short, long_ = sides[0], sides[-1]
    kind = room_kind(plan.name, plan.description)
    words = set(_tokens(plan.name)) | set(_tokens(plan.description))
    area = float(floor.area)
    if kind is not None:
        lo, hi = ROOM_AREAS[kind][1]
        if area > hi * AREA_SLACK or area < lo / AREA_SLACK:
            yield Finding("room.polygon", f"the floor is {area:.1f} m² ({long_:.2f} x "
                          f"{short:.2f} m); {article(kind)} {kind} is usually "
                          f"{_fmt(lo)}-{_fmt(hi)} m²",
                          "resize the polygon", refs=("room",))
            return
    if short > 0 and long_ / short > _MAX_ASPECT and not words & {"corridor", "hallway",
                                                                    "hall", "gallery"}:
        yield Finding("room.polygon", f"the room is {long_:.2f} x {short:.2f} m, "
                      f"{long_ / short:.1f} times as long as wide",
                      f"use a room at most {_MAX_ASPECT:g} times as long as wide",
                      refs=("room",))


def _door_findings(plan: Plan) -> Iterable[Finding]:
    """Doors on different walls whose swings (the square of a door's width inside the room,
    which the checks keep free) overlap, as at a corner: the open doors would hit each
    other. One finding for the later of each pair."""
    doors = plan.room.doors
    if len(doors) < 2:
        return
    geom = geo.RoomGeometry.from_room(plan.room)
    squares = [shapely.Polygon(c) for c in geo.corners_from_axes(*geom.door_squares)]
    for b in range(1, len(doors)):
        for a in range(b):
            overlap = squares[b].intersection(squares[a]).area
            if doors[a].wall != doors[b].wall and overlap > 1e-4:
                yield Finding(f"room.doors[{b}].offset",
                              f"its swing (the square of its width inside the room) overlaps "
                              f"that of room.doors[{a}] by {overlap:.2f} m²: the two open "
                              "doors would hit each other",
                              "move one along its wall, away from the corner",
                              refs=(f"room.doors[{a}]", f"room.doors[{b}]"))
                break


def _rule(name: str) -> Rule | None:
    """The registered rule ``name`` (its class declares what the findings need), or None."""
    try:
        return registry.get_rule(name)
    except UnknownRuleError:
        return None


def gap_band(close: Rule, close_params: Any, far: Rule, far_params: Any
             ) -> tuple[float, float] | None:
    """The footprint gaps a close rule and a far rule on one pair both allow, or None.

    Rules that bound the gap of two footprints do so with a ``distance``
    parameter: at most it for a close rule (``near``, ``next_to``,
    ``in_front_of``), at least it for a far one (``far_from``). Two such rules
    on one pair keep it in the band between (``far_from`` 0.8 m and ``near``
    1.2 m: two armchairs facing each other across a side table), which is
    no contradiction. ``None`` where either rule has no ``distance`` or the
    band is empty.
    """
    try:
        lo = float(far.Params.model_validate(far_params or {}).distance)  # type: ignore[attr-defined]
        hi = float(close.Params.model_validate(close_params or {}).distance)  # type: ignore[attr-defined]
    except (AttributeError, TypeError, ValueError):  # no distance, or params it refuses
        return None
    return (lo, hi) if lo < hi else None


def _is_corner(name: str) -> bool:
    """Whether the rule tucks its object into a corner (limited by the floor's corners)."""
    rule = _rule(name)
    return rule is not None and rule.start is not None and rule.start.place == "corner"


def _opposite(name: str) -> str | None:
    """The rule ``name`` declares to contradict it (the relation is symmetric)."""
    return getattr(_rule(name), "opposite", None)


#: Gap two objects pushed together come to rest at, about (the contact margin of the
#: physics, metres): a close rule asking for less is seldom met.
CONTACT_GAP = 0.03


def _rule_findings(plan: Plan) -> Iterable[Finding]:
    # a close rule whose distance is below the gap objects come to rest at
    for k, r in enumerate(plan.rules):
        rule = _rule(r.rule)
        value = r.params.get("distance")
        if rule is not None and rule.closeness == "close" and isinstance(value, int | float) \
                and 0 <= value < CONTACT_GAP:
            yield Finding(f"rules[{k}] ({r.rule}).params.distance",
                          f"{value:g} m is less than the {CONTACT_GAP * 100:.0f} cm or so two "
                          "objects come to rest apart when pushed together, so it is seldom "
                          "met (cabinets in a run settle about 2.5 cm apart)",
                          "give a distance of 0.05 m or more", refs=(f"rules[{k}]",))
    # an angle in degrees that reads as radians (max_angle 0.5: half a degree)
    for k, r in enumerate(plan.rules):
        for name, value in r.params.items():
            if name.endswith("angle") and isinstance(value, float) and 0 < value < math.pi \
                    and not value.is_integer():
                yield Finding(f"rules[{k}] ({r.rule}).params.{name}",
                              f"{value:g} is in degrees (under {math.ceil(value):d}°); "
                              f"{value:g} radians would be {math.degrees(value):.0f}°",
                              f"give {name} in degrees, e.g. {math.degrees(value):.0f}",
                              refs=(f"rules[{k}]",))
    # duplicates
    first: dict[tuple[str, str, str | None], int] = {}
    for k, r in enumerate(plan.rules):
        key = (r.rule, r.object, r.target)
        if key in first:
            j = first[key]
            yield Finding(f"rules[{k}] ({r.rule})", f"repeats rules[{j}] "
                          f"({r.rule} {r.object}" + (f" -> {r.target})" if r.target else ")"),
                          "remove it", refs=(f"rules[{k}]",))
        else:
            first[key] = k
    # more corner objects than corners
    corners = convex_corners(plan.room.polygon)
    in_corner = [k for k, r in enumerate(plan.rules) if _is_corner(r.rule)]
    objs = list(dict.fromkeys(plan.rules[k].object for k in in_corner))
    area_corner = [a.name for a in plan.areas if any(_is_corner(x.rule) for x in a.rules)]
    wanted = len(objs) + len(area_corner)
    if wanted > corners:
        refs = tuple(f"rules[{k}]" for k in in_corner) + tuple(
            f"areas[{i}]" for i, a in enumerate(plan.areas) if a.name in area_corner)
        extra = ", ".join(f"rules[{k}]" for k in in_corner[corners:]) or "the area rules"
        names = list(dict.fromkeys([plan.rules[k].rule for k in in_corner] + [
            x.rule for a in plan.areas for x in a.rules if _is_corner(x.rule)]))
        fallbacks = [f for f in dict.fromkeys(getattr(_rule(n), "fallback", None) for n in names)
                     if f is not None]
        instead = (f"use {' or '.join(fallbacks)} for {extra}" if fallbacks
                   else f"bind {extra} otherwise")
        yield Finding(f"rules[{in_corner[-1]}] ({plan.rules[in_corner[-1]].rule})"
                      if in_corner else "areas",
                      f"{wanted} objects or areas are tucked into corners but the room has "
                      f"{corners} convex corners",
                      f"keep at most {corners} {' / '.join(names)} rules ({instead})",
                      severity="infeasible", refs=refs)
    # contradictions on one object or one pair
    by_obj: dict[str, dict[str, int]] = defaultdict(dict)
    by_pair: dict[frozenset[str], dict[str, int]] = defaultdict(dict)
    for k, r in enumerate(plan.rules):
        by_obj[r.object].setdefault(r.rule, k)
        if r.target is not None:
            by_pair[frozenset((r.object, r.target))].setdefault(r.rule, k)
    for oid, rules in by_obj.items():
        seen: set[frozenset[str]] = set()
        for a in rules:
            b = _opposite(a)
            if b is None or b not in rules or frozenset((a, b)) in seen or \
                    plan.rules[rules[a]].target != plan.rules[rules[b]].target:
                continue
            seen.add(frozenset((a, b)))
            k = max(rules[a], rules[b])
            yield Finding(f"rules[{k}] ({plan.rules[k].rule})",
                          f"{oid!r} is both {a} and {b}"
                          + (f" {plan.rules[k].target!r}" if plan.rules[k].target else ""),
                          f"keep one of rules[{min(rules[a], rules[b])}] and rules[{k}]",
                          severity="infeasible", refs=(f"rules[{rules[a]}]",
                                                       f"rules[{rules[b]}]"))
    for pair, rules in by_pair.items():
        far = [n for n in rules if getattr(_rule(n), "closeness", None) == "far"]
        close = [n for n in rules if getattr(_rule(n), "closeness", None) == "close"]
        if far and close:
            name = far[0]
            k, j = rules[name], rules[close[0]]
            if gap_band(_rule(close[0]), plan.rules[j].params, _rule(name),  # type: ignore[arg-type]
                        plan.rules[k].params) is not None:
                continue  # a band of gaps between the two: no contradiction
            a, b = sorted(pair)
            yield Finding(f"rules[{k}] ({name})", f"{a!r} and {b!r} are both {name} and "
                          f"{close[0]} (rules[{j}])", f"keep one of rules[{min(j, k)}] and "
                          f"rules[{max(j, k)}]", severity="infeasible",
                          refs=(f"rules[{j}]", f"rules[{k}]"))
    # a floor cover under a target that covers it whole: it never shows (a rule that
    # starts its object beneath its target: ``under``)
    for k, r in enumerate(plan.rules):
        rule = _rule(r.rule)
        if rule is None or rule.start is None or rule.start.place != "beneath" \
                or r.target is None:
            continue
        cover, over = plan.object(r.object).size, plan.object(r.target).size
        if cover[0] <= over[0] + 1e-9 and cover[1] <= over[1] + 1e-9:
            yield Finding(f"rules[{k}] ({r.rule})",
                          f"{r.object!r} ({_fmt(cover[0])} x {_fmt(cover[1])} m) lies wholly "
                          f"under {r.target!r} ({_fmt(over[0])} x {_fmt(over[1])} m), so it is "
                          "hidden in every layout",
                          f"make {r.object!r} wider and longer than {r.target!r} (a rug under a "
                          "bed shows 0.3 to 0.6 m at its sides and foot), or drop the rule",
                          refs=(f"rules[{k}]", f"objects[{plan.ids.index(r.object)}]"))
    # one object bound to many targets by one positional relation
    targets: dict[tuple[str, str], list[int]] = defaultdict(list)
    for k, r in enumerate(plan.rules):
        if getattr(_rule(r.rule), "positional", False) and r.target is not None:
            ks = targets[(r.object, r.rule)]
            if r.target not in {plan.rules[j].target for j in ks}:
                ks.append(k)
    for (oid, rule), ks in targets.items():
        if len(ks) > MAX_TARGETS:
            yield Finding(f"rules[{ks[-1]}] ({rule})", f"{oid!r} is {rule} {len(ks)} targets "
                          f"({', '.join(repr(plan.rules[j].target) for j in ks)})",
                          f"keep it {rule} at most {MAX_TARGETS} of them (drop "
                          f"{', '.join(f'rules[{j}]' for j in ks[MAX_TARGETS:])})",
                          refs=tuple(f"rules[{j}]" for j in ks))


def _spots(room: geo.RoomGeometry, size: np.ndarray, at_wall: bool
           ) -> tuple[np.ndarray, np.ndarray]:
    """Poses (M, 2) and headings (M,) an object of ``size`` could take, swept every
    :data:`SPOT_STEP`: backs against each wall along its length with ``at_wall``, else a
    grid over the floor's bounds at the headings that square it with each wall."""
    w, d = float(size[0]), float(size[1])
    if at_wall:
        pos, yaw = [], []
        for k in range(room.n_walls):
            t = np.arange(0.5 * w, room.length[k] - 0.5 * w + 1e-9, SPOT_STEP)
            n = room.normal[k]
            pos.append(room.a[k] + t[:, None] * room.tangent[k] + (0.5 * d + 1e-3) * n)
            yaw.append(np.full(len(t), math.atan2(-n[0], n[1])))
        return np.concatenate(pos).reshape(-1, 2), np.concatenate(yaw)
    lo, hi = room.bounds[:2], room.bounds[2:]
    gx, gy = np.meshgrid(np.arange(lo[0], hi[0] + 1e-9, SPOT_STEP),
                         np.arange(lo[1], hi[1] + 1e-9, SPOT_STEP))
    grid = np.stack([gx.ravel(), gy.ravel()], axis=1)
    square = np.unique(np.round(np.mod(np.arctan2(room.tangent[:, 1], room.tangent[:, 0]),
                                       0.5 * np.pi), 6))
    turns = np.concatenate([square, square + 0.5 * np.pi])  # either side along each wall
    pos = np.concatenate([grid] * len(turns))
    return pos, np.repeat(turns, len(grid))


def _zones_below(plan: Plan, geom: geo.RoomGeometry) -> Callable[[float], tuple]:
    """The zones the checks keep free of an object ``height`` tall, as boxes (centre, right,
    front, half; each (Z, 2)): every door's swing square and the zone in front of every
    window whose sill is below it."""
    from forcelayout.validate import window_zones

    zc, zr, zf, zh, sill = window_zones(plan.room)
    dc, dr, df, dh = geom.door_squares

    def below(height: float) -> tuple[np.ndarray, ...]:
        keep = (zh[:, 1] > 0) & (sill < height - 1e-9)
        return tuple(np.concatenate([a[keep], b]) for a, b in
                     ((zc, dc), (zr, dr), (zf, df), (zh, dh)))

    return below


class _Spots:
    """The swept spots of one object bound near an opening, judged by its rules' own checks
    and, lazily and once each, by the clearance the checks ask of them."""

    def __init__(self, geom: geo.RoomGeometry, floor: shapely.Polygon,
                 zones: tuple[np.ndarray, ...], size: np.ndarray, rule: Rule,
                 walls: list[tuple[int, Rule, object]]):
        self.floor, self.zones, self.rule = floor, zones, rule
        self.half = 0.5 * size[:2]
        self.pos, self.yaw = _spots(geom, size, bool(walls))
        m = len(self.pos)
        self.state = State(self.pos, self.yaw, np.repeat(size[None], m, axis=0), geom)
        self.at_wall = np.ones(m, dtype=bool)
        for _, wall_rule, wall_params in walls:
            self.at_wall &= self._satisfied(wall_rule, wall_params)
        self.tested = np.zeros(m, dtype=bool)  # spots whose clearance is known
        self.clear = np.zeros(m, dtype=bool)

    def _satisfied(self, rule: Rule, params: object) -> np.ndarray:
        m = len(self.pos)
        return rule.satisfied(self.state, np.arange(m), None,
                              ParamArrays.from_models([params] * m, np.ones(m)))

    def any_met(self, params: object) -> bool:
        """Whether a clear spot meets the rule with ``params`` (and the wall rules); the
        clearance is judged a few hundred spots at a time until one is clear."""
        near = self.at_wall & self._satisfied(self.rule, params)
        if (near & self.clear).any():
            return True
        todo = np.flatnonzero(near & ~self.tested)
        for first in range(0, len(todo), _SPOT_CHUNK):
            k = todo[first:first + _SPOT_CHUNK]
            self.clear[k] = self._clear(k)
            self.tested[k] = True
            if self.clear[k].any():
                return True
        return False

    def _clear(self, k: np.ndarray) -> np.ndarray:
        """Which of the spots ``k`` lie inside the floor and clear of the zones (what the
        checks ask, less :data:`_SPOT_SLACK`)."""
        pos, rgt, fwd = self.pos[k], self.state.right[k], self.state.front[k]
        corners = geo.corners_from_axes(pos, rgt, fwd, np.broadcast_to(self.half, pos.shape))
        ok = shapely.contains(self.floor, shapely.polygons(corners))
        zc, zr, zf, zh = self.zones
        if len(zc):
            sep = geo.obb_separation(zc[None] - pos[:, None], rgt[:, None], fwd[:, None],
                                     self.half[None, None], zr[None], zf[None], zh[None])
            ok &= sep.min(axis=1) >= -_SPOT_SLACK
        return ok


def _zones_in_the_way(room: Room, height: float) -> tuple[bool, str]:
    """Whether a window's zone keeps out an object ``height`` tall, and the zones the checks
    keep it out of, in words: "the door swings and the zones in front of the windows whose
    sill is below its 2 m" (empty for none)."""
    low = any(w.sill < height - 1e-9 and w.clearance > 0 for w in room.windows)
    zones = " and ".join(
        ["the door swings"] * bool(room.doors)
        + [f"the zones in front of the windows whose sill is below its {height:g} m"] * low)
    return low, zones


@dataclass(frozen=True)
class OutOfReach:
    """A rule that binds an object near a door or a window no spot within its reach allows.

    Attributes
    ----------
    rule : int
        Index of the rule in ``plan.rules``.
    param : str
        The rule's parameter that sets its reach (``StartHint.reach``, e.g. ``"distance"``).
    reach : float
        Its value, metres.
    wider : float or None
        The least reach of those tried (up to 3 times the rule's own, rounded up to
        5 cm) that leaves a spot, or None.
    finding : Finding
        What :func:`plan_findings` says about it.
    """

    rule: int
    param: str
    reach: float
    wider: float | None
    finding: Finding


def out_of_reach(plan: Plan) -> list[OutOfReach]:
    """Objects bound near a door or a window with no spot within the rule's reach.

    For each rule whose start hint places its object at a ``"door"`` or a
    ``"window"`` within a ``reach`` (``near_door``, ``near_window``, plugins
    that declare the same), the object's spots are swept every
    :data:`SPOT_STEP` — along the walls with their backs to them when a rule
    with start place ``"wall"`` binds it too (``at_wall``), else over the
    floor — and judged by those rules' own checks and by the clearance the
    checks ask: inside the floor, clear of the door swings and of the zones
    in front of windows whose sill is below the object. A rule no clear spot
    meets is listed, with the least wider reach (of 1.25, 1.5, 2 and 3 times
    its own) that would leave one.

    Parameters
    ----------
    plan : Plan

    Returns
    -------
    list of OutOfReach
        In the order of ``plan.rules``.
    """
    room = plan.room
    geom = geo.RoomGeometry.from_room(room)
    obstacles = {o.id for o in plan.floor_objects() if not o.is_walkable}
    floor = geom.shape.buffer(_SPOT_SLACK)
    shapely.prepare(floor)
    zones_below = _zones_below(plan, geom)

    out: list[OutOfReach] = []
    for k, spec in enumerate(plan.rules):
        got = _unary(spec)
        hint = getattr(got[0], "start", None) if got else None
        if got is None or hint is None or hint.place not in ("door", "window") or \
                not hint.reach:
            continue
        rule, params = got
        reach = float(getattr(params, hint.reach))
        if not getattr(room, f"{hint.place}s"):  # none of that kind: said so, nothing swept
            out.append(OutOfReach(k, hint.reach, reach, None, Finding(
                f"rules[{k}] ({spec.rule})",
                f"{spec.rule}({spec.object}) cannot be met: the room has no {hint.place}",
                f"add one to room.{hint.place}s or drop rules[{k}]", severity="infeasible",
                refs=(f"rules[{k}]",))))
            continue
        if spec.object not in obstacles:
            continue
        walls = [(j, *w) for j, r in enumerate(plan.rules)
                 if r.object == spec.object and (w := _unary(r)) is not None
                 and w[0].start is not None and w[0].start.place == "wall"]
        size = np.asarray(plan.object(spec.object).size, dtype=float)
        try:
            spots = _Spots(geom, floor, zones_below(float(size[2])), size, rule, walls)
            if spots.any_met(params):
                continue
            tries = [math.ceil(f * reach * 20 - 1e-9) / 20 for f in _REACH_FACTORS]  # 5 cm
            wider = next((x for x in tries
                          if spots.any_met(params.model_copy(update={hint.reach: x}))), None)
        except Exception:  # noqa: BLE001 - a plugin rule whose check needs more than a
            continue  # lone object's pose: nothing said rather than no findings at all
        low, zones = _zones_in_the_way(room, float(size[2]))
        where = "against a wall " if walls else ""
        both = (f"{spec.rule}({spec.object}) and "
                f"{', '.join(f'{plan.rules[j].rule}({spec.object})' for j, *_ in walls)}"
                " cannot both be met" if walls else f"{spec.rule}({spec.object}) cannot be met")
        fix = (f"give rules[{k}] a {hint.reach} of {wider:g} m" if wider is not None
               else "move or narrow the openings in the way")
        if low:
            fix += f", make {spec.object!r} no taller than the sill"
        fix += " or drop " + ("one of these rules" if walls else f"rules[{k}]")
        finding = Finding(f"rules[{k}] ({spec.rule})",
                          f"{both}: no spot {where}within {reach:g} m of a {hint.place}'s "
                          f"centre is clear of {zones}", fix, severity="infeasible",
                          refs=(f"rules[{k}]", *(f"rules[{j}]" for j, *_ in walls)))
        out.append(OutOfReach(k, hint.reach, reach, wider, finding))
    return out


def _unary(spec: RuleSpec) -> tuple[Rule, object] | None:
    """A unary rule of the plan and its parameters, or None (a relation, an unknown rule,
    parameters that do not validate)."""
    rule = _rule(spec.rule)
    if rule is None or spec.target is not None:
        return None
    try:
        return rule, rule.Params.model_validate(dict(spec.params or {}))
    except ValidationError:
        return None


def off_the_walls(plan: Plan) -> list[Finding]:
    """Objects a wall rule binds that no stretch of wall can hold.

    For each floor object bound by a rule whose start hint places it at a
    ``"wall"`` (``at_wall``, plugins that declare the same), its spots with the
    back against each wall are swept every :data:`SPOT_STEP` and judged by
    that rule's own check and by the clearance the checks ask: inside the
    floor, clear of the door swings and of the zones in front of windows
    whose sill is below the object. An object with no such spot (a 3.2 m wall
    unit in a room whose long walls hold a door and a window) is listed once,
    with its first such rule.

    Parameters
    ----------
    plan : Plan

    Returns
    -------
    list of Finding
        ``"infeasible"``, in the order of ``plan.rules``.
    """
    room = plan.room
    obstacles = {o.id for o in plan.floor_objects() if not o.is_walkable}
    geom = floor = zones_below = None
    out: list[Finding] = []
    seen: set[str] = set()
    for k, spec in enumerate(plan.rules):
        got = _unary(spec) if spec.object in obstacles and spec.object not in seen else None
        hint = getattr(got[0], "start", None) if got else None
        if got is None or hint is None or hint.place != "wall":
            continue
        seen.add(spec.object)
        if geom is None:
            geom = geo.RoomGeometry.from_room(room)
            floor = geom.shape.buffer(_SPOT_SLACK)
            shapely.prepare(floor)
            zones_below = _zones_below(plan, geom)
        rule, params = got
        size = np.asarray(plan.object(spec.object).size, dtype=float)
        try:
            spots = _Spots(geom, floor, zones_below(float(size[2])), size, rule,
                           [(k, rule, params)])
            if spots.any_met(params):
                continue
        except Exception:  # noqa: BLE001 - a plugin rule whose check needs more than a
            continue  # lone object's pose: nothing said rather than no findings at all
        low, zones = _zones_in_the_way(room, float(size[2]))
        clear = f" is clear of {zones}" if zones else " holds it"
        fix = f"make {spec.object!r} narrower"
        fix += ", move or narrow the openings in the way" if zones else ""
        fix += f" or drop rules[{k}]"
        out.append(Finding(f"rules[{k}] ({spec.rule})",
                           f"{spec.rule}({spec.object}) cannot be met: no stretch of wall "
                           f"{size[0]:g} m long{clear}", fix, severity="infeasible",
                           refs=(f"rules[{k}]",)))
    return out


#: Step of the sweep over the wall spots of two objects that face each other, metres.
PAIR_STEP = 0.1
#: Most spots of one object that sweep pairs (a longer step in a hall with long walls).
_PAIR_SPOTS = 400


def facing_apart(plan: Plan) -> list[Finding]:
    """Two objects at walls that face each other with a close rule no pair of spots meets.

    For each close rule (``closeness="close"``: ``near``, ``next_to``, ...)
    between two floor objects that a wall rule binds (a start hint with
    ``place="wall"``) and that each face the other (a rule whose start hint
    turns the object to its target, ``facing``), the spots of each with its
    back against a wall, swept every :data:`PAIR_STEP`, that meet its own
    unary rules (``away_from_window``, ...) and are clear of the door swings
    and of the zones in front of windows whose sill is below it, are paired
    and judged by those rules' own checks. Where pairs face each other but
    none meets the close rule, and the least gap between such a pair exceeds
    the rule's ``distance`` by more than the sweep's step (a sofa and the TV
    stand it faces across a 4.6 m room, ``near`` 3 m: 3.35 m apart at the
    least), the close rule is listed, with the distance that would do.

    Returns
    -------
    list of Finding
        ``"infeasible"``, in the order of ``plan.rules``.
    """
    floor_ids = {o.id for o in plan.floor_objects() if not o.is_walkable}
    unary: dict[str, list[tuple[int, Rule, object]]] = defaultdict(list)
    faces: dict[tuple[str, str], list[tuple[Rule, object]]] = defaultdict(list)
    close: list[tuple[int, Rule, object]] = []
    for k, spec in enumerate(plan.rules):
        rule = _rule(spec.rule)
        if rule is None or spec.object not in floor_ids:
            continue
        try:
            params = rule.Params.model_validate(dict(spec.params or {}))
        except ValidationError:
            continue
        hint = rule.start
        if spec.target is None:
            unary[spec.object].append((k, rule, params))
        elif spec.target in floor_ids:
            if hint is not None and hint.turn == "face_target" and hint.place is None:
                faces[spec.object, spec.target].append((rule, params))
            if rule.closeness == "close":
                close.append((k, rule, params))

    def walled(oid: str) -> bool:
        return any(r.start is not None and r.start.place == "wall" for _, r, _ in unary[oid])

    out: list[Finding] = []
    spots: dict[str, tuple[np.ndarray, np.ndarray, float]] = {}
    geom = None
    for k, rule, params in close:
        a, b = plan.rules[k].object, plan.rules[k].target
        distance = getattr(params, "distance", None)
        if distance is None or not (walled(a) and walled(b) and faces.get((a, b))
                                    and faces.get((b, a))):
            continue
        if geom is None:
            geom = geo.RoomGeometry.from_room(plan.room)
            floor = geom.shape.buffer(_SPOT_SLACK)
            shapely.prepare(floor)
            zones_below = _zones_below(plan, geom)
        for oid in (a, b):
            if oid not in spots:
                spots[oid] = _own_spots(geom, floor, zones_below, plan.object(oid).size,
                                        unary[oid])
        (pa, ya, step_a), (pb, yb, step_b) = spots[a], spots[b]
        m = len(pa) * len(pb)
        if m == 0:
            continue  # no spot at all: said by off_the_walls
        ia, ib = np.repeat(np.arange(len(pa)), len(pb)), np.tile(np.arange(len(pb)), len(pa))
        size = np.asarray([plan.object(a).size, plan.object(b).size], dtype=float)
        state = State(np.stack([pa[ia], pb[ib]], axis=1).reshape(-1, 2),
                      np.stack([ya[ia], yb[ib]], axis=1).reshape(-1), np.tile(size, (m, 1)),
                      geom, samples=m)
        i, j = np.arange(0, 2 * m, 2), np.arange(1, 2 * m, 2)
        facing = np.ones(m, dtype=bool)
        try:
            for (x, y), rules in (((i, j), faces[a, b]), ((j, i), faces[b, a])):
                for r, p in rules:
                    facing &= r.satisfied(state, x, y,
                                          ParamArrays.from_models([p] * m, np.ones(m)))
            met = rule.satisfied(state, i, j, ParamArrays.from_models([params] * m, np.ones(m)))
        except Exception:  # noqa: BLE001 - a plugin rule whose check needs more than the
            continue  # pair's poses: nothing said rather than no findings at all
        if not facing.any() or (met & facing).any():
            continue  # they never face each other (another finding, or none), or they can
        least = float(state.gap_estimate(i, j)[facing].min())
        if least <= float(distance) + max(step_a, step_b):
            continue
        spec = plan.rules[k]
        out.append(Finding(
            f"rules[{k}] ({spec.rule})",
            f"{spec.rule}({a}, {b}) with distance {float(distance):g} m cannot be met: at "
            f"walls and facing each other, {a!r} and {b!r} stand {least:.2f} m apart at the "
            "least", f"give rules[{k}] a distance of {math.ceil(least * 10 + 0.5) / 10:g} m, "
            "or let one of them off its wall", severity="infeasible", refs=(f"rules[{k}]",)))
    return out


def _own_spots(geom: geo.RoomGeometry, floor: shapely.Polygon,
               zones_below: Callable[[float], tuple], size: Sequence[float],
               unary: list[tuple[int, Rule, object]]
               ) -> tuple[np.ndarray, np.ndarray, float]:
    """An object's spots with its back against a wall, every :data:`PAIR_STEP` (or more, for
    at most ``_PAIR_SPOTS`` of them), that meet its own unary rules and are clear of the
    zones the checks keep free of it, and the step (metres)."""
    size = np.asarray(size, dtype=float)
    walls = [(k, r, p) for k, r, p in unary if r.start is not None and r.start.place == "wall"]
    sp = _Spots(geom, floor, zones_below(float(size[2])), size, walls[0][1], walls)
    keep = sp.at_wall.copy()
    for _, r, p in unary:
        try:
            keep &= sp._satisfied(r, p)
        except Exception:  # noqa: BLE001 - a plugin rule whose check needs more than a
            continue  # lone object's pose: judged by the others alone
    k = np.flatnonzero(keep)
    every = max(1, round(PAIR_STEP / SPOT_STEP), -(-len(k) // _PAIR_SPOTS))
    k = k[::every]
    k = k[sp._clear(k)] if len(k) else k
    return sp.pos[k], sp.yaw[k], every * SPOT_STEP


def _access_findings(plan: Plan, required: bool) -> Iterable[Finding]:
    """Objects used from the back only that a rule stands with the back to a wall
    (infeasible where the access check is ``required``)."""
    from forcelayout.access import access_of  # imports the rule registry's bindings

    rules_of: dict[str, list[tuple[int, Rule]]] = defaultdict(list)
    for k, spec in enumerate(plan.rules):
        rule = _rule(spec.rule)
        if rule is not None:
            rules_of[spec.object].append((k, rule))
    for i, obj in enumerate(plan.objects):
        walled = [(k, r) for k, r in rules_of.get(obj.id, ())
                  if r.start is not None and r.start.place in ("wall", "corner")]
        if not walled:
            continue
        own = [SimpleNamespace(object=obj.id, rule=r) for _, r in rules_of[obj.id]]
        acc = access_of(obj, own)  # type: ignore[arg-type]
        if acc is None or not acc.sides or set(acc.sides) != {"back"}:
            continue
        k, rule = walled[0]
        given = obj.access is not None
        where = "as its access says" if given else f"as a {obj.category!r} is"
        yield Finding(f"objects[{i}].access" if given else f"objects[{i}]",
                      f"{obj.id!r} is used from its back ({where}), but "
                      f"{plan.rules[k].rule}({obj.id}) stands its back against a wall: that "
                      "side is never free, and --access rejects every layout",
                      "an object at a wall faces the room with its front: give it "
                      '"access": {"sides": ["front"]} (or "access": false), or drop '
                      f"rules[{k}]", severity="infeasible" if required else "implausible",
                      refs=(f"objects[{i}]", f"rules[{k}]"))


def plan_findings(plan: Plan, *, access: bool = False) -> list[Finding]:
    """Everything impossible or implausible about a valid plan, infeasible first.

    Checks: more ``in_corner`` objects (and areas) than the floor has convex
    corners; an object bound near a door or a window (``near_door``,
    ``near_window``: a rule whose start hint places it there within a reach)
    with no spot within that reach clear of the door swings and of the zones
    in front of windows whose sill is below it (against a wall when a wall
    rule binds it too; :func:`out_of_reach`); an object bound to a wall that
    no stretch of wall clear of them holds (:func:`off_the_walls`, said in
    place of its :func:`out_of_reach` finding); one object
    both ``far_from`` and close to the same target, or
    bound by opposite rules (``in_front_of`` and ``behind``, ``at_wall`` and
    ``in_middle``, ...); duplicated rules; one object bound by one positional
    relation to more than two targets; a floor cover ``under`` a target that
    covers it whole (hidden in every layout); a door or window listed as an object;
    an object whose size is far (a factor 1.5) from its category's usual
    range (:data:`CATEGORY_SIZES`); a floor far from the usual area of the
    room type its name or description names (:data:`ROOM_AREAS`), or more
    than 2.5 times as long as wide; two doors whose swings overlap (at a
    corner: the open doors would hit each other); two objects at walls that face
    each other with a close rule no pair of their spots meets
    (:func:`facing_apart`); an object used from its back
    alone (its ``access``, else its category's) that a rule stands with its
    back to a wall (``at_wall``, ``in_corner``).

    Parameters
    ----------
    plan : Plan
        A validated plan.
    access : bool
        Whether the layouts must leave every object a free access zone (the
        ``access`` check, ``--access``): an object whose only access side
        stands against a wall is then infeasible, else implausible.

    Returns
    -------
    list of Finding
    """
    walls = off_the_walls(plan)
    stuck = {plan.rules[int(f.refs[0][6:-1])].object for f in walls}
    out = [*_rule_findings(plan), *walls,
           *(u.finding for u in out_of_reach(plan)
             if plan.rules[u.rule].object not in stuck),  # said once, the simpler way
           *_size_findings(plan),
           *_room_findings(plan),
           *_door_findings(plan),
           *facing_apart(plan),
           *_access_findings(plan, access)]
    return sorted(out, key=lambda f: f.severity != "infeasible")

