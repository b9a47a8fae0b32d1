"""The blocked, pivoted Householder solver at millions of rows, beside numpy.linalg.lstsq.

Run from the repository root:
    PYTHONPATH=. .venv/bin/python benchmarks/bench_solver.py [--rounds 7] [--rows 1000000,10000000]
    PYTHONPATH=. .venv/bin/python benchmarks/bench_solver.py --tune 4096,8192,16384,32768

For each row count N, column count p (3, 6) and memory order (C, F) it times,
in one process and interleaved round by round (the order of the four rotates
each round): `solve_least_squares`, `numpy.linalg.lstsq`, one pass over the
data (`X.sum()`) and a normal-equations solve (X^T X theta = X^T y, the fastest
and least accurate way). It prints ours / baseline for each round's pair as
min / median / max over the rounds, then peak extra memory as a multiple of
the regressor's size: traced by tracemalloc in this process, and the growth of
the peak resident set (which also sees LAPACK's workspace) in a fresh process
per solver. Goals: median ours / lstsq <= 0.5, median ours / X.sum() <= 15,
memory <= 0.25. Exits 1 if the estimates disagree with lstsq's.

--tune times `solve_least_squares` with each block size (values of X per
block; see `jointid.estimation.solver.block_rows_for`) against
X.sum(), interleaved, to choose `jointid.estimation.solver.BLOCK_VALUES`.
"""

import argparse
import json
import os
import subprocess
import sys
import time
import tracemalloc

import numpy as np

from jointid.estimation.solver import BLOCK_VALUES, block_rows_for, solve_least_squares

THETA = np.array([0.8, 0.4, 0.15, 0.05, -0.02, 0.3])
SCALES = np.array([1.4, 9.81, 0.8, 1.0, 0.6, 2.0])
NOISE = 0.2
GOALS = {"lstsq": 0.5, "sum": 15.0, "memory": 0.25}


