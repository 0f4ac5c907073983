"""Top-down pictures of layouts (PNG, SVG, PDF), headless and notebook-friendly.

Everything draws on :class:`matplotlib.figure.Figure` objects with the Agg
canvas; pyplot's global state is never touched, so drawing works on servers
without a display, in worker processes and in notebooks alike.

What a picture shows (room coordinates, metres, equal aspect):

* the floor polygon and its walls (thick lines), doors as gaps with their
  swing arc and swing square (dotted), windows as double lines;
* each floor object as its oriented footprint, filled with a colour per
  functional area (or per category when it has no area), labelled with its
  id, with a thick line on its front edge;
* walkable floor covers (rugs, mats; :attr:`SceneObject.is_walkable`) first,
  beneath the furniture, as a light translucent hatched footprint with a thin
  dashed outline and the label in a corner, so furniture standing on them
  stays visible;
* objects on top of others (dashed outline), on walls (dash-dot outline)
  and on the ceiling (dotted outline, no fill);
* optionally the cells free for the agent's centre (``show_free_space``);
* optionally each object's access zones, dashed (``show_access``), red for an
  object with none of them free;
* when the layout fails a check, the failing objects outlined in red and
  the failures listed under the plan.
"""

from __future__ import annotations

import io
import math
import re
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely
from matplotlib import colormaps, rc_context
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import to_rgba
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Arc, Patch
from matplotlib.patches import Polygon as PolygonPatch
from matplotlib.ticker import MultipleLocator

from forcelayout.geometry import box_corners

if TYPE_CHECKING:
    from forcelayout.layout import Layout

__all__ = ["draw_layout", "draw_many", "layout_svg", "save_figure", "FORMATS"]

#: File suffixes :func:`draw_layout` and :func:`draw_many` can write.
FORMATS = (".png", ".svg", ".pdf")

_WALL = "#2b2b2b"
_FAIL = "#d62728"
_ACCESS = "#1f77b4"
_FLOOR = "#f5f2eb"
_MAX_GRID = 200  # most layouts drawn in one contact sheet


