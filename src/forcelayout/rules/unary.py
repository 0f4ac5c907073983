"""Unary rules: an object related to the room (walls, corners, middle, openings)."""

from __future__ import annotations

import numpy as np
from pydantic import Field

from forcelayout import geometry as geo
from forcelayout.rules.base import ParamArrays, Rule, State

__all__ = ["AtWall"]


def _signed_angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angle from unit vectors ``a`` to ``b``, radians CCW in [-pi, pi]."""
    cross = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    dot = np.einsum("...k,...k->...", a, b)
    return np.arctan2(cross, dot)


class AtWall(Rule):
    """Back against the nearest wall, front facing into the room.

    Satisfied when the object's back edge lies within ``tolerance`` metres of
    a wall and within ``max_angle`` degrees of parallel to it.
    """

    kind = "unary"
    weight = 3.0

    class Params(Rule.Params):
        tolerance: float = Field(0.05, gt=0, description="Largest back-edge gap to the wall, m.")
        max_angle: float = Field(10.0, gt=0, le=90, description="Largest angle to the wall, deg.")

    def _nearest_wall(self, state: State, i: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        room = state.room
        d, _ = room.wall_distance(state.pos[i])  # (B, W)
        # only walls long enough to take the object's width
        short = room.length[None, :] < state.size[i, 0:1] * 0.9
        return np.argmin(np.where(short, np.inf, d), axis=1), d

    def force(self, state: State, i: np.ndarray, j: np.ndarray | None, p: ParamArrays):
        room = state.room
        wall, d = self._nearest_wall(state, i)
        n = room.normal[wall]  # inward normal of the chosen wall
        half_d = state.size[i, 1] * 0.5
        dist = d[np.arange(len(i)), wall]
        excess = np.clip(dist - half_d + 0.02, -0.1, 1.5)  # pull slightly into the wall
        f = -n * (p.weight * 4.0 * excess)[:, None]
        err = _signed_angle(state.front[i], n)
        tau = p.weight * 2.0 * err
        return f, tau

    def satisfied(self, state: State, i: np.ndarray, j: np.ndarray | None, p: ParamArrays):
        room = state.room
        c = state.corners[i]  # (B, 4, 2)
        back = c[:, :2, :]  # back-left, back-right
        d, _ = room.wall_distance(back)  # (B, 2, W)
        tang = c[:, 1, :] - c[:, 0, :]
        tang /= np.maximum(np.linalg.norm(tang, axis=1, keepdims=True), 1e-12)
        par = np.abs(np.einsum("bk,wk->bw", tang, room.tangent))  # |cos| to each wall
        ok_angle = par >= np.cos(np.radians(p.max_angle))[:, None]
        ok_dist = d.max(axis=1) <= p.tolerance[:, None]
        facing_in = np.einsum("bk,wk->bw", state.front[i], room.normal) > 0
        return np.any(ok_angle & ok_dist & facing_in, axis=1)
