"""Tools for testing code built on forcelayout: hypothesis strategies and a rule checker.

Strategies (need ``hypothesis``, part of the ``dev`` extra):

* :func:`rooms` — rectangles and simple L-shaped rooms with doors and windows;
* :func:`scene_objects` — furniture with plausible sizes;
* :func:`plans` — feasible plans that validate, with rules from the built-in
  vocabulary.

:func:`check_rule` is a conformance check for rule plugin authors, in the
spirit of Gymnasium's environment checker: it runs a rule on random states
and raises :class:`RuleConformanceError` with a clear message when the rule
breaks the contract every rule must keep.

Examples
--------
>>> from forcelayout.testing import check_rule
>>> report = check_rule("near", n_states=5)
>>> report["states"]
5

In a test suite::

    from hypothesis import given, settings
    from forcelayout.testing import plans

    @settings(max_examples=20, deadline=None)
    @given(plans(max_objects=5))
    def test_my_exporter(plan):
        ...
"""

from __future__ import annotations

import functools
import math
from typing import Any

import numpy as np

from forcelayout import rules as registry
from forcelayout.bindings import RuleGroup
from forcelayout.geometry import RoomGeometry
from forcelayout.plan import Plan, Room, SceneObject
from forcelayout.rules.base import ParamArrays, Rule, State
from forcelayout.surfaces.walls import free_intervals

__all__ = [
    "rooms",
    "scene_objects",
    "plans",
    "check_rule",
    "RuleConformanceError",
    "make_state",
    "bind",
    "FURNITURE",
    "UNARY_RULES",
    "BINARY_RULES",
]

#: Categories with typical ``[width, depth, height]`` in metres, used by :func:`scene_objects`.
FURNITURE: dict[str, tuple[float, float, float]] = {
    "bed": (1.4, 2.0, 0.5),
    "nightstand": (0.45, 0.4, 0.55),
    "wardrobe": (1.0, 0.6, 2.0),
    "dresser": (1.0, 0.5, 0.8),
    "desk": (1.2, 0.6, 0.75),
    "chair": (0.5, 0.5, 0.9),
    "armchair": (0.8, 0.8, 0.9),
    "sofa": (2.0, 0.9, 0.8),
    "coffee_table": (1.0, 0.6, 0.45),
    "side_table": (0.45, 0.45, 0.55),
    "tv_stand": (1.4, 0.45, 0.5),
    "bookshelf": (0.8, 0.35, 1.8),
    "dining_table": (1.4, 0.9, 0.75),
    "plant": (0.4, 0.4, 1.0),
}
#: Built-in floor rules without a target, drawn by :func:`plans` (from the registry).
UNARY_RULES = tuple(registry.builtin_rules(target="none", surface="floor"))
#: Built-in floor rules with a target, drawn by :func:`plans` (from the registry).
BINARY_RULES = tuple(registry.builtin_rules(target="required", surface="floor"))


def _st() -> Any:
    from forcelayout._optional import import_optional

    return import_optional("hypothesis.strategies", "dev")


# -- strategies ------------------------------------------------------------------------


def _round(x: float, step: float = 0.05) -> float:
    return round(round(x / step) * step, 6)


