"""Benchmark: load + fit a 1,000,000-row, 5-column CSV log against numpy.loadtxt + numpy.linalg.lstsq.

Run `python benchmarks/bench_csv.py [ROWS]`. It writes the log to a temporary
directory, then times both pipelines alternately (best of REPEATS each, so
disk cache and machine noise treat them alike), and measures each one's peak
traced memory in a separate run: tracemalloc slows allocation-heavy code, so
timed runs are untraced. Goals (issue 5): ours <= 2.0 s, not slower than the
baseline, peak memory <= 4x the numeric data (rows * 5 * 8 bytes).

The timed runs share one process, so they exclude imports: ours parses with
pandas, imported on the first load (jointid itself never imports it). The
first load in a fresh process, imports included, is measured and printed
separately for both pipelines, with pandas' import time on its own. Traced
memory does not see buffers that pandas' C reader allocates itself; the
fresh-process runs print each pipeline's growth of the peak resident set too
(after imports: pandas' own code is some 50 MB of it).
"""

from __future__ import annotations

import gc
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from common import peak_memory, write_log  # noqa: E402  (this folder is first on sys.path)

from jointid.estimation.fit import fit_joint  # noqa: E402
from jointid.logs.csv_reader import load_log  # noqa: E402
from jointid.model.terms import TRUE_PARAMETERS, G  # noqa: E402

REPEATS = 7
"""Timed runs of each pipeline; the best is reported."""

GOAL_SECONDS = 2.0
GOAL_MEMORY_MULTIPLE = 4.0


def ours(path: Path) -> np.ndarray:
    """jointid: checked chunked load, then the pivoted-QR fit."""
    return fit_joint(load_log(path).data).estimate


def baseline(path: Path) -> np.ndarray:
    """numpy.loadtxt of the whole file, regressor by hand, numpy.linalg.lstsq."""
    table = np.loadtxt(path, delimiter=",", skiprows=1)
    X = np.column_stack([table[:, 3], G * np.cos(table[:, 1]), table[:, 2]])
    return np.linalg.lstsq(X, table[:, 4], rcond=None)[0]


def timed(function, path: Path) -> tuple[float, float, np.ndarray]:
    """Wall time and process CPU time of one call, and its result."""
    gc.collect()
    start, cpu = time.perf_counter(), time.process_time()
    result = function(path)
    return time.perf_counter() - start, time.process_time() - cpu, result


FRESH = """
import sys, time
def high_water():  # peak resident set of this process in bytes (ru_maxrss would include the parent's, from before exec)
    with open("/proc/self/status") as status:
        return next(int(line.split()[1]) * 1024 for line in status if line.startswith("VmHWM:"))
start = time.perf_counter()
import numpy as np
kind, path = sys.argv[1], sys.argv[2]
if kind == "pandas-import":
    import pandas
    print(time.perf_counter() - start, 0)
    raise SystemExit
sys.path.insert(0, sys.argv[3])
from bench_csv import baseline, ours
if kind == "ours":
    import pandas  # what the first load would import anyway: its code is not data
resident = high_water()
(ours if kind == "ours" else baseline)(path)
print(time.perf_counter() - start, high_water() - resident)
"""
"""Run in a new interpreter: seconds from before `import numpy` to the fitted estimate, and peak RSS growth."""


def fresh_process(kind: str, path: Path) -> tuple[float, int]:
    """(seconds, bytes) of FRESH for one pipeline, or for importing pandas alone."""
    here = str(Path(__file__).resolve().parent)
    output = subprocess.run(
        [sys.executable, "-c", FRESH, kind, str(path), here], capture_output=True, text=True, check=True
    ).stdout.split()
    return float(output[0]), int(output[1])


def main(rows: int = 1_000_000) -> int:
    """Write the log, measure both pipelines and print the figures; exit 1 if a goal is missed."""
    numeric_bytes = rows * 5 * 8
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "log.csv"
        write_log(path, rows)
        print(f"log: {rows} rows x 5 columns, {os.path.getsize(path) / 1e6:.1f} MB of text, "
              f"{numeric_bytes / 1e6:.1f} MB of numbers")
        times = {"ours": [], "baseline": []}
        cpu = {"ours": [], "baseline": []}
        for _ in range(REPEATS):
            for name, function in (("ours", ours), ("baseline", baseline)):
                seconds, cpu_seconds, estimate = timed(function, path)
                times[name].append(seconds)
                cpu[name].append(cpu_seconds)
                error = np.max(np.abs(estimate / TRUE_PARAMETERS - 1))
                if error > 1e-6:
                    print(f"{name}: wrong estimate {estimate}")
                    return 1
        memory = {name: peak_memory(f, path) / numeric_bytes for name, f in (("ours", ours), ("baseline", baseline))}
        fresh = {name: [fresh_process(name, path) for _ in range(3)] for name in ("ours", "baseline", "pandas-import")}
    best = {name: min(values) for name, values in times.items()}
    best_cpu = {name: min(values) for name, values in cpu.items()}
    ratio = best["ours"] / best["baseline"]
    for name in ("ours", "baseline"):
        runs = ", ".join(f"{s:.3f}" for s in times[name])
        print(f"{name:<9} best {best[name]:.3f} s wall, {best_cpu[name]:.3f} s CPU (wall runs {runs}); "
              f"peak memory {memory[name]:.2f}x the numeric data")
    # CPU time is less disturbed by other processes on a shared machine than wall time.
    print(f"ratio ours/baseline {ratio:.3f} wall, {best_cpu['ours'] / best_cpu['baseline']:.3f} CPU")
    first = {name: min(s for s, _ in runs) for name, runs in fresh.items()}
    rss = {name: min(b for _, b in runs) / numeric_bytes for name, runs in fresh.items()}
    print(f"fresh process, first load with imports (best of 3): ours {first['ours']:.3f} s, "
          f"baseline {first['baseline']:.3f} s, ratio {first['ours'] / first['baseline']:.3f}; "
          f"numpy + pandas import alone {first['pandas-import']:.3f} s")
    print(f"fresh process, peak resident set growth during the load: ours {rss['ours']:.2f}x, "
          f"baseline {rss['baseline']:.2f}x the numeric data")
    met = best["ours"] <= GOAL_SECONDS and ratio <= 1.0 and memory["ours"] <= GOAL_MEMORY_MULTIPLE
    print("goals met" if met else "GOALS MISSED")
    return 0 if met else 1


if __name__ == "__main__":
    raise SystemExit(main(*(int(a) for a in sys.argv[1:2])))
