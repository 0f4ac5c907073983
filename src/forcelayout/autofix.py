"""Deterministic fixes of a plan draft: what needs no judgement is fixed without asking.

:func:`autofix` takes a plan as a dict (before validation) and returns a
fixed copy and one line per change, so the LLM planner fixes near misses
itself and asks the model again only about what needs a choice:

* a floor far outside the usual area of the room type the plan names
  (:data:`forcelayout.sanity.ROOM_AREAS`: a 10 x 5 m office) is scaled to
  the nearest end of that range; a floor the floor objects would cover
  beyond :data:`FILL_LIMIT` is enlarged, within that range, until they
  cover :data:`FILL_TARGET` (doors and windows keep their relative place);
* a door or window that leaves its wall is moved (and if needed narrowed)
  onto it; a window reaching above the ceiling is lowered;
* a unary rule given a target (``at_wall`` with target ``"room"``) loses it;
  a binary rule whose target names the door, the window, a wall or a corner
  becomes the unary rule meant (``near`` ``"window"`` -> ``near_window``);
* near-miss rule names (``"next to"``, ``"nextTo"``, ``"against_wall"``)
  and object ids (``"bed"`` for the only bed, ``"desk chair"``) are mapped;
  categories are written in lower case with underscores;
* duplicated rules are dropped; an object's area that is not declared is
  mapped onto the declared one it spells differently, else dropped;
* doors and windows listed as objects are removed with their rules, and so
  is the room itself (or a wall, the floor) listed as an object;
* more ``in_corner`` objects (and areas) than the floor has convex
  corners: the extra ones become ``at_wall``;
* an object both ``far_from`` and close to one target loses the
  ``far_from``; of two opposite rules on one object (``at_wall`` and
  ``in_middle``, ``left_of`` and ``right_of`` one target) the later is
  dropped, and so is a positional relation of one object to more than
  :data:`forcelayout.sanity.MAX_TARGETS` targets;
* an off-floor rule that cannot hold is dropped (the object stays on the
  floor): a second surface for one object, a child larger than its
  parent's top (a sofa on a coffee table), a child resting on its own
  descendant;
* an object bound near a door or a window with no spot within the rule's
  reach clear of the door swings and of the zones in front of windows whose
  sill is below it (:func:`forcelayout.sanity.out_of_reach`: a desk at a
  wall near a low window that fills most of its wall) gets the least wider
  reach that leaves a spot, up to three times its own.

What these fixes know about rules (aliases, the rule a feature of the room
means, corner rules and their fallback, close and far rules) is read from
the rules' declarations (:class:`forcelayout.rules.Rule`), so a plugin rule
takes part by declaring it.

Examples
--------
>>> from forcelayout.autofix import autofix
>>> fixed, notes = autofix({
...     "name": "office",
...     "room": {"polygon": [[0, 0], [10, 0], [10, 5], [0, 5]],
...              "doors": [{"wall": 0, "offset": 0.05, "width": 0.9}]},
...     "objects": [{"id": "desk", "category": "Desk", "size": [1.4, 0.7, 0.75]}],
...     "rules": [{"rule": "at wall", "object": "desk", "target": "room"}]})
>>> fixed["room"]["polygon"][2], fixed["room"]["doors"][0]["offset"], fixed["rules"]
([7.746, 3.873], 0.45, [{'rule': 'at_wall', 'object': 'desk'}])
>>> for n in notes: print(n.split(" (")[0])
objects[0].category: 'Desk' -> 'desk'
rules[0].rule: 'at wall' read as 'at_wall'
rules[0]
room.polygon: scaled by 0.77 from 50.0 to 30.0 m²
room.doors[0].offset: moved the door onto wall 0: offset 0.039 -> 0.45 m
"""

from __future__ import annotations

import copy
import difflib
import math
import re
from typing import Any