def rooms(
    *, min_side: float = 3.0, max_side: float = 7.0, shapes: tuple[str, ...] = ("rect", "L")
) -> Any:
    """Strategy for :class:`~forcelayout.plan.Room`: rectangles and simple L shapes.

    Parameters
    ----------
    min_side, max_side : float
        Range of the bounding box's sides, metres (``min_side >= 2``).
    shapes : tuple of {"rect", "L"}
        Which outlines to draw. An L is the rectangle with one corner cut away
        (30–50 % of each side).

    Every room has one door, and zero to two windows, on walls long enough
    to hold them; the origin is shifted at random, so code under test must
    not assume the room starts at (0, 0).
    """
    st = _st()
    if min_side < 2.0 or max_side < min_side:
        raise ValueError(f"rooms(): need 2 <= min_side <= max_side, got {min_side}, {max_side}")

    @st.composite
    def _rooms(draw: Any) -> Room:
        w = _round(draw(st.floats(min_side, max_side)))
        h = _round(draw(st.floats(min_side, max_side)))
        shape = draw(st.sampled_from(shapes))
        if shape == "L":
            cw = _round(w * draw(st.floats(0.3, 0.5)))
            ch = _round(h * draw(st.floats(0.3, 0.5)))
            poly = [(0, 0), (w, 0), (w, h - ch), (w - cw, h - ch), (w - cw, h), (0, h)]
        else:
            poly = [(0, 0), (w, 0), (w, h), (0, h)]
        ox = _round(draw(st.floats(-10.0, 10.0)))
        oy = _round(draw(st.floats(-10.0, 10.0)))
        poly = [(round(x + ox, 6), round(y + oy, 6)) for x, y in poly]
        lengths = [math.dist(poly[k], poly[(k + 1) % len(poly)]) for k in range(len(poly))]

        taken: dict[int, list[tuple[float, float]]] = {}  # stretches of wall in use

        def opening(width: float) -> dict[str, float] | None:
            # free stretches long enough, 0.1 m from the wall's ends and from other openings
            gaps = [(k, a, b) for k, n in enumerate(lengths)
                    for a, b in free_intervals(n, [(a, b, 0.0, 1.0) for a, b in taken.get(k, [])],
                                               0.0, 1.0, margin=0.0)
                    if b - a >= width + 0.2 + 1e-6]
            if not gaps:
                return None
            k, a, b = draw(st.sampled_from(gaps))
            lo, hi = a + width / 2 + 0.1, b - width / 2 - 0.1
            offset = round(lo + (hi - lo) * draw(st.floats(0, 1)), 4)
            taken.setdefault(k, []).append((offset - width / 2, offset + width / 2))
            return {"wall": k, "offset": offset, "width": width}

        door = opening(_round(draw(st.floats(0.8, 1.0))))
        windows = [opening(_round(draw(st.floats(0.8, 1.4))))
                   for _ in range(draw(st.integers(0, 2)))]
        return Room.model_validate({
            "polygon": poly, "height": _round(draw(st.floats(2.4, 3.0))),
            "doors": [door] if door else [], "windows": [o for o in windows if o]})

    return _rooms()


def scene_objects(*, id: str | None = None, max_height: float = 2.3) -> Any:
    """Strategy for :class:`~forcelayout.plan.SceneObject`: furniture of plausible size.

    Parameters
    ----------
    id : str, optional
        The object's id; defaults to its category.
    max_height : float
        Cap on the height, metres (keep it below the room's ceiling).

    Categories come from :data:`FURNITURE`; each size is the typical one
    scaled by 0.8–1.2 per dimension.
    """
    st = _st()

    @st.composite
    def _objects(draw: Any) -> SceneObject:
        cat = draw(st.sampled_from(sorted(FURNITURE)))
        size = [_round(s * draw(st.floats(0.8, 1.2)), 0.01) for s in FURNITURE[cat]]
        size[2] = min(size[2], max_height)
        return SceneObject(id=id or cat, category=cat, size=tuple(size),
                           primary=draw(st.booleans()))

    return _objects()


