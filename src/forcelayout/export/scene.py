"""A layout as a 3D scene (trimesh): floor, walls with door and window gaps, object boxes.

Frame of :func:`scene`: metres, **z up** (the library's frame: x, y on the
floor plan, the floor's top at z = 0). glTF viewers and most robotics
simulators use **y up**; ``y_up=True`` turns the whole scene by -90° about x,
so a point ``(x, y, z)`` of the plan lands at ``(x, z, -y)`` and the plan's
+y points along glTF's -z ("forward"). :func:`scene` is z-up by default,
:func:`export_glb` and :func:`export_obj` write y-up by default.
"""

from __future__ import annotations

import hashlib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from forcelayout._atomic import write_bytes
from forcelayout._optional import import_optional
from forcelayout.export._boxes import Box, box_mesh, floor_mesh, object_boxes, room_boxes
from forcelayout.layout import Layout

trimesh = import_optional("trimesh", "export")

__all__ = ["scene", "export_glb", "export_obj", "Z_UP_TO_Y_UP", "category_colour"]

#: 4x4 rotation taking the library's z-up frame to glTF's y-up frame: (x, y, z) -> (x, z, -y).
Z_UP_TO_Y_UP = np.array([[1.0, 0.0, 0.0, 0.0],
                         [0.0, 0.0, 1.0, 0.0],
                         [0.0, -1.0, 0.0, 0.0],
                         [0.0, 0.0, 0.0, 1.0]])

#: Names of the room's nodes: ``room`` (parent), ``room/floor``, ``room/wall_<i>_<k>``.
ROOM_NODE = "room"
_FLOOR_RGBA = (205, 190, 165, 255)
_WALL_RGBA = (225, 225, 220, 255)

AssetLike = Any  # a trimesh.Trimesh, a trimesh.Scene, or a path to a mesh file


def category_colour(category: str) -> tuple[int, int, int, int]:
    """A stable RGBA colour (0-255) for an object category (same in every picture and file)."""
    h = int(hashlib.md5(category.encode("utf-8")).hexdigest()[:8], 16)
    hue = (h % 360) / 360.0
    import colorsys

    r, g, b = colorsys.hsv_to_rgb(hue, 0.45, 0.85)
    return int(r * 255), int(g * 255), int(b * 255), 255


def _mesh(vertices: np.ndarray, faces: np.ndarray, rgba: tuple[int, int, int, int],
          metadata: dict[str, Any]) -> Any:
    m = trimesh.Trimesh(vertices=vertices, faces=faces, process=False)
    m.visual.face_colors = np.tile(np.asarray(rgba, dtype=np.uint8), (len(faces), 1))
    m.metadata.update(metadata)
    return m


def _fit_asset(asset: AssetLike, size: np.ndarray, oid: str) -> Any:
    """An asset mesh scaled uniformly to fit inside ``size``, footprint centred, bottom at 0."""
    if isinstance(asset, str | Path):
        path = Path(asset)
        if not path.exists():
            raise FileNotFoundError(f"assets[{oid!r}]: no mesh file {str(path)!r}")
        asset = trimesh.load(str(path), force="mesh")
    elif isinstance(asset, trimesh.Scene):
        asset = asset.to_mesh()
    if not isinstance(asset, trimesh.Trimesh) or len(asset.vertices) == 0:
        raise TypeError(f"assets[{oid!r}]: expected a trimesh.Trimesh, trimesh.Scene or a mesh "
                        f"file path, got {type(asset).__name__}")
    mesh = asset.copy()
    lo, hi = mesh.bounds
    ext = np.maximum(hi - lo, 1e-12)
    scale = float(np.min(np.asarray(size, dtype=float) / ext))
    mesh.apply_translation([-(lo[0] + hi[0]) / 2, -(lo[1] + hi[1]) / 2, -lo[2]])
    mesh.apply_scale(scale)
    return mesh


def object_mesh(box: Box, *, asset: AssetLike | None = None, plan: str = "") -> Any:
    """One object's mesh in its own frame: origin at its bottom centre, z up, front +y.

    Parameters
    ----------
    box : Box
        The object's box (from :func:`forcelayout.export._boxes.object_boxes`).
    asset : trimesh.Trimesh, trimesh.Scene or path, optional
        A mesh to use instead of the box, given z up with its front along +y;
        it is centred on its footprint, put on z = 0 and scaled uniformly to
        the largest size that fits inside the object's ``[w, d, h]``.
    plan : str
        The plan's name, stored in the mesh's metadata.
    """
    meta = {"id": box.name, "category": box.category, "plan": plan,
            "size": [float(v) for v in box.extents], "surface": box.meta.get("surface", "floor")}
    if asset is None:
        v, f = box_mesh(box.extents)
        v = v + [0.0, 0.0, box.extents[2] / 2]
        return _mesh(v, f, category_colour(box.category), meta)
    mesh = _fit_asset(asset, box.extents, box.name)
    mesh.metadata.update(meta)
    return mesh


def _pick_asset(assets: Mapping[str, AssetLike] | None, box: Box) -> AssetLike | None:
    if not assets:
        return None
    if box.name in assets:
        return assets[box.name]
    return assets.get(box.category)


def check_assets(layout: Layout, assets: Mapping[str, AssetLike] | None) -> None:
    """Refuse asset keys that are neither object ids nor categories of the layout's plan.

    Raises
    ------
    KeyError
        Naming the unknown keys.
    """
    unknown = sorted(set(assets or {}) - set(layout.plan.ids)
                     - {o.category for o in layout.plan.objects})
    if unknown:
        raise KeyError(f"assets: {unknown} are neither object ids nor categories of plan "
                       f"{layout.plan.name!r}")


