"""Footprints, walls and distances as pure numpy functions (no physics).

Units are metres and radians (CCW). An object's footprint is the rectangle of
half extents ``half = (width/2, depth/2)`` centred at ``pos`` and turned by
``yaw``; local +y is the object's front. Corners are ordered CCW starting at
the back-left corner: back-left, back-right, front-right, front-left, so edge
0 (corner 0 → 1) is the back edge, edge 1 the right side, edge 2 the front,
edge 3 the left side.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np
import shapely

from forcelayout._compiled import kernels

if TYPE_CHECKING:
    from forcelayout.plan import Room

__all__ = [
    "RoomGeometry",
    "Openings",
    "front_vectors",
    "right_vectors",
    "yaw_facing",
    "toward_nearest",
    "rays_to_walls",
    "facing_point",
    "box_corners",
    "box_sides",
    "box_gap",
    "box_separation",
    "obb_separation",
    "obb_gap",
    "separation_matrix",
    "point_segment_distance",
    "wrap_angle",
    "footprint_polygon",
]

#: Extra depth, metres, of the zone in front of each door that the simulation keeps clear.
ENTRY_DEPTH = 0.45
#: Extra width, metres, on each side of that zone (so nothing stands flush with the swing).
ENTRY_SIDE = 0.04





def wrap_angle(a: np.ndarray | float) -> np.ndarray:
    """Wrap angles to ``[-pi, pi)`` radians."""
    return (np.asarray(a) + np.pi) % (2.0 * np.pi) - np.pi


def front_vectors(yaw: np.ndarray) -> np.ndarray:
    """Unit front directions ``(-sin yaw, cos yaw)``, shape ``yaw.shape + (2,)``."""
    yaw = np.asarray(yaw, dtype=float)
    out = np.empty((*yaw.shape, 2))
    np.sin(yaw, out=out[..., 0])
    np.negative(out[..., 0], out=out[..., 0])
    np.cos(yaw, out=out[..., 1])
    return out


def yaw_facing(direction: np.ndarray) -> np.ndarray:
    """The yaw whose front (local +y) points along ``direction`` (..., 2): the inverse of
    :func:`front_vectors` for unit directions; shape ``direction.shape[:-1]``."""
    direction = np.asarray(direction, dtype=float)
    return np.arctan2(-direction[..., 0], direction[..., 1])


def toward_nearest(points: np.ndarray, centres: np.ndarray) -> np.ndarray:
    """From each of ``points`` (..., 2) to the nearest of ``centres`` (M, 2), M >= 1: the
    offsets, shape (..., 2) (the first of equally near centres)."""
    points = np.asarray(points, dtype=float)
    d = np.asarray(centres, dtype=float)[None] - points.reshape(-1, 1, 2)
    k = np.argmin((d * d).sum(-1), axis=1)
    return d[np.arange(len(d)), k].reshape(points.shape)


def facing_point(points: np.ndarray, centre: np.ndarray, right: np.ndarray,
                 front: np.ndarray, half: np.ndarray) -> np.ndarray:
    """What an object at each of ``points`` faces when it faces an oriented rectangle: the
    rectangle's point nearest it, or the rectangle's centre where the point lies inside.
    All arrays (..., 2), broadcast; shape of the broadcast.

    >>> facing_point(np.array([3.0, 0.2]), np.zeros(2), np.array([1.0, 0.0]),
    ...              np.array([0.0, 1.0]), np.array([1.0, 0.5])).tolist()
    [1.0, 0.2]
    >>> facing_point(np.array([0.5, 0.2]), np.zeros(2), np.array([1.0, 0.0]),
    ...              np.array([0.0, 1.0]), np.array([1.0, 0.5])).tolist()
    [0.0, 0.0]
    """
    points, centre = np.asarray(points, dtype=float), np.asarray(centre, dtype=float)
    d = points - centre
    lx = np.clip((d * right).sum(-1), -half[..., 0], half[..., 0])
    ly = np.clip((d * front).sum(-1), -half[..., 1], half[..., 1])
    aim = centre + right * lx[..., None] + front * ly[..., None]
    inside = (np.abs(aim - points) < 1e-9).all(-1)
    return np.where(inside[..., None], centre, aim)


def right_vectors(yaw: np.ndarray) -> np.ndarray:
    """Unit local +x directions ``(cos yaw, sin yaw)``, shape ``yaw.shape + (2,)``."""
    yaw = np.asarray(yaw, dtype=float)
    out = np.empty((*yaw.shape, 2))  # filled in place: a stack of two costs more here
    np.cos(yaw, out=out[..., 0])
    np.sin(yaw, out=out[..., 1])
    return out


def rays_to_walls(room: RoomGeometry, points: np.ndarray, directions: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Where rays first meet a wall of the room (what an object looks at along its front).

    Parameters
    ----------
    room : RoomGeometry
    points : ndarray, shape (K, 2)
        Where the rays start.
    directions : ndarray, shape (K, 2)
        Unit directions of the rays.

    Returns
    -------
    wall, along, distance : ndarray, shapes (K,)
        The wall each ray meets first, the distance along that wall from its
        start (``room.a``) and the distance along the ray; ``-1``, ``inf`` and
        ``inf`` for a ray that meets none.
    """
    p, f = np.asarray(points, dtype=float), np.asarray(directions, dtype=float)
    a, t, length = room.a, room.tangent, room.length  # (W, 2), (W, 2), (W,)
    # p + s f = a + u t: solve for s (along each ray) and u (along each wall), (K, W)
    det = f[:, :1] * -t[None, :, 1] + t[None, :, 0] * f[:, 1:]
    ok = np.abs(det) > 1e-12
    safe = np.where(ok, det, 1.0)
    d = a[None] - p[:, None]  # (K, W, 2)
    s = (d[..., 0] * -t[None, :, 1] + t[None, :, 0] * d[..., 1]) / safe
    u = (f[:, :1] * d[..., 1] - f[:, 1:] * d[..., 0]) / safe
    hit = ok & (s > 1e-9) & (u >= -1e-9) & (u <= length[None] + 1e-9)
    s = np.where(hit, s, np.inf)
    k = np.argmin(s, axis=1)
    rows = np.arange(len(p))
    found = np.isfinite(s[rows, k])
    return (np.where(found, k, -1), np.where(found, u[rows, k], np.inf),
            np.where(found, s[rows, k], np.inf))


