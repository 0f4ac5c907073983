"""Jaccard distances between sets, and between the rows of a boolean matrix."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import numpy as np

__all__ = ["jaccard_distance"]


def jaccard_distance(a: Iterable[Any], b: Iterable[Any]) -> float:
    """``1 − |A ∩ B| / |A ∪ B|`` of two sets (0 when both are empty)."""
    sa, sb = set(a), set(b)
    union = len(sa | sb)
    return 1.0 - len(sa & sb) / union if union else 0.0


def jaccard_matrix(x: np.ndarray) -> np.ndarray:
    """Pairwise Jaccard distances between rows of a boolean matrix (K, M), shape (K, K).

    Two empty rows are at distance 0, as are a row and itself.
    """
    xf = x.astype(np.float64)
    inter = xf @ xf.T
    n = xf.sum(1)
    union = n[:, None] + n[None, :] - inter
    with np.errstate(invalid="ignore", divide="ignore"):
        d = np.where(union > 0, 1.0 - inter / np.where(union > 0, union, 1.0), 0.0)
    np.fill_diagonal(d, 0.0)
    return d
