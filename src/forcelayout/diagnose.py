"""Say why, early: a plan's feasibility before sampling, a run's dominant failure after.

:func:`feasibility` looks at a plan alone (no simulation, a few milliseconds)
and estimates whether its floor objects can leave the free floor the checks
ask for, whether each fits the room, and whether the objects that must stand
against a wall find enough wall. :func:`dominant_cause` reads the failure
lines of a run's :class:`~forcelayout.layout.SampleReport` s and names, in
one line, the check that fails most often, the rules most often missed and
the objects that most often block a path.

Examples
--------
>>> import forcelayout as fl
>>> from forcelayout.diagnose import feasibility, dominant_cause
>>> feasibility("bedroom").verdict
'ok'
>>> reports = [fl.SampleReport(seed=0, valid=False, failures=[
...     "reachable: 'bed' cannot be reached from door 0 (blocked by 'wardrobe', 'desk')"]),
...     fl.SampleReport(seed=1)]
>>> dominant_cause(reports)
"50 % of samples fail 'reachable'; wardrobe and desk block the path to bed"
"""

from __future__ import annotations

import math
import re
import sys
import warnings
from collections import Counter
from collections.abc import Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any, Literal

import shapely
from shapely import affinity

from forcelayout.plan import MAX_FLOOR_FILL, Plan
from forcelayout.sanity import Finding, plan_findings
from forcelayout.sources import load_plan

__all__ = ["Feasibility", "feasibility", "dominant_cause", "missed_rules", "WALL_PLACES",
           "FeasibilityWarning", "FewLayoutsWarning", "EmptyGenerationError",
           "feasibility_warnings_as_lines"]

#: Start-hint places (:attr:`StartHint.place`) that put an object against a wall.
WALL_PLACES = frozenset({"wall", "corner"})

#: Thresholds of the verdict "tight": estimated free share within this margin of the
#: minimum, walls this full, the largest object spanning this share of the room.
_TIGHT_FREE_MARGIN = 0.05
_TIGHT_WALL = 0.8
_TIGHT_SPAN = 0.9

Verdict = Literal["ok", "tight", "infeasible"]


class FeasibilityWarning(UserWarning):
    """:func:`forcelayout.generate` found the plan infeasible before sampling; it samples anyway.

    The message lists the notes of the :class:`Feasibility` estimate, which
    is kept as the ``feasibility`` attribute (and as ``Generation.feasibility``).
    """

    def __init__(self, message: str, feasibility: Feasibility | None = None):
        super().__init__(message)
        self.feasibility = feasibility

    @classmethod
    def of(cls, plan: str, feasibility: Feasibility) -> FeasibilityWarning:
        """The warning for plan ``plan`` whose estimate is infeasible: its infeasible notes,
        and that it is sampled anyway."""
        return cls(f"plan {plan!r} looks infeasible before sampling: "
                   f"{'; '.join(feasibility.infeasible_notes)}; sampling anyway", feasibility)


class FewLayoutsWarning(UserWarning):
    """:func:`forcelayout.generate` accepted fewer layouts than asked for.

    The message names accepted / wanted / attempted, the dominant cause
    (:func:`dominant_cause`) and what to try; the same facts are the
    attributes ``accepted``, ``wanted``, ``attempted`` and ``why``.
    """

    def __init__(self, message: str, *, accepted: int = 0, wanted: int = 0, attempted: int = 0,
                 why: str | None = None):
        super().__init__(message)
        self.accepted, self.wanted, self.attempted, self.why = accepted, wanted, attempted, why


class EmptyGenerationError(IndexError):
    """Indexing a :class:`~forcelayout.Generation` that holds no layout.

    The message says why it is empty: the dominant cause of the rejections
    and how many samples were attempted.
    """


