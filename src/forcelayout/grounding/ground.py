"""Grounding a plan: each object gets the best asset, scaled isotropically to the plan's size.

For each object of the plan: retrieve candidates (:class:`AssetIndex`), take the
best one if it scores at least ``min_score`` (else the object stays a box and
the report says why), scale its mesh uniformly, and write back into the plan

- ``asset``: the asset's id, and
- ``size``: the scaled mesh's bounding box ``[w, d, h]`` in the object's frame
  (front +y), so the solver, the checks and the pictures use the real
  footprint;
- ``footprint`` (only with ``hull=True``): a convex polygon around the scaled
  mesh's outline seen from above (at most 8 corners: its extent along x, y
  and both diagonals), which the solver uses as the object's Box2D fixture.

Which dimension drives the scale (``scale_by``):

``"fit"`` (default)
    the largest uniform scale at which the mesh fits inside the plan's
    ``[w, d, h]`` box: the dimension with the smallest plan/asset ratio is met
    exactly, the others come out at most as large as planned. A plan that is
    feasible with its boxes stays feasible.
``"width"``, ``"depth"``, ``"height"``
    that dimension is met exactly; the others follow the asset's proportions
    (and may exceed the plan's).
``"longest"``
    the longer horizontal side (width or depth) is met exactly.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from forcelayout.grounding.embedders import Embedder
from forcelayout.grounding.library import AssetLibrary, AssetLibraryError
from forcelayout.grounding.retrieval import DEFAULT_SIZE_WEIGHT, AssetIndex, Match, query_text
from forcelayout.plan import Plan
from forcelayout.sources import load_plan

__all__ = ["ground_plan", "GroundingReport", "ObjectGrounding", "scale_for", "hull_footprint",
           "scene_assets", "SCALE_BY", "DEFAULT_MIN_SCORE"]

#: Accepted values of ``scale_by``.
SCALE_BY = ("fit", "width", "depth", "height", "longest")
#: Default ``min_score``: below it an object stays a box.
DEFAULT_MIN_SCORE = 0.2


@dataclass
class ObjectGrounding:
    """What grounding did with one object.

    Attributes
    ----------
    object : str
        The object's id.
    query : str
        The text that was embedded.
    asset : str or None
        The chosen asset's id; None when the object stays a box.
    score : float or None
        The chosen (or best rejected) candidate's score.
    candidates : list of Match
        The top-k candidates, best first.
    planned_size, size : tuple of float
        ``[w, d, h]`` before and after (the scaled mesh's box), metres.
    scale : float or None
        The uniform factor applied to the asset (in metres).
    note : str
        Why the object stays a box, or "" when matched.
    """

    object: str
    query: str
    asset: str | None
    score: float | None
    candidates: list[Match]
    planned_size: tuple[float, float, float]
    size: tuple[float, float, float]
    scale: float | None = None
    note: str = ""

    def to_dict(self) -> dict[str, Any]:
        """As a plain dict (for JSON reports)."""
        return {"object": self.object, "query": self.query, "asset": self.asset,
                "score": None if self.score is None else round(self.score, 6),
                "planned_size": list(self.planned_size), "size": list(self.size),
                "scale": self.scale, "note": self.note,
                "candidates": [m.to_dict() for m in self.candidates]}

    def line(self) -> str:
        """One line for people: ``id -> asset (score, size)`` or why it stays a box."""
        if self.asset is None:
            return f"{self.object}: box ({self.note})"
        w, d, h = self.size
        pw, pd, ph = self.planned_size
        return (f"{self.object} -> {self.asset}  score {self.score:.3f}  size {w:.2f} x {d:.2f} "
                f"x {h:.2f} m (planned {pw:g} x {pd:g} x {ph:g}, scale {self.scale:.3f})")


@dataclass
class GroundingReport:
    """The grounded plan and what happened to each object.

    Attributes
    ----------
    plan : Plan
        The grounded plan (a new object; the input is unchanged).
    objects : list of ObjectGrounding
        In plan order.
    embedder : str
        The embedder's name.
    seconds : float
        Wall time of grounding (index building included).
    index_from_cache : bool
        Whether the asset vectors came from the cache.
    """

    plan: Plan
    objects: list[ObjectGrounding]
    embedder: str
    seconds: float
    index_from_cache: bool = False
    settings: dict[str, Any] = field(default_factory=dict)

    @property
    def matched(self) -> list[str]:
        """Ids of objects that got an asset."""
        return [o.object for o in self.objects if o.asset is not None]

    @property
    def boxes(self) -> list[str]:
        """Ids of objects that stay boxes."""
        return [o.object for o in self.objects if o.asset is None]

    def to_dict(self) -> dict[str, Any]:
        """As a plain dict (for JSON reports)."""
        return {"plan": self.plan.name, "embedder": self.embedder,
                "seconds": round(self.seconds, 4), "index_from_cache": self.index_from_cache,
                "settings": self.settings, "matched": len(self.matched),
                "boxes": len(self.boxes), "objects": [o.to_dict() for o in self.objects]}

    def lines(self) -> list[str]:
        """One line per object (see :meth:`ObjectGrounding.line`)."""
        return [o.line() for o in self.objects]


def scale_for(planned: Iterable[float], extents: Iterable[float], scale_by: str = "fit") -> float:
    """The uniform factor taking an asset of ``extents`` to the plan's ``planned`` size.

    See the module docstring for ``scale_by``.

    Examples
    --------
    >>> scale_for([2.0, 0.9, 0.8], [1.0, 0.5, 0.5])          # depth drives: 0.9 / 0.5
    1.6
    >>> scale_for([2.0, 0.9, 0.8], [1.0, 0.5, 0.5], "width")
    2.0
    """
    p = np.asarray(list(planned), dtype=float)
    e = np.maximum(np.asarray(list(extents), dtype=float), 1e-9)
    if scale_by == "fit":
        return float(np.min(p / e))
    if scale_by in ("width", "depth", "height"):
        k = ("width", "depth", "height").index(scale_by)
        return float(p[k] / e[k])
    if scale_by == "longest":
        k = 0 if p[0] >= p[1] else 1
        return float(p[k] / e[k])
    raise ValueError(f"unknown scale_by {scale_by!r}; use one of {', '.join(SCALE_BY)}")


def hull_footprint(points: np.ndarray, size: Iterable[float]) -> list[tuple[float, float]] | None:
    """A convex polygon (≤ 8 corners, CCW) around 2D ``points``, inside the ``[w, d]`` box.

    It is the intersection of the points' extents along x, y and the two
    diagonals (an "8-DOP"): it contains every point, so a fixture of this
    shape never lets anything into the mesh's outline. Returns None when it
    is (almost) the whole rectangle — the rectangle is then the better fixture.
    """
    import shapely

    p = np.asarray(points, dtype=float)[:, :2]
    w, d = (float(v) for v in list(size)[:2])
    s = math.sqrt(0.5)
    u, v = (p[:, 0] + p[:, 1]) * s, (p[:, 0] - p[:, 1]) * s
    diag = shapely.Polygon([((a + b) * s, (a - b) * s) for a, b in
                            ((u.min(), v.min()), (u.max(), v.min()), (u.max(), v.max()),
                             (u.min(), v.max()))])
    rect = shapely.box(-w / 2, -d / 2, w / 2, d / 2)
    poly = shapely.orient_polygons(rect.intersection(diag)) if hasattr(
        shapely, "orient_polygons") else shapely.geometry.polygon.orient(rect.intersection(diag))
    if poly.is_empty or poly.area >= 0.995 * rect.area:
        return None
    poly = poly.simplify(1e-6)
    xy = np.asarray(poly.exterior.coords)[:-1]
    xy = np.clip(xy, [-w / 2, -d / 2], [w / 2, d / 2])
    return [(float(round(x, 6)), float(round(y, 6))) for x, y in xy]


def ground_plan(
    plan: Plan | str | Any,
    library: AssetLibrary | str | Any,
    *,
    embedder: Embedder | str = "auto",
    k: int = 5,
    min_score: float = DEFAULT_MIN_SCORE,
    size_weight: float = DEFAULT_SIZE_WEIGHT,
    category_filter: bool = True,
    scale_by: str = "fit",
    hull: bool = False,
    index: AssetIndex | None = None,
) -> GroundingReport:
    """Give each object of a plan its best asset, scaled to the plan's size.

    Parameters
    ----------
    plan : Plan, path, dict or bundled plan name
    library : AssetLibrary or path of its folder
    embedder : Embedder or str
        ``"auto"`` (MiniLM when installed, else lexical), ``"minilm"``,
        ``"lexical"``, ``"clip"`` or your own (see
        :mod:`forcelayout.grounding.embedders`).
    k : int
        Candidates kept per object (in the report).
    min_score : float
        An object whose best candidate scores less stays a box.
    size_weight : float
        Score lost per metre of mean difference of sorted dimensions.
    category_filter : bool
        Only assets of the object's category compete, when the library has any.
    scale_by : str
        Which dimension drives the uniform scale; see the module docstring.
    hull : bool
        Also record each grounded object's convex ``footprint`` (the solver's fixture).
    index : AssetIndex, optional
        A ready index (then ``library`` and ``embedder`` are taken from it).

    Returns
    -------
    GroundingReport
        ``report.plan`` is the grounded plan.

    Raises
    ------
    AssetLibraryError
        For an unusable library.
    PlanError
        If the grounded sizes make the plan invalid (with ``scale_by`` other
        than ``"fit"`` an object may outgrow the room).
    """
    if scale_by not in SCALE_BY:
        raise ValueError(f"unknown scale_by {scale_by!r}; use one of {', '.join(SCALE_BY)}")
    t0 = time.perf_counter()
    plan = load_plan(plan)
    if index is None:
        index = AssetIndex(library, embedder)
    lib = index.library
    data = plan.model_dump(mode="json")
    results: list[ObjectGrounding] = []
    index.embed_queries([query_text(o.category, o.description) for o in plan.objects])  # a batch
    for o, raw in zip(plan.objects, data["objects"], strict=True):
        query = query_text(o.category, o.description)
        cands = index.search(o.description, category=o.category, size=o.size, k=k,
                             size_weight=size_weight, category_filter=category_filter)
        best = cands[0] if cands else None
        planned = tuple(float(v) for v in o.size)
        if best is None or best.score < min_score:
            note = "no asset" if best is None else (
                f"best {best.asset!r} scores {best.score:.3f} < min_score {min_score:g}")
            raw["asset"] = None
            raw["footprint"] = None
            results.append(ObjectGrounding(o.id, query, None, None if best is None else
                                           best.score, cands, planned, planned, None, note))
            continue
        mesh = lib.mesh(best.asset)
        lo, hi = mesh.bounds
        scale = scale_for(planned, hi - lo, scale_by)
        size = tuple(float(round(v, 4)) for v in (hi - lo) * scale)
        if min(size) <= 0:
            raise AssetLibraryError(f"asset {best.asset!r} is flat (extents {hi - lo}); it "
                                    "cannot be scaled to an object")
        raw["asset"] = best.asset
        raw["size"] = list(size)
        raw["footprint"] = hull_footprint(mesh.vertices[:, :2] * scale, size) if hull else None
        results.append(ObjectGrounding(o.id, query, best.asset, best.score, cands, planned,
                                       size, round(scale, 6)))
    grounded = Plan.from_dict(data)
    settings = {"k": k, "min_score": min_score, "size_weight": size_weight,
                "category_filter": category_filter, "scale_by": scale_by, "hull": hull,
                "library": str(lib.folder)}
    return GroundingReport(grounded, results, index.embedder.name, time.perf_counter() - t0,
                           index.from_cache, settings)


def scene_assets(plan: Plan, library: AssetLibrary | str) -> dict[str, Any]:
    """Meshes for the exporters: object id -> its asset's mesh (plan frame), for grounded objects.

    Pass the result as ``assets=`` to :func:`forcelayout.export.export_glb`,
    :func:`~forcelayout.export.export_usd`, :func:`~forcelayout.export.export_mjcf`,
    :func:`~forcelayout.export.export_habitat` or
    :func:`~forcelayout.export.write_exports`; each mesh is fitted to the
    object's (grounded) size, which reproduces the grounding's scale.

    Raises
    ------
    AssetLibraryError
        If an object names an asset the library does not have.
    """
    lib = library if isinstance(library, AssetLibrary) else AssetLibrary.load(library)
    out: dict[str, Any] = {}
    for o in plan.objects:
        if o.asset is None:
            continue
        if o.asset not in lib:
            raise AssetLibraryError(f"object {o.id!r} is grounded to asset {o.asset!r}, which "
                                    f"{lib!r} does not have")
        out[o.id] = lib.mesh(o.asset)
    return out
