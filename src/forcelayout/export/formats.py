"""One entry point that writes a layout in several simulator formats, atomically.

:func:`write_exports` is what the command line (``forcelayout export``) uses,
and what a dataset writer calls in its worker processes: one stem, the
formats asked for, every file or folder moved into place only when complete.

- ``glb``: ``<stem>.glb``, for glTF viewers, Blender, three.js (y up);
- ``usd``: ``<stem>.usda``, for Isaac Sim, Omniverse, usdview (z up, UsdPhysics);
- ``mjcf``: ``<stem>.xml``, for MuJoCo, ManiSkill, Genesis (z up);
- ``habitat``: ``<stem>.habitat/``, a habitat-sim scene dataset folder (y up).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from forcelayout._atomic import atomic_dir
from forcelayout.layout import Layout

__all__ = ["EXPORT_FORMATS", "export_paths", "parse_formats", "write_exports"]

#: The formats :func:`write_exports` writes, in this order of mention.
EXPORT_FORMATS: tuple[str, ...] = ("glb", "usd", "mjcf", "habitat")

_SUFFIXES = {"glb": ".glb", "usd": ".usda", "mjcf": ".xml", "habitat": ".habitat"}


def parse_formats(formats: str | Iterable[str]) -> tuple[str, ...]:
    """The formats asked for, checked, lower-cased, without repeats, in the order given.

    Parameters
    ----------
    formats : str or iterable of str
        Names from :data:`EXPORT_FORMATS`; a string is a comma-separated
        list (``"glb,usd"``).

    Raises
    ------
    ValueError
        For a name that is not a format; the message lists the accepted ones.
    """
    items = formats.split(",") if isinstance(formats, str) else list(formats)
    out: list[str] = []
    for item in items:
        if not isinstance(item, str):
            raise ValueError(f"export formats are names, got {item!r}; accepted: "
                             f"{', '.join(EXPORT_FORMATS)}")
        name = item.strip().lower()
        if not name:
            continue
        if name not in EXPORT_FORMATS:
            raise ValueError(f"unknown export format {item.strip()!r}; accepted: "
                             f"{', '.join(EXPORT_FORMATS)}")
        if name not in out:
            out.append(name)
    return tuple(out)


def _at(stem: Path, fmt: str) -> Path:
    return stem.with_name(stem.name + _SUFFIXES[fmt])


def export_paths(stem: str | Path, formats: str | Iterable[str]) -> list[Path]:
    """Where :func:`write_exports` writes each format for ``stem``, without writing.

    Examples
    --------
    >>> [p.name for p in export_paths("out/bedroom_07", "glb,usd,mjcf,habitat")]
    ['bedroom_07.glb', 'bedroom_07.usda', 'bedroom_07.xml', 'bedroom_07.habitat']
    """
    stem = Path(stem)
    return [_at(stem, f) for f in parse_formats(formats)]


def write_exports(
    layout: Layout,
    stem: str | Path,
    formats: Sequence[str] | str,
    *,
    movable: str | Iterable[str] = (),
    assets: Mapping[str, Any] | None = None,
) -> list[Path]:
    """Write ``layout`` in each of ``formats`` next to ``stem``; returns what was written.

    Every file (and the Habitat folder) is written under a temporary name in
    the same folder and moved into place with :func:`os.replace` when
    complete, so a process killed at any moment never leaves a half-written
    file under a final name. An existing file of the same name is replaced.

    Parameters
    ----------
    layout : Layout
    stem : str or Path
        Path without suffix, e.g. ``out/bedroom_0007``; the suffix of each
        format is appended (a dot in the stem's name is kept as it is).
        Folders are created.
    formats : sequence of str, or str
        Names from :data:`EXPORT_FORMATS` (a string is comma-separated):
        ``"glb"`` -> ``<stem>.glb`` (y up), ``"usd"`` -> ``<stem>.usda`` (z up,
        UsdPhysics), ``"mjcf"`` -> ``<stem>.xml``, ``"habitat"`` ->
        ``<stem>.habitat/`` (a scene dataset folder holding this one layout).
    movable : str or iterable of str
        Categories (or object ids) exported as movable bodies: USD rigid
        bodies, MJCF free joints, Habitat ``"DYNAMIC"`` instances. Everything
        else is static. Names no object has are ignored.
    assets : mapping, optional
        Meshes instead of boxes, keyed by object id or category (e.g.
        :func:`forcelayout.grounding.scene_assets` of a grounded plan), in
        every format: GLB nodes, USD meshes and MJCF mesh geoms (both collided
        by their convex hull), Habitat object GLBs.

    Returns
    -------
    list of Path
        The files (the folder for ``habitat``, and the ``<stem>_meshes`` folder of
        the STL files an MJCF with assets names) written, in the order of ``formats``.

    Raises
    ------
    ValueError
        For an unknown format (before anything is written), naming the accepted ones.
    MissingExtraError
        (an ImportError) for ``usd`` without ``usd-core`` installed.
    """
    from forcelayout.export.habitat import export_habitat
    from forcelayout.export.mjcf import export_mjcf
    from forcelayout.export.scene import export_glb
    from forcelayout.export.usd import export_usd

    wanted = parse_formats(formats)
    stem = Path(stem)
    written: list[Path] = []
    for fmt in wanted:
        path = _at(stem, fmt)
        if fmt == "glb":
            export_glb(layout, path, assets=assets)
        elif fmt == "usd":
            export_usd(layout, path, movable=movable, assets=assets)
        elif fmt == "mjcf":
            export_mjcf(layout, path, movable=movable, assets=assets)
        else:
            with atomic_dir(path) as tmp:
                export_habitat(layout, tmp, movable=movable, assets=assets)
        written.append(path)
        meshes = path.parent / f"{path.stem}_meshes"  # the STL files an MJCF file names
        if fmt == "mjcf" and assets and meshes.is_dir():
            written.append(meshes)
    return written
