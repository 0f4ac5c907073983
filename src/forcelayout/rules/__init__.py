"""The rule registry: rules are plugins registered by name.

Three ways in:

* ``@register("near_plant")`` on a :class:`Rule` subclass in the same process;
* ``register("near_plant", "mypkg.rules:NearPlant")`` — a lazy entry,
  imported only when a plan names the rule;
* an entry point in the group ``forcelayout.rules`` of an installed package::

      [project.entry-points."forcelayout.rules"]
      near_plant = "mypkg.rules:NearPlant"

Entry points are read on demand (the first lookup of a name not registered in
process, or a listing), never at ``import forcelayout``.

Examples
--------
>>> from forcelayout import rules
>>> "at_wall" in rules.available_rules()
True
>>> rules.get_rule("next_to").kind
'binary'
"""

from __future__ import annotations

import difflib
import fnmatch
import functools
import importlib
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from importlib.metadata import entry_points, packages_distributions
from typing import Any, TypeVar

from forcelayout.errors import UnknownRuleError
from forcelayout.rules.base import (
    Access,
    Closeness,
    ParamArrays,
    Rule,
    RuleKind,
    StartHint,
    State,
    Surface,
    TargetNeed,
)

__all__ = [
    "Rule",
    "State",
    "ParamArrays",
    "RuleKind",
    "TargetNeed",
    "Surface",
    "StartHint",
    "Access",
    "Closeness",
    "RuleInfo",
    "register",
    "unregister",
    "get_rule",
    "available_rules",
    "builtin_rules",
    "describe_rules",
    "ENTRY_POINT_GROUP",
]

ENTRY_POINT_GROUP = "forcelayout.rules"

R = TypeVar("R", bound=type[Rule])

# name -> Rule subclass, or "module:Class" string not imported yet
_registry: dict[str, type[Rule] | str] = {}
_instances: dict[str, Rule] = {}
_entry_points_loaded = False

_BUILTIN = {
    "forcelayout.rules.unary": [
        ("at_wall", "AtWall"),
        ("in_corner", "InCorner"),
        ("in_middle", "InMiddle"),
        ("near_window", "NearWindow"),
        ("near_door", "NearDoor"),
        ("away_from_door", "AwayFromDoor"),
        ("away_from_window", "AwayFromWindow"),
    ],
    "forcelayout.rules.binary": [
        ("next_to", "NextTo"),
        ("near", "Near"),
        ("far_from", "FarFrom"),
        ("facing", "Facing"),
        ("face_same_as", "FaceSameAs"),
        ("in_front_of", "InFrontOf"),
        ("behind", "Behind"),
        ("left_of", "LeftOf"),
        ("right_of", "RightOf"),
        ("aligned_with", "AlignedWith"),
        ("around", "Around"),
        ("under", "Under"),
    ],
    "forcelayout.rules.surface": [
        ("on_top", "OnTop"),
        ("on_wall", "OnWall"),
        ("on_wall_mid", "OnWallMid"),
        ("above", "Above"),
        ("on_ceiling", "OnCeiling"),
    ],
}
for _mod, _names in _BUILTIN.items():
    for _name, _cls in _names:
        _registry[_name] = f"{_mod}:{_cls}"


@dataclass(frozen=True)
class RuleInfo:
    """What the registry says about one rule (for listings and docs).

    ``target``, ``surface``, ``bond``, ``hard``, ``start``, ``positional``,
    ``closeness``, ``opposite``, ``aliases``, ``feature``, ``specialises`` and
    ``fallback`` repeat the rule class's declarations (see :class:`Rule`).
    """

    name: str
    kind: RuleKind
    summary: str
    doc: str
    params: dict[str, dict[str, Any]]
    weight: float
    target: TargetNeed = "none"
    surface: Surface = "floor"
    bond: bool = False
    hard: bool = False
    start: StartHint | None = None
    positional: bool = False
    closeness: Closeness | None = None
    opposite: str | None = None
    aliases: tuple[str, ...] = ()
    feature: str | None = None
    specialises: tuple[str, ...] = ()
    fallback: str | None = None
    #: The installed distribution that provides the rule: ``"forcelayout"`` for the
    #: built-in vocabulary, a plugin's package otherwise.
    package: str = "forcelayout"


def register(
    name: str, target: type[Rule] | str | None = None, *, replace: bool = False
) -> Callable[[R], R] | None:
    """Register a rule class under ``name``.

    Parameters
    ----------
    name : str
        The name plans use in ``"rule": name``.
    target : Rule subclass or str, optional
        The class, or a lazy ``"module:Class"`` string. When omitted,
        ``register`` returns a class decorator.
    replace : bool, default False
        Allow replacing an existing rule of the same name. Without it a
        duplicate name raises ``ValueError``, so clashing plugins are seen.

    Examples
    --------
    >>> import numpy as np
    >>> from forcelayout.rules import Rule, register, unregister
    >>> @register("stay_put")
    ... class StayPut(Rule):
    ...     '''Apply no force; always satisfied.'''
    ...     def force(self, state, i, j, p):
    ...         return np.zeros((len(i), 2)), np.zeros(len(i))
    ...     def satisfied(self, state, i, j, p):
    ...         return np.ones(len(i), dtype=bool)
    >>> unregister("stay_put")
    """
    if not name or not name.isidentifier():
        raise ValueError(f"rule name {name!r} must be a Python identifier such as 'near_plant'")

    def _do(cls: type[Rule] | str) -> None:
        if name in _registry and not replace and _registry[name] is not cls:
            raise ValueError(
                f"a rule named {name!r} is already registered ({_describe(_registry[name])}); "
                "pass replace=True to override it"
            )
        if not isinstance(cls, str):
            if not (isinstance(cls, type) and issubclass(cls, Rule)):
                raise TypeError(f"register({name!r}) needs a Rule subclass, got {cls!r}")
            cls.name = name
        _registry[name] = cls
        _instances.pop(name, None)

    if target is not None:
        _do(target)
        return None

    def decorator(cls: R) -> R:
        _do(cls)
        return cls

    return decorator


