"""Stand-ins for `design_motion` that a design process's child imports by name, and `gone` for its pid."""

from __future__ import annotations

import os
import time

from jointid.studies.design import DesignError


def refused_design(spec, progress=None):
    """Fail the way a design the limits do not allow fails."""
    raise DesignError("no start found a motion within the limits that determines every parameter")


def broken_design(spec, progress=None):
    """Fail the way a bug in the optimiser would."""
    return 1 / 0


def endless_design(spec, progress=None):
    """Report a start every 10 ms and never finish (only a kill ends it)."""
    done = 0
    while True:
        time.sleep(0.01)
        done += 1
        if progress is not None:
            progress(done, 10**9)


def gone(pid: int) -> bool:
    """True when no process runs under this id: none has it, or it is a zombie (ended, not yet reaped)."""
    try:
        with open(f"/proc/{pid}/stat") as stat:
            return stat.read().rsplit(")", 1)[1].split()[0] == "Z"
    except FileNotFoundError:
        return True
    except OSError:  # no /proc: ask the kernel (a zombie counts as running there)
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return True
        return False
