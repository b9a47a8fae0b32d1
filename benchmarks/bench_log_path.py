"""The log path against the script a user would write instead: like for like, and with every default.

Run from the repository root: PYTHONPATH=. .venv/bin/python benchmarks/bench_log_path.py [ROUNDS [ROWS]]

It writes a 1,000,000-row log of t, q, qd, qdd, tau (common.write_log: the rich motion at 1 kHz, 17 significant
digits, about 97 MB) and runs interleaved rounds of three fresh processes, their order rotating from round to round:

- the script: `pandas.read_csv(path)`, the regressor by hand and `numpy.linalg.lstsq` (bench_log_load's);
- like for like: `jointid fit --csv FILE --json --model plain --no-robust --cutoff 0` (the same model, every
  sample, no filter), goal at most 1.0x the script;
- every default: `jointid fit --csv FILE --json` (the log model, the automatic low-pass and decimation, the robust
  step, standstill, the sensitivity refits, the omitted-terms test), goal at most 1.5x the script.

It prints each one's wall and CPU time and each ratio to the script in the same round as min / median / max (the goal
is on wall time; CPU time, from os.wait4, is less moved by a busy machine), and whether
each median meets its goal (exit 1 if not). Then, in this process and warm, where the default path spends its
time beyond the like-for-like fit (median of 3 calls each, wall and CPU seconds), to say which step to make
cheaper.
"""

from __future__ import annotations

import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from bench_log_load import BASELINE_SCRIPT  # noqa: E402  (this folder is first on sys.path)
from common import JOINTID, launch, write_log  # noqa: E402

ROUNDS = 7
ROWS = 1_000_000
LIKE_FOR_LIKE = ["--model", "plain", "--no-robust", "--cutoff", "0"]
GOALS = {"like for like": 1.0, "every default": 1.5}


def spread(values: list[float]) -> str:
    """'min / median / max' to two decimals."""
    return " / ".join(f"{value:.2f}" for value in (min(values), statistics.median(values), max(values)))


def default_path_steps(path: Path) -> dict[str, tuple[float, float]]:
    """Median (wall, CPU) seconds (3 warm calls) of each step of the default log fit beyond the like-for-like fit;
    CPU above wall is work done on more than one core (jointid.threads)."""
    import functools

    import jointid.estimation.low_pass as low_pass
    import jointid.studies.log_fit as log_fit
    from jointid.estimation.exclusion import ExclusionRequest
    from jointid.estimation.low_pass import FilterRequest
    from jointid.logs.csv_reader import read_table
    from jointid.logs.pipeline import joint_log_from_table
    from jointid.model.terms import model_named
    from jointid.options import LOG_MODEL

    steps = {"the automatic cutoff": (low_pass, "automatic_cutoff"),
             "low-pass of the columns (refits', candidates')": (log_fit, "filtered_regressors"),
             "robust step": (log_fit, "outside_torques"), "sensitivity refits": (log_fit, "_sensitivity"),
             "omitted-terms test": (log_fit, "_omitted_terms")}
    spent: dict[str, list[tuple[float, float]]] = {name: [] for name in (*steps, "whole fit", "like-for-like fit")}
    this_call: dict[str, tuple[float, float]] = {}

    def now() -> tuple[float, float]:
        return time.perf_counter(), time.process_time()

    def since(start: tuple[float, float]) -> tuple[float, float]:
        return tuple(b - a for a, b in zip(start, now()))

    for name, (module, attribute) in steps.items():
        def timed(*args, _function=getattr(module, attribute), _name=name, **kwargs):
            start = now()
            try:
                return _function(*args, **kwargs)
            finally:
                before = this_call.get(_name, (0.0, 0.0))
                this_call[_name] = tuple(a + b for a, b in zip(before, since(start)))
        setattr(module, attribute, functools.wraps(getattr(module, attribute))(timed))
    log = joint_log_from_table(read_table(path))
    for _ in range(3):
        this_call.clear()
        start = now()
        log_fit.fit_logs(log, model=model_named(LOG_MODEL))
        spent["whole fit"].append(since(start))
        for name in steps:
            spent[name].append(this_call.get(name, (0.0, 0.0)))
        start = now()
        log_fit.fit_logs(log, model=model_named("plain"), filtering=FilterRequest(0),
                         exclusion=ExclusionRequest(False))
        spent["like-for-like fit"].append(since(start))
    return {name: tuple(statistics.median(value[k] for value in values) for k in (0, 1))
            for name, values in spent.items()}


def main() -> int:
    """Write the log, run the rounds, print the ratios and the default path's steps; exit 1 if a goal is missed."""
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else ROUNDS
    rows = int(sys.argv[2]) if len(sys.argv) > 2 else ROWS
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "log.csv"
        write_log(path, rows)
        script = Path(folder) / "script.py"
        script.write_text(BASELINE_SCRIPT)
        commands = {"script": [sys.executable, str(script), str(path)],
                    "like for like": JOINTID + ["fit", "--csv", str(path), "--json", *LIKE_FOR_LIKE],
                    "every default": JOINTID + ["fit", "--csv", str(path), "--json"]}
        print(f"log: {rows:,} rows x 5 columns, {path.stat().st_size / 1e6:.1f} MB; {rounds} interleaved rounds")
        for command in commands.values():  # warm-up: bytecode caches, the page cache
            launch(command)
        seconds: dict[str, list[tuple[float, float]]] = {name: [] for name in commands}
        ratios: dict[str, list[float]] = {name: [] for name in GOALS}
        cpu_ratios: dict[str, list[float]] = {name: [] for name in GOALS}
        names = list(commands)
        for index in range(rounds):
            order = names[index % len(names):] + names[:index % len(names)]
            this_round = {name: launch(commands[name]) for name in order}
            for name, value in this_round.items():
                seconds[name].append(value)
            for name in GOALS:
                ratios[name].append(this_round[name][0] / this_round["script"][0])
                cpu_ratios[name].append(this_round[name][1] / this_round["script"][1])
        for name, values in seconds.items():
            print(f"{name:>14}: wall {spread([v[0] for v in values])} s, CPU {spread([v[1] for v in values])} s")
        missed = []
        for name, goal in GOALS.items():
            met = statistics.median(ratios[name]) <= goal
            missed += [] if met else [name]
            print(f"{name:>14} / script: wall {spread(ratios[name])}  (goal {goal:g}: {'met' if met else 'missed'}); "
                  f"CPU {spread(cpu_ratios[name])}")
        print("\nThe default fit's steps in this process (seconds, median of 3 warm calls):")
        for name, (wall, cpu) in default_path_steps(path).items():
            print(f"  {name:<47} wall {wall:.3f}  CPU {cpu:.3f}")
    return 1 if missed else 0


if __name__ == "__main__":
    sys.exit(main())
