"""Real-signal tests' one procedure: start a command, wait for a stderr line, signal it, time its
exit."""

import queue
import subprocess
import threading
import time


def interrupt_after_line(args, ready, signum, timeout=300.0, before=None, cwd=None):
    """Run ``args``; once a stderr line satisfies ``ready(line)``, call ``before()`` (if
    given), send ``signum``; return (exit status, seconds from the signal to the exit,
    the stderr lines seen up to the signal)."""
    proc = subprocess.Popen(
        args, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True
    )
    lines = queue.Queue()
    threading.Thread(target=lambda: [lines.put(x) for x in proc.stderr], daemon=True).start()
    seen = []
    try:
        deadline = time.monotonic() + timeout
        while not (seen and ready(seen[-1])):
            assert time.monotonic() < deadline and proc.poll() is None, seen
            try:
                seen.append(lines.get(timeout=0.1))
            except queue.Empty:
                continue
        if before is not None:
            before()
        sent = time.monotonic()
        proc.send_signal(signum)
        status = proc.wait(timeout=30)
        return status, time.monotonic() - sent, seen
    finally:
        proc.kill()
        proc.wait()
