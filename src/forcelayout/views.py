"""Views for people: printable summaries and a run's layouts as a grid of thumbnails.

:class:`Summary` is the plain-data summary of a run (a ``dict``, so it
indexes, compares and serialises to JSON as before) that also prints as an
aligned two-column table and shows as an HTML table in Jupyter.
:func:`generation_html` is what a :class:`~forcelayout.sampling.Generation`
shows in a notebook: a grid of small top-down pictures, each captioned with
its index, seed and share of rules met, above the run's summary table.
Thumbnails are drawn from the poses alone; nothing is solved or checked
again.
"""

from __future__ import annotations

import base64
import html
import math
import textwrap
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from forcelayout.sampling import Generation

__all__ = ["Summary", "generation_html", "MAX_THUMBNAILS"]

#: Most thumbnails :func:`generation_html` draws by default (the rest are counted).
MAX_THUMBNAILS = 24

_TEXT_WIDTH = 88  # plain-text table width before long values wrap


def _is_fraction(key: str) -> bool:
    return key.endswith(("_fraction", "_satisfaction", "_rate")) or key == "yield_per_try"


def _number(value: float, key: str) -> str:
    if math.isnan(value):
        return "n/a"
    if _is_fraction(key):
        return f"{value:.1%}"
    text = f"{value:.4g}"
    return f"{text} s" if key == "seconds" else text


def _value_text(value: Any, key: str = "") -> str:
    """One summary value as a short line of text."""
    if value is None:
        return "–"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return _number(value, key)
    if isinstance(value, Mapping):
        if not value:
            return "none"
        return ", ".join(f"{k} ×{v}" if isinstance(v, int) and not isinstance(v, bool)
                         else f"{k}: {_value_text(v, str(k))}" for k, v in value.items())
    if isinstance(value, list | tuple):
        if not value:
            return "none"
        if all(isinstance(v, str | int | float) for v in value):
            return "; ".join(_value_text(v, key) for v in value)
        return f"{len(value)} entries"
    return str(value)


class Summary(dict[str, Any]):
    """Counts, rates and timing of a run: a ``dict`` that also prints as a table.

    Everything a ``dict`` does still works (``summary["accepted"]``,
    ``json.dumps(summary)``, comparison with a plain dict); ``str()`` gives
    an aligned two-column text table, one key a line, and Jupyter shows an
    HTML table. Fractions print as percentages and ``seconds`` with its
    unit; the values themselves are left as they are.

    Examples
    --------
    >>> s = Summary({"plan": "bedroom", "accepted": 3, "valid_fraction": 0.75,
    ...              "failure_reasons": {"collision": 2}})
    >>> print(s)
    plan             bedroom
    accepted         3
    valid_fraction   75.0%
    failure_reasons  collision ×2
    >>> s["accepted"]
    3
    """

    def rows(self) -> list[tuple[str, str]]:
        """``(key, value as text)`` pairs, in the dict's order."""
        return [(str(k), _value_text(v, str(k))) for k, v in self.items()]

    def __str__(self) -> str:
        rows = self.rows()
        if not rows:
            return "(empty summary)"
        width = max(len(k) for k, _ in rows) + 2
        lines: list[str] = []
        for key, text in rows:
            wrapped = textwrap.wrap(text, max(_TEXT_WIDTH - width, 24)) or [""]
            lines.append(f"{key:<{width}}{wrapped[0]}")
            lines.extend(" " * width + more for more in wrapped[1:])
        return "\n".join(lines)

    def _repr_html_(self) -> str:
        return _table_html(self.rows())


def _table_html(rows: list[tuple[str, str]]) -> str:
    cells = "".join(
        f'<tr><th style="text-align:left;padding-right:1em">{html.escape(k)}</th>'
        f'<td style="text-align:left">{html.escape(v)}</td></tr>' for k, v in rows)
    return f'<table class="forcelayout-summary">{cells}</table>'


def generation_html(generation: Generation, *, limit: int = MAX_THUMBNAILS,
                    size: float = 1.6) -> str:
    """A run as HTML: a grid of thumbnails, then its summary as a table.

    Parameters
    ----------
    generation : Generation
        The result of :func:`forcelayout.generate`.
    limit : int
        Draw at most this many layouts (the first ones); the others are
        counted in a line under the grid.
    size : float
        Longer side of each thumbnail, inches at 96 pixels per inch.

    Returns
    -------
    str
        An HTML fragment: a header line (layouts, samples, seed, seconds),
        the hint when fewer layouts were accepted than wanted, one ``<img>``
        (a base64 PNG) per drawn layout captioned ``#index · seed s`` and
        the share of its rules met, and the summary table. A run without
        layouts shows why it is empty instead of the grid.
    """
    from forcelayout.render import _thumbnail_png

    if limit < 0:
        raise ValueError(f"limit must be >= 0, got {limit}")
    gen = generation
    k = len(gen.layouts)
    of = f" of {gen.wanted}" if gen.wanted is not None else ""
    noun = "layout" if (gen.wanted if gen.wanted is not None else k) == 1 else "layouts"
    head = (f"<p><b>{k}{of} {noun}</b> of plan "
            f"<code>{html.escape(gen.plan.name)}</code> from {gen.attempted} sample"
            f"{'s' if gen.attempted != 1 else ''} · seed {gen.seed} · {gen.seconds:.2f} s</p>")
    parts = [head]
    if not gen.layouts:
        parts.append(f'<p style="color:#b00020">{html.escape(gen._empty_message())}</p>')
    else:
        hint = gen.hint()
        if hint is not None:
            parts.append(f'<p style="color:#8a5a00">{html.escape(hint)}</p>')
        px = round(96 * size)
        cells = []
        for i, lay in enumerate(gen.layouts[:limit]):
            data = base64.b64encode(_thumbnail_png(lay, size=size)).decode("ascii")
            rules = f"{lay.report.rule_satisfaction:.0%} of rules met"
            mark = "" if lay.report.valid else " · ✗ invalid"
            cells.append(
                f'<figure style="margin:0;width:{px}px;text-align:center">'
                f'<img src="data:image/png;base64,{data}" style="max-width:{px}px;'
                f'max-height:{px}px" alt="layout {i}, seed {lay.seed}"/>'
                f'<figcaption style="font-size:11px;line-height:1.3;word-break:break-all">'
                f"#{i} · seed {lay.seed}<br/>{rules}{mark}</figcaption></figure>")
        parts.append('<div style="display:flex;flex-wrap:wrap;gap:10px;align-items:flex-end">'
                     + "".join(cells) + "</div>")
        if k > limit:
            parts.append(f"<p>… and {k - limit} more (<code>generation[{limit}:]</code>)</p>")
    parts.append(gen.summary()._repr_html_())
    return '<div class="forcelayout-generation">' + "".join(parts) + "</div>"