@dataclass
class Feasibility:
    """What a plan asks of its room, estimated before any simulation.

    Attributes
    ----------
    plan : str
        The plan's name.
    verdict : {"ok", "tight", "infeasible"}
        ``"infeasible"``: no layout can pass the checks (an object fits
        nowhere, the furniture leaves too little floor even packed into one
        block, or the wall-bound objects need more wall than there is).
        ``"tight"``: layouts exist only if the solver packs well (expect many
        rejected samples). ``"ok"``: otherwise.
    notes : list of str
        One human-readable sentence per finding, worst first.
    floor_area : float
        Floor area, m².
    footprint_area : float
        Footprints of the floor objects that are obstacles (walkable covers
        such as rugs left out), m².
    fill : float
        ``footprint_area / floor_area``.
    free_fraction : float
        Estimated share of the floor left free for the agent (the
        ``navigable`` check's measure: floor minus obstacles inflated by the
        agent radius) when the obstacles stand apart, wall-bound ones with
        their backs to a wall. Objects pushed together share their margins, so
        layouts often do better.
    free_fraction_best : float
        The most any layout could leave free: all obstacles packed into one
        compact block in a corner.
    min_free_fraction : float
        The share the ``navigable`` check asks for.
    room_span : tuple of float
        Short and long side of the floor's smallest enclosing rectangle, m.
    largest : str or None
        Id of the obstacle with the longest side.
    largest_size : tuple of float
        Its ``(width, depth)``, m.
    misfits : list of str
        Obstacles that fit nowhere on the floor at a cardinal heading.
    wall_bound : list of str
        Obstacles a rule puts against a wall or into a corner (rules whose
        start hint's place is in :data:`WALL_PLACES`).
    wall_demand : float
        Wall length those objects take: their width, or width plus depth in
        a corner, m.
    wall_available : float
        Wall length without the doors, m.
    tall_demand : float
        Wall length taken by wall-bound objects taller than the lowest sill, m.
    tall_available : float
        Wall length without the doors and the windows, m.
    agent_radius : float
        Agent radius the estimates use, m.
    blocking : int
        How many of the first ``notes`` say why no layout can meet the plan
        (:attr:`infeasible_notes`); the others are warnings.
    findings : list of Finding
        What :func:`forcelayout.sanity.plan_findings` finds: impossible rule
        sets (more ``in_corner`` objects than corners, contradictory
        relations) make the verdict ``"infeasible"``; implausible ones
        (duplicated rules, a 0.5 m wide bed, a window listed as an object, a
        70 m² bedroom) are listed in ``notes`` after the others and leave the
        verdict as it is.
    """

    plan: str
    verdict: Verdict
    notes: list[str] = field(default_factory=list)
    floor_area: float = 0.0
    footprint_area: float = 0.0
    fill: float = 0.0
    free_fraction: float = 1.0
    free_fraction_best: float = 1.0
    min_free_fraction: float = 0.3
    room_span: tuple[float, float] = (0.0, 0.0)
    largest: str | None = None
    largest_size: tuple[float, float] = (0.0, 0.0)
    misfits: list[str] = field(default_factory=list)
    wall_bound: list[str] = field(default_factory=list)
    wall_demand: float = 0.0
    wall_available: float = 0.0
    tall_demand: float = 0.0
    tall_available: float = 0.0
    agent_radius: float = 0.2
    findings: list[Finding] = field(default_factory=list)
    blocking: int = 0

    @property
    def ok(self) -> bool:
        """Whether the verdict is not ``"infeasible"``."""
        return self.verdict != "infeasible"

    @property
    def infeasible_notes(self) -> list[str]:
        """The notes that make the verdict ``"infeasible"`` (the first ``blocking``
        notes); the rest are warnings."""
        return self.notes[:self.blocking]

    def __str__(self) -> str:
        lines = [
            f"plan {self.plan!r}: {self.verdict}",
            f"  floor {self.floor_area:.2f} m²; obstacles cover {self.footprint_area:.2f} m² "
            f"({self.fill:.0%}); about {self.free_fraction:.0%} stays free for an agent of "
            f"radius {self.agent_radius:g} m (at best {self.free_fraction_best:.0%}; "
            f"need {self.min_free_fraction:.0%})",
            f"  room {self.room_span[1]:.2f} x {self.room_span[0]:.2f} m"  # long x short,
            # as the plan's errors and findings give it
            + (f"; largest object {self.largest!r} {self.largest_size[0]:.2f} x "
               f"{self.largest_size[1]:.2f} m" if self.largest else ""),
            f"  {len(self.wall_bound)} wall-bound objects take {self.wall_demand:.2f} m of "
            f"{self.wall_available:.2f} m of wall without doors (the tall ones "
            f"{self.tall_demand:.2f} m of {self.tall_available:.2f} m without doors and "
            "windows)",
        ]
        return "\n".join(lines + [f"  - {n}" for n in self.notes])


