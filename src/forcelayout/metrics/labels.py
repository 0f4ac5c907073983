"""Object categories for the metrics: label canonicalisation and its synonym table.

Metrics compare objects of the same *category*, not the same id, so two
nightstands that swap places are the same layout. :func:`canonical_label`
folds spellings (``"Couch_2"``, ``"sofas"``) into one category; every metric
takes ``canonical=`` to use another callable (e.g. one backed by a
text-embedding model).
"""

from __future__ import annotations

import re
from collections.abc import Callable

__all__ = ["Canonical", "SYNONYMS", "canonical_label"]

#: A canonicaliser: maps an object's category label to the label metrics compare.
Canonical = Callable[[str], str]

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
