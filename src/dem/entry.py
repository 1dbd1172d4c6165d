"""What every command-line entry point shares: exit codes, signals, broken pipes, output paths.

- bad input (:class:`dem.errors.InputError`): one line ``error: <field>: <problem>; <fix>``,
  exit 2;
- SIGINT: exit 130, SIGTERM: exit 143 (128 + the signal number, as shells report them),
  with one line ``interrupted``; both arrive as :class:`Interrupted` (a
  ``KeyboardInterrupt``), so :func:`dem.atomic.write_atomically` removes its temporary
  file and nothing is left under the output name;
- a closed stdout (``dem ... | head``): exit quietly, no BrokenPipe traceback;
- :func:`check_output_path`: an output path is refused before any computing when it is an
  input, a directory, or in a folder that cannot be created or written.
"""

from __future__ import annotations

import os
import signal
import sys
from pathlib import Path
from typing import Callable, Iterable

from dem.errors import InputError

EXIT_INPUT = 2
EXIT_SIGINT = 128 + signal.SIGINT
EXIT_SIGTERM = 128 + signal.SIGTERM


class Interrupted(KeyboardInterrupt):
    """SIGINT or SIGTERM arrived; ``signum`` says which."""

    def __init__(self, signum: int):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


# set by the signal handler; the compiled time loop runs in chunks and checks it between them
_pending: list[int] = []


def _on_signal(signum, frame):
    _pending.append(signum)
    raise Interrupted(signum)


def install_signal_handlers() -> None:
    """SIGINT and SIGTERM raise :class:`Interrupted` in the main thread."""
    signal.signal(signal.SIGINT, _on_signal)
    signal.signal(signal.SIGTERM, _on_signal)


def interrupted() -> bool:
    """True once SIGINT or SIGTERM has arrived in this process."""
    return bool(_pending)


def guarded(command: Callable[[], int]) -> int:
    """Run ``command`` with the shared exit conventions; returns the exit status."""
    install_signal_handlers()
    try:
        status = command()
        sys.stdout.flush()
        return status
    except InputError as err:
        print(f"error: {err}", file=sys.stderr)
        return EXIT_INPUT
    except Interrupted as sig:
        print("interrupted", file=sys.stderr)
        return EXIT_SIGTERM if sig.signum == signal.SIGTERM else EXIT_SIGINT
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return EXIT_SIGINT
    except BrokenPipeError:
        # the reader went away (| head): stop writing, without a traceback at exit
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0


def check_output_path(path: str | Path, field: str, *, inputs: Iterable[str | Path] = (),
                      suffixes: tuple[str, ...] = ()) -> Path:
    """The output path, or an InputError naming ``field`` before any computing.

    Refused: a suffix not in ``suffixes`` (when given), an existing directory, one of the
    ``inputs`` (same file), a parent that is a file or cannot be created, a folder that is
    not writable. The parent folder is created when missing.
    """
    path = Path(path)
    if suffixes and path.suffix not in suffixes:
        raise InputError(field, f"{path} does not end in {' or '.join(suffixes)}",
                         f"give an output path ending in {suffixes[0]}")
    if path.is_dir():
        raise InputError(field, f"{path} is a directory", "give a file name inside it")
    for source in inputs:
        source = Path(source)
        try:
            same = path.exists() and source.exists() and path.samefile(source)
        except OSError:
            same = False
        if same or path.resolve() == source.resolve():
            raise InputError(field, f"{path} is the input file {source}",
                             "give a different output path; the input would be overwritten")
    parent = path.parent
    for folder in (parent, *parent.parents):
        if folder.exists():
            if not folder.is_dir():
                raise InputError(field, f"{folder} is a file, not a folder", "give a path in a folder")
            break
    try:
        parent.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise InputError(field, f"cannot create folder {parent} ({err.strerror})",
                         "give a path in a writable folder") from None
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(field, f"folder {parent} is not writable", "give a path in a writable folder")
    return path
