"""A layout as an MJCF model (MuJoCo's XML), for MuJoCo, ManiSkill and Genesis.

Written with the standard library only (``mujoco`` is not needed to write
the file). Frame: the plan's, metres, z up, angles in radians
(``<compiler angle="radian"/>``), quaternions ``w x y z``::

    <mujoco model="<plan>_<seed>">
      <compiler angle="radian"/>
      <asset>      the floor slab as a mesh ("room/floor"); one mesh per asset
      <custom>     text "plan", numeric "seed", text "category:<id>" per object
      <worldbody>
        <light .../>                               one directional light from above
        <geom name="room/floor" type="mesh" .../>  top at z = 0
        <geom name="room/wall_<i>_<k>" type="box" size="half-extents" .../>
        <body name="<id>" pos="bottom centre" quat="turn about +z">
          [<freejoint name="<id>"/>]               only objects listed in ``movable``
          <geom name="<id>" type="box" size="w/2 d/2 h/2" pos="0 0 h/2" .../>
        </body>

Walls are boxes standing outside the floor polygon with doors and windows
left out as gaps (the same pieces as every other exporter). Objects are
static (bodies without joints are welded to the world) unless their category
or id is in ``movable``: those get a free joint and the mass ``density`` ×
their box's volume (objects on a wall or the ceiling stay static). Walkable
floor covers (rugs, mats) do not collide (``contype="0" conaffinity="0"``).
With ``assets``, an object's geom is the fitted asset mesh (written as STL
beside the XML, in ``<stem>_meshes/``) instead of a box; MuJoCo collides
meshes by their convex hull.

MuJoCo also takes the floor slab's convex hull for collisions: in an
L-shaped room that hull covers the notch outside the walls too, which no
object inside the room can reach.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from forcelayout._atomic import atomic_path, write_bytes
from forcelayout.export._boxes import (
    DEFAULT_DENSITY,
    collides,
    floor_mesh,
    is_movable,
    movable_names,
    object_boxes,
    room_boxes,
)
from forcelayout.layout import Layout

__all__ = ["export_mjcf", "mjcf_text"]

_FLOOR_RGBA = (0.8, 0.75, 0.65, 1.0)
_WALL_RGBA = (0.88, 0.88, 0.86, 1.0)


def _num(v: float) -> str:
    v = float(v)
    return "0" if abs(v) < 1e-12 else format(v, ".9g")  # no "-0", no 6.1e-17 for cos(pi/2)


def _vec(values: Iterable[float]) -> str:
    return " ".join(_num(v) for v in values)


def _yaw_quat(yaw: float) -> str:
    return _vec((math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)))


def _colour(category: str) -> str:
    from forcelayout.export.scene import category_colour

    r, g, b, _ = category_colour(category)
    return _vec((r / 255, g / 255, b / 255, 1.0))


def _build(layout: Layout, *, movable: str | Iterable[str], density: float,
           wall_thickness: float, floor_thickness: float,
           meshes: Mapping[str, str] | None) -> ET.Element:
    """The MJCF tree; ``meshes`` maps object ids to mesh file names (relative to the XML)."""
    if not np.isfinite(density) or density <= 0:
        raise ValueError(f"density must be a positive number of kg/m^3, got {density!r}")
    if not np.isfinite(floor_thickness) or floor_thickness <= 0:
        raise ValueError(f"floor_thickness must be a positive number of metres, got "
                         f"{floor_thickness!r}")
    moving = movable_names(movable)
    plan = layout.plan.name
    walls = room_boxes(layout.plan.room, wall_thickness=wall_thickness)
    objects = object_boxes(layout)

    root = ET.Element("mujoco", model=f"{plan}_{layout.seed}")
    ET.SubElement(root, "compiler", angle="radian")
    asset = ET.SubElement(root, "asset")
    fv, ff = floor_mesh(np.asarray(layout.plan.room.polygon), thickness=floor_thickness)
    ET.SubElement(asset, "mesh", name="room/floor", vertex=_vec(fv.reshape(-1)),
                  face=" ".join(str(int(i)) for i in ff.reshape(-1)))
    for oid, file in (meshes or {}).items():
        ET.SubElement(asset, "mesh", name=f"mesh/{oid}", file=file)

    custom = ET.SubElement(root, "custom")
    ET.SubElement(custom, "text", name="plan", data=plan)
    ET.SubElement(custom, "numeric", name="seed", data=str(layout.seed))
    for b in objects:
        ET.SubElement(custom, "text", name=f"category:{b.name}", data=b.category)

    world = ET.SubElement(root, "worldbody")
    lo = np.min(fv, axis=0)
    hi = np.max(fv, axis=0)
    centre = (lo + hi) / 2
    ET.SubElement(world, "light", name="light", directional="true", dir="0 0 -1",
                  pos=_vec((centre[0], centre[1], layout.plan.room.height + 1.0)))
    ET.SubElement(world, "geom", name="room/floor", type="mesh", mesh="room/floor",
                  rgba=_vec(_FLOOR_RGBA))
    for b in walls:
        ET.SubElement(world, "geom", name=f"room/{b.name}", type="box",
                      pos=_vec(b.centre), quat=_yaw_quat(b.yaw), size=_vec(b.extents / 2),
                      rgba=_vec(_WALL_RGBA))
    for b in objects:
        body = ET.SubElement(world, "body", name=b.name,
                             pos=_vec((b.centre[0], b.centre[1], b.bottom)),
                             quat=_yaw_quat(b.yaw))
        geom: dict[str, str] = {"name": b.name, "rgba": _colour(b.category)}
        if not collides(b):  # a rug: seen, not collided with
            geom.update(contype="0", conaffinity="0")
        if is_movable(b, moving):
            ET.SubElement(body, "freejoint", name=b.name)
            geom["mass"] = _num(density * float(np.prod(b.extents)))
        if meshes and b.name in meshes:
            geom.update(type="mesh", mesh=f"mesh/{b.name}")
        else:
            geom.update(type="box", size=_vec(b.extents / 2), pos=_vec((0, 0, b.extents[2] / 2)))
        ET.SubElement(body, "geom", geom)
    ET.indent(root)
    return root


def _text(root: ET.Element) -> str:
    return ET.tostring(root, encoding="unicode") + "\n"


def mjcf_text(
    layout: Layout,
    *,
    movable: str | Iterable[str] = (),
    density: float = DEFAULT_DENSITY,
    wall_thickness: float = 0.1,
    floor_thickness: float = 0.05,
) -> str:
    """The layout as MJCF text with box geoms (see the module docstring).

    Load it with ``mujoco.MjModel.from_xml_string(text)``. Parameters as in
    :func:`export_mjcf` (assets need files, so only :func:`export_mjcf` takes them).
    """
    return _text(_build(layout, movable=movable, density=density,
                        wall_thickness=wall_thickness, floor_thickness=floor_thickness,
                        meshes=None))


def export_mjcf(
    layout: Layout,
    path: str | Path,
    *,
    movable: str | Iterable[str] = (),
    density: float = DEFAULT_DENSITY,
    wall_thickness: float = 0.1,
    floor_thickness: float = 0.05,
    assets: Mapping[str, Any] | None = None,
) -> Path:
    """Write the layout as an MJCF file (MuJoCo XML): floor, walls with gaps, objects.

    Parameters
    ----------
    layout : Layout
    path : str or Path
        The ``.xml`` file to write (parent folders are created; the file
        appears only when complete).
    movable : str or iterable of str
        Categories (or object ids) that get a free joint and a mass; the rest
        is static. A string is a comma-separated list; names no object has
        are ignored.
    density : float
        Kilograms per cubic metre of a movable object's box.
    wall_thickness, floor_thickness : float
        Metres, see :func:`forcelayout.export.scene`.
    assets : mapping, optional
        Meshes instead of boxes, keyed by object id or category, fitted as in
        :func:`forcelayout.export.scene`; written as STL files into
        ``<stem>_meshes/`` beside the XML and referenced relative to it.

    Returns
    -------
    Path
        The XML file written.

    Examples
    --------
    >>> export_mjcf(layout, "room.xml", movable="chair,lamp")   # doctest: +SKIP
    >>> import mujoco                                           # doctest: +SKIP
    >>> model = mujoco.MjModel.from_xml_path("room.xml")        # doctest: +SKIP
    """
    path = Path(path)
    meshes: dict[str, str] = {}
    if assets:
        from forcelayout.export.scene import _pick_asset, check_assets, object_mesh

        check_assets(layout, assets)
        folder = path.parent / f"{path.stem}_meshes"
        for b in object_boxes(layout):
            asset = _pick_asset(assets, b)
            if asset is None:
                continue
            mesh = object_mesh(b, asset=asset, plan=layout.plan.name)
            write_bytes(folder / f"{b.name}.stl", mesh.export(file_type="stl"))
            meshes[b.name] = f"{folder.name}/{b.name}.stl"
    root = _build(layout, movable=movable, density=density, wall_thickness=wall_thickness,
                  floor_thickness=floor_thickness, meshes=meshes)
    with atomic_path(path) as tmp:
        tmp.write_text(_text(root), encoding="utf-8")
    return path
