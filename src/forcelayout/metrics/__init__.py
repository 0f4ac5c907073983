"""The paper's evaluation: diversity, validity and speed of generated layouts.

Three dissimilarities between two layouts, each in ``[0, 1]`` (0: the same,
1: nothing in common), plus rates, throughput and bootstrap confidence
intervals. Everything here is plain numpy/scipy/shapely and needs no extra.
One module per concept:

* :mod:`~forcelayout.metrics.geometric` — :func:`geometric_dissimilarity`:
  optimal per-category matching of objects (Hungarian algorithm) with a cost
  mixing position, size and yaw, and a fixed penalty for objects without a
  partner.
* :mod:`~forcelayout.metrics.topological` — :func:`topological_dissimilarity`:
  Jaccard distance between the occupancy masks of the two floors, obstacles
  inflated by the agent radius (0.2 m).
* :mod:`~forcelayout.metrics.relational` — :func:`relational_dissimilarity`:
  Jaccard distance between the sets of relation triples
  ``(category, rule, category)``, judged by every registered rule that
  declares ``relation = True``.
* :mod:`~forcelayout.metrics.sets` — :func:`pairwise`, :func:`intra_plan`
  (all pairs of layouts of one plan), :func:`inter_plan` (pairs of
  layouts of different plans) and :func:`still_objects` (objects that stand
  in one spot in every layout of a set).
* :mod:`~forcelayout.metrics.stats` — :func:`validity_rate`,
  :func:`rule_satisfaction_rate`, :func:`throughput`, :func:`bootstrap_ci`.
* :mod:`~forcelayout.metrics.agreement` — :func:`judge_agreement`: how a
  plausibility judge agrees with human labels (Cohen's κ, raw agreement;
  Fleiss' κ among annotators), as the paper calibrates its VLM judge.
* :mod:`~forcelayout.metrics.labels` — :func:`canonical_label`: object
  categories are compared after it (``"Couch"`` and ``"sofa_2"`` are the
  same category); pass ``canonical=`` your own callable (e.g. one backed by
  a text-embedding model) to change that.

Baselines to compare against (random placement, rule-aware rejection
sampling) live in :mod:`forcelayout.baselines`.

Units: metres, radians (CCW), seconds. See ``docs/evaluating.md`` for the
formulas.

Examples
--------
>>> import forcelayout as fl
>>> from forcelayout import metrics
>>> from forcelayout.baselines import random_layout
>>> plan = fl.examples.load_example("bedroom")
>>> a, b = random_layout(plan, 0), random_layout(plan, 1)
>>> 0.0 <= metrics.geometric_dissimilarity(a, b) <= 1.0
True
>>> metrics.geometric_dissimilarity(a, a)
0.0
"""

from __future__ import annotations

from typing import Any

from forcelayout.metrics.agreement import (
    Agreement,
    cohen_kappa,
    fleiss_kappa,
    judge_agreement,
    majority_vote,
    raw_agreement,
)
from forcelayout.metrics.geometric import geometric_dissimilarity
from forcelayout.metrics.jaccard import jaccard_distance
from forcelayout.metrics.labels import SYNONYMS, canonical_label
from forcelayout.metrics.relational import (
    relation_rules,
    relation_triples,
    relational_dissimilarity,
)
from forcelayout.metrics.sets import inter_plan, intra_plan, pairwise, still_objects
from forcelayout.metrics.stats import (
    ConfidenceInterval,
    bootstrap_ci,
    rule_satisfaction_rate,
    throughput,
    validity_rate,
)
from forcelayout.metrics.topological import occupancy_masks, topological_dissimilarity

__all__ = [
    "canonical_label",
    "SYNONYMS",
    "geometric_dissimilarity",
    "occupancy_masks",
    "topological_dissimilarity",
    "RELATIONS",
    "relation_rules",
    "relation_triples",
    "relational_dissimilarity",
    "jaccard_distance",
    "pairwise",
    "intra_plan",
    "inter_plan",
    "still_objects",
    "validity_rate",
    "rule_satisfaction_rate",
    "throughput",
    "ConfidenceInterval",
    "bootstrap_ci",
    "raw_agreement",
    "cohen_kappa",
    "fleiss_kappa",
    "majority_vote",
    "Agreement",
    "judge_agreement",
]


def __getattr__(name: str) -> Any:
    # RELATIONS is read from the registry when asked for, so plugins registered later count
    if name == "RELATIONS":
        return relation_rules()
    if name == "random_layout":  # moved; kept working for code written against 0.1
        import warnings

        from forcelayout.baselines import random_layout

        warnings.warn("forcelayout.metrics.random_layout moved to "
                      "forcelayout.baselines.random_layout", DeprecationWarning, stacklevel=2)
        return random_layout
    raise AttributeError(f"module 'forcelayout.metrics' has no attribute {name!r}")