def plans(*, min_objects: int = 1, max_objects: int = 8, rules: bool = True,
          fill: float = 0.3) -> Any:
    """Strategy for feasible :class:`~forcelayout.plan.Plan` objects that validate.

    Parameters
    ----------
    min_objects, max_objects : int
        Number of (floor) objects.
    rules : bool
        Draw zero to two rules per object from the built-in unary and binary
        vocabulary (:data:`UNARY_RULES`, :data:`BINARY_RULES`), binary ones
        with another object of the plan as target, with default parameters
        (``under`` only on walkable covers).
    fill : float
        Largest fraction of the floor the footprints may cover; objects are
        shrunk to fit (the plan validator allows up to 0.6).

    Rooms come from :func:`rooms`, objects from :func:`scene_objects`; ids
    are ``<category>_<k>``.
    """
    st = _st()
    if not 1 <= min_objects <= max_objects:
        raise ValueError(f"plans(): need 1 <= min_objects <= max_objects, got "
                         f"{min_objects}, {max_objects}")
    if not 0 < fill <= 0.6:
        raise ValueError(f"plans(): fill must be in (0, 0.6], got {fill}")

    @st.composite
    def _plans(draw: Any) -> Plan:
        room = draw(rooms())
        area = room.shape.area
        n = draw(st.integers(min_objects, max_objects))
        objs = [draw(scene_objects(id=f"obj_{k}", max_height=room.height - 0.1))
                for k in range(n)]
        total = sum(o.size[0] * o.size[1] for o in objs)
        scale = min(1.0, math.sqrt(fill * area / total))
        objects = []
        for k, o in enumerate(objs):
            w, d, h = o.size
            objects.append({"id": f"{o.category}_{k}", "category": o.category,
                            "size": [max(0.1, math.floor(w * scale * 100) / 100),
                                     max(0.1, math.floor(d * scale * 100) / 100), h],
                            "primary": o.primary})
        ids = [o["id"] for o in objects]
        specs: list[dict[str, Any]] = []
        if rules:
            vocab = UNARY_RULES + (BINARY_RULES if n > 1 else ())
            # a rule that lays its object beneath its target takes a walkable cover only
            solid = tuple(r for r in vocab if (h := registry.get_rule(r).start) is None
                          or h.place != "beneath")
            for oid, o in zip(ids, objs, strict=True):
                for _ in range(draw(st.integers(0, 2))):
                    name = draw(st.sampled_from(vocab if o.is_walkable else solid))
                    spec: dict[str, Any] = {"rule": name, "object": oid}
                    if name in BINARY_RULES:
                        spec["target"] = draw(st.sampled_from([t for t in ids if t != oid]))
                    if spec not in specs:
                        specs.append(spec)
        return Plan.from_dict({"name": "generated", "room": room.model_dump(),
                               "objects": objects, "rules": specs})

    return _plans()


# -- hand-built states for rule tests --------------------------------------------------


def make_state(
    pos: Any,
    yaw: Any,
    size: Any,
    *,
    room: RoomGeometry | Room | dict[str, Any] | None = None,
) -> State:
    """A :class:`~forcelayout.rules.State` from plain lists, for testing rules by hand.

    Parameters
    ----------
    pos : array_like, shape (N, 2)
        Footprint centres, metres.
    yaw : array_like, shape (N,)
        Headings, radians CCW (0: front faces +y).
    size : array_like, shape (N, 2) or (N, 3)
        ``[width, depth(, height)]`` in metres (height defaults to 1 m).
    room : RoomGeometry, Room or dict, optional
        Defaults to a 4 x 3.5 m room with a door on wall 0 (centre (1, 0))
        and a window on wall 2 (centre (2, 3.5)).

    Examples
    --------
    >>> st = make_state([[2.0, 0.3]], [0.0], [[1.0, 0.5]])
    >>> st.front.round(3).tolist()
    [[-0.0, 1.0]]
    """
    if room is None:
        room = {"polygon": [[0, 0], [4, 0], [4, 3.5], [0, 3.5]],
                "doors": [{"wall": 0, "offset": 1.0, "width": 0.9}],
                "windows": [{"wall": 2, "offset": 2.0, "width": 1.2}]}
    if isinstance(room, dict):
        room = Room.model_validate(room)
    if isinstance(room, Room):
        room = RoomGeometry.from_room(room)
    pos = np.asarray(pos, dtype=float).reshape(-1, 2)
    size = np.asarray(size, dtype=float).reshape(len(pos), -1)
    if size.shape[1] == 2:
        size = np.column_stack([size, np.ones(len(pos))])
    ids = tuple(f"obj_{k}" for k in range(len(pos)))
    return State(pos, np.asarray(yaw, dtype=float).reshape(len(pos)), size, room, ids)


