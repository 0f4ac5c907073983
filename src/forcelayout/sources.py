"""Where plans come from: a plan file, JSON text, a dict, or a bundled example's name.

Examples
--------
>>> from forcelayout.sources import load_plan
>>> load_plan("bedroom").name
'bedroom'
"""

from __future__ import annotations

import difflib
from pathlib import Path
from typing import Any

from forcelayout import examples
from forcelayout.plan import Plan

__all__ = ["load_plan"]


def load_plan(source: str | Path | dict[str, Any] | Plan) -> Plan:
    """Load a plan from a path, JSON text, a dict, or return a Plan unchanged.

    Parameters
    ----------
    source : Plan, path, JSON text, dict or str
        A bare name such as ``"bedroom"`` loads a bundled example plan
        (see :func:`forcelayout.examples.list_plans`).

    Returns
    -------
    Plan

    Raises
    ------
    PlanError
        If the plan is invalid (every problem with its JSON path).
    FileNotFoundError
        If ``source`` is neither a file, JSON text nor a bundled plan's name.
    """
    if isinstance(source, Plan):
        return source
    if isinstance(source, dict):
        return Plan.from_dict(source)
    text = str(source)
    if isinstance(source, str) and text.lstrip().startswith("{"):
        return Plan.from_json(text)
    path = Path(text)
    if path.exists():
        return Plan.load(path)
    if text in examples.list_plans():
        return examples.load_example(text)
    close = difflib.get_close_matches(text, examples.list_plans(), n=1, cutoff=0.75)
    meant = f" (did you mean {close[0]!r}?)" if close else ""
    raise FileNotFoundError(
        f"no plan file {text!r}{meant}; give a path to a plan JSON or one of the bundled "
        f"plans {examples.list_plans()}"
    )
