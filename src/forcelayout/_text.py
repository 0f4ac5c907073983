"""Text for one line of output: what messages, hints and prompts print."""

from __future__ import annotations

__all__ = ["one_line"]


def one_line(text: str, limit: int) -> str:
    """``text`` on one line (runs of whitespace made one space), cut to at most ``limit``
    characters with ``...`` at the end where it is longer.

    Examples
    --------
    >>> one_line("a  failure\\nline", 40)
    'a failure line'
    >>> one_line("x" * 12, 10)
    'xxxxxxx...'
    """
    flat = " ".join(text.split())
    return flat if len(flat) <= limit else flat[: limit - 3].rstrip() + "..."
