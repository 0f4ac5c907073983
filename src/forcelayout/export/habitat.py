"""Habitat-style scene instances: a room stage, one object per placed object.

Writes the file layout of a Habitat scene dataset (as used by habitat-sim's
scene datasets, e.g. HSSD or ReplicaCAD) into one folder::

    <folder>/<plan>.scene_dataset_config.json
    <folder>/scenes/<plan>_<seed>.scene_instance.json
    <folder>/stages/<plan>.stage_config.json   <folder>/stages/<plan>.glb
    <folder>/objects/<plan>_<id>.object_config.json   <folder>/objects/<plan>_<id>.glb

Frame: Habitat is y up with -z forward, so a point ``(x, y, z)`` of the plan is
written as ``(x, z, -y)``; an object's yaw about the plan's +z becomes a turn
about +y, quaternion ``[w, x, y, z] = [cos(yaw/2), 0, sin(yaw/2), 0]``.
Object meshes have their origin at their bottom centre (``translation_origin``
``"asset_local"``) and their front along -z (Habitat's default ``front``).

Template names are the config files' paths inside the folder
(``"objects/<plan>_<id>.object_config.json"``): habitat-sim finds a template
by substring of its handle (the config file's path) and takes the first
match, so a bare ``"<plan>_desk"`` could pick ``<plan>_desk_2``'s config.
Asset paths inside a config are relative to the config's own folder.

The files follow the Habitat scene-dataset format (the fields habitat-sim
reads are checked in the tests) but are not loaded by habitat-sim here.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from forcelayout._atomic import write_bytes, write_text
from forcelayout.export._boxes import (
    DEFAULT_DENSITY,
    collides,
    is_movable,
    movable_names,
    object_boxes,
)
from forcelayout.export.scene import (
    Z_UP_TO_Y_UP,
    AssetLike,
    _pick_asset,
    check_assets,
    object_mesh,
    room_scene,
    trimesh,
)
from forcelayout.layout import Layout

__all__ = ["export_habitat", "yaw_quaternion", "to_y_up"]

_MOTION_TYPES = {"STATIC", "KINEMATIC", "DYNAMIC"}


def yaw_quaternion(yaw: float) -> list[float]:
    """Unit quaternion ``[w, x, y, z]`` of a turn by ``yaw`` radians (CCW seen from
    above) in the y-up frame, i.e. about +y."""
    return [float(np.cos(yaw / 2)), 0.0, float(np.sin(yaw / 2)), 0.0]


def to_y_up(point: np.ndarray) -> list[float]:
    """A z-up point ``(x, y, z)`` of the plan in the y-up frame: ``(x, z, -y)``, metres."""
    return [round(float(v), 9) + 0.0 for v in Z_UP_TO_Y_UP[:3, :3] @ np.asarray(point, float)]


def _write_json(path: Path, data: dict[str, Any]) -> None:
    write_text(path, json.dumps(data, indent=2))


def export_habitat(
    layout: Layout,
    folder: str | Path,
    *,
    wall_thickness: float = 0.1,
    assets: Mapping[str, AssetLike] | None = None,
    motion_type: str = "STATIC",
    movable: str | Iterable[str] = (),
    density: float = DEFAULT_DENSITY,
) -> Path:
    """Write a layout as a Habitat-style scene dataset folder.

    Several layouts of the same plan can be written into one folder: they
    share the stage (the room) and the object files, and each adds its own
    ``scenes/<plan>_<seed>.scene_instance.json``.

    Parameters
    ----------
    layout : Layout
    folder : str or Path
        Folder to write into (created if missing).
    wall_thickness : float
        Metres, see :func:`forcelayout.export.scene`.
    assets : mapping, optional
        Meshes instead of boxes, keyed by object id or category, see
        :func:`forcelayout.export.scene`.
    motion_type : str
        ``"STATIC"`` (default), ``"KINEMATIC"`` or ``"DYNAMIC"`` for every
        object not listed in ``movable``.
    movable : str or iterable of str
        Categories (or object ids) whose instances are ``"DYNAMIC"``. A string
        is a comma-separated list; names no object has are ignored.
    density : float
        Kilograms per cubic metre of an object's box; its config's ``mass``
        is ``density * w * d * h`` (habitat-sim uses it for dynamic objects).

    Returns
    -------
    Path
        The ``*.scene_instance.json`` written.
    """
    if motion_type.upper() not in _MOTION_TYPES:
        raise ValueError(f"motion_type must be one of {sorted(_MOTION_TYPES)}, got "
                         f"{motion_type!r}")
    if not np.isfinite(density) or density <= 0:
        raise ValueError(f"density must be a positive number of kg/m^3, got {density!r}")
    check_assets(layout, assets)
    moving = movable_names(movable)
    folder = Path(folder)
    plan = layout.plan.name
    for sub in ("scenes", "stages", "objects"):
        (folder / sub).mkdir(parents=True, exist_ok=True)

    _write_json(folder / f"{plan}.scene_dataset_config.json", {
        "stages": {"paths": {".json": ["stages"]}},
        "objects": {"paths": {".json": ["objects"]}},
        "scene_instances": {"paths": {".json": ["scenes"]}},
    })
    stage_glb = folder / "stages" / f"{plan}.glb"
    write_bytes(stage_glb, room_scene(layout, wall_thickness=wall_thickness, y_up=True)
                .export(file_type="glb"))
    _write_json(folder / "stages" / f"{plan}.stage_config.json", {
        "render_asset": stage_glb.name,
        "collision_asset": stage_glb.name,
        "up": [0.0, 1.0, 0.0],
        "front": [0.0, 0.0, -1.0],
    })

    instances = []
    for b in object_boxes(layout):
        handle = f"{plan}_{b.name}"
        asset = _pick_asset(assets, b)
        mesh = object_mesh(b, asset=asset, plan=plan)
        mesh.apply_transform(Z_UP_TO_Y_UP)
        glb = folder / "objects" / f"{handle}.glb"
        write_bytes(glb, trimesh.Scene(mesh).export(file_type="glb"))
        _write_json(folder / "objects" / f"{handle}.object_config.json", {
            "render_asset": glb.name,
            "collision_asset": glb.name,
            "up": [0.0, 1.0, 0.0],
            "front": [0.0, 0.0, -1.0],
            "mass": round(float(density * np.prod(b.extents)), 9),
            "use_bounding_box_for_collision": asset is None,  # the mesh is its box
            "is_collidable": collides(b),  # rugs and mats are walked over
            "user_defined": {"id": b.name, "category": b.category, "plan": plan,
                             "size": [float(v) for v in b.extents]},
        })
        instances.append({
            "template_name": f"objects/{handle}.object_config.json",
            "translation": to_y_up([b.centre[0], b.centre[1], b.bottom]),
            "rotation": yaw_quaternion(b.yaw),
            "motion_type": "DYNAMIC" if is_movable(b, moving) else motion_type.upper(),
            "user_defined": {"id": b.name, "category": b.category,
                             "surface": b.meta.get("surface", "floor")},
        })

    out = folder / "scenes" / f"{plan}_{layout.seed}.scene_instance.json"
    _write_json(out, {
        "stage_instance": {"template_name": f"stages/{plan}.stage_config.json"},
        "translation_origin": "asset_local",
        "default_lighting": "",
        "object_instances": instances,
        "user_defined": {"plan": plan, "seed": layout.seed, "generator": "forcelayout"},
    })
    return out
