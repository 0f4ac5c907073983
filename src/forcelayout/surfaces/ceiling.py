"""Objects on the ceiling: the floor polygon seen from below, one 2D simulation.

Each ceiling object is pulled to the room's centroid, its target object's
centre or a functional area's centre (a ``centred`` param, default true),
else starts at a random point under the ceiling. Several objects over one
target object share it out: evenly along its long axis (two pendants over
an island, each over one half).
"""

from __future__ import annotations

import numpy as np

from forcelayout.batching import SampleTask, SimRequest
from forcelayout.bindings import CompiledPlan
from forcelayout.geometry import box_corners
from forcelayout.layout import Pose
from forcelayout.options import SolverConfig
from forcelayout.surfaces.plane import AnchorTerm, SurfacePlacement, plane_model, plane_solver

__all__ = ["place_on_ceiling"]


def place_on_ceiling(cp: CompiledPlan, poses: dict[str, Pose], rng: np.random.Generator,
                     relations: bool, cfg: SolverConfig, out: SurfacePlacement,
                     models: dict | None = None) -> SampleTask[None]:
    """Place every object that hangs from the ceiling.

    A sample task (:mod:`forcelayout.batching`): the simulation is a
    :class:`~forcelayout.batching.SimRequest` with the sample's own anchors;
    samples given the same ``models`` dict share the force model of the
    same objects, so their simulations run as one batch.
    """
    specs = cp.on("ceiling")
    if not specs:
        return
    models = {} if models is None else models
    plan = cp.plan
    room = cp.room
    H = plan.room.height
    areas = {a.name for a in plan.areas}
    ids, anchor, stiff = [], [], []
    over: dict[str, list[int]] = {}  # target object -> the rows centred over it
    for b in specs:
        centred = bool(getattr(b.params, "centred", True))
        centre = room.centroid
        if b.target in areas:
            members = [o.id for o in plan.objects if o.area == b.target and o.id in poses
                       and poses[o.id].surface == "floor"]
            if members:
                centre = np.mean([[poses[m].x, poses[m].y] for m in members], axis=0)
        elif b.target is not None:
            if b.target not in poses:
                out.missing.append(f"{b.object}: its target {b.target!r} was not placed")
                continue
            centre = np.array([poses[b.target].x, poses[b.target].y])
        if not centred:
            lo, hi = room.bounds[:2], room.bounds[2:]
            for _ in range(50):
                centre = rng.uniform(lo, hi)
                if room.contains(centre):
                    break
        elif b.target is not None and b.target not in areas:
            over.setdefault(b.target, []).append(len(ids))
        ids.append(b.object)
        anchor.append(centre)
        stiff.append([1.0, 1.0] if centred else [0.0, 0.0])
    if not ids:
        return
    for target, rows in over.items():
        if len(rows) > 1:  # evenly along its long axis, in plan order
            t = poses[target]
            w, d = cp.size([target])[0, :2]
            axis = np.array([np.cos(t.yaw), np.sin(t.yaw)]) if w >= d else \
                np.array([-np.sin(t.yaw), np.cos(t.yaw)])
            share = max(w, d) / len(rows)
            for k, r in enumerate(rows):
                anchor[r] = anchor[r] + axis * (share * (k + 0.5) - max(w, d) / 2)
    size = cp.size(ids)
    pos = np.array(anchor, dtype=float).reshape(-1, 2)
    if len(ids) > 1:  # apart, so objects on one anchor push each other a definite way
        pos = pos + rng.normal(0.0, 0.02, (len(ids), 2))
    model = plane_model(models, ("ceiling", id(cp), tuple(ids), relations), cp, ids,
                        room.polygon, relations)
    res = yield SimRequest(model, pos, np.zeros(len(ids)), plane_solver(cfg),
                           terms=(AnchorTerm(np.array(anchor), np.array(stiff)),))
    out.steps += res.steps
    out.converged &= res.converged
    inside = room.contains(box_corners(res.pos, res.yaw, size[:, :2] * 0.5)).all(axis=1)
    for k, o in enumerate(ids):
        if not inside[k]:
            out.missing.append(f"{o}: does not fit on the ceiling")
            continue
        poses[o] = Pose(float(res.pos[k, 0]), float(res.pos[k, 1]), float(res.yaw[k]),
                        float(H - size[k, 2]), "ceiling")