def make_problem(rows: int, columns: int, order: str, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """A regressor (rows, columns) in the given memory order and a noisy y, built without full-size temporaries."""
    rng = np.random.default_rng(seed)
    X = np.empty((rows, columns), order=order)
    y = np.empty(rows)
    step = 1 << 20
    for start in range(0, rows, step):
        block = X[start : start + step]
        block[...] = rng.standard_normal((len(block), columns)) * SCALES[:columns]
        y[start : start + step] = block @ THETA[:columns] + NOISE * rng.uniform(-1, 1, len(block))
    return X, y


def ours(X, y):
    """The estimate of jointid's solver."""
    return solve_least_squares(X, y).estimate


def lstsq(X, y):
    """The estimate of numpy.linalg.lstsq (SVD-based, no scaling, no pivoting)."""
    return np.linalg.lstsq(X, y, rcond=None)[0]


def normal_equations(X, y):
    """The estimate from X^T X theta = X^T y: one BLAS pass, but it squares the condition number."""
    return np.linalg.solve(X.T @ X, X.T @ y)


def one_pass(X, y):
    """One pass over the data: the floor for anything that reads X."""
    return X.sum()


SOLVERS = {"ours": ours, "lstsq": lstsq, "normal": normal_equations, "sum": one_pass}


def timed_rounds(functions: dict, rounds: int, warm_up: dict) -> tuple[dict[str, list[float]], dict]:
    """(seconds per call of each function, each one's last result): every round runs all, in a rotated order."""
    names = list(functions)
    times = {name: [] for name in names}
    results = {}
    for name in names:  # first-call costs (imports, LAPACK's set-up) on a small problem
        warm_up[name]()
    for round_index in range(rounds):
        shift = round_index % len(names)
        order = names[shift:] + names[:shift]
        if round_index % 2:
            order.reverse()
        for name in order:
            start = time.perf_counter()
            results[name] = functions[name]()
            times[name].append(time.perf_counter() - start)
    return times, results


def spread(numerators: list[float], denominators: list[float]) -> tuple[float, float, float]:
    """(min, median, max) of the per-round ratios."""
    ratios = np.array(numerators) / np.array(denominators)
    return float(ratios.min()), float(np.median(ratios)), float(ratios.max())


def traced_peak(function) -> int:
    """Peak bytes traced by tracemalloc while `function` runs."""
    tracemalloc.start()
    function()
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return peak


def rss_child(rows: int, columns: int, order: str, solver: str) -> None:
    """In a fresh process: print the growth of the peak resident set while `solver` runs, in bytes."""
    X, y = make_problem(rows, columns, order)
    SOLVERS[solver](X[:2000], y[:2000])  # warm-up (LAPACK's first call), below the blocked path's sizes
    with open("/proc/self/clear_refs", "w") as refs:
        refs.write("5")  # reset VmHWM to the current resident set
    before = proc_status("VmRSS")
    SOLVERS[solver](X, y)
    print(json.dumps({"extra": proc_status("VmHWM") - before}))


def proc_status(field: str) -> int:
    """A memory field of /proc/self/status, in bytes."""
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith(field + ":"):
                return int(line.split()[1]) * 1024
    raise RuntimeError(f"{field} not in /proc/self/status")


def rss_extra(rows: int, columns: int, order: str, solver: str) -> int | None:
    """Peak resident-set growth of `solver` measured in a fresh process (None where /proc is unavailable)."""
    if not os.path.exists("/proc/self/clear_refs"):
        return None
    command = [sys.executable, __file__, "--rss-child", f"{rows},{columns},{order},{solver}"]
    output = subprocess.run(command, capture_output=True, text=True, check=True).stdout
    return json.loads(output.splitlines()[-1])["extra"]


def agreement(theta: np.ndarray, reference: np.ndarray, X: np.ndarray) -> float:
    """Largest difference of the two estimates in unit-column coordinates, relative to the estimate's size."""
    norms = np.sqrt(np.einsum("ij,ij->j", X, X))
    return float(np.max(np.abs((theta - reference) * norms)) / np.max(np.abs(reference * norms)))


def compare(rows: int, columns: int, order: str, rounds: int) -> tuple[bool, list[str]]:
    """Print one (N, p, order) line set; (whether the estimates agree with lstsq's, the goals missed)."""
    X, y = make_problem(rows, columns, order)
    times, results = timed_rounds(
        {name: (lambda f=f: f(X, y)) for name, f in SOLVERS.items()},
        rounds,
        {name: (lambda f=f: f(X[:20_000], y[:20_000])) for name, f in SOLVERS.items()},
    )
    difference = agreement(results["ours"], results["lstsq"], X)
    size = X.nbytes
    traced = traced_peak(lambda: ours(X, y)) / size
    del X, y, results
    resident = {name: rss_extra(rows, columns, order, name) for name in ("ours", "lstsq")}
    to_lstsq = spread(times["ours"], times["lstsq"])
    to_sum = spread(times["ours"], times["sum"])
    to_normal = spread(times["ours"], times["normal"])
    memory = max(traced, (resident["ours"] or 0) / size)
    print(f"N = {rows:,}, p = {columns}, {order}-ordered ({size / 1e6:.0f} MB), {rounds} rounds")
    lstsq_met = verdict(to_lstsq[1] <= GOALS["lstsq"])
    print(f"  ours / lstsq           {fmt(to_lstsq)}   goal <= {GOALS['lstsq']}: {lstsq_met}")
    print(f"  ours / X.sum()         {fmt(to_sum)}   goal <= {GOALS['sum']}: {verdict(to_sum[1] <= GOALS['sum'])}")
    print(f"  ours / normal eqs.     {fmt(to_normal)}")
    print(f"  lstsq / X.sum()        {fmt(spread(times['lstsq'], times['sum']))}")
    # A QR does twice the normal equations' arithmetic: their ratio to one pass is the floor this machine sets.
    print(f"  normal eqs. / X.sum()  {fmt(spread(times['normal'], times['sum']))}")
    print(
        f"  peak extra memory / X  ours: traced {traced:.3f}, resident {mem(resident['ours'], size)};"
        f"  lstsq: resident {mem(resident['lstsq'], size)}"
        f"   goal <= {GOALS['memory']}: {verdict(memory <= GOALS['memory'])}"
    )
    print(f"  agreement with lstsq   {difference:.1e} (largest scaled difference)", flush=True)
    case = f"N = {rows:,}, p = {columns}, {order}"
    missed = [
        f"{case}: {goal}"
        for goal, met in (
            ("ours / lstsq", to_lstsq[1] <= GOALS["lstsq"]),
            ("ours / X.sum()", to_sum[1] <= GOALS["sum"]),
            ("memory", memory <= GOALS["memory"]),
        )
        if not met
    ]
    return difference <= 1e-9, missed


def tune(rows_list: list[int], blocks: list[int], rounds: int) -> None:
    """Print solve time / X.sum() for each block size (values of X per block), interleaved."""
    for rows in rows_list:
        for columns in (3, 6):
            for order in "CF":
                X, y = make_problem(rows, columns, order)
                functions = {"sum": lambda: X.sum()}
                for block in blocks:
                    rows_per_block = block_rows_for(columns, block)
                    functions[block] = lambda b=rows_per_block: solve_least_squares(X, y, block_rows=b).estimate
                times = timed_rounds(functions, rounds, functions)[0]
                cells = "  ".join(f"{block}: {fmt(spread(times[block], times['sum']), 4)}" for block in blocks)
                print(f"N = {rows:,}, p = {columns}, {order}: ours / X.sum()  {cells}", flush=True)


def fmt(values: tuple[float, float, float], width: int = 5) -> str:
    """min / median / max."""
    return " / ".join(f"{v:{width}.2f}" for v in values)


def mem(extra: int | None, size: int) -> str:
    """A resident-set growth as a multiple of the regressor's size."""
    return "n/a" if extra is None else f"{extra / size:.3f}"


def verdict(met: bool) -> str:
    """'met' or 'NOT met'."""
    return "met" if met else "NOT met"


def main() -> None:
    """Parse the options and run the comparison (or the block-size tuning)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--rows", default="1000000,10000000")
    parser.add_argument("--tune", help="comma-separated block sizes to compare")
    parser.add_argument("--rss-child", help=argparse.SUPPRESS)
    options = parser.parse_args()
    if options.rss_child:
        rows, columns, order, solver = options.rss_child.split(",")
        rss_child(int(rows), int(columns), order, solver)
        return
    rows_list = [int(r) for r in options.rows.split(",")]
    if options.tune:
        tune(rows_list, [int(b) for b in options.tune.split(",")], options.rounds)
        return
    print(
        f"solve_least_squares with BLOCK_VALUES = {BLOCK_VALUES} (blocks of {block_rows_for(3)} rows at p = 3, "
        f"{block_rows_for(6)} at p = 6); ratios are min / median / max over rounds"
    )
    cases = [(rows, columns, order) for rows in rows_list for columns in (3, 6) for order in "CF"]
    outcomes = [compare(*case, options.rounds) for case in cases]
    agree = all(agreed for agreed, _ in outcomes)
    missed = [goal for _, goals in outcomes for goal in goals]
    print(f"estimates agree with lstsq (scaled difference <= 1e-9): {agree}")
    print("goals met: all" if not missed else "goals NOT met: " + "; ".join(missed))
    if not agree:
        sys.exit(1)


if __name__ == "__main__":
    main()
