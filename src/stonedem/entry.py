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
from typing import Callable

from stonedem.errors import InputError, one_line

# the output-path checks every command makes, re-exported where the commands import them
from stonedem.io.paths import check_output_path, real_path  # noqa: F401

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
    threading.Thread(
        target=_watchdog, args=(read_end,), name="stonedem-signal-watchdog", daemon=True
    ).start()

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


def workflow_log(path: str, buffering: int = 1):
    """A Snakemake script's stderr: its log file, and bad input ends the job as one line.

    An :class:`InputError` that reaches the top of the script is written as ``error: ...``
    to the log and to the terminal's stderr (Snakemake shows it beside the failed rule),
    without a traceback, and the job exits 2; anything else keeps its traceback (a bug).
    Returns the log stream (also set as ``sys.stderr``).
    """
    terminal = sys.stderr
    log = open(path, "w", buffering=buffering)
    sys.stderr = log

    def hook(kind, value, tb):
        if not issubclass(kind, InputError):
            return sys.__excepthook__(kind, value, tb)
        for stream in (log, terminal):
            try:
                print(f"error: {value}", file=stream, flush=True)
            except (OSError, ValueError, AttributeError):
                pass
        exit_now(EXIT_INPUT)

    sys.excepthook = hook
    return log


def exit_now(status: int) -> None:
    """End a command-line process without the interpreter's teardown of numba, scipy and
    xarray (~0.5-1.4 s on a loaded machine), once everything is written and flushed."""
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (BrokenPipeError, ValueError, OSError):
            pass
    os._exit(status)


def standard_streams() -> None:
    """Put /dev/null on a closed stdin, stdout or stderr (``cmd >&- 2>&-``).

    Python sets ``sys.stdout``/``sys.stderr`` to None for a closed descriptor; ``print`` to
    None then goes nowhere or, for stderr, to stdout, and a flush raises, so a complete run
    exited 1 and an error line landed on stdout. Worse, the next file opened would take the
    free descriptor 1 or 2 and receive the output meant for the terminal. The exit status
    must report the work, never the logging.
    """
    for fd, name, mode in (
        (0, "stdin", os.O_RDONLY),
        (1, "stdout", os.O_WRONLY),
        (2, "stderr", os.O_WRONLY),
    ):
        try:
            os.fstat(fd)
            continue
        except OSError:
            pass
        null = os.open(os.devnull, mode)
        if null != fd:
            os.dup2(null, fd)
            os.close(null)
        setattr(sys, name, open(fd, "r" if fd == 0 else "w", closefd=False))


def guarded(command: Callable[[], int]) -> int:
    """Run ``command`` with the shared exit conventions; returns the exit status."""
    standard_streams()
    restore = install_signal_handlers()
    try:
        status = command()
        sys.stdout.flush()
        return status
    except InputError as err:
        _say(f"error: {err}")
        return EXIT_INPUT
    except Interrupted as sig:
        _say("interrupted")
        return EXIT_SIGTERM if sig.signum == signal.SIGTERM else EXIT_SIGINT
    except KeyboardInterrupt:
        _say("interrupted")
        return EXIT_SIGINT
    except BrokenPipeError:
        # the reader went away (| head): stop writing, without a traceback at exit
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0
    except OSError as err:
        if err.filename is not None or not _is_stdout_failure(err):
            raise
        # what the command printed is its result (stonedem record info > /dev/full)
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        _say(f"error: stdout: cannot write ({err.strerror}); the printed result is incomplete")
        return 1
    finally:
        restore()


def _is_stdout_failure(err: OSError) -> bool:
    import errno

    return err.errno in (errno.ENOSPC, errno.EIO, errno.EDQUOT, errno.EFBIG)


def _say(line: str) -> None:
    """The one closing line on stderr; a stderr that cannot take it must not change the status."""
    try:
        print(line, file=sys.stderr, flush=True)
    except (OSError, ValueError, AttributeError):
        pass
