"""Agreement helpers (forcelayout.metrics.agreement) against hand-computed values."""

from __future__ import annotations

import math

import numpy as np
import pytest

from forcelayout.metrics import (
    cohen_kappa,
    fleiss_kappa,
    judge_agreement,
    majority_vote,
    raw_agreement,
)

# Fleiss (1971) as tabulated on Wikipedia: 10 items, 14 raters, 5 labels; kappa 0.210.
FLEISS_TABLE = [[0, 0, 0, 0, 14], [0, 2, 6, 4, 2], [0, 0, 3, 5, 6], [0, 3, 9, 2, 0],
                [2, 2, 8, 1, 1], [7, 7, 0, 0, 0], [3, 2, 6, 3, 0], [2, 5, 3, 2, 2],
                [6, 5, 2, 1, 0], [0, 2, 2, 3, 7]]


def test_cohen_kappa_of_the_textbook_table():
    # yes/yes 20, yes/no 5, no/yes 10, no/no 15: p_o 0.7, p_e 0.5*0.6 + 0.5*0.4 = 0.5
    a = ["yes"] * 25 + ["no"] * 25
    b = ["yes"] * 20 + ["no"] * 5 + ["yes"] * 10 + ["no"] * 15
    assert raw_agreement(a, b) == pytest.approx(0.7)
    assert cohen_kappa(a, b) == pytest.approx(0.4)
    assert cohen_kappa(b, a) == pytest.approx(0.4)  # symmetric


def test_cohen_kappa_of_ten_items():
    # p_o 8/10; both raters 6 yes / 4 no: p_e 0.52; kappa 0.28 / 0.48
    a = [1, 1, 0, 0, 1, 0, 1, 1, 0, 1]
    b = [1, 0, 0, 0, 1, 1, 1, 1, 0, 1]
    assert raw_agreement(a, b) == pytest.approx(0.8)
    assert cohen_kappa(a, b) == pytest.approx(0.28 / 0.48)


def test_cohen_kappa_extremes():
    a = [True, False, True, False]
    assert cohen_kappa(a, a) == pytest.approx(1.0)
    assert cohen_kappa(a, [not x for x in a]) == pytest.approx(-1.0)
    assert math.isnan(cohen_kappa([True] * 3, [True] * 3))  # chance explains everything
    # labels one rater never uses count as frequency 0
    assert cohen_kappa(["a", "b"], ["a", "c"]) == pytest.approx((0.5 - 0.25) / 0.75)


def test_unequal_or_empty_raters_are_refused():
    with pytest.raises(ValueError, match="different numbers of items"):
        cohen_kappa([1, 0], [1])
    with pytest.raises(ValueError, match="no items"):
        raw_agreement([], [])


def test_fleiss_kappa_of_the_published_table():
    assert fleiss_kappa(FLEISS_TABLE, counts=True) == pytest.approx(0.2099, abs=1e-4)


def test_fleiss_kappa_from_labels_by_hand():
    # P_i = 1, 1/3, 1 -> P = 7/9; p_yes 5/9, p_no 4/9 -> P_e 41/81; kappa 22/40
    assert fleiss_kappa([[1, 1, 1], [1, 1, 0], [0, 0, 0]]) == pytest.approx(0.55)
    assert fleiss_kappa(np.array([[True, True], [False, False]])) == pytest.approx(1.0)
    assert math.isnan(fleiss_kappa([["y", "y"], ["y", "y"]]))


def test_fleiss_kappa_of_labels_equals_that_of_their_counts():
    rng = np.random.default_rng(3)
    labels = rng.integers(0, 3, size=(30, 4))
    table = np.stack([(labels == j).sum(axis=1) for j in range(3)], axis=1)
    assert fleiss_kappa(labels) == pytest.approx(fleiss_kappa(table, counts=True))


def test_fleiss_kappa_needs_equal_ratings_per_item():
    with pytest.raises(ValueError, match="same number of ratings"):
        fleiss_kappa([[1, 1, 0], [1, 0]])
    with pytest.raises(ValueError, match="at least two"):
        fleiss_kappa([[1], [0]])


def test_majority_vote_and_ties():
    assert majority_vote([[1, 1, 0], [0, 0, 1], ["a", "b", "b"]]) == [1, 0, "b"]
    with pytest.raises(ValueError, match="tie"):
        majority_vote([[True, False]])
    assert majority_vote([[True, False]], tie=False) == [False]


def test_judge_agreement_with_three_annotators():
    humans = [[True, True, False], [False, False, True], [True, True, True],
              [False, True, False], [True, False, True]]
    majority = [True, False, True, False, True]
    judge = [True, True, True, False, None]
    a = judge_agreement(judge, humans)
    assert (a.items, a.unjudged, a.annotators) == (4, 1, 3)
    assert a.raw_agreement == pytest.approx(raw_agreement(judge[:4], majority[:4])) == 0.75
    assert a.cohen_kappa == pytest.approx(cohen_kappa(judge[:4], majority[:4]))
    assert a.fleiss_kappa == pytest.approx(fleiss_kappa(humans))  # over all items
    assert "Cohen's kappa" in str(a) and "1 unjudged" in str(a)
    assert a.to_dict()["items"] == 4


def test_judge_agreement_with_one_label_per_item():
    a = judge_agreement([True, False, True], np.array([True, False, False]))
    assert a.fleiss_kappa is None and a.annotators == 1
    assert a.raw_agreement == pytest.approx(2 / 3)
    with pytest.raises(ValueError, match="one of each"):
        judge_agreement([True], [True, False])
    with pytest.raises(ValueError, match="no item"):
        judge_agreement([None], [True])
