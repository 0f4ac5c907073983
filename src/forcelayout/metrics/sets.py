"""Diversity of sets of layouts: all-pairs matrices, intra-plan and inter-plan means."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from itertools import combinations
from typing import Any, Literal

import numpy as np

from forcelayout.layout import Layout
from forcelayout.metrics.geometric import geometric_dissimilarity
from forcelayout.metrics.jaccard import jaccard_matrix
from forcelayout.metrics.relational import relation_triples
from forcelayout.metrics.topological import occupancy_masks

__all__ = ["pairwise", "intra_plan", "inter_plan", "still_objects"]

#: The built-in metrics by name (or pass any callable ``(a, b) -> float``).
MetricName = Literal["geometric", "topological", "relational"]


def pairwise(
    layouts: Sequence[Layout],
    metric: MetricName | Callable[[Layout, Layout], float] = "geometric",
    **kwargs: Any,
) -> np.ndarray:
    """Symmetric matrix of dissimilarities between all layouts, shape (K, K).

    Parameters
    ----------
    layouts : sequence of Layout
    metric : {"geometric", "topological", "relational"} or callable
        A callable takes two layouts and returns a float.
    **kwargs
        Passed to the metric (``agent_radius=``, ``canonical=``, weights ...).
        Topological and relational matrices are computed in one vectorised
        pass (each layout rasterised or read once).
    """
    k = len(layouts)
    if metric == "topological":
        masks, _ = occupancy_masks(layouts, **kwargs)
        return jaccard_matrix(masks.reshape(k, -1))
    if metric == "relational":
        sets = [relation_triples(lay, **kwargs) for lay in layouts]
        vocab = {t: n for n, t in enumerate(sorted(set().union(*sets)))}
        x = np.zeros((k, len(vocab)), dtype=bool)
        for r, s in enumerate(sets):
            x[r, [vocab[t] for t in s]] = True
        return jaccard_matrix(x)
    if metric == "geometric":
        fn: Callable[..., float] = geometric_dissimilarity
    elif callable(metric):
        fn = metric
    else:
        raise ValueError(f"unknown metric {metric!r}; use 'geometric', 'topological', "
                         "'relational' or a callable(a, b) -> float")
    d = np.zeros((k, k))
    for i, j in combinations(range(k), 2):
        d[i, j] = d[j, i] = fn(layouts[i], layouts[j], **kwargs)
    return d


def intra_plan(
    layouts: Sequence[Layout],
    metric: MetricName | Callable[[Layout, Layout], float] = "geometric",
    **kwargs: Any,
) -> float:
    """Mean dissimilarity over all pairs of layouts of one plan (NaN for fewer than 2)."""
    if len(layouts) < 2:
        return float("nan")
    d = pairwise(layouts, metric, **kwargs)
    return float(d[np.triu_indices(len(layouts), 1)].mean())


def inter_plan(
    groups: Sequence[Sequence[Layout]],
    metric: MetricName | Callable[[Layout, Layout], float] = "geometric",
    **kwargs: Any,
) -> float:
    """Mean dissimilarity over all pairs of layouts from different plans.

    Parameters
    ----------
    groups : sequence of sequences of Layout
        One group per plan. The paper's inter-prompt figure compares the first
        accepted layout of each plan: ``inter_plan([[g[0]] for g in groups])``.

    Returns
    -------
    float
        NaN when fewer than two groups are non-empty.
    """
    flat = [lay for g in groups for lay in g]
    label = np.array([k for k, g in enumerate(groups) for _ in g])
    if len(set(label.tolist())) < 2:
        return float("nan")
    d = pairwise(flat, metric, **kwargs)
    iu = np.triu_indices(len(flat), 1)
    cross = label[iu[0]] != label[iu[1]]
    return float(d[iu][cross].mean())


def still_objects(layouts: Sequence[Layout], *, tolerance: float = 0.05,
                  max_turn: float = 5.0, least: int = 5) -> list[str]:
    """Floor objects that stand in the same spot in every layout of a set.

    A plan whose rules and room leave an object one place gives it the same
    pose in every layout (a counter in the one corner two doors leave free):
    what a set's diversity cannot show object by object.

    Parameters
    ----------
    layouts : sequence of Layout
        Layouts of one plan.
    tolerance : float
        Largest distance of an object's centre from its mean over the set, m.
    max_turn : float
        Largest difference of its heading from its first, degrees.
    least : int
        Fewer layouts than this say nothing: an empty list.

    Returns
    -------
    list of str
        Object ids, in plan order.

    Examples
    --------
    >>> import forcelayout as fl
    >>> from forcelayout.metrics import still_objects
    >>> g = fl.generate("bedroom", 6, seed=0)
    >>> still_objects(list(g))
    []
    >>> still_objects([g[0]] * 6)[:2]
    ['bed', 'nightstand_1']
    """
    if len(layouts) < max(least, 2):
        return []
    out = []
    for oid in layouts[0].ids():
        poses = [lay.poses.get(oid) for lay in layouts]
        if any(p is None or p.surface != "floor" for p in poses):
            continue
        xy = np.array([[p.x, p.y] for p in poses])
        yaw = np.array([p.yaw for p in poses])
        turn = np.abs((yaw - yaw[0] + np.pi) % (2 * np.pi) - np.pi)
        if (np.linalg.norm(xy - xy.mean(0), axis=1).max() <= tolerance
                and np.degrees(turn).max() <= max_turn):
            out.append(oid)
    return out