from forcelayout import rules as registry
from forcelayout.errors import PlanError
from forcelayout.plan import Plan, SceneObject
from forcelayout.rules import Rule
from forcelayout.sanity import (
    AREA_SLACK,
    MAX_TARGETS,
    OPENING_WORDS,
    ROOM_AREAS,
    article,
    category_key,
    convex_corners,
    gap_band,
    names_the_room,
    out_of_reach,
    room_kind,
)
from forcelayout.surfaces.tops import holds

__all__ = ["autofix", "rule_aliases", "FILL_LIMIT", "FILL_TARGET"]

#: Share of the floor the floor objects may cover before :func:`autofix` enlarges the room
#: (crowded rooms of the benchmark suite reach 0.45 and still pack) ...
FILL_LIMIT = 0.5
#: ... and the share they cover once it is enlarged.
FILL_TARGET = 0.45


def _declared() -> list[Rule]:
    """Every registered rule whose class can be loaded (its declarations drive the fixes)."""
    out = []
    for name in registry.available_rules():
        try:
            out.append(registry.get_rule(name))
        except Exception:  # a broken plugin is reported where a plan names it, not here
            continue
    return out


def rule_aliases() -> dict[str, str]:
    """Near-miss rule names and the registered rule each means, from the rules' ``aliases``.

    An alias two rules declare is ambiguous and left out; so is an alias that
    is itself a registered name.
    """
    claims: dict[str, set[str]] = {}
    for rule in _declared():
        for alias in rule.aliases:
            claims.setdefault(alias, set()).add(rule.name)
    return {a: next(iter(names)) for a, names in sorted(claims.items())
            if len(names) == 1 and not registry.is_registered(a)}


def __getattr__(name: str) -> Any:
    if name == "RULE_ALIASES":  # computed: plugins registered later declare aliases too
        return rule_aliases()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _feature_rules() -> dict[str, dict[str, str]]:
    """``{feature: {target rule: rule meant}}`` from the rules' ``feature`` and ``specialises``.

    A target rule aimed at a room feature (``near`` the ``"window"``) means the
    rule declaring that feature and specialising it (``near_window``).
    """
    out: dict[str, dict[str, str]] = {}
    for rule in _declared():
        if rule.feature is not None:
            meant = out.setdefault(rule.feature, {})
            for general in rule.specialises:
                meant.setdefault(general, rule.name)
    return out


def _snake(text: str) -> str:
    s = re.sub(r"([a-z0-9])([A-Z])", r"\1_\2", text.strip())
    return re.sub(r"[^A-Za-z0-9]+", "_", s).strip("_").lower()


def _rule_name(name: str, known: list[str], aliases: dict[str, str]) -> str | None:
    """The registered rule a near-miss name means, or None."""
    s = _snake(name)
    if s in known:
        return s
    if s in aliases and aliases[s] in known:
        return aliases[s]
    close = difflib.get_close_matches(s, known, n=1, cutoff=0.8)
    return close[0] if close else None


def _feature(target: str, features: dict[str, dict[str, str]]) -> str | None:
    words = [w for w in re.split(r"[^a-z]+", target.lower()) if w]
    for w in words:
        w = w[:-1] if w.endswith("s") else w
        if w in features or w == "room":
            return w
    return None


def room_feature_hint(rule: str, target: str, obj: str = "...") -> str:
    """The hint for a target that names a feature of the room (``"window"``, ``"door_0"``),
    not an object: the rule meant for it (``near`` the window is ``near_window``), else
    the rules about that feature; ``""`` for any other target."""
    features = _feature_rules()
    feature = _feature(target, features)
    if feature is None or feature == "room":
        return ""
    meant = features.get(feature, {}).get(rule)
    place = f"room.{feature}s"
    if meant is not None:
        return (f" A {feature} is part of the room ({place}), not an object: use "
                f"{{\"rule\": \"{meant}\", \"object\": \"{obj}\"}} with no target.")
    about = sorted({r.name for r in _declared() if r.feature == feature})
    return (f" A {feature} is part of the room ({place}), not an object"
            + (f"; the rules about {feature}s: {', '.join(about)}." if about else "."))


