"""Benchmark: what the default parallel low-pass and sensitivity check add to a log fit.

Run `PYTHONPATH=. python benchmarks/bench_log_filter.py [ROWS] [ROUNDS]` from the
repository root (defaults 1,000,000 rows, 7 rounds). It writes a log with
`jointid simulate --samples ROWS --duration ROWS/1000 --noise 0.2` (t, q, qd,
qdd, tau at 1 kHz: nothing to differentiate, so the check refits with the
cutoff halved and doubled) and times, as fresh processes, interleaved in a
rotated order each round:

- default: `jointid fit --csv FILE --json` (low-pass, decimation, the robust step and standstill with the
  log's coulomb+bias model, sensitivity check),
- off:     `jointid fit --csv FILE --json --cutoff 0 --no-robust --model plain` (none of them),
- pandas:  the script a user would write, `pandas.read_csv(path)` + `numpy.linalg.lstsq`.

Each child's wall time (from spawning it to its exit), CPU time (user +
system, less disturbed than wall time by other processes on a shared machine)
and peak resident set (ru_maxrss from os.wait4; this parent imports nothing
heavy before the children run, so its own pages do not count) are printed as
min / median / max over the rounds, with per-round ratios. Goals: the default's overhead over
`off`, (default - off) / pandas per round, at most 0.10 at the median; the
default's peak RSS at most the pandas script's (median of the per-round ratio
at most 1.0).

Then, in this process, 7 interleaved rounds of `fit_logs` on the loaded log
(the filter's choice from the motion's bandwidth, the low-pass and decimation,
the fit, and the sensitivity refits), `fit_logs` with `--cutoff 0`, no robust step and no
check, and one `numpy.linalg.lstsq` of the full-rate 1e6 x 3 regressor,
printed as ratios to lstsq.
"""

from __future__ import annotations

import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

PANDAS_SCRIPT = """\
import sys, numpy as np, pandas as pd
d = pd.read_csv(sys.argv[1], comment="#")
X = np.column_stack([d.qdd, 9.81*np.cos(d.q), d.qd])
print(np.linalg.lstsq(X, d.tau.to_numpy(), rcond=None)[0])
"""
"""The baseline: a user's load and fit of the same file (the file starts with a # comment line)."""

GOAL_OVERHEAD = 0.10
"""(default - off) / pandas, median over the rounds."""
GOAL_RSS = 1.0
"""default peak RSS / pandas peak RSS, median over the rounds."""


