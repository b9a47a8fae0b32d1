"""How far should a push's stretch be widened by the filter's support? What widening costs and buys (not a
timing).

The robust step ends a stretch where its residuals fall below 2 robust scales,
then widens each stretch inside the log by WIDENING x the filter's support
(jointid.estimation.exclusion). This sets WIDENING to 0, 0.25 (the default),
0.5 and 1 and prints, on the tests' synthetic Coulomb joint (three 1 N m pushes; SEEDS
seeds): the share of the log left out beyond the pushes (issue 23's goal: at
most 10 %), the share a clean log loses (at most 3 %), whether I, h, B, Fc stay
within 3 % or 3 standard errors; and on ../shared/real-logs: the ddp fit's
prediction of the energy-shaping and pd runs against the published parameters'
(scored by the reference pipeline outside the stretches left out; goal 0.5).

    PYTHONPATH=. python benchmarks/push_widening_study.py [SEEDS]
"""

from __future__ import annotations

import importlib.util
import os
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))

from support.coulomb_joint import coulomb_joint_log  # noqa: E402  (the tests' own generator)

import jointid.estimation.exclusion as exclusion  # noqa: E402
from jointid import fit_log  # noqa: E402

DEFAULT = exclusion.WIDENING
PUSHES = ((4.0, 0.5, 1.0), (9.0, 1.2, -1.0), (14.5, 2.0, 1.0))
TRUTH = {"I": 0.8, "h": 0.4, "B": 0.15, "Fc": 0.2}
PUBLISHED = {"I": 0.06259, "h": 0.1022, "B": 0.04707, "Fc": 0.1839, "tau0": -0.07586}
LOGS = ROOT.parent / "shared" / "real-logs"
FACTORS = (0.0, 0.25, 0.5, 1.0)
"""Widenings tried, in filter supports."""


def reference():
    spec = importlib.util.spec_from_file_location("reference", ROOT / "benchmarks" / "real_logs_reference" /
                                                  "pipeline.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def scored(pipeline, run, excluded, theta, friction="sign"):
    t, measured, predicted = pipeline.predict_filtered(pipeline.load_log(str(LOGS / f"pendulum_{run}.csv")),
                                                       theta, 3.0, friction)
    keep = np.ones(len(t), dtype=bool)
    for start, end in excluded:
        keep &= ~((t >= start) & (t <= end))
    return float(np.sqrt(np.mean((measured - predicted)[keep] ** 2)))


def main(seeds: int) -> None:
    pipeline = reference() if LOGS.is_dir() else None
    for factor in FACTORS:
        exclusion.WIDENING = factor
        beyond, clean, within = [], [], 0
        for seed in range(1, seeds + 1):
            logs = fit_log(coulomb_joint_log(seed, PUSHES), sensitivity=False)
            t = logs.exclusions.since
            pushed = np.zeros(len(t), dtype=bool)
            for start, length, _ in PUSHES:
                pushed |= (t >= start) & (t <= start + length)
            beyond.append(float(np.mean(logs.exclusions.pushes & ~pushed)))
            within += all(abs(logs.params[k] - v) <= max(0.03 * v, 3 * logs.bse[k]) for k, v in TRUTH.items())
            clean.append(fit_log(coulomb_joint_log(seed), sensitivity=False).exclusions.excluded_share)
        line = (f"widened by {factor:g} x support: beyond the pushes {min(beyond):.1%}-{max(beyond):.1%}, "
                f"clean logs {min(clean):.1%}-{max(clean):.1%}, parameters within {within}/{seeds}")
        if pipeline is not None:
            here = os.getcwd()
            os.chdir(LOGS)
            try:
                runs = {run: fit_log(f"pendulum_{run}.csv", zero="down", sensitivity=False)
                        for run in ("pd", "ddp", "energy_shaping")}
            finally:
                os.chdir(here)
            ours = np.array([runs["ddp"].params[k] for k in PUBLISHED])
            theirs = np.array(list(PUBLISHED.values()))
            ratios = {run: scored(pipeline, run, runs[run].exclusions.excluded, ours)
                      / scored(pipeline, run, runs[run].exclusions.excluded, theirs, "atan100")
                      for run in ("energy_shaping", "pd")}
            line += f"; ddp predicts energy shaping {ratios['energy_shaping']:.3f}, pd {ratios['pd']:.3f}"
        print(line)
    exclusion.WIDENING = DEFAULT


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 3)