def resolve_id(value: Any, ids: list[str], by_category: dict[str, list[str]]) -> Any:
    """The object id a near-miss reference means (``"bed"`` for the only bed), else ``value``.

    Tries, in order: a category with one object, the id in snake case, the one
    numbered id of that name (``"desk chair"`` -> ``"desk_chair_1"``) and a
    close spelling (difflib ratio >= 0.85).
    """
    if not isinstance(value, str) or value in ids or not ids:
        return value
    if value in by_category and len(by_category[value]) == 1:
        return by_category[value][0]
    s = _snake(value)
    if s in ids:
        return s
    numbered = [i for i in ids if re.fullmatch(re.escape(s) + r"_?\d+", i)]
    if len(numbered) == 1:
        return numbered[0]
    close = difflib.get_close_matches(s, ids, n=1, cutoff=0.85)
    return close[0] if close else value


def _num(x: Any) -> float | None:
    return float(x) if isinstance(x, int | float) and not isinstance(x, bool) \
        and math.isfinite(x) else None


def _points(room: dict[str, Any]) -> list[tuple[float, float]] | None:
    try:
        pts = [(float(p[0]), float(p[1])) for p in room.get("polygon")]  # type: ignore[union-attr]
    except (TypeError, ValueError, IndexError):
        return None
    return pts if len(pts) >= 3 and all(map(math.isfinite, sum(pts, ()))) else None


def _area(pts: list[tuple[float, float]]) -> float:
    nxt = pts[1:] + pts[:1]
    return 0.5 * abs(sum(ax * by - bx * ay for (ax, ay), (bx, by) in zip(pts, nxt, strict=True)))


def _floor_footprint(objects: list[dict[str, Any]], rules: list[Any]) -> float:
    """Footprint (m²) of the objects standing on the floor as obstacles (as validation counts)."""
    off = {r.get("object") for r in rules if isinstance(r, dict)
           and isinstance(r.get("rule"), str) and registry.is_registered(r["rule"])
           and registry.get_rule(r["rule"]).surface != "floor"}
    total = 0.0
    for o in objects:
        if o.get("id") in off:
            continue
        try:
            obj = SceneObject.model_validate(o)
        except ValueError:
            continue
        if not obj.is_walkable:
            total += obj.size[0] * obj.size[1]
    return total


def _size(o: dict[str, Any] | None) -> tuple[float, float] | None:
    size = o.get("size") if isinstance(o, dict) else None
    if not isinstance(size, list | tuple) or len(size) < 2:
        return None
    w, d = _num(size[0]), _num(size[1])
    return None if w is None or d is None else (w, d)


def _fix_surfaces(rules: list[Any], objects: list[dict[str, Any]], notes: list[str]
                  ) -> list[Any]:
    """Drop off-floor rules that cannot hold: a second surface for one object, a top too small
    for its child, a child resting on its own descendant. The object stays on the floor."""
    by_id = {o.get("id"): o for o in objects}
    placed: dict[str, str] = {}
    parent: dict[str, str] = {}
    held: dict[str, list[tuple[float, float]]] = {}  # the footprints on each top so far
    out = []
    for r in rules:
        rule = (registry.get_rule(r["rule"]) if isinstance(r, dict)
                and isinstance(r.get("rule"), str) and registry.is_registered(r["rule"])
                else None)
        if rule is None or rule.surface == "floor" or not isinstance(r.get("object"), str):
            out.append(r)
            continue
        child, target = r["object"], r.get("target")
        why, c = None, None  # c: the child's footprint, when it goes on a top
        if child in placed:
            why = f"{child!r} already rests on {placed[child]}"
        elif rule.surface == "top" and isinstance(target, str):
            c, p = _size(by_id.get(child)), _size(by_id.get(target))
            cur: str | None = target
            for _ in range(len(parent) + 1):  # is the target resting on the child already?
                if cur is None or cur == child:
                    break
                cur = parent.get(cur)
            if cur == child:
                why = f"{target!r} already rests on {child!r}"
            elif c is not None and p is not None and (
                    min(c) > min(p) + 1e-9 or max(c) > max(p) + 1e-9):
                why = (f"{child!r} ({c[0]:g} x {c[1]:g} m) does not fit on top of {target!r} "
                       f"({p[0]:g} x {p[1]:g} m)")
            elif c is not None and p is not None and not holds(
                    [*held.get(target, []), c], p[0], p[1]):
                why = (f"the top of {target!r} ({p[0]:g} x {p[1]:g} m) has no room left for "
                       f"{child!r} ({c[0]:g} x {c[1]:g} m) beside "
                       f"{len(held[target])} other object(s)")
        if why is not None:
            notes.append(f"rules ({child}): removed {r['rule']} {target!r} ({why}); it stays "
                         "on the floor")
            continue
        placed[child] = f"{target!r}" if isinstance(target, str) else f"the {rule.surface}"
        if rule.surface == "top" and isinstance(target, str):
            parent[child] = target
            if c is not None:
                held.setdefault(target, []).append(c)
        out.append(r)
    return out


