"""How often the omitted-terms test calls a right model wrong, and how surely it finds a missing friction (not a
timing).

Right model: SEEDS logs of the lesson's plain joint written by `jointid simulate --noise 0.1 --rate 1000
--encoder-counts 4096` (8 s, 12-bit angles, so qd and qdd are estimated), fitted with `--model plain`: prints the
largest |t| of any candidate against its threshold and how many logs it says follow a term. Missing friction:
the tests' synthetic Coulomb joint (FC 0.2 N m) fitted with the plain model and with the default, and the real
pendulum's runs (../shared/real-logs) with both models.

    PYTHONPATH=. python benchmarks/omitted_terms_study.py [SEEDS]
"""

from __future__ import annotations

import contextlib
import io
import os
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))

from support.coulomb_joint import coulomb_joint_log  # noqa: E402  (the tests' own generator)

from jointid import fit_log  # noqa: E402
from jointid.cli import main as jointid  # noqa: E402

LOGS = ROOT.parent / "shared" / "real-logs"


def summary(logs) -> str:
    test = logs.omitted
    ts = ", ".join(f"{c.name} {c.t:+.1f}" for c in test.candidates)
    return f"t {ts} (threshold {test.threshold:.2f}); follows {list(test.followed)}, decides {list(test.decided)}"


def main(seeds: int) -> None:
    largest, found = 0.0, 0
    with tempfile.TemporaryDirectory() as folder:
        for seed in range(1, seeds + 1):
            path = os.path.join(folder, f"log{seed}.csv")
            with contextlib.redirect_stdout(io.StringIO()):
                jointid(["simulate", "--noise", "0.1", "--rate", "1000", "--encoder-counts", "4096",
                         "--seed", str(seed), "--out", path])
            test = fit_log(path, model="plain", sensitivity=False).omitted
            largest = max(largest, max(abs(c.t) / test.threshold for c in test.candidates))
            found += test.found
    print(f"right model, {seeds} quantised logs: {found} said to follow a term; largest |t| / threshold "
          f"{largest:.2f}")
    for seed in (1, 2, 3):
        for model in ("plain", "coulomb+bias"):
            print(f"Coulomb joint seed {seed}, {model}: {summary(fit_log(coulomb_joint_log(seed), model=model, sensitivity=False))}")
    if LOGS.is_dir():
        os.chdir(LOGS)
        for run in ("pd", "ddp", "energy_shaping"):
            for model in ("plain", "coulomb+bias"):
                logs = fit_log(f"pendulum_{run}.csv", zero="down", model=model, sensitivity=False)
                print(f"{run}, {model}: {summary(logs)}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 20)
