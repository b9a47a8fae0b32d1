"""How often the defaults meet issue 14's acceptance on robot-like logs, over many seeds (not a timing).

tests/core/logs/test_robot_logs.py checks one seed per rate; this runs the same closed-form
logs (the lesson's joint, +-10 % jitter, 12-bit angles, torque noise of 10 % of
its RMS, 20 s) over SEEDS seeds at 50, 300 and 1000 Hz through `jointid fit`'s
defaults and prints, per rate: fits missing "within 3 % or 3 standard errors",
default fits the sensitivity check flags, and the RMS of each parameter's
error in its standard errors (1 when the standard errors are honest).

    PYTHONPATH=. python benchmarks/real_logs_study.py [SEEDS] [ORDER]

ORDER (default: jointid's) sets the Savitzky-Golay order, to compare orders.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

from support.robot_logs import TRUE, robot_log  # noqa: E402  (the tests' own generator)

from jointid.logs.pipeline import joint_log_from_table
from jointid.logs.table import LogTable  # noqa: E402
from jointid.options import DEFAULT_ORDER
from jointid.studies.log_fit import fit_logs  # noqa: E402


def main() -> None:
    """Print the study's counts per rate."""
    seeds = int(sys.argv[1]) if len(sys.argv) > 1 else 20
    order = int(sys.argv[2]) if len(sys.argv) > 2 else DEFAULT_ORDER
    print(f"Savitzky-Golay order {order}")
    truth = np.array(list(TRUE.values()))
    for rate in (50, 300, 1000):
        misses = flags = 0
        errors = []
        for seed in range(seeds):
            columns = robot_log(rate, seed=seed)
            table = LogTable(f"robot_{rate}_{seed}.csv", columns, {"t": 1, "q": 2, "tau": 3}, (), ((0, 0),))
            logs = fit_logs(joint_log_from_table(table, order=order))
            estimate, std_error = logs.result.estimate, logs.result.uncertainty.residual_std_error
            misses += not np.all(np.abs(estimate - truth) <= np.maximum(0.03 * truth, 3 * std_error))
            flags += logs.sensitivity.flagged
            errors.append((estimate - truth) / std_error)
        z = np.sqrt(np.mean(np.square(errors), axis=0))
        print(f"{rate:>5} Hz, {seeds} seeds: {misses} outside 3 % / 3 SE, {flags} flagged by the sensitivity "
              f"check; RMS error in standard errors I {z[0]:.2f}, h {z[1]:.2f}, B {z[2]:.2f}")


if __name__ == "__main__":
    main()
