"""Compiled kernels of the hottest footprint geometry, used when numba is installed.

``pip install "forcelayout[fast]"`` adds numba; :mod:`forcelayout.geometry`
then computes :func:`~forcelayout.geometry.obb_separation` and
:func:`~forcelayout.geometry.obb_gap` (and whether footprints lie on a
floor that is not a rectangle,
:meth:`~forcelayout.geometry.RoomGeometry.contains_boxes`, and whether points lie on
it, :meth:`~forcelayout.geometry.RoomGeometry.contains`) with the numba
generalised ufuncs below instead of a few dozen numpy operations on
temporaries, and
:mod:`forcelayout.validate` the distance of every free-floor grid cell to
every footprint with a compiled loop. The ufuncs broadcast like the numpy
forms; every kernel does the same floating-point operations in the same
order and precision, so results are the same bit for bit
(tests/test_geometry.py checks it): layouts do not depend on whether numba
is installed.

The kernels compile on first use and numba caches the machine code on disk
(next to this file, or in the user's cache directory where that is not
writable), so later processes load it in about half a second. Processes
compile or load it one at a time, under a lock file in the temporary folder:
two that compiled at once could leave a cache that crashed every later
process (:func:`_one_at_a_time`). The
environment variable ``FORCELAYOUT_COMPILED`` chooses: unset, the kernels
are used when numba is installed; ``0``, the numpy forms are used even
then; ``1``, numba is required (an ImportError names the extra).
"""

from __future__ import annotations

import math
import os
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from types import SimpleNamespace
from typing import Any

import numpy as np

__all__ = ["kernels", "ENV"]

#: Environment variable that switches the compiled kernels off (``0``).
ENV = "FORCELAYOUT_COMPILED"

_LOADED: list[Any] = []  # [namespace of kernels, or None when numba is absent or off]


def kernels() -> SimpleNamespace | None:
    """The compiled kernels (``obb_separation``, ``obb_gap``, ``footprint_dist2``,
    ``contains_boxes``, ``contains_points``), or None without numba.

    Compiled (or loaded from numba's cache) on the first call in a process.
    """
    if not _LOADED:
        want = os.environ.get(ENV, "").strip()
        _LOADED.append(None if want == "0" else _compile(required=want == "1"))
    return _LOADED[0]


#: Seconds a process waits for another that compiles the kernels before it compiles them
#: without waiting any longer.
_LOCK_WAIT = 300.0


