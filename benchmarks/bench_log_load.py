"""Loading and fitting a large log against the pandas script a user would write instead.

Run from the repository root: PYTHONPATH=. .venv/bin/python benchmarks/bench_log_load.py [ROUNDS [ROWS]]

It writes a 1,000,000-row log of t, q, qd, qdd, tau (the rich motion at 1 kHz,
17 significant digits, about 97 MB) to a temporary directory, then runs
interleaved rounds, each with the two pairs below in a rotating order and the
two sides of a pair in alternating order:

1. Fresh processes: `jointid fit --csv FILE --json` (the console script next to
   this interpreter) against BASELINE_SCRIPT, ten lines doing
   `pandas.read_csv(path)` (C engine, its defaults), a regressor by hand and
   `numpy.linalg.lstsq`. Both include every import (pandas among them).
   Ratios: wall time, and peak resident set (each child's own ru_maxrss, from
   GNU time). Goals: time <= 1.5 (every default: issue 31's goal, also bench_log_path's; like for like, goal
   1.0, is timed there), memory <= 1.0.
2. In-process: `jointid.logs.table.load_log(path)` against one
   `pandas.read_csv(path)`, both after a warm-up in this process. Goal <= 1.3.

It prints min / median / max of the per-round ratios and whether each median
meets its goal, and two floors: how much more jointid holds than the script
when pandas starts reading (both peaks come during that read), and
the share of the script's time that jointid's checks the script does not make
(time checks, the automatic cutoff, the robust step, the sensitivity refits) take. It checks
both estimates against the true parameters, and exits 1 if a goal is missed.
"""

from __future__ import annotations

import gc
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from common import ENVIRONMENT, JOINTID, write_log  # noqa: E402  (this folder is first on sys.path)

from jointid.logs.csv_reader import load_log, read_table  # noqa: E402
from jointid.estimation.exclusion import ExclusionRequest  # noqa: E402
from jointid.estimation.low_pass import automatic_cutoff  # noqa: E402
from jointid.logs.pipeline import check_time, joint_log_from_table
from jointid.model.terms import TRUE_PARAMETERS  # noqa: E402
from jointid.studies.log_fit import fit_logs  # noqa: E402

ROUNDS = 7
ROWS = 1_000_000
GOALS = {"fresh process, wall time": 1.5, "fresh process, peak resident set": 1.0, "in-process load": 1.3}

BASELINE_SCRIPT = """\
import sys

import numpy as np
import pandas as pd

frame = pd.read_csv(sys.argv[1])
X = np.column_stack([frame["qdd"], 9.81 * np.cos(frame["q"]), frame["qd"]])
theta = np.linalg.lstsq(X, frame["tau"], rcond=None)[0]
print(*theta)
"""
"""What a user would write instead of `jointid fit --csv FILE --json`."""


AT_THE_READ = """\
import os, runpy, sys
import pandas

def reading(*args, **kwargs):
    with open("/proc/self/status") as status:
        print(next(line.split()[1] for line in status if line.startswith("VmRSS:")), flush=True)
    os._exit(0)

pandas.read_csv = reading
if sys.argv[1] == "-m":  # python -m jointid, where no console script is installed
    sys.argv = sys.argv[2:]
    runpy.run_module(sys.argv[0], run_name="__main__", alter_sys=True)
sys.argv = sys.argv[1:]
runpy.run_path(sys.argv[0], run_name="__main__")
"""
"""Runs a script (argv[1:], or -m and a module) until it calls pandas.read_csv, then prints the resident set (kB)
and stops."""


def resident_at_the_read(command: list[str]) -> int:
    """Resident bytes of `command` (a Python script and its arguments) when it starts reading with pandas."""
    done = subprocess.run([sys.executable, "-c", AT_THE_READ, *command[1:]], cwd=ROOT, env=ENVIRONMENT,
                          stdout=subprocess.PIPE, check=True)
    return int(done.stdout.split()[-1]) * 1024


def child(command: list[str], folder: Path) -> tuple[float, int, str]:
    """(wall seconds, peak resident bytes, stdout) of one fresh process run to its end (status 0 required).

    The peak comes from /usr/bin/time (GNU time's %M, the child's ru_maxrss): a child forked from this
    process would report this process's resident set, from before its exec, if that were larger.
    """
    report = folder / "rss.txt"
    start = time.perf_counter()
    done = subprocess.run(["/usr/bin/time", "-f", "%M", "-o", str(report), *command], cwd=ROOT, env=ENVIRONMENT,
                          stdout=subprocess.PIPE)
    seconds = time.perf_counter() - start
    if done.returncode:
        raise SystemExit(f"{command} exited with {done.returncode}")
    return seconds, int(report.read_text().split()[-1]) * 1024, done.stdout.decode()


def in_process(function) -> float:
    """Wall seconds of one call, after a collection."""
    gc.collect()
    start = time.perf_counter()
    function()
    return time.perf_counter() - start


def checks_the_script_skips(path: Path) -> dict[str, float]:
    """Median seconds (of 5 warm calls each) of what `jointid fit` does to a loaded log beyond a regressor and
    a solve: the time checks, the automatic cutoff, the robust step with standstill, and the sensitivity check's
    refits. Warm, so lower than in a fresh process, where new arrays also cost page faults."""
    table = read_table(path)
    log = joint_log_from_table(table)  # the same log as load_log(path), without reading the file again

    def median_seconds(function) -> float:
        return statistics.median(in_process(function) for _ in range(5))

    single = median_seconds(lambda: fit_logs(log, sensitivity=False))
    refits = median_seconds(lambda: fit_logs(log)) - single
    robust = single - median_seconds(lambda: fit_logs(log, sensitivity=False, exclusion=ExclusionRequest(False)))
    return {"time checks": median_seconds(lambda: check_time(table, uniform=False)),
            "automatic cutoff": median_seconds(lambda: automatic_cutoff(log.data.q, log.timing.step)),
            "robust step and standstill": robust,
            "sensitivity refits": refits}


