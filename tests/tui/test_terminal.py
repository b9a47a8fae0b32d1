"""The explorer as a process: it needs a terminal, and SIGINT ends it with status 130.

These start `python -m jointid` for real, on a pseudo-terminal or without one;
each waits on what the process writes or on its end, with a time limit that
turns a hang into a failure.
"""

from __future__ import annotations

import fcntl
import os
import pty
import select
import signal
import struct
import subprocess
import sys
import termios
import time

import pytest

from tui.app import terminal_problem

LIMIT = 60.0
"""Seconds a process may take to draw or to end before the test fails (either takes a second or two)."""

FIRST_FRAME = b"Rich motion"
"""Text of the explorer's first frame (the motion list's first entry)."""


def terminal_driver_environment() -> dict[str, str]:
    """This process's environment without TEXTUAL_DRIVER, so the child uses Textual's terminal driver."""
    return {name: value for name, value in os.environ.items() if name != "TEXTUAL_DRIVER"}


def test_without_a_terminal_the_explorer_is_refused_in_one_line():
    try:
        done = subprocess.run([sys.executable, "-m", "jointid"], stdin=subprocess.DEVNULL, capture_output=True,
                              text=True, timeout=LIMIT, check=False, env=terminal_driver_environment())
    except subprocess.TimeoutExpired:
        pytest.fail(f"the explorer without a terminal still ran after {LIMIT} s")
    assert done.returncode == 2 and done.stdout == ""
    assert done.stderr == ("jointid: the explorer needs a terminal, and its standard input is not one; run `jointid` "
                           "in a terminal, or use a subcommand such as `jointid fit`\n")


def test_another_driver_brings_its_own_terminal(monkeypatch):
    monkeypatch.setenv("TEXTUAL_DRIVER", "textual.drivers.web_driver:WebDriver")  # as textual-serve starts it
    assert terminal_problem() is None


def read_until(fd: int, wanted: bytes | None) -> bytes:
    """What the process writes to the terminal, up to `wanted` (None: until it closes it); fails at LIMIT."""
    seen = b""
    deadline = time.monotonic() + LIMIT
    while wanted is None or wanted not in seen:
        ready, _, _ = select.select([fd], [], [], max(0.0, deadline - time.monotonic()))
        if not ready:
            pytest.fail(f"waited {LIMIT} s for {wanted!r}; the terminal showed {seen[-300:]!r}")
        try:
            chunk = os.read(fd, 65536)
        except OSError:  # EIO: the process closed its terminal
            chunk = b""
        if not chunk:
            if wanted is None:
                return seen
            pytest.fail(f"the explorer ended before showing {wanted!r}: {seen[-300:]!r}")
        seen += chunk
    return seen


@pytest.mark.skipif(sys.platform == "win32", reason="pseudo-terminals and SIGINT are POSIX")
def test_sigint_ends_the_explorer_with_status_130():
    pid, fd = pty.fork()
    if pid == 0:  # the child: stdin, stdout and stderr are the pseudo-terminal
        os.environ.pop("TEXTUAL_DRIVER", None)
        os.environ["TERM"] = "xterm-256color"
        os.execv(sys.executable, [sys.executable, "-m", "jointid"])
    try:
        fcntl.ioctl(fd, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 80, 0, 0))
        read_until(fd, FIRST_FRAME)
        os.kill(pid, signal.SIGINT)
        read_until(fd, None)  # drain the terminal (the app restores it on the way out) until it is closed
        _, status = os.waitpid(pid, 0)
    finally:
        os.close(fd)
        try:
            os.kill(pid, signal.SIGKILL)  # only if it still runs after a failure
            os.waitpid(pid, 0)
        except (ProcessLookupError, ChildProcessError):
            pass
    assert os.waitstatus_to_exitcode(status) == 130
