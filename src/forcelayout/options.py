"""How samples are made and judged: :class:`Options` and the solver's :class:`SolverConfig`.

Plain frozen dataclasses with no dependency on the engine, so every module
(sampling, the pipeline, the hierarchy, the solver) reads its settings from
here without importing the others.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from numbers import Integral
from typing import Any

__all__ = ["Options", "SolverConfig"]


@dataclass(frozen=True)
class SolverConfig:
    """Parameters of the annealed simulation.

    Attributes
    ----------
    k : float
        Cooling rate of ``T(t) = 1 / (1 + k t)`` (paper: 0.02).
    dt : float
        Box2D time step, seconds.
    mobility : float
        Velocity per unit force, m/s per N (overdamped motion).
    angular_mobility : float
        Angular velocity per unit torque, rad/s per N·m.
    max_speed : float
        Speed cap, m/s.
    max_turn : float
        Angular speed cap, rad/s.
    min_steps, max_steps : int
        The loop runs at least ``min_steps`` and at most ``max_steps`` steps.
    tol_pos : float
        Convergence threshold on per-step displacement, metres.
    tol_yaw : float
        Convergence threshold on per-step rotation, radians.
    patience : int
        Consecutive quiet steps that mean convergence.
    velocity_iterations, position_iterations : int
        Box2D solver iterations.
    semantic_interval : int
        The rule forces are recomputed every this many steps and held in
        between (multiple time stepping: the slow, soft semantic terms are
        sampled less often than the stiff physical ones, which are computed
        every step). 1 recomputes everything every step.
    settle_steps : int
        A start that already passes every check and meets every rule is
        first settled for at most this many steps by the rules and the
        physical terms alone (squared up, pressed to its walls), without the
        walking-room and access terms that would rearrange it, with doors
        keeping only their swing squares clear (:meth:`ForceModel.settling`),
        and with the bindings the start leaves unmet (within the sample's
        tolerance) muted (:meth:`ForceModel.muting`: their pull would drag an
        object across the room and break the bindings it meets); the full
        simulation runs only if that leaves a check failed or a rule unmet.
        0 always runs the full simulation. A floor still moving that does
        not pass after these steps settles as many again. Squaring up and
        pressing take 10-30 steps; beyond that, starts went on slowly turning
        a chair already within its facing cone, or pulling at a binding the
        start missed (which settling rarely met: 1 of 46 in a crowded dorm).
    """

    k: float = 0.02
    dt: float = 1.0 / 30.0
    mobility: float = 1.0
    angular_mobility: float = 4.0
    max_speed: float = 1.0
    max_turn: float = 3.0
    min_steps: int = 40
    max_steps: int = 400
    tol_pos: float = 2e-3
    tol_yaw: float = 4e-3
    patience: int = 8
    velocity_iterations: int = 6
    position_iterations: int = 3
    semantic_interval: int = 2
    settle_steps: int = 40

    def __post_init__(self) -> None:
        if self.max_steps < 1 or self.min_steps < 0 or self.patience < 1:
            raise ValueError("SolverConfig: max_steps >= 1, min_steps >= 0 and patience >= 1")
        if not (self.k >= 0 and self.dt > 0 and self.mobility > 0):
            raise ValueError("SolverConfig: k >= 0, dt > 0 and mobility > 0")
        if self.semantic_interval < 1:
            raise ValueError("SolverConfig: semantic_interval >= 1")
        if self.settle_steps < 0:
            raise ValueError("SolverConfig: settle_steps >= 0")


@dataclass(frozen=True)
class Options:
    """How samples are made and judged (all keyword arguments of :func:`generate`).

    Attributes
    ----------
    solver : SolverConfig
        Simulation parameters (annealing rate, step cap, thresholds).
    relations : bool
        ``False`` zeroes object-object rules (the −Relations ablation).
    decor : bool
        ``False`` removes secondary (``decor``) objects (the −Decor ablation).
    min_rule_satisfaction : float
        A sample meeting a smaller fraction of its rules is rejected
        (default 0.95: layouts that are valid *and* do what the plan says).
        The floor's start poses are judged the same way: a start that passes
        the checks and leaves no more bindings unmet than this allows is
        settled as it is, not searched further (1.0 asks for every rule); a
        lower value than 0.95 (``pipeline.START_RULE_SATISFACTION``) accepts
        more samples but does not let starts miss more rules.
    check : bool
        Run the deterministic checks (collisions, inside the room, door
        clearance, navigability, reachability) and reject failures.
    check_kwargs : dict
        Thresholds passed to :func:`forcelayout.validate.check_layout`
        (``None`` is no change to the defaults).
    hierarchy : bool
        Place the floor by the hierarchical path (area variants assembled in
        the room, see :mod:`forcelayout.hierarchy`) instead of one flat
        simulation.
    repair : int
        Repair rounds for a floor that fails a check or a rule: only the
        objects at fault move, in a short simulation (see
        :mod:`forcelayout.repair`); 0 runs none (with ``floor_attempts=1`` too,
        such samples are rejected at once).
    starts : int
        Most start rounds a sample's floor draws (:class:`forcelayout.initial.Starts`)
        before it simulates the one nearest passing (default 96). A start that
        passes ends the search at once, so only crowded plans spend them: 96
        against 32 took 60 plans of the benchmark suite from 1,837 to 1,875 of
        1,920 samples accepted for 47 % more time (the L-shaped hotel room 10
        -> 23 of 32, the L-shaped living room with two doors 18 -> 24).
    floor_attempts : int
        Times a sample's floor is tried at most (default 2): where the floor of
        the start nearest passing still fails its checks or rules after its
        repair rounds, the sample starts over with new starts (up to
        ``starts`` again), and keeps the better floor of its attempts. The
        report's repairs say "started over" for a layout a later attempt made.
        A floor that passes is not tried again, so only failing samples pay:
        2 against 1 took the 60 suite and held-out plans from 937 to 949 of 960
        samples accepted (the L-shaped living room with two doors 37 -> 47 of
        48, the dorm for two 39 -> 47); 3 added two more for half as much CPU
        again.
    variants : int
        Variants generated per functional area on the hierarchical path.
    variant_seed : int
        Seed of the variant library (shared by all samples of a run).
    batch : int
        Samples one process simulates together (the batched engine: the
        rule and physical terms are computed once per step for all of them).
        Layouts do not depend on it, bit for bit; larger batches save time
        per sample and hold more in memory (about 1 MB per sample of a
        22-object plan: 280 MB peak for a process at 64 against 226 MB at
        16, 134 MB of it the imports). 1 runs one sample at a time.
    """

    solver: SolverConfig = field(default_factory=SolverConfig)
    relations: bool = True
    decor: bool = True
    min_rule_satisfaction: float = 0.95
    check: bool = True
    check_kwargs: dict[str, Any] = field(default_factory=dict)
    hierarchy: bool = False
    repair: int = 6
    starts: int = 96
    floor_attempts: int = 2
    variants: int = 6
    variant_seed: int = 0
    batch: int = 64

    def __post_init__(self) -> None:
        if isinstance(self.batch, bool) or not isinstance(self.batch, Integral) \
                or self.batch < 1:
            raise ValueError(f"Options.batch must be a whole number >= 1 (samples simulated "
                             f"together), got {self.batch!r}")
        if isinstance(self.starts, bool) or not isinstance(self.starts, Integral) \
                or self.starts < 1:
            raise ValueError(f"Options.starts must be a whole number >= 1 (start rounds a "
                             f"sample may draw), got {self.starts!r}")
        tries = self.floor_attempts
        if isinstance(tries, bool) or not isinstance(tries, Integral) or tries < 1:
            raise ValueError(f"Options.floor_attempts must be a whole number >= 1 (times a "
                             f"sample's floor is tried), got {tries!r}")
        if self.check_kwargs is None:
            object.__setattr__(self, "check_kwargs", {})
        elif not isinstance(self.check_kwargs, Mapping):
            raise TypeError("Options.check_kwargs must be a dict of check parameters, e.g. "
                            f"{{'access_clearance': True}}; got {self.check_kwargs!r}")
        _check_names(self.check_kwargs)


def _check_names(kwargs: dict[str, Any]) -> None:
    """Refuse a ``check_kwargs`` key that :func:`~forcelayout.validate.check_layout` does
    not take, before any sampling, saying which it takes."""
    import difflib
    import inspect

    from forcelayout.validate.checks import check_layout, check_parameters

    known = [n for n, p in inspect.signature(check_layout).parameters.items()
             if p.kind is p.KEYWORD_ONLY]
    for key in kwargs:
        if key not in known:
            close = difflib.get_close_matches(str(key), known, n=1)
            hint = f" Did you mean {close[0]!r}?" if close else ""
            raise ValueError(f"Options.check_kwargs: unknown check parameter {key!r}.{hint} "
                             f"The checks take: {', '.join(known)}")
    try:
        check_parameters(**kwargs)
    except ValueError as e:
        raise ValueError(f"Options.check_kwargs: {str(e).removeprefix('check_layout: ')}") from None
    idle = [k for k in ("access_width", "max_access_overlap") if k in kwargs]
    if idle and not kwargs.get("access_clearance", False):
        import warnings

        warnings.warn(f"Options.check_kwargs: {', '.join(idle)} set but the access check is "
                      "off; add access_clearance=True to run it", UserWarning, stacklevel=3)
