"""The one helper through which every optional import goes.

Optional subpackages (``forcelayout.llm``, ``forcelayout.export``, ...) import
their third-party dependencies with :func:`import_optional`, so a missing
package turns into an ImportError that says which pip extra to install.

Examples
--------
>>> from forcelayout._optional import import_optional
>>> json = import_optional("json", "llm")      # present: the module itself
>>> json.__name__
'json'
"""

from __future__ import annotations

import importlib
import importlib.util
from types import ModuleType

from forcelayout.errors import MissingExtraError

__all__ = ["import_optional", "require_optional"]


def import_optional(module: str, extra: str, *, package: str | None = None) -> ModuleType:
    """Import ``module``, or raise an ImportError that names the extra to install.

    Parameters
    ----------
    module : str
        Dotted module name, e.g. ``"openai"``.
    extra : str
        The forcelayout pip extra that installs it, e.g. ``"llm"``.
    package : str, optional
        The pip package that provides the module when its name differs from
        the module's (``"usd-core"`` provides ``pxr``); named in the message.

    Returns
    -------
    module
        The imported module.

    Raises
    ------
    MissingExtraError
        (an :class:`ImportError`) if the module cannot be imported; the
        message reads ``pip install "forcelayout[<extra>]"``.
    """
    try:
        return importlib.import_module(module)
    except ImportError as e:
        raise _missing(module, extra, package, str(e)) from e


def require_optional(module: str, extra: str, *, package: str | None = None) -> None:
    """Check that ``module`` is installed without importing it.

    For a subpackage that imports a slow dependency only where it is used
    (``forcelayout.llm`` imports ``openai`` when a client is made), so that
    importing the subpackage still fails at once, naming the extra, but does
    not pay for the import. Parameters as :func:`import_optional`.

    Raises
    ------
    MissingExtraError
        If no installed package provides the top-level module.
    """
    top = module.partition(".")[0]
    try:
        found = importlib.util.find_spec(top) is not None
    except (ImportError, ValueError):
        found = False
    if not found:
        raise _missing(module, extra, package, f"No module named {top!r}")


def _missing(module: str, extra: str, package: str | None, why: str) -> MissingExtraError:
    top = module.partition(".")[0]
    what = repr(top) if package is None else f"{package!r} (module {top!r})"
    return MissingExtraError(
        f"this feature needs the optional package {what}, which is not installed "
        f"({why}). Install it with: pip install \"forcelayout[{extra}]\"",
        name=module,
    )
