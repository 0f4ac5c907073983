"""Objects on a parent's top: a 2D simulation on the top, carried into the room.

The top is a rectangle "room" of the parent's width x depth in the parent's
frame; the children are simulated there with their rules between each other
(a rule whose start hint is a wall or corner, such as ``at_wall``, means the
top's edge; an ``at_wall`` child starts at the parent's back edge, turned as
the parent is, so a TV ends against the wall behind its stand), then carried
to the room at ``z`` = parent's ``z`` + parent's
height. A top too crowded for the simulation to settle (four boxes on a
0.2 x 0.4 m shelf) has its objects set out in rows instead, in a random
order; only objects that cannot fit at all are reported missing.
"""

from __future__ import annotations

import math

import numpy as np

from forcelayout.batching import SampleTask, SimRequest
from forcelayout.bindings import Binding, CompiledPlan
from forcelayout.geometry import RoomGeometry, box_corners
from forcelayout.layout import Pose
from forcelayout.options import SolverConfig
from forcelayout.rules.base import State
from forcelayout.surfaces.plane import SurfacePlacement, plane_model, plane_solver, rect

__all__ = ["place_on_tops", "holds"]

#: Start hints of room rules that keep their meaning on a top (its edges are its walls).
_EDGE_PLACES = frozenset({"wall", "corner"})


def _top_bindings(cp: CompiledPlan, kids: set[str]) -> list[Binding]:
    """Floor-rule bindings among the children of one top (plus edge rules)."""
    out = []
    for b in cp.bindings:
        if b.object not in kids or b.rule.surface != "floor":
            continue
        if b.target in kids:
            out.append(b)
        elif b.target is None and b.rule.start is not None \
                and b.rule.start.place in _EDGE_PLACES:
            out.append(b)
    return out


def place_on_tops(cp: CompiledPlan, poses: dict[str, Pose], rng: np.random.Generator,
                  relations: bool, cfg: SolverConfig, out: SurfacePlacement,
                  models: dict | None = None) -> SampleTask[None]:
    """Place every object that rests on a parent's top, parents before their children.

    A sample task (:mod:`forcelayout.batching`): each top's simulation is a
    :class:`~forcelayout.batching.SimRequest`. A top's plane is the same for
    every sample (the parent's top in its own frame), so samples given the
    same ``models`` dict share its force model and their simulations of it
    run as one batch.
    """
    models = {} if models is None else models
    children: dict[str, list[str]] = {}
    for b in cp.on("top"):
        if b.target is not None:
            children.setdefault(b.target, []).append(b.object)
    done: set[str] = set()
    for _ in range(len(children) + 1):  # parents in order: a parent must be placed first
        ready = [p for p in children if p not in done and p in poses]
        if not ready:
            break
        for parent in ready:
            done.add(parent)
            yield from _top_plane(cp, parent, children[parent], poses, rng, relations, cfg,
                                  out, models)
    for parent, kids in children.items():
        if parent not in done:
            out.missing.extend(f"{c}: its parent {parent!r} was not placed" for c in kids)