def _wall_places(plan: Plan) -> dict[str, str]:
    """Object id -> ``"wall"`` or ``"corner"`` for objects a wall rule binds (via the registry)."""
    from forcelayout import rules as registry

    out: dict[str, str] = {}
    for spec in plan.rules:
        start = type(registry.get_rule(spec.rule)).start
        place = getattr(start, "place", None)
        if place in WALL_PLACES and out.get(spec.object) != "corner":
            out[spec.object] = place
    return out


def _fits(floor: shapely.Polygon, a: float, b: float) -> bool:
    """Whether an axis-aligned ``a`` x ``b`` box fits inside the floor somewhere.

    The floor is stretched so the box becomes a square, then eroded by half
    its side (exact for rooms with axis-aligned walls, generous otherwise).
    """
    squashed = affinity.scale(floor, xfact=1.0, yfact=a / b, origin=(0.0, 0.0))
    core = squashed.buffer(-(0.5 * a - 1e-6), join_style="mitre")
    return not core.is_empty


def _span(floor: shapely.Polygon) -> tuple[float, float]:
    rect = floor.minimum_rotated_rectangle
    xs, ys = rect.exterior.xy
    sides = sorted({math.hypot(xs[1] - xs[0], ys[1] - ys[0]),
                    math.hypot(xs[2] - xs[1], ys[2] - ys[1])})
    return sides[0], sides[-1]


