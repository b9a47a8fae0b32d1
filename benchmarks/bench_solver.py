"""The pivoted Householder solver at millions of rows, beside numpy.linalg.lstsq.

Run: .venv/bin/python benchmarks/bench_solver.py
Prints wall time and peak traced memory of both, and their ratios, measured in
this one process. Memory is given as a multiple of the regressor's own size.
"""

import time
import tracemalloc

import numpy as np

from jointid.solver import solve_least_squares


def measure(function):
    """(result, seconds, peak bytes allocated while running `function`)."""
    tracemalloc.start()
    start = time.perf_counter()
    result = function()
    seconds = time.perf_counter() - start
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return result, seconds, peak


def main() -> None:
    """Solve a 3-column problem at 1e6 and 1e7 rows with both solvers."""
    rng = np.random.default_rng(0)
    for rows in (1_000_000, 10_000_000):
        X = rng.normal(size=(rows, 3)) * [1.4, 9.81, 0.8]
        y = X @ [0.8, 0.4, 0.15] + 0.2 * rng.uniform(-1, 1, rows)
        data_bytes = X.nbytes
        ours, our_time, our_peak = measure(lambda: solve_least_squares(X, y).estimate)
        ref, ref_time, ref_peak = measure(lambda: np.linalg.lstsq(X, y, rcond=None)[0])
        assert np.allclose(ours, ref, rtol=1e-9)
        print(
            f"{rows:>10,} rows: ours {our_time:.3f} s, peak {our_peak / data_bytes:.2f}x X; "
            f"lstsq {ref_time:.3f} s, peak {ref_peak / data_bytes:.2f}x X; "
            f"time ratio ours/lstsq {our_time / ref_time:.2f}"
        )


if __name__ == "__main__":
    main()