def _top_plane(cp: CompiledPlan, parent: str, kids: list[str], poses: dict[str, Pose],
               rng: np.random.Generator, relations: bool, cfg: SolverConfig,
               out: SurfacePlacement, models: dict) -> SampleTask[None]:
    pw, pd, ph = cp.size([parent])[0]
    size = cp.size(kids)
    pos = np.zeros((len(kids), 2))
    yaw = np.zeros(len(kids))
    bindings = _top_bindings(cp, set(kids))
    # a child that stands at a wall starts at the parent's back edge, turned as the
    # parent is: the parent's back is the side at a wall (a TV at the wall behind its stand)
    at_back = {b.object for b in bindings if b.target is None
               and b.rule.start is not None and b.rule.start.place == "wall"}
    model = plane_model(models, ("top", id(cp), parent, tuple(kids), relations), cp, kids,
                        rect(-pw / 2, -pd / 2, pw / 2, pd / 2), relations, bindings=bindings)
    edge = model.physical_weights.boundary_range + 1e-3  # starts beyond the terms' reach
    apart = model.physical_weights.repulsion_range + 1e-3
    for r in range(len(kids)):
        best, best_gap = None, -np.inf
        back = kids[r] in at_back and size[r, 0] <= pw + 1e-9 and size[r, 1] <= pd + 1e-9
        # turned as the parent is (a TV, a monitor, a microwave faces the front of what
        # it stands on), a quarter turn only for one that fits on it no other way
        y = 0.0 if back or (size[r, 0] <= pw + 1e-9 and size[r, 1] <= pd + 1e-9) \
            else np.pi / 2
        w, d = (size[r, 0], size[r, 1]) if y == 0.0 else (size[r, 1], size[r, 0])
        for _ in range(12 if w <= pw + 1e-9 and d <= pd + 1e-9 else 0):
            # clear of the edges by the walls' reach where the top allows (else centred):
            # where the plane's simulation would push it
            slack = np.array([pw - w, pd - d]) / 2
            inner = slack - np.minimum(slack, edge)
            p = rng.uniform(-inner, inner)
            if back:
                p[1] = -(pd - d) / 2
            gap = _min_gap(np.vstack([pos[:r], p]), np.append(yaw[:r], y), size[: r + 1],
                           last_only=True)
            if gap > best_gap:
                best, best_gap = (p, y), gap
            if gap > apart:
                break
        if best is None:
            out.missing.append(f"{kids[r]}: does not fit on top of {parent!r} in any orientation")
            return
        pos[r], yaw[r] = best
    res = yield SimRequest(model, pos, yaw, plane_solver(cfg))
    out.steps += res.steps
    out.converged &= res.converged
    fpos, fyaw = _clamp_inside(res.pos, res.yaw, size, pw, pd)
    if not _fits_rect(fpos, fyaw, size, pw, pd):
        fpos, fyaw = pos, yaw
    if not _fits_rect(fpos, fyaw, size, pw, pd):  # a crowded top: set them out in rows
        packed = _rows(size, pw, pd, rng.permutation(len(kids)))
        if packed is None:  # deepest first packs any set that rows can hold
            packed = _rows(size, pw, pd, _deepest_first(size, pw))
        if packed is not None:
            fpos, fyaw = packed
    if not _fits_rect(fpos, fyaw, size, pw, pd):
        out.missing.extend(f"{k}: no room for it on top of {parent!r} beside the other objects "
                           "there" for k in kids)
        return
    P = poses[parent]
    c, s = math.cos(P.yaw), math.sin(P.yaw)
    z = P.z + ph
    for k, (x, y), t in zip(kids, fpos.tolist(), fyaw.tolist(), strict=True):
        a = (t + P.yaw + np.pi) % (2 * np.pi) - np.pi
        poses[k] = Pose(P.x + c * x - s * y, P.y + s * x + c * y, float(a), float(z), parent)


def holds(sizes: np.ndarray | list[list[float]], width: float, depth: float) -> bool:
    """Whether a ``width x depth`` top holds footprints of ``sizes`` side by side.

    The test the top simulation's last resort passes: the footprints set out in rows, the
    deepest first, each turned to lie shallow where that fits.

    Parameters
    ----------
    sizes : array_like, shape (n, 2)
        The children's footprints, ``[width, depth]`` in metres.
    width, depth : float
        The top, metres.

    Examples
    --------
    >>> holds([[0.3, 0.3], [0.2, 0.2], [0.5, 0.5]], 1.2, 0.5)
    True
    >>> holds([[0.3, 0.3], [0.2, 0.2], [0.5, 0.5], [0.3, 0.3]], 1.2, 0.5)
    False
    """
    size = np.asarray(sizes, dtype=float).reshape(-1, 2)
    if len(size) == 0:
        return True
    return _rows(size, float(width), float(depth), _deepest_first(size, float(width))) is not None