@contextmanager
def _one_at_a_time() -> Iterator[None]:
    """Holds a lock file that processes of this machine compile (or load) the kernels under,
    one at a time.

    numba's cache of a generalised ufunc is two files, the kernel's and its
    wrapper's, and the wrapper names the kernel by a version tag that counts
    the functions the process has compiled so far. Two processes that compile
    at once (the workers of a pool on a fresh install, finding the other's
    kernels half written) can leave a wrapper of one beside a kernel of the
    other: every later process that loads them calls a null pointer and
    crashes (numba issue 10128). Under the lock, the first process compiles
    every kernel and writes both files of each; the next ones load them.
    Where no lock file can be opened (a read-only temporary folder, no
    ``fcntl``), or the lock is held for longer than ``_LOCK_WAIT`` seconds,
    the kernels are compiled without it.
    """
    try:
        import fcntl
    except ImportError:  # not a POSIX system
        yield
        return
    path = os.path.join(tempfile.gettempdir(), "forcelayout-kernels.lock")
    try:
        handle = open(path, "a+")  # noqa: SIM115 - closed below, after the lock is released
    except OSError:
        yield
        return
    held = False
    try:
        deadline = time.monotonic() + _LOCK_WAIT
        while True:
            try:
                fcntl.flock(handle.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
                held = True
                break
            except OSError:
                if time.monotonic() > deadline:
                    break
                time.sleep(0.05)
        yield
    finally:
        if held:
            fcntl.flock(handle.fileno(), fcntl.LOCK_UN)
        handle.close()


def _compile(*, required: bool) -> SimpleNamespace | None:
    try:
        import numba  # noqa: F401 - only whether it is installed
    except ImportError:
        if required:
            from forcelayout._optional import import_optional

            import_optional("numba", "fast")  # raises, naming the extra
        return None
    with _one_at_a_time():
        return _build()


def _build() -> SimpleNamespace:
    """Compiles the kernels, or loads them from numba's cache."""
    from numba import boolean, float32, float64, guvectorize, njit

    sig = [(float64[:],) * 8]
    layout = "(n),(n),(n),(n),(n),(n),(n)->()"

    @guvectorize(sig, layout, nopython=True, cache=True)
    def obb_separation(d, ra, fa, ha, rb, fb, hb, out):  # pragma: no cover - compiled
        # geometry.obb_separation, one pair at a time, operation for operation
        c = abs(ra[0] * rb[0] + ra[1] * rb[1])
        s = abs(ra[0] * fb[0] + ra[1] * fb[1])
        hax, hay, hbx, hby = ha[0], ha[1], hb[0], hb[1]
        g1 = abs(d[0] * ra[0] + d[1] * ra[1]) - hax - (hbx * c + hby * s)
        g2 = abs(d[0] * fa[0] + d[1] * fa[1]) - hay - (hbx * s + hby * c)
        g3 = abs(d[0] * rb[0] + d[1] * rb[1]) - hbx - (hax * c + hay * s)
        g4 = abs(d[0] * fb[0] + d[1] * fb[1]) - hby - (hax * s + hay * c)
        out[0] = max(max(g1, g2), max(g3, g4))

    @guvectorize(sig, layout, nopython=True, cache=True)
    def obb_gap(d, ra, fa, ha, rb, fb, hb, out):  # pragma: no cover - compiled
        # geometry.obb_gap, one pair at a time: each rectangle's corners in the other's
        # frame (corners back-left, back-right, front-right, front-left)
        rr = ra[0] * rb[0] + ra[1] * rb[1]
        rf = ra[0] * fb[0] + ra[1] * fb[1]
        fr = fa[0] * rb[0] + fa[1] * rb[1]
        ff = fa[0] * fb[0] + fa[1] * fb[1]
        bcx = d[0] * ra[0] + d[1] * ra[1]
        bcy = d[0] * fa[0] + d[1] * fa[1]
        acx = -(d[0] * rb[0] + d[1] * rb[1])
        acy = -(d[0] * fb[0] + d[1] * fb[1])
        hax, hay, hbx, hby = ha[0], ha[1], hb[0], hb[1]
        bu, bv, bu2, bv2 = hbx * rr, hby * rf, hbx * fr, hby * ff  # B: axes (rr, fr), (rf, ff)
        au, av, au2, av2 = hax * rr, hay * fr, hax * rf, hay * ff  # A: axes (rr, rf), (fr, ff)
        bx_lo = by_lo = ax_lo = ay_lo = math.inf
        bx_hi = by_hi = ax_hi = ay_hi = -math.inf
        db = da = math.inf
        for k in range(4):
            su = -1.0 if k == 0 or k == 3 else 1.0
            sv = -1.0 if k < 2 else 1.0
            bx = bcx + su * bu + sv * bv
            by = bcy + su * bu2 + sv * bv2
            ax = acx + su * au + sv * av
            ay = acy + su * au2 + sv * av2
            bx_lo, bx_hi = min(bx_lo, bx), max(bx_hi, bx)
            by_lo, by_hi = min(by_lo, by), max(by_hi, by)
            ax_lo, ax_hi = min(ax_lo, ax), max(ax_hi, ax)
            ay_lo, ay_hi = min(ay_lo, ay), max(ay_hi, ay)
            ex, ey = max(abs(bx) - hax, 0.0), max(abs(by) - hay, 0.0)
            gx, gy = max(abs(ax) - hbx, 0.0), max(abs(ay) - hby, 0.0)
            db = min(db, ex * ex + ey * ey)
            da = min(da, gx * gx + gy * gy)
        sep = max(max(max(bx_lo - hax, -hax - bx_hi), max(by_lo - hay, -hay - by_hi)),
                  max(max(ax_lo - hbx, -hbx - ax_hi), max(ay_lo - hby, -hby - ay_hi)))
        out[0] = math.sqrt(min(db, da)) if sep > 0.0 else 0.0

    v = float32[::1]

    @njit(float32[:, :, ::1](v, v, v, v, v, v, v, v), cache=True)
    def footprint_dist2(xs, ys, px, py, c, s, hx, hy):  # pragma: no cover - compiled
        # validate.occupancy._footprint_dist2, in float32 as there: cell (h, w) against
        # footprint n, whose cosine and sine numpy gives
        n_obj, n_y, n_x = px.shape[0], ys.shape[0], xs.shape[0]
        out = np.empty((n_obj, n_y, n_x), dtype=np.float32)
        zero = np.float32(0.0)
        for n in range(n_obj):
            cn, sn, hxn, hyn = c[n], s[n], hx[n], hy[n]
            for h in range(n_y):
                dy = ys[h] - py[n]
                for w in range(n_x):
                    dx = xs[w] - px[n]
                    qx = max(abs(dx * cn + dy * sn) - hxn, zero)
                    qy = max(abs(dy * cn - dx * sn) - hyn, zero)
                    out[n, h, w] = qx * qx + qy * qy
        return out

    m = float64[:, :]

    @guvectorize([(m, m, m, m, boolean[:])], "(k,t),(w,t),(w,t),(w,t)->()", nopython=True,
                 cache=True)
    def contains_boxes(c, a, b, normal, out):  # pragma: no cover - compiled
        # geometry._contains_boxes, one rectangle at a time, operation for operation
        cx = (((c[0, 0] + c[1, 0]) + c[2, 0]) + c[3, 0]) / 4.0
        cy = (((c[0, 1] + c[1, 1]) + c[2, 1]) + c[3, 1]) / 4.0
        axx, axy = c[1, 0] - c[0, 0], c[1, 1] - c[0, 1]
        ayx, ayy = c[3, 0] - c[0, 0], c[3, 1] - c[0, 1]
        lx = math.sqrt(axx * axx + axy * axy)
        ly = math.sqrt(ayx * ayx + ayy * ayy)
        hx, hy = 0.5 * lx, 0.5 * ly
        uxx, uxy = axx / max(lx, 1e-12), axy / max(lx, 1e-12)
        uyx, uyy = ayx / max(ly, 1e-12), ayy / max(ly, 1e-12)
        tx, ty = max(hx - 1e-9, 0.0), max(hy - 1e-9, 0.0)
        n_wall = a.shape[0]
        inside = True
        for k in range(4):
            sx = -1.0 if k == 0 or k == 3 else 1.0
            sy = -1.0 if k < 2 else 1.0
            x = (cx + (sx * tx) * uxx) + (sy * ty) * uyx
            y = (cy + (sx * tx) * uxy) + (sy * ty) * uyy
            odd = False
            for w in range(n_wall):
                if (a[w, 1] > y) != (b[w, 1] > y):
                    if x < a[w, 0] + (y - a[w, 1]) * (b[w, 0] - a[w, 0]) / (b[w, 1] - a[w, 1]):
                        odd = not odd
            inside = inside and odd
        crossed = False
        for w in range(n_wall):
            dax, day = a[w, 0] - cx, a[w, 1] - cy
            dbx, dby = b[w, 0] - cx, b[w, 1] - cy
            pa, pb = dax * uxx + day * uxy, dbx * uxx + dby * uxy
            hit = (max(pa, pb) > -hx + 1e-9) and (min(pa, pb) < hx - 1e-9)
            pa, pb = dax * uyx + day * uyy, dbx * uyx + dby * uyy
            hit = hit and (max(pa, pb) > -hy + 1e-9) and (min(pa, pb) < hy - 1e-9)
            nx, ny = normal[w, 0], normal[w, 1]
            off = abs(dax * nx + day * ny)
            reach = hx * abs(uxx * nx + uxy * ny) + hy * abs(uyx * nx + uyy * ny)
            crossed = crossed or (hit and off < reach - 1e-9)
        out[0] = inside and not crossed

    @guvectorize([(float64[:], m, m, boolean[:])], "(t),(w,t),(w,t)->()", nopython=True,
                 cache=True)
    def contains_points(p, a, b, out):  # pragma: no cover - compiled
        # geometry.RoomGeometry.contains, one point at a time, operation for operation
        x, y = p[0], p[1]
        odd = False
        for w in range(a.shape[0]):
            if (a[w, 1] > y) != (b[w, 1] > y):
                if x < a[w, 0] + (y - a[w, 1]) * (b[w, 0] - a[w, 0]) / (b[w, 1] - a[w, 1]):
                    odd = not odd
        out[0] = odd

    return SimpleNamespace(obb_separation=obb_separation, obb_gap=obb_gap,
                           footprint_dist2=footprint_dist2, contains_boxes=contains_boxes,
                           contains_points=contains_points)
