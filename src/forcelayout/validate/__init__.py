"""Validation of layouts: deterministic checks, and the V loop with a plausibility judge.

The checks (collisions, room bounds, doors, free space, paths) need only
the core dependencies (numpy, scipy, shapely) and are fast enough to run on
every generated sample. :func:`generate_validated` (the V loop,
:mod:`forcelayout.validate.loop`) sends the samples that pass them to any
plausibility judge; a judge backed by a vision-language model is
:class:`forcelayout.validate.vlm.VLMJudge` (extra ``vlm``).

Examples
--------
>>> from forcelayout.validate import check_layout
>>> report = check_layout(layout, agent_radius=0.2)   # doctest: +SKIP
>>> print(report)                                     # doctest: +SKIP
ok: 58% of the floor free (47% with the wall band)
"""

from forcelayout.validate.checks import (
    CHECKS,
    CheckReport,
    check_floors,
    check_layout,
    check_parameters,
    window_zones,
)
from forcelayout.validate.loop import (
    Candidate,
    Judgement,
    ObjectComplaint,
    ValidatedGeneration,
    Verdict,
    generate_validated,
    judge_layout,
    load_judge,
)
from forcelayout.validate.occupancy import RoomGrid, footprint_distance, occupancy_mask, room_grid

__all__ = [
    "check_layout",
    "check_floors",
    "check_parameters",
    "CheckReport",
    "CHECKS",
    "occupancy_mask",
    "room_grid",
    "RoomGrid",
    "footprint_distance",
    "window_zones",
    "generate_validated",
    "ValidatedGeneration",
    "Candidate",
    "Verdict",
    "ObjectComplaint",
    "Judgement",
    "judge_layout",
    "load_judge",
]
