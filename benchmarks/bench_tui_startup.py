"""Start-up to first complete frame: the explorer against the minimal one-PlotextPlot app importing numpy.

Run: .venv/bin/python benchmarks/bench_tui_startup.py [ROUNDS]

Each app starts as a fresh Python process, headless at 120x40, draws its first
complete frame (for the explorer: the fit, readouts and both charts) and exits
straight after that frame. The explorer runs twice over: as the app class
alone, and as users start it, the `jointid` command (tui.command: the command
line's parsing and checks, then the explorer). The baseline is the least a
numeric terminal chart app can be: a Textual app with one stock `PlotextPlot`
that imports numpy first (the explorer's fit cannot do without numpy). Every
round launches the four, and `python -m jointid` (the core's command line,
which finds the explorer through its entry point, no goal), in an order
rotated from round to round; each round's
ratio to the baseline of wall time (and of CPU time, user + system of all
threads) is printed as min / median / max over the rounds. Goal: median wall
ratio <= 1.05, for the app and for the command. The minimal app without numpy
over the baseline is printed too: numpy's share.
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


def command_line(module: str, undo: str = "") -> str:
    """`jointid` with no subcommand, through `module`'s console_script, leaving after the first frame as
    EXPLORER does (importing tui.app first changes the order of the imports, not their sum); `undo` runs first
    (bench_startup_budget takes a trick away with it)."""
    return f"""
import functools, sys
{undo}
from tui.app import JointIdApp

explorer_ready = JointIdApp.on_ready

def on_ready(self):
    explorer_ready(self)
    self.call_after_refresh(self.exit)

JointIdApp.on_ready = on_ready
JointIdApp.run = functools.partialmethod(JointIdApp.run, headless=True, size=(120, 40))
sys.argv = ["jointid"]
from {module} import console_script
console_script()
"""


COMMAND = command_line("tui.command")
"""What pip's `jointid` script runs: the UI hands its explorer to the core's command line."""

MODULE = command_line("jointid.cli")
"""`python -m jointid`: the core's own command line, which finds the explorer through its entry point."""

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


GOAL = 1.05


def main() -> int:
    """Launch the five apps round by round and print the ratios; exit 1 if a goal is missed."""
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else ROUNDS
    apps = {"explorer": EXPLORER, "command": COMMAND, "module": MODULE, "baseline": NUMPY_FLOOR, "minimal": MINIMAL}
    for code in apps.values():  # warm the file cache and compiled modules
        launch(code)
    times: dict[str, list[tuple[float, float]]] = {name: [] for name in apps}
    names = list(apps)
    for index in range(rounds):
        for name in names[index % len(names):] + names[:index % len(names)]:
            times[name].append(launch(apps[name]))
    print(f"first complete frame at 120x40, fresh processes, {rounds} interleaved rounds; baseline: the minimal "
          f"one-PlotextPlot app importing numpy (median {statistics.median(w for w, _ in times['baseline']) * 1000:.0f}"
          f" ms wall, for scale only)")
    print(f"{'ratio':<50}min / median / max")
    verdict = True
    labels = (("explorer", "explorer app / baseline"), ("command", "`jointid` command / baseline"),
              ("module", "`python -m jointid` / baseline"), ("minimal", "minimal app without numpy / baseline"))
    for index, kind in enumerate(("wall", "CPU")):
        for name, label in labels:
            ratios = [a[index] / b[index] for a, b in zip(times[name], times["baseline"])]
            middle = statistics.median(ratios)
            note = ""
            if name in ("explorer", "command") and kind == "wall":
                verdict = verdict and middle <= GOAL
                note = f"  goal <= {GOAL:.2f}: {'met' if middle <= GOAL else 'MISSED'}"
            print(f"  {label + ', ' + kind:<48}{min(ratios):.2f} / {middle:.2f} / {max(ratios):.2f}{note}")
    return 0 if verdict else 1


if __name__ == "__main__":
    raise SystemExit(main())
