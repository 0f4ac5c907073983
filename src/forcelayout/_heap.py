"""The objects that exist before a run, left out of the cyclic collector's passes during it.

A run allocates many short-lived containers; every so often Python's cyclic
garbage collector then makes a full pass over every tracked object, and most
of those are the modules imported before the run (numpy, numba, scipy,
networkx: about 150,000 objects once a plan is solved). :func:`older_objects_frozen`
moves the objects of the moment into the collector's permanent generation
(:func:`gc.freeze`) for the length of a run and back (:func:`gc.unfreeze`) at
its end, so the passes during the run look at the run's own objects only.
Nothing is collected that would not be: garbage among the older objects waits
for the first pass after the run.
"""

from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager

__all__ = ["older_objects_frozen"]


@contextmanager
def older_objects_frozen() -> Iterator[None]:
    """Leave the objects that exist now out of the collector's passes until the block ends.

    Does nothing where the caller froze objects itself (:func:`gc.get_freeze_count`
    above zero: the block leaves those as they are, inside a run of its own too) or
    turned the collector off.

    Examples
    --------
    >>> import gc
    >>> with older_objects_frozen():
    ...     gc.get_freeze_count() > 0
    True
    >>> gc.get_freeze_count()
    0
    """
    if gc.get_freeze_count() or not gc.isenabled():
        yield
        return
    gc.freeze()
    try:
        yield
    finally:
        gc.unfreeze()
