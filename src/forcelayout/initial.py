"""Random start poses for a simulation: parents anywhere, children near their parents.

Paper §III-B-3: "to ensure diversity, parent objects are placed randomly,
while child objects are placed near their parents to accelerate
convergence". Here a *child* is the object of a binary rule that asks it to
stay close to its target (``next_to``, ``in_front_of``, ``around``, ...);
the target is its parent. Starting a nightstand beside its bed rather than
across the room keeps it from settling against the wrong wall.
"""

from __future__ import annotations

import numpy as np
import shapely

from forcelayout import geometry as geo
from forcelayout.forces import ForceModel

__all__ = ["CLOSE_RULES", "parents", "initial_poses", "propose_poses"]

#: Binary rules whose object should start near its target, strongest bond first.
CLOSE_RULES = ("next_to", "around", "in_front_of", "behind", "left_of", "right_of", "near",
               "aligned_with", "facing")


def parents(model: ForceModel) -> np.ndarray:
    """The parent row of each simulated object (``-1`` for none), shape (N,).

    Each object's parent is the target of its strongest close rule (order of
    :data:`CLOSE_RULES`); bindings that would close a cycle are ignored.
    """
    n = model.n
    parent = np.full(n, -1, dtype=int)
    rank = np.full(n, len(CLOSE_RULES), dtype=int)
    for g in model.groups:
        if g.j is None or g.rule.name not in CLOSE_RULES:
            continue
        r = CLOSE_RULES.index(g.rule.name)
        for i, j in zip(g.i.tolist(), g.j.tolist(), strict=True):
            if r >= rank[i] or _reaches(parent, j, i):
                continue
            parent[i], rank[i] = j, r
    return parent


def _reaches(parent: np.ndarray, start: int, goal: int) -> bool:
    """Whether following parents from ``start`` reaches ``goal`` (bounded walk)."""
    cur = start
    for _ in range(parent.shape[0] + 1):
        if cur == goal:
            return True
        if cur < 0:
            return False
        cur = int(parent[cur])
    return False


def _order(parent: np.ndarray, area: np.ndarray) -> list[int]:
    """Largest roots first, each followed at once by its descendants (largest first).

    Children come right after their parent, so the room kept free beside a
    parent is taken by its children before any unrelated object can take it.
    """
    n = parent.shape[0]
    kids: dict[int, list[int]] = {}
    for r in range(n):
        kids.setdefault(int(parent[r]), []).append(r)
    for v in kids.values():
        v.sort(key=lambda r: (-area[r], r))
    out: list[int] = []
    stack = list(reversed(kids.get(-1, [])))
    while stack and len(out) < n:
        r = stack.pop()
        out.append(r)
        stack.extend(reversed(kids.get(r, [])))
    seen = set(out)  # parents() never forms a cycle; this only guards the bound above
    return out + [r for r in range(n) if r not in seen]


_SIDE_RULES = {"next_to", "left_of", "right_of"}


def _rules_by_object(model: ForceModel) -> list[dict[str, list[int]]]:
    """For each row: ``{rule name: [target rows or -1]}`` of its simulated bindings."""
    out: list[dict[str, list[int]]] = [{} for _ in range(model.n)]
    for g in model.groups:
        js = g.j.tolist() if g.j is not None else [-1] * len(g.i)
        for i, j in zip(g.i.tolist(), js, strict=True):
            out[i].setdefault(g.rule.name, []).append(j)
    return out


def _yaw_facing(direction: np.ndarray) -> np.ndarray:
    """Yaw whose front (local +y) points along ``direction`` (K, 2)."""
    return np.arctan2(-direction[:, 0], direction[:, 1])