def _colour_table(layout: Layout) -> dict[str, Any]:
    """A colour per functional area (or category), in a stable order."""
    plan = layout.plan
    keys: list[str] = [a.name for a in plan.areas]
    for o in plan.objects:
        k = o.area or o.category
        if k not in keys:
            keys.append(k)
    cmap = colormaps["tab20"]
    return {k: cmap((2 * i) % 20 + (i // 10) % 2) for i, k in enumerate(keys)}


def _draw_room(ax: Axes, layout: Layout) -> None:
    from forcelayout.validate.occupancy import _solid_walls

    room = layout.room
    ax.add_patch(PolygonPatch(room.polygon, closed=True, facecolor=_FLOOR, edgecolor="none",
                              zorder=0))
    sa, sb = _solid_walls(room)
    for a, b in zip(sa, sb, strict=True):
        ax.plot([a[0], b[0]], [a[1], b[1]], color=_WALL, lw=3.5, solid_capstyle="projecting",
                zorder=5)
    w = room.windows
    for k in range(len(w)):
        a, b, n = w.a[k], w.b[k], w.normal[k]
        ax.plot([a[0], b[0]], [a[1], b[1]], color="white", lw=3.5, zorder=6)
        for off in (-0.03, 0.03):
            ax.plot([a[0] + off * n[0], b[0] + off * n[0]], [a[1] + off * n[1], b[1] + off * n[1]],
                    color="#4a7fb5", lw=1.0, zorder=7)
    d = room.doors
    centre, right, front, half = room.door_squares
    sq = box_corners(centre, np.arctan2(right[:, 1], right[:, 0]), half) if len(d) else []
    for k in range(len(d)):
        hinge, width = d.a[k], float(d.width[k])
        t_ang = math.degrees(math.atan2(d.tangent[k][1], d.tangent[k][0]))
        n_ang = math.degrees(math.atan2(d.normal[k][1], d.normal[k][0]))
        lo, hi = (t_ang, n_ang) if (n_ang - t_ang) % 360 <= 180 else (n_ang, t_ang)
        ax.add_patch(Arc(tuple(hinge), 2 * width, 2 * width, theta1=lo, theta2=hi,
                         color="#8c6d46", lw=1.0, zorder=6))
        leaf = hinge + d.normal[k] * width
        ax.plot([hinge[0], leaf[0]], [hinge[1], leaf[1]], color="#8c6d46", lw=1.8, zorder=6)
        ax.add_patch(PolygonPatch(sq[k], closed=True, fill=False, edgecolor="#8c6d46",
                                  lw=0.6, ls=":", zorder=1))
        ax.annotate(f"door {k}", tuple(d.centre[k] + d.normal[k] * 0.12), fontsize=6,
                    ha="center", va="center", color="#8c6d46", zorder=8)


_COVER_Z = 1.5  # walkable covers: above the floor and door squares, below the free cells


def _draw_objects(ax: Axes, layout: Layout, labels: bool, failing: set[str]
                  ) -> tuple[dict[str, Any], set[str]]:
    """Draw every placed object; return the legend's colours and the keys of the covers."""
    colours = _colour_table(layout)
    used: dict[str, Any] = {}
    cover_keys: set[str] = set()
    styles = {"floor": ("-", 1.0, 3), "top": ("--", 0.75, 4), "wall": ("-.", 0.6, 4),
              "ceiling": (":", 0.0, 9)}
    plan = layout.plan
    ids = layout.ids()
    covers = [oid for oid in ids
              if layout.poses[oid].surface == "floor" and plan.object(oid).is_walkable]
    for oid in covers:  # first, so everything else draws over them
        obj = plan.object(oid)
        key = obj.area or obj.category
        colour = colours[key]
        used[key] = colour
        cover_keys.add(key)
        c = layout.corners(oid)
        edge = _FAIL if oid in failing else colour
        ax.add_patch(PolygonPatch(c, closed=True, facecolor=(*colour[:3], 0.22),
                                  edgecolor=edge, lw=1.4 if oid in failing else 0.8, ls="--",
                                  hatch="//", zorder=_COVER_Z, gid=f"walkable:{oid}"))
        if labels:
            at = c[3] + 0.2 * (c[1] - c[3])  # inside, near the front-left corner
            ax.text(at[0], at[1], oid, fontsize=5.5, ha="center", va="center", zorder=10,
                    color="#555555", style="italic")
    placed: list[np.ndarray] = []  # where the labels so far stand
    ymin, ymax = float(layout.room.bounds[1]), float(layout.room.bounds[3])
    for oid in ids:
        if oid in covers:
            continue
        obj = plan.object(oid)
        surf = layout.poses[oid].surface
        kind = ("floor" if surf == "floor" else "ceiling" if surf == "ceiling"
                else "wall" if surf.startswith("wall:") else "top")
        ls, alpha, z = styles[kind]
        key = obj.area or obj.category
        colour = colours[key]
        used[key] = colour
        c = layout.corners(oid)
        edge = _FAIL if oid in failing else _WALL
        face = (*colour[:3], alpha) if alpha > 0 else "none"
        ax.add_patch(PolygonPatch(c, closed=True, facecolor=face, edgecolor=edge,
                                  lw=1.6 if oid in failing else 0.9, ls=ls, zorder=z,
                                  gid=f"object:{oid}"))
        if kind != "ceiling":  # front edge: corners 2 -> 3
            ax.plot(c[2:4, 0], c[2:4, 1], color=edge, lw=2.6, solid_capstyle="butt",
                    zorder=z + 0.1)
        if labels:
            centre = _label_spot(c.mean(0), placed, (ymin, ymax))
            ax.text(centre[0], centre[1], oid, fontsize=6, ha="center", va="center",
                    zorder=10, color="#111111",
                    style="italic" if kind != "floor" else "normal")
        cover_keys.discard(key)  # the key also names furniture: a plain legend patch
    return used, cover_keys


#: How far apart two object labels stand at the least (metres: across, up), and the step
#: a label moves down by until it is so far from the others.
_LABEL_ROOM = (0.45, 0.11)


def _label_spot(centre: np.ndarray, placed: list[np.ndarray],
                bounds: tuple[float, float] = (-np.inf, np.inf)) -> np.ndarray:
    """Where an object's label goes: its centre, moved down a line at a time (at most four)
    while it would stand on a label drawn before (a pendant's over its table's), or up where
    down leaves the room's ``bounds`` (lowest, highest y: a vase on a sideboard at the
    bottom wall); the spot is kept in ``placed``."""
    base = np.array(centre, dtype=float)
    lo, hi = bounds[0] + 0.5 * _LABEL_ROOM[1], bounds[1] - 0.5 * _LABEL_ROOM[1]
    steps = [0, -1, -2, -3, -4] if base[1] - 4 * _LABEL_ROOM[1] >= lo else [0, 1, 2, 3, 4]
    at = base
    for k in steps:
        at = base + np.array([0.0, k * _LABEL_ROOM[1]])
        if not any(abs(at[0] - p[0]) < _LABEL_ROOM[0] - 1e-9
                   and abs(at[1] - p[1]) < _LABEL_ROOM[1] - 1e-9
                   for p in placed) and lo <= at[1] <= hi or k == steps[-1]:
            break
    placed.append(at)
    return at


def _draw_access(ax: Axes, layout: Layout) -> set[str]:
    """Dashed access zones, the part of each on the floor, as the ``access`` check judges
    them (:func:`forcelayout.access.zone_states`): free, blocked beside a free one (grey),
    or red for an object with none free. Returns the kinds drawn."""
    from forcelayout.access import zone_states

    zones = zone_states(layout)
    owners_free = {z.object for z in zones if z.free}
    floor = layout.room.shape
    kinds = set()
    for z in zones:
        kind = "free" if z.free else "spare" if z.object in owners_free else "blocked"
        kinds.add(kind)
        colour = to_rgba(_ACCESS_COLOURS[kind])
        on_floor = shapely.intersection(shapely.Polygon(z.corners), floor)  # none past a wall
        parts = getattr(on_floor, "geoms", [on_floor])
        for part in parts:
            if part.geom_type != "Polygon" or part.area <= 1e-9:
                continue
            ax.add_patch(PolygonPatch(np.asarray(part.exterior.coords), closed=True,
                                      facecolor=(*colour[:3], 0.12), edgecolor=colour, lw=0.6,
                                      ls="--", zorder=2.5, gid=f"access:{z.object}:{z.side}"))
    return kinds


#: Access zone colours: free, blocked while another side of the object is free, and
#: blocked with no side free (the object fails the ``access`` check).
_ACCESS_COLOURS = {"free": _ACCESS, "spare": "#8c8c8c", "blocked": _FAIL}
_ACCESS_LABELS = {"free": "access zone", "spare": "access zone, blocked (another is free)",
                  "blocked": "access zone, no side free"}


def _failing_ids(layout: Layout, failures: Sequence[str]) -> set[str]:
    quoted = {m for f in failures for m in re.findall(r"'([^']+)'", f)}
    return quoted & set(layout.poses)


def draw_layout(
    layout: Layout,
    path: str | Path | None = None,
    *,
    ax: Axes | None = None,
    labels: bool = True,
    show_free_space: bool = False,
    title: str | None = None,
    check: bool = True,
    list_failures: bool = True,
    agent_radius: float = 0.2,
    show_access: bool = False,
) -> Figure:
    """Draw a layout top-down.

    Parameters
    ----------
    layout : Layout
    path : str or Path, optional
        Write the picture there; the format follows the suffix (``.png``,
        ``.svg`` or ``.pdf``). Missing folders are created.
    ax : matplotlib Axes, optional
        Draw into this axes (e.g. a subplot of your own figure) instead of a
        new figure.
    labels : bool
        Write each object's id on it (default True).
    show_free_space : bool
        Shade the floor cells free for an agent's centre (from
        :func:`forcelayout.validate.check_layout`).
    title : str, optional
        Axes title; default ``"<plan> · seed <s>"``.
    check : bool
        Run the deterministic checks and, if the layout fails them, outline
        the failing objects in red and list the failures (default True).
    agent_radius : float
        Agent radius in metres for the checks and the free-space overlay.
    show_access : bool
        Draw each object's access zones as dashed outlines, as the ``access``
        check judges them (:func:`forcelayout.access.zone_states`), and run that
        check with the others: a free zone blue, a blocked one grey where
        another side of its object is free, red where none is.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn on (``ax.figure`` when ``ax`` is given).
    """
    room = layout.room
    xmin, ymin, xmax, ymax = (float(v) for v in room.bounds)
    if ax is None:
        span = max(xmax - xmin, ymax - ymin, 1e-6)
        fig = Figure(figsize=(6.0 * (xmax - xmin) / span + 2.2, 6.0 * (ymax - ymin) / span + 0.8))
        FigureCanvasAgg(fig)
        ax = fig.add_subplot(1, 1, 1)
    else:
        fig = ax.figure  # type: ignore[assignment]
    report = None
    if check or show_free_space or show_access:
        from forcelayout.validate import check_layout

        report = check_layout(layout, agent_radius=agent_radius,
                              access_clearance=show_access)
    failures = report.failures if (report is not None and check) else []

    _draw_room(ax, layout)
    if show_free_space and report is not None and report.free_mask is not None:
        h, w = report.free_mask.shape
        ox, oy = report.origin
        ax.imshow(np.where(report.free_mask, 1.0, np.nan), origin="lower", cmap="Greens",
                  vmin=0.0, vmax=2.0, alpha=0.45, interpolation="nearest", zorder=2,
                  extent=(ox, ox + w * report.grid, oy, oy + h * report.grid))
    used, cover_keys = _draw_objects(ax, layout, labels, _failing_ids(layout, failures))
    access_kinds: set[str] = set()
    if show_access:
        access_kinds = _draw_access(ax, layout)

    pad = 0.25
    ax.set_xlim(xmin - pad, xmax + pad)
    ax.set_ylim(ymin - pad, ymax + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.tick_params(labelsize=7)
    if max(xmax - xmin, ymax - ymin) <= 12.0:  # a tick every metre (half metres in a small
        # room doubled the labels, and text is most of a picture's drawing time)
        ax.xaxis.set_major_locator(MultipleLocator(1.0))
        ax.yaxis.set_major_locator(MultipleLocator(1.0))
    ax.set_title(title if title is not None else f"{layout.plan.name} · seed {layout.seed}",
                 fontsize=9)
    handles: list[Any] = [
        Patch(facecolor=(*c[:3], 0.22), edgecolor=c, hatch="//", ls="--", lw=0.6,
              label=f"{k} (walkable)") if k in cover_keys
        else Patch(facecolor=c, edgecolor=_WALL, lw=0.5, label=k)
        for k, c in used.items()]
    handles.append(Line2D([], [], color=_WALL, lw=2.6, label="front"))
    for kind in _ACCESS_LABELS:
        if kind in access_kinds or (kind == "free" and show_access):
            c = _ACCESS_COLOURS[kind]
            handles.append(Patch(facecolor=to_rgba(c, 0.12), edgecolor=c, ls="--", lw=0.6,
                                 label=_ACCESS_LABELS[kind]))
    if show_free_space:
        handles.append(Patch(facecolor=colormaps["Greens"](0.5), alpha=0.45,
                             label=f"free (agent r={agent_radius:g} m)"))
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=6,
              frameon=False)
    if failures and list_failures:
        shown = failures[:12] + ([f"... and {len(failures) - 12} more"]
                                 if len(failures) > 12 else [])
        ax.text(0.0, -0.1, "\n".join(shown), transform=ax.transAxes, va="top", ha="left",
                fontsize=6, color=_FAIL, wrap=True)
    if path is not None:
        save_figure(fig, path)
    return fig


def save_figure(fig: Figure, path: str | Path, *, dpi: int = 150) -> Path:
    """Write a figure; the format follows the suffix (``.png``, ``.svg``, ``.pdf``).

    Returns
    -------
    Path
        The written file.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in FORMATS:
        raise ValueError(f"cannot write a picture to {str(path)!r}: the suffix must be one of "
                         f"{', '.join(FORMATS)}")
    path.parent.mkdir(parents=True, exist_ok=True)
    if not isinstance(fig.canvas, FigureCanvasAgg):
        FigureCanvasAgg(fig)
    if suffix == ".png":
        png = _tight_png(fig, dpi)
        if png is not None:
            path.write_bytes(png)
            return path
    with rc_context({"svg.fonttype": "none", "svg.hashsalt": "forcelayout"}):
        fig.savefig(path, format=suffix[1:], dpi=dpi, bbox_inches="tight",
                    metadata={"Date": None} if suffix in (".svg", ".pdf") else None)
    return path


#: Margin kept round the drawn content of a PNG picture, inches (matplotlib's
#: ``savefig.pad_inches``, which ``bbox_inches="tight"`` keeps).
_PAD_INCHES = 0.1


def _tight_png(fig: Figure, dpi: int, *, compress_level: int = 6) -> bytes | None:
    """The figure as PNG bytes cropped to its drawn content, in one draw.

    What ``savefig(bbox_inches="tight")`` writes, but without its second draw:
    the figure is drawn once at ``dpi`` on its Agg canvas and the pixels
    outside the content's bounding box (plus ``_PAD_INCHES``, filled with the
    figure's colour where the canvas ends first) are cut away. ``None`` when
    the content itself reaches past the figure's edge (a long list of
    failures under the plan): only a redraw on a larger canvas shows it all.
    """
    from PIL import Image

    canvas = fig.canvas if isinstance(fig.canvas, FigureCanvasAgg) else FigureCanvasAgg(fig)
    old_dpi = fig.dpi
    fig.set_dpi(dpi)
    try:
        canvas.draw()
        box = fig.get_tightbbox(canvas.get_renderer())
        pixels = np.asarray(canvas.buffer_rgba())
    finally:
        fig.set_dpi(old_dpi)
    if box is None:
        return None
    height, width = pixels.shape[:2]
    if box.x0 * dpi < -0.5 or box.y0 * dpi < -0.5 or box.x1 * dpi > width + 0.5 \
            or box.y1 * dpi > height + 0.5:
        return None
    # the padded box in pixel rows and columns (rows from the top), and the canvas in it
    left, right = (int(math.floor((box.x0 - _PAD_INCHES) * dpi)),
                   int(math.ceil((box.x1 + _PAD_INCHES) * dpi)))
    top = height - int(math.ceil((box.y1 + _PAD_INCHES) * dpi))
    bottom = height - int(math.floor((box.y0 - _PAD_INCHES) * dpi))
    out = np.empty((bottom - top, right - left, 4), dtype=np.uint8)
    out[:] = np.round(np.array(to_rgba(fig.get_facecolor())) * 255).astype(np.uint8)
    r0, r1, c0, c1 = max(top, 0), min(bottom, height), max(left, 0), min(right, width)
    out[r0 - top:r1 - top, c0 - left:c1 - left] = pixels[r0:r1, c0:c1]
    opaque = bool((out[..., 3] == 255).all())  # no alpha channel needed: a quarter less
    image = Image.fromarray(np.ascontiguousarray(out[..., :3] if opaque else out),
                            "RGB" if opaque else "RGBA")
    buf = io.BytesIO()
    image.save(buf, format="png", compress_level=compress_level, dpi=(dpi, dpi))
    return buf.getvalue()


def layout_svg(layout: Layout, **kwargs: Any) -> str:
    """The layout's top-down picture as SVG text (what notebooks show inline).

    Text stays text (object ids are searchable in the SVG). Keyword
    arguments go to :func:`draw_layout`.
    """
    fig = draw_layout(layout, **kwargs)
    buf = io.StringIO()
    with rc_context({"svg.fonttype": "none", "svg.hashsalt": "forcelayout"}):
        fig.savefig(buf, format="svg", bbox_inches="tight", metadata={"Date": None})
    return buf.getvalue()


def draw_many(
    layouts: Sequence[Layout],
    path: str | Path | None = None,
    *,
    cols: int = 4,
    labels: bool = False,
    show_free_space: bool = False,
    check: bool = True,
    show_access: bool = False,
) -> Figure:
    """A contact sheet: several layouts side by side.

    Parameters
    ----------
    layouts : sequence of Layout
        At most 200 layouts.
    path : str or Path, optional
        Write the sheet there (``.png``, ``.svg`` or ``.pdf``).
    cols : int
        Layouts per row (default 4).
    labels, show_free_space, check, show_access : bool
        As in :func:`draw_layout` (labels off by default to keep cells legible).
        Each title ends with ✓ or ✗: the checks' verdict when ``check`` is
        True (the ``access`` check too with ``show_access``), else the layout's
        own ``report.valid``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    layouts = list(layouts)
    if not layouts:
        raise ValueError("draw_many: no layouts given; pass at least one Layout")
    if len(layouts) > _MAX_GRID:
        raise ValueError(f"draw_many: {len(layouts)} layouts is too many for one sheet "
                         f"(limit {_MAX_GRID}); draw them in chunks")
    if cols < 1:
        raise ValueError(f"draw_many: cols must be >= 1, got {cols}")
    cols = min(cols, len(layouts))
    rows = math.ceil(len(layouts) / cols)
    fig = Figure(figsize=(4.2 * cols, 3.8 * rows))
    FigureCanvasAgg(fig)
    axes = np.atleast_1d(fig.subplots(rows, cols, squeeze=False)).ravel()
    for ax, lay in zip(axes, layouts, strict=False):
        if check:
            from forcelayout.validate import check_layout

            valid = check_layout(lay, access_clearance=show_access).ok
        else:
            valid = lay.report.valid
        status = " ✓" if valid else " ✗"
        draw_layout(lay, ax=ax, labels=labels, show_free_space=show_free_space, check=check,
                    list_failures=False, title=f"{lay.plan.name} · seed {lay.seed}{status}",
                    show_access=show_access)
        legend = ax.get_legend()
        if legend is not None:
            legend.remove()
    for ax in axes[len(layouts):]:
        ax.set_axis_off()
    fig.tight_layout()
    if path is not None:
        save_figure(fig, path)
    return fig


def _thumbnail_png(layout: Layout, *, size: float = 1.6, dpi: int = 192) -> bytes:
    """A small top-down PNG of a layout: room and footprints, no text, legend or axes.

    Draws what :func:`draw_layout` draws with ``labels=False, check=False``
    (nothing is checked again), on a figure whose longer side is ``size``
    inches; ``dpi`` 192 gives sharp pictures on high-density screens when
    shown at 96 pixels per inch.
    """
    xmin, ymin, xmax, ymax = (float(v) for v in layout.room.bounds)
    pad = 0.25  # as draw_layout's limits
    w, h = xmax - xmin + 2 * pad, ymax - ymin + 2 * pad
    span = max(w, h)
    fig = Figure(figsize=(size * w / span, size * h / span))
    FigureCanvasAgg(fig)
    ax = fig.add_axes((0.0, 0.0, 1.0, 1.0))
    draw_layout(layout, ax=ax, labels=False, check=False, title="")
    legend = ax.get_legend()
    if legend is not None:
        legend.remove()
    for text in list(ax.texts):  # door names are unreadable at this size
        text.remove()
    ax.set_axis_off()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, metadata={"Software": None})
    return buf.getvalue()