def feasibility(
    plan: Plan | str | dict[str, Any],
    *,
    agent_radius: float = 0.2,
    min_free_fraction: float = 0.3,
    access: bool = False,
) -> Feasibility:
    """Estimate, before sampling, whether a plan's room can hold its objects.

    Parameters
    ----------
    plan : Plan, str or dict
        A plan, or anything :func:`forcelayout.load_plan` takes (a path, JSON
        text, a dict or a bundled plan's name).
    agent_radius : float
        Radius of the disc-shaped agent, metres (default 0.2, as the checks).
    min_free_fraction : float
        Share of the floor the ``navigable`` check asks to stay free
        (default 0.3, as the checks).
    access : bool
        Whether the ``access`` check will run (``--access``): an object whose
        only access side a rule stands against a wall then makes the plan
        infeasible (:func:`forcelayout.sanity.plan_findings`).

    Returns
    -------
    Feasibility
        The estimates, a verdict and notes; ``print()`` it for a summary.

    Notes
    -----
    Only floor objects that are obstacles count: objects placed on a top, a
    wall or the ceiling, and walkable covers (rugs), take no floor. The free
    floor is estimated from each footprint inflated by the agent radius
    (``w d + 2 r (w + d) + π r²``), less the margin behind a wall-bound
    object, which lies outside the room.

    Examples
    --------
    >>> from forcelayout.diagnose import feasibility
    >>> print(feasibility("bedroom"))              # doctest: +SKIP
    plan 'bedroom': ok
      floor 15.96 m²; obstacles cover 4.07 m² (25%); about 48% stays free ...
    """
    if not (math.isfinite(agent_radius) and agent_radius >= 0):
        raise ValueError(f"feasibility: agent_radius must be >= 0 metres, got {agent_radius!r}")
    if not 0.0 <= min_free_fraction <= 1.0:
        raise ValueError(f"feasibility: min_free_fraction must lie in [0, 1], "
                         f"got {min_free_fraction!r}")
    plan = load_plan(plan)
    r = float(agent_radius)
    floor = plan.room.shape
    area = float(floor.area)
    obstacles = [o for o in plan.floor_objects() if not o.is_walkable]
    places = _wall_places(plan)

    footprint = sum(o.size[0] * o.size[1] for o in obstacles)
    blocked = 0.0
    for o in obstacles:
        w, d = o.size[0], o.size[1]
        inflated = w * d + 2 * r * (w + d) + math.pi * r * r
        place = places.get(o.id)
        if place == "wall":  # the strip behind it and half its rounded corners are outside
            inflated -= r * w + 0.5 * math.pi * r * r
        elif place == "corner":
            inflated -= r * (w + d) + 0.75 * math.pi * r * r
        blocked += inflated
    free = max(0.0, 1.0 - blocked / area)
    best_blocked = footprint + (math.sqrt(math.pi * footprint) * r if footprint > 0 else 0.0)
    free_best = max(0.0, 1.0 - best_blocked / area)

    span = _span(floor)
    largest = max(obstacles, key=lambda o: (max(o.size[:2]), o.size[0] * o.size[1]),
                  default=None)
    misfits = [o.id for o in obstacles
               if not (_fits(floor, o.size[0], o.size[1]) or _fits(floor, o.size[1], o.size[0]))]

    room = plan.room
    perimeter = sum(room.wall_length(k) for k in range(len(room.polygon)))
    doors = sum(d.width for d in room.doors)
    windows = sum(w.width for w in room.windows)
    sill = min((w.sill for w in room.windows), default=math.inf)
    bound = [o for o in obstacles if o.id in places]
    demand = {o.id: o.size[0] + (o.size[1] if places[o.id] == "corner" else 0.0) for o in bound}
    wall_demand = sum(demand.values())
    tall_demand = sum(demand[o.id] for o in bound if o.size[2] > sill + 1e-9)
    wall_available = max(0.0, perimeter - doors)
    tall_available = max(0.0, perimeter - doors - windows)

    bad: list[str] = []
    tight: list[str] = []
    for oid in misfits:
        o = plan.object(oid)
        bad.append(f"{oid!r} ({o.size[0]:g} x {o.size[1]:g} m) fits nowhere on the floor at a "
                   "cardinal heading")
    fill = footprint / area
    if fill > MAX_FLOOR_FILL:
        bad.append(f"the obstacles cover {fill:.0%} of the floor (more than "
                   f"{MAX_FLOOR_FILL:.0%})")
    if free_best < min_free_fraction:
        bad.append(f"even packed into one block the obstacles leave at most {free_best:.0%} "
                   f"of the floor free for a {r:g} m agent (need {min_free_fraction:.0%}); "
                   "remove objects or enlarge the room")
    elif free < min_free_fraction + _TIGHT_FREE_MARGIN:
        hint = ("only layouts that group furniture pass" if free < min_free_fraction
                else "little to spare")
        tight.append(f"if the objects stood apart, they would leave about {free:.0%} of the "
                     f"floor free for a {r:g} m agent ({min_free_fraction:.0%} needed): {hint}")
    if wall_demand > wall_available + 1e-9:
        bad.append(f"the wall-bound objects need {wall_demand:.2f} m of wall, the room has "
                   f"{wall_available:.2f} m without its doors")
    elif tall_demand > tall_available + 1e-9:
        bad.append(f"the wall-bound objects taller than the sill need {tall_demand:.2f} m of "
                   f"wall, the room has {tall_available:.2f} m without doors and windows")
    elif wall_available > 0 and wall_demand > _TIGHT_WALL * wall_available:
        tight.append(f"the wall-bound objects take {wall_demand / wall_available:.0%} of the "
                     "wall without doors; corners and door swings leave less")
    elif tall_available > 0 and tall_demand > _TIGHT_WALL * tall_available:
        tight.append(f"the tall wall-bound objects take {tall_demand / tall_available:.0%} of "
                     "the wall without doors and windows")
    if largest is not None and largest.id not in misfits:
        long_side = max(largest.size[:2])
        if long_side > _TIGHT_SPAN * span[1]:  # both ways (a square room has no long walls)
            tight.append(f"{largest.id!r} ({long_side:g} m long) spans "
                         f"{long_side / span[0]:.0%} of the room's width ({span[0]:.2f} m) "
                         f"and {long_side / span[1]:.0%} of its length ({span[1]:.2f} m); "
                         "at either heading little floor is left beside its ends")
        elif long_side > _TIGHT_SPAN * span[0]:
            tight.append(f"{largest.id!r} ({long_side:g} m long) spans "
                         f"{long_side / span[0]:.0%} of the room's short side "
                         f"({span[0]:.2f} m); it can only lie along the long walls")
    findings = plan_findings(plan, access=access)
    bad += [str(f) for f in findings if f.severity == "infeasible"]
    odd = [str(f) for f in findings if f.severity != "infeasible"]
    verdict: Verdict = "infeasible" if bad else "tight" if tight else "ok"
    return Feasibility(
        plan=plan.name, verdict=verdict, notes=bad + tight + odd, findings=findings,
        blocking=len(bad),
        floor_area=area,
        footprint_area=footprint, fill=fill, free_fraction=free, free_fraction_best=free_best,
        min_free_fraction=min_free_fraction, room_span=span,
        largest=largest.id if largest is not None else None,
        largest_size=(largest.size[0], largest.size[1]) if largest is not None else (0.0, 0.0),
        misfits=misfits, wall_bound=[o.id for o in bound], wall_demand=wall_demand,
        wall_available=wall_available, tall_demand=tall_demand, tall_available=tall_available,
        agent_radius=r)


