"""Seed sweep: one factorisation for K seeds against the naive run_experiment-per-seed loop.

Run: .venv/bin/python benchmarks/bench_sweep.py
Prints both times for K = 10,000 seeds at N = 24 samples (slow motion, noise
0.20, seeds from 1000), their ratio, and whether the sweep meets its 50 ms
goal. Both run in this one process; the sweep's time is the best of several
runs after a warm-up, the loop's is one run (it takes seconds).
"""

import time

import numpy as np
from bench_noise import best_of  # the script's own folder is on sys.path

from jointid.studies.experiment import run_experiment
from jointid.studies.sweep import run_sweep
from jointid.synthetic.settings import Settings

SEEDS = 10_000
GOAL_SECONDS = 0.050
SETTINGS = Settings(motion="slow", noise=0.2, samples=24, seed=1000)


def naive_loop() -> np.ndarray:
    """(3, K) estimates from one run_experiment per seed."""
    motion, noise, samples, first = SETTINGS.motion, SETTINGS.noise, SETTINGS.samples, SETTINGS.seed
    return np.array(
        [run_experiment(Settings(motion, noise, samples, first + k)).estimate for k in range(SEEDS)]
    ).T


def main() -> None:
    """Time both ways, check they agree, and print the ratio."""
    run_sweep(SETTINGS, SEEDS)  # warm-up: imports, cached validation data, LCG coefficients
    sweep_time = best_of(7, lambda: run_sweep(SETTINGS, SEEDS))
    start = time.perf_counter()
    loop_estimates = naive_loop()
    loop_time = time.perf_counter() - start
    identical = np.array_equal(run_sweep(SETTINGS, SEEDS).estimates, loop_estimates)
    verdict = "met" if sweep_time <= GOAL_SECONDS else "NOT met"
    print(f"K = {SEEDS:,} seeds, N = {SETTINGS.samples} samples, {SETTINGS.motion} motion, noise {SETTINGS.noise}")
    print(f"vectorised sweep: {1000 * sweep_time:8.2f} ms (best of 7)")
    print(f"per-seed loop:    {1000 * loop_time:8.2f} ms (run_experiment per seed)")
    print(f"ratio loop/sweep: {loop_time / sweep_time:8.1f}x")
    print(f"estimates identical: {identical}")
    print(f"50 ms goal: {verdict}")


if __name__ == "__main__":
    main()
