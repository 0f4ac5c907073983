"""What every surface plane shares: the anchor force term, the plane's solver settings and
force model, rectangles, and the result record of the surface stage."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from forcelayout.bindings import Binding, CompiledPlan
from forcelayout.forces import ForceModel
from forcelayout.geometry import RoomGeometry
from forcelayout.layout import Pose
from forcelayout.options import SolverConfig
from forcelayout.rules.base import State

__all__ = ["AnchorTerm", "SurfacePlacement", "rect", "plane_solver", "plane_model"]


class AnchorTerm:
    """An annealed spring pulling each object towards an anchor point of its plane.

    ``F = stiffness * (anchor - pos) * max(T, floor)``: strong early, never
    below ``floor`` of its strength, so an object keeps settling towards its
    anchor (eye level on a wall, the centre over a target, the middle of the
    ceiling) while the annealing cools the rules.

    Parameters
    ----------
    anchor : ndarray, shape (N, 2)
        Anchor point of each object in the plane's coordinates, metres.
    stiffness : ndarray, shape (N, 2)
        Spring constant per axis (0 leaves that axis free), per metre.
    floor : float
        Smallest temperature factor.
    """

    annealed = True

    def __init__(self, anchor: np.ndarray, stiffness: np.ndarray, floor: float = 0.25):
        self.anchor = np.asarray(anchor, dtype=float).reshape(-1, 2)
        self.stiffness = np.asarray(stiffness, dtype=float).reshape(-1, 2)
        self.floor = float(floor)

    def __call__(self, state: State, temperature: float) -> tuple[np.ndarray, np.ndarray]:
        f = self.stiffness * (self.anchor - state.pos) * max(float(temperature), self.floor)
        return f, np.zeros(state.n)

    def stack(self, samples: int, rows: int) -> AnchorTerm:
        """The same anchors in each of ``samples`` stacked samples."""
        return AnchorTerm(np.tile(self.anchor, (samples, 1)), np.tile(self.stiffness, (samples, 1)),
                          self.floor)

    @classmethod
    def join(cls, terms: list[AnchorTerm]) -> AnchorTerm:
        """One term for stacked samples, sample ``b`` anchored as ``terms[b]`` anchors it."""
        floors = {t.floor for t in terms}
        if len(floors) > 1:
            raise ValueError(f"anchor terms of one batch need one floor; got {sorted(floors)}")
        return cls(np.concatenate([t.anchor for t in terms]),
                   np.concatenate([t.stiffness for t in terms]), floors.pop())


@dataclass
class SurfacePlacement:
    """Poses of the off-floor objects and how their placement went.

    Attributes
    ----------
    poses : dict of str to Pose
        Every pose (the floor poses given in, plus the surface objects placed).
    missing : list of str
        ``"<id>: <reason>"`` per object that could not be placed.
    steps : int
        Simulation steps over all surface planes.
    converged : bool
        Whether every surface simulation settled.
    stages : dict of str to float
        Seconds spent on ``"tops"``, ``"walls"`` and ``"ceiling"``.
    """

    poses: dict[str, Pose]
    missing: list[str] = field(default_factory=list)
    steps: int = 0
    converged: bool = True
    stages: dict[str, float] = field(default_factory=dict)


def rect(x0: float, y0: float, x1: float, y1: float) -> np.ndarray:
    """The corners of an axis-aligned rectangle, shape (4, 2), counter-clockwise."""
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], dtype=float)


def plane_solver(cfg: SolverConfig) -> SolverConfig:
    """A surface plane's settings: at most 120 steps, quicker to call it settled."""
    return replace(cfg, min_steps=min(cfg.min_steps, 10), max_steps=min(cfg.max_steps, 120),
                   patience=min(cfg.patience, 5))


def plane_model(models: dict, key: tuple, cp: CompiledPlan, ids: list[str], polygon: np.ndarray,
                relations: bool, *, bindings: tuple[Binding, ...] | list[Binding] = (),
                sizes: dict[str, tuple[float, float, float]] | None = None) -> ForceModel:
    """The force model of objects ``ids`` on a plane bounded by ``polygon``, kept in
    ``models`` under ``key``: samples that share ``models`` share the model, so their
    simulations of the plane run as one batch (:mod:`forcelayout.batching`)."""
    model = models.get(key)
    if model is None:
        model = models[key] = ForceModel(cp, ids, sizes=sizes, bindings=bindings,
                                         room=RoomGeometry(polygon, height=1.0),
                                         relations=relations)
    return model