# -- after a run ---------------------------------------------------------------------------

_QUOTED = re.compile(r"'([^']+)'")
_BINDING = re.compile(r"([A-Za-z_][\w]*)\(([^()]*)\)")
_BLOCKERS = re.compile(r"\(blocked by ([^)]*)\)")
_UNREACHED = re.compile(r"^(?:'([^']+)'|(door \d+)) cannot be reached")


def _names(ids: Sequence[str]) -> str:
    ids = list(ids)
    return ids[0] if len(ids) == 1 else ", ".join(ids[:-1]) + " and " + ids[-1]


def _top(counter: Counter[str], *, share: float = 0.75, most: int = 3) -> list[str]:
    """The most common keys: the first, and those at least ``share`` as common.

    Ties keep the order in which the keys were first counted.
    """
    if not counter:
        return []
    ranked = sorted(counter.items(), key=lambda kv: -kv[1])
    first = ranked[0][1]
    return [k for k, c in ranked if c >= share * first][:most]


def _pct(k: int, n: int) -> str:
    return f"{100.0 * k / n:.0f} %"


def missed_rules(failures: Iterable[str]) -> list[str]:
    """The rule bindings a rejected sample misses, from its ``rules:`` failure line.

    Parameters
    ----------
    failures : iterable of str
        A sample's failure lines (``SampleReport.failures``).

    Returns
    -------
    list of str
        Each binding once, as the rule check names it, in order.

    Examples
    --------
    >>> missed_rules(["rules: 80% met, below 95%; unmet: next_to(nightstand_2, bed), "
    ...               "at_wall(desk)", "reachable: 'desk' cannot be reached"])
    ['next_to(nightstand_2, bed)', 'at_wall(desk)']
    """
    out: dict[str, None] = {}
    for line in failures:
        check, colon, reason = line.partition(":")
        if not colon or check.strip() != "rules":
            continue
        for name, args in _BINDING.findall(reason.partition("unmet:")[2]):
            out[f"{name}({', '.join(a.strip() for a in args.split(','))})"] = None
    return list(out)


