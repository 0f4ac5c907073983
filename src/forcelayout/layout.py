"""Layouts: the poses a plan's objects end at, with a report of how they got there.

A :class:`Layout` is plain data: a pose per object (x, y, yaw, z, surface),
the plan it realises, the seed that made it and a :class:`SampleReport`. It
round-trips through JSON, judges its own rules, and shows itself as a
top-down picture in notebooks.

Pose convention: ``x, y`` are the footprint centre in room coordinates
(metres); ``yaw`` is radians CCW with 0 meaning the front faces +y; ``z`` is
the height of the object's bottom above the floor; ``surface`` is
``"floor"``, a parent object's id, ``"wall:<i>"`` or ``"ceiling"``.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from forcelayout.geometry import RoomGeometry, box_corners
from forcelayout.plan import Plan, _binding_label

if TYPE_CHECKING:
    from forcelayout.rules.base import State

__all__ = ["Pose", "RuleResult", "SampleReport", "Layout"]

#: SampleReport fields that measure time, left out of layout files.
_TIMINGS = frozenset({"seconds", "stages"})


@dataclass(frozen=True)
class Pose:
    """Where one object ends.

    Attributes
    ----------
    x, y : float
        Footprint centre, metres, room coordinates.
    yaw : float
        Radians CCW; 0 = front faces +y.
    z : float
        Height of the object's bottom above the floor, metres.
    surface : str
        ``"floor"``, a parent id (on top of it), ``"wall:<i>"`` or ``"ceiling"``.
    """

    x: float
    y: float
    yaw: float
    z: float = 0.0
    surface: str = "floor"


@dataclass(frozen=True)
class RuleResult:
    """Whether one binding of the plan is met in a layout."""

    index: int
    rule: str
    object: str
    target: str | None
    satisfied: bool | None  # None: not judged (an object of the binding is not placed)

    @property
    def label(self) -> str:
        """The binding as reports name it: ``near(sofa, tv)``."""
        return _binding_label(self.rule, self.object, self.target)


@dataclass
class SampleReport:
    """How one sample went.

    Attributes
    ----------
    seed : int
        Seed of this sample (derived from the run's seed and its index).
    steps : int
        Simulation steps taken (all stages).
    converged : bool
        Whether every simulation settled before its step cap.
    seconds : float
        Wall time of the sample.
    valid : bool
        Whether the sample passed: every object placed, the deterministic
        checks passed and at least ``min_rule_satisfaction`` of its rules met
        (what ``generate`` accepts).
    failures : list of str
        Why the sample was rejected (empty when valid).
    missing : list of str
        Objects of the plan not placed (with the reason), never dropped silently.
    rule_satisfaction : float
        Fraction of judged rule bindings met, in [0, 1].
    stages : dict of str to float
        Seconds per stage of the sample.
    repairs : list of str
        What each repair round did (see :mod:`forcelayout.repair`); empty
        when the sample needed none.
    """

    seed: int
    steps: int = 0
    converged: bool = True
    seconds: float = 0.0
    valid: bool = True
    failures: list[str] = field(default_factory=list)
    missing: list[str] = field(default_factory=list)
    rule_satisfaction: float = 1.0
    stages: dict[str, float] = field(default_factory=dict)
    repairs: list[str] = field(default_factory=list)

    @property
    def repaired(self) -> bool:
        """Whether a repair round changed the sample."""
        return bool(self.repairs)


class Layout:
    """One realisation of a plan.

    Parameters
    ----------
    plan : Plan
    poses : dict of str to Pose
        Pose per placed object.
    seed : int
    report : SampleReport, optional
    """

    def __init__(
        self,
        plan: Plan,
        poses: dict[str, Pose],
        seed: int = 0,
        report: SampleReport | None = None,
    ):
        self.plan = plan
        self.poses = dict(poses)
        self.seed = int(seed)
        self.report = report if report is not None else SampleReport(seed=self.seed)
        self._room: RoomGeometry | None = None
        self._rules: list[RuleResult] | None = None

    # -- geometry ---------------------------------------------------------------
    @property
    def room(self) -> RoomGeometry:
        """The room as arrays."""
        if self._room is None:
            self._room = RoomGeometry.from_room(self.plan.room)
        return self._room

    def ids(self, surface: str | None = None) -> list[str]:
        """Placed object ids in plan order, optionally only those on ``surface``."""
        return [o.id for o in self.plan.objects
                if o.id in self.poses and (surface is None or self.poses[o.id].surface == surface)]

    def state(self, ids: list[str] | None = None) -> State:
        """The floor objects (or ``ids``) as a :class:`~forcelayout.rules.State`."""
        from forcelayout.rules.base import State

        ids = self.ids("floor") if ids is None else ids
        pos = np.array([[self.poses[i].x, self.poses[i].y] for i in ids], dtype=float)
        yaw = np.array([self.poses[i].yaw for i in ids], dtype=float)
        size = np.array([self.plan.object(i).size for i in ids], dtype=float)
        return State(pos.reshape(-1, 2), yaw, size.reshape(-1, 3), self.room, tuple(ids))

    def corners(self, object_id: str) -> np.ndarray:
        """Footprint corners of one object, shape (4, 2), CCW from back-left."""
        p = self.poses[object_id]
        half = 0.5 * np.array([self.plan.object(object_id).size[:2]], dtype=float)
        return box_corners(np.array([[p.x, p.y]]), np.array([p.yaw]), half)[0]

    def gap(self, a: str, b: str) -> float:
        """Clearance between the footprints of objects ``a`` and ``b``, metres."""
        s = self.state([a, b])
        return float(s.gap(np.array([0]), np.array([1]))[0])

    # -- rules ------------------------------------------------------------------
    def rule_report(self) -> list[RuleResult]:
        """Whether each rule binding of the plan is met (None where not judged).

        Computed once per layout (a layout's poses are not meant to change
        after it is made; build a new Layout for new poses).
        """
        if self._rules is None:
            from forcelayout.report import judge_rules

            self._rules = judge_rules(self)
        return list(self._rules)

    @staticmethod
    def _judge_rules_of(layouts: list[Layout]) -> None:
        """Compute the rule reports of many layouts at once (on stacked states), as
        :meth:`rule_report` would one by one."""
        from forcelayout.report import judge_rules_many

        todo = [lay for lay in layouts if lay._rules is None]
        for lay, rules in zip(todo, judge_rules_many(todo), strict=True):
            lay._rules = rules

    @property
    def rule_satisfaction(self) -> float:
        """Fraction of judged bindings met, in [0, 1] (1 if there are none)."""
        judged = [r.satisfied for r in self.rule_report() if r.satisfied is not None]
        return float(np.mean(judged)) if judged else 1.0

    @property
    def required_unmet(self) -> list[str]:
        """The rules the plan marks ``required`` that this layout leaves unmet, labelled as
        reports label them (``at_wall(desk_chair)``); no acceptance share lets one go."""
        rules = self.plan.rules
        return [r.label for r in self.rule_report()
                if r.satisfied is False and rules[r.index].required]

    def check(self, **kwargs: Any) -> Any:
        """Run the deterministic checks; see :func:`forcelayout.validate.check_layout`."""
        from forcelayout.validate import check_layout

        return check_layout(self, **kwargs)

    # -- JSON -------------------------------------------------------------------
    def to_dict(self, *, include_plan: bool = False) -> dict[str, Any]:
        """Plain-data form: ``{"plan": name, "seed": s, "objects": {id: pose}, "report": ...}``.

        The report leaves out the wall-clock timings (``seconds``, ``stages``),
        so the same plan and seed always give the same JSON bytes.
        """
        d: dict[str, Any] = {
            "plan": self.plan.name,
            "seed": self.seed,
            "objects": {
                oid: {"x": p.x, "y": p.y, "yaw": p.yaw, "z": p.z, "surface": p.surface}
                for oid, p in self.poses.items()
            },
            # timings stay out of the file: the same sample gives the same bytes
            "report": {k: v for k, v in asdict(self.report).items() if k not in _TIMINGS},
            "rules": [asdict(r) for r in self.rule_report()],
        }
        if include_plan:
            d["plan_spec"] = self.plan.model_dump(mode="json")
        return d

    def to_json(self, *, indent: int | None = 2, include_plan: bool = False) -> str:
        """JSON text of :meth:`to_dict`."""
        return json.dumps(self.to_dict(include_plan=include_plan), indent=indent)

    @classmethod
    def from_dict(cls, data: dict[str, Any], plan: Plan | None = None) -> Layout:
        """Rebuild a layout from :meth:`to_dict` output.

        ``plan`` is required unless the data embeds it (``include_plan=True``).
        """
        if not isinstance(data, dict) or not isinstance(data.get("objects"), dict):
            raise ValueError("not a layout: expected a JSON object with an 'objects' mapping "
                             "of poses (as written by Layout.save)")
        if plan is None:
            if "plan_spec" not in data:
                raise ValueError("layout JSON has no embedded plan and no plan.json beside "
                                 "it; pass plan=... (forcelayout.load_plan(path)), or write "
                                 "it with save(path, include_plan=True)")
            plan = Plan.from_dict(data["plan_spec"])
        unknown = set(data.get("objects", {})) - set(plan.ids)
        if unknown:
            raise ValueError(f"layout objects {sorted(unknown)} are not in plan {plan.name!r}")
        poses = {}
        for oid, p in data["objects"].items():
            missing = [k for k in ("x", "y", "yaw") if not isinstance(p, dict) or k not in p]
            if missing:
                raise ValueError(f"objects.{oid} has no {', '.join(map(repr, missing))}: each "
                                 "pose needs 'x', 'y' and 'yaw' (as written by Layout.save)")
            try:
                poses[oid] = Pose(float(p["x"]), float(p["y"]), float(p["yaw"]),
                                  float(p.get("z", 0.0)), str(p.get("surface", "floor")))
            except (TypeError, ValueError):
                raise ValueError(f"objects.{oid}: 'x', 'y', 'yaw' and 'z' are numbers, got "
                                 f"{ {k: p.get(k) for k in ('x', 'y', 'yaw', 'z') if k in p} }"
                                 ) from None
        rep = data.get("report")
        report = SampleReport(**rep) if isinstance(rep, dict) else None
        return cls(plan, poses, int(data.get("seed", 0)), report)

    @classmethod
    def from_json(cls, text: str, plan: Plan | None = None) -> Layout:
        """Rebuild a layout from JSON text."""
        return cls.from_dict(json.loads(text), plan)

    def save(self, path: str | Path, *, include_plan: bool = False) -> Path:
        """Write the layout JSON to ``path``."""
        path = Path(path)
        path.write_text(self.to_json(include_plan=include_plan), encoding="utf-8")
        return path

    @classmethod
    def load(cls, path: str | Path, plan: Plan | None = None) -> Layout:
        """Read a layout JSON file.

        Its plan is ``plan`` if given, else the one embedded in the file
        (``save(include_plan=True)``), else the ``plan.json`` beside it (as
        ``forcelayout generate`` and datasets write it).
        """
        path = Path(path)
        data = json.loads(path.read_text(encoding="utf-8"))
        beside = path.parent / "plan.json"
        if plan is None and isinstance(data, dict) and "plan_spec" not in data \
                and beside.is_file():
            plan = Plan.from_json(beside.read_text(encoding="utf-8"))
        return cls.from_dict(data, plan)

    # -- pictures ---------------------------------------------------------------
    def picture(self, path: str | Path | None = None, **kwargs: Any) -> Any:
        """Draw the layout top-down; see :func:`forcelayout.render.draw_layout`."""
        from forcelayout.render import draw_layout

        return draw_layout(self, path, **kwargs)

    def _repr_svg_(self) -> str:
        from forcelayout.render import layout_svg

        return layout_svg(self)

    def __repr__(self) -> str:
        return (f"<Layout plan={self.plan.name!r} seed={self.seed} objects={len(self.poses)}/"
                f"{len(self.plan.objects)} valid={self.report.valid}>")

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Layout):
            return NotImplemented
        return self.plan.name == other.plan.name and self.poses == other.poses
