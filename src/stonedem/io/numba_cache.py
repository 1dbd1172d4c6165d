"""Numba's cache files, read so that a damaged one costs a compile, not every later run
(issue 43).

Numba unpickles a cached kernel's index (``.nbi``) and code (``.nbc``) on the kernel's first
call and lets any error through: an empty or truncated file (a full disk, a killed copy)
raised ``EOFError`` or ``UnpicklingError`` from every run until the user deleted
``~/.cache/stonedem/numba``. :func:`guard` wraps Numba's two readers: a file that does not
unpickle is moved aside (``<name>.damaged``; left in place where the folder is read-only),
the kernel is compiled again and Numba writes a fresh entry. One line on stderr says so,
once per process.
"""

from __future__ import annotations

import os
import pickle
import sys

from numba.core import caching

# what unpickling a cut or garbled pickle raises (OSError stays Numba's: a missing file is
# no entry, a refused one is an error worth seeing)
DAMAGED = (
    EOFError,
    pickle.UnpicklingError,
    ValueError,
    TypeError,
    AttributeError,
    ImportError,
    IndexError,
    KeyError,
)
_WARNED: list[str] = []


def _set_aside(path: str, err: BaseException) -> None:
    aside = f"{path}.damaged"
    try:
        os.replace(path, aside)
        what = f"moved to {os.path.basename(aside)}"
    except OSError as move:
        what = f"left in place ({move.strerror})"
    if not _WARNED:  # one line per process, however many files were hit
        _WARNED.append(path)
        try:
            print(
                f"warning: compiled-kernel cache file {path} is damaged "
                f"({type(err).__name__}); {what}, "
                f"compiling the kernel again",
                file=sys.stderr,
                flush=True,
            )
        except (OSError, ValueError):
            pass  # a closed stderr must not end the run


def guard() -> None:
    """Wrap Numba's cache readers (once; idempotent)."""
    cls = caching.IndexDataCacheFile
    if getattr(cls, "_stonedem_guarded", False):
        return
    if not (hasattr(cls, "_load_index") and hasattr(cls, "_load_data")):
        return  # another Numba's internals: its own behaviour stands (numba 0.58-0.68 have both)
    load_index, load_data = cls._load_index, cls._load_data

    def _load_index(self):
        try:
            return load_index(self)
        except DAMAGED as err:
            _set_aside(self._index_path, err)
            return {}  # no entries: compile, and Numba writes a new index

    def _load_data(self, name):
        try:
            return load_data(self, name)
        except DAMAGED as err:
            _set_aside(self._data_path(name), err)
            return None  # no entry: compile, and Numba writes new data

    cls._load_index, cls._load_data = _load_index, _load_data
    cls._stonedem_guarded = True
