"""The paper's evaluation: diversity, validity and speed of generated layouts.

Three dissimilarities between two layouts, each in ``[0, 1]`` (0: the same,
1: nothing in common), plus rates, throughput and bootstrap confidence
intervals. Everything here is plain numpy/scipy/shapely and needs no extra.

* :func:`geometric_dissimilarity` — optimal per-category matching of objects
  (Hungarian algorithm) with a cost mixing position, size and yaw, and a fixed
  penalty for objects without a partner.
* :func:`topological_dissimilarity` — Jaccard distance between the occupancy
  masks of the two floors, obstacles inflated by the agent radius (0.2 m).
* :func:`relational_dissimilarity` — Jaccard distance between the sets of
  relation triples ``(category, relation, category)`` read off the geometry.
* :func:`intra_plan` (all pairs of layouts of one plan) and
  :func:`inter_plan` (pairs of layouts of different plans).
* :func:`validity_rate`, :func:`rule_satisfaction_rate`, :func:`throughput`,
  :func:`bootstrap_ci`, and :func:`random_layout` (the Random baseline).

Object categories are compared after :func:`canonical_label` (``"Couch"`` and
``"sofa_2"`` are the same category); pass ``canonical=`` your own callable
(e.g. one backed by a text-embedding model) to change that.

Units: metres, radians (CCW), seconds. See ``docs/evaluating.md`` for the
formulas.

Examples
--------
>>> import forcelayout as fl
>>> from forcelayout import metrics
>>> plan = fl.examples.load_example("bedroom")
>>> a, b = metrics.random_layout(plan, 0), metrics.random_layout(plan, 1)
>>> 0.0 <= metrics.geometric_dissimilarity(a, b) <= 1.0
True
>>> metrics.geometric_dissimilarity(a, a)
0.0
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from itertools import combinations
from typing import Any, Literal

import numpy as np
from scipy.optimize import linear_sum_assignment

from forcelayout import geometry as geo
from forcelayout.layout import Layout, Pose, SampleReport
from forcelayout.plan import Plan

__all__ = [
    "canonical_label",
    "SYNONYMS",
    "geometric_dissimilarity",
    "occupancy_masks",
    "topological_dissimilarity",
    "RELATIONS",
    "relation_triples",
    "relational_dissimilarity",
    "jaccard_distance",
    "pairwise",
    "intra_plan",
    "inter_plan",
    "validity_rate",
    "rule_satisfaction_rate",
    "throughput",
    "ConfidenceInterval",
    "bootstrap_ci",
    "random_layout",
]

Canonical = Callable[[str], str]
MetricName = Literal["geometric", "topological", "relational"]

# -- categories ---------------------------------------------------------------------

#: Synonym table of the default :func:`canonical_label`: variant -> canonical name.
SYNONYMS: dict[str, str] = {
    "couch": "sofa",
    "settee": "sofa",
    "loveseat": "sofa",
    "love seat": "sofa",
    "bedside table": "nightstand",
    "night stand": "nightstand",
    "night table": "nightstand",
    "bedside cabinet": "nightstand",
    "closet": "wardrobe",
    "armoire": "wardrobe",
    "chest of drawers": "dresser",
    "tv": "television",
    "tv stand": "tv stand",
    "television stand": "tv stand",
    "media console": "tv stand",
    "coffee table": "coffee table",
    "cocktail table": "coffee table",
    "writing desk": "desk",
    "office chair": "chair",
    "desk chair": "chair",
    "swivel chair": "chair",
    "dining chair": "chair",
    "armchair": "armchair",
    "arm chair": "armchair",
    "easy chair": "armchair",
    "bookcase": "bookshelf",
    "book shelf": "bookshelf",
    "bookshelves": "bookshelf",
    "potted plant": "plant",
    "houseplant": "plant",
    "floor lamp": "lamp",
    "table lamp": "lamp",
    "desk lamp": "lamp",
    "rug": "rug",
    "carpet": "rug",
    "picture": "painting",
    "artwork": "painting",
    "poster": "painting",
    "ceiling lamp": "ceiling light",
}


def canonical_label(label: str) -> str:
    """The canonical category of an object label (the default canonicaliser).

    Lower-cases, turns ``_``/``-`` into spaces, drops digits, collapses
    whitespace, removes a plural ``s``/``es`` when the singular is
    in :data:`SYNONYMS`, then maps synonyms (``couch`` → ``sofa``, ``bedside
    table`` → ``nightstand``). Needs no model; replace it by passing
    ``canonical=`` to the metrics.

    Examples
    --------
    >>> canonical_label("Couch_2")
    'sofa'
    >>> canonical_label("bedside-table")
    'nightstand'
    """
    s = re.sub(r"[\d_\-]+", " ", str(label).lower())
    s = " ".join(s.split())
    known = SYNONYMS.keys() | set(SYNONYMS.values())
    if s not in known:
        for cut in ("es", "s"):
            if s.endswith(cut) and s[: -len(cut)] in known:
                s = s[: -len(cut)]
                break
    return SYNONYMS.get(s, s)


# -- helpers ------------------------------------------------------------------------


def _objects(layout: Layout) -> tuple[list[str], np.ndarray, np.ndarray, np.ndarray]:
    """Placed objects as (ids, positions (N, 3), sizes (N, 3), yaws (N,))."""
    ids = layout.ids()
    poses = [layout.poses[i] for i in ids]
    pos = np.array([[p.x, p.y, p.z] for p in poses], dtype=float).reshape(-1, 3)
    size = np.array([layout.plan.object(i).size for i in ids], dtype=float).reshape(-1, 3)
    yaw = np.array([p.yaw for p in poses], dtype=float)
    return ids, pos, size, yaw


def _room_diagonal(layout: Layout) -> float:
    xmin, ymin, xmax, ymax = layout.room.bounds
    return float(math.sqrt((xmax - xmin) ** 2 + (ymax - ymin) ** 2 + layout.room.height ** 2))


def _check_weights(**weights: float) -> None:
    for name, w in weights.items():
        if not (np.isfinite(w) and w >= 0):
            raise ValueError(f"{name} must be a finite number >= 0, got {w!r}")


# -- geometric ----------------------------------------------------------------------


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
        r, c = linear_sum_assignment(cost)
        total += float(cost[r, c].sum())
    return float(total / count) if count else 0.0


# -- topological --------------------------------------------------------------------


def occupancy_masks(
    layouts: Sequence[Layout],
    *,
    agent_radius: float = 0.2,
    grid: float = 0.05,
) -> tuple[np.ndarray, np.ndarray]:
    """Occupancy masks of several layouts on one shared grid.

    A cell is *occupied* when its centre lies inside the layout's floor
    polygon and within ``agent_radius`` of the footprint of an object standing
    on the floor (:func:`forcelayout.validate.occupancy_mask`). Objects on
    other objects, walls or the ceiling are not obstacles; walls are not
    marked. Each layout's mask is placed on a canvas covering all of their
    grids, so masks of different rooms are comparable cell by cell.

    Parameters
    ----------
    layouts : sequence of Layout
    agent_radius : float
        Inflation of every footprint, metres (the agent's radius).
    grid : float
        Cell size, metres.

    Returns
    -------
    masks : ndarray of bool, shape (K, H, W)
        Row ``r``, column ``c`` is the cell centred at
        ``origin + ((c + 0.5)·grid, (r + 0.5)·grid)``.
    origin : ndarray, shape (2,)
        Room coordinates of the canvas's lower-left corner, metres.
    """
    from forcelayout.validate import occupancy_mask

    if not (agent_radius >= 0 and np.isfinite(agent_radius)):
        raise ValueError(f"agent_radius must be >= 0 metres, got {agent_radius}")
    if not (grid > 0 and np.isfinite(grid)):
        raise ValueError(f"grid must be a positive cell size in metres, got {grid}")
    if not layouts:
        return np.zeros((0, 0, 0), dtype=bool), np.zeros(2)
    parts = [occupancy_mask(lay, agent_radius=agent_radius, grid=grid) for lay in layouts]
    lo = np.min([o for _, o in parts], axis=0)
    offs = [np.rint((o - lo) / grid).astype(int) for _, o in parts]  # (col, row) offsets
    h = max(off[1] + m.shape[0] for (m, _), off in zip(parts, offs, strict=True))
    w = max(off[0] + m.shape[1] for (m, _), off in zip(parts, offs, strict=True))
    masks = np.zeros((len(parts), h, w), dtype=bool)
    for k, ((m, _), off) in enumerate(zip(parts, offs, strict=True)):
        masks[k, off[1]: off[1] + m.shape[0], off[0]: off[0] + m.shape[1]] = m
    return masks, lo


def _jaccard_matrix(x: np.ndarray) -> np.ndarray:
    """Pairwise Jaccard distances between rows of a boolean matrix (K, M)."""
    xf = x.astype(np.float64)
    inter = xf @ xf.T
    n = xf.sum(1)
    union = n[:, None] + n[None, :] - inter
    with np.errstate(invalid="ignore", divide="ignore"):
        d = np.where(union > 0, 1.0 - inter / np.where(union > 0, union, 1.0), 0.0)
    np.fill_diagonal(d, 0.0)
    return d


def topological_dissimilarity(
    a: Layout, b: Layout, *, agent_radius: float = 0.2, grid: float = 0.05
) -> float:
    """Jaccard distance between the two layouts' inflated occupancy masks, in ``[0, 1]``.

    ``1 − |A ∩ B| / |A ∪ B|`` over the occupied cells of
    :func:`occupancy_masks` (0 when neither floor has obstacles).

    Parameters
    ----------
    a, b : Layout
    agent_radius : float
        Obstacle inflation, metres (default 0.2 m as in the paper).
    grid : float
        Cell size, metres.
    """
    masks, _ = occupancy_masks([a, b], agent_radius=agent_radius, grid=grid)
    return float(_jaccard_matrix(masks.reshape(2, -1))[0, 1])


# -- relational ---------------------------------------------------------------------

#: The relation vocabulary of :func:`relation_triples` and what makes each hold.
RELATIONS: dict[str, str] = {
    "next_to": "footprint gap <= 0.15 m (floor objects; symmetric)",
    "near": "footprint gap in (0.15, 1.0] m (floor objects; symmetric)",
    "facing": "the other's centre within 30° of the object's front (floor objects)",
    "on_top": "the object rests on the other (its surface is the other's id)",
    "at_wall": "back edge within 0.05 m of a wall and within 10° of parallel, facing in",
    "in_corner": "footprint within 0.05 m of two walls that are not parallel",
    "in_middle": "centre within 25 % of the room's extent from its centroid, on each axis",
    "near_window": "centre within 1.5 m of a window's centre",
    "near_door": "centre within 1.5 m of a door's centre",
    "on_wall": "the object hangs on a wall",
    "on_ceiling": "the object hangs from the ceiling",
}

Triple = tuple[str, str, str]


def relation_triples(
    layout: Layout, *, canonical: Canonical = canonical_label
) -> frozenset[Triple]:
    """The set of ``(category, relation, category)`` triples that hold in a layout.

    Relations are read off the geometry with the fixed vocabulary of
    :data:`RELATIONS`, never copied from the plan, so two layouts of one plan
    can differ. Relations to the room use ``"room"``, ``"window"`` or
    ``"door"`` as the second category; symmetric relations list their two
    categories in sorted order. As a set, two nightstands next to a bed give
    one triple.
    """
    ids = layout.ids()
    cat = {i: canonical(layout.plan.object(i).category) for i in ids}
    out: set[Triple] = set()
    for i in ids:
        s = layout.poses[i].surface
        if s == "ceiling":
            out.add((cat[i], "on_ceiling", "room"))
        elif s.startswith("wall"):
            out.add((cat[i], "on_wall", "room"))
        elif s != "floor" and s in cat:
            out.add((cat[i], "on_top", cat[s]))
    st = layout.state()
    n = st.n
    if n == 0:
        return frozenset(out)
    fids = st.ids
    room = st.room
    # pairwise relations among floor objects
    if n > 1:
        i, j = np.triu_indices(n, 1)
        gap = geo.box_gap(st.corners[i], st.corners[j])
        for rel, hit in (("next_to", gap <= 0.15), ("near", (gap > 0.15) & (gap <= 1.0))):
            for a, b in zip(i[hit], j[hit], strict=True):
                x, y = sorted((cat[fids[a]], cat[fids[b]]))
                out.add((x, rel, y))
        ii, jj = np.nonzero(~np.eye(n, dtype=bool))
        d = st.pos[jj] - st.pos[ii]
        cos = (d * st.front[ii]).sum(1) / np.maximum(np.linalg.norm(d, axis=1), 1e-12)
        for a, b in zip(ii[cos >= math.cos(math.radians(30))],
                        jj[cos >= math.cos(math.radians(30))], strict=True):
            out.add((cat[fids[a]], "facing", cat[fids[b]]))
    # relations to the room
    c = st.corners
    back = c[:, :2, :]
    dback, _ = room.wall_distance(back)  # (N, 2, W)
    tang = c[:, 1, :] - c[:, 0, :]
    tang /= np.maximum(np.linalg.norm(tang, axis=1, keepdims=True), 1e-12)
    par = np.abs(tang @ room.tangent.T) >= math.cos(math.radians(10))
    inward = st.front @ room.normal.T > 0
    at_wall = np.any(par & (dback.max(1) <= 0.05) & inward, axis=1)
    dall, _ = room.wall_distance(c)  # (N, 4, W)
    touch = dall.min(1) <= 0.05  # (N, W): some corner within 0.05 m of wall w
    cross = np.abs(room.tangent @ room.tangent.T) < math.cos(math.radians(45))
    in_corner = np.einsum("nw,wv,nv->n", touch.astype(float), cross.astype(float),
                          touch.astype(float)) > 0
    xmin, ymin, xmax, ymax = room.bounds
    ext = np.array([xmax - xmin, ymax - ymin])
    in_middle = np.all(np.abs(st.pos - room.centroid) <= 0.25 * ext, axis=1)
    flags = {"at_wall": (at_wall, "room"), "in_corner": (in_corner, "room"),
             "in_middle": (in_middle, "room")}
    for name, opening, label in (("near_window", room.windows, "window"),
                                 ("near_door", room.doors, "door")):
        if len(opening):
            dist = np.linalg.norm(st.pos[:, None, :] - opening.centre[None], axis=-1)
            flags[name] = ((dist <= 1.5).any(1), label)
    for rel, (hit, other) in flags.items():
        for k in np.nonzero(hit)[0]:
            out.add((cat[fids[k]], rel, other))
    return frozenset(out)


def jaccard_distance(a: Iterable[Any], b: Iterable[Any]) -> float:
    """``1 − |A ∩ B| / |A ∪ B|`` of two sets (0 when both are empty)."""
    sa, sb = set(a), set(b)
    union = len(sa | sb)
    return 1.0 - len(sa & sb) / union if union else 0.0


def relational_dissimilarity(
    a: Layout, b: Layout, *, canonical: Canonical = canonical_label
) -> float:
    """Jaccard distance between the relation triples of two layouts, in ``[0, 1]``.

    See :func:`relation_triples` for how the triples are read off the geometry.
    """
    return jaccard_distance(relation_triples(a, canonical=canonical),
                            relation_triples(b, canonical=canonical))


# -- sets of layouts ----------------------------------------------------------------


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
        return _jaccard_matrix(masks.reshape(k, -1))
    if metric == "relational":
        sets = [relation_triples(lay, **kwargs) for lay in layouts]
        vocab = {t: n for n, t in enumerate(sorted(set().union(*sets)))}
        x = np.zeros((k, len(vocab)), dtype=bool)
        for r, s in enumerate(sets):
            x[r, [vocab[t] for t in s]] = True
        return _jaccard_matrix(x)
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


# -- validity, rules, speed ---------------------------------------------------------


def _report(item: Layout | SampleReport) -> SampleReport:
    return item.report if isinstance(item, Layout) else item


def validity_rate(items: Iterable[Layout | SampleReport | bool]) -> float:
    """Fraction of samples that passed the deterministic checks, in ``[0, 1]``.

    Items are layouts, their reports, or booleans (NaN when there are none).
    """
    flags = [bool(x) if isinstance(x, bool | np.bool_) else _report(x).valid for x in items]
    return float(np.mean(flags)) if flags else float("nan")


def rule_satisfaction_rate(items: Iterable[Layout | SampleReport | float]) -> float:
    """Mean fraction of rule bindings met over samples, in ``[0, 1]`` (NaN when empty)."""
    vals = [float(x) if isinstance(x, int | float | np.floating) else
            _report(x).rule_satisfaction for x in items]
    return float(np.mean(vals)) if vals else float("nan")


def throughput(count: int, seconds: float, *, cores: int = 1) -> float:
    """Layouts per second per core: ``count / (seconds · cores)``.

    Parameters
    ----------
    count : int
        Layouts produced (e.g. valid ones).
    seconds : float
        Wall time they took on ``cores`` cores, or CPU time with ``cores=1``.
    cores : int
    """
    if seconds < 0 or cores < 1:
        raise ValueError(f"need seconds >= 0 and cores >= 1, got {seconds}, {cores}")
    return float(count / (seconds * cores)) if seconds > 0 else float("nan")


# -- confidence intervals -----------------------------------------------------------


@dataclass(frozen=True)
class ConfidenceInterval:
    """A statistic with its bootstrap confidence interval.

    Attributes
    ----------
    estimate : float
        The statistic on the original data.
    low, high : float
        Percentile interval bounds.
    level : float
        Coverage, e.g. 0.95.
    n_groups : int
        Number of plans (resampling units).
    """

    estimate: float
    low: float
    high: float
    level: float = 0.95
    n_groups: int = 0

    def to_dict(self) -> dict[str, float | int | None]:
        """Plain data; NaN becomes ``None`` so the result is valid JSON."""
        def f(v: float) -> float | None:
            return None if not np.isfinite(v) else float(v)
        return {"estimate": f(self.estimate), "low": f(self.low), "high": f(self.high),
                "level": self.level, "n_groups": self.n_groups}

    def __str__(self) -> str:
        return f"{self.estimate:.3g} [{self.low:.3g}, {self.high:.3g}]"


def bootstrap_ci(
    values_per_plan: Sequence[float] | Sequence[Sequence[float]],
    stat: Callable[..., Any] = np.mean,
    *,
    n_resamples: int = 10_000,
    seed: int | np.random.Generator = 0,
    level: float = 0.95,
    resample_within: bool = False,
) -> ConfidenceInterval:
    """Percentile bootstrap confidence interval, resampling plans with replacement.

    Parameters
    ----------
    values_per_plan : sequence of float, or sequence of sequences of float
        One value per plan, or the values of each plan's samples (pooled for
        the statistic). NaN values are dropped.
    stat : callable
        Statistic of a 1-D array; ``np.mean`` (default) and ``np.median``
        are computed for all resamples at once.
    n_resamples : int
        Bootstrap resamples (10,000 as in the paper).
    seed : int or numpy.random.Generator
    level : float
        Coverage in (0, 1).
    resample_within : bool
        Also resample each drawn plan's own values (two-stage bootstrap), so a
        handful of plans with many samples still gives an informative interval.

    Returns
    -------
    ConfidenceInterval
        NaN bounds when there are no values.
    """
    if not 0 < level < 1:
        raise ValueError(f"level must lie in (0, 1), got {level}")
    if n_resamples < 1 or n_resamples > 10_000_000:
        raise ValueError(f"n_resamples must lie in [1, 10_000_000], got {n_resamples}")
    groups = [np.atleast_1d(np.asarray(v, dtype=float)) for v in values_per_plan]
    groups = [g[np.isfinite(g)] for g in groups]
    groups = [g for g in groups if g.size]
    p = len(groups)
    if p == 0:
        nan = float("nan")
        return ConfidenceInterval(nan, nan, nan, level, 0)
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    estimate = float(stat(np.concatenate(groups)))
    lmax = max(g.size for g in groups)
    pad = np.full((p, lmax), np.nan)
    for k, g in enumerate(groups):
        pad[k, : g.size] = g
    sizes = np.array([g.size for g in groups])
    chunk = max(1, 4_000_000 // (p * lmax))  # resamples per block, bounding memory
    blocks = []
    for start in range(0, n_resamples, chunk):
        r = min(chunk, n_resamples - start)
        pick = rng.integers(0, p, size=(r, p))  # plans drawn per resample
        if resample_within:
            n_pick = sizes[pick][..., None]
            col = np.minimum((rng.random((r, p, lmax)) * n_pick).astype(int), n_pick - 1)
            vals = np.where(np.arange(lmax)[None, None, :] < n_pick, pad[pick[..., None], col],
                            np.nan)
        else:
            vals = pad[pick]  # (r, P, L)
        vals = vals.reshape(r, -1)
        if stat is np.mean:
            blocks.append(np.nanmean(vals, axis=1))
        elif stat is np.median:
            blocks.append(np.nanmedian(vals, axis=1))
        else:
            blocks.append(np.array([stat(row[np.isfinite(row)]) for row in vals], dtype=float))
    stats = np.concatenate(blocks)
    alpha = (1 - level) / 2
    low, high = np.quantile(stats, [alpha, 1 - alpha])
    return ConfidenceInterval(estimate, float(low), float(high), level, p)


# -- the Random baseline ------------------------------------------------------------


def random_layout(
    plan: Plan,
    seed: int | np.random.Generator = 0,
    *,
    max_tries: int = 200,
    reject: bool = True,
) -> Layout:
    """Random poses for every object of a plan: the paper's Random baseline.

    Floor objects, in plan order, get a uniform random centre and a random
    cardinal yaw (0, π/2, π, 3π/2); a draw is rejected while its footprint
    leaves the room or (with ``reject``) overlaps an object placed before it
    or a door's swing square, at most ``max_tries`` draws per object (the
    last draw is kept otherwise). No rule guides the placement: judge the
    result with :func:`forcelayout.validate.check_layout` and
    :attr:`Layout.rule_satisfaction` like any other sample. Objects on
    another object (``on_top``) land at a random point of the parent's top;
    wall objects on a random wall at a random height; ceiling objects at a
    random point under the ceiling.

    Parameters
    ----------
    plan : Plan
    seed : int or numpy.random.Generator
    max_tries : int
        Draws per floor object before giving up.
    reject : bool
        Reject draws that collide with earlier objects or door squares
        (``False``: only keep footprints inside the room).

    Returns
    -------
    Layout
        Its report is a fresh :class:`SampleReport` (not yet judged).
    """
    if max_tries < 1:
        raise ValueError(f"max_tries must be >= 1, got {max_tries}")
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    from forcelayout.geometry import RoomGeometry

    room = RoomGeometry.from_room(plan.room)
    xmin, ymin, xmax, ymax = room.bounds
    poses: dict[str, Pose] = {}
    parent: dict[str, tuple[str, str | None]] = {}
    for r in plan.rules:
        if r.rule in {"on_top", "on_wall", "on_wall_mid", "above", "on_ceiling"}:
            parent.setdefault(r.object, (r.rule, r.target))
    floor = [o for o in plan.objects if o.id not in parent]
    # boxes already on the floor (door swing squares first) as corners (M, 4, 2)
    dc, dr, df, dh = room.door_squares
    placed = (dc[:, None, :] + geo._LOCAL_CORNERS[None, :, :1] * (dr * dh[:, :1])[:, None, :]
              + geo._LOCAL_CORNERS[None, :, 1:] * (df * dh[:, 1:])[:, None, :])
    if not reject:
        placed = placed[:0]
    for o in floor:
        half = np.array([o.size[0], o.size[1]]) / 2
        yaw = rng.integers(0, 4, size=max_tries) * (math.pi / 2)
        draws = rng.random((max_tries, 2)) * [xmax - xmin, ymax - ymin] + [xmin, ymin]
        corners = geo.box_corners(draws, yaw, np.repeat(half[None], max_tries, axis=0))
        ok = room.contains(corners).all(axis=1)
        if reject and len(placed):
            sep = geo.box_separation(corners[:, None], placed[None])  # (T, M)
            ok &= (sep > 0).all(axis=1)
        k = int(np.argmax(ok)) if ok.any() else max_tries - 1
        poses[o.id] = Pose(float(draws[k, 0]), float(draws[k, 1]), float(yaw[k]))
        placed = np.concatenate([placed, corners[k: k + 1]]) if reject else placed
    rest = [o for o in plan.objects if o.id in parent]
    for _ in range(len(rest) + 1):  # parents before children; bounded by the count
        pending = [o for o in rest if o.id not in poses]
        if not pending:
            break
        for o in pending:
            rule, target = parent[o.id]
            if rule == "on_top":
                if target not in poses:
                    continue
                tp = poses[target]
                tsize = plan.object(target).size
                u = (rng.random(2) - 0.5) * np.maximum(np.array(tsize[:2]) - o.size[:2], 0.0)
                c, s = math.cos(tp.yaw), math.sin(tp.yaw)
                x = tp.x + c * u[0] - s * u[1]
                y = tp.y + s * u[0] + c * u[1]
                yaw = tp.yaw + float(rng.integers(0, 4)) * math.pi / 2
                poses[o.id] = Pose(x, y, yaw, tp.z + tsize[2], target)
            elif rule == "on_ceiling":
                draws = rng.random((max_tries, 2)) * [xmax - xmin, ymax - ymin] + [xmin, ymin]
                half = np.repeat(np.array(o.size[:2])[None] / 2, max_tries, axis=0)
                ok = room.contains(geo.box_corners(draws, np.zeros(max_tries), half)).all(1)
                k = int(np.argmax(ok)) if ok.any() else max_tries - 1
                poses[o.id] = Pose(float(draws[k, 0]), float(draws[k, 1]), 0.0,
                                   plan.room.height - o.size[2], "ceiling")
            else:  # on a wall, back to it
                w = int(rng.integers(0, room.n_walls))
                t = float(rng.uniform(min(o.size[0] / 2, room.length[w] / 2),
                                      max(room.length[w] - o.size[0] / 2, room.length[w] / 2)))
                xy = room.a[w] + room.tangent[w] * t + room.normal[w] * o.size[1] / 2
                n = room.normal[w]
                yaw = math.atan2(-n[0], n[1])  # front along the inward normal
                z = float(rng.uniform(0.0, max(plan.room.height - o.size[2], 0.0)))
                poses[o.id] = Pose(float(xy[0]), float(xy[1]), yaw, z, f"wall:{w}")
    return Layout(plan, poses, seed if isinstance(seed, int) else 0)
