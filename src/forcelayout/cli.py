"""The ``forcelayout`` command line.

Sub-commands: ``generate``, ``dataset``, ``rules``, ``validate``, ``render``;
optional subpackages add their own (``plan`` from ``forcelayout.llm``,
``export`` from :mod:`forcelayout.export_cmd`, ``ground`` from
:mod:`forcelayout.ground_cmd`) through a
``register(subparsers)`` function in their command module. A missing extra
turns into a command that says which extra to install.
"""

from __future__ import annotations

import argparse
import importlib
import json
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import NoReturn

__all__ = ["main", "build_parser"]

#: Optional subpackages that add sub-commands: (module, extra, commands it adds).
OPTIONAL_COMMANDS = [("forcelayout.llm.cli", "llm", ["plan"]),
                     ("forcelayout.export_cmd", "export", ["export"]),
                     ("forcelayout.ground_cmd", "grounding", ["ground"])]

#: Help of the ``--access`` option of ``generate`` and ``dataset``.
ACCESS_HELP = ("require every object's access zone to be free (the front of a wardrobe, "
               "counter or fridge, a long side of a bed: see docs/concepts.md) and draw the "
               "zones in the pictures; the layouts otherwise only lean that way")


def _cmd_generate(args: argparse.Namespace) -> int:
    from forcelayout.generate_cmd import run_generate

    return run_generate(args)


def _cmd_dataset(args: argparse.Namespace) -> int:
    from forcelayout.dataset_cmd import run_dataset

    return run_dataset(args)


def _cmd_rules(args: argparse.Namespace) -> int:
    from forcelayout.rules import describe_rules

    infos = describe_rules(args.pattern)
    if not infos:
        print(f"forcelayout: no rule matches {args.pattern!r}; run `forcelayout rules` for the "
              "whole vocabulary (patterns are shell-style, e.g. 'near*')", file=sys.stderr)
        return 1
    if args.json:
        print(json.dumps([{"name": i.name, "kind": i.kind, "target": i.target,
                           "surface": i.surface, "bond": i.bond, "hard": i.hard,
                           "start": None if i.start is None else {
                               "place": i.start.place, "turn": i.start.turn,
                               "parent": i.start.parent},
                           "positional": i.positional, "closeness": i.closeness,
                           "opposite": i.opposite, "aliases": list(i.aliases),
                           "feature": i.feature, "specialises": list(i.specialises),
                           "fallback": i.fallback, "package": i.package,
                           "summary": i.summary, "weight": i.weight, "params": i.params}
                          for i in infos],
                         indent=2, default=str))
        return 0
    width = max((len(i.name) for i in infos), default=4)
    for i in infos:
        params = ", ".join(f"{k}={v['default']}" for k, v in i.params.items())
        plugin = "" if i.package == "forcelayout" else f"  (plugin: {i.package})"
        print(f"{i.name:<{width}}  {i.kind:<7}  {i.summary}" + (f"  [{params}]" if params else "")
              + plugin)
    return 0


def _cmd_validate(args: argparse.Namespace) -> int:
    from forcelayout.layout import Layout
    from forcelayout.sources import load_plan
    from forcelayout.validate import check_layout

    plan = load_plan(args.plan)
    if not args.layouts:
        from forcelayout.diagnose import feasibility
        from forcelayout.pipeline import prepare

        prepare(plan)  # what generate refuses before sampling (a wall object with no room)

        feas = feasibility(plan)
        print(f"plan {plan.name!r} is valid: {_count_of(len(plan.objects), 'object')}, "
              f"{_count_of(len(plan.rules), 'rule')}"
              + ("; but no layout can meet it" if not feas.ok
                 else "; tight (see the warnings below)"
                 if feas.verdict == "tight" else ""), flush=True)  # before the warnings
        for k, note in enumerate(feas.notes):
            print(f"{'infeasible' if k < feas.blocking else 'warning'}: {note}",
                  file=sys.stderr)
        return 0 if feas.ok else 1
    bad = passed = skipped = 0
    for path in args.layouts:
        other = _not_a_layout(path)
        if other is not None:  # DIR/*.json also matches the run's plan.json, summary.json
            print(f"{path}: skipped ({other}, not a layout)", file=sys.stderr)
            skipped += 1
            continue
        try:
            lay = Layout.load(path, plan)
        except OSError as e:
            print(f"{path}: cannot be read: {e.strerror or e}", file=sys.stderr)
            bad += 1
            continue
        except (ValueError, KeyError, TypeError) as e:
            print(f"{path}: not a layout of plan {plan.name!r}: {e}", file=sys.stderr)
            bad += 1
            continue
        rep = check_layout(lay, access_clearance=args.access)
        sat = lay.rule_satisfaction
        status = "ok" if rep.ok else "FAIL"
        print(f"{path}: {status}  rules met {sat:.0%}")
        for f in rep.failures:
            print(f"    {f}")
        bad += not rep.ok
        passed += rep.ok
    checked = passed + bad
    print(f"{passed} of {checked} layout file{'s' * (checked != 1)} pass the checks"
          + (" (with access)" if args.access else "")
          + (f"; {skipped} skipped" if skipped else ""))
    return 1 if bad else 0