def bind(rule: type[Rule] | Rule | str, n: int = 1, *, weight: float | None = None,
         **params: Any) -> tuple[Rule, ParamArrays]:
    """A rule instance and :class:`~forcelayout.rules.ParamArrays` for ``n`` bindings.

    Parameters
    ----------
    rule : str, Rule subclass or instance
    n : int
        Number of bindings (all with the same parameters).
    weight : float, optional
        Binding weight; the rule's default otherwise.
    **params
        Parameter values (validated by the rule's ``Params``).

    Examples
    --------
    >>> rule, p = bind("near", 2, distance=0.5)
    >>> p.distance.tolist()
    [0.5, 0.5]
    """
    inst = _instance(rule)
    model = inst.Params.model_validate(params)
    w = inst.weight if weight is None else weight
    return inst, ParamArrays.from_models([model] * n, np.full(n, float(w)))


# -- conformance check for rule plugins -------------------------------------------------


class RuleConformanceError(Exception):
    """A rule breaks the contract every rule must keep (see :func:`check_rule`)."""


def _instance(rule: type[Rule] | Rule | str) -> Rule:
    if isinstance(rule, str):
        return registry.get_rule(rule)
    if isinstance(rule, Rule):
        return rule
    if isinstance(rule, type) and issubclass(rule, Rule):
        inst = rule()
        if "name" not in vars(rule):  # not registered: name it after its class
            inst.name = rule.__name__  # type: ignore[misc]
        return inst
    raise TypeError(f"check_rule() takes a rule name, Rule subclass or instance, got {rule!r}")


def _random_room(rng: np.random.Generator) -> RoomGeometry:
    w, h = rng.uniform(3.0, 6.0, 2)
    if rng.random() < 0.3:
        cw, ch = w * rng.uniform(0.3, 0.5), h * rng.uniform(0.3, 0.5)
        poly = np.array([[0, 0], [w, 0], [w, h - ch], [w - cw, h - ch], [w - cw, h], [0, h]])
    else:
        poly = np.array([[0, 0], [w, 0], [w, h], [0, h]])
    poly = poly + rng.uniform(-3.0, 3.0, 2)
    return RoomGeometry(poly, 2.7, [(0, 0.3 * w, 0.9)], [(1, 0.5 * h if len(poly) == 4
                                                         else 0.5 * (h - ch), 0.8)])


def _shifted(state: State, delta: np.ndarray) -> State:
    room = state.room
    shifted = RoomGeometry(
        room.polygon + delta, room.height,
        [(int(k), float(o), float(wd)) for k, o, wd in _opening_specs(room.doors, room)],
        [(int(k), float(o), float(wd)) for k, o, wd in _opening_specs(room.windows, room)])
    return State(state.pos + delta, state.yaw.copy(), state.size, shifted, state.ids)


def _opening_specs(o: Any, room: RoomGeometry) -> list[tuple[int, float, float]]:
    offset = ((o.centre - room.a[o.wall]) * o.tangent).sum(1)
    return list(zip(o.wall.tolist(), offset.tolist(), o.width.tolist(), strict=True))


def _raw(rule: Rule, method: str) -> Any:
    """The rule's own ``force`` or ``satisfied``, without the engine's check of a plugin's
    results (check_rule says more about what is wrong)."""
    fn = getattr(type(rule), method)
    return functools.partial(getattr(fn, "__wrapped__", fn), rule)


def _call_force(rule: Rule, state: State, i: np.ndarray, j: np.ndarray | None,
                p: ParamArrays, where: str) -> tuple[np.ndarray, np.ndarray]:
    b = len(i)
    with np.errstate(all="ignore"):  # non-finite results are reported below
        out = _raw(rule, "force")(state, i, j, p)
    if not (isinstance(out, tuple) and len(out) == 2):
        raise RuleConformanceError(
            f"{rule.name}.force() must return a tuple (F, tau), got {type(out).__name__} "
            f"({where})")
    f, tau = (np.asarray(a) for a in out)
    if f.shape != (b, 2):
        raise RuleConformanceError(
            f"{rule.name}.force(): F has shape {f.shape}, expected ({b}, 2) for {b} bindings "
            f"({where}); return one 2D force per binding")
    if tau.shape != (b,):
        raise RuleConformanceError(
            f"{rule.name}.force(): tau has shape {tau.shape}, expected ({b},) for {b} bindings "
            f"({where}); return one torque per binding (np.zeros(len(i)) for none)")
    if not (np.all(np.isfinite(f)) and np.all(np.isfinite(tau))):
        raise RuleConformanceError(
            f"{rule.name}.force() returned non-finite values ({where}); guard divisions by "
            "distances that can be zero (e.g. objects at the same centre)")
    return f.astype(float), tau.astype(float)


