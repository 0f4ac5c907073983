"""An asset library: a folder of meshes and one ``assets.json`` describing them.

::

    my_assets/
      assets.json            [{"id": "sofa_3seat", "file": "sofa.glb", "category": "sofa",
                               "description": "a three-seat fabric sofa", ...}, ...]
      sofa.glb  chair.obj  ...
      .forcelayout-index/    embedding caches, one per embedder (written on first use)

Each entry has exactly these keys (optional ones marked): ``id``, ``file``
(relative to the folder; GLB, glTF, OBJ, PLY, STL, OFF — anything trimesh
loads), ``category``, ``description``, ``tags`` (optional list of words),
``up`` (optional axis the mesh's top points along, ``"+z"`` by default; one of
``+x -x +y -y +z -z``), ``front`` (optional axis its front faces, ``"+y"`` by
default) and ``units`` (optional, ``"m"`` or ``"cm"``, default ``"m"``).

:meth:`AssetLibrary.mesh` gives an asset in the library's frame: metres, z up,
front along +y, footprint centred on the origin, bottom at z = 0 — the frame
of an object of a plan (see :mod:`forcelayout.plan`).
"""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from forcelayout._optional import import_optional
from forcelayout.errors import InputError

trimesh = import_optional("trimesh", "grounding")

__all__ = ["AssetEntry", "AssetLibrary", "AssetLibraryError", "METADATA_FILE", "AXES",
           "axis_frame"]

#: Name of the metadata file of an asset library.
METADATA_FILE = "assets.json"
#: Axis strings an asset's ``up`` and ``front`` may take.
AXES = ("+x", "-x", "+y", "-y", "+z", "-z")
#: Folder (inside the library) holding cached embedding indexes.
INDEX_FOLDER = ".forcelayout-index"
_UNITS = {"m": 1.0, "cm": 0.01}


class AssetLibraryError(InputError, ValueError):
    """An asset library that cannot be used; the message lists every problem found."""


class AssetEntry(BaseModel):
    """One asset of ``assets.json``."""

    model_config = ConfigDict(extra="forbid")

    id: str = Field(min_length=1, description="Unique id, e.g. 'sofa_3seat'.")
    file: str = Field(min_length=1, description="Mesh file, relative to the library's folder.")
    category: str = Field(min_length=1, description="Object class, e.g. 'sofa'.")
    description: str = Field(min_length=1, description="What the asset is, in words.")
    tags: list[str] = Field(default_factory=list, description="Extra words for retrieval.")
    up: str = Field("+z", description="Axis of the mesh that points up.")
    front: str = Field("+y", description="Axis of the mesh that the object's front faces.")
    units: Literal["m", "cm"] = Field("m", description="Length unit of the mesh's coordinates.")

    @field_validator("up", "front")
    @classmethod
    def _axis(cls, v: str) -> str:
        v = v.strip().lower()
        if v in ("x", "y", "z"):
            v = "+" + v
        if v not in AXES:
            raise ValueError(f"unknown axis {v!r}; use one of {', '.join(AXES)}")
        return v

    @property
    def text(self) -> str:
        """The words retrieval embeds for this asset: category, description, tags."""
        words = f"{self.category.replace('_', ' ')}: {self.description}"
        return words + (f" ({', '.join(self.tags)})" if self.tags else "")


def _axis_vector(axis: str) -> np.ndarray:
    v = np.zeros(3)
    v["xyz".index(axis[1])] = 1.0 if axis[0] == "+" else -1.0
    return v


def axis_frame(up: str, front: str) -> np.ndarray:
    """The 3x3 rotation taking a mesh whose top is ``up`` and front ``front`` to z up, front +y.

    Raises
    ------
    ValueError
        If ``up`` and ``front`` are not perpendicular axes of :data:`AXES`.

    Examples
    --------
    >>> axis_frame("+y", "+z") @ [0, 1, 0]     # a y-up glTF mesh: its up goes to +z
    array([0., 0., 1.])
    """
    u, f = _axis_vector(up), _axis_vector(front)
    if abs(float(u @ f)) > 0.5:
        raise ValueError(f"up {up!r} and front {front!r} must be different, perpendicular axes")
    right = np.cross(f, u)  # the mesh's local +x (right-handed: x = y cross z)
    src = np.stack([right, f, u])  # rows: where x, y, z of the target frame lie in the mesh
    return src  # maps mesh coordinates to target: target = src @ p