def _fix_object_areas(out: dict[str, Any], objects: list[dict[str, Any]], notes: list[str]
                      ) -> None:
    """An object's area a plan with areas does not declare: the declared one it spells differently
    (``"Sleeping area"`` for ``sleeping``), else none (the object keeps its own rules)."""
    names = [str(a.get("name")) for a in out.get("areas") or []
             if isinstance(a, dict) and isinstance(a.get("name"), str)]
    if not names:  # a plan without areas may label its objects freely
        return
    by_key = {_snake(n): n for n in names}
    for k, o in enumerate(objects):
        area = o.get("area")
        if not isinstance(area, str) or not area or area in names:
            continue
        key = _snake(area)
        match = by_key.get(key) or by_key.get(re.sub(r"_?area$", "", key))
        if match is not None:
            notes.append(f"objects[{k}].area: {area!r} read as {match!r}")
            o["area"] = match
        else:
            notes.append(f"objects[{k}].area: removed {area!r} (no such area is declared); "
                         f"{o.get('id')!r} belongs to no area")
            o["area"] = None


def _rule_of(r: Any) -> Rule | None:
    """The registered rule a rule dict names, or None."""
    if not isinstance(r, dict) or not isinstance(r.get("rule"), str) \
            or not registry.is_registered(r["rule"]):
        return None
    return registry.get_rule(r["rule"])


def _fix_contradictions(rules: list[Any], notes: list[str]) -> list[Any]:
    """Drop the later of two opposite rules on one object, and positional relations of one
    object beyond :data:`forcelayout.sanity.MAX_TARGETS` targets."""
    kept: list[Any] = []
    by_obj: dict[Any, list[tuple[str, Rule, Any]]] = {}
    targets: dict[tuple[Any, str], list[Any]] = {}
    for r in rules:
        rule = _rule_of(r)
        if rule is None:
            kept.append(r)
            continue
        obj, target, name = r.get("object"), r.get("target"), r["rule"]
        clash = next((other for other, o_rule, t in by_obj.get(obj, []) if t == target and (
            rule.opposite == other or o_rule.opposite == name)), None)
        if clash is not None:
            notes.append(f"rules ({obj}): removed {name}"
                         + (f" {target!r}" if target is not None else "")
                         + f", which contradicts its {clash} rule")
            continue
        if rule.positional and target is not None:
            have = targets.setdefault((obj, name), [])
            if target not in have and len(have) >= MAX_TARGETS:
                notes.append(f"rules ({obj}): removed {name} {target!r} (it is already {name} "
                             f"{' and '.join(repr(t) for t in have)}; one object keeps a "
                             f"relation to at most {MAX_TARGETS} targets)")
                continue
            if target not in have:
                have.append(target)
        by_obj.setdefault(obj, []).append((name, rule, target))
        kept.append(r)
    return kept


