"""Retrieval: the assets whose words (or pictures) best match an object's description.

score = cosine(query, asset) − ``size_weight`` × mean |sorted(plan size) − sorted(asset size)|

The query is the object's category and description (``"sofa: a three-seat
fabric settee"``); an asset's vector comes from its category, description
and tags (or, for image embedders, also its rendered views). The size term
is the peer Holodeck's size-compatibility penalty (10 × the mean difference
of the sorted bounding-box dimensions in metres on its 100× cosine scale),
here on the plain cosine scale: 0.1 per metre by default. Sorting the
dimensions makes it blind to the asset's orientation.

With a category given and ``category_filter`` on, only assets of that
category compete (categories compare case-, ``_``- and plural-blind); when
the library holds none, all assets do and the match says so. Ties are broken
by asset id, so results never depend on file order or platform.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from forcelayout.grounding.embedders import Embedder, get_embedder, normalise
from forcelayout.grounding.library import AssetLibrary

__all__ = ["AssetIndex", "Match", "retrieve", "query_text", "same_category",
           "DEFAULT_SIZE_WEIGHT"]

#: Score lost per metre of mean difference of sorted dimensions (cosine scale).
DEFAULT_SIZE_WEIGHT = 0.1


@dataclass(frozen=True)
class Match:
    """One candidate asset for a query.

    Attributes
    ----------
    asset : str
        The asset's id.
    score : float
        ``similarity - size_penalty``; what candidates are ranked by.
    similarity : float
        Cosine similarity of query and asset, in [-1, 1].
    size_penalty : float
        ``size_weight`` × the mean difference of sorted dimensions (0 without a size).
    category : str
        The asset's category.
    category_match : bool
        Whether the asset's category is the query's (False when no asset of
        the query's category existed, or no category was given).
    """

    asset: str
    score: float
    similarity: float
    size_penalty: float
    category: str
    category_match: bool

    def to_dict(self) -> dict[str, Any]:
        """As a plain dict (for JSON reports)."""
        return {"asset": self.asset, "score": round(self.score, 6),
                "similarity": round(self.similarity, 6),
                "size_penalty": round(self.size_penalty, 6), "category": self.category,
                "category_match": self.category_match}


_SPLIT = re.compile(r"[^a-z0-9]+")


def _norm_category(category: str) -> str:
    words = [w for w in _SPLIT.split(category.lower()) if w]
    words = [w[:-1] if len(w) > 3 and w.endswith("s") and not w.endswith("ss") else w
             for w in words]
    return " ".join(words)


def same_category(a: str, b: str) -> bool:
    """Whether two category names are the same one (case, ``_``/``-``/space and plural aside).

    Examples
    --------
    >>> same_category("Night_Stands", "night stand")
    True
    """
    return _norm_category(a) == _norm_category(b)


def query_text(category: str | None, description: str = "") -> str:
    """The text embedded for a plan object: ``"<category>: <description>"`` or either alone."""
    cat = (category or "").replace("_", " ").strip()
    desc = description.strip()
    if cat and desc:
        return f"{cat}: {desc}"
    return cat or desc


class AssetIndex:
    """A library's asset vectors for one embedder, cached beside the library.

    The vectors are stored in ``<library>/.forcelayout-index/`` as a numpy
    file keyed by the embedder's ``name`` and the hash of ``assets.json``'s
    entries (and of the mesh files, for embedders that look at meshes);
    either changing rebuilds it. A read-only library keeps them in memory.

    Parameters
    ----------
    library : AssetLibrary or path
    embedder : Embedder or str
        See :func:`forcelayout.grounding.get_embedder` (default ``"auto"``).
    cache : bool
        Read and write the cache file (default True).

    Attributes
    ----------
    embeddings : ndarray, shape (n_assets, d)
    from_cache : bool
        Whether the vectors were read from the cache file.
    """

    def __init__(self, library: AssetLibrary | str, embedder: Embedder | str = "auto", *,
                 cache: bool = True):
        self.library = library if isinstance(library, AssetLibrary) else \
            AssetLibrary.load(library)
        self.embedder = get_embedder(embedder)
        looks = hasattr(self.embedder, "embed_assets")
        meta_hash = self.library.metadata_hash(with_files=looks)
        key = self.embedder.name
        got = self.library.load_index(key, meta_hash) if cache else None
        self.from_cache = got is not None
        if got is None:
            if looks:
                got = self.embedder.embed_assets(self.library)  # type: ignore[attr-defined]
            else:
                got = self.embedder.embed([e.text for e in self.library.entries])
            got = normalise(got)
            if cache:
                self.library.save_index(key, meta_hash, got)
        self.embeddings = got
        self._categories = [_norm_category(e.category) for e in self.library.entries]
        self._ids = np.array(self.library.ids)
        self._extents: dict[str, np.ndarray] = {}
        self._queries: dict[str, np.ndarray] = {}

    def embed_queries(self, texts: Sequence[str]) -> np.ndarray:
        """Unit vectors of query texts, embedded in one batch and remembered for :meth:`search`."""
        new = [t for t in dict.fromkeys(texts) if t not in self._queries]
        if new:
            for t, v in zip(new, normalise(self.embedder.embed(new)), strict=True):
                self._queries[t] = v
        return np.stack([self._queries[t] for t in texts]) if len(texts) else \
            np.zeros((0, self.embeddings.shape[1]), dtype=np.float32)

    def extents(self, asset_id: str) -> np.ndarray:
        """Sorted extents of an asset (metres), cached."""
        if asset_id not in self._extents:
            self._extents[asset_id] = np.sort(self.library.extents(asset_id))
        return self._extents[asset_id]

    def search(self, description: str, *, category: str | None = None,
               size: Sequence[float] | None = None, k: int = 5,
               size_weight: float = DEFAULT_SIZE_WEIGHT, category_filter: bool = True,
               min_score: float | None = None) -> list[Match]:
        """The ``k`` best assets for an object, best first.

        Parameters
        ----------
        description : str
            The object's free-text description ("" to match on the category alone).
        category : str, optional
            The object's category: part of the query, and a filter (below).
        size : (w, d, h), optional
            The plan's size in metres, for the size penalty.
        k : int
            How many candidates.
        size_weight : float
            Score lost per metre of mean difference of sorted dimensions.
        category_filter : bool
            Keep only assets of ``category`` when the library has any.
        min_score : float, optional
            Drop candidates scoring below it.

        Returns
        -------
        list of Match
        """
        if k < 1:
            raise ValueError(f"k must be at least 1, got {k}")
        text = query_text(category, description)
        if not text:
            raise ValueError("a query needs a category or a description")
        q = self.embed_queries([text])[0]
        sim = self.embeddings @ q
        rows = np.arange(len(sim))
        matched = np.zeros(len(sim), dtype=bool)
        if category:
            want = _norm_category(category)
            matched = np.array([c == want for c in self._categories], dtype=bool)
            if category_filter and matched.any():
                rows = rows[matched]
        penalty = np.zeros(len(sim))
        if size is not None and size_weight:
            s = np.sort(np.asarray(size, dtype=float))
            for r in rows:
                penalty[r] = size_weight * float(np.mean(np.abs(s - self.extents(self._ids[r]))))
        score = sim - penalty
        # rank by score (rounded: float noise never reorders), ties by asset id
        order = sorted(rows.tolist(), key=lambda r: (-round(float(score[r]), 6), self._ids[r]))
        out = []
        for r in order:
            if min_score is not None and score[r] < min_score:
                break
            e = self.library.entries[r]
            out.append(Match(e.id, float(score[r]), float(sim[r]), float(penalty[r]),
                             e.category, bool(matched[r])))
            if len(out) == k:
                break
        return out


def retrieve(library: AssetLibrary | str, description: str, *, category: str | None = None,
             size: Sequence[float] | None = None, k: int = 5,
             embedder: Embedder | str = "auto", **kwargs: Any) -> list[Match]:
    """One-off retrieval: build (or load) the index and search it (see :meth:`AssetIndex.search`).

    Examples
    --------
    >>> retrieve("examples/assets", "a three-seat fabric settee", k=1)  # doctest: +SKIP
    [Match(asset='sofa_3seat', score=0.62, ...)]
    """
    return AssetIndex(library, embedder).search(description, category=category, size=size,
                                                k=k, **kwargs)
