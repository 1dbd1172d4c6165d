"""Atomic file output: write to a temporary file beside the target, then rename over it.

A run killed at any point leaves either the old file or the new one under the real name,
never a partial one. An interrupt (SIGINT, SIGTERM as :class:`stonedem.entry.Interrupted`)
while writing removes the temporary file at once: the write runs in a worker thread
(NetCDF and zlib release the GIL), so the main thread, which handles signals, is never
stuck in one long C call; the abandoned worker is recorded in :data:`abandoned` and the
command-line entry ends the process without waiting for it. Only SIGKILL can leave a
stray ``.<name>.*.tmp<suffix>`` (never read).
"""

from __future__ import annotations

import csv
import io
import os
import tempfile
import threading
from pathlib import Path
from typing import Callable, Sequence

from stonedem.errors import InputError

# temporary files being written (the signal watchdog of stonedem.entry removes them when it
# has to end the process itself)
in_progress: set[str] = set()


def remove_in_progress() -> None:
    for tmp in list(in_progress):
        Path(tmp).unlink(missing_ok=True)


# writer threads left running by an interrupt (the process should end without joining them)
abandoned: list[threading.Thread] = []


def _write_in_thread(write: Callable[[str], object], tmp: str) -> None:
    """write(tmp) in a daemon thread, waited for in short joins so signals get through."""
    failure: list[BaseException] = []

    def work():
        try:
            write(tmp)
        except BaseException as err:  # handed to the waiting thread
            failure.append(err)

    worker = threading.Thread(target=work, name="stonedem-write", daemon=True)
    worker.start()
    try:
        while worker.is_alive():
            worker.join(0.05)
    except BaseException:
        abandoned.append(worker)
        raise
    if failure:
        raise failure[0]


class WriteFailed(InputError):
    """The final write of ``path`` failed (full disk, quota, file-size limit, a filesystem
    that refuses the name...): one line naming the path and the cause; nothing is left under
    the path, and the folders the write created are removed again."""

    def __init__(self, path: Path, err: BaseException):
        if isinstance(err, OSError) and err.strerror:
            cause = err.strerror
        else:
            # netCDF4/HDF5 report a failed write(2) as "NetCDF: HDF error", without the errno
            cause = (
                f"{type(err).__name__}: {err}; a full disk, a quota or a file-size limit gives this"
            )
        super().__init__(
            str(path),
            f"cannot write the file ({cause}); nothing was written under this name",
            "free space, lift the limit or give another path",
        )


def _make_folders(folder: Path) -> list[Path]:
    """Create ``folder`` and its missing parents; returns those created, deepest first."""
    created = []
    for missing in (folder, *folder.parents):
        if missing.exists():
            break
        created.append(missing)
    folder.mkdir(parents=True, exist_ok=True)
    return created


def write_atomically(path: str | Path, write: Callable[[str], object]) -> Path:
    """Call ``write(tmp)`` on a temporary file beside ``path``, then rename it over ``path``.

    An OSError or a library's RuntimeError on the way (full disk, file-size limit) becomes
    :class:`WriteFailed`; the temporary file and any folder made for it are removed.
    """
    path = Path(path)
    created: list[Path] = []
    tmp = None
    try:
        created = _make_folders(path.parent)
        # the temporary name keeps the real suffix: matplotlib and Pillow pick the format from it
        fd, tmp = tempfile.mkstemp(
            prefix=f".{path.stem}.", suffix=f".tmp{path.suffix}", dir=path.parent
        )
        os.close(fd)
        in_progress.add(tmp)
        if threading.current_thread() is threading.main_thread():
            _write_in_thread(write, tmp)
        else:
            write(tmp)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes 0600; give the file normal permissions
        os.replace(tmp, path)
        in_progress.discard(tmp)
        tmp = None
    except (OSError, RuntimeError) as err:
        _clean(tmp, created)
        raise WriteFailed(path, err) from None
    except BaseException:
        _clean(tmp, created)
        raise
    return path


def _clean(tmp: str | None, created: list[Path]) -> None:
    if tmp is not None:
        Path(tmp).unlink(missing_ok=True)
        in_progress.discard(tmp)
    for folder in created:
        try:
            folder.rmdir()
        except OSError:
            break


def write_text(path: str | Path, text: str) -> Path:
    """Write ``text`` atomically (newlines as given)."""

    def write(tmp):
        with open(tmp, "w", newline="") as handle:
            handle.write(text)

    return write_atomically(path, write)


def write_csv(
    path: str | Path, rows: list[dict], fieldnames: Sequence[str] | None = None, restval: str = ""
) -> Path:
    """Write rows of dicts as CSV, atomically; fieldnames default to the first row's keys."""
    buffer = io.StringIO()
    writer = csv.DictWriter(
        buffer, fieldnames=list(fieldnames or (rows[0] if rows else [])), restval=restval
    )
    writer.writeheader()
    writer.writerows(rows)
    return write_text(path, buffer.getvalue())
