"""``forcelayout export``: layout files written as simulator scenes (needs ``forcelayout[export]``).

::

    forcelayout export out/bedroom/*.json --format usd,mjcf --out scenes/
    forcelayout export lay.json --format habitat --out scenes/ --plan my_plan.json
    forcelayout export lay.json --format usd --out scenes/ --movable chair,lamp

Each ``LAYOUT.json`` is written as ``DIR/<name>.glb``, ``.usda``, ``.xml``
(MJCF) and the folder ``DIR/<name>.habitat/``, see
:func:`forcelayout.export.write_exports`.

The plan of a layout comes from ``--plan`` if given; otherwise from the plan
embedded in the layout file (``Layout.save(..., include_plan=True)``);
otherwise from the ``plan.json`` beside it (as ``forcelayout generate``
writes) when that plan has the name the layout names. Every input is read
and checked before anything is written.

This module is imported by the command line to register the sub-command; it
checks that the extra is installed without importing it (so ``forcelayout``
starts as fast as before) and raises :class:`~forcelayout.errors.MissingExtraError`
otherwise.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
from pathlib import Path
from typing import Any

from forcelayout.errors import MissingExtraError, PlanError
from forcelayout.layout import Layout
from forcelayout.plan import Plan

__all__ = ["register", "run_export", "plan_of_layout"]

if importlib.util.find_spec("trimesh") is None:
    raise MissingExtraError("forcelayout export needs the optional package 'trimesh'. Install "
                            "it with: pip install \"forcelayout[export]\"", name="trimesh")

_ACCEPTED = "glb, usd, mjcf, habitat"  # kept equal to EXPORT_FORMATS by a test


class _InputError(Exception):
    """A layout file that cannot be exported; the message is one line."""


def plan_of_layout(path: Path, data: dict[str, Any], plan: Plan | None = None) -> Plan:
    """The plan a layout file is of: ``plan`` if given, else embedded, else ``plan.json`` beside.

    Raises
    ------
    ValueError
        When ``plan`` has another name than the one the layout names, or when
        none of the three gives the plan the layout names.
    """
    name = data.get("plan")
    if plan is not None:
        if isinstance(name, str) and name != plan.name:
            raise ValueError(f"it is a layout of plan {name!r}, not of the --plan given "
                             f"({plan.name!r})")
        return plan
    if isinstance(data.get("plan_spec"), dict):
        return Plan.from_dict(data["plan_spec"])
    beside = path.parent / "plan.json"
    if beside.is_file() and isinstance(name, str):
        try:
            candidate = Plan.load(beside)
        except (PlanError, ValueError, OSError) as e:
            raise ValueError(f"the plan.json beside it is not a valid plan "
                             f"({str(e).splitlines()[0]}); pass --plan PLAN") from None
        if candidate.name == name:
            return candidate
    raise ValueError(f"it names plan {name!r} but neither embeds it nor has that plan's "
                     f"plan.json beside it; pass --plan PLAN (a plan file or bundled name)")


def _load(path: Path, plan: Plan | None) -> Layout:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise _InputError(f"{path}: no such file") from None
    except (OSError, ValueError) as e:
        raise _InputError(f"{path}: not a layout JSON file ({e})") from None
    if not isinstance(data, dict) or not isinstance(data.get("objects"), dict):
        raise _InputError(f"{path}: not a layout: expected a JSON object with an 'objects' "
                          "mapping of poses (as written by Layout.save)")
    try:
        of = plan_of_layout(path, data, plan)
        return Layout.from_dict(data, of)
    except (ValueError, KeyError, TypeError) as e:
        raise _InputError(f"{path}: {' '.join(str(e).split())}") from None


def run_export(args: argparse.Namespace) -> int:
    """Run the ``export`` sub-command; returns the exit status."""
    from forcelayout.export import write_exports
    from forcelayout.export.formats import parse_formats
    from forcelayout.sources import load_plan

    try:
        formats = parse_formats(args.format)
    except ValueError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    if not formats:
        print(f"error: --format names no format; accepted: {_ACCEPTED}", file=sys.stderr)
        return 2
    if "usd" in formats:  # before anything is written
        from forcelayout._optional import import_optional

        import_optional("pxr.Usd", "export", package="usd-core")
    plan = load_plan(args.plan) if args.plan is not None else None
    layouts: list[tuple[Path, Layout]] = []
    stems: dict[str, Path] = {}
    try:
        for path in args.layouts:
            lay = _load(path, plan)
            if path.stem in stems:
                raise _InputError(f"{path}: {stems[path.stem]} would be written under the same "
                                  f"name {args.out / path.stem}; export them into separate "
                                  "folders")
            stems[path.stem] = path
            layouts.append((path, lay))
    except _InputError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    for path, lay in layouts:
        for written in write_exports(lay, args.out / path.stem, formats, movable=args.movable):
            print(written)
    return 0


def register(sub: Any) -> None:
    """Add the ``export`` sub-command to the ``forcelayout`` command's subparsers."""
    p = sub.add_parser("export", help="write layout JSON files as simulator scenes "
                                      "(GLB, USD, MJCF, Habitat)")
    p.add_argument("layouts", nargs="+", type=Path, metavar="LAYOUT.json")
    p.add_argument("--format", required=True,
                   help=f"comma-separated formats: {_ACCEPTED}")
    p.add_argument("-o", "--out", type=Path, required=True, help="output folder")
    p.add_argument("--plan", default=None,
                   help="plan file or bundled name (default: the plan embedded in each layout "
                        "file, or the plan.json beside it)")
    p.add_argument("--movable", default="",
                   help="comma-separated categories (or object ids) exported as movable "
                        "bodies, e.g. chair,lamp (default: everything static)")
    p.set_defaults(func=run_export)
