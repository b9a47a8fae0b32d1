"""A long fit's progress on a terminal: what it is doing, how much memory it takes, and the seconds so far."""

from __future__ import annotations

import contextlib
import sys
import threading

FIRST_TICK = 1.0
"""Seconds before the first line: a fit that ends sooner prints nothing."""


@contextlib.contextmanager
def elapsed_on_terminal(message: str, stream=None):
    """While the block runs, `message` and the seconds elapsed on one rewritten line of `stream` (stderr), only
    when it is a terminal; the line is cleared at the end, so nothing is left between the command and its output."""
    stream = sys.stderr if stream is None else stream
    if not stream.isatty():
        yield
        return
    done = threading.Event()
    shown = []

    def tick() -> None:
        """Rewrite the line every second until the block ends."""
        seconds = 0
        while not done.wait(FIRST_TICK if not seconds else 1.0):
            seconds += 1
            line = f"\r{message}: {seconds} s"
            shown.append(len(line))
            stream.write(line)
            stream.flush()

    thread = threading.Thread(target=tick, daemon=True)
    thread.start()
    try:
        yield
    finally:
        done.set()
        thread.join()
        if shown:
            stream.write("\r" + " " * max(shown) + "\r")
            stream.flush()