def dominant_cause(reports: Iterable[Any]) -> str | None:
    """The most common reason samples failed, in one line.

    Parameters
    ----------
    reports : iterable of SampleReport
        One report per sample of a run (e.g. ``Generation.reports``); any
        object with a ``failures`` list of ``"<check>: <reason>"`` lines works.

    Returns
    -------
    str or None
        ``None`` when no sample failed. Otherwise the check that fails most
        often with the share of samples and the objects its lines name most
        often; then, when some samples miss rules, the bindings missed most
        often; then, when paths are blocked, the objects that most often
        block them and what they cut off. Shares are of all samples.

    Examples
    --------
    >>> from forcelayout import SampleReport
    >>> from forcelayout.diagnose import dominant_cause
    >>> dominant_cause([SampleReport(seed=0, valid=False, failures=[
    ...     "rules: 80% met, below 95%; unmet: next_to(nightstand_2, bed)"])])
    "100 % of samples fail 'rules' (miss next_to(nightstand_2, bed))"
    """
    reports = list(reports)
    n = len(reports)
    failing = [list(getattr(r, "failures", []) or []) for r in reports]
    if not any(failing):
        return None
    checks: Counter[str] = Counter()
    named: dict[str, Counter[str]] = {}
    missed: Counter[str] = Counter()
    blockers: Counter[str] = Counter()
    cut_off: Counter[str] = Counter()
    raised: Counter[str] = Counter()  # the exceptions samples raised, as their lines give them
    for lines in failing:
        # per sample, each name counts once; dicts keep the order names first appear
        seen_checks: dict[str, None] = {}
        seen_named: dict[tuple[str, str], None] = {}
        seen_missed: dict[str, None] = {}
        seen_block: dict[str, None] = {}
        seen_cut: dict[str, None] = {}
        for line in lines:
            check, colon, reason = line.partition(":")
            check = (check.strip() or "unknown") if colon else "other"
            reason = reason.strip()
            seen_checks[check] = None
            if check == "rules":
                seen_missed.update(dict.fromkeys(missed_rules([line])))
                continue
            if check == "error":
                raised[reason] += 1
                continue
            block = _BLOCKERS.search(reason)
            if block:
                seen_block.update(dict.fromkeys(_QUOTED.findall(block.group(1))))
                target = _UNREACHED.match(reason)
                if target:
                    seen_cut[target.group(1) or target.group(2)] = None
                reason = reason[:block.start()]
            # a missing object leads its part of the line ("missing: a: why; b: why"); the
            # names quoted in the why are where it was to go
            names = ([part.partition(":")[0].strip() for part in reason.split("; ")]
                     if check == "missing" else _QUOTED.findall(reason))
            for oid in names:
                seen_named[(check, oid)] = None
        checks.update(list(seen_checks))
        missed.update(list(seen_missed))
        blockers.update(list(seen_block))
        cut_off.update(list(seen_cut))
        for check, oid in seen_named:
            named.setdefault(check, Counter())[oid] += 1

    k = max(checks.values())
    tops = sorted(c for c, v in checks.items() if v == k)  # ties: all of them, by name
    check = tops[0]
    head = f"{_pct(k, n)} of samples fail " + " and ".join(repr(c) for c in tops)
    parts = []
    if check == "rules" and missed:
        head += f" (miss {', '.join(_top(missed))})"
    elif check == "error":
        head += f" (raised {raised.most_common(1)[0][0]})"
    else:
        who = [] if check == "reachable" and blockers else _top(named.get(check, Counter()))
        if who:
            head += f" (most often {_names(who)})"
        if missed:
            rule = _top(missed, share=1.0, most=2)
            noun = "rule" if len(rule) == 1 else "rules"
            parts.append(f"{_pct(missed[rule[0]], n)} miss {noun} {' and '.join(rule)}")
    if blockers:
        who = _top(blockers)
        what = _top(cut_off)
        verb = "blocks" if len(who) == 1 else "block"
        parts.append(f"{_names(who)} {verb} the path to {_names(what)}"
                     if what else f"{_names(who)} {verb} the way")
    return "; ".join([head, *parts])


@contextmanager
def feasibility_warnings_as_lines() -> Iterator[None]:
    """Inside the block, every :class:`FeasibilityWarning` is one ``warning: ...`` line on stderr.

    For command lines: the warning is shown each time (not once per place),
    without the file and line of the code that raised it. Other warnings
    are shown as usual; :class:`FewLayoutsWarning` is left to the caller.
    """
    with warnings.catch_warnings():
        warnings.simplefilter("always", FeasibilityWarning)
        show = warnings.showwarning

        def say(message: Any, category: type[Warning], *rest: Any, **kw: Any) -> None:
            if issubclass(category, FeasibilityWarning):
                print(" ".join(f"warning: {message}".split()), file=sys.stderr, flush=True)
            else:
                show(message, category, *rest, **kw)

        warnings.showwarning = say
        yield
