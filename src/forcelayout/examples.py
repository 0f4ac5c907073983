"""Bundled example plans, so the library works offline on a fresh machine.

Examples
--------
>>> from forcelayout import examples
>>> examples.list_plans()
['bedroom', 'home_office', 'l_shaped_studio', 'living_room']
>>> examples.load_example("bedroom").name
'bedroom'
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from forcelayout.plan import Plan

__all__ = ["list_plans", "load_example", "example_path"]

_PACKAGE = "forcelayout.data.plans"


def list_plans() -> list[str]:
    """Names of the bundled plans, sorted."""
    root = resources.files(_PACKAGE)
    return sorted(p.name.removesuffix(".json") for p in root.iterdir()
                  if p.name.endswith(".json"))


def example_path(name: str) -> Path:
    """Path of a bundled plan's JSON file."""
    if name not in list_plans():
        raise FileNotFoundError(f"no bundled plan {name!r}; choose one of {list_plans()}")
    return Path(str(resources.files(_PACKAGE).joinpath(f"{name}.json")))


def load_example(name: str) -> Plan:
    """Load and validate a bundled plan by name (see :func:`list_plans`)."""
    return Plan.load(example_path(name))
