"""3D scenes of layouts: GLB/OBJ, USD with physics, MJCF, Habitat scene instances, pictures.

Needs the ``export`` extra (trimesh, and usd-core for USD)::

    pip install "forcelayout[export]"

:func:`write_exports` writes any of :data:`EXPORT_FORMATS` (``glb``, ``usd``,
``mjcf``, ``habitat``) for one layout, each file atomically; the command
line's ``forcelayout export`` uses it.

Every exporter shows the same scene: the floor (the plan's polygon as a thin
slab whose top is at z = 0), walls standing outside the polygon up to the
room's height with doors and windows cut out as gaps, and each placed object
as a box of its size ``[w, d, h]`` (or a fitted asset mesh) at its pose.

Frames: :func:`scene`, :func:`export_usd` and :func:`export_mjcf` use the
plan's frame (metres, z up); :func:`export_glb`, :func:`export_obj` and
:func:`export_habitat` write y up by default, as glTF and Habitat expect:
``(x, y, z) -> (x, z, -y)``.

Examples
--------
>>> import forcelayout as fl
>>> from forcelayout import export
>>> layout = fl.solve(fl.examples.load_example("bedroom"), seed=0)  # doctest: +SKIP
>>> export.export_glb(layout, "bedroom.glb")                        # doctest: +SKIP
>>> export.isometric(layout, "bedroom_3d.png")                      # doctest: +SKIP
>>> export.write_exports(layout, "out/bed", ["usd", "mjcf"], movable=["chair"])  # doctest: +SKIP
"""

from __future__ import annotations

from forcelayout._optional import import_optional

import_optional("trimesh", "export")

from forcelayout.export.formats import EXPORT_FORMATS, export_paths, write_exports  # noqa: E402
from forcelayout.export.habitat import export_habitat  # noqa: E402
from forcelayout.export.isometric import isometric  # noqa: E402
from forcelayout.export.mjcf import export_mjcf, mjcf_text  # noqa: E402
from forcelayout.export.scene import (  # noqa: E402
    Z_UP_TO_Y_UP,
    export_glb,
    export_obj,
    room_scene,
    scene,
)
from forcelayout.export.usd import export_usd, usd_stage, usda_text  # noqa: E402

__all__ = [
    "scene",
    "room_scene",
    "export_glb",
    "export_obj",
    "export_habitat",
    "export_usd",
    "usda_text",
    "usd_stage",
    "export_mjcf",
    "mjcf_text",
    "write_exports",
    "export_paths",
    "EXPORT_FORMATS",
    "isometric",
    "Z_UP_TO_Y_UP",
]
