"""A layout as a USD stage with physics (``usd-core``, the ``pxr`` modules).

The stage follows the conventions Isaac Sim and Omniverse expect: z up,
metres (``upAxis = "Z"``, ``metersPerUnit = 1``, ``kilogramsPerUnit = 1``),
``/World`` as the default prim, and a ``UsdPhysics.Scene`` with gravity
9.81 m/s² along -z::

    /World                       Xform, defaultPrim; customData plan, seed
      /Room                      Xform
        /floor                   Mesh (the floor slab, top at z = 0)    CollisionAPI
        /wall_<i>_<k>            Cube, size 1, scaled to the piece      CollisionAPI
      /Objects                   Xform
        /<id>                    Xform at the object's bottom centre, turned by yaw
          /box                   Cube, size 1, scaled to [w, d, h], raised by h/2  CollisionAPI
          /mesh                  (with ``assets``: instead of /box) Mesh of the fitted asset,
                                 CollisionAPI + MeshCollisionAPI approximation "convexHull"
    /physicsScene                UsdPhysics.Scene

Every geometry prim has ``UsdPhysics.CollisionAPI`` and is a static collider
(no rigid body), except walkable floor covers (rugs, mats), which have no
collider. Objects whose category (or id) is listed in ``movable`` get
``UsdPhysics.RigidBodyAPI`` and ``UsdPhysics.MassAPI`` (mass = ``density`` ×
the box's volume) on their Xform, so the simulator moves them as one body;
objects on a wall or the ceiling stay static.

With ``assets`` (object id or category -> a ``trimesh.Trimesh``, a
``trimesh.Scene`` or a mesh file, fitted as in
:func:`forcelayout.export.scene`), an object is its asset's mesh instead of the
box; PhysX collides it by its convex hull (``physics:approximation =
"convexHull"``), a convex collision proxy the simulator computes from the mesh.

The physics scene sits beside ``/World``, not under it: a stage opened on its
own simulates, and a stage referenced into another (its default prim
``/World``, e.g. once per environment in Isaac Lab) brings no second physics
scene along.

Transforms use Isaac Sim's op order ``xformOp:translate``, ``xformOp:orient``
(a quaternion), ``xformOp:scale``. Ids that are not valid USD names (they may
contain ``.`` or ``-`` or start with a digit) are turned into valid ones with
``_``; each object's Xform keeps its original ``id``, ``category``, ``plan``
and ``surface`` in ``customData`` and, where ``UsdSemantics`` is available,
its category as a ``class`` semantic label (what Isaac Sim's Replicator reads).
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from forcelayout._atomic import atomic_path
from forcelayout._optional import import_optional
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

__all__ = ["export_usd", "usda_text", "usd_stage", "usd_name", "USD_SUFFIXES"]

#: File suffixes :func:`export_usd` writes: text (``.usda``) or binary crate (``.usdc``, ``.usd``).
USD_SUFFIXES = (".usda", ".usdc", ".usd")

#: Path of the physics scene (Isaac Sim's default name), beside the default prim.
PHYSICS_SCENE = "/physicsScene"

_FLOOR_RGB = (0.8, 0.75, 0.65)
_WALL_RGB = (0.88, 0.88, 0.86)


def _pxr() -> Any:
    """The pxr namespace, or an ImportError that names the ``export`` extra."""
    import_optional("pxr.Usd", "export", package="usd-core")
    import pxr.Gf
    import pxr.Usd
    import pxr.UsdGeom
    import pxr.UsdPhysics
    import pxr.Vt

    return pxr


def usd_name(name: str, taken: set[str] | None = None) -> str:
    """A valid USD prim name for ``name`` (letters, digits, ``_``; not starting with a digit),
    made unique against ``taken`` (which is updated)."""
    out = re.sub(r"[^A-Za-z0-9_]", "_", name) or "_"
    if out[0].isdigit():
        out = "_" + out
    if taken is not None:
        base, k = out, 1
        while out in taken and k < 1_000_000:
            out = f"{base}_{k}"
            k += 1
        taken.add(out)
    return out


def _yaw_quat(pxr: Any, yaw: float) -> Any:
    return pxr.Gf.Quatd(math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2))


def _place(pxr: Any, prim: Any, translate: Iterable[float], yaw: float | None = None,
           scale: Iterable[float] | None = None) -> None:
    """Give ``prim`` the ops translate, orient (a turn about +z) and scale, those given."""
    xf = pxr.UsdGeom.Xformable(prim)
    double = pxr.UsdGeom.XformOp.PrecisionDouble
    xf.AddTranslateOp(double).Set(pxr.Gf.Vec3d(*(float(v) for v in translate)))
    if yaw is not None:
        xf.AddOrientOp(double).Set(_yaw_quat(pxr, yaw))
    if scale is not None:
        xf.AddScaleOp(double).Set(pxr.Gf.Vec3d(*(float(v) for v in scale)))


def _unit_cube(pxr: Any, stage: Any, path: str, rgb: tuple[float, float, float],
               collision: bool = True) -> Any:
    cube = pxr.UsdGeom.Cube.Define(stage, path)
    cube.CreateSizeAttr(1.0)
    cube.CreateExtentAttr([pxr.Gf.Vec3f(-0.5, -0.5, -0.5), pxr.Gf.Vec3f(0.5, 0.5, 0.5)])
    cube.CreateDisplayColorAttr([pxr.Gf.Vec3f(*rgb)])
    if collision:
        pxr.UsdPhysics.CollisionAPI.Apply(cube.GetPrim())
    return cube


def _label(prim: Any, category: str) -> None:
    """The category as a ``class`` semantic label, where this USD has UsdSemantics."""
    try:
        from pxr import UsdSemantics
    except ImportError:  # usd-core older than UsdSemantics: customData still says it
        return
    UsdSemantics.LabelsAPI.Apply(prim, "class").CreateLabelsAttr([category])


def _custom(prim: Any, data: dict[str, Any]) -> None:
    for key, value in data.items():
        prim.SetCustomDataByKey(key, value)


def _mesh_prim(pxr: Any, stage: Any, path: str, vertices: np.ndarray, faces: np.ndarray,
               rgb: tuple[float, float, float], collision: bool) -> Any:
    """A triangle mesh prim; as a collider, PhysX takes its convex hull."""
    Gf, UsdGeom, UsdPhysics = pxr.Gf, pxr.UsdGeom, pxr.UsdPhysics
    mesh = UsdGeom.Mesh.Define(stage, path)
    points = [Gf.Vec3f(*(float(c) for c in p)) for p in vertices]
    mesh.CreatePointsAttr(points)
    mesh.CreateFaceVertexCountsAttr([3] * len(faces))
    mesh.CreateFaceVertexIndicesAttr([int(i) for i in np.asarray(faces).reshape(-1)])
    mesh.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    mesh.CreateExtentAttr(UsdGeom.PointBased.ComputeExtent(points))
    mesh.CreateDisplayColorAttr([Gf.Vec3f(*rgb)])
    if collision:
        UsdPhysics.CollisionAPI.Apply(mesh.GetPrim())
        UsdPhysics.MeshCollisionAPI.Apply(mesh.GetPrim()).CreateApproximationAttr(
            UsdPhysics.Tokens.convexHull)
    return mesh


def usd_stage(
    layout: Layout,
    *,
    movable: str | Iterable[str] = (),
    density: float = DEFAULT_DENSITY,
    wall_thickness: float = 0.1,
    floor_thickness: float = 0.05,
    assets: Mapping[str, Any] | None = None,
) -> Any:
    """The layout as an in-memory ``pxr.Usd.Stage`` (see the module docstring for the tree).

    Parameters
    ----------
    layout : Layout
    movable : str or iterable of str
        Categories (or object ids) exported as rigid bodies; everything else
        is static. A string is a comma-separated list. Names no object has
        are ignored.
    density : float
        Kilograms per cubic metre of a movable object's box (its
        ``physics:mass`` is ``density * w * d * h``).
    wall_thickness, floor_thickness : float
        Metres, see :func:`forcelayout.export.scene`.
    assets : mapping, optional
        Meshes instead of boxes, keyed by object id or category (e.g.
        :func:`forcelayout.grounding.scene_assets`), fitted to each object's
        size as in :func:`forcelayout.export.scene`; collided by their convex hull.

    Returns
    -------
    pxr.Usd.Stage

    Raises
    ------
    MissingExtraError
        (an ImportError) if ``usd-core`` is not installed; it names
        ``pip install "forcelayout[export]"``.
    """
    pxr = _pxr()
    Gf, Usd, UsdGeom, UsdPhysics = pxr.Gf, pxr.Usd, pxr.UsdGeom, pxr.UsdPhysics
    if not np.isfinite(density) or density <= 0:
        raise ValueError(f"density must be a positive number of kg/m^3, got {density!r}")
    if not np.isfinite(floor_thickness) or floor_thickness <= 0:
        raise ValueError(f"floor_thickness must be a positive number of metres, got "
                         f"{floor_thickness!r}")
    moving = movable_names(movable)
    plan = layout.plan.name
    walls = room_boxes(layout.plan.room, wall_thickness=wall_thickness)

    stage = Usd.Stage.CreateInMemory()
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    UsdPhysics.SetStageKilogramsPerUnit(stage, 1.0)
    stage.GetRootLayer().customLayerData = {"forcelayout": {"plan": plan,
                                                            "seed": layout.seed}}

    world = UsdGeom.Xform.Define(stage, "/World").GetPrim()
    stage.SetDefaultPrim(world)
    _custom(world, {"plan": plan, "seed": layout.seed})

    scene = UsdPhysics.Scene.Define(stage, PHYSICS_SCENE)
    scene.CreateGravityDirectionAttr(Gf.Vec3f(0.0, 0.0, -1.0))
    scene.CreateGravityMagnitudeAttr(9.81)

    UsdGeom.Xform.Define(stage, "/World/Room")
    fv, ff = floor_mesh(np.asarray(layout.plan.room.polygon), thickness=floor_thickness)
    floor = UsdGeom.Mesh.Define(stage, "/World/Room/floor")
    points = [Gf.Vec3f(*(float(c) for c in p)) for p in fv]
    floor.CreatePointsAttr(points)
    floor.CreateFaceVertexCountsAttr([3] * len(ff))
    floor.CreateFaceVertexIndicesAttr([int(i) for i in ff.reshape(-1)])
    floor.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    floor.CreateExtentAttr(UsdGeom.PointBased.ComputeExtent(points))
    floor.CreateDisplayColorAttr([Gf.Vec3f(*_FLOOR_RGB)])
    UsdPhysics.CollisionAPI.Apply(floor.GetPrim())
    # a static triangle mesh: PhysX takes it as is (no convex hull)
    UsdPhysics.MeshCollisionAPI.Apply(floor.GetPrim()).CreateApproximationAttr(
        UsdPhysics.Tokens.none)
    _custom(floor.GetPrim(), {"category": "floor", "plan": plan})
    _label(floor.GetPrim(), "floor")

    for b in walls:
        cube = _unit_cube(pxr, stage, f"/World/Room/{b.name}", _WALL_RGB)
        _place(pxr, cube.GetPrim(), b.centre, b.yaw, b.extents)
        _custom(cube.GetPrim(), {"category": "wall", "wall": int(b.meta["wall"]), "plan": plan})
        _label(cube.GetPrim(), "wall")

    from forcelayout.export.scene import _pick_asset, category_colour, check_assets, object_mesh

    check_assets(layout, assets)

    UsdGeom.Xform.Define(stage, "/World/Objects")
    taken: set[str] = set()
    for b in object_boxes(layout):
        path = f"/World/Objects/{usd_name(b.name, taken)}"
        xform = UsdGeom.Xform.Define(stage, path).GetPrim()
        _place(pxr, xform, (b.centre[0], b.centre[1], b.bottom), b.yaw)
        _custom(xform, {"id": b.name, "category": b.category, "plan": plan,
                        "surface": str(b.meta.get("surface", "floor"))})
        _label(xform, b.category)
        r, g, bl, _ = category_colour(b.category)
        rgb = (r / 255, g / 255, bl / 255)
        asset = _pick_asset(assets, b)
        if asset is None:
            box = _unit_cube(pxr, stage, f"{path}/box", rgb, collision=collides(b))
            _place(pxr, box.GetPrim(), (0.0, 0.0, b.extents[2] / 2), scale=b.extents)
        else:
            fitted = object_mesh(b, asset=asset, plan=plan)
            _mesh_prim(pxr, stage, f"{path}/mesh", np.asarray(fitted.vertices),
                       np.asarray(fitted.faces), rgb, collision=collides(b))
        if is_movable(b, moving):
            UsdPhysics.RigidBodyAPI.Apply(xform)
            mass = UsdPhysics.MassAPI.Apply(xform)
            mass.CreateMassAttr(float(density * np.prod(b.extents)))
    return stage


def usda_text(layout: Layout, **kwargs: Any) -> str:
    """The stage of :func:`usd_stage` as USDA text (``**kwargs`` go to it)."""
    stage = usd_stage(layout, **kwargs)  # held: the layer lives only as long as its stage
    return str(stage.GetRootLayer().ExportToString())


def export_usd(layout: Layout, path: str | Path, **kwargs: Any) -> Path:
    """Write the layout as a USD file with physics, z up, metres (Isaac Sim's conventions).

    Parameters
    ----------
    layout : Layout
    path : str or Path
        File to write; its suffix picks the encoding: ``.usda`` text,
        ``.usdc`` or ``.usd`` binary crate. Parent folders are created; the
        file appears only when complete (written to a temporary name first).
    **kwargs
        ``movable``, ``density``, ``wall_thickness``, ``floor_thickness``,
        ``assets``, see :func:`usd_stage`.

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    ValueError
        For another suffix.
    MissingExtraError
        (an ImportError) if ``usd-core`` is not installed.

    Examples
    --------
    >>> export_usd(layout, "room.usda", movable=("chair", "lamp"))  # doctest: +SKIP
    """
    path = Path(path)
    if path.suffix.lower() not in USD_SUFFIXES:
        raise ValueError(f"export_usd writes {', '.join(USD_SUFFIXES)} files; got "
                         f"{str(path)!r}")
    stage = usd_stage(layout, **kwargs)
    with atomic_path(path) as tmp:
        if not stage.GetRootLayer().Export(str(tmp)):
            raise OSError(f"could not write the USD file {str(path)!r}")
    return path