def run(command: list[str]) -> tuple[float, float, int]:
    """(wall seconds, CPU seconds, peak RSS bytes) of one child process, its output discarded; exits on failure."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    devnull = os.open(os.devnull, os.O_WRONLY)
    actions = [(os.POSIX_SPAWN_DUP2, devnull, 1)]
    start = time.perf_counter()
    pid = os.posix_spawn(command[0], command, env, file_actions=actions)
    _, status, usage = os.wait4(pid, 0)
    seconds = time.perf_counter() - start
    os.close(devnull)
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"failed: {' '.join(command)}")
    return seconds, usage.ru_utime + usage.ru_stime, usage.ru_maxrss * 1024


def spread(values) -> str:
    """'min / median / max' of the values."""
    return f"{min(values):.3f} / {statistics.median(values):.3f} / {max(values):.3f}"


def in_process(path: Path, rounds: int) -> None:
    """Time fit_logs default and off, and lstsq of the full-rate regressor, interleaved in this process."""
    import numpy as np

    sys.path.insert(0, str(ROOT))
    from jointid.estimation.exclusion import ExclusionRequest
    from jointid.estimation.low_pass import FilterRequest
    from jointid.present.notes import low_pass_note
    from jointid.logs.csv_reader import load_log
    from jointid.model.terms import PLAIN
    from jointid.studies.log_fit import fit_logs

    log = load_log(str(path))
    X = PLAIN.data_regressor(log.data)
    tau = log.data.tau
    cases = {
        "default": lambda: fit_logs(log),
        "off": lambda: fit_logs(log, filtering=FilterRequest(0), sensitivity=False, exclusion=ExclusionRequest(False)),
        "lstsq": lambda: np.linalg.lstsq(X, tau, rcond=None),
    }
    times = {name: [] for name in cases}
    names = list(cases)
    for round_ in range(rounds):
        for name in names[round_ % 3:] + names[: round_ % 3]:
            start = time.perf_counter()
            cases[name]()
            times[name].append(time.perf_counter() - start)
    chosen = fit_logs(log).filter
    print(f"\nin process ({rounds} rounds): the chosen low-pass: {low_pass_note(chosen)}")
    for name in ("default", "off"):
        ratios = [a / b for a, b in zip(times[name], times["lstsq"])]
        print(f"  fit_logs {name:<8} / one lstsq of the {len(tau)} x 3 regressor: {spread(ratios)}")
    added = [(d - o) / b for d, o, b in zip(times["default"], times["off"], times["lstsq"])]
    print(f"  (default - off) / lstsq, what the filter and the check add: {spread(added)}")
    print(f"  (seconds, min / median / max: default {spread(times['default'])}, off {spread(times['off'])}, "
          f"lstsq {spread(times['lstsq'])})")


def main(rows: int = 1_000_000, rounds: int = 7) -> int:
    """Write the log, time the three commands as fresh processes and in process, print ratios and goals."""
    python = sys.executable
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "log.csv"
        script = Path(folder) / "pandas_fit.py"
        script.write_text(PANDAS_SCRIPT)
        run([python, "-m", "jointid", "simulate", "--samples", str(rows), "--duration", str(rows / 1000),
             "--noise", "0.2", "--out", str(path)])
        print(f"log: {rows} rows x 5 columns at 1 kHz, {path.stat().st_size / 1e6:.1f} MB; {rounds} rounds")
        fit = [python, "-m", "jointid", "fit", "--csv", str(path), "--json"]
        commands = {"default": fit, "off": fit + ["--cutoff", "0", "--no-robust", "--model", "plain"],
                    "pandas": [python, str(script), str(path)]}
        seconds = {name: [] for name in commands}
        cpu = {name: [] for name in commands}
        rss = {name: [] for name in commands}
        names = list(commands)
        for round_ in range(rounds):
            for name in names[round_ % 3:] + names[: round_ % 3]:
                wall, used, peak = run(commands[name])
                seconds[name].append(wall)
                cpu[name].append(used)
                rss[name].append(peak)
        print("fresh processes, wall seconds, CPU seconds (user + system) and peak RSS (MB), min / median / max:")
        for name in names:
            print(f"  {name:<8} {spread(seconds[name])} s   {spread(cpu[name])} s CPU   "
                  f"{spread([b / 1e6 for b in rss[name]])} MB")
        per_round = {
            "default / pandas, time": [d / p for d, p in zip(seconds["default"], seconds["pandas"])],
            "off / pandas, time": [o / p for o, p in zip(seconds["off"], seconds["pandas"])],
            "(default - off) / pandas, time": [(d - o) / p for d, o, p in
                                               zip(seconds["default"], seconds["off"], seconds["pandas"])],
            "(default - off) / pandas, CPU": [(d - o) / p for d, o, p in
                                              zip(cpu["default"], cpu["off"], cpu["pandas"])],
            "default / pandas, peak RSS": [d / p for d, p in zip(rss["default"], rss["pandas"])],
            "default / off, peak RSS": [d / o for d, o in zip(rss["default"], rss["off"])],
        }
        print("ratios per round, min / median / max:")
        for label, values in per_round.items():
            print(f"  {label:<32} {spread(values)}")
        overhead = statistics.median(per_round["(default - off) / pandas, time"])
        memory = statistics.median(per_round["default / pandas, peak RSS"])
        print(f"goal: overhead <= {GOAL_OVERHEAD:.2f} of the pandas script's time: "
              f"{'met' if overhead <= GOAL_OVERHEAD else 'MISSED'} ({overhead:.3f}); "
              f"peak RSS <= {GOAL_RSS:.1f}x the script's: {'met' if memory <= GOAL_RSS else 'MISSED'} "
              f"({memory:.3f})")
        in_process(path, rounds)
    return 0


if __name__ == "__main__":
    raise SystemExit(main(*(int(a) for a in sys.argv[1:3])))