def _not_a_layout(path: Path) -> str | None:
    """What a JSON file is when it is a plan or a run's summary (None otherwise, or when it
    cannot be read: the layout reader says why)."""
    import json

    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if not isinstance(data, dict) or "objects" in data and "report" in data:
        return None
    if {"room", "objects"} <= data.keys():
        return "a plan"
    if {"accepted", "attempted"} <= data.keys():
        return "a run's summary"
    return None


def _cmd_render(args: argparse.Namespace) -> int:
    from forcelayout.layout import Layout
    from forcelayout.sources import load_plan

    plan = load_plan(args.plan)
    if args.out is not None:
        _output_folder(args.out, make=True, what="pictures")
    for path in args.layouts:
        try:
            lay = Layout.load(path, plan)
        except (ValueError, KeyError, TypeError) as e:
            print(f"error: {path}: not a layout of plan {plan.name!r}: {e}", file=sys.stderr)
            return 2
        out = Path(path).with_suffix(f".{args.format}")
        if args.out is not None:
            out = args.out / out.name
        lay.picture(out, show_access=args.access)
        print(out)
    return 0


def _count(least: int):
    """An argparse type: a whole number of at least ``least``, refused with the reason."""
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
        if value < least:
            raise argparse.ArgumentTypeError(f"{value} is less than {least}")
        return value
    parse.__name__ = f"whole number >= {least}"
    return parse


