"""Binary rules: an object related to a target object.

Each binding places object ``i`` relative to target ``j``. Forces act on
``i``; a rule's ``reaction`` says what fraction of that force pushes back on
the target. Distances in forces use a fast estimate of the footprint gap
(exact for parallel footprints), the checks use the exact gap
(:meth:`State.gap`). Directions "front", "left" and "right" are the
*target's*: its local +y, -x and +x (left and right as seen by someone
standing behind the target, looking where it faces).

Units: metres, radians CCW (angles in ``Params`` are degrees).
"""

from __future__ import annotations

import numpy as np
from pydantic import Field

from forcelayout.geometry import facing_point
from forcelayout.plan import WALKABLE_HEIGHT
from forcelayout.rules.base import Access, ParamArrays, Rule, StartHint, State
from forcelayout.rules.shaping import (
    CAP,
    GAIN,
    extent,
    ramp,
    signed_angle,
    square_error,
    turn,
    unit,
    view_blockers,
)

__all__ = [
    "NextTo",
    "Near",
    "FarFrom",
    "Facing",
    "FaceSameAs",
    "InFrontOf",
    "Behind",
    "LeftOf",
    "RightOf",
    "AlignedWith",
    "Around",
    "Under",
]


def _aim(state: State, i: np.ndarray, j: np.ndarray) -> np.ndarray:
    """What each object faces: the point of its target's footprint nearest its centre (a
    stool squarely at the long side of a counter faces the counter, not its far-off
    centre); the target's centre where the object's centre lies over the target."""
    return facing_point(state.pos[i], state.pos[j], state.right[j], state.front[j],
                        state.half[j])


def _facing_error(state: State, i: np.ndarray, j: np.ndarray) -> np.ndarray:
    """Angle from each object's front to the direction of what it faces (:func:`_aim`),
    radians."""
    return signed_angle(state.front[i], _aim(state, i, j) - state.pos[i])  # needs no unit


