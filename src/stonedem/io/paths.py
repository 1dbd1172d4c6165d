"""Output paths checked before anything is computed: one line naming the field for a folder,
an input, a symlink loop, a name too long or a folder that cannot be written (issue 43: a
symlink loop used to end in pathlib's bare ``RuntimeError``)."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Iterable

from stonedem.errors import InputError, one_line


def _check_name_lengths(path: Path, field: str) -> None:
    """Refuse names the filesystem would refuse at the final write (ENAMETOOLONG), and names
    that are not valid text (surrogate-escaped bytes cannot be written into NetCDF attributes)."""
    text = str(path)
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        raise InputError(
            field, f"{ascii(text)} is not valid UTF-8", "give a path in UTF-8 text"
        ) from None
    name_max = 255
    try:
        name_max = os.pathconf(
            next(f for f in (path.parent, *path.parent.parents) if f.exists()), "PC_NAME_MAX"
        )
    except (OSError, ValueError, StopIteration):
        pass
    # the temporary file beside it is named ".<stem>.<8 random>.tmp<suffix>": 14 bytes more
    for part in path.parts:
        if len(os.fsencode(part)) + (14 if part == path.name else 0) > name_max:
            raise InputError(
                field,
                f"the name {part[:40]}... is longer than {name_max - 14} bytes",
                "give a shorter file or folder name",
            )
    if len(os.fsencode(str(path.absolute()))) > 4000:
        raise InputError(field, "the path is longer than 4000 bytes", "give a shorter path")


def real_path(path: str | Path, field: str) -> Path:
    """``path`` with every symlink followed, or an InputError naming ``field`` for a symlink
    loop on the way (pathlib raises a bare RuntimeError for one before Python 3.13)."""
    try:
        return Path(path).resolve()
    except (RuntimeError, OSError) as err:
        cause = err.strerror if isinstance(err, OSError) and err.strerror else "a symlink loop"
        raise InputError(
            field,
            f"{one_line(str(path), 200)} cannot be followed ({cause})",
            "give a path whose symlinks end in a file or folder",
        ) from None


def check_output_path(
    path: str | Path,
    field: str,
    *,
    inputs: Iterable[str | Path] = (),
    suffixes: tuple[str, ...] = (),
) -> Path:
    """The output path, or an InputError naming ``field`` before any computing.

    Refused: a suffix not in ``suffixes`` (when given), an existing directory, one of the
    ``inputs`` (same file, also through a symlink or a hard link), a device, pipe or socket
    (also through a symlink: the write would replace the link), a path through a symlink
    loop, a parent that is a file or cannot be created, a folder that is not writable, a name
    too long for the filesystem or not UTF-8. Nothing is created: a missing parent folder is
    made by the write itself.
    """
    if str(path).strip() in ("", "."):  # an empty argument arrives as Path(""), which is "."
        raise InputError(field, "is empty (or the working folder)", "give an output file name")
    path = Path(path)
    if any(ord(c) < 32 for c in str(path)):
        raise InputError(
            field,
            f"{str(path).encode('unicode_escape').decode()!s} contains control characters",
            "give a plain file name",
        )
    if suffixes and path.name in suffixes:  # ".nc" alone: pathlib sees a hidden file, no suffix
        raise InputError(
            field, f"{path} has no name before {path.name}", f"give a name such as out{path.name}"
        )
    if suffixes and path.suffix not in suffixes:
        raise InputError(
            field,
            f"{path} does not end in {' or '.join(suffixes)}",
            f"give an output path ending in {suffixes[0]}",
        )
    _check_name_lengths(path, field)  # before any stat(): a long name raises ENAMETOOLONG there
    real = real_path(path, field)
    if path.is_dir():
        raise InputError(field, f"{path} is a directory", "give a file name inside it")
    if (
        path.exists() and not path.is_file()
    ):  # the rename would replace a link to /dev/full unwritten
        raise InputError(
            field,
            f"{path} is not a regular file (a device, pipe or socket)",
            "give the path of a file to write",
        )
    for source in inputs:
        source = Path(source)
        try:
            same = path.exists() and source.exists() and path.samefile(source)
            source_real = source.resolve()
        except (OSError, RuntimeError):  # an input that loops is refused where it is read
            continue
        if same or real == source_real:
            raise InputError(
                field,
                f"{path} is the input file {source}",
                "give a different output path; the input would be overwritten",
            )
    parent = path.parent
    # the nearest folder that exists must take a new entry; the missing ones are created only
    # when the result is written (write_atomically), so a later refusal leaves no folder behind.
    # Probed by making and removing one entry: access() says yes to root on /proc or /sys.
    missing = []
    for folder in (parent, *parent.parents):
        if folder.exists():
            if not folder.is_dir():
                raise InputError(
                    field, f"{folder} is a file, not a folder", "give a path in a folder"
                )
            break
        missing.append(folder)
    probe = missing[-1] if missing else None
    try:
        if probe is not None:
            probe.mkdir()
            probe.rmdir()
        else:
            with tempfile.TemporaryFile(dir=parent):
                pass
    except OSError as err:
        what = (
            f"cannot create folder {probe}"
            if probe is not None
            else f"cannot write in folder {parent}"
        )
        raise InputError(
            field, f"{what} ({err.strerror})", "give a path in a writable folder"
        ) from None
    return path
