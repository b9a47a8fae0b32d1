"""The model ladder and the simulation check, as ratios to what a user would otherwise run.

Run: .venv/bin/python benchmarks/bench_ladder.py [--rows N] [--rounds R]

1. `compare` on N log rows (default 1,000,000) of a Coulomb joint against one plain
   fit of the same rows (`fit_joint`, what `jointid fit --csv` runs after loading):
   goal at most 3x. Both see the same in-memory JointData; rounds interleave.
2. The simulation check of each ladder model (8 windows of 1 s) against one
   solve_ivp integration of the true joint over the whole 8 s, the least a user
   who wanted any simulation would run; the issue's goal is 0.5 s per model, so
   the absolute time is printed too, beside the baseline that calibrates it.
Every figure is min / median / max over the rounds.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from jointid.estimation.fit import fit_joint
from jointid.model.truth import TrueJoint
from jointid.options import LADDER
from jointid.samples import JointData
from jointid.studies.experiment import run_experiment
from jointid.studies.ladder import compare_models
from jointid.studies.simulation import simulation_check
from jointid.synthetic.motions import TRAINING_MOTIONS, VALIDATION_MOTION
from jointid.synthetic.settings import Settings

JOINT = TrueJoint(coulomb=0.3)


def log_rows(count: int) -> JointData:
    """A Coulomb joint's rich motion sampled `count` times over 8 s with bounded noise."""
    states = TRAINING_MOTIONS["rich"].states(np.linspace(0.0, 8.0, count))
    noise = np.random.default_rng(7).uniform(-0.05, 0.05, count)
    return JointData(t=states.t, q=states.q, qd=states.qd, qdd=states.qdd,
                     tau=JOINT.measured_torque(states.q, states.qd, states.qdd) + noise)


def timed(function) -> float:
    start = time.perf_counter()
    function()
    return time.perf_counter() - start


def spread(values: list[float]) -> str:
    return f"{min(values):.2f} / {statistics.median(values):.2f} / {max(values):.2f}"


def true_simulation() -> None:
    """The baseline: solve_ivp of the true joint along the validation motion's torque, once over 8 s."""
    from scipy.integrate import solve_ivp

    def rates(t, state):
        states = VALIDATION_MOTION.states(t)
        torque = float(JOINT.measured_torque(states.q, states.qd, states.qdd))
        q, qd = state
        rest = float(JOINT.measured_torque(q, qd, 0.0))
        return [qd, (torque - rest) / JOINT.inertia]

    start = VALIDATION_MOTION.states(0.0)
    solve_ivp(rates, (0.0, 8.0), [float(start.q), float(start.qd)], method="LSODA", rtol=1e-9, atol=1e-11,
              t_eval=np.linspace(0.0, 8.0, 801))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rows", type=int, default=1_000_000)
    parser.add_argument("--rounds", type=int, default=7)
    args = parser.parse_args()

    data = log_rows(args.rows)
    compare_models(data)  # warm-up: imports and first-touch of the arrays
    ratios, compare_times, fit_times = [], [], []
    for _ in range(args.rounds):
        fit = timed(lambda: fit_joint(data).estimate)
        ladder = timed(lambda: compare_models(data))
        ratios.append(ladder / fit)
        compare_times.append(ladder)
        fit_times.append(fit)
    print(f"compare ({len(LADDER)} models) on {args.rows:,} rows / one plain fit of the same rows: "
          f"{spread(ratios)} (goal <= 3)")

    settings = Settings(noise=0.05, true_coulomb=0.3)
    fits = {name: run_experiment(Settings(**{**vars(settings), "model": name})) for name in LADDER}
    true_simulation()  # warm-up: scipy's import
    for name, result in fits.items():
        per_model, ratio = [], []
        for _ in range(args.rounds):
            baseline = timed(true_simulation)
            check = timed(lambda: simulation_check(result, settings.true_joint))
            per_model.append(check)
            ratio.append(check / baseline)
        print(f"simulation check, {name:<21} / one 8 s solve_ivp of the true joint: {spread(ratio)}; "
              f"seconds {spread(per_model)} (goal <= 0.5 s)")


if __name__ == "__main__":
    main()
