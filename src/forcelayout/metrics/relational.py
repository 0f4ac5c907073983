"""Relational dissimilarity: Jaccard distance of the relation triples two layouts hold.

A relation triple ``(category, rule, category)`` says that a rule holds
between two objects of a layout (or between an object and ``"room"``). The
vocabulary is the rule registry: every registered rule whose class declares
``relation = True`` (:class:`forcelayout.rules.Rule`) is judged by its own
``satisfied()`` check with its default parameters, on the geometry of the
layout and never on the plan, so two layouts of one plan can differ. A
plugin rule that declares ``relation = True`` joins the vocabulary.
"""

from __future__ import annotations

import warnings

import numpy as np
from pydantic import ValidationError

from forcelayout import rules as registry
from forcelayout.layout import Layout
from forcelayout.metrics.jaccard import jaccard_distance
from forcelayout.metrics.labels import Canonical, canonical_label
from forcelayout.rules.base import ParamArrays, Rule, State

__all__ = [
    "relation_rules",
    "relation_triples",
    "relational_dissimilarity",
]

Triple = tuple[str, str, str]

#: The second category of a relation between an object and the room (a rule without target).
ROOM = "room"


def _relation_classes(pattern: str = "*") -> list[type[Rule]]:
    """Registered rule classes that declare ``relation = True``, sorted by name.

    A rule whose module cannot be imported is left out with a warning (the
    metric must not fail because an unrelated plugin is broken).
    """
    out = []
    for name in registry.available_rules(pattern):
        try:
            cls = type(registry.get_rule(name))
        except Exception as e:  # a broken plugin: say so, measure without it
            warnings.warn(f"relation_triples: rule {name!r} could not be loaded and is left out "
                          f"({type(e).__name__}: {e})", RuntimeWarning, stacklevel=3)
            continue
        if getattr(cls, "relation", False):
            out.append(cls)
    return out


def relation_rules(pattern: str = "*") -> dict[str, str]:
    """The relation vocabulary: every registered rule with ``relation = True``.

    Parameters
    ----------
    pattern : str
        Shell-style filter on rule names (``"near*"``).

    Returns
    -------
    dict of str to str
        Rule name → the first line of its docstring (what makes it hold),
        sorted by name. Read from the registry at each call, so rules
        registered later (plugins) appear too.

    Examples
    --------
    >>> from forcelayout import metrics
    >>> rules = metrics.relation_rules()
    >>> all(isinstance(summary, str) for summary in rules.values())
    True
    """
    return {cls.name: cls.summary() for cls in _relation_classes(pattern)}


def _surface_kind(surface: str, ids: set[str]) -> str:
    """``"floor"``, ``"top"`` (on another object), ``"wall"`` or ``"ceiling"``."""
    if surface == "floor" or surface == "ceiling":
        return surface
    if surface.startswith("wall"):
        return "wall"
    return "top" if surface in ids else "other"


def _default_params(cls: type[Rule], b: int) -> ParamArrays | None:
    """Default parameters for ``b`` bindings, or None when a parameter has no default."""
    try:
        params = cls.Params()
    except ValidationError:
        return None
    return ParamArrays.from_models([params] * b, np.ones(b))


def _layout_state(layout: Layout) -> State:
    from forcelayout.report import layout_state

    return layout_state(layout)


def relation_triples(
    layout: Layout, *, canonical: Canonical = canonical_label
) -> frozenset[Triple]:
    """The set of ``(category, relation, category)`` triples that hold in a layout.

    Every registered rule with ``relation = True`` (see
    :func:`relation_rules`) is judged by its own ``satisfied()`` check with
    default parameters, over the placed objects its ``surface`` declares:

    * floor rules (``surface = "floor"``) over the objects standing on the
      floor: a rule with a required target over every ordered pair of two
      of them, ``(a, rule, b)``; a rule without one (or with an optional
      one) over each of them, ``(a, rule, "room")``;
    * off-floor rules over the objects on that kind of surface (``"top"``:
      on another object; ``"wall"``; ``"ceiling"``), with every other
      placed object as the candidate target when a target is required (so
      ``on_top`` holds for the object it rests on), else against
      ``"room"``.

    Categories pass through ``canonical``; as a set, two nightstands next to
    a bed give one triple for that relation. Rules whose
    parameters have no defaults cannot be judged and are left out.

    Parameters
    ----------
    layout : Layout
    canonical : callable
        Maps an object's category to the label in the triples.

    Returns
    -------
    frozenset of (str, str, str)
    """
    state = _layout_state(layout)
    ids = state.ids
    if not ids:
        return frozenset()
    cat = [canonical(layout.plan.object(i).category) for i in ids]
    surfaces = state.surfaces or ("floor",) * len(ids)
    idset = set(ids)
    kind = np.array([_surface_kind(s, idset) for s in surfaces])
    floor = np.flatnonzero(kind == "floor")
    out: set[Triple] = set()
    for cls in _relation_classes():
        rule = registry.get_rule(cls.name)
        subj = np.flatnonzero(kind == cls.surface)
        if subj.size == 0:
            continue
        if cls.target == "required":
            pool = floor if cls.surface == "floor" else np.arange(len(ids))
            i = np.repeat(subj, pool.size)
            j = np.tile(pool, subj.size)
            keep = i != j
            i, j = i[keep], j[keep]
        else:
            i, j = subj, None
        if i.size == 0:
            continue
        p = _default_params(cls, int(i.size))
        if p is None:
            continue
        ok = np.asarray(rule.satisfied(state, i, j, p), dtype=bool)
        for a, b in zip(i[ok].tolist(), (j[ok].tolist() if j is not None
                                         else [None] * int(ok.sum())), strict=True):
            out.add((cat[a], cls.name, ROOM if b is None else cat[b]))
    return frozenset(out)


def relational_dissimilarity(
    a: Layout, b: Layout, *, canonical: Canonical = canonical_label
) -> float:
    """Jaccard distance between the relation triples of two layouts, in ``[0, 1]``.

    See :func:`relation_triples` for how the triples are read off the geometry.
    """
    return jaccard_distance(relation_triples(a, canonical=canonical),
                            relation_triples(b, canonical=canonical))