def _call_satisfied(rule: Rule, state: State, i: np.ndarray, j: np.ndarray | None,
                    p: ParamArrays, where: str) -> np.ndarray:
    ok = _raw(rule, "satisfied")(state, i, j, p)
    if not isinstance(ok, np.ndarray) or ok.dtype != np.bool_ or ok.shape != (len(i),):
        shape = getattr(ok, "shape", None)
        dtype = getattr(ok, "dtype", type(ok).__name__)
        raise RuleConformanceError(
            f"{rule.name}.satisfied() must return a numpy bool array of shape ({len(i)},), "
            f"got {dtype} with shape {shape} ({where}); e.g. return gap <= p.distance")
    return ok


def check_rule(
    rule: type[Rule] | Rule | str,
    *,
    n_states: int = 50,
    seed: int = 0,
    params: dict[str, Any] | None = None,
    max_satisfied_force: float = 0.5,
    steps: int = 120,
) -> dict[str, Any]:
    """Check that a floor rule keeps the contract of :class:`~forcelayout.rules.Rule`.

    The rule runs on ``n_states`` random rooms (rectangles and L shapes, a
    door and a window, shifted origins) with four random objects, including
    degenerate states (all objects at one centre, objects outside the room).
    Unary rules bind every object; binary rules bind the pairs (0, 1) and
    (2, 3), and all ordered pairs for the shape checks. Then:

    1. ``force`` returns ``(F, tau)`` with shapes (B, 2) and (B,), finite;
    2. forces are translation invariant: moving the room and the objects
       together by the same vector gives the same forces and torques;
    3. ``satisfied`` returns a numpy bool array of shape (B,);
    4. following the rule's own force for ``steps`` steps (as the solver
       does, without collisions) does not make its check fail more often;
    5. where the check says "satisfied with margin" (it stays satisfied
       when every object is nudged by about 2 cm and 1°), the force is at most
       ``max_satisfied_force`` times the binding weight, so a finished layout
       is not pulled around;
    6. a rule that declares ``batched = True`` gives each sample of a state
       stacking three samples (``State.samples``) the forces and checks that
       sample gets alone, bit for bit.

    Parameters
    ----------
    rule : str, Rule subclass or Rule instance
        A registered name or the rule itself.
    n_states : int
        Number of random states (each also relaxed along the rule's force).
    seed : int
        Seed of the random states.
    params : dict, optional
        Parameters for every binding; the rule's ``Params`` defaults otherwise.
    max_satisfied_force : float
        Largest force per unit weight allowed where the rule is satisfied
        with margin.
    steps : int
        Relaxation steps (dt = 1/30 s, speed capped at 1 m/s, annealed
        weight ``1 / (1 + 0.02 t)``).

    Returns
    -------
    dict
        ``{"rule", "states", "bindings", "satisfied_before", "satisfied_after"}``
        (fractions of bindings satisfied before and after relaxation).

    Raises
    ------
    RuleConformanceError
        Naming the rule, the broken check and what to do.
    TypeError
        For surface rules (they act on other planes; not checked here).
    """
    inst = _instance(rule)
    if inst.surface != "floor":
        raise TypeError(f"check_rule() checks floor rules; {inst.name!r} places its object on "
                        f"a {inst.surface!r} surface")
    if n_states < 1 or steps < 0:
        raise ValueError("check_rule(): n_states >= 1 and steps >= 0")
    from forcelayout.errors import RuleOutputError

    try:
        return _check(inst, n_states, seed, steps, params, max_satisfied_force)
    except RuleOutputError as e:  # from a stacked or nudged call the checks below make
        raise RuleConformanceError(str(e)) from None


