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
from types import ModuleType

from forcelayout.errors import MissingExtraError

__all__ = ["import_optional"]


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
        top = module.partition(".")[0]
        what = repr(top) if package is None else f"{package!r} (module {top!r})"
        raise MissingExtraError(
            f"this feature needs the optional package {what}, which is not installed "
            f"({e}). Install it with: pip install \"forcelayout[{extra}]\"",
            name=module,
        ) from e
