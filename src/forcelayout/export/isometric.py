"""A 3D picture of a layout without a GPU: boxes projected and painted back to front.

The camera looks down on the room from ``elevation`` degrees above the floor
and from the compass direction ``azimuth`` (degrees CCW from +x; the default
-135° looks from the room's lower-left corner towards its upper right). The
projection is orthographic (parallel, as in an isometric drawing). Faces
turned away from the camera are skipped and the rest are painted from far to
near (the painter's algorithm): first the floor, then the far walls, then the
objects ordered by the depth of their bottom centre, and last the walls nearest
the camera, cut down to ``cutaway`` metres so they do not hide the room. The
ordering is the usual approximation of painters: boxes that interlock in depth
can be drawn in the wrong order.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from forcelayout.export._boxes import Box, box_mesh, object_boxes, room_boxes
from forcelayout.layout import Layout

__all__ = ["isometric"]

# quads of a box (indices into box_mesh's 8 vertices) with their outward normals (local)
_QUADS = np.array([[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6],
                   [3, 0, 4, 7]])
_NORMALS = np.array([[0, 0, -1], [0, 0, 1], [0, -1, 0], [1, 0, 0], [0, 1, 0], [-1, 0, 0]],
                    dtype=float)
_SHADE = np.array([0.5, 1.0, 0.72, 0.85, 0.72, 0.85])  # per face: bottom, top, sides
_WALL_RGB = np.array([0.86, 0.86, 0.84])
_FLOOR_RGB = np.array([0.80, 0.75, 0.65])
_MAX_CHUNKS = 10_000


def _chunks(box: Box, length: float) -> list[Box]:
    """A wall piece cut into pieces at most ``length`` metres long (for depth sorting)."""
    n = int(min(_MAX_CHUNKS, max(1, np.ceil(box.extents[0] / length))))
    if n == 1:
        return [box]
    t = np.array([np.cos(box.yaw), np.sin(box.yaw), 0.0])
    step = box.extents[0] / n
    out = []
    for k in range(n):
        c = box.centre + t * (-box.extents[0] / 2 + step * (k + 0.5))
        out.append(Box(box.name, c, np.array([step, *box.extents[1:]]), box.yaw, box.kind,
                       box.category, box.meta))
    return out


def _lowered(box: Box, top: float) -> Box | None:
    """The part of a wall piece below ``top`` metres, or None."""
    z0 = box.bottom
    z1 = min(z0 + box.extents[2], top)
    if z1 <= z0 + 1e-9:
        return None
    c = box.centre.copy()
    c[2] = 0.5 * (z0 + z1)
    return Box(box.name, c, np.array([*box.extents[:2], z1 - z0]), box.yaw, box.kind,
               box.category, box.meta)


def isometric(
    layout: Layout,
    path: str | Path | None = None,
    *,
    azimuth: float = -135.0,
    elevation: float = 35.0,
    wall_thickness: float = 0.1,
    cutaway: float = 0.15,
    labels: bool = True,
    figsize: tuple[float, float] = (7.0, 6.0),
    dpi: int = 120,
) -> Any:
    """Draw the layout's room and object boxes as a 3D (parallel-projection) picture.

    Needs only matplotlib (Agg); no GPU, OpenGL or display.

    Parameters
    ----------
    layout : Layout
    path : str or Path, optional
        Where to save the picture (format from the suffix: .png, .svg, .pdf).
    azimuth : float
        Compass direction the camera looks from, degrees CCW from +x.
    elevation : float
        Camera height angle above the floor, degrees in (0, 90].
    wall_thickness : float
        Metres.
    cutaway : float
        Walls facing the camera are cut to this height, metres (0 hides them).
    labels : bool
        Write each object's id on its top.
    figsize, dpi
        Figure size in inches and resolution when saving.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.collections import PolyCollection
    from matplotlib.figure import Figure

    if not 0.0 < elevation <= 90.0:
        raise ValueError(f"elevation must be in (0, 90] degrees, got {elevation!r}")
    az, el = np.radians(azimuth), np.radians(elevation)
    cam = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
    fwd = -cam
    right = np.array([-np.sin(az), np.cos(az), 0.0])
    up = np.cross(right, fwd)

    from forcelayout.export.scene import category_colour

    room = layout.plan.room
    poly = np.asarray(room.polygon, dtype=float)
    walls = room_boxes(room, wall_thickness=wall_thickness)
    far, near = [], []
    for b in walls:
        inward = np.array([*b.meta["inward"], 0.0])
        (far if inward @ cam > 1e-9 else near).append(b)
    near = [c for c in (_lowered(b, cutaway) for b in near) if c is not None]
    objects = object_boxes(layout)

    polys: list[np.ndarray] = []
    faces: list[np.ndarray] = []
    edges: list[str] = []

    def project(p: np.ndarray) -> np.ndarray:
        return np.stack([p @ right, p @ up], axis=-1)

    def depth(b: Box) -> float:
        return float(np.array([b.centre[0], b.centre[1], b.bottom]) @ fwd)

    def paint(boxes: list[Box], rgb_of) -> None:
        for b in sorted(boxes, key=depth, reverse=True):
            v, _ = box_mesh(b.extents)
            rot = b.transform()[:3, :3]
            world = v @ rot.T + b.centre
            normals = _NORMALS @ rot.T
            rgb = rgb_of(b)
            for q, n, s in zip(_QUADS, normals, _SHADE, strict=True):
                if n @ cam <= 1e-9:
                    continue
                polys.append(project(world[q]))
                faces.append(np.append(np.clip(rgb * s, 0, 1), 1.0))
                edges.append("#444444" if b.kind == "object" else faces[-1])

    polys.append(project(np.column_stack([poly, np.zeros(len(poly))])))
    faces.append(np.append(_FLOOR_RGB, 1.0))
    edges.append("#8a7f6a")
    wall_chunks = [c for b in far for c in _chunks(b, 0.5)]
    paint(wall_chunks, lambda b: _WALL_RGB)
    paint(objects, lambda b: np.asarray(category_colour(b.category)[:3], dtype=float) / 255)
    paint([c for b in near for c in _chunks(b, 0.5)], lambda b: _WALL_RGB)

    fig = Figure(figsize=figsize, dpi=dpi)
    ax = fig.add_subplot()
    ax.add_collection(PolyCollection(polys, facecolors=faces, edgecolors=edges,
                                      linewidths=0.5))
    if labels:
        for b in objects:
            top = np.array([b.centre[0], b.centre[1], b.bottom + b.extents[2]])
            sx, sy = project(top)
            ax.text(sx, sy, b.name, fontsize=6, ha="center", va="center", color="#111111")
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.margins(0.03)
    ax.axis("off")
    ax.set_title(f"{layout.plan.name} (seed {layout.seed})", fontsize=9)
    if path is not None:
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path, dpi=dpi, bbox_inches="tight")
    return fig
