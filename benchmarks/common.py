"""Helpers the benchmark scripts share: the synthetic CSV log they read and tracemalloc's peak of one call.

Import it from a script in this folder (`from common import ...`): running `python benchmarks/X.py`
puts this folder first on sys.path. The scripts put the repository root there for `jointid`.
"""

from __future__ import annotations

import gc
import os
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np

from jointid.model.terms import predict_torque
from jointid.synthetic.motions import TRAINING_MOTIONS

ROOT = Path(__file__).resolve().parent.parent

ENVIRONMENT = {name: value for name, value in os.environ.items() if name != "PYTHONDONTWRITEBYTECODE"}
ENVIRONMENT["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT), os.environ.get("PYTHONPATH")) if p)
"""The environment of the fresh processes timed: this tree's jointid first on the path, bytecode caching allowed
as on a user's machine (this VM sets PYTHONDONTWRITEBYTECODE)."""

SCRIPT = Path(sys.executable).parent / "jointid"
JOINTID = [sys.executable, str(SCRIPT)] if SCRIPT.exists() else [sys.executable, "-m", "jointid"]
"""The console script pip installed (run by this interpreter, so that PYTHONPATH picks this tree)."""


def write_log(path: Path, rows: int) -> None:
    """A full-column log of the rich motion at 1 kHz with exact torques, 17 significant digits."""
    t = np.arange(rows) * 1e-3
    states = TRAINING_MOTIONS["rich"].states(t)
    tau = predict_torque(states.q, states.qd, states.qdd)
    table = np.column_stack([t, states.q, states.qd, states.qdd, tau])
    np.savetxt(path, table, delimiter=",", fmt="%.17g", header="t,q,qd,qdd,tau", comments="")


def peak_memory(function, path) -> int:
    """Peak bytes traced by tracemalloc during one call of `function(path)`."""
    gc.collect()
    tracemalloc.start()
    try:
        function(path)
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def launch(command: list[str]) -> tuple[float, float]:
    """(wall, CPU) seconds of one fresh process running `command` to its exit (status 0 required).

    CPU is the child's user + system time (os.wait4), which other processes on this shared machine
    disturb far less than wall time.
    """
    start = time.perf_counter()
    process = subprocess.Popen(command, cwd=ROOT, env=ENVIRONMENT, stdout=subprocess.DEVNULL)
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.perf_counter() - start
    process.returncode = os.waitstatus_to_exitcode(status)
    if process.returncode:
        raise SystemExit(f"{command} exited with {process.returncode}")
    return wall, usage.ru_utime + usage.ru_stime