def _side(state: State, i: np.ndarray, j: np.ndarray
          ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The side of target ``j`` that each object ``i`` stands at: its outward normal and
    the unit axis along it (both (B, 2)), the object's offset along that axis and the
    side's half length (both (B,))."""
    d = state.pos[i] - state.pos[j]
    r, f = state.right[j], state.front[j]
    lx, ly = (d * r).sum(1), (d * f).sum(1)
    hw, hd = state.half[j, 0], state.half[j, 1]
    at_end = np.abs(lx) * hd >= np.abs(ly) * hw  # beyond the left or right end
    sx = np.where(lx >= 0, 1.0, -1.0)[:, None]
    sy = np.where(ly >= 0, 1.0, -1.0)[:, None]
    normal = np.where(at_end[:, None], r * sx, f * sy)
    axis = np.where(at_end[:, None], f, r)
    return normal, axis, np.where(at_end, ly, lx), np.where(at_end, hd, hw)


def _gap_estimate(state: State, i: np.ndarray, j: np.ndarray) -> np.ndarray:
    """Fast lower bound of the footprint gap between `i` and `j`, metres.

    See :meth:`State.gap_estimate`: exact when the two footprints are
    parallel (the usual case once objects settle at cardinal angles), never
    more than the true gap. Negative values are overlap depths.
    """
    return state.gap_estimate(i, j)


class _Distance(Rule):
    """Shared pull towards the target while the gap exceeds a bound."""

    target = "required"
    reaction = 0.2

    def _pull(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays, target):
        u, _ = unit(state.pos[j] - state.pos[i])
        gap = _gap_estimate(state, i, j)
        return u * (p.weight * ramp(gap - target))[:, None], np.zeros(len(i))


class NextTo(_Distance):
    """Beside the target: footprint gap at most `distance` metres."""

    aliases = ("beside", "adjacent", "adjacent_to")
    closeness = "close"

    bond = True
    relation = True
    start = StartHint(place="beside", parent=0)
    weight = 1.5

    class Params(Rule.Params):
        distance: float = Field(0.15, gt=0, description="Largest footprint gap, m.")

    batched = True  # relates rows through i, j and per-sample pairs only

    def force(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        return self._pull(state, i, j, p, 0.5 * p.distance)

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        return state.gap(i, j) <= p.distance


class Near(_Distance):
    """Near the target: footprint gap at most `distance` metres (a soft relation)."""

    aliases = ("close_to", "nearby")
    closeness = "close"

    relation = True
    start = StartHint(parent=6, reach="distance")
    weight = 1.0

    class Params(Rule.Params):
        distance: float = Field(1.0, gt=0, description="Largest footprint gap, m.")

    batched = True  # relates rows through i, j and per-sample pairs only

    def force(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        return self._pull(state, i, j, p, p.distance - np.minimum(0.1, 0.3 * p.distance))

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        return state.gap(i, j) <= p.distance


class FarFrom(Rule):
    """Far from the target: footprint gap at least `distance` metres.

    Both objects are pushed apart (``reaction`` 0.5).
    """

    aliases = ("away_from", "far")
    closeness = "far"
    start = StartHint(least="distance")

    target = "required"
    weight = 1.0
    reaction = 0.5

    class Params(Rule.Params):
        distance: float = Field(2.0, gt=0, description="Smallest footprint gap, m.")

    batched = True  # relates rows through i, j and per-sample pairs only

    def force(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        u, _ = unit(state.pos[i] - state.pos[j], fallback=True)
        target = p.distance + 0.1
        gap = _gap_estimate(state, i, j)  # a lower bound
        # an upper bound: the gap between the footprints' inscribed circles
        d = state.pos[i] - state.pos[j]
        upper = np.sqrt((d * d).sum(1)) - 0.5 * (state.size[i, :2].min(1)
                                                 + state.size[j, :2].min(1))
        unsure = (gap < target) & (upper > gap + 1e-3)
        if unsure.any():  # refine with the exact gap only where the bounds disagree
            gap = gap.copy()
            gap[unsure] = state.gap(i[unsure], j[unsure])
        return u * (p.weight * ramp(target - gap))[:, None], np.zeros(len(i))

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        return state.gap(i, j) >= p.distance


class Facing(Rule):
    """Turned towards the target with a clear view: its footprint within `max_angle` of the front.

    Satisfied when the point of the target's footprint nearest the object's
    centre lies within ``max_angle`` degrees of the object's front (squarely
    at any stretch of a long side: stools along a counter, chairs along a
    table; towards the centre of a small target) and no floor object taller
    than ``view_height`` stands on the line between the two centres (a sofa
    facing the TV over a low coffee table, not through a wardrobe). Small misses are fixed by
    sliding sideways (along the object's own right axis) until the target is
    well inside the cone, so an object held square by a wall lines up with
    its target along that wall; large misses also turn the object. A blocked
    view slides the object sideways, away from the blocker.
    """

    aliases = ("faces", "face", "facing_towards")
    positional = True

    target = "required"
    relation = True
    start = StartHint(turn="face_target", parent=8, cone="max_angle")
    weight = 1.5

    class Params(Rule.Params):
        max_angle: float = Field(30.0, gt=0, le=180,
                                 description="Largest angle between the object's front and "
                                             "the direction to the nearest point of the "
                                             "target's footprint, deg.")
        view_height: float = Field(1.1, gt=0,
                                   description="Floor objects taller than this on the line "
                                               "between the two block the view, m.")

    batched = True  # relates rows through i, j and per-sample pairs only

    def force(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        err = _facing_error(state, i, j)
        half_cone = np.radians(p.max_angle)
        d = _aim(state, i, j) - state.pos[i]
        r = state.right[i]
        lat = (d * r).sum(1)
        ahead = (d * state.front[i]).sum(1)
        reach = np.maximum(ahead, 0.0) * np.tan(np.minimum(0.6 * half_cone, 1.4))
        slide = np.where(ahead > 0, ramp(np.abs(lat) - reach), 0.0) * np.sign(lat)
        slide *= np.where(np.abs(err) <= half_cone, 0.3, 1.0)  # gently, once inside the cone
        blocked = view_blockers(state, i, j, p.view_height)
        if blocked.any():  # slide away from the blockers' side of the line of sight
            others = state.pos[state.peers(i)]  # (B, rows, 2): the objects of i's sample
            off = ((others - state.pos[i][:, None, :]) * r[:, None, :]).sum(2)
            side = np.where(blocked, np.sign(off - lat[:, None] * 0.5), 0.0).sum(1)
            slide = slide - 0.5 * CAP * np.sign(side) * blocked.any(1)
        return r * (p.weight * slide)[:, None], turn(err, 0.6 * half_cone, p.weight)

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        aimed = np.abs(_facing_error(state, i, j)) <= np.radians(p.max_angle)
        return aimed & ~view_blockers(state, i, j, p.view_height).any(1)


class FaceSameAs(Rule):
    """Facing the same way as the target: headings within `max_angle` degrees.

    A torque only (e.g. a row of bookshelves or chairs in a row).
    """

    target = "required"
    start = StartHint(turn="target_heading")
    weight = 1.0

    class Params(Rule.Params):
        max_angle: float = Field(15.0, gt=0, le=180,
                                 description="Largest difference of the two headings, deg.")

    @staticmethod
    def _err(state: State, i: np.ndarray, j: np.ndarray) -> np.ndarray:
        return signed_angle(state.front[i], state.front[j])

    batched = True  # relates rows through i, j and per-sample pairs only

    def force(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        dead = 0.25 * np.radians(p.max_angle)
        return np.zeros((len(i), 2)), turn(self._err(state, i, j), dead, p.weight)

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        return np.abs(self._err(state, i, j)) <= np.radians(p.max_angle)


#: How far a walkable cover at a side of its target may reach under it, metres.
_UNDER = 0.01


def _thin(state: State, i: np.ndarray) -> np.ndarray:
    """Which rows are floor covers by their height (``WALKABLE_HEIGHT``: a mat, a rug), what
    nothing keeps from lying under another object."""
    return state.size[i, 2] <= WALKABLE_HEIGHT + 1e-9


class _Side(Rule):
    """Placed on one side of the target, in the target's frame.

    ``axis(state, j)`` gives the unit direction ``u`` of the side and the
    unit lateral direction ``v``; ``hu``/``hv`` are the target's half
    extents along them. Satisfied when the object's centre lies beyond the
    target's edge on that side, the footprint gap along ``u`` is at most
    ``distance``, and the centre is within the target's half extent plus
    ``lateral`` of the target's centre line; a floor cover there (no higher
    than ``WALKABLE_HEIGHT``: a bath mat in front of the tub) reaches at most
    1 cm under the target, and is pushed out from under it.
    """

    target = "required"
    closeness = "close"
    positional = True
    weight = 1.5
    reaction = 0.3

    class Params(Rule.Params):
        distance: float = Field(1.0, ge=0,
                                description="Largest gap between the two footprints on that "
                                            "side, m.")
        lateral: float = Field(0.1, ge=0,
                               description="Allowed sideways offset of the centre beyond the "
                                           "target's half extent, m.")

    _sign = 1.0
    _front = True  # side along the target's front axis (else along its right axis)

    def _frame(self, state: State, j: np.ndarray):
        f, r, h = state.front[j], state.right[j], state.half[j]
        if self._front:
            return self._sign * f, r, h[:, 1], h[:, 0]
        return self._sign * r, f, h[:, 0], h[:, 1]

    def _coords(self, state: State, i: np.ndarray, j: np.ndarray):
        u, v, hu, hv = self._frame(state, j)
        d = state.pos[i] - state.pos[j]
        a = (d * u).sum(1)  # ahead along the side's direction
        lat = (d * v).sum(1)
        gap = a - hu - extent(state, i, u)
        return u, v, hu, hv, a, lat, gap

    batched = True  # relates rows through i, j and per-sample pairs only

    def force(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        u, v, hu, hv, a, lat, gap = self._coords(state, i, j)
        w = p.weight
        ext_v = extent(state, i, v)
        on_side = a > hu
        # along u: closer than a little less than the allowed gap (contacts keep it off)
        fu = -ramp(gap - p.distance + np.minimum(0.1, 0.5 * p.distance))
        fu += np.where(_thin(state, i), ramp(-gap), 0.0)  # a cover out from under it
        fu = np.where(on_side, fu, 0.5 * CAP)
        # along v: onto the centre line when on the side, else around the target
        band = hv + p.lateral
        band = band - np.minimum(0.1, 0.5 * band)
        sgn = np.where(lat >= 0.0, 1.0, -1.0)
        inward = -sgn * ramp(np.abs(lat) - band)
        around = sgn * ramp(hv + ext_v + 0.05 - np.abs(lat))
        fv = np.where(on_side, inward, around)
        f = u * (w * fu)[:, None] + v * (w * fv)[:, None]
        return f, np.zeros(len(i))

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        u, v, hu, hv, a, lat, under = self._coords(state, i, j)
        return (a > hu) & (state.gap(i, j) <= p.distance) \
            & ((under >= -_UNDER) | ~_thin(state, i)) & (np.abs(lat) <= hv + p.lateral)


class InFrontOf(_Side):
    """In front of the target: in its front half-plane, within `distance` metres of it.

    Satisfied when the object's centre lies beyond the target's front edge,
    the footprint gap is at most ``distance``, and the centre is within the
    target's half width plus ``lateral`` of its centre line.
    """

    aliases = ("in_front", "front_of")
    opposite = "behind"

    _sign, _front = 1.0, True
    bond = True
    start = StartHint(place="front", parent=2, reach="distance")


class Behind(_Side):
    """Behind the target: beyond its back edge, within `distance` metres of it.

    Satisfied when the object's centre lies beyond the target's back edge,
    the footprint gap is at most ``distance``, and the centre is within the
    target's half width plus ``lateral`` of its centre line.
    """

    aliases = ("behind_of",)

    _sign, _front = -1.0, True
    start = StartHint(place="back", parent=3, reach="distance")


class LeftOf(_Side):
    """Left of the target (its local -x, seen from behind it), within `distance` metres.

    Satisfied when the object's centre lies beyond the target's left side,
    the footprint gap is at most ``distance``, and the centre is within the
    target's half depth plus ``lateral`` of its side-to-side centre line.
    """

    aliases = ("left",)
    opposite = "right_of"

    _sign, _front = -1.0, False
    start = StartHint(place="left", parent=4)


class RightOf(_Side):
    """Right of the target (its local +x, seen from behind it), within `distance` metres.

    Satisfied when the object's centre lies beyond the target's right side,
    the footprint gap is at most ``distance``, and the centre is within the
    target's half depth plus ``lateral`` of its side-to-side centre line.
    """

    aliases = ("right",)

    _sign, _front = 1.0, False
    start = StartHint(place="right", parent=5)


class AlignedWith(Rule):
    """Lined up with the target: parallel, centre on one of the target's axes.

    Satisfied when the object's axes are within ``max_angle`` degrees of
    the target's (modulo 90°) and its centre lies within ``tolerance``
    metres of the target's front-back or left-right centre line (whichever
    is nearer), e.g. a row of shelves or a lamp lined up with a sofa.
    """

    aliases = ("aligned", "align_with")
    positional = True

    target = "required"
    start = StartHint(turn="target_heading", parent=7)
    weight = 1.0

    class Params(Rule.Params):
        tolerance: float = Field(0.1, gt=0,
                                 description="Largest offset of the centre from the target's "
                                             "centre line, m.")
        max_angle: float = Field(10.0, gt=0, le=45,
                                 description="Largest angle between the axes (mod 90°), deg.")

    @staticmethod
    def _geometry(state: State, i: np.ndarray, j: np.ndarray):
        d = state.pos[i] - state.pos[j]
        f, r = state.front[j], state.right[j]
        a, lat = (d * f).sum(1), (d * r).sum(1)
        # beside the front-back line (|lat| small) or the left-right line (|a| small)
        on_fb = np.abs(lat) <= np.abs(a)
        off = np.where(on_fb, lat, a)
        axis = np.where(on_fb[:, None], r, f)
        err = square_error(state.yaw[i], state.yaw[j])
        return off, axis, err

    batched = True  # relates rows through i, j and per-sample pairs only

    def force(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        off, axis, err = self._geometry(state, i, j)
        mag = ramp(np.abs(off) - 0.5 * p.tolerance) * -np.sign(off)
        dead = 0.25 * np.radians(p.max_angle)
        return axis * (p.weight * mag)[:, None], turn(err, dead, p.weight)

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        off, _, err = self._geometry(state, i, j)
        return (np.abs(off) <= p.tolerance) & (np.abs(err) <= np.radians(p.max_angle))


def _same_target(j: np.ndarray) -> np.ndarray:
    """For each binding, the other bindings with the same target, shape (B, K).

    Row ``k`` lists them in binding order, padded with -1 to ``K``, the
    most any target has less one: the same whichever other samples' bindings
    are stacked with these (each sample has its own targets).
    """
    b = len(j)
    if b < 2:
        return np.zeros((b, 0), dtype=int)
    order = np.argsort(j, kind="stable")
    js = j[order]
    start = np.flatnonzero(np.r_[True, js[1:] != js[:-1]])
    size = np.diff(np.r_[start, b])
    k = int(size.max()) - 1
    if k == 0:
        return np.zeros((b, 0), dtype=int)
    first = np.repeat(start, size)  # each sorted binding's group: where it starts, its size
    n = np.repeat(size, size)
    q = np.arange(k + 1)[None, :]
    others = q != (np.arange(b) - first)[:, None]  # every member but itself: k columns
    at = (first[:, None] + q)[others].reshape(b, k)
    valid = (q < n[:, None])[others].reshape(b, k)
    out = np.empty((b, k), dtype=int)
    out[order] = np.where(valid, order[np.minimum(at, b - 1)], -1)
    return out


class Around(Rule):
    """Around the target (chairs around a table): close to one of its sides, facing it.

    Satisfied when the footprint gap to the target is at most ``distance``
    metres, the object stands beside one of the target's sides, not past its
    corners (its centre at most ``overhang`` times its width beyond where it
    would stand flush with the side's end; a chair wider than the side is
    centred on it), and its front is within ``max_angle`` degrees of square
    to that side. Besides pulling each object in, back along its side when it
    is past a corner, and turning it square to that side, the force pushes
    the objects bound around the same target at the same side apart along
    it until each has room beside the next (their widths and 10 cm between
    them). Objects start at a side chosen by its length, square to it. Each
    needs 0.3 m of free floor behind it (its access zone, see
    :mod:`forcelayout.access`): room to pull the chair out and sit down.
    """

    closeness = "close"
    positional = True

    target = "required"
    bond = True
    start = StartHint(place="all_round", turn="face_target", parent=1)
    access = Access(("back",), 0.3)
    weight = 2.0

    class Params(Rule.Params):
        distance: float = Field(0.3, gt=0, description="Largest footprint gap to the target, m.")
        max_angle: float = Field(30.0, gt=0, le=180,
                                 description="Largest angle between the object's front and "
                                             "square to the side of the target it stands "
                                             "at, deg.")
        overhang: float = Field(0.1, ge=0, le=0.5,
                                description="How far past a corner of the target the object "
                                            "may stand, as a share of its width (0.5: its "
                                            "centre at the corner).")

    batched = True  # relates rows through i, j and per-sample pairs only

    @staticmethod
    def _reach(state: State, i: np.ndarray, half: np.ndarray, p: ParamArrays) -> np.ndarray:
        """How far along its side each object's centre may lie from the side's middle."""
        width = state.size[i, 0]
        return np.maximum(half - (0.5 - np.asarray(p.overhang, dtype=float)) * width, 0.0)

    def force(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        w = p.weight
        u, _ = unit(state.pos[j] - state.pos[i])  # towards the target
        gap = _gap_estimate(state, i, j)
        f = u * (w * ramp(gap - p.distance + np.minimum(0.1, 0.5 * p.distance)))[:, None]
        normal, axis, along, half = _side(state, i, j)
        mates = _same_target(j)  # (B, K): the other bindings around the same target
        if mates.shape[1]:  # spread: apart along a shared side until each has room
            m = np.maximum(mates, 0)
            same = (mates >= 0) & ((normal[:, None, :] * normal[m]).sum(2) > 0.5)
            width = state.size[i, 0] * 0.5
            need = width[:, None] + width[m] + 0.1  # their widths and 10 cm between them
            d = along[:, None] - along[m]
            away = np.where(d > 0, 1.0, np.where(d < 0, -1.0, np.where(mates > np.arange(
                len(i))[:, None], -1.0, 1.0)))  # two at one spot: the later binding goes +
            push = np.where(same, away * np.maximum(need - np.abs(d), 0.0), 0.0)
            f += axis * (w * np.clip(push.sum(1), -CAP / GAIN, CAP / GAIN) * GAIN * 0.5)[:, None]
        # past a corner of its side: back along the side
        f -= axis * (w * np.sign(along) * ramp(np.abs(along) - self._reach(state, i, half, p))
                     )[:, None]
        dead = 0.25 * np.radians(p.max_angle)
        return f, turn(signed_angle(state.front[i], -normal), dead, w)

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        close = state.gap(i, j) <= p.distance
        normal, _, along, half = _side(state, i, j)
        square = np.abs(signed_angle(state.front[i], -normal)) <= np.radians(p.max_angle)
        return close & square & (np.abs(along) <= self._reach(state, i, half, p) + 1e-6)


class Under(Rule):
    """Lie under the target (a rug under the coffee table or the bed).

    Satisfied when the target's centre lies inside the object's footprint,
    at least ``margin`` metres from its edges, and the two are within
    ``max_angle`` degrees of parallel (modulo 90°). Meant for walkable floor
    covers (``walkable``; rugs, mats), on which furniture may stand. The
    force pulls the object's centre under the target's and squares it with
    the target; the target is not moved.
    """

    aliases = ("underneath", "below")
    closeness = "close"
    positional = True

    target = "required"
    bond = True
    relation = True
    start = StartHint(place="beneath", turn="target_heading", parent=0)
    weight = 2.0

    class Params(Rule.Params):
        margin: float = Field(0.0, ge=0,
                              description="Smallest distance from the target's centre to the "
                                          "object's edges, m.")
        max_angle: float = Field(10.0, gt=0, le=45,
                                 description="Largest angle between the axes (mod 90°), deg.")

    @staticmethod
    def _local(state: State, i: np.ndarray, j: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        d = state.pos[j] - state.pos[i]
        return (d * state.right[i]).sum(1), (d * state.front[i]).sum(1)

    @staticmethod
    def _heading_error(state: State, i: np.ndarray, j: np.ndarray) -> np.ndarray:
        return square_error(state.yaw[i], state.yaw[j])

    batched = True  # relates rows through i, j and per-sample pairs only

    def force(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        x, y = self._local(state, i, j)  # the target's centre in the object's frame
        h = state.half[i]
        aim = np.maximum(h - p.margin[:, None] - 0.05, 0.0)  # a little inside the edges
        fx = ramp(np.abs(x) - aim[:, 0]) * np.sign(x)
        fy = ramp(np.abs(y) - aim[:, 1]) * np.sign(y)
        f = (state.right[i] * fx[:, None] + state.front[i] * fy[:, None]) * p.weight[:, None]
        dead = 0.25 * np.radians(p.max_angle)
        return f, turn(self._heading_error(state, i, j), dead, p.weight)

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray, p: ParamArrays):
        x, y = self._local(state, i, j)
        h = state.half[i]
        inside = (np.abs(x) <= h[:, 0] - p.margin) & (np.abs(y) <= h[:, 1] - p.margin)
        return inside & (np.abs(self._heading_error(state, i, j)) <= np.radians(p.max_angle))