def _fix_room_size(data: dict[str, Any], room: dict[str, Any], notes: list[str]) -> None:
    """Scale a floor of an implausible size, or one its floor objects would crowd."""
    pts = _points(room)
    if pts is None:
        return
    area = _area(pts)
    if area <= 1e-6:
        return
    kind = room_kind(str(data.get("name") or ""), str(data.get("description") or ""))
    lo, hi = ROOM_AREAS[kind][1] if kind is not None else (0.0, 2.0 * area)
    new, why = area, ""
    if kind is not None and not lo / AREA_SLACK <= area <= hi * AREA_SLACK:
        new = min(max(area, lo), hi)
        why = f"{article(kind)} {kind} is usually {lo:g}-{hi:g} m²"
    objects = [o for o in data.get("objects") or [] if isinstance(o, dict)]
    foot = _floor_footprint(objects, data.get("rules") or [])
    if foot > FILL_LIMIT * new and foot / FILL_TARGET <= hi + 1e-9:
        new = foot / FILL_TARGET
        why = (f"the floor objects cover {foot:.1f} m², more than {FILL_LIMIT:.0%} of "
               f"{area:.1f} m²")
    if not why:
        return
    s = math.sqrt(new / area)
    x0, y0 = min(p[0] for p in pts), min(p[1] for p in pts)
    room["polygon"] = [[round(x0 + (x - x0) * s, 3), round(y0 + (y - y0) * s, 3)]
                       for x, y in pts]
    for kind_ in ("doors", "windows"):
        for o in room.get(kind_) or []:
            if isinstance(o, dict) and _num(o.get("offset")) is not None:
                o["offset"] = round(o["offset"] * s, 3)
    notes.append(f"room.polygon: scaled by {s:.2f} from {area:.1f} to {new:.1f} m² ({why}); "
                 "doors and windows keep their relative place")


def _free_spot(length: float, width: float, taken: list[tuple[float, float]],
               near: float) -> float | None:
    """The centre nearest ``near`` of a ``width`` stretch of a wall ``length`` long clear of
    the ``taken`` stretches by 0.1 m (and within the wall), or None."""
    from forcelayout.surfaces.walls import free_intervals

    free = free_intervals(length, [(a, b, 0.0, 1.0) for a, b in taken], 0.0, 1.0, margin=0.1)
    spots = [min(max(near, a + width / 2), b - width / 2) for a, b in free if b - a >= width]
    return min(spots, key=lambda x: abs(x - near), default=None)


def _fix_overlaps(room: dict[str, Any], pts: list[tuple[float, float]], notes: list[str]
                  ) -> None:
    """Move an opening that shares a stretch of its wall with an earlier one at the same
    heights (doors first, then windows) to the nearest free stretch of that wall, else to
    the middle of the longest free stretch of another wall."""
    n = len(pts)
    length = [math.dist(pts[i], pts[(i + 1) % n]) for i in range(n)]
    placed: list[tuple[int, float, float, float, float]] = []  # wall, from, to, low, high
    for kind, noun in (("doors", "door"), ("windows", "window")):
        for k, o in enumerate(room.get(kind) or []):
            if not isinstance(o, dict) or not isinstance(o.get("wall"), int) \
                    or not 0 <= o["wall"] < n or _num(o.get("offset")) is None:
                continue
            width = _num(o.get("width")) or (0.9 if kind == "doors" else 1.2)
            if kind == "doors":
                low, high = 0.0, _num(o.get("height")) or 2.05
            else:
                low = 0.9 if _num(o.get("sill")) is None else _num(o.get("sill"))
                high = low + (_num(o.get("height")) or 1.2)

            def taken(wall: int, low: float = low, high: float = high
                      ) -> list[tuple[float, float]]:
                return [(a, b) for w, a, b, lo, hi in placed
                        if w == wall and min(hi, high) - max(lo, low) > 1e-6]

            wall, offset = o["wall"], float(o["offset"])
            clash = any(min(b, offset + width / 2) - max(a, offset - width / 2) > 1e-6
                        for a, b in taken(wall))
            if clash:
                spot = _free_spot(length[wall], width, taken(wall), offset)
                new_wall = wall
                if spot is None:  # the longest free stretch of another wall
                    others = [(w, _free_spot(length[w], width, taken(w), length[w] / 2))
                              for w in range(n) if w != wall]
                    others = [(w, x) for w, x in others if x is not None]
                    if others:
                        new_wall, spot = max(others, key=lambda wx: length[wx[0]])
                if spot is not None:
                    spot = round(spot, 3)
                    where = f"to wall {new_wall}" if new_wall != wall else f"along wall {wall}"
                    notes.append(f"room.{kind}[{k}].offset: moved the {noun} {where} off the "
                                 f"opening it overlapped: offset {offset:g} -> {spot:g} m")
                    o["wall"], o["offset"], wall, offset = new_wall, spot, new_wall, spot
            placed.append((wall, offset - width / 2, offset + width / 2, low, high))