def room_scene(layout: Layout, *, wall_thickness: float = 0.1, floor_thickness: float = 0.05,
               y_up: bool = False) -> Any:
    """Only the room (floor and walls) as a trimesh.Scene, in the frame :func:`scene` uses."""
    sc = trimesh.Scene(metadata={"plan": layout.plan.name, "units": "metres",
                                 "up": "+y" if y_up else "+z"})
    _add_room(sc, layout, wall_thickness, floor_thickness, y_up)
    return sc


def _add_room(sc: Any, layout: Layout, wall_thickness: float, floor_thickness: float,
              y_up: bool) -> None:
    plan = layout.plan.name
    sc.graph.update(frame_to=ROOM_NODE, frame_from=sc.graph.base_frame,
                    matrix=Z_UP_TO_Y_UP if y_up else np.eye(4),
                    metadata={"plan": plan, "category": "room"})
    fv, ff = floor_mesh(np.asarray(layout.plan.room.polygon), thickness=floor_thickness)
    sc.add_geometry(_mesh(fv, ff, _FLOOR_RGBA, {"category": "floor", "plan": plan}),
                    node_name=f"{ROOM_NODE}/floor", geom_name=f"{ROOM_NODE}/floor",
                    parent_node_name=ROOM_NODE, metadata={"category": "floor", "plan": plan})
    for b in room_boxes(layout.plan.room, wall_thickness=wall_thickness):
        v, f = box_mesh(b.extents)
        meta = {"category": "wall", "wall": int(b.meta["wall"]), "plan": plan}
        name = f"{ROOM_NODE}/{b.name}"
        sc.add_geometry(_mesh(v, f, _WALL_RGBA, meta), node_name=name, geom_name=name,
                        parent_node_name=ROOM_NODE, transform=b.transform(), metadata=meta)


def scene(
    layout: Layout,
    *,
    wall_thickness: float = 0.1,
    floor_thickness: float = 0.05,
    assets: Mapping[str, AssetLike] | None = None,
    y_up: bool = False,
) -> Any:
    """A layout as a trimesh.Scene: the room and a box (or asset) per placed object.

    Parameters
    ----------
    layout : Layout
        The layout to show.
    wall_thickness : float
        Metres. Walls stand outside the floor polygon, from the floor to the
        room's height; doors are gaps from the floor to the door's height,
        windows gaps from the sill to ``sill + height``.
    floor_thickness : float
        Metres; the floor slab's top is at z = 0.
    assets : mapping, optional
        Meshes to use instead of boxes, keyed by object id or, failing that,
        category: a ``trimesh.Trimesh``, a ``trimesh.Scene`` or a mesh file
        path, z up with its front along +y; each is scaled uniformly to fit in
        its object's size, centred on the footprint, bottom on the pose's z.
    y_up : bool
        False (default): metres, z up, the plan's frame. True: turned for
        glTF consumers, ``(x, y, z) -> (x, z, -y)``.

    Returns
    -------
    trimesh.Scene
        Nodes: ``"room"`` with children ``"room/floor"`` and
        ``"room/wall_<i>_<k>"`` (piece k of wall i), and one node per placed
        object named by its id, whose transform is its pose (origin at the
        object's bottom centre, turned by yaw about +z). Mesh and node
        metadata carry ``category`` and ``plan``; ``scene.metadata`` carries
        ``plan``, ``seed``, ``units`` and ``up``.

    Examples
    --------
    >>> sc = scene(layout)                       # doctest: +SKIP
    >>> sc.graph["bed"][0][:3, 3]                # the bed's bottom centre  # doctest: +SKIP
    """
    if not np.isfinite(floor_thickness) or floor_thickness <= 0:
        raise ValueError(f"floor_thickness must be a positive number of metres, got "
                         f"{floor_thickness!r}")
    sc = trimesh.Scene(metadata={"plan": layout.plan.name, "seed": layout.seed,
                                 "units": "metres", "up": "+y" if y_up else "+z"})
    _add_room(sc, layout, wall_thickness, floor_thickness, y_up)
    root = Z_UP_TO_Y_UP if y_up else np.eye(4)
    check_assets(layout, assets)
    for b in object_boxes(layout):
        mesh = object_mesh(b, asset=_pick_asset(assets, b), plan=layout.plan.name)
        sc.add_geometry(mesh, node_name=b.name, geom_name=b.name,
                        transform=root @ b.transform(origin="bottom"),
                        metadata={"category": b.category, "plan": layout.plan.name})
    return sc


def export_glb(layout: Layout, path: str | Path, *, y_up: bool = True, **kwargs: Any) -> Path:
    """Write the layout's scene as a binary glTF (GLB) file.

    Parameters
    ----------
    layout : Layout
    path : str or Path
        File to write (parent folders are created; the file appears only
        when complete).
    y_up : bool
        True (default): glTF's y-up frame, ``(x, y, z) -> (x, z, -y)``.
        False: the plan's z-up frame.
    **kwargs
        Passed to :func:`scene` (``wall_thickness``, ``floor_thickness``, ``assets``).

    Returns
    -------
    Path
        The file written.
    """
    data = scene(layout, y_up=y_up, **kwargs).export(file_type="glb")
    return write_bytes(path, data)


def export_obj(layout: Layout, path: str | Path, *, y_up: bool = True, **kwargs: Any) -> Path:
    """Write the layout's scene as a Wavefront OBJ file (one ``o`` group per node).

    Colours are written as per-vertex colours (``v x y z r g b``, which most
    importers read). Like :func:`export_glb`
    the default frame is y up (what most OBJ importers assume); ``y_up=False``
    keeps the plan's z-up frame. ``**kwargs`` go to :func:`scene`.

    Returns
    -------
    Path
        The OBJ file written.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    sc = scene(layout, y_up=y_up, **kwargs)
    sc.export(str(path), file_type="obj")
    return path
