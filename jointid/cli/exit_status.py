"""The exit statuses every face returns, by name (as httpie's ExitStatus)."""

from __future__ import annotations

from enum import IntEnum


class ExitStatus(IntEnum):
    """What a `jointid` process's exit status means; scripts may rely on these numbers."""

    SUCCESS = 0
    """The command did what was asked (the explorer: the user quit)."""
    ERROR = 1
    """jointid itself failed: a bug, reported with its traceback."""
    USER_ERROR = 2
    """Something the user can fix, said in one line on stderr: a flag, a value, a file, or output that cannot be
    written."""
    INTERRUPTED = 130
    """Stopped by Ctrl+C (SIGINT), 128 + 2 as shells report it."""