def _deepest_first(size: np.ndarray, w: float) -> np.ndarray:
    return np.argsort(-_laid(size, w)[0][:, 1], kind="stable")


def _laid(size: np.ndarray, w: float) -> tuple[np.ndarray, np.ndarray]:
    """Footprints as rows across a top ``w`` wide lay them: the long side along the width where
    it fits (or where the short side would not), and each one's turn."""
    foot = size[:, :2]
    a, b = foot[:, 0], foot[:, 1]
    turned = ((b > a) & (b <= w + 1e-9)) | (a > w + 1e-9)
    return np.where(turned[:, None], foot[:, ::-1], foot), np.where(turned, np.pi / 2, 0.0)


def _rows(size: np.ndarray, w: float, d: float, order: np.ndarray
          ) -> tuple[np.ndarray, np.ndarray] | None:
    """Footprints set out in rows across a ``w x d`` top (in ``order``, each turned to be
    shallow where that is what fits), the spare room shared out between them; None if they do
    not fit."""
    n = len(size)
    foot, yaw = _laid(size, w)
    if (foot[:, 0] > w + 1e-9).any() or (foot[:, 1] > d + 1e-9).any():
        return None
    rows: list[list[int]] = [[]]
    used = 0.0
    for k in order.tolist():
        if rows[-1] and used + foot[k, 0] > w + 1e-9:
            rows.append([])
            used = 0.0
        rows[-1].append(k)
        used += foot[k, 0]
    depths = [max(foot[k, 1] for k in row) for row in rows]
    spare_y = d - sum(depths)
    if spare_y < -1e-9:
        return None
    pos = np.zeros((n, 2))
    gy = spare_y / (len(rows) + 1)
    y = -d / 2 + gy
    for row, depth in zip(rows, depths, strict=True):
        gx = (w - sum(foot[k, 0] for k in row)) / (len(row) + 1)
        x = -w / 2 + gx
        for k in row:
            pos[k] = x + foot[k, 0] / 2, y + depth / 2
            x += foot[k, 0] + gx
        y += depth + gy
    return pos, yaw


def _min_gap(pos: np.ndarray, yaw: np.ndarray, size: np.ndarray, *, last_only: bool = False
             ) -> float:
    """Smallest clearance between footprints (or from the last one to the others), metres."""
    if len(pos) < 2:
        return np.inf
    st = State(pos, yaw, size, RoomGeometry(rect(-1, -1, 1, 1)))
    m = st.separations.copy()
    np.fill_diagonal(m, np.inf)
    return float(m[-1].min() if last_only else m.min())


def _clamp_inside(pos: np.ndarray, yaw: np.ndarray, size: np.ndarray, w: float, d: float
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Settled poses moved the last millimetres inside a ``w x d`` top.

    Headings within 0.05 rad of a right angle are squared; each footprint's
    centre is then clipped so its extents lie inside the top (where they fit).
    The simulation's walls stop an object at the edge, not always a hair
    inside it.
    """
    quarter = np.round(yaw / (np.pi / 2)) * (np.pi / 2)
    yaw = np.where(np.abs(yaw - quarter) < 0.05, quarter, yaw)
    c, s = np.abs(np.cos(yaw)), np.abs(np.sin(yaw))
    ext = np.stack([c * size[:, 0] + s * size[:, 1], s * size[:, 0] + c * size[:, 1]], 1) / 2
    room = np.maximum(np.array([w / 2, d / 2])[None, :] - ext, 0.0)
    return np.clip(pos, -room, room), yaw


def _fits_rect(pos: np.ndarray, yaw: np.ndarray, size: np.ndarray, w: float, d: float) -> bool:
    c = box_corners(pos, yaw, size[:, :2] * 0.5)
    inside = (np.abs(c[..., 0]) <= w / 2 + 1e-9).all() and (np.abs(c[..., 1]) <= d / 2 + 1e-9).all()
    return bool(inside) and _min_gap(pos, yaw, size) >= -1e-3