def _fix_openings(room: dict[str, Any], notes: list[str]) -> None:
    pts = _points(room)
    if pts is None:
        return
    n = len(pts)
    height = _num(room.get("height")) or 2.7
    for kind, noun in (("doors", "door"), ("windows", "window")):
        for k, o in enumerate(room.get(kind) or []):
            if not isinstance(o, dict) or not isinstance(o.get("wall"), int) \
                    or not 0 <= o["wall"] < n:
                continue
            i = o["wall"]
            (ax, ay), (bx, by) = pts[i], pts[(i + 1) % n]
            length = math.hypot(bx - ax, by - ay)
            width = _num(o.get("width")) or (0.9 if kind == "doors" else 1.2)
            offset = _num(o.get("offset"))
            path = f"room.{kind}[{k}]"
            if length <= 0.3 or offset is None:
                continue
            if width > length - 0.1:
                new_w = round(max(0.3, length - 0.2), 2)
                notes.append(f"{path}.width: narrowed the {noun} from {width:g} to {new_w:g} m "
                             f"to fit wall {i} ({length:.2f} m)")
                o["width"] = width = new_w
            lo, hi = width / 2, length - width / 2
            if not lo - 1e-9 <= offset <= hi + 1e-9:
                new = round(min(max(offset, lo), hi), 3)
                notes.append(f"{path}.offset: moved the {noun} onto wall {i}: offset "
                             f"{offset:g} -> {new:g} m (offset must lie in [{lo:.2f}, "
                             f"{hi:.2f}] m for a {width:g} m {noun} on a "
                             f"{round(length, 2):g} m wall)")
                o["offset"] = new
            if kind == "windows":
                sill, h = _num(o.get("sill")), _num(o.get("height"))
                sill = 0.9 if sill is None else sill
                h = 1.2 if h is None else h
                if sill + h > height and h < height:
                    new_sill = round(max(0.0, height - h - 0.1), 2)
                    notes.append(f"{path}.sill: lowered the window from {sill:g} to "
                                 f"{new_sill:g} m so it ends below the {height:g} m ceiling")
                    o["sill"] = new_sill
    _fix_overlaps(room, pts, notes)


