"""Prompt templates of the planning steps, and the rule vocabulary text.

Templates are :class:`string.Template` strings (``$name`` placeholders), so
JSON braces need no escaping. Users override any of them::

    from dataclasses import replace
    from forcelayout.llm import DEFAULT_TEMPLATES, Planner
    templates = replace(DEFAULT_TEMPLATES, decor="Add only plants and lamps. $plan ...")
    planner = Planner(client, templates=templates)

Placeholders available to every template: ``$prompt`` (the user's scene
description), ``$conventions``, ``$vocabulary`` (generated from the rule
registry, so plugin rules are offered automatically), ``$plan`` (the plan so
far, JSON), ``$shape`` (an outline of the reply's keys in order, with their types and
meanings; :func:`forcelayout.llm.steps.shape_of`), ``$schema`` (the step's whole JSON
Schema, which the server is given to enforce; a fifth of a small model's prompt if shown)
and, in ``expand``,
``$room_type`` and ``$k``. ``repair`` gets ``$problems``; ``check`` gets
``$report``, the library's own findings about the plan
(:func:`forcelayout.diagnose.feasibility`); ``correct`` gets ``$issues``, the
problems the check listed.
"""

from __future__ import annotations

import string
from dataclasses import dataclass, fields

from forcelayout._text import one_line
from forcelayout.rules import RuleInfo, available_rules, describe_rules

__all__ = ["PromptTemplates", "DEFAULT_TEMPLATES", "vocabulary", "vocabulary_text", "render",
           "PLANNING_KINDS", "RULE_EXAMPLES"]

#: Rule kinds the planner may use.
PLANNING_KINDS = ("unary", "binary", "surface")

_CONVENTIONS = """\
Conventions: lengths in metres. The floor is a simple polygon of [x, y] corners listed in \
order; wall i runs from polygon[i] to polygon[i+1] (the last wall closes back to \
polygon[0]). A door or window sits on wall i with its centre `offset` metres from \
polygon[i]; it must fit on the wall. An object's size is [width, depth, height]: width \
along its left-right axis, depth front-to-back (its front is where a person uses it, e.g. \
the seat side of a sofa), height upwards. Floor objects together must cover well under \
60 % of the floor. Ids are unique, made of letters, digits and underscores \
(e.g. chair_1, chair_2)."""

_SYSTEM = """\
You plan indoor scenes for a physics-based layout generator. You never give coordinates \
of furniture: you describe the room, the objects and the rules that place them; the \
generator finds many layouts that meet the rules. Answer every request with exactly one \
JSON object with the keys asked for, in that order, with no other text. Write the JSON \
compactly, without indentation, and give each rule once: a few rules that matter beat many \
that restate each other.

$conventions

The placement rules, the only ones you may use (unary rules take no target; binary \
rules, on_top and above need a target object id):
$vocabulary"""

_ROOM = """\
Scene description: "$prompt"

Step 1 of 5: room properties and functional areas.
Choose a plausible room for the description: its floor polygon (usually a rectangle, an \
L-shape when the description suggests it), ceiling height, doors and windows; and 2 to 4 \
functional areas (e.g. sleeping, work, storage, seating).

Answer with one JSON object with these keys, in this order:
$shape"""

_OBJECTS = """\
Scene description: "$prompt"

Step 2 of 5: the furniture and its placement rules.
List the main (non-decorative) objects this room needs, each with a realistic size, its \
functional area and whether it is primary (main furniture a person must reach). Then give \
the placement rules and pairwise relations that make the room functional: one or two rules \
for each object, using only the rules of the system message.

The plan so far:
$plan

Answer with one JSON object with these keys, in this order:
$shape"""

_GRAPH = """\
Scene description: "$prompt"

Step 3 of 5: the scene graph.
Group the objects into the functional areas (every object id in at most one area) and give \
each area its placement rules (e.g. at_wall for a sleeping area). List support bonds: an \
object that rests on top of another (a lamp on a nightstand) as \
{"object": child id, "parent": parent id}. Area rules may use only the unary rules \
(no target).

The plan so far:
$plan

Answer with one JSON object with these keys, in this order:
$shape"""