def _check(inst: Rule, n_states: int, seed: int, steps: int, params: dict[str, Any] | None,
           max_satisfied_force: float) -> dict[str, Any]:
    """The body of :func:`check_rule`."""
    try:
        model = inst.Params.model_validate(params or {})
    except Exception as e:
        raise RuleConformanceError(
            f"{inst.name}.Params could not be built from {params or {}!r}: {e}. Give every "
            "parameter a default, or pass params=") from e
    rng = np.random.default_rng(seed)
    n = 4
    binary = inst.target == "required"
    i = np.array([0, 2]) if binary else np.arange(n)
    j = np.array([1, 3]) if binary else None
    ai, aj = (np.nonzero(~np.eye(n, dtype=bool)) if binary else (np.arange(n), None))

    def params_for(b: int, scale: float = 1.0) -> ParamArrays:
        return ParamArrays.from_models([model] * b, np.full(b, inst.weight * scale))

    before: list[np.ndarray] = []
    after: list[np.ndarray] = []
    for k in range(n_states):
        room = _random_room(rng)
        lo, hi = room.bounds[:2], room.bounds[2:]
        size = np.column_stack([rng.uniform(0.3, 1.5, (n, 2)), rng.uniform(0.4, 1.5, n)])
        pos = rng.uniform(lo, hi, (n, 2))
        yaw = rng.uniform(-np.pi, np.pi, n)
        if k == 0:  # degenerate: every object at one centre, same heading
            pos[:] = room.centroid
            yaw[:] = 0.0
        elif k == 1:  # outside the room
            pos = hi + rng.uniform(0.5, 2.0, (n, 2))
        ids = tuple(f"obj_{r}" for r in range(n))
        state = State(pos, yaw, size, room, ids)
        where = f"state {k} of seed {seed}"
        for ii, jj in ((i, j), (ai, aj)):
            delta = rng.uniform(-20.0, 20.0, 2)
            for attempt in range(2):  # a nudge breaks exact ties (e.g. two equally near walls)
                if attempt:
                    state = State(state.pos + rng.normal(0.0, 1e-3, state.pos.shape),
                                  state.yaw.copy(), size, room, ids)
                f, tau = _call_force(inst, state, ii, jj, params_for(len(ii)), where)
                f2, tau2 = _call_force(inst, _shifted(state, delta), ii, jj,
                                       params_for(len(ii)), where + ", shifted")
                scale = 1e-6 * (1.0 + np.abs(f).max() + np.abs(tau).max())
                same = (np.allclose(f, f2, rtol=1e-6, atol=scale)
                        and np.allclose(tau, tau2, rtol=1e-6, atol=scale))
                if same:
                    break
            if not same:
                raise RuleConformanceError(
                    f"{inst.name}.force() is not translation invariant ({where}): moving the "
                    f"room and all objects by {np.round(delta, 2).tolist()} m changed the force "
                    f"from {np.round(f, 4).tolist()} to {np.round(f2, 4).tolist()}. Use "
                    "positions relative to the room's walls or the target, not absolute ones")
            _call_satisfied(inst, state, ii, jj, params_for(len(ii)), where)
        if inst.batched:
            _check_batched(inst, state, i, j, params_for(len(i)), rng, where)
        ok = _call_satisfied(inst, state, i, j, params_for(len(i)), where)
        before.append(ok)
        _check_margin(inst, state, i, j, params_for(len(i)), ok, rng, max_satisfied_force, where)
        # relax along the rule's own force, the way the solver moves bodies
        pos, yaw = state.pos.copy(), state.yaw.copy()
        for t in range(steps):
            f, tau = _call_force(inst, state, i, j, params_for(len(i), 1.0 / (1.0 + 0.02 * t)),
                                 where + f", relaxation step {t}")
            speed = np.sqrt((f * f).sum(1, keepdims=True))
            pos[i] += f * np.minimum(1.0, 1.0 / np.maximum(speed, 1e-12)) / 30.0
            yaw[i] += np.clip(tau * 4.0, -3.0, 3.0) / 30.0
            state = State(pos, yaw, size, room, ids)
        ok = _call_satisfied(inst, state, i, j, params_for(len(i)), where + ", relaxed")
        after.append(ok)
        _check_margin(inst, state, i, j, params_for(len(i)), ok, rng, max_satisfied_force, where)
    frac_before = float(np.mean(np.concatenate(before)))
    frac_after = float(np.mean(np.concatenate(after)))
    if frac_after < min(frac_before - 0.02, 0.9 * frac_before):  # more than noise
        raise RuleConformanceError(
            f"{inst.name}: following its own force for {steps} steps made its check pass less "
            f"often ({frac_before:.0%} of bindings satisfied before, {frac_after:.0%} after). "
            "The force must point towards what satisfied() accepts")
    return {"rule": inst.name, "states": n_states, "bindings": len(i) * n_states,
            "satisfied_before": frac_before, "satisfied_after": frac_after}


