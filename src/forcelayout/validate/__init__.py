"""Deterministic validation of layouts: collisions, room bounds, doors, free space, paths.

The checks need only the core dependencies (numpy, scipy, shapely) and are
fast enough to run on every generated sample.

Examples
--------
>>> from forcelayout.validate import check_layout
>>> report = check_layout(layout, agent_radius=0.2)   # doctest: +SKIP
>>> print(report)                                     # doctest: +SKIP
ok: 58% of the floor free (47% with the wall band)
"""

from forcelayout.validate.checks import CHECKS, CheckReport, check_layout, window_zones
from forcelayout.validate.occupancy import RoomGrid, footprint_distance, occupancy_mask, room_grid

__all__ = [
    "check_layout",
    "CheckReport",
    "CHECKS",
    "occupancy_mask",
    "room_grid",
    "RoomGrid",
    "footprint_distance",
    "window_zones",
]
