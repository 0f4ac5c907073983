"""A layout as a plain-text USD file (``.usda``), written without any USD library.

The file is z up, metres (``upAxis = "Z"``, ``metersPerUnit = 1``), so the
plan's frame is kept as is::

    /World
      /Room        Mesh prims "floor" and "wall_<i>_<k>" (walls cut at doors/windows)
      /Objects     one Xform per placed object, named by its id
        /<id>      xformOp:translate = (x, y, z), xformOp:rotateZ = yaw in degrees
          /box     Cube (size 1) scaled to [w, d, h] and raised by h/2

Ids that are not valid USD names (they may contain ``.`` or ``-`` or start
with a digit) are turned into valid ones (``_``); the original id is kept in
each prim's ``customData`` together with its category.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from forcelayout.export._boxes import box_mesh, floor_mesh, object_boxes, room_boxes
from forcelayout.layout import Layout

__all__ = ["export_usd", "usda_text", "usd_name"]


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


def _f(v: float) -> str:
    return format(float(v), ".9g")


def _tuple(v: np.ndarray) -> str:
    return "(" + ", ".join(_f(x) for x in v) + ")"


def _mesh_prim(name: str, vertices: np.ndarray, faces: np.ndarray, rgb: tuple[float, ...],
               custom: dict[str, str], indent: str) -> list[str]:
    pts = ", ".join(_tuple(p) for p in vertices)
    idx = ", ".join(str(int(i)) for i in faces.reshape(-1))
    counts = ", ".join("3" for _ in range(len(faces)))
    data = "; ".join(f'string {k} = "{v}"' for k, v in custom.items())
    return [
        f'{indent}def Mesh "{name}" (',
        f"{indent}    customData = {{{data}}}",
        f"{indent})",
        f"{indent}{{",
        f"{indent}    int[] faceVertexCounts = [{counts}]",
        f"{indent}    int[] faceVertexIndices = [{idx}]",
        f"{indent}    point3f[] points = [{pts}]",
        f"{indent}    color3f[] primvars:displayColor = [{_tuple(np.asarray(rgb))}]",
        f'{indent}    uniform token subdivisionScheme = "none"',
        f"{indent}}}",
    ]


def usda_text(layout: Layout, *, wall_thickness: float = 0.1,
              floor_thickness: float = 0.05) -> str:
    """The layout as USDA text (see the module docstring for the prim tree).

    Parameters
    ----------
    layout : Layout
    wall_thickness, floor_thickness : float
        Metres, see :func:`forcelayout.export.scene`.
    """
    from forcelayout.export.scene import category_colour

    plan = layout.plan.name
    lines = [
        "#usda 1.0",
        "(",
        '    defaultPrim = "World"',
        "    metersPerUnit = 1",
        '    upAxis = "Z"',
        f'    doc = "forcelayout: plan {plan}, seed {layout.seed}"',
        ")",
        "",
        'def Xform "World"',
        "{",
        '    def Xform "Room"',
        "    {",
    ]
    fv, ff = floor_mesh(np.asarray(layout.plan.room.polygon), thickness=floor_thickness)
    lines += _mesh_prim("floor", fv, ff, (0.8, 0.75, 0.65), {"category": "floor"}, " " * 8)
    for b in room_boxes(layout.plan.room, wall_thickness=wall_thickness):
        v, f = box_mesh(b.extents)
        world = v @ b.transform()[:3, :3].T + b.centre
        lines += _mesh_prim(b.name, world, f, (0.88, 0.88, 0.86),
                            {"category": "wall", "wall": str(b.meta["wall"])}, " " * 8)
    lines += ["    }", "", '    def Xform "Objects"', "    {"]
    taken: set[str] = set()
    for b in object_boxes(layout):
        r, g, bl, _ = category_colour(b.category)
        name = usd_name(b.name, taken)
        w, d, h = b.extents
        lines += [
            f'        def Xform "{name}" (',
            f'            customData = {{string id = "{b.name}"; string category = '
            f'"{b.category}"; string surface = "{b.meta.get("surface", "floor")}"}}',
            "        )",
            "        {",
            f"            double3 xformOp:translate = "
            f"{_tuple(np.array([b.centre[0], b.centre[1], b.bottom]))}",
            f"            float xformOp:rotateZ = {_f(math.degrees(b.yaw))}",
            '            uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateZ"]',
            "",
            '            def Cube "box"',
            "            {",
            "                double size = 1",
            f"                color3f[] primvars:displayColor = "
            f"[({_f(r / 255)}, {_f(g / 255)}, {_f(bl / 255)})]",
            f"                double3 xformOp:translate = (0, 0, {_f(h / 2)})",
            f"                float3 xformOp:scale = ({_f(w)}, {_f(d)}, {_f(h)})",
            '                uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:scale"]',
            "            }",
            "        }",
        ]
    lines += ["    }", "}", ""]
    return "\n".join(lines)


def export_usd(layout: Layout, path: str | Path, **kwargs: float) -> Path:
    """Write the layout as a plain-text USD file (``.usda``), z up, metres.

    Parameters
    ----------
    layout : Layout
    path : str or Path
        File to write; give it the ``.usda`` suffix.
    **kwargs
        ``wall_thickness``, ``floor_thickness`` (metres), see :func:`usda_text`.

    Returns
    -------
    Path
        The file written.
    """
    path = Path(path)
    if path.suffix.lower() not in {".usda", ".usd"}:
        raise ValueError(f"export_usd writes USD text; name the file '*.usda', got {str(path)!r}")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(usda_text(layout, **kwargs), encoding="utf-8")
    return path