def _share(text: str) -> float:
    """An argparse type: a share between 0 and 1, refused with the reason."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not 0.0 <= value <= 1.0:
        raise argparse.ArgumentTypeError(f"{value:g} is not between 0 and 1 (a share of the "
                                         "plan's rules: 1 asks for every one)")
    return value


_share.__name__ = "share between 0 and 1"

#: Help of the ``--min-rules`` option of ``generate`` and ``dataset``.
MIN_RULES_HELP = ("share of the plan's rules every accepted layout meets (default 0.95: with "
                  "20 or more rules one may go unmet; 1 asks for every rule, at some cost in "
                  "yield and time on crowded plans)")


def _min_rules(args: argparse.Namespace) -> float:
    """``--min-rules`` of ``generate`` or ``dataset`` (the default acceptance where a caller's
    namespace has none)."""
    from forcelayout.options import Options

    return float(getattr(args, "min_rules", Options().min_rule_satisfaction))


def _repaired_line(counts: dict[str, int], key: str, total: int, noun: str) -> str | None:
    """The ``repaired:`` line of ``generate`` and ``dataset`` from repair counts
    (:func:`forcelayout.sampling.repair_counts`, ``counts[key]`` of ``total`` ``noun``), or
    None where nothing was repaired."""
    if not counts.get(key):
        return None
    kinds = ", ".join(f"{k} x{v}" for k, v in counts.items() if k != key and v)
    return f"repaired: {counts[key]} of {total} {noun} ({kinds})"


class _Parser(argparse.ArgumentParser):
    """An argument parser that says what is wrong with the command line in one line (and
    where the usage is), not the whole usage text first."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {message} (see: {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``forcelayout`` command."""
    from forcelayout import __version__

    p = _Parser(prog="forcelayout", description=(
        "One declarative scene plan -> many physically valid room layouts."))
    p.add_argument("--version", action="version", version=f"forcelayout {__version__}")
    p.add_argument("--debug", action="store_true",
                   help="show the full traceback of an error instead of one line")
    sub = p.add_subparsers(dest="command", required=True)

    g = sub.add_parser("generate", help="generate layouts of a plan (JSON + PNG per layout)")
    g.add_argument("plan", nargs="?", help="plan JSON file or a bundled plan name "
                   "(bedroom, living_room, home_office, l_shaped_studio)")
    g.add_argument("-n", type=_count(1), default=10, help="layouts wanted (default 10)")
    g.add_argument("-o", "--out", type=Path, required=True, help="output folder")
    g.add_argument("--seed", type=_count(0), default=0, help="seed of the run (default 0)")
    g.add_argument("--workers", type=_count(1), default=1, help="processes (default 1)")
    g.add_argument("--max-attempts", type=_count(0), default=None, help="sample budget")
    g.add_argument("--format", "--pictures", dest="format", choices=["png", "svg", "none"],
                   default="png", help="picture per layout (default png; --pictures as for "
                   "dataset)")
    g.add_argument("--no-relations", action="store_true", help="ablation: no relation forces")
    g.add_argument("--no-decor", action="store_true", help="ablation: drop decor objects")
    g.add_argument("--access", action="store_true", help=ACCESS_HELP)
    g.add_argument("--min-rules", type=_share, default=0.95, metavar="SHARE",
                   help=MIN_RULES_HELP)
    g.add_argument("--overwrite", action="store_true",
                   help="replace the layouts of another plan that an earlier run wrote to --out "
                        "(an earlier run of the same plan is always replaced)")
    g.add_argument("--quiet", action="store_true", help="no progress bar")
    g.add_argument("--assets", type=Path, default=None, metavar="DIR",
                   help="ground the plan to this asset library first: each object gets a mesh, "
                        "its size the scaled mesh's (needs forcelayout[grounding]; see "
                        "`forcelayout ground --help`)")
    g.add_argument("--prompt", default=None,
                   help="plan the scene from this description with an LLM first "
                        "(needs forcelayout[llm]; see `forcelayout plan --help`)")
    try:
        from forcelayout.llm.cli import add_client_options
    except ImportError:
        pass
    else:
        add_client_options(g)
    g.set_defaults(func=_cmd_generate)

    from forcelayout.dataset_cmd import add_dataset_parser

    add_dataset_parser(sub, _count, _share).set_defaults(func=_cmd_dataset)

    r = sub.add_parser("rules", help="list the rule vocabulary")
    r.add_argument("pattern", nargs="?", default="*", help="shell pattern, e.g. 'near*'")
    r.add_argument("--json", action="store_true", help="print JSON")
    r.set_defaults(func=_cmd_rules)

    v = sub.add_parser("validate", help="validate a plan, and layouts of it if given")
    v.add_argument("plan")
    v.add_argument("layouts", nargs="*", type=Path)
    v.add_argument("--access", action="store_true",
                   help="also check that every object's access zone is free (as "
                        "generate --access requires)")
    v.set_defaults(func=_cmd_validate)

    d = sub.add_parser("render", help="draw layout JSON files top-down")
    d.add_argument("plan")
    d.add_argument("layouts", nargs="+", type=Path)
    d.add_argument("--format", choices=["png", "svg"], default="png")
    d.add_argument("--access", action="store_true",
                   help="draw the access zones, and mark objects with none free (the access "
                        "check)")
    d.add_argument("--out", type=Path, default=None,
                   help="folder for the pictures (default: beside each layout, replacing the "
                        "picture generate drew there)")
    d.set_defaults(func=_cmd_render)

    for module, extra, commands in OPTIONAL_COMMANDS:
        try:
            mod = importlib.import_module(module)
        except ImportError:
            for name in commands:
                m = sub.add_parser(name, help=f"(needs: pip install \"forcelayout[{extra}]\")")
                m.add_argument("rest", nargs=argparse.REMAINDER)
                m.set_defaults(func=lambda a, e=extra: _missing(e))
            continue
        mod.register(sub)
    return p


def _missing(extra: str) -> int:
    print(f"error: this command needs the optional extra: pip install \"forcelayout[{extra}]\"",
          file=sys.stderr)
    return 2


def _output_folder(out: Path, *, make: bool, what: str = "layouts") -> None:
    """Refuse an ``--out`` that is a file or cannot be made (one ``error:`` line, before
    the plan's warnings); with ``make``, make it."""
    from forcelayout.errors import InputError

    if out.exists() and not out.is_dir():
        raise InputError(f"--out {str(out)!r} is a file, not a folder: give a folder for the "
                         f"{what}")
    if not make:
        return
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise InputError(f"--out {str(out)!r}: cannot make the folder ({e.strerror}); give "
                         "a folder you can write to") from e


def _count_of(n: int, noun: str) -> str:
    """``"1 rule"``, ``"3 rules"``."""
    return f"{n} {noun}{'' if n == 1 else 's'}"


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    from forcelayout.errors import InputError, MissingExtraError, UnknownRuleError

    args = build_parser().parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except (InputError, UnknownRuleError, MissingExtraError, FileNotFoundError) as e:
        if args.debug:
            raise
        print(f"error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        if args.debug:
            raise
        print("interrupted", file=sys.stderr)
        return 130
    except Exception as e:  # never a traceback unless asked for
        if args.debug:
            raise
        print(f"error: {type(e).__name__}: {e} (run with --debug for the traceback)",
              file=sys.stderr)
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
