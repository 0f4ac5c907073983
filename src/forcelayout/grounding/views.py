"""Pictures of a mesh from a few directions, drawn with matplotlib (no GPU, no display).

Used by image embedders (:class:`forcelayout.grounding.ClipEmbedder`) to see
an asset as a picture; flat-shaded, grey, on white.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["render_views"]


def render_views(mesh: Any, *, n: int = 2, size: int = 224, elevation: float = 20.0,
                 max_faces: int = 20_000) -> list[np.ndarray]:
    """``n`` RGB pictures ``(size, size, 3)`` of a mesh (z up, front +y), turned about z.

    The first view looks at the mesh's front from the front-right, above by
    ``elevation`` degrees; the others turn by ``360 / n`` degrees each.
    Meshes with more than ``max_faces`` triangles are drawn from a subset.
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    v = np.asarray(mesh.vertices, dtype=float)
    f = np.asarray(mesh.faces, dtype=int)
    if len(f) > max_faces:
        f = f[np.linspace(0, len(f) - 1, max_faces).astype(int)]
    tris = v[f]
    normals = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12)
    light = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    shade = 0.35 + 0.6 * np.abs(normals @ light)
    colours = np.repeat(shade[:, None], 3, axis=1) * np.array([0.75, 0.72, 0.68])
    lo, hi = v.min(axis=0), v.max(axis=0)
    centre, half = (lo + hi) / 2, max(float((hi - lo).max()) / 2, 1e-6)
    out: list[np.ndarray] = []
    for k in range(n):
        fig = Figure(figsize=(size / 100, size / 100), dpi=100)
        canvas = FigureCanvasAgg(fig)
        ax = fig.add_axes((0, 0, 1, 1), projection="3d")
        ax.add_collection3d(Poly3DCollection(tris, facecolors=colours, edgecolors="none"))
        for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre, strict=True):
            setter(c - half, c + half)
        ax.set_box_aspect((1, 1, 1))
        ax.view_init(elev=elevation, azim=60.0 + 360.0 * k / n)  # camera at front-right
        ax.set_axis_off()
        canvas.draw()
        rgba = np.asarray(canvas.buffer_rgba())
        out.append(np.array(rgba[..., :3]))
    return out
