"""What every command-line entry point shares: exit codes, signals, broken pipes, output paths.

- bad input (:class:`stonedem.errors.InputError`): one line ``error: <field>: <problem>; <fix>``,
  exit 2;
- SIGINT: exit 130, SIGTERM: exit 143 (128 + the signal number, as shells report them),
  with one line ``interrupted``; both arrive as :class:`Interrupted` (a
  ``KeyboardInterrupt``), so :func:`stonedem.io.atomic.write_atomically` removes its temporary
  file and nothing is left under the output name;
- a closed stdout (``stonedem ... | head``): exit quietly, no BrokenPipe traceback;
- :func:`check_output_path`: an output path is refused before any computing when it is an
  input, a directory, or in a folder that cannot be created or written.
"""

from __future__ import annotations

import argparse
import functools
import os
import signal
import sys
import threading
import time
from contextlib import contextmanager
from pathlib import Path
from typing import Callable, Iterable

from stonedem.errors import InputError, one_line

EXIT_INPUT = 2
EXIT_SIGINT = 128 + signal.SIGINT
EXIT_SIGTERM = 128 + signal.SIGTERM


class Interrupted(KeyboardInterrupt):
    """SIGINT or SIGTERM arrived; ``signum`` says which."""

    def __init__(self, signum: int):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


# set by the signal handlers; loops that call compiled code check it between calls
_pending: list[int] = []
SIGNALS = (signal.SIGINT, signal.SIGTERM)
_depth = [0]


def _on_signal(signum, frame):
    _pending.append(signum)
    raise Interrupted(signum)


def _record(signum, frame):
    _pending.append(signum)


def check_interrupt() -> None:
    """Raise :class:`Interrupted` if SIGINT or SIGTERM arrived during a deferred section."""
    if _pending:
        signum = _pending[0]
        _pending.clear()
        raise Interrupted(signum)


@contextmanager
def deferred_signals():
    """Within: SIGINT/SIGTERM handlers that raise are swapped for ones that only record, and
    the loop calls :func:`check_interrupt` between compiled calls; on leaving, the handlers
    are restored and a signal still pending is raised.

    An exception raised by a handler while numba's dispatcher is inside a compiled call
    corrupts the dispatcher (measured on the wall solver: ``SystemError: ... returned a
    result with an exception set``, exit 1 instead of 130, and ``free(): double free`` under
    an interrupt storm). Ignored and default dispositions are left alone.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    saved = {}
    if _depth[0] == 0:
        _pending.clear()
        for signum in SIGNALS:
            handler = signal.getsignal(signum)
            if callable(handler):  # not SIG_IGN / SIG_DFL / None (set outside Python)
                saved[signum] = handler
                signal.signal(signum, _record)
    _depth[0] += 1
    try:
        yield
    finally:
        _depth[0] -= 1
        for signum, handler in saved.items():
            signal.signal(signum, handler)
    check_interrupt()


def interruptible(func):
    """Run ``func`` inside :func:`deferred_signals`."""

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        with deferred_signals():
            return func(*args, **kwargs)
    return wrapper


# the main thread gets this long to act on a signal itself (exception, temporary files
# removed on the way out) before the watchdog ends the process; a Python handler waits
# for the interpreter, which a long C call (LLVM compiling the time loop) can hold ~1 s
GRACE_SECONDS = 0.5


def _watchdog(sock) -> None:
    """Wake on every signal (written by C to the wakeup socket at once, whatever the main
    thread is doing); if the process is still alive GRACE_SECONDS later, remove the
    temporary files in progress and end it with 128 + signum."""
    import time

    from stonedem.io import atomic

    while True:
        try:
            data = sock.recv(1)
        except OSError:
            return
        if not data or data[0] not in (signal.SIGINT, signal.SIGTERM):
            continue
        time.sleep(GRACE_SECONDS)
        atomic.remove_in_progress()
        try:
            os.write(2, b"interrupted\n")
        finally:
            os._exit(128 + data[0])


def install_signal_handlers() -> Callable[[], None]:
    """SIGINT and SIGTERM raise :class:`Interrupted` in the main thread, and a watchdog
    thread makes sure the process ends within about a second even when the main thread is
    inside a long C call. Returns a function that puts the previous handling back."""
    import socket

    if threading.current_thread() is not threading.main_thread():
        return lambda: None
    previous = signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)
    signal.signal(signal.SIGINT, _on_signal)
    signal.signal(signal.SIGTERM, _on_signal)
    read_end, write_end = socket.socketpair()
    write_end.setblocking(False)
    previous_fd = signal.set_wakeup_fd(write_end.fileno(), warn_on_full_buffer=False)
    threading.Thread(target=_watchdog, args=(read_end,), name="stonedem-signal-watchdog", daemon=True).start()

    def restore():
        signal.set_wakeup_fd(previous_fd)
        signal.signal(signal.SIGINT, previous[0])
        signal.signal(signal.SIGTERM, previous[1])
        write_end.close()
        read_end.close()

    return restore


class Parser(argparse.ArgumentParser):
    """argparse with one-line usage errors (exit 2), like every other input error."""

    def error(self, message):
        self.exit(EXIT_INPUT, f"error: {self.prog}: {one_line(message)}; see {self.prog} --help\n")


def progress_print(stream, text: str, end: str = "\n"):
    """Write a progress line; returns the stream, or None once it is closed (progress is best
    effort: a closed stderr must not end the run)."""
    if stream is None:
        return None
    try:
        print(text, end=end, file=stream, flush=True)
    except (OSError, ValueError):
        return None
    return stream


@contextmanager
def logged_seconds(stream, label: str):
    """Time the block and write ``label: N.NN s`` to stream (a batch job's line per item)."""
    start = time.perf_counter()
    yield
    progress_print(stream, f"{label}: {time.perf_counter() - start:.2f} s")


def exit_now(status: int) -> None:
    """End a command-line process without the interpreter's teardown of numba, scipy and
    xarray (~0.5-1.4 s on a loaded machine), once everything is written and flushed."""
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (BrokenPipeError, ValueError, OSError):
            pass
    os._exit(status)


def guarded(command: Callable[[], int]) -> int:
    """Run ``command`` with the shared exit conventions; returns the exit status."""
    restore = install_signal_handlers()
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
    finally:
        restore()


def check_output_path(path: str | Path, field: str, *, inputs: Iterable[str | Path] = (),
                      suffixes: tuple[str, ...] = ()) -> Path:
    """The output path, or an InputError naming ``field`` before any computing.

    Refused: a suffix not in ``suffixes`` (when given), an existing directory, one of the
    ``inputs`` (same file), a parent that is a file or cannot be created, a folder that is
    not writable. The parent folder is created when missing.
    """
    path = Path(path)
    if any(ord(c) < 32 for c in str(path)):
        raise InputError(field, f"{str(path).encode('unicode_escape').decode()!s} contains control characters",
                         "give a plain file name")
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
