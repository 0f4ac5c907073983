"""What can be known about off-floor bindings before any simulation."""

from __future__ import annotations

from forcelayout.bindings import compile_plan
from forcelayout.errors import PlanError, Problem
from forcelayout.plan import Plan
from forcelayout.surfaces.walls import binding_walls, fits_band, free_wall_stretches, wall_band

__all__ = ["check_surfaces"]


def check_surfaces(plan: Plan) -> None:
    """Raise :class:`~forcelayout.errors.PlanError` for surface bindings that cannot be met.

    Checks, before any simulation, that each wall object fits its height
    band (above its target's top, for a wall rule with a target), that a
    pinned wall exists, and that the object is not wider than every free
    stretch of the walls it may use (doors and windows taken out).

    Raises
    ------
    PlanError
        Listing every problem with its ``rules[k]`` path.
    """
    problems: list[Problem] = []
    cp = compile_plan(plan)
    room = plan.room
    n_walls = len(room.polygon)
    ids = set(plan.ids)
    for b in cp.on("wall"):
        k = b.index
        path = f"rules[{k}] ({b.rule.name})"
        w, _, h = plan.object(b.object).size
        on_floor = b.target in ids and cp.surface_of(b.target) is None
        low, high = wall_band(b, room.height,
                              plan.object(b.target).size[2] if on_floor else None, h)
        if not fits_band(low, high, h):
            problems.append(Problem(f"{path}.params", f"{b.object!r} is {h:g} m tall but its "
                                    f"band on the wall is {low:.2f}..{high:.2f} m; lower 'low', "
                                    "raise 'high' or use a smaller object"))
            continue
        pinned = getattr(b.params, "wall", None)
        if pinned is not None and int(pinned) >= n_walls:
            problems.append(Problem(f"{path}.params.wall", f"wall {pinned} does not exist; the "
                                    f"room has walls 0..{n_walls - 1}"))
            continue
        walls = binding_walls(b, n_walls)
        widest = max((v - u for wl in walls
                      for u, v in free_wall_stretches(plan, wl, low, high, h)), default=0.0)
        if w > widest + 1e-9:
            where = f"wall {pinned}" if pinned is not None else "any wall"
            problems.append(Problem(path, f"{b.object!r} is {w:g} m wide but the widest free "
                                    f"stretch of {where} in its band {low:.2f}..{high:.2f} m "
                                    f"is {widest:.2f} m (doors and windows taken out); use a "
                                    "narrower object or another wall"
                                    + (", or raise max_gap" if on_floor
                                       and getattr(b.params, "max_gap", None) is not None
                                       else "")))
    if problems:
        raise PlanError(problems)