def _snap_to_wall(
    room, cand: np.ndarray, half: np.ndarray, walls: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Put candidates' backs against a wall (the nearest, or ``walls``), fronts inward."""
    if walls is None:
        s = cand @ room.normal.T - room.normal_offset
        t = cand @ room.tangent.T - room.tangent_offset
        beyond = np.maximum(np.maximum(-t, t - room.length), 0.0)
        walls = np.argmin(np.abs(s) + beyond + (room.length < 2 * half[0]) * 100.0, axis=1)
    n, tan = room.normal[walls], room.tangent[walls]
    along = (cand * tan).sum(1) - room.tangent_offset[walls]
    lo = np.minimum(half[0], room.length[walls] * 0.5)
    along = np.clip(along, lo, room.length[walls] - lo)
    pos = room.a[walls] + tan * along[:, None] + n * (half[1] + 0.01)
    return pos, _yaw_facing(n)


def _wall_candidates(
    room,
    rng: np.random.Generator,
    k: int,
    half: np.ndarray,
    near: np.ndarray | None,
    margin: float = 0.0,
) -> tuple[np.ndarray, np.ndarray]:
    """``k`` poses with the back against a random wall (near ``near`` points if given).

    ``margin`` metres of wall are left free on both sides (room for objects
    that stand beside this one, e.g. nightstands beside a bed).
    """
    if near is not None and len(near):
        pick = near[rng.integers(0, len(near), k)]
        cand = pick + rng.normal(0.0, 0.6, (k, 2))
        return _snap_to_wall(room, cand, half)
    need = 2 * (half[0] + margin) + 0.02
    ok = room.length >= need
    if not ok.any():
        ok, need = room.length >= 2 * half[0] + 0.02, 2 * half[0] + 0.02
    weight = np.where(ok, room.length, 0.0)
    if weight.sum() <= 0:
        weight = room.length.copy()
    walls = rng.choice(room.n_walls, size=k, p=weight / weight.sum())
    slack = np.maximum(room.length[walls] - need, 0.0)
    along = 0.5 * need + rng.uniform(0.0, 1.0, k) * slack
    cand = room.a[walls] + room.tangent[walls] * along[:, None]
    return _snap_to_wall(room, cand, half, walls)


def _corner_candidates(
    room, rng: np.random.Generator, k: int, half: np.ndarray
) -> tuple[np.ndarray, np.ndarray] | None:
    """``k`` poses tucked into random convex corners, backs against one of the walls."""
    t_prev = np.roll(room.tangent, 1, axis=0)
    cross = t_prev[:, 0] * room.tangent[:, 1] - t_prev[:, 1] * room.tangent[:, 0]
    convex = np.flatnonzero(cross * np.sign(room.signed_area) > 1e-9)
    if convex.size == 0:
        return None
    v = convex[rng.integers(0, convex.size, k)]
    w1, w2 = (v - 1) % room.n_walls, v  # the two walls meeting at vertex v
    back_first = rng.random(k) < 0.5
    wb = np.where(back_first, w1, w2)  # wall behind the object
    ws = np.where(back_first, w2, w1)  # wall at its side
    pos = room.a[v] + room.normal[wb] * (half[1] + 0.01) + room.normal[ws] * (half[0] + 0.01)
    return pos, _yaw_facing(room.normal[wb])


def _back_wall(room, p: np.ndarray, yaw: float, half: np.ndarray) -> int:
    """The wall an object at pose (p, yaw) stands with its back against, or -1."""
    f = np.array([-np.sin(yaw), np.cos(yaw)])
    s = room.normal @ p - room.normal_offset - half[1]
    t = room.tangent @ p - room.tangent_offset
    ok = (room.normal @ f > 0.9) & (np.abs(s) < 0.15) & (t > -0.1) & (t < room.length + 0.1)
    return int(np.flatnonzero(ok)[np.argmin(np.abs(s[ok]))]) if ok.any() else -1


def _child_candidates(room, rng, k, names, q, r, pos, yaw, half, radius, spread):
    """Poses for object ``r`` around its parent ``q``, laid out as its rules ask."""
    fq = np.array([-np.sin(yaw[q]), np.cos(yaw[q])])
    rq = np.array([np.cos(yaw[q]), np.sin(yaw[q])])
    side = np.where(rng.random(k) < 0.5, -1.0, 1.0)
    if "right_of" in names:
        side[:] = 1.0
    elif "left_of" in names:
        side[:] = -1.0
    gap = rng.uniform(0.02, 0.1, k)[:, None]
    same = np.full(k, yaw[q])
    if names.keys() & {"in_front_of", "behind"}:
        sign = -1.0 if "behind" in names else 1.0
        dist = half[q, 1] + half[r, 1] + rng.uniform(0.1, 0.1 + spread, k)
        cand = pos[q] + sign * fq * dist[:, None] + rq * rng.normal(0.0, 0.15, (k, 1))
        cyaw = _yaw_facing(pos[q] - cand) if "facing" in names else same
        return cand, cyaw
    if names.keys() & _SIDE_RULES:
        wall = _back_wall(room, pos[q], yaw[q], half[q]) if "at_wall" in names else -1
        cand = pos[q] + rq * (side[:, None] * (half[q, 0] + half[r, 0] + gap))
        if wall >= 0:
            return _snap_to_wall(room, cand, half[r], np.full(k, wall))
        return cand, same
    if "at_wall" in names and "facing" in names:  # across the room, on the wall it faces
        span = float(np.hypot(*(room.bounds[2:] - room.bounds[:2])))
        cand = pos[q] + fq * rng.uniform(1.0, span, (k, 1)) + rq * rng.normal(0.0, 0.3, (k, 1))
        cand, cyaw = _snap_to_wall(room, cand, half[r])
        return cand, cyaw
    ang = rng.uniform(-np.pi, np.pi, k)
    dist = radius[q] * 0.8 + radius[r] + rng.uniform(0.0, spread, k)
    cand = pos[q] + dist[:, None] * np.stack([np.cos(ang), np.sin(ang)], axis=1)
    if "at_wall" in names:
        return _snap_to_wall(room, cand, half[r])
    if names.keys() & {"facing", "around"}:
        return cand, _yaw_facing(pos[q] - cand)
    if names.keys() & {"face_same_as", "aligned_with"}:
        return cand, same
    return cand, rng.uniform(-np.pi, np.pi, k)


def _unmet(room, names, cand, fwd, rgt, half_r, pos, half, placed) -> np.ndarray:
    """How many of an object's cheaply judged rules each candidate pose misses, shape (K,).

    Judged: ``facing`` (target within 25° of the front), ``near_window`` /
    ``near_door`` (centre within 1.3 m of an opening), ``next_to``
    (footprint roughly beside the target's) for targets already placed, and
    for objects that something hangs ``above``: no window or door in the wall
    above or close beside.
    """
    unmet = np.zeros(len(cand))
    for j in names.get("facing", []):
        if j in placed:
            d = pos[j] - cand
            cos = (d * fwd).sum(1) / np.maximum(np.sqrt((d * d).sum(1)), 1e-9)
            unmet += cos < np.cos(np.radians(25.0))
    for rule, openings in (("near_window", room.windows), ("near_door", room.doors)):
        if rule in names and len(openings):
            d = cand[:, None, :] - openings.centre[None]
            unmet += np.sqrt((d * d).sum(2)).min(1) > 1.3
    for win in (room.windows, room.doors) if "_below_art" in names else ():
        if not len(win):  # keep the wall above it free of windows and doors
            continue
        d = cand[:, None, :] - win.centre[None]
        along = np.abs((d * win.tangent[None]).sum(2))
        off = np.abs((d * win.normal[None]).sum(2))
        reach = win.width[None] * 0.5 + 0.3 + np.abs((rgt[:, None] * win.tangent[None]).sum(2)) \
            * half_r[0] + np.abs((fwd[:, None] * win.tangent[None]).sum(2)) * half_r[1]
        unmet += ((along < reach) & (off < half_r.max() + 0.3)).any(1)
    for j in names.get("next_to", []):
        if j in placed:
            d = np.abs(cand - pos[j])
            ext = np.abs(rgt) * half_r[0] + np.abs(fwd) * half_r[1]
            # a rough axis-aligned test; the simulation closes small gaps
            gap = (d - ext - np.sqrt((half[j] ** 2).sum())).max(1)
            unmet += gap > 0.35
    return unmet


def initial_poses(
    model: ForceModel,
    rng: np.random.Generator,
    *,
    tries: int = 16,
    spread: float = 0.3,
    restarts: int = 12,
) -> tuple[np.ndarray, np.ndarray]:
    """Random start poses that already lean towards the rules; the best of ``restarts``.

    Draws up to ``restarts`` independent starts with :func:`propose_poses` and
    keeps the one that meets the most of the model's rules (the first on
    ties); the first that meets them all and passes the deterministic checks
    ends the search at once. So
    a bed that landed in a corner with no room for its second nightstand is
    tried elsewhere before any simulation time is spent on it.
    """
    best, best_score = None, -1.0
    for _ in range(max(1, restarts)):
        pos, yaw = propose_poses(model, rng, tries=tries, spread=spread)
        met = model.satisfied(model.state(pos, yaw))
        score = float(sum(met.values()))
        if score == len(met):  # every rule met: take it if it also passes the checks
            if _passes_checks(model, pos, yaw):
                return pos, yaw
            score -= 0.5
        if score > best_score:
            best, best_score = (pos, yaw), score
    return best  # type: ignore[return-value]


def _passes_checks(model: ForceModel, pos: np.ndarray, yaw: np.ndarray) -> bool:
    """Whether start poses already pass the deterministic checks (floor objects only)."""
    from forcelayout.layout import Layout, Pose
    from forcelayout.validate import check_layout

    poses = {oid: Pose(float(p[0]), float(p[1]), float(y))
             for oid, p, y in zip(model.ids, pos, yaw, strict=True)}
    return check_layout(Layout(model.plan, poses)).ok


def propose_poses(
    model: ForceModel, rng: np.random.Generator, *, tries: int = 16, spread: float = 0.3
) -> tuple[np.ndarray, np.ndarray]:
    """Random start poses inside the room that already lean towards the rules.

    Objects are placed parents first. Each draws ``tries`` candidate poses
    at once from a proposal chosen by its rules — a child around its parent
    (at most ``spread`` metres beyond touching), an ``in_corner`` object in a
    random convex corner, an ``at_wall`` object against a random wall (near
    the window or door if it should be), an ``in_middle`` object near the
    centroid, anything else uniformly in the room; objects that should stand
    at a wall are turned with their backs to it, objects that face a target
    are turned towards it. The first candidate whose footprint lies inside
    the floor, clear of the objects placed so far and of the door swing
    squares is kept (else the one with the most clearance), so the start is
    random — which wall, which corner, where along it — but close to a valid
    arrangement. Nothing loops beyond ``tries`` draws per object.

    Returns
    -------
    pos : ndarray, shape (N, 2)
    yaw : ndarray, shape (N,)
    """
    room = model.room
    n = model.n
    pos = np.zeros((n, 2))
    yaw = rng.uniform(-np.pi, np.pi, n)
    if n == 0:
        return pos, yaw
    half = model.size[:, :2] * 0.5
    radius = np.hypot(half[:, 0], half[:, 1])
    parent = parents(model)
    rules = _rules_by_object(model)
    row = {oid: k for k, oid in enumerate(model.ids)}
    for spec in model.plan.rules:  # objects with a picture or shelf to hang above them
        if spec.rule == "above" and spec.target in row:
            rules[row[spec.target]]["_below_art"] = []
    order = _order(parent, model.size[:, 0] * model.size[:, 1])
    # wall length to keep free beside a parent for children standing beside it
    margin = np.zeros(n)
    for c in range(n):
        if parent[c] >= 0 and "at_wall" in rules[c] and rules[c].keys() & _SIDE_RULES:
            margin[parent[c]] = max(margin[parent[c]], model.size[c, 0] + 0.1)
    lo, hi = room.bounds[:2], room.bounds[2:]
    floor = room.shape
    shapely.prepare(floor)
    dc, dr, df, dh = room.door_zones
    placed: list[int] = []
    for r in order:
        names = rules[r]
        q = int(parent[r])
        cyaw = rng.uniform(-np.pi, np.pi, tries)
        corner = _corner_candidates(room, rng, tries, half[r]) if "in_corner" in names else None
        if corner is not None:
            cand, cyaw = corner
        elif q >= 0:
            cand, cyaw = _child_candidates(room, rng, tries, names, q, r, pos, yaw, half,
                                           radius, spread)
        elif "at_wall" in names:
            near = None
            if "near_window" in names and len(room.windows):
                near = room.windows.centre
            elif "near_door" in names and len(room.doors):
                near = room.doors.centre
            cand, cyaw = _wall_candidates(room, rng, tries, half[r], near, margin[r])
        elif "near_window" in names and len(room.windows):
            cand = room.windows.centre[rng.integers(0, len(room.windows), tries)] \
                + rng.normal(0.0, 0.6, (tries, 2))
        elif "in_middle" in names:
            cand = room.centroid + rng.normal(0.0, 0.3, (tries, 2))
        else:
            cand = rng.uniform(lo, hi, (tries, 2))
        # fall-backs after the proposals: anywhere at a wall for objects that
        # belong at one, anywhere in the room for the rest
        extra = tries // 2
        if "at_wall" in names:
            more, more_yaw = _wall_candidates(room, rng, extra, half[r], None)
        else:
            more, more_yaw = rng.uniform(lo, hi, (extra, 2)), rng.uniform(-np.pi, np.pi, extra)
        cand = np.concatenate([cand, more])
        cyaw = np.concatenate([cyaw, more_yaw])
        c, s = np.cos(cyaw), np.sin(cyaw)
        rgt = np.stack([c, s], axis=1)
        fwd = np.stack([-s, c], axis=1)
        # judge the footprint widened by the room its side children need
        reserve = half[r] + np.array([margin[r], 0.0])
        hr, hf = rgt * reserve[0], fwd * reserve[1]
        corners = np.stack([cand - hr - hf, cand + hr - hf, cand + hr + hf, cand - hr + hf],
                           axis=1)
        inside = shapely.contains(floor, shapely.polygons(corners))
        clear = np.full(len(cand), 0.3)
        if placed:
            oy = yaw[placed]
            oc, os_ = np.cos(oy), np.sin(oy)
            sep = geo.obb_separation(pos[placed][None] - cand[:, None], rgt[:, None],
                                     fwd[:, None], reserve[None, None],
                                     np.stack([oc, os_], axis=1)[None],
                                     np.stack([-os_, oc], axis=1)[None], half[placed][None])
            # objects this one is related to may stand right beside it
            related = {j for js in names.values() for j in js if j >= 0}
            slack = np.array([0.045 if p in related else 0.0 for p in placed])
            clear = np.minimum(clear, (sep + slack[None, :]).min(axis=1))
        if len(dc):
            dsep = geo.obb_separation(dc[None] - cand[:, None], rgt[:, None], fwd[:, None],
                                      reserve[None, None], dr[None], df[None], dh[None])
            clear = np.minimum(clear, dsep.min(axis=1))
        unmet = _unmet(room, names, cand, fwd, rgt, half[r], pos, half, set(placed))
        score = np.where(inside, clear, -np.inf)
        # first candidate that is clear and meets the rules it can be judged by,
        # else the clear one meeting most, else the one with the most clearance
        rank = np.where(score >= 0.05, 10.0 - unmet, np.where(np.isfinite(score), -10.0, -99.0))
        k = int(np.argmax(rank)) if rank.max() > -10.0 else int(np.argmax(score))
        if np.isfinite(score[k]):
            pos[r], yaw[r] = cand[k], cyaw[k]
        else:  # no candidate inside the floor: the centroid, and let the walls push
            pos[r] = room.centroid
        placed.append(r)
    return pos, yaw
