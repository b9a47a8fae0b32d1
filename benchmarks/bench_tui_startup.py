"""Start-up to first complete frame: the explorer against a minimal one-PlotextPlot Textual app.

Run: .venv/bin/python benchmarks/bench_tui_startup.py

Each app starts as a fresh Python process, headless at 120x40, draws its first
complete frame (for the explorer: the fit, readouts and both charts) and exits
straight after that frame. The wall time from launching the process to its
exit is measured, alternating the two apps, several rounds; the medians and
their ratio are printed, for wall time and for the process's CPU time (user +
system, all threads; numpy's BLAS threads make the explorer's CPU time exceed its
wall time). A third app, the minimal one importing numpy first, shows the part of
the ratio that numpy's import alone takes. Goal: ratio <= 1.3.
"""

from __future__ import annotations

import os
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
ROUNDS = 9

EXPLORER = """
from tui.app import JointIdApp

class FirstFrame(JointIdApp):
    restore_gc = False  # as `jointid` runs it (tui/entry.py): the process ends with the app

    def on_ready(self):
        self.call_after_refresh(self.exit)

FirstFrame().run(headless=True, size=(120, 40))
"""

MINIMAL = """
from textual.app import App
from textual_plotext import PlotextPlot

class Minimal(App):
    def compose(self):
        yield PlotextPlot()

    def on_mount(self):
        plt = self.query_one(PlotextPlot).plt
        plt.scatter([0, 1, 2, 3], [1, 3, 2, 4])
        plt.title("minimal")

    def on_ready(self):
        self.call_after_refresh(self.exit)

Minimal().run(headless=True, size=(120, 40))
"""


NUMPY_FLOOR = "import numpy\n" + MINIMAL
"""The minimal app after importing numpy, which the explorer's fit cannot do without: how
much of the gap no change to the explorer's own code can remove."""


def child_cpu() -> float:
    """CPU seconds (user + system) used so far by finished child processes."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


ENVIRONMENT = {name: value for name, value in os.environ.items() if name != "PYTHONDONTWRITEBYTECODE"}
"""As on a user's machine, Python may cache compiled modules: the warm-up start writes them
(pip compiled the libraries' already; jointid and tui are installed editable, from source).
This machine sets PYTHONDONTWRITEBYTECODE, which would compile them afresh at every start."""


def launch(code: str) -> tuple[float, float]:
    """Wall and CPU seconds of a fresh interpreter running `code` until it exits."""
    start, cpu = time.perf_counter(), child_cpu()
    subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=ENVIRONMENT, check=True)
    return time.perf_counter() - start, child_cpu() - cpu


def main() -> None:
    launch(MINIMAL), launch(EXPLORER), launch(NUMPY_FLOOR)  # warm the file cache and compiled modules
    explorer, minimal, floor = [], [], []
    for _ in range(ROUNDS):
        minimal.append(launch(MINIMAL))
        explorer.append(launch(EXPLORER))
        floor.append(launch(NUMPY_FLOOR))
    for index, kind in enumerate(("wall", "CPU")):
        m_explorer, m_minimal, m_floor = (statistics.median(run[index] for run in runs)
                                          for runs in (explorer, minimal, floor))
        best = min(run[index] for run in explorer) / min(run[index] for run in minimal)
        print(f"{kind:4}: minimal PlotextPlot app median {m_minimal * 1000:.0f} ms, jointid explorer "
              f"median {m_explorer * 1000:.0f} ms over {ROUNDS} runs; ratio {m_explorer / m_minimal:.2f} "
              f"(best to best {best:.2f}; goal <= 1.30); the minimal app importing numpy: "
              f"{m_floor / m_minimal:.2f}")


if __name__ == "__main__":
    main()
