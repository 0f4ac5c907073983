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

The layout follows the Habitat scene-dataset instance format but is not
validated against habitat-sim here.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from forcelayout.export._boxes import object_boxes
from forcelayout.export.scene import (
    Z_UP_TO_Y_UP,
    AssetLike,
    _pick_asset,
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
    path.write_text(json.dumps(data, indent=2), encoding="utf-8")


def export_habitat(
    layout: Layout,
    folder: str | Path,
    *,
    wall_thickness: float = 0.1,
    assets: Mapping[str, AssetLike] | None = None,
    motion_type: str = "STATIC",
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
        ``"STATIC"`` (default), ``"KINEMATIC"`` or ``"DYNAMIC"`` for every object.

    Returns
    -------
    Path
        The ``*.scene_instance.json`` written.
    """
    if motion_type.upper() not in _MOTION_TYPES:
        raise ValueError(f"motion_type must be one of {sorted(_MOTION_TYPES)}, got "
                         f"{motion_type!r}")
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
    stage_glb.write_bytes(room_scene(layout, wall_thickness=wall_thickness, y_up=True)
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
        mesh = object_mesh(b, asset=_pick_asset(assets, b), plan=plan)
        mesh.apply_transform(Z_UP_TO_Y_UP)
        glb = folder / "objects" / f"{handle}.glb"
        glb.write_bytes(trimesh.Scene(mesh).export(file_type="glb"))
        _write_json(folder / "objects" / f"{handle}.object_config.json", {
            "render_asset": glb.name,
            "collision_asset": glb.name,
            "up": [0.0, 1.0, 0.0],
            "front": [0.0, 0.0, -1.0],
            "user_defined": {"id": b.name, "category": b.category, "plan": plan,
                             "size": [float(v) for v in b.extents]},
        })
        instances.append({
            "template_name": handle,
            "translation": to_y_up([b.centre[0], b.centre[1], b.bottom]),
            "rotation": yaw_quaternion(b.yaw),
            "motion_type": motion_type.upper(),
            "user_defined": {"id": b.name, "category": b.category,
                             "surface": b.meta.get("surface", "floor")},
        })

    out = folder / "scenes" / f"{plan}_{layout.seed}.scene_instance.json"
    _write_json(out, {
        "stage_instance": {"template_name": f"stages/{plan}"},
        "translation_origin": "asset_local",
        "default_lighting": "",
        "object_instances": instances,
        "user_defined": {"plan": plan, "seed": layout.seed, "generator": "forcelayout"},
    })
    return out