def unregister(name: str) -> None:
    """Remove a rule from the registry (no error if it is absent)."""
    _registry.pop(name, None)
    _instances.pop(name, None)


def _describe(entry: type[Rule] | str) -> str:
    return entry if isinstance(entry, str) else f"{entry.__module__}:{entry.__qualname__}"


def _package_of(entry: str) -> str:
    """The installed distribution that provides the module of ``"module:Class"``."""
    top = entry.split(":", 1)[0].split(".", 1)[0]
    return (_distributions().get(top) or [top])[0]


@functools.cache
def _distributions() -> Mapping[str, list[str]]:
    """Top-level modules -> the installed distributions providing them (read once: the
    scan of every installed package's metadata takes tens of milliseconds)."""
    try:
        return packages_distributions()
    except Exception:  # broken metadata must not stop a lookup
        return {}


def _load_entry_points() -> None:
    global _entry_points_loaded
    if _entry_points_loaded:
        return
    _entry_points_loaded = True
    for ep in entry_points(group=ENTRY_POINT_GROUP):
        if ep.name in _registry:
            if _describe(_registry[ep.name]) != ep.value:
                ours = _describe(_registry[ep.name])
                theirs = ep.dist.name if ep.dist is not None else ep.value
                warnings.warn(
                    f"the entry point {ep.name!r} of package {theirs!r} ({ep.value}) shadows "
                    f"the rule already registered as {ep.name!r} ({ours}, package "
                    f"{_package_of(ours)!r}); the registered rule is kept. Rename the entry "
                    "point, or call forcelayout.rules.register(name, target, replace=True) "
                    "to choose the plugin.", RuntimeWarning, stacklevel=3)
            continue
        _registry[ep.name] = ep.value


def _resolve(name: str) -> type[Rule]:
    entry = _registry[name]
    if isinstance(entry, str):
        module, _, qual = entry.partition(":")
        obj: Any = importlib.import_module(module)
        for part in qual.split("."):
            obj = getattr(obj, part)
        if not (isinstance(obj, type) and issubclass(obj, Rule)):
            raise TypeError(f"rule {name!r} points at {entry!r}, which is not a Rule subclass")
        obj.name = name
        _registry[name] = obj
        return obj
    return entry


def get_rule(name: str) -> Rule:
    """Return the (shared) instance of the rule registered as ``name``.

    Raises
    ------
    UnknownRuleError
        If no rule has that name; the message lists close matches.
    """
    inst = _instances.get(name)
    if inst is not None:
        return inst
    if name not in _registry:
        _load_entry_points()
    if name not in _registry:
        close = difflib.get_close_matches(name, list(_registry), n=3, cutoff=0.6)
        hint = f" Did you mean {' or '.join(repr(c) for c in close)}?" if close else ""
        raise UnknownRuleError(
            f"unknown rule {name!r}.{hint} Run `forcelayout rules` for the vocabulary, or "
            f"register a plugin with @forcelayout.rules.register({name!r})."
        )
    inst = _resolve(name)()
    _instances[name] = inst
    return inst


def suggest(name: str) -> list[str]:
    """Registered names close to ``name`` (for error messages)."""
    _load_entry_points()
    return difflib.get_close_matches(name, list(_registry), n=3, cutoff=0.6)


def is_registered(name: str) -> bool:
    """Whether ``name`` is a registered rule (reads entry points if needed)."""
    if name not in _registry:
        _load_entry_points()
    return name in _registry


def available_rules(pattern: str = "*") -> list[str]:
    """Sorted names of registered rules matching a shell-style ``pattern``.

    Lists without importing any plugin module.
    """
    _load_entry_points()
    return sorted(n for n in _registry if fnmatch.fnmatchcase(n, pattern))


def builtin_rules(*, target: TargetNeed | None = None, surface: Surface | None = None
                  ) -> list[str]:
    """Sorted names of the rules that ship with forcelayout, optionally filtered.

    Parameters
    ----------
    target : {"none", "required", "optional"}, optional
        Keep only rules whose class declares this ``target``.
    surface : {"floor", "top", "wall", "ceiling"}, optional
        Keep only rules whose class declares this ``surface``.
    """
    names = sorted(n for names in _BUILTIN.values() for n, _ in names)
    out = []
    for n in names:
        cls = _resolve(n) if n in _registry else None
        if cls is None:
            continue
        if (target is None or cls.target == target) and (surface is None or cls.surface == surface):
            out.append(n)
    return out


def describe_rules(pattern: str = "*") -> list[RuleInfo]:
    """Every matching rule with its kind, one-line summary, docs and params."""
    out = []
    for n in available_rules(pattern):
        cls = _resolve(n)
        out.append(
            RuleInfo(n, cls.kind, cls.summary(), (cls.__doc__ or "").strip(),
                     cls.param_info(), float(cls.weight), cls.target, cls.surface,
                     bool(cls.bond), bool(cls.hard), cls.start, bool(cls.positional),
                     cls.closeness, cls.opposite, tuple(cls.aliases), cls.feature,
                     tuple(cls.specialises), cls.fallback,
                     _package_of(_describe(_registry[n])))
        )
    return out