_DECOR = """\
Scene description: "$prompt"

Step 4 of 5: secondary decorative items.
Add the small and decorative items that make the room look lived-in (plants, lamps, \
pictures, ceiling lights) with realistic sizes and rules that place them: on_top of \
furniture, on walls, on the ceiling, or on the floor next to furniture. Use new unique ids \
and only the rules of the system message.

The plan so far:
$plan

Answer with one JSON object with these keys, in this order:
$shape"""

_CHECK = """\
Scene description: "$prompt"

Step 5 of 5: check the plan.
The layout generator's own check of the plan below found:
$report

List the problems of the plan: the ones above, furniture the description asks for but the \
plan lacks, objects of an absurd size, rules that contradict each other. Each problem in one \
short sentence; an empty list if there are none. Do not repeat the plan.

The plan:
$plan

Answer with one JSON object with these keys, in this order:
$shape"""

_CORRECT = """\
Scene description: "$prompt"

Step 5 of 5, continued: correct the plan.
These problems were found in the plan below:
$issues

Give the whole corrected plan, using only the rules of the system message. Change only what \
the problems need.

The plan:
$plan

Answer with one JSON object with these keys, in this order:
$shape"""

_REPAIR = """\
Your reply could not be used:
$problems

Answer again with the complete corrected JSON object for this step, with the keys asked for."""

_EXPAND = """\
Write $k distinct, specific descriptions of a "$room_type" as one might ask an interior \
designer for it (e.g. "a student's bedroom with a desk by the window", "a cosy reading \
corner living room"). Vary who lives there, the style, the size and the furniture. Each \
description is one sentence.

Answer with one JSON object with these keys, in this order:
$shape"""


@dataclass(frozen=True)
class PromptTemplates:
    """The planner's prompt templates (``string.Template`` syntax, ``$name``).

    Attributes
    ----------
    system : str
        System message of every request.
    room, objects, graph, decor, check : str
        User message of planning steps 1-5 (``check`` asks for the problems only).
    correct : str
        User message asking for the corrected plan once the check found problems
        (``$issues``).
    repair : str
        Message sent after an unusable reply; ``$problems`` lists what was wrong.
    expand : str
        Message asking for ``$k`` descriptions of ``$room_type`` (semantic diversity).
    conventions : str
        Text inserted for ``$conventions``.
    """

    system: str = _SYSTEM
    room: str = _ROOM
    objects: str = _OBJECTS
    graph: str = _GRAPH
    decor: str = _DECOR
    check: str = _CHECK
    correct: str = _CORRECT
    repair: str = _REPAIR
    expand: str = _EXPAND
    conventions: str = _CONVENTIONS


#: The templates used unless a planner is given others.
DEFAULT_TEMPLATES = PromptTemplates()


def render(templates: PromptTemplates, which: str, **values: object) -> str:
    """Fill template ``which`` of ``templates`` with ``values``.

    Raises
    ------
    ValueError
        If the template uses a placeholder that has no value, or is not a field.
    """
    names = [f.name for f in fields(templates)]
    if which not in names:
        raise ValueError(f"no prompt template {which!r}; templates are {names}")
    values.setdefault("conventions", templates.conventions)
    try:
        return string.Template(getattr(templates, which)).substitute(
            {k: str(v) for k, v in values.items()})
    except KeyError as e:
        raise ValueError(f"prompt template {which!r} uses ${e.args[0]}, which is not available "
                         f"here; available: {', '.join('$' + k for k in sorted(values))}"
                         ) from None
    except ValueError as e:
        raise ValueError(f"prompt template {which!r}: {e}; write a literal $ as $$") from None