def spread(values: list[float], digits: int = 2) -> str:
    """'min / median / max'."""
    return " / ".join(f"{value:.{digits}f}" for value in (min(values), statistics.median(values), max(values)))


def main() -> int:
    """Write the log, run the rounds, print the ratios; exit 1 if a goal or an estimate is missed."""
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else ROUNDS
    rows = int(sys.argv[2]) if len(sys.argv) > 2 else ROWS
    ratios: dict[str, list[float]] = {name: [] for name in GOALS}
    seconds: dict[str, list[float]] = {"jointid fit": [], "pandas script": [], "load_log": [], "read_csv": []}
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "log.csv"
        write_log(path, rows)
        baseline_file = Path(folder) / "baseline.py"
        baseline_file.write_text(BASELINE_SCRIPT)
        ours_command = JOINTID + ["fit", "--csv", str(path), "--json"]
        baseline_command = [sys.executable, str(baseline_file), str(path)]
        print(f"log: {rows:,} rows x 5 columns, {path.stat().st_size / 1e6:.1f} MB of text; "
              f"{rounds} interleaved rounds; pandas {pandas.__version__}, numpy {np.__version__}")
        # Warm-up: bytecode caches, the page cache, pandas imported here.
        import json

        document = json.loads(child(ours_command, Path(folder))[2])
        estimate = np.array([document["estimate"][name] for name in ("I", "h", "B")])
        theirs = np.array([float(v) for v in child(baseline_command, Path(folder))[2].split()])
        for name, values in (("jointid fit", estimate), ("pandas script", theirs)):
            if np.max(np.abs(values / TRUE_PARAMETERS - 1)) > 1e-6:
                print(f"{name}: wrong estimate {values}")
                return 1
        load_log(path), pandas.read_csv(path)
        # The memory floor: what each process holds when pandas starts reading (code, parsed arguments),
        # pandas imported first in both. Both peaks come during that read.
        at_the_read = {name: min(resident_at_the_read(command) for _ in range(3))
                       for name, command in (("script", baseline_command), ("jointid", ours_command))}
        for index in range(rounds):
            pairs = [("fresh", ours_command, baseline_command), ("in-process", None, None)]
            for kind, _, _ in pairs[index % 2:] + pairs[:index % 2]:
                if kind == "fresh":
                    if index % 2:
                        theirs, ours = child(baseline_command, Path(folder)), child(ours_command, Path(folder))
                    else:
                        ours, theirs = child(ours_command, Path(folder)), child(baseline_command, Path(folder))
                    seconds["jointid fit"].append(ours[0])
                    seconds["pandas script"].append(theirs[0])
                    ratios["fresh process, wall time"].append(ours[0] / theirs[0])
                    ratios["fresh process, peak resident set"].append(ours[1] / theirs[1])
                    rss = (ours[1], theirs[1])
                else:
                    if index % 2:
                        theirs_s, ours_s = in_process(lambda: pandas.read_csv(path)), in_process(lambda: load_log(path))
                    else:
                        ours_s, theirs_s = in_process(lambda: load_log(path)), in_process(lambda: pandas.read_csv(path))
                    seconds["load_log"].append(ours_s)
                    seconds["read_csv"].append(theirs_s)
                    ratios["in-process load"].append(ours_s / theirs_s)
        skipped = checks_the_script_skips(path)
    scale = ", ".join(f"{name} {statistics.median(v):.3f} s" for name, v in seconds.items())
    print(f"medians (for scale only): {scale}"
          + f"; last peak resident sets {rss[0] / 1e6:.0f} MB (jointid) and {rss[1] / 1e6:.0f} MB (script)")
    print()
    print(f"{'ratio, jointid / baseline':<52}min / median / max")
    missed = []
    labels = {"fresh process, wall time": "fresh process, wall time (jointid fit / script)",
              "fresh process, peak resident set": "fresh process, peak RSS (jointid fit / script)",
              "in-process load": "in-process, load_log(path) / read_csv(path)"}
    for name, goal in GOALS.items():
        met = statistics.median(ratios[name]) <= goal
        missed += [] if met else [name]
        digits = 3 if "resident" in name else 2  # a fraction of a per cent decides this one
        print(f"  {labels[name]:<50}{spread(ratios[name], digits)}  goal <= {goal:.1f}: {'met' if met else 'MISSED'}")
    extra = at_the_read["jointid"] - at_the_read["script"]
    print(f"  floor: when pandas starts reading, jointid holds {extra / 1e6:.1f} MB more than the script (its code "
          f"and parsed arguments), {extra / rss[1]:.3f} of the script's peak")
    script = statistics.median(seconds["pandas script"])
    parts = ", ".join(f"{name} {value / script:.3f}" for name, value in skipped.items())
    print(f"  floor: checks the script does not make take {sum(skipped.values()) / script:.3f} of its wall time, "
          f"warm and in-process ({parts})")
    print()
    print("goals met: all" if not missed else f"goals missed: {', '.join(missed)}")
    return 1 if missed else 0


if __name__ == "__main__":
    raise SystemExit(main())
