"""The robust default and pooled runs against the plain ways a user would fit the same data.

1. A 1,000,000-row log (500 Hz, the rich motion on a Coulomb joint, 12-bit
   angles, torque noise, a push every 20 s): `fit_log` with its defaults (the
   robust step, standstill) against `fit_log(..., robust=False)` of the same
   arrays, both with the sensitivity check; goal: robust / plain <= 1.5.
2. Ten runs of 100,000 rows each: `fit_runs` (each run prepared alone, then
   pooled, each predicted by the others) against one `fit_logs` of their
   concatenation (times made continuous); goal: runs / concatenation <= 1.2.

Interleaved rounds, min / median / max of the ratios.

    PYTHONPATH=. .venv/bin/python benchmarks/bench_robust.py [ROUNDS]
"""

from __future__ import annotations

import sys
import time

import numpy as np

from jointid.logs.arrays import read_arrays
from jointid.logs.pipeline import joint_log_from_table
from jointid.model.terms import model_named
from jointid.studies.log_fit import fit_log, fit_logs
from jointid.studies.runs import fit_runs

RATE = 500.0


def joint_log(rows: int, seed: int, start: float = 0.0) -> dict:
    """t, q, tau of the rich motion on a joint with Coulomb friction 0.2 N m, pushed 1 N m for 1 s every 20 s."""
    rng = np.random.default_rng(seed)
    t = start + np.arange(rows) / RATE
    q = 0.7 * np.sin(1.3 * t) + 0.25 * np.sin(2.7 * t)
    qd = 0.91 * np.cos(1.3 * t) + 0.675 * np.cos(2.7 * t)
    qdd = -1.183 * np.sin(1.3 * t) - 1.8225 * np.sin(2.7 * t)
    tau = 0.8 * qdd + 0.4 * 9.81 * np.cos(q) + 0.15 * qd + 0.2 * np.sign(qd) + rng.normal(0, 0.05, rows)
    phase = np.mod(t, 20.0)
    tau -= np.where(phase < 1.0, 0.5 * (1 - np.cos(2 * np.pi * phase)), 0.0)
    step = 2 * np.pi / 4096
    return {"t": t, "q": np.round(q / step) * step, "tau": tau}


def timed(run) -> float:
    """Wall seconds of one call."""
    start = time.perf_counter()
    run()
    return time.perf_counter() - start


def interleaved_ratios(ours, baseline, rounds: int) -> list[float]:
    """ours / baseline wall time per round, which runs first alternating."""
    ratios = []
    for round_index in range(rounds):
        first, second = (ours, baseline) if round_index % 2 == 0 else (baseline, ours)
        a, b = timed(first), timed(second)
        ratios.append(a / b if round_index % 2 == 0 else b / a)
    return ratios


def summary(ratios: list[float]) -> str:
    """min / median / max."""
    return f"{min(ratios):.2f} / {float(np.median(ratios)):.2f} / {max(ratios):.2f}"


def main() -> None:
    """Print both ratios."""
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    big = joint_log(1_000_000, 1)
    robust_ratios = interleaved_ratios(lambda: fit_log(big), lambda: fit_log(big, robust=False), rounds)
    print(f"1,000,000 rows, robust default / robust=False (both with the sensitivity check), {rounds} rounds: "
          f"{summary(robust_ratios)}  (goal 1.5)")

    runs = [joint_log(100_000, seed, start=seed * 100_000 / RATE) for seed in range(10)]
    logs = [joint_log_from_table(read_arrays(run)) for run in runs]
    joined = joint_log_from_table(read_arrays({key: np.concatenate([run[key] for run in runs]) for key in runs[0]}))
    model = model_named("coulomb+bias")
    pooling_ratios = interleaved_ratios(lambda: fit_runs(logs, model), lambda: fit_logs(joined, model=model), rounds)
    print(f"10 runs of 100,000 rows, fit_runs / fit_logs of their concatenation, {rounds} rounds: "
          f"{summary(pooling_ratios)}  (goal 1.2)")


if __name__ == "__main__":
    main()
