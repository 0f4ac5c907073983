"""Random start poses for a simulation: parents anywhere, children near their parents.

Paper §III-B-3: "to ensure diversity, parent objects are placed randomly,
while child objects are placed near their parents to accelerate
convergence". Here a *child* is the object of a binary rule that asks it to
stay close to its target (``next_to``, ``in_front_of``, ``around``, ...);
the target is its parent. Starting a nightstand beside its bed rather than
across the room keeps it from settling against the wrong wall.
"""

from __future__ import annotations

import numpy as np
import shapely

from forcelayout import geometry as geo
from forcelayout.forces import ForceModel

__all__ = ["CLOSE_RULES", "parents", "initial_poses"]

#: Binary rules whose object should start near its target, strongest bond first.
CLOSE_RULES = ("next_to", "around", "in_front_of", "behind", "left_of", "right_of", "near",
               "aligned_with", "facing")


def parents(model: ForceModel) -> np.ndarray:
    """The parent row of each simulated object (``-1`` for none), shape (N,).

    Each object's parent is the target of its strongest close rule (order of
    :data:`CLOSE_RULES`); bindings that would close a cycle are ignored.
    """
    n = model.n
    parent = np.full(n, -1, dtype=int)
    rank = np.full(n, len(CLOSE_RULES), dtype=int)
    for g in model.groups:
        if g.j is None or g.rule.name not in CLOSE_RULES:
            continue
        r = CLOSE_RULES.index(g.rule.name)
        for i, j in zip(g.i.tolist(), g.j.tolist(), strict=True):
            if r >= rank[i] or _reaches(parent, j, i):
                continue
            parent[i], rank[i] = j, r
    return parent


def _reaches(parent: np.ndarray, start: int, goal: int) -> bool:
    """Whether following parents from ``start`` reaches ``goal`` (bounded walk)."""
    cur = start
    for _ in range(parent.shape[0] + 1):
        if cur == goal:
            return True
        if cur < 0:
            return False
        cur = int(parent[cur])
    return False


def _order(parent: np.ndarray, area: np.ndarray) -> list[int]:
    """Objects with parents after their parents; larger objects first otherwise."""
    depth = np.zeros(parent.shape[0], dtype=int)
    for r in range(parent.shape[0]):
        cur, d = r, 0
        while parent[cur] >= 0 and d <= parent.shape[0]:
            cur, d = int(parent[cur]), d + 1
        depth[r] = d
    return sorted(range(parent.shape[0]), key=lambda r: (depth[r], -area[r], r))


def initial_poses(
    model: ForceModel, rng: np.random.Generator, *, tries: int = 24, spread: float = 0.3
) -> tuple[np.ndarray, np.ndarray]:
    """Random start poses inside the room, children near their parents.

    Each object draws ``tries`` candidate poses at once (uniform in the room,
    or for a child: around its parent, at most ``spread`` metres beyond
    touching) and keeps the first whose footprint lies inside the floor and
    clear of the objects placed so far, else the candidate with the most
    clearance. Nothing loops beyond ``tries`` draws per object.

    Returns
    -------
    pos : ndarray, shape (N, 2)
    yaw : ndarray, shape (N,)
    """
    room = model.room
    n = model.n
    pos = np.zeros((n, 2))
    yaw = rng.uniform(-np.pi, np.pi, n)
    if n == 0:
        return pos, yaw
    half = model.size[:, :2] * 0.5
    radius = np.hypot(half[:, 0], half[:, 1])
    parent = parents(model)
    order = _order(parent, model.size[:, 0] * model.size[:, 1])
    lo, hi = room.bounds[:2], room.bounds[2:]
    floor = room.shape
    shapely.prepare(floor)
    placed: list[int] = []
    for r in order:
        cand = rng.uniform(lo, hi, (tries, 2))
        if parent[r] >= 0:  # near the parent first, anywhere as a fall-back
            q = parent[r]
            ang = rng.uniform(-np.pi, np.pi, tries)
            dist = radius[q] * 0.8 + radius[r] + rng.uniform(0.0, spread, tries)
            near = pos[q] + dist[:, None] * np.stack([np.cos(ang), np.sin(ang)], axis=1)
            cand = np.concatenate([near, cand[: tries // 2]])
        cand_yaw = np.full(len(cand), yaw[r])
        c, s = np.cos(cand_yaw), np.sin(cand_yaw)
        rgt = np.stack([c, s], axis=1) * half[r, 0]
        fwd = np.stack([-s, c], axis=1) * half[r, 1]
        corners = np.stack([cand - rgt - fwd, cand + rgt - fwd, cand + rgt + fwd,
                            cand - rgt + fwd], axis=1)
        inside = shapely.contains(floor, shapely.polygons(corners))
        clear = np.full(len(cand), 0.3)
        if placed:
            others = model.state(pos[placed], yaw[placed])
            others.size = model.size[placed]
            oc = others.corners  # (P, 4, 2)
            sep = geo.box_separation(corners[:, None], oc[None, :])  # (tries, P)
            clear = np.minimum(clear, sep.min(axis=1))
        score = np.where(inside, clear, -np.inf)
        good = np.flatnonzero(score >= 0.05)
        k = int(good[0]) if good.size else int(np.argmax(score))
        if not np.isfinite(score[k]):  # no candidate inside the floor: fall back to the centroid
            pos[r] = room.centroid
        else:
            pos[r] = cand[k]
        placed.append(r)
    return pos, yaw
