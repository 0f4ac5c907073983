"""Topological dissimilarity: Jaccard distance of the floors' inflated occupancy masks.

A floor cell is occupied when it lies within the agent's radius of an object
standing on the floor; two layouts differ topologically where their free
floor differs. Units: metres.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from forcelayout.layout import Layout
from forcelayout.metrics.jaccard import jaccard_matrix

__all__ = ["occupancy_masks", "topological_dissimilarity"]


def occupancy_masks(
    layouts: Sequence[Layout],
    *,
    agent_radius: float = 0.2,
    grid: float = 0.05,
) -> tuple[np.ndarray, np.ndarray]:
    """Occupancy masks of several layouts on one shared grid.

    A cell is *occupied* when its centre lies inside the layout's floor
    polygon and within ``agent_radius`` of the footprint of an object standing
    on the floor (:func:`forcelayout.validate.occupancy_mask`). Objects on
    other objects, walls or the ceiling are not obstacles; walls are not
    marked. Each layout's mask is placed on a canvas covering all of their
    grids, so masks of different rooms are comparable cell by cell.

    Parameters
    ----------
    layouts : sequence of Layout
    agent_radius : float
        Inflation of every footprint, metres (the agent's radius).
    grid : float
        Cell size, metres.

    Returns
    -------
    masks : ndarray of bool, shape (K, H, W)
        Row ``r``, column ``c`` is the cell centred at
        ``origin + ((c + 0.5)·grid, (r + 0.5)·grid)``.
    origin : ndarray, shape (2,)
        Room coordinates of the canvas's lower-left corner, metres.
    """
    from forcelayout.validate import occupancy_mask

    if not (agent_radius >= 0 and np.isfinite(agent_radius)):
        raise ValueError(f"agent_radius must be >= 0 metres, got {agent_radius}")
    if not (grid > 0 and np.isfinite(grid)):
        raise ValueError(f"grid must be a positive cell size in metres, got {grid}")
    if not layouts:
        return np.zeros((0, 0, 0), dtype=bool), np.zeros(2)
    parts = [occupancy_mask(lay, agent_radius=agent_radius, grid=grid) for lay in layouts]
    lo = np.min([o for _, o in parts], axis=0)
    offs = [np.rint((o - lo) / grid).astype(int) for _, o in parts]  # (col, row) offsets
    h = max(off[1] + m.shape[0] for (m, _), off in zip(parts, offs, strict=True))
    w = max(off[0] + m.shape[1] for (m, _), off in zip(parts, offs, strict=True))
    masks = np.zeros((len(parts), h, w), dtype=bool)
    for k, ((m, _), off) in enumerate(zip(parts, offs, strict=True)):
        masks[k, off[1]: off[1] + m.shape[0], off[0]: off[0] + m.shape[1]] = m
    return masks, lo


def topological_dissimilarity(
    a: Layout, b: Layout, *, agent_radius: float = 0.2, grid: float = 0.05
) -> float:
    """Jaccard distance between the two layouts' inflated occupancy masks, in ``[0, 1]``.

    ``1 − |A ∩ B| / |A ∪ B|`` over the occupied cells of
    :func:`occupancy_masks` (0 when neither floor has obstacles).

    Parameters
    ----------
    a, b : Layout
    agent_radius : float
        Obstacle inflation, metres (default 0.2 m as in the paper).
    grid : float
        Cell size, metres.
    """
    masks, _ = occupancy_masks([a, b], agent_radius=agent_radius, grid=grid)
    return float(jaccard_matrix(masks.reshape(2, -1))[0, 1])
