"""Keep-out boxes: zones of the floor that solid objects are pushed out of.

Two kinds of zone share the push: the access zones of objects
(:mod:`forcelayout.access`) and the clearance zones in front of windows
(:class:`WindowTerm`: no floor object taller than the sill within
``Window.clearance`` metres of a window, as the ``window`` check asks). An
object in a zone is pushed out along the zone's cheaper way out: sideways
past its nearer end, or out through the zone's far side (away from the wall
or the owner).
"""

from __future__ import annotations

import numpy as np

from forcelayout import geometry as geo
from forcelayout.rules.base import State

__all__ = ["push_out", "WindowTerm"]


def push_out(f: np.ndarray, state: State, centre: np.ndarray, out: np.ndarray,
             lateral: np.ndarray, half: np.ndarray, pen: np.ndarray, active: np.ndarray,
             strength: float, slide: np.ndarray | None = None,
             cols: np.ndarray | None = None) -> None:
    """Add to ``f`` (N, 2) the push of every active (zone, object) pair out of the zone.

    Parameters
    ----------
    f : ndarray, shape (N, 2)
        Forces, added to in place.
    state : State
    centre, out, lateral : ndarray, shape (Z, 2)
        Zone centres and unit axes (``out``: away from the wall or owner).
    half : ndarray, shape (Z, 2)
        Half extents along ``lateral`` and ``out``, metres.
    pen : ndarray, shape (Z, M)
        Intrusion of each object into each zone, metres (>= 0).
    active : ndarray of bool, shape (Z, M)
        Pairs to push.
    strength : float
        Force per metre of intrusion; capped at ``0.15 * strength``.
    slide : ndarray of bool, shape (N,), optional
        Objects always pushed sideways (held at a wall: pushed along it).
    cols : ndarray of int, shape (Z, M), optional
        The row of each column of ``pen`` (a zone meets the objects of its own
        sample, :meth:`State.peers`); by default column ``m`` is row ``m``.
    """
    if not active.any():
        return
    z, c = np.nonzero(active)
    pen_zb = pen[z, c]
    b = c if cols is None else cols[z, c]
    d = state.pos[b] - centre[z]
    a = (d * lateral[z]).sum(1)
    ahead = (d * out[z]).sum(1)
    ext_a = np.abs((state.right[b] * lateral[z]).sum(1)) * state.half[b, 0] \
        + np.abs((state.front[b] * lateral[z]).sum(1)) * state.half[b, 1]
    ext_o = np.abs((state.right[b] * out[z]).sum(1)) * state.half[b, 0] \
        + np.abs((state.front[b] * out[z]).sum(1)) * state.half[b, 1]
    pen_side = half[z, 0] + ext_a - np.abs(a)  # to leave sideways
    pen_out = half[z, 1] + ext_o - ahead  # to leave through the far side
    sideways = pen_side <= pen_out
    mag = np.minimum(strength * pen_zb, 0.15 * strength)
    side_dir = lateral[z] * np.where(a >= 0, 1.0, -1.0)[:, None]
    push = np.where(sideways[:, None], side_dir, out[z])
    if slide is not None and slide[b].any():
        # an object held at a wall leaves along its wall (its own x axis): sideways past
        # the zone's end when it stands on the zone's wall, out through the far side when
        # it stands on a wall across (a fridge in the corner beside a window)
        r = state.right[b]
        along_side = np.abs((r * lateral[z]).sum(1)) >= np.abs((r * out[z]).sum(1))
        held = np.where(along_side[:, None], side_dir, out[z])
        proj = (held * r).sum(1, keepdims=True)
        held = r * np.where(proj >= 0.0, 1.0, -1.0)
        push = np.where(slide[b][:, None], held, push)
    np.add.at(f, b, push * mag[:, None])


class WindowTerm:
    """Pushes floor objects taller than a window's sill out of its clearance zone.

    Not weakened by the annealing; sampled with the rules (every
    ``SolverConfig.semantic_interval`` steps).

    Parameters
    ----------
    centre, lateral, out, half : ndarray, shape (K, 2)
        The windows' clearance zones (see
        :func:`forcelayout.validate.window_zones`).
    sill : ndarray, shape (K,)
        Sill heights, metres.
    height : ndarray, shape (N,)
        Height of each simulated object, metres.
    exempt : ndarray of bool, shape (N,)
        Rows never pushed (walkable covers).
    strength : float
        Force per metre of intrusion.
    slide : ndarray of bool, shape (N,), optional
        Rows pushed along the wall only (held at it by a hard rule).
    """

    annealed = True

    def __init__(self, centre: np.ndarray, lateral: np.ndarray, out: np.ndarray,
                 half: np.ndarray, sill: np.ndarray, height: np.ndarray, exempt: np.ndarray,
                 strength: float = 10.0, slide: np.ndarray | None = None):
        keep = half[:, 1] > 0  # a zone of depth 0 is switched off
        self.centre, self.lateral, self.out, self.half = (a[keep] for a in (
            centre, lateral, out, half))
        self.tall = (height[None, :] > sill[keep][:, None] + 1e-9) & ~exempt[None, :]
        self.strength = float(strength)
        self.slide = slide

    def stack(self, samples: int, rows: int) -> WindowTerm:
        """The same zones for ``samples`` stacked samples of ``rows`` rows each."""
        out = object.__new__(WindowTerm)
        out.centre, out.lateral, out.out, out.half = self.centre, self.lateral, self.out, \
            self.half
        out.tall = np.tile(self.tall, (1, samples))
        out.strength = self.strength
        out.slide = None if self.slide is None else np.tile(self.slide, samples)
        return out

    def __call__(self, state: State, temperature: float) -> tuple[np.ndarray, np.ndarray]:
        n = state.n
        f = np.zeros((n, 2))
        if not len(self.centre) or not self.tall.any():
            return f, np.zeros(n)
        sep = geo.obb_separation(state.pos[None, :, :] - self.centre[:, None, :],
                                 self.lateral[:, None], self.out[:, None], self.half[:, None],
                                 state.right[None], state.front[None], state.half[None])
        pen = np.maximum(0.05 - sep, 0.0)  # from 5 cm before the zone: rules lean on it
        push_out(f, state, self.centre, self.out, self.lateral, self.half, pen,
                 (pen > 0) & self.tall, self.strength, self.slide)
        return f, np.zeros(n)