def box_sides(right: np.ndarray, front: np.ndarray, half: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The four sides of one oriented rectangle: front, right, back, left.

    Parameters
    ----------
    right, front : ndarray, shape (2,)
        The rectangle's unit axes.
    half : ndarray, shape (2,)
        Half width (along ``right``) and half depth (along ``front``), metres.

    Returns
    -------
    normals : ndarray, shape (4, 2)
        Each side's outward unit normal.
    axes : ndarray, shape (4, 2)
        A unit axis along each side.
    lengths : ndarray, shape (4,)
        Each side's half length, metres.
    depths : ndarray, shape (4,)
        The distance from the centre to each side, metres.

    Examples
    --------
    >>> n, a, length, depth = box_sides(np.array([1.0, 0.0]), np.array([0.0, 1.0]),
    ...                                 np.array([0.8, 0.45]))
    >>> n.tolist()
    [[0.0, 1.0], [1.0, 0.0], [-0.0, -1.0], [-1.0, -0.0]]
    >>> length.tolist(), depth.tolist()
    ([0.8, 0.45, 0.8, 0.45], [0.45, 0.8, 0.45, 0.8])
    """
    hw, hd = half[0], half[1]
    normals = np.stack([front, right, -front, -right])
    axes = np.stack([right, front, right, front])
    return normals, axes, np.array([hw, hd, hw, hd]), np.array([hd, hw, hd, hw])


def box_corners(pos: np.ndarray, yaw: np.ndarray, half: np.ndarray) -> np.ndarray:
    """Corners of oriented rectangles (footprints): the one corner function of the library.

    Parameters
    ----------
    pos : ndarray, shape (N, 2)
        Centres, metres.
    yaw : ndarray, shape (N,)
        Headings, radians CCW.
    half : ndarray, shape (N, 2)
        Half width and half depth, metres.

    Returns
    -------
    ndarray, shape (N, 4, 2)
        Back-left, back-right, front-right, front-left corners (CCW).
    """
    return corners_from_axes(pos, right_vectors(yaw), front_vectors(yaw), half)


def corners_from_axes(pos: np.ndarray, right: np.ndarray, front: np.ndarray,
                      half: np.ndarray) -> np.ndarray:
    """:func:`box_corners` from the rectangles' unit axes (when they are at hand).

    Parameters
    ----------
    pos : ndarray, shape (N, 2)
    right, front : ndarray, shape (N, 2)
        Unit local +x and +y directions in the world.
    half : ndarray, shape (N, 2)
        Half width and half depth, metres.

    Returns
    -------
    ndarray, shape (N, 4, 2)
        Back-left, back-right, front-right, front-left corners (CCW).
    """
    r = right * half[:, 0:1]
    f = front * half[:, 1:2]
    c = np.empty((pos.shape[0], 4, 2))
    c[:, 0] = pos - r - f
    c[:, 1] = pos + r - f
    c[:, 2] = pos + r + f
    c[:, 3] = pos - r + f
    return c


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Dot products of 2-vectors along the last axis: ``(a * b).sum(-1)``, bit for bit, without
    a reduction (several times faster on the small arrays of the simulation loop)."""
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1]


