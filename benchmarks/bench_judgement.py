"""What judging a log fit costs: the refits behind one verdict per parameter, against the fit they judge.

A 1,000,000-row log (bench_robust's: 500 Hz, the rich motion on a Coulomb joint, 12-bit angles, torque noise, a
push every 20 s) fitted once by `fit_log` with its defaults; then, interleaved round by round, the judgement's own
work (`judge_log`: the --no-robust refit and the halves, each from the already filtered columns) against the whole
`fit_logs` of the same loaded log (which includes it). Prints judge / fit, min / median / max; the share of the
default path the judgement adds (goal: a few percent, so the log path stays within i31's 1.5x of pandas + lstsq).

    PYTHONPATH=. .venv/bin/python benchmarks/bench_judgement.py [ROUNDS]
"""

from __future__ import annotations

import statistics
import sys

from bench_robust import joint_log, timed

from jointid.logs.arrays import read_arrays
from jointid.logs.pipeline import joint_log_from_table
from jointid.model.terms import model_named
from jointid.options import LOG_MODEL
from jointid.studies.log_fit import fit_logs, judge_log


def main(rounds: int) -> None:
    log = joint_log_from_table(read_arrays(joint_log(1_000_000, 1), "arrays"))
    model = model_named(LOG_MODEL)
    fitted = fit_logs(log, model=model)
    ratios = []
    for index in range(rounds):
        judge = lambda: judge_log(fitted)  # noqa: E731
        fit = lambda: fit_logs(log, model=model)  # noqa: E731
        if index % 2 == 0:
            a, b = timed(judge), timed(fit)
        else:
            b, a = timed(fit), timed(judge)
        ratios.append(a / b)
    print(f"judge_log / fit_logs on 1e6 rows ({fitted.result.training.count} fitted samples), {rounds} rounds: "
          f"min {min(ratios):.3f}, median {statistics.median(ratios):.3f}, max {max(ratios):.3f}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 5)
