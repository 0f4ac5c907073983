"""Agreement between raters: a plausibility judge against human labels, and humans among themselves.

The paper calibrates its VLM judge on 200 scenes labelled by three people:
the judge agrees with the annotators' majority vote with Cohen's
κ = 0.49 (80.5 % raw agreement), and the annotators agree among themselves
with Fleiss' κ = 0.22. :func:`judge_agreement` computes the same three
figures for your judge and your labels; the plain helpers
(:func:`cohen_kappa`, :func:`raw_agreement`, :func:`fleiss_kappa`,
:func:`majority_vote`) work on any categorical labels (bools, strings,
ints).

Definitions (Cohen 1960; Fleiss 1971):

* raw agreement ``p_o``: fraction of items given the same label;
* Cohen's κ of two raters: ``(p_o - p_e) / (1 - p_e)``, where ``p_e`` =
  Σ over labels of the product of the two raters' label frequencies;
* Fleiss' κ of ``n`` raters per item: ``(P̄ - P̄_e) / (1 - P̄_e)``, where
  ``P̄`` is the mean over items of ``(Σ_j n_ij² - n) / (n (n - 1))``
  (``n_ij``: raters giving item i label j) and ``P̄_e = Σ_j p_j²`` with
  ``p_j`` the share of all ratings that are label j.

A κ whose chance agreement is 1 (every rating is the same label) is
undefined and returned as NaN.

Examples
--------
>>> from forcelayout.metrics import cohen_kappa, fleiss_kappa, judge_agreement
>>> judge = [True, True, False, False, True, False, True, True, False, True]
>>> human = [True, False, False, False, True, True, True, True, False, True]
>>> round(cohen_kappa(judge, human), 4)
0.5833
>>> round(fleiss_kappa([[1, 1, 1], [1, 1, 0], [0, 0, 0]]), 4)
0.55
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Hashable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = [
    "raw_agreement",
    "cohen_kappa",
    "fleiss_kappa",
    "majority_vote",
    "Agreement",
    "judge_agreement",
]


def _pair(a: Sequence[Hashable], b: Sequence[Hashable]) -> tuple[list, list]:
    a, b = list(a), list(b)
    if len(a) != len(b):
        raise ValueError(f"the two raters label different numbers of items ({len(a)} and "
                         f"{len(b)}); give one label per item to each")
    if not a:
        raise ValueError("no items: give at least one label per rater")
    return a, b


def raw_agreement(rater_a: Sequence[Hashable], rater_b: Sequence[Hashable]) -> float:
    """Fraction of items on which two raters give the same label, in ``[0, 1]``.

    Parameters
    ----------
    rater_a, rater_b : sequence of hashable
        One label per item each (bools, strings, ints, ...), in the same item order.

    Returns
    -------
    float
    """
    a, b = _pair(rater_a, rater_b)
    return sum(x == y for x, y in zip(a, b, strict=True)) / len(a)


def cohen_kappa(rater_a: Sequence[Hashable], rater_b: Sequence[Hashable]) -> float:
    """Cohen's κ of two raters: agreement beyond chance, in ``[-1, 1]``.

    Parameters
    ----------
    rater_a, rater_b : sequence of hashable
        One label per item each, in the same item order.

    Returns
    -------
    float
        ``(p_o - p_e) / (1 - p_e)``; NaN when ``p_e`` is 1 (both raters use
        one and the same label for every item, so chance explains everything).

    Raises
    ------
    ValueError
        When the raters label different numbers of items, or none.

    Examples
    --------
    Yes/yes 20, yes/no 5, no/yes 10, no/no 15 (50 items): ``p_o = 0.7``,
    ``p_e = 0.5 · 0.6 + 0.5 · 0.4 = 0.5``, κ = 0.4.

    >>> a = [1] * 25 + [0] * 25
    >>> b = [1] * 20 + [0] * 5 + [1] * 10 + [0] * 15
    >>> round(cohen_kappa(a, b), 6)
    0.4
    """
    a, b = _pair(rater_a, rater_b)
    n = len(a)
    po = sum(x == y for x, y in zip(a, b, strict=True)) / n
    ca, cb = Counter(a), Counter(b)
    pe = sum(ca[k] * cb.get(k, 0) for k in ca) / (n * n)
    if pe >= 1.0 - 1e-12:
        return float("nan")
    return float((po - pe) / (1.0 - pe))


def _counts(ratings: Any, counts: bool) -> np.ndarray:
    if counts:
        table = np.asarray(ratings, dtype=float)
        if table.ndim != 2 or not table.size:
            raise ValueError("counts must be a table of items x labels")
        if (table < 0).any() or not np.allclose(table, np.round(table)):
            raise ValueError("counts must be whole numbers >= 0")
        return table
    rows = [list(r) for r in ratings]
    if not rows:
        raise ValueError("no items: give one row of labels per item")
    labels = sorted({x for r in rows for x in r}, key=repr)
    col = {x: j for j, x in enumerate(labels)}
    table = np.zeros((len(rows), len(labels)))
    for i, r in enumerate(rows):
        for x in r:
            table[i, col[x]] += 1
    return table


def fleiss_kappa(ratings: Any, *, counts: bool = False) -> float:
    """Fleiss' κ: agreement among a fixed number of raters per item, beyond chance.

    Parameters
    ----------
    ratings : 2D array-like
        Items x raters: ``ratings[i]`` holds every rater's label for item i
        (any hashable labels). With ``counts=True``, items x labels instead:
        ``ratings[i][j]`` raters gave item i label j.
    counts : bool
        Whether ``ratings`` is a table of counts.

    Returns
    -------
    float
        NaN when every rating is the same label.

    Raises
    ------
    ValueError
        When items have different numbers of ratings, or fewer than two.

    Examples
    --------
    Three raters, three items: all say yes; two yes, one no; all say no.
    ``P̄ = (1 + 1/3 + 1) / 3 = 7/9``, ``p_yes = 5/9``, ``P̄_e = 41/81``, κ = 0.55.

    >>> round(fleiss_kappa([[1, 1, 1], [1, 1, 0], [0, 0, 0]]), 6)
    0.55
    """
    table = _counts(ratings, counts)
    per_item = table.sum(axis=1)
    n = per_item[0]
    if not np.allclose(per_item, n):
        raise ValueError("every item needs the same number of ratings (Fleiss' κ); items "
                         f"have between {per_item.min():g} and {per_item.max():g}")
    if n < 2:
        raise ValueError("Fleiss' κ needs at least two ratings per item")
    p_item = ((table ** 2).sum(axis=1) - n) / (n * (n - 1))
    p_bar = float(p_item.mean())
    p_label = table.sum(axis=0) / table.sum()
    pe = float((p_label ** 2).sum())
    if pe >= 1.0 - 1e-12:
        return float("nan")
    return (p_bar - pe) / (1.0 - pe)


def majority_vote(ratings: Any, *, tie: Hashable | None = None) -> list[Hashable]:
    """The label most raters gave each item.

    Parameters
    ----------
    ratings : 2D array-like
        Items x raters, labels as in :func:`fleiss_kappa`.
    tie : hashable, optional
        The label of an item whose top labels tie (e.g. ``False``: "not
        plausible unless most say so"). Without it a tie raises.

    Returns
    -------
    list
        One label per item.

    Raises
    ------
    ValueError
        On a tie when ``tie`` is not given (use an odd number of raters for
        yes/no labels).
    """
    out: list[Hashable] = []
    for i, row in enumerate(ratings):
        ranked = Counter(list(row)).most_common()
        if not ranked:
            raise ValueError(f"item {i} has no ratings")
        if len(ranked) > 1 and ranked[0][1] == ranked[1][1]:
            if tie is None:
                top = sorted((repr(k) for k, c in ranked if c == ranked[0][1]))
                raise ValueError(f"item {i}: the labels {', '.join(top)} tie; give tie= the "
                                 "label to use, or an odd number of raters")
            out.append(tie)
        else:
            out.append(ranked[0][0])
    return out


@dataclass(frozen=True)
class Agreement:
    """How a judge agrees with human labels (the paper's calibration figures).

    Attributes
    ----------
    items : int
        Items compared (those the judge gave a label).
    unjudged : int
        Items left out because the judge gave no label (``None``).
    cohen_kappa : float
        Judge vs the human label (the majority vote when several annotators).
    raw_agreement : float
        Fraction of items where the judge gives the human label.
    fleiss_kappa : float or None
        Among the annotators, over all items; None with one label per item.
    annotators : int
        Labels per item.
    """

    items: int
    unjudged: int
    cohen_kappa: float
    raw_agreement: float
    fleiss_kappa: float | None
    annotators: int

    def to_dict(self) -> dict[str, Any]:
        """The figures as a JSON-ready dict."""
        return {"items": self.items, "unjudged": self.unjudged,
                "cohen_kappa": self.cohen_kappa, "raw_agreement": self.raw_agreement,
                "fleiss_kappa": self.fleiss_kappa, "annotators": self.annotators}

    def __str__(self) -> str:
        text = (f"judge vs humans on {self.items} items: Cohen's kappa {self.cohen_kappa:.2f}, "
                f"raw agreement {self.raw_agreement:.1%}")
        if self.fleiss_kappa is not None:
            text += (f"; among the {self.annotators} annotators: Fleiss' kappa "
                     f"{self.fleiss_kappa:.2f}")
        if self.unjudged:
            text += f" ({self.unjudged} unjudged left out)"
        return text


def judge_agreement(
    judge: Sequence[Hashable | None], humans: Sequence[Any], *, tie: Hashable | None = None,
) -> Agreement:
    """Agreement of a judge's labels with human labels, as the paper reports it.

    Parameters
    ----------
    judge : sequence
        The judge's label per item (e.g. ``verdict.plausible``); ``None`` for
        an item it did not judge (left out of every figure, counted).
    humans : sequence
        Per item, either one label or a sequence of several annotators'
        labels (the same number for every item). With several, the judge is
        compared with their :func:`majority_vote` and Fleiss' κ among them
        is computed over all items.
    tie : hashable, optional
        Passed to :func:`majority_vote`.

    Returns
    -------
    Agreement

    Examples
    --------
    >>> from forcelayout.metrics import judge_agreement
    >>> a = judge_agreement([True, False, True, None],
    ...                     [[True, True, False], [False, False, True], [True, True, True],
    ...                      [False, False, False]])
    >>> a.items, a.unjudged, a.raw_agreement
    (3, 1, 1.0)
    """
    judge = list(judge)
    humans = [list(h) if isinstance(h, Sequence | np.ndarray) and not isinstance(h, str) else h
              for h in humans]
    if len(judge) != len(humans):
        raise ValueError(f"{len(judge)} judge labels but {len(humans)} human labels; give one "
                         "of each per item")
    several = bool(humans) and all(isinstance(h, list) for h in humans)
    if several:
        human_label = majority_vote(humans, tie=tie)
        widths = {len(h) for h in humans}
        annotators = widths.pop() if len(widths) == 1 else -1
        if annotators < 0:
            raise ValueError("every item needs the same number of annotator labels")
        fleiss: float | None = fleiss_kappa(humans) if annotators >= 2 else None
    else:
        human_label, annotators, fleiss = humans, 1, None
    kept = [(j, h) for j, h in zip(judge, human_label, strict=True) if j is not None]
    if not kept:
        raise ValueError("the judge labelled no item; nothing to compare")
    a = [j for j, _ in kept]
    b = [h for _, h in kept]
    return Agreement(items=len(kept), unjudged=len(judge) - len(kept),
                     cohen_kappa=cohen_kappa(a, b), raw_agreement=raw_agreement(a, b),
                     fleiss_kappa=fleiss, annotators=annotators)
