"""Baselines to judge the method against, run in the same process on the same plans.

Random placement with rejection already reaches high validity and high
diversity, so a figure of the method means something only beside a baseline
measured the same way.

* :func:`random_layout` — the paper's *Random* baseline: uniform random
  poses, no rule guides them (one draw, not judged).

Units: metres, radians (CCW, yaw 0 = front faces +y), seconds.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from forcelayout import geometry as geo
from forcelayout import rules as registry
from forcelayout.geometry import RoomGeometry
from forcelayout.layout import Layout, Pose
from forcelayout.plan import Plan

if TYPE_CHECKING:
    from forcelayout.rules.base import Rule

__all__ = ["random_layout"]


def _rng(seed: int | np.random.Generator) -> np.random.Generator:
    return seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)


def _rule_class(name: str) -> type[Rule]:
    return type(registry.get_rule(name))


def _off_floor(plan: Plan) -> dict[str, tuple[type[Rule], str | None]]:
    """Objects an off-floor rule places: id -> (its first such rule class, its target)."""
    out: dict[str, tuple[type[Rule], str | None]] = {}
    for spec in plan.rules:
        cls = _rule_class(spec.rule)
        if cls.surface != "floor":
            out.setdefault(spec.object, (cls, spec.target))
    return out


def _door_boxes(room: RoomGeometry) -> np.ndarray:
    """Each door's swing square as box corners, shape (D, 4, 2)."""
    dc, dr, df, dh = room.door_squares
    return (dc[:, None, :] + geo._LOCAL_CORNERS[None, :, :1] * (dr * dh[:, :1])[:, None, :]
            + geo._LOCAL_CORNERS[None, :, 1:] * (df * dh[:, 1:])[:, None, :])


# -- the Random baseline ------------------------------------------------------------------


def random_layout(
    plan: Plan,
    seed: int | np.random.Generator = 0,
    *,
    max_tries: int = 200,
    reject: bool = True,
) -> Layout:
    """Random poses for every object of a plan: the paper's Random baseline.

    Floor objects, in plan order, get a uniform random centre and a random
    cardinal yaw (0, π/2, π, 3π/2); a draw is rejected while its footprint
    leaves the room or (with ``reject``) overlaps an object placed before it
    or a door's swing square, at most ``max_tries`` draws per object (the
    last draw is kept otherwise). No rule guides the placement: judge the
    result with :func:`forcelayout.validate.check_layout` and
    :attr:`Layout.rule_satisfaction` like any other sample. Objects that a
    rule places on another object's top (``surface = "top"``) land at a
    random point of the parent's top; wall objects on a random wall at a
    random height; ceiling objects at a random point under the ceiling.

    Parameters
    ----------
    plan : Plan
    seed : int or numpy.random.Generator
    max_tries : int
        Draws per floor object before giving up.
    reject : bool
        Reject draws that collide with earlier objects or door squares
        (``False``: only keep footprints inside the room).

    Returns
    -------
    Layout
        Its report is a fresh :class:`SampleReport` (not yet judged).

    Examples
    --------
    >>> import forcelayout as fl
    >>> plan = fl.examples.load_example("bedroom")
    >>> random_layout(plan, 3) == random_layout(plan, 3)
    True
    """
    if max_tries < 1:
        raise ValueError(f"max_tries must be >= 1, got {max_tries}")
    rng = _rng(seed)
    room = RoomGeometry.from_room(plan.room)
    xmin, ymin, xmax, ymax = room.bounds
    poses: dict[str, Pose] = {}
    parent = _off_floor(plan)
    floor = [o for o in plan.objects if o.id not in parent]
    placed = _door_boxes(room)  # boxes already on the floor, door swing squares first
    if not reject:
        placed = placed[:0]
    for o in floor:
        half = np.array([o.size[0], o.size[1]]) / 2
        yaw = rng.integers(0, 4, size=max_tries) * (math.pi / 2)
        draws = rng.random((max_tries, 2)) * [xmax - xmin, ymax - ymin] + [xmin, ymin]
        corners = geo.box_corners(draws, yaw, np.repeat(half[None], max_tries, axis=0))
        ok = room.contains(corners).all(axis=1)
        if reject and len(placed):
            sep = geo.box_separation(corners[:, None], placed[None])  # (T, M)
            ok &= (sep > 0).all(axis=1)
        k = int(np.argmax(ok)) if ok.any() else max_tries - 1
        poses[o.id] = Pose(float(draws[k, 0]), float(draws[k, 1]), float(yaw[k]))
        placed = np.concatenate([placed, corners[k: k + 1]]) if reject else placed
    rest = [o for o in plan.objects if o.id in parent]
    for _ in range(len(rest) + 1):  # parents before children; bounded by the count
        pending = [o for o in rest if o.id not in poses]
        if not pending:
            break
        for o in pending:
            cls, target = parent[o.id]
            if cls.surface == "top":
                if target not in poses:
                    continue
                tp = poses[target]
                tsize = plan.object(target).size
                u = (rng.random(2) - 0.5) * np.maximum(np.array(tsize[:2]) - o.size[:2], 0.0)
                c, s = math.cos(tp.yaw), math.sin(tp.yaw)
                x = tp.x + c * u[0] - s * u[1]
                y = tp.y + s * u[0] + c * u[1]
                yaw = tp.yaw + float(rng.integers(0, 4)) * math.pi / 2
                poses[o.id] = Pose(x, y, yaw, tp.z + tsize[2], target)
            elif cls.surface == "ceiling":
                draws = rng.random((max_tries, 2)) * [xmax - xmin, ymax - ymin] + [xmin, ymin]
                half = np.repeat(np.array(o.size[:2])[None] / 2, max_tries, axis=0)
                ok = room.contains(geo.box_corners(draws, np.zeros(max_tries), half)).all(1)
                k = int(np.argmax(ok)) if ok.any() else max_tries - 1
                poses[o.id] = Pose(float(draws[k, 0]), float(draws[k, 1]), 0.0,
                                   plan.room.height - o.size[2], "ceiling")
            else:  # on a wall, back to it
                w = int(rng.integers(0, room.n_walls))
                t = float(rng.uniform(min(o.size[0] / 2, room.length[w] / 2),
                                      max(room.length[w] - o.size[0] / 2, room.length[w] / 2)))
                xy = room.a[w] + room.tangent[w] * t + room.normal[w] * o.size[1] / 2
                n = room.normal[w]
                yaw = math.atan2(-n[0], n[1])  # front along the inward normal
                z = float(rng.uniform(0.0, max(plan.room.height - o.size[2], 0.0)))
                poses[o.id] = Pose(float(xy[0]), float(xy[1]), yaw, z, f"wall:{w}")
    return Layout(plan, poses, seed if isinstance(seed, int) else 0)
