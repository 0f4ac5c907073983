"""Atomic writes: a file or folder appears under its final name only when complete.

Everything is first written under a temporary name in the same folder (so the
final rename stays on one file system) and then moved into place with
:func:`os.replace`. A process killed half-way leaves at most a temporary
``.<name>.<pid>.<token>.tmp...`` entry, never a half-written file under the
final name.
"""

from __future__ import annotations

import os
import secrets
import shutil
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

__all__ = ["atomic_path", "atomic_dir", "write_bytes", "write_text", "TMP_MARK"]

#: Part of every temporary name (``.<name>.<pid>.<token>.tmp<suffix>``).
TMP_MARK = ".tmp"


def _temporary_name(path: Path) -> Path:
    token = f"{os.getpid()}.{secrets.token_hex(4)}"
    # the suffix is kept last: some writers (USD) pick the file format by it
    return path.with_name(f".{path.name}.{token}{TMP_MARK}{path.suffix}")


@contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """A temporary path to write ``path``'s content to; moved onto ``path`` on success.

    The temporary file is in ``path``'s folder (created if missing) and ends
    with the same suffix. If the block raises, it is removed and ``path`` is
    left as it was.

    Examples
    --------
    >>> import tempfile
    >>> target = Path(tempfile.mkdtemp()) / "a.txt"
    >>> with atomic_path(target) as tmp:
    ...     _ = tmp.write_text("done")
    >>> target.read_text()
    'done'
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = _temporary_name(path)
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


@contextmanager
def atomic_dir(path: str | Path) -> Iterator[Path]:
    """A temporary folder to fill; renamed to ``path`` when the block ends without error.

    An existing ``path`` is replaced: it is first renamed aside, the new
    folder renamed into place, then the old one deleted, so ``path`` is always
    either the old complete folder, missing, or the new complete folder.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = _temporary_name(path)
    tmp.mkdir()
    try:
        yield tmp
        if path.exists():
            old = _temporary_name(path)
            os.replace(path, old)
            os.replace(tmp, path)
            shutil.rmtree(old, ignore_errors=True)
        else:
            os.replace(tmp, path)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


def write_bytes(path: str | Path, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically; returns ``path``."""
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_bytes(data)
    return path


def write_text(path: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically; returns ``path``."""
    return write_bytes(path, text.encode("utf-8"))
