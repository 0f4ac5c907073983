"""Geometric dissimilarity: optimal per-category matching of two layouts' objects.

Objects of one canonical category are paired by the Hungarian algorithm on a
cost mixing position, size and yaw; objects left without a partner cost a
fixed penalty. Units: metres, radians (CCW).
"""

from __future__ import annotations

import math

import numpy as np

from forcelayout.layout import Layout
from forcelayout.metrics.labels import Canonical, canonical_label

__all__ = ["geometric_dissimilarity"]


def _objects(layout: Layout) -> tuple[list[str], np.ndarray, np.ndarray, np.ndarray]:
    """Placed objects as (ids, positions (N, 3), sizes (N, 3), yaws (N,))."""
    ids = layout.ids()
    poses = [layout.poses[i] for i in ids]
    pos = np.array([[p.x, p.y, p.z] for p in poses], dtype=float).reshape(-1, 3)
    size = np.array([layout.plan.object(i).size for i in ids], dtype=float).reshape(-1, 3)
    yaw = np.array([p.yaw for p in poses], dtype=float)
    return ids, pos, size, yaw


def _assignment(cost: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`scipy.optimize.linear_sum_assignment`, imported when first needed (scipy's
    optimize package takes half a second to import: every command line call paid it)."""
    from scipy.optimize import linear_sum_assignment

    return linear_sum_assignment(cost)


def _room_diagonal(layout: Layout) -> float:
    xmin, ymin, xmax, ymax = layout.room.bounds
    return float(math.sqrt((xmax - xmin) ** 2 + (ymax - ymin) ** 2 + layout.room.height ** 2))


def _check_weights(**weights: float) -> None:
    for name, w in weights.items():
        if not (np.isfinite(w) and w >= 0):
            raise ValueError(f"{name} must be a finite number >= 0, got {w!r}")


def geometric_dissimilarity(
    a: Layout,
    b: Layout,
    *,
    canonical: Canonical = canonical_label,
    position_weight: float = 0.5,
    size_weight: float = 0.25,
    yaw_weight: float = 0.25,
    unmatched_cost: float = 1.0,
    yaw_period: float = 2 * math.pi,
) -> float:
    """Optimal-matching distance between the objects of two layouts, in ``[0, 1]``.

    Objects are grouped by canonical category. Within each category the
    objects of ``a`` and ``b`` are paired by the Hungarian algorithm
    (:func:`scipy.optimize.linear_sum_assignment`) on the cost

    ``c = clip(w_p·‖Δ(x, y, z)‖/D + w_s·‖Δsize‖/max(‖size_a‖, ‖size_b‖) + w_y·δ/(P/2), 0, 1)``

    where ``D`` is the larger room diagonal ``√(Δx² + Δy² + height²)`` of the
    two rooms' bounding boxes (metres), ``δ`` the yaw difference modulo the
    symmetry period ``P`` (radians, in ``[0, P/2]``). Objects left without a
    partner (a category has more objects in one layout) cost
    ``unmatched_cost``. The result is the total cost divided by the number of
    matched pairs plus unmatched objects (``Σ_c max(n_a,c, n_b,c)``).

    Identical layouts give 0, layouts with no category in common give
    ``unmatched_cost`` (1 by default); the measure is symmetric.

    Parameters
    ----------
    a, b : Layout
    canonical : callable, default :func:`canonical_label`
        Maps an object's category to the label used for matching.
    position_weight, size_weight, yaw_weight : float
        ``w_p, w_s, w_y`` (dimensionless, >= 0; defaults sum to 1).
    unmatched_cost : float
        Penalty per object without a partner, in ``[0, 1]``.
    yaw_period : float
        Rotational symmetry period ``P`` in radians; ``2π`` (default) treats an
        object turned by 180° as different, ``π`` as the same.

    Returns
    -------
    float
        0 when both layouts are empty.
    """
    _check_weights(position_weight=position_weight, size_weight=size_weight,
                   yaw_weight=yaw_weight, unmatched_cost=unmatched_cost)
    if unmatched_cost > 1:
        raise ValueError(f"unmatched_cost must lie in [0, 1], got {unmatched_cost}")
    if not (yaw_period > 0 and np.isfinite(yaw_period)):
        raise ValueError(f"yaw_period must be a positive number of radians, got {yaw_period}")
    ia, pa, sa, ya = _objects(a)
    ib, pb, sb, yb = _objects(b)
    ca = [canonical(a.plan.object(i).category) for i in ia]
    cb = [canonical(b.plan.object(i).category) for i in ib]
    diag = max(_room_diagonal(a), _room_diagonal(b), 1e-9)
    total, count = 0.0, 0
    for cat in set(ca) | set(cb):
        ka = np.array([k for k, c in enumerate(ca) if c == cat], dtype=int)
        kb = np.array([k for k, c in enumerate(cb) if c == cat], dtype=int)
        count += max(len(ka), len(kb))
        total += unmatched_cost * abs(len(ka) - len(kb))
        if len(ka) == 0 or len(kb) == 0:
            continue
        dpos = np.linalg.norm(pa[ka, None, :] - pb[None, kb, :], axis=-1) / diag
        norms = np.maximum(np.linalg.norm(sa[ka], axis=1)[:, None],
                           np.linalg.norm(sb[kb], axis=1)[None, :])
        dsize = np.linalg.norm(sa[ka, None, :] - sb[None, kb, :], axis=-1) / np.maximum(norms,
                                                                                      1e-12)
        dyaw = np.mod(ya[ka, None] - yb[None, kb], yaw_period)
        dyaw = np.minimum(dyaw, yaw_period - dyaw) / (yaw_period / 2)
        cost = np.clip(position_weight * np.minimum(dpos, 1.0)
                       + size_weight * np.minimum(dsize, 1.0)
                       + yaw_weight * np.minimum(dyaw, 1.0), 0.0, 1.0)
        r, c = _assignment(cost)
        total += float(cost[r, c].sum())
    return float(total / count) if count else 0.0