def vocabulary(pattern: str = "*") -> list[RuleInfo]:
    """The registered rules the planner may offer (kinds unary, binary, surface).

    Rules whose plugin cannot be loaded are left out (and logged), so one
    broken plugin does not stop planning.
    """
    import logging

    out = []
    for name in available_rules(pattern):
        try:
            info = describe_rules(name)
        except Exception as e:  # a broken plugin: leave it out of the vocabulary
            logging.getLogger("forcelayout.llm").warning(
                "rule %r is left out of the LLM vocabulary: it failed to load (%s)", name, e)
            continue
        out.extend(i for i in info if i.name == name and i.kind in PLANNING_KINDS)
    return out


#: One example binding per built-in rule, shown in the short vocabulary.
RULE_EXAMPLES = {
    "at_wall": ("wardrobe",), "in_corner": ("bookshelf",), "in_middle": ("coffee_table",),
    "near_door": ("coat_rack",), "away_from_door": ("bed",), "near_window": ("desk",),
    "away_from_window": ("tv_stand",),
    "next_to": ("nightstand_1", "bed"), "near": ("armchair", "bookshelf"),
    "far_from": ("bed", "desk"), "facing": ("sofa", "tv_stand"),
    "in_front_of": ("coffee_table", "sofa"), "behind": ("console_table", "sofa"),
    "left_of": ("nightstand_1", "bed"), "right_of": ("nightstand_2", "bed"),
    "around": ("chair_1", "dining_table"), "aligned_with": ("rug", "sofa"),
    "face_same_as": ("bookshelf_2", "bookshelf_1"), "under": ("rug", "coffee_table"),
    "near_plant": ("armchair", "plant"), "on_top": ("lamp", "nightstand_1"),
    "on_wall": ("mirror",), "on_wall_mid": ("painting",), "above": ("painting", "bed"),
    "on_ceiling": ("ceiling_light",),
}


def _example(info: RuleInfo) -> str:
    ex = RULE_EXAMPLES.get(info.name)
    if ex is None:
        ex = ("object_1",) if info.kind == "unary" else ("object_1", "object_2")
    text = f'{{"rule": "{info.name}", "object": "{ex[0]}"'
    if len(ex) > 1:
        text += f', "target": "{ex[1]}"'
    return text + "}"


def vocabulary_text(infos: list[RuleInfo], *, detail: bool = False) -> str:
    """The vocabulary as prompt text, one line per rule, grouped by kind.

    Parameters
    ----------
    infos : list of RuleInfo
        The rules (see :func:`vocabulary`).
    detail : bool, default False
        False: each rule's summary, its parameters with their defaults and
        one example binding — short enough for small models and 8k contexts.
        True: the whole docstring and each parameter's description.
    """
    if not detail:
        lines = []
        for kind in PLANNING_KINDS:
            group = [i for i in infos if i.kind == kind]
            if not group:
                continue
            head = {"unary": "unary rules (no target):",
                    "binary": "binary rules (target: another object's id):",
                    "surface": "surface rules (place the object off the floor):"}[kind]
            lines.append(head)
            for i in group:
                params = ", ".join(f"{k}={v.get('default')!r}" for k, v in i.params.items())
                lines.append(f"- {i.name}: {one_line(i.summary, 160)}"
                             + (f" Params: {params}." if params else "")
                             + f" Example: {_example(i)}")
        return "\n".join(lines)
    lines = []
    for kind in PLANNING_KINDS:
        group = [i for i in infos if i.kind == kind]
        if not group:
            continue
        lines.append(f"{kind} rules:")
        for i in group:
            doc = i.doc
            if doc.startswith(i.summary):
                doc = doc[len(i.summary):]
            text = one_line(f"{i.summary} {doc}", 400)
            params = ", ".join(
                f"{k}={v.get('default')!r}" + (f" ({v['description']})" if v.get("description")
                                               else "")
                for k, v in i.params.items())
            lines.append(f"- {i.name}: {text}" + (f" Params: {params}." if params else ""))
    return "\n".join(lines)