def _check_batched(rule: Rule, state: State, i: np.ndarray, j: np.ndarray | None,
                   p: ParamArrays, rng: np.random.Generator, where: str) -> None:
    """A ``batched`` rule on three stacked samples: each gets its own forces, bit for bit."""
    n = state.n
    states = [state] + [State(state.pos + rng.normal(0.0, 0.3, state.pos.shape),
                              state.yaw + rng.normal(0.0, 0.5, n), state.size, state.room,
                              state.ids) for _ in range(2)]
    stacked = State(np.concatenate([s.pos for s in states]),
                    np.concatenate([s.yaw for s in states]), np.tile(state.size, (3, 1)),
                    state.room, state.ids * 3, samples=3)
    # the bindings of each sample, as the engine stacks them
    big = RuleGroup(rule, i, j, p, np.full(len(i), -1), np.arange(len(i))).stack(3, n)
    f, tau = _call_force(rule, stacked, big.i, big.j, big.params, where + ", stacked")
    ok = _call_satisfied(rule, stacked, big.i, big.j, big.params, where + ", stacked")
    for b, one in enumerate(states):
        f1, t1 = _call_force(rule, one, i, j, p, where)
        ok1 = _call_satisfied(rule, one, i, j, p, where)
        rows = slice(b * len(i), (b + 1) * len(i))
        if not (np.array_equal(f[rows], f1) and np.array_equal(tau[rows], t1)
                and np.array_equal(ok[rows], ok1)):
            raise RuleConformanceError(
                f"{rule.name} declares batched = True, but on a state stacking three samples "
                f"({where}) sample {b} got other forces or checks than alone: it relates rows of "
                "different samples. Use only i, j and State.separation, gap_estimate, gap "
                "and peers (never the all-pairs matrices or every row), or set "
                "batched = False (the engine then calls the rule once per sample)")


def _check_margin(rule: Rule, state: State, i: np.ndarray, j: np.ndarray | None,
                  p: ParamArrays, ok: np.ndarray, rng: np.random.Generator, limit: float,
                  where: str) -> None:
    robust = ok.copy()
    for _ in range(4):
        if not robust.any():
            return
        nudged = State(state.pos + rng.normal(0.0, 0.02, state.pos.shape),
                       state.yaw + rng.normal(0.0, np.radians(1.0), state.yaw.shape),
                       state.size, state.room, state.ids)
        robust &= _call_satisfied(rule, nudged, i, j, p, where)
    f, _ = _call_force(rule, state, i, j, p, where)
    mag = np.sqrt((f * f).sum(1))
    bad = robust & (mag > limit * np.maximum(p.weight, 1e-12))
    if bad.any():
        b = int(np.flatnonzero(bad)[0])
        raise RuleConformanceError(
            f"{rule.name}: binding {b} is satisfied with margin ({where}) but the force on it is "
            f"{mag[b]:.3g} (weight {p.weight[b]:g}, allowed {limit:g} x weight). A finished "
            "layout would be pulled around; let the force fade to zero inside the region "
            "satisfied() accepts")