def autofix(data: dict[str, Any]) -> tuple[dict[str, Any], list[str]]:
    """Fix what needs no judgement in a plan dict; return the fixed copy and one note per fix.

    The input is not changed and need not be valid: fields of the wrong type
    are left for validation to report. See the module docstring for the list
    of fixes. Rule names are mapped only onto registered rules.

    Parameters
    ----------
    data : dict
        A plan as JSON data (``room``, ``objects``, ``rules``, ``areas``).

    Returns
    -------
    (dict, list of str)
        The fixed plan and, for each change, ``"<path>: <what was done>"``.
    """
    out = copy.deepcopy(data)
    notes: list[str] = []
    room = out.get("room")
    objects = [o for o in out.get("objects") or [] if isinstance(o, dict)]
    rules = out.get("rules")
    if not isinstance(rules, list):
        if isinstance(room, dict):
            _fix_room_size(out, room, notes)
            _fix_openings(room, notes)
        return out, notes
    # categories; doors and windows listed as objects
    removed: set[str] = set()
    kept = []
    for k, o in enumerate(objects):
        cat = o.get("category")
        if isinstance(cat, str):
            words = [w for w in re.split(r"[^a-z0-9]+", cat.lower()) if w]
            if words and words[-1] in OPENING_WORDS and category_key(cat) is None:
                removed.add(str(o.get("id")))
                notes.append(f"objects[{k}]: removed {o.get('id')!r}, a {cat} listed as an "
                             "object (doors and windows belong in room.doors / room.windows)")
                continue
            if names_the_room(cat):
                removed.add(str(o.get("id")))
                notes.append(f"objects[{k}]: removed {o.get('id')!r} ({cat}), the room itself "
                             "listed as an object (the room is described by 'room')")
                continue
            snake = _snake(cat)
            if snake and snake != cat:
                notes.append(f"objects[{k}].category: {cat!r} -> {snake!r}")
                o["category"] = snake
        kept.append(o)
    _fix_object_areas(out, kept, notes)
    if removed and isinstance(out.get("objects"), list):
        out["objects"] = [o for o in out["objects"]
                          if not (isinstance(o, dict) and str(o.get("id")) in removed)]
    ids = [str(o.get("id")) for o in kept if isinstance(o.get("id"), str)]
    by_cat: dict[str, list[str]] = {}
    for o in kept:
        if isinstance(o.get("id"), str) and isinstance(o.get("category"), str):
            by_cat.setdefault(o["category"], []).append(o["id"])
    known = registry.available_rules()
    aliases = rule_aliases()
    features = _feature_rules()

    def map_id(value: Any) -> Any:
        return resolve_id(value, ids, by_cat)

    new_rules: list[Any] = []
    seen: set[str] = set()
    for k, r in enumerate(rules):
        if not isinstance(r, dict) or not isinstance(r.get("rule"), str):
            new_rules.append(r)
            continue
        name = r["rule"]
        if not registry.is_registered(name):
            mapped = _rule_name(name, known, aliases)
            if mapped is not None:
                notes.append(f"rules[{k}].rule: {name!r} read as {mapped!r}")
                r["rule"] = name = mapped
        if r.get("object") in removed or r.get("target") in removed:
            notes.append(f"rules[{k}] ({name}): removed with the object it names")
            continue
        for field in ("object", "target"):
            new = map_id(r.get(field))
            if new != r.get(field):
                notes.append(f"rules[{k}] ({name}).{field}: {r[field]!r} read as {new!r}")
                r[field] = new
        target = r.get("target")
        if registry.is_registered(name):
            rule = registry.get_rule(name)
            if isinstance(target, str) and target not in ids and rule.target != "none":
                feature = _feature(target, features)
                unary = features.get(feature or "", {}).get(name)
                if unary is not None and registry.is_registered(unary):
                    notes.append(f"rules[{k}] ({name}): {name} {target!r} read as {unary} "
                                 "(the target is the room's, not an object)")
                    r = {**r, "rule": unary}
                    r.pop("target", None)
                    r["params"] = {}
                    name, rule = unary, registry.get_rule(unary)
            if rule.target == "none" and r.get("target") not in (None, ""):
                notes.append(f"rules[{k}] ({name}).target: removed {r['target']!r} "
                             f"({name} takes no target)")
                r.pop("target")
        if r.get("target") == "":
            r.pop("target")
        key = repr((r.get("rule"), r.get("object"), r.get("target"),
                    sorted((r.get("params") or {}).items()) if isinstance(r.get("params"), dict)
                    else r.get("params")))
        if key in seen:
            notes.append(f"rules[{k}] ({name}): removed, it repeats an earlier rule")
            continue
        seen.add(key)
        new_rules.append(r)
    # more corner objects than corners -> the extra ones become the rule's fallback
    if isinstance(room, dict):
        try:
            corners = convex_corners(room.get("polygon") or [])
        except (TypeError, ValueError, IndexError):
            corners = 4
        in_corner = [r for r in new_rules if (rule := _rule_of(r)) is not None
                     and rule.start is not None and rule.start.place == "corner"]
        names = "/".join(dict.fromkeys(r["rule"] for r in in_corner))
        have = {(r.get("rule"), r.get("object"), r.get("target")) for r in new_rules
                if isinstance(r, dict)}
        dropped: list[Any] = []
        for r in in_corner[corners:]:
            fallback = registry.get_rule(r["rule"]).fallback
            if fallback is None or not registry.is_registered(fallback):
                continue
            why = f"the room has {corners} convex corners for {len(in_corner)} {names} objects"
            if (fallback, r.get("object"), r.get("target")) in have:
                notes.append(f"rules ({r.get('object')}): removed {r['rule']} ({why}; it is "
                             f"already {fallback})")
                dropped.append(r)
                continue
            notes.append(f"rules ({r.get('object')}): {r['rule']} -> {fallback} ({why})")
            r["rule"] = fallback
            r["params"] = {}
            have.add((fallback, r.get("object"), r.get("target")))
        new_rules = [r for r in new_rules if not any(r is d for d in dropped)]
        # areas tucked into corners take what the objects left
        left = max(corners - len(in_corner), 0)
        for i, area in enumerate(out.get("areas") or []):
            if not isinstance(area, dict) or not isinstance(area.get("rules"), list):
                continue
            for j, x in enumerate(area["rules"]):
                rule = _rule_of(x)
                if rule is None or rule.start is None or rule.start.place != "corner":
                    continue
                if left > 0:
                    left -= 1
                    continue
                fallback = rule.fallback
                if fallback is None or not registry.is_registered(fallback):
                    continue
                notes.append(f"areas[{i}].rules[{j}]: {x['rule']} -> {fallback} (the room's "
                             f"{corners} convex corners are taken)")
                x["rule"] = fallback
                x["params"] = {}
            # the fallback may now repeat a rule of the area
            unique: dict[str, Any] = {}
            for x in area["rules"]:
                key = repr((x.get("rule"), x.get("params"))) if isinstance(x, dict) else repr(x)
                unique.setdefault(key, x)
            area["rules"] = list(unique.values())
    # far and close to the same target, with no band of gaps between -> drop the far rule
    close_pairs: dict[frozenset, tuple[Rule, Any]] = {}
    for r in new_rules:
        if (rule := _rule_of(r)) is not None and rule.closeness == "close" and r.get("target"):
            close_pairs.setdefault(frozenset((r.get("object"), r.get("target"))),
                                   (rule, r.get("params")))
    final = []
    for r in new_rules:
        rule = _rule_of(r)
        pair = frozenset((r.get("object"), r.get("target")))
        if rule is not None and rule.closeness == "far" and pair in close_pairs and \
                gap_band(*close_pairs[pair], rule, r.get("params")) is None:
            notes.append(f"rules ({r.get('object')}): removed {r['rule']} {r.get('target')!r}, "
                         "which contradicts a rule that keeps them close")
            continue
        final.append(r)
    final = _fix_contradictions(final, notes)
    out["rules"] = _fix_surfaces(final, kept, notes)
    if isinstance(room, dict):
        _fix_room_size(out, room, notes)
        _fix_openings(room, notes)
    _fix_reach(out, notes)
    return out, notes


def _fix_reach(out: dict[str, Any], notes: list[str]) -> None:
    """Rules that bind an object near a door or a window no spot within their reach allows
    (:func:`forcelayout.sanity.out_of_reach`) get the least wider reach that leaves one."""
    try:
        plan = Plan.from_dict(out)
    except PlanError:
        return  # validation reports what is wrong first
    for u in out_of_reach(plan):
        r = out["rules"][u.rule]
        if u.wider is None or not isinstance(r, dict):
            continue
        r["params"] = {**(r.get("params") or {}), u.param: u.wider}
        notes.append(f"rules[{u.rule}] ({r.get('rule')}).params.{u.param}: {u.reach:g} -> "
                     f"{u.wider:g} m ({u.finding.message.split(': ', 1)[1]})")