class AssetLibrary:
    """A validated asset library (see the module docstring for the folder).

    Parameters
    ----------
    folder : str or Path
        The folder holding ``assets.json`` and the meshes.
    entries : sequence of AssetEntry
        Already validated entries (use :meth:`load` to read a folder).

    Examples
    --------
    >>> lib = AssetLibrary.load("examples/assets")       # doctest: +SKIP
    >>> lib.mesh("sofa_3seat").bounds                    # doctest: +SKIP
    """

    def __init__(self, folder: str | Path, entries: Sequence[AssetEntry]):
        self.folder = Path(folder)
        self.entries: tuple[AssetEntry, ...] = tuple(entries)
        self._by_id = {e.id: e for e in self.entries}
        self._meshes: dict[str, Any] = {}

    # -- loading --------------------------------------------------------------
    @classmethod
    def load(cls, folder: str | Path) -> AssetLibrary:
        """Read and validate ``folder/assets.json`` and check that every mesh file exists.

        Raises
        ------
        AssetLibraryError
            Listing every problem (missing folder or file, bad JSON, unknown
            key, unknown axis, duplicate id, missing mesh file), each with its
            place, e.g. ``assets.json[3].up``.
        """
        folder = Path(folder)
        meta = folder / METADATA_FILE
        if not folder.is_dir():
            raise AssetLibraryError(f"asset library {str(folder)!r} is not a folder")
        if not meta.is_file():
            raise AssetLibraryError(f"asset library {str(folder)!r} has no {METADATA_FILE}")
        try:
            data = json.loads(meta.read_text(encoding="utf-8"))
        except (ValueError, UnicodeDecodeError) as e:
            raise AssetLibraryError(f"{meta}: not valid JSON ({e})") from None
        if not isinstance(data, list):
            raise AssetLibraryError(f"{meta}: expected a list of assets, got "
                                    f"{type(data).__name__}")
        problems: list[str] = []
        entries: list[AssetEntry] = []
        seen: dict[str, int] = {}
        for k, item in enumerate(data):
            where = f"{METADATA_FILE}[{k}]"
            try:
                e = AssetEntry.model_validate(item)
            except ValidationError as err:
                for d in err.errors():
                    loc = ".".join(str(p) for p in d["loc"])
                    msg = d["msg"].removeprefix("Value error, ")
                    if d["type"] == "extra_forbidden":
                        msg = (f"unknown key; an asset has {', '.join(AssetEntry.model_fields)}")
                    elif d["type"] == "missing":
                        msg = "required key is missing"
                    problems.append(f"{where}{'.' + loc if loc else ''}: {msg}")
                continue
            try:
                axis_frame(e.up, e.front)
            except ValueError as err:
                problems.append(f"{where}: {err}")
            if e.id in seen:
                problems.append(f"{where}.id: duplicate id {e.id!r} (also "
                                f"{METADATA_FILE}[{seen[e.id]}])")
            seen.setdefault(e.id, k)
            path = (folder / e.file)
            if not path.is_file():
                problems.append(f"{where}.file: no mesh file {e.file!r} in {str(folder)!r}")
            entries.append(e)
        if not data:
            problems.append(f"{METADATA_FILE}: the library holds no asset")
        if problems:
            head = f"asset library {str(folder)!r} has {len(problems)} problem" + \
                   ("s" if len(problems) > 1 else "") + ": "
            raise AssetLibraryError(head + "; ".join(problems))
        return cls(folder, entries)

    # -- access ---------------------------------------------------------------
    def __len__(self) -> int:
        return len(self.entries)

    def __iter__(self) -> Iterator[AssetEntry]:
        return iter(self.entries)

    def __contains__(self, asset_id: object) -> bool:
        return asset_id in self._by_id

    def __repr__(self) -> str:
        return f"AssetLibrary({str(self.folder)!r}, {len(self)} assets)"

    @property
    def ids(self) -> list[str]:
        """Asset ids in file order."""
        return [e.id for e in self.entries]

    def entry(self, asset_id: str) -> AssetEntry:
        """The entry with id ``asset_id``; a KeyError names close ids."""
        try:
            return self._by_id[asset_id]
        except KeyError:
            import difflib

            close = difflib.get_close_matches(asset_id, self.ids, n=1)
            hint = f"; did you mean {close[0]!r}?" if close else ""
            raise KeyError(f"no asset {asset_id!r} in {self!r}{hint}") from None

    def path(self, asset_id: str) -> Path:
        """The mesh file of an asset."""
        return self.folder / self.entry(asset_id).file

    def mesh(self, asset_id: str) -> Any:
        """An asset's mesh in the plan's frame: metres, z up, front +y, footprint centred, bottom 0.

        Returns a fresh ``trimesh.Trimesh`` (a copy; the library keeps its own).

        Raises
        ------
        AssetLibraryError
            If the file cannot be read as a mesh or holds no triangles.
        """
        if asset_id not in self._meshes:
            e = self.entry(asset_id)
            path = self.folder / e.file
            try:
                mesh = trimesh.load(str(path), force="mesh")
            except Exception as err:  # trimesh raises many kinds
                raise AssetLibraryError(f"asset {asset_id!r}: cannot read {str(path)!r} as a "
                                        f"mesh ({type(err).__name__}: {err})") from None
            if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
                raise AssetLibraryError(f"asset {asset_id!r}: {str(path)!r} holds no triangles")
            m = np.eye(4)
            m[:3, :3] = axis_frame(e.up, e.front) * _UNITS[e.units]
            mesh.apply_transform(m)
            lo, hi = mesh.bounds
            mesh.apply_translation([-(lo[0] + hi[0]) / 2, -(lo[1] + hi[1]) / 2, -lo[2]])
            mesh.metadata.update({"asset": e.id, "category": e.category})
            self._meshes[asset_id] = mesh
        return self._meshes[asset_id].copy()

    def extents(self, asset_id: str) -> np.ndarray:
        """An asset's size ``[w, d, h]`` in metres in the plan's frame (front +y, z up)."""
        if asset_id not in self._meshes:
            self.mesh(asset_id)
        lo, hi = self._meshes[asset_id].bounds
        return np.asarray(hi - lo, dtype=float)

    # -- hashing and the index cache --------------------------------------------
    def metadata_hash(self, *, with_files: bool = False) -> str:
        """SHA-256 of the entries (canonical JSON); with ``with_files`` also of the mesh bytes."""
        h = hashlib.sha256()
        h.update(json.dumps([e.model_dump() for e in self.entries], sort_keys=True).encode())
        if with_files:
            for e in self.entries:
                h.update(hashlib.sha256((self.folder / e.file).read_bytes()).digest())
        return h.hexdigest()

    def index_path(self, key: str) -> Path:
        """Where the embedding index for ``key`` (an embedder's name) is cached."""
        safe = "".join(c if c.isalnum() or c in "-_." else "_" for c in key)[:80]
        digest = hashlib.sha256(key.encode()).hexdigest()[:10]
        return self.folder / INDEX_FOLDER / f"{safe}-{digest}.npz"

    def load_index(self, key: str, meta_hash: str) -> np.ndarray | None:
        """The cached embeddings for ``key`` if they were built from ``meta_hash``, else None."""
        path = self.index_path(key)
        try:
            with np.load(path, allow_pickle=False) as z:
                if str(z["meta_hash"]) != meta_hash or str(z["embedder"]) != key \
                        or list(z["ids"]) != self.ids:
                    return None
                return np.array(z["embeddings"], dtype=np.float32)
        except (OSError, KeyError, ValueError):
            return None

    def save_index(self, key: str, meta_hash: str, embeddings: np.ndarray) -> Path | None:
        """Cache embeddings for ``key``; returns the file, or None if the folder is read-only."""
        path = self.index_path(key)
        try:
            path.parent.mkdir(exist_ok=True)
            tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp.npz")
            np.savez(tmp, embeddings=np.asarray(embeddings, dtype=np.float32),
                     ids=np.array(self.ids), meta_hash=np.array(meta_hash),
                     embedder=np.array(key))
            os.replace(tmp, path)
        except OSError:
            return None
        return path