def point_segment_distance(
    p: np.ndarray, a: np.ndarray, b: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Distance from points to segments, broadcasting over leading axes.

    Parameters
    ----------
    p, a, b : ndarray, shape (..., 2)
        Points and segment end points (broadcastable).

    Returns
    -------
    dist : ndarray, shape (...)
        Euclidean distance, metres.
    closest : ndarray, shape (..., 2)
        The closest point on each segment.
    """
    ab = b - a
    ap = p - a
    denom = np.maximum(_dot(ab, ab), 1e-18)
    t = np.clip(_dot(ap, ab) / denom, 0.0, 1.0)
    closest = a + t[..., None] * ab
    d = p - closest
    return np.sqrt(_dot(d, d)), closest


def obb_separation(
    d: np.ndarray,
    ra: np.ndarray,
    fa: np.ndarray,
    ha: np.ndarray,
    rb: np.ndarray,
    fb: np.ndarray,
    hb: np.ndarray,
) -> np.ndarray:
    """Separating-axis clearance of oriented rectangles given by their axes.

    The fast form of :func:`box_separation` used in the simulation loop.

    Parameters
    ----------
    d : ndarray, shape (..., 2)
        Centre of B minus centre of A.
    ra, fa, rb, fb : ndarray, shape (..., 2)
        Unit right and front axes of A and B.
    ha, hb : ndarray, shape (..., 2)
        Half extents (width/2, depth/2) of A and B.

    Returns
    -------
    ndarray, shape (...)
        Signed clearance in metres (negative: overlap depth).

    Notes
    -----
    With numba installed (``forcelayout[fast]``) a compiled kernel computes
    it, the same bit for bit for finite inputs (:mod:`forcelayout._compiled`).
    """
    fast = kernels()
    if fast is not None:
        return fast.obb_separation(d, ra, fa, ha, rb, fb, hb)
    return _obb_separation(d, ra, fa, ha, rb, fb, hb)


def _obb_separation(d: np.ndarray, ra: np.ndarray, fa: np.ndarray, ha: np.ndarray,
                    rb: np.ndarray, fb: np.ndarray, hb: np.ndarray) -> np.ndarray:
    """:func:`obb_separation` in numpy."""
    c = np.abs(_dot(ra, rb))
    s = np.abs(_dot(ra, fb))
    hax, hay, hbx, hby = ha[..., 0], ha[..., 1], hb[..., 0], hb[..., 1]
    g1 = np.abs(_dot(d, ra)) - hax - (hbx * c + hby * s)
    g2 = np.abs(_dot(d, fa)) - hay - (hbx * s + hby * c)
    g3 = np.abs(_dot(d, rb)) - hbx - (hax * c + hay * s)
    g4 = np.abs(_dot(d, fb)) - hby - (hax * s + hay * c)
    return np.maximum(np.maximum(g1, g2), np.maximum(g3, g4))


#: Corner signs of a rectangle along its own right and front axes, CCW from back-left.
_CORNER_SIGNS = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])


def _corners_in_frame(cx: np.ndarray, cy: np.ndarray, ux: np.ndarray, uy: np.ndarray,
                      vx: np.ndarray, vy: np.ndarray, hu: np.ndarray, hv: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray]:
    """x and y, shape (..., 4), of the corners of rectangles with centres ``(cx, cy)``, unit
    axes ``u`` and ``v`` and half extents ``hu``, ``hv``, all given in some frame."""
    su, sv = _CORNER_SIGNS[:, 0], _CORNER_SIGNS[:, 1]
    au, av = (hu * ux)[..., None], (hv * vx)[..., None]
    bu, bv = (hu * uy)[..., None], (hv * vy)[..., None]
    return cx[..., None] + su * au + sv * av, cy[..., None] + su * bu + sv * bv


def obb_gap(
    d: np.ndarray,
    ra: np.ndarray,
    fa: np.ndarray,
    ha: np.ndarray,
    rb: np.ndarray,
    fb: np.ndarray,
    hb: np.ndarray,
) -> np.ndarray:
    """Exact clearance between oriented rectangles given by their axes (0 where they touch
    or overlap); :func:`box_gap` takes their corners.

    Each rectangle's corners are taken into the other's frame, where the
    distance from a corner to the rectangle is that of a point to an
    axis-aligned box; the smallest over the eight corners is the distance
    between two rectangles that do not overlap, and the same coordinates
    give the separating-axis test that tells whether they do.

    Parameters
    ----------
    d : ndarray, shape (..., 2)
        Centre of B minus centre of A.
    ra, fa, rb, fb : ndarray, shape (..., 2)
        Unit right and front axes of A and B.
    ha, hb : ndarray, shape (..., 2)
        Half extents (width/2, depth/2) of A and B.

    Returns
    -------
    ndarray, shape (...)
        Distance in metres, ``>= 0``.

    Notes
    -----
    With numba installed (``forcelayout[fast]``) a compiled kernel computes
    it, the same bit for bit for finite inputs (:mod:`forcelayout._compiled`).
    """
    fast = kernels()
    if fast is not None:
        return fast.obb_gap(d, ra, fa, ha, rb, fb, hb)
    return _obb_gap(d, ra, fa, ha, rb, fb, hb)


def _obb_gap(d: np.ndarray, ra: np.ndarray, fa: np.ndarray, ha: np.ndarray, rb: np.ndarray,
             fb: np.ndarray, hb: np.ndarray) -> np.ndarray:
    """:func:`obb_gap` in numpy."""
    rr, rf, fr, ff = _dot(ra, rb), _dot(ra, fb), _dot(fa, rb), _dot(fa, fb)
    # B in A's frame (its axes there: right (ra.rb, fa.rb), front (ra.fb, fa.fb)), and A in B's
    bx, by = _corners_in_frame(_dot(d, ra), _dot(d, fa), rr, fr, rf, ff, hb[..., 0], hb[..., 1])
    ax, ay = _corners_in_frame(-_dot(d, rb), -_dot(d, fb), rr, rf, fr, ff, ha[..., 0],
                               ha[..., 1])
    hax, hay, hbx, hby = ha[..., 0:1], ha[..., 1:2], hb[..., 0:1], hb[..., 1:2]
    # separating axes: each rectangle's own two, where the other's corners project
    sep = np.maximum(
        np.maximum(np.maximum(bx.min(-1) - ha[..., 0], -ha[..., 0] - bx.max(-1)),
                   np.maximum(by.min(-1) - ha[..., 1], -ha[..., 1] - by.max(-1))),
        np.maximum(np.maximum(ax.min(-1) - hb[..., 0], -hb[..., 0] - ax.max(-1)),
                   np.maximum(ay.min(-1) - hb[..., 1], -hb[..., 1] - ay.max(-1))))
    ex, ey = np.maximum(np.abs(bx) - hax, 0.0), np.maximum(np.abs(by) - hay, 0.0)
    gx, gy = np.maximum(np.abs(ax) - hbx, 0.0), np.maximum(np.abs(ay) - hby, 0.0)
    d2 = np.minimum((ex * ex + ey * ey).min(-1), (gx * gx + gy * gy).min(-1))
    return np.where(sep > 0.0, np.sqrt(d2), 0.0)


def separation_matrix(
    pos: np.ndarray,
    right: np.ndarray,
    front: np.ndarray,
    half: np.ndarray,
    *,
    with_axis_gaps: bool = False,
) -> np.ndarray | tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Separating-axis clearance between every pair of oriented rectangles.

    The all-pairs form of :func:`obb_separation`, built from a few (M, M)
    matrix products instead of per-pair gathers. Leading axes are sets of
    rectangles computed independently (a stack of samples): each set's
    matrix is the same, bit for bit, whatever else is stacked with it.

    Parameters
    ----------
    pos, right, front, half : ndarray, shape (..., M, 2)
        Centres, unit right and front axes, half extents.

    Returns
    -------
    sep : ndarray, shape (..., M, M)
        Symmetric signed clearance in metres; the diagonal is meaningless.
    along_right, along_front : ndarray, shape (..., M, M)
        Only with ``with_axis_gaps``: ``[i, j]`` is the clearance between
        footprint i and the bounding box of footprint j in i's frame, along
        i's right and front axes.
    """
    rt, ft = np.swapaxes(right, -1, -2), np.swapaxes(front, -1, -2)
    pr = np.matmul(pos, rt)  # [j, i] = pos_j . r_i
    pf = np.matmul(pos, ft)
    dr = np.abs(pr - np.diagonal(pr, axis1=-2, axis2=-1)[..., None, :])  # |(pos_j - pos_i).r_i|
    df = np.abs(pf - np.diagonal(pf, axis1=-2, axis2=-1)[..., None, :])
    c = np.abs(np.matmul(right, rt))
    s = np.abs(np.matmul(right, ft))  # |sin| of the relative angle, symmetric for rectangles
    hx, hy = half[..., 0], half[..., 1]
    # g1[j, i]: gap along r_i; g2[j, i]: gap along f_i
    g1 = dr - hx[..., None, :] - (hx[..., :, None] * c + hy[..., :, None] * s)
    g2 = df - hy[..., None, :] - (hx[..., :, None] * s + hy[..., :, None] * c)
    g = np.maximum(g1, g2)
    sep = np.maximum(g, np.swapaxes(g, -1, -2))
    if with_axis_gaps:
        return sep, np.swapaxes(g1, -1, -2), np.swapaxes(g2, -1, -2)
    return sep


def box_separation(ca: np.ndarray, cb: np.ndarray) -> np.ndarray:
    """Separating-axis clearance between oriented rectangles.

    The largest gap of the two projections over the four edge normals: a
    lower bound on the true distance when positive, minus the smallest
    penetration depth when the rectangles overlap.

    Parameters
    ----------
    ca, cb : ndarray, shape (..., 4, 2)
        Corners as returned by :func:`box_corners`.

    Returns
    -------
    ndarray, shape (...)
        Signed clearance in metres.
    """
    ca, cb = np.broadcast_arrays(ca, cb)
    ax, ay, bx, by = ca[..., 0], ca[..., 1], cb[..., 0], cb[..., 1]  # (..., 4 corners)
    # the two edge directions of each rectangle, as unit vectors: (..., 4 axes)
    ux = np.stack([ax[..., 1] - ax[..., 0], ax[..., 3] - ax[..., 0],
                   bx[..., 1] - bx[..., 0], bx[..., 3] - bx[..., 0]], axis=-1)
    uy = np.stack([ay[..., 1] - ay[..., 0], ay[..., 3] - ay[..., 0],
                   by[..., 1] - by[..., 0], by[..., 3] - by[..., 0]], axis=-1)
    norm = np.maximum(np.sqrt(ux * ux + uy * uy), 1e-12)
    ux, uy = (ux / norm)[..., :, None], (uy / norm)[..., :, None]
    pa = ax[..., None, :] * ux + ay[..., None, :] * uy  # (..., 4 axes, 4 corners)
    pb = bx[..., None, :] * ux + by[..., None, :] * uy
    gap = np.maximum(pb.min(-1) - pa.max(-1), pa.min(-1) - pb.max(-1))
    return gap.max(-1)


def _frame_of(c: np.ndarray) -> tuple[np.ndarray, ...]:
    """Centres, unit right and front axes and half extents of rectangles given by their
    corners (..., 4, 2), CCW from back-left."""
    along, across = c[..., 1, :] - c[..., 0, :], c[..., 3, :] - c[..., 0, :]
    w = np.sqrt(_dot(along, along))
    d = np.sqrt(_dot(across, across))
    half = 0.5 * np.stack([w, d], axis=-1)
    return (0.5 * (c[..., 0, :] + c[..., 2, :]), along / np.maximum(w, 1e-12)[..., None],
            across / np.maximum(d, 1e-12)[..., None], half)


def box_gap(ca: np.ndarray, cb: np.ndarray) -> np.ndarray:
    """Exact clearance between oriented rectangles (0 where they touch or overlap).

    :func:`obb_gap` of the rectangles' centres, axes and half extents.

    Parameters
    ----------
    ca, cb : ndarray, shape (..., 4, 2)
        Corners as returned by :func:`box_corners`.

    Returns
    -------
    ndarray, shape (...)
        Distance in metres, ``>= 0``.
    """
    ca, cb = np.broadcast_arrays(np.asarray(ca, dtype=float), np.asarray(cb, dtype=float))
    pa, ra, fa, ha = _frame_of(ca)
    pb, rb, fb, hb = _frame_of(cb)
    return obb_gap(pb - pa, ra, fa, ha, rb, fb, hb)


def footprint_polygon(corners: np.ndarray) -> shapely.Polygon:
    """A shapely polygon of one footprint's (4, 2) corners."""
    return shapely.Polygon(np.asarray(corners))


@dataclass(frozen=True)
class Openings:
    """Doors or windows as arrays, one row per opening.

    Attributes
    ----------
    wall : ndarray of int, shape (K,)
    centre : ndarray, shape (K, 2)
        Centre of the opening on its wall, metres.
    tangent : ndarray, shape (K, 2)
        Unit direction of the wall (from its start vertex to its end vertex).
    normal : ndarray, shape (K, 2)
        Unit normal pointing into the room.
    width : ndarray, shape (K,)
    """

    wall: np.ndarray
    centre: np.ndarray
    tangent: np.ndarray
    normal: np.ndarray
    width: np.ndarray

    def __len__(self) -> int:
        return int(self.wall.shape[0])

    @property
    def a(self) -> np.ndarray:
        """Start points of the openings on their walls, shape (K, 2)."""
        return self.centre - self.tangent * self.width[:, None] * 0.5

    @property
    def b(self) -> np.ndarray:
        """End points of the openings on their walls, shape (K, 2)."""
        return self.centre + self.tangent * self.width[:, None] * 0.5

    def centres(self, pick: int = -1) -> np.ndarray:
        """The centres of every opening (K, 2), or of opening ``pick`` alone (1, 2) where
        ``0 <= pick < K`` (the one a rule names, ``StartHint.which``)."""
        return self.centre[[pick]] if 0 <= pick < len(self) else self.centre

    def zones(self, depth: np.ndarray | float) -> tuple[np.ndarray, np.ndarray]:
        """The box in front of each opening: as wide as it, ``depth`` metres into the room.

        Parameters
        ----------
        depth : float or ndarray
            Depth of the boxes, metres, of a shape that broadcasts to ``(K, *S)``:
            a float, one per opening (K,), or one per opening and item
            ((K or 1, B): the bindings of a rule, each with its own depth).

        Returns
        -------
        centre, half : ndarray, shapes (K, *S, 2)
            Centres, and half extents along the wall (``tangent``) and into the room
            (``normal``), metres.
        """
        d = np.asarray(depth, dtype=float)
        d = d.reshape(1) if d.ndim == 0 else d
        d = np.broadcast_to(d, (len(self), *d.shape[1:]))
        axes = (slice(None),) + (None,) * (d.ndim - 1)
        centre = self.centre[axes] + self.normal[axes] * (0.5 * d)[..., None]
        half = np.stack(np.broadcast_arrays(0.5 * self.width[axes], 0.5 * d), axis=-1)
        return centre, half


#: RoomGeometry.from_room's cache: id of a plan's room -> (the room, its geometry).
_ROOMS: dict[int, tuple[Room, RoomGeometry]] = {}


def _contains_points(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Whether points (..., 2) lie inside the polygon of walls ``a`` to ``b`` (W, 2) by the
    even-odd rule, shape (...): the numpy form of :meth:`RoomGeometry.contains`."""
    x, y = p[..., 0:1], p[..., 1:2]
    ax, ay, bx, by = a[:, 0], a[:, 1], b[:, 0], b[:, 1]
    crosses = (ay > y) != (by > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        xint = ax + (y - ay) * (bx - ax) / (by - ay)
    return (np.sum(crosses & (x < xint), axis=-1) % 2) == 1


def _contains_boxes(c: np.ndarray, a: np.ndarray, b: np.ndarray,
                    normal: np.ndarray) -> np.ndarray:
    """:meth:`RoomGeometry.contains_boxes` in numpy, on rectangles (..., 4, 2) and the walls
    from ``a`` to ``b`` (W, 2) with their inward ``normal`` (each product and sum written
    out, in the order the compiled kernel does them)."""
    p0, p1, p2, p3 = c[..., 0, :], c[..., 1, :], c[..., 2, :], c[..., 3, :]
    cx = (((p0[..., 0] + p1[..., 0]) + p2[..., 0]) + p3[..., 0]) / 4.0
    cy = (((p0[..., 1] + p1[..., 1]) + p2[..., 1]) + p3[..., 1]) / 4.0
    axx, axy = p1[..., 0] - p0[..., 0], p1[..., 1] - p0[..., 1]
    ayx, ayy = p3[..., 0] - p0[..., 0], p3[..., 1] - p0[..., 1]
    lx = np.sqrt(axx * axx + axy * axy)
    ly = np.sqrt(ayx * ayx + ayy * ayy)
    hx, hy = 0.5 * lx, 0.5 * ly
    uxx, uxy = axx / np.maximum(lx, 1e-12), axy / np.maximum(lx, 1e-12)  # unit axes
    uyx, uyy = ayx / np.maximum(ly, 1e-12), ayy / np.maximum(ly, 1e-12)
    # the corners drawn in by 1e-9 m: a rectangle that touches the walls from inside (as
    # wide as the room) has them on the floor; even-odd rule against every wall
    tx, ty = np.maximum(hx - 1e-9, 0.0), np.maximum(hy - 1e-9, 0.0)
    ax_, ay_, bx_, by_ = a[:, 0], a[:, 1], b[:, 0], b[:, 1]
    inside = np.ones(c.shape[:-2], dtype=bool)
    for sx, sy in ((-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)):
        x = ((cx + (sx * tx) * uxx) + (sy * ty) * uyx)[..., None]
        y = ((cy + (sx * tx) * uxy) + (sy * ty) * uyy)[..., None]
        crosses = (ay_ > y) != (by_ > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            xint = ax_ + (y - ay_) * (bx_ - ax_) / (by_ - ay_)
        inside &= (np.sum(crosses & (x < xint), axis=-1) % 2) == 1
    # separating axes of a wall segment and a rectangle: the rectangle's two axes and the
    # wall's normal; a wall crosses a rectangle where none of them separates
    dax, day = ax_ - cx[..., None], ay_ - cy[..., None]  # (..., W)
    dbx, dby = bx_ - cx[..., None], by_ - cy[..., None]
    crossed = np.ones(dax.shape, dtype=bool)
    for ux, uy, h in ((uxx, uxy, hx), (uyx, uyy, hy)):
        ux, uy, h = ux[..., None], uy[..., None], h[..., None]
        pa = dax * ux + day * uy
        pb = dbx * ux + dby * uy
        crossed &= (np.maximum(pa, pb) > -h + 1e-9) & (np.minimum(pa, pb) < h - 1e-9)
    nx, ny = normal[:, 0], normal[:, 1]
    off = np.abs(dax * nx + day * ny)  # the centre from each wall's line
    reach = (hx[..., None] * np.abs(uxx[..., None] * nx + uxy[..., None] * ny)
             + hy[..., None] * np.abs(uyx[..., None] * nx + uyy[..., None] * ny))
    crossed &= off < reach - 1e-9
    return inside & ~crossed.any(-1)


class RoomGeometry:
    """A room's floor polygon, walls and openings as numpy arrays.

    Wall ``i`` runs from ``polygon[i]`` to ``polygon[i + 1]`` (wrapping).
    The polygon may be given in either orientation; :attr:`normal` always
    points into the room.

    Parameters
    ----------
    polygon : array_like, shape (V, 2)
        Floor polygon vertices, metres.
    height : float
        Ceiling height, metres.
    doors, windows : list of (wall, offset, width) tuples
        Openings; ``offset`` is the distance of the opening's centre from the
        wall's start vertex.
    """

    def __init__(
        self,
        polygon: np.ndarray,
        height: float = 2.7,
        doors: list[tuple[int, float, float]] | None = None,
        windows: list[tuple[int, float, float]] | None = None,
    ):
        self.polygon = np.asarray(polygon, dtype=float)
        self.height = float(height)
        self.a = self.polygon
        self.b = np.roll(self.polygon, -1, axis=0)
        d = self.b - self.a
        self.length = np.linalg.norm(d, axis=1)
        self.tangent = d / np.maximum(self.length[:, None], 1e-12)
        x, y = self.polygon[:, 0], self.polygon[:, 1]
        self.signed_area = 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
        sign = 1.0 if self.signed_area > 0 else -1.0
        # inward normal: left of the direction of travel for a CCW polygon
        self.normal = sign * np.stack([-self.tangent[:, 1], self.tangent[:, 0]], axis=1)
        #: ``a · normal`` and ``a · tangent`` per wall: ``p · normal - normal_offset`` is
        #: the distance of ``p`` from wall i's line (positive inside).
        self.normal_offset = (self.a * self.normal).sum(1)
        self.tangent_offset = (self.a * self.tangent).sum(1)
        self.doors = self._openings(doors or [])
        self.windows = self._openings(windows or [])

    @classmethod
    def from_room(cls, room: Room) -> RoomGeometry:
        """Build from a :class:`forcelayout.plan.Room` (once per room object: the arrays and
        their derived caches are shared by every layout of a plan)."""
        hit = _ROOMS.get(id(room))
        if hit is not None and hit[0] is room:
            return hit[1]
        out = cls(
            np.asarray(room.polygon, dtype=float),
            room.height,
            [(d.wall, d.offset, d.width) for d in room.doors],
            [(w.wall, w.offset, w.width) for w in room.windows],
        )
        if len(_ROOMS) > 64:
            _ROOMS.clear()
        _ROOMS[id(room)] = (room, out)
        return out

    def _openings(self, items: list[tuple[int, float, float]]) -> Openings:
        if not items:
            z2 = np.zeros((0, 2))
            return Openings(np.zeros(0, dtype=int), z2, z2, z2, np.zeros(0))
        wall = np.array([w for w, _, _ in items], dtype=int)
        offset = np.array([o for _, o, _ in items], dtype=float)
        width = np.array([w for _, _, w in items], dtype=float)
        centre = self.a[wall] + self.tangent[wall] * offset[:, None]
        return Openings(wall, centre, self.tangent[wall], self.normal[wall], width)

    @cached_property
    def door_squares(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Each door's swing square (door width deep into the room) as a box.

        Returns
        -------
        centre, right, front, half : ndarray, shapes (D, 2)
            Centre, unit axes (front points into the room) and half extents.
        """
        d = self.doors
        centre = d.centre + d.normal * d.width[:, None] * 0.5
        half = np.repeat(d.width[:, None] * 0.5, 2, axis=1)
        return centre, d.tangent.copy(), d.normal.copy(), half

    @cached_property
    def door_zones(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Each door's entry zone: its swing square plus an agent's width deeper.

        The simulation keeps furniture out of this zone (the checks only ask
        for the swing square), so the way in from a door stays open.

        Returns
        -------
        centre, right, front, half : ndarray, shapes (D, 2)
        """
        d = self.doors
        depth = d.width + ENTRY_DEPTH
        centre = d.centre + d.normal * depth[:, None] * 0.5
        half = np.stack([d.width * 0.5 + ENTRY_SIDE, depth * 0.5], axis=1)
        return centre, d.tangent.copy(), d.normal.copy(), half

    @property
    def n_walls(self) -> int:
        """Number of walls (= polygon vertices)."""
        return int(self.polygon.shape[0])

    @property
    def area(self) -> float:
        """Floor area, square metres."""
        return abs(self.signed_area)

    @cached_property
    def convex_corners(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The room's convex vertices, computed once.

        Returns
        -------
        k : ndarray of int, shape (K,)
            Vertex indices; vertex ``k`` joins wall ``k - 1`` (ending there)
            and wall ``k``.
        points : ndarray, shape (K, 2)
            Their positions, metres.
        previous : ndarray of int, shape (K,)
            The wall ending at each vertex (``k - 1`` modulo the wall count).
        angle : ndarray, shape (K,)
            Direction of wall ``k``, radians CCW.
        """
        t_prev = np.roll(self.tangent, 1, axis=0)
        cross = t_prev[:, 0] * self.tangent[:, 1] - t_prev[:, 1] * self.tangent[:, 0]
        k = np.flatnonzero(cross * np.sign(self.signed_area) > 1e-9)
        return (k, self.polygon[k], (k - 1) % self.n_walls,
                np.arctan2(self.tangent[k, 1], self.tangent[k, 0]))

    @cached_property
    def shape(self) -> shapely.Polygon:
        """The floor as a shapely polygon."""
        return shapely.Polygon(self.polygon)

    @cached_property
    def centroid(self) -> np.ndarray:
        """Floor centroid, shape (2,)."""
        c = self.shape.centroid
        return np.array([c.x, c.y])

    @cached_property
    def bounds(self) -> np.ndarray:
        """``[xmin, ymin, xmax, ymax]`` of the floor."""
        return np.array(self.shape.bounds)

    def wall_distance(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Distance from points to every wall.

        Parameters
        ----------
        points : ndarray, shape (..., 2)

        Returns
        -------
        dist : ndarray, shape (..., W)
        closest : ndarray, shape (..., W, 2)
        """
        return point_segment_distance(points[..., None, :], self.a, self.b)

    def contains_boxes(self, corners: np.ndarray) -> np.ndarray:
        """Whether rectangles lie inside the floor polygon, shape (...).

        ``corners`` (..., 4, 2) in order round each rectangle. A rectangle is
        inside when every corner is and no wall crosses it (a wall corner
        inside it, or a wall right across it: a bench over the notch of a
        U-shaped room has every corner on the floor); walls that only touch
        it do not (within 1e-9 m), as for ``shapely.contains``.

        Notes
        -----
        With numba installed (``forcelayout[fast]``) a compiled kernel computes
        it, the same for finite inputs (:mod:`forcelayout._compiled`).
        """
        c = np.asarray(corners, dtype=float)
        fast = kernels()
        if fast is not None:
            return fast.contains_boxes(c, self.a, self.b, self.normal)
        return _contains_boxes(c, self.a, self.b, self.normal)

    def contains(self, points: np.ndarray) -> np.ndarray:
        """Whether points lie inside the floor polygon (even-odd rule), shape (...).

        Notes
        -----
        With numba installed (``forcelayout[fast]``) a compiled kernel computes
        it, the same for finite inputs (:mod:`forcelayout._compiled`).
        """
        p = np.asarray(points, dtype=float)
        fast = kernels()
        if fast is not None:
            return fast.contains_points(p, self.a, self.b)
        return _contains_points(p, self.a, self.b)
