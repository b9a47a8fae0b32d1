"""`jointid compare` and `report --compare` with several runs: the ladder on the runs pooled, each run's own choice
beside it, never the first run alone."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from support.cli_support import run
from support.coulomb_joint import coulomb_joint_log

from jointid.studies.ladder import ALL_COLUMNS


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Two logs of the synthetic Coulomb joint (seeds 1 and 2), as CSV files."""
    folder = tmp_path_factory.mktemp("runs")
    paths = []
    for seed in (1, 2):
        log = coulomb_joint_log(seed)
        path = folder / f"run{seed}.csv"
        rows = ["t,q,tau", *(f"{t:.17g},{q:.17g},{tau:.17g}" for t, q, tau in zip(log["t"], log["q"], log["tau"]))]
        path.write_text("\n".join(rows) + "\n")
        paths.append(path)
    return paths


def compared(capsys, *paths) -> dict:
    """`jointid compare --csv PATH ... --json`'s document."""
    status, out, err = run(capsys, "compare", *(word for path in paths for word in ("--csv", path)), "--json")
    assert (status, err) == (0, ""), err
    return json.loads(out)


def test_several_runs_are_compared_pooled_with_each_runs_own_choice(capsys, runs):
    alone = [compared(capsys, path) for path in runs]
    pooled = compared(capsys, *runs)
    # Every run's samples count, not the first run's alone.
    assert pooled["samples"] == sum(document["samples"] for document in alone)
    assert pooled["run_preferences"] == [{"run": path.name, "preferred": document["preferred"]}
                                         for path, document in zip(runs, alone)]
    # A model with a bias gives each run its own: one more parameter per run after the first, in BIC and the rank.
    rows = {row["model"]: row for row in pooled["models"]}
    assert rows["coulomb+bias"]["rank"] == 5 + len(runs) - 1
    # BIC counts the independent samples of both runs: n (pinned by two rows of each document, see _independent)
    # is the two runs' own n together.
    assert _independent(pooled) == pytest.approx(sum(_independent(document) for document in alone), rel=1e-6)
    assert "Each run alone prefers: run1.csv" in pooled["message"]


def _independent(document: dict) -> float:
    """The independent samples n a comparison's BIC counts: BIC = n ln(RSS/N) + k ln n, so the plain and coulomb
    rows differ by n times their fit terms' gap (RSS/N = RMSE²) and one parameter's ln n, which pins n."""
    rows = {row["model"]: row for row in document["models"]}
    plain, coulomb = rows["plain"], rows["coulomb"]
    fit_gap = 2 * (math.log(plain["training_rmse"]) - math.log(coulomb["training_rmse"]))
    low, high = 1.0, 1e7
    for _ in range(200):
        middle = math.sqrt(low * high)
        value = middle * fit_gap - math.log(middle) - (plain["bic"] - coulomb["bic"])
        low, high = (middle, high) if value < 0 else (low, middle)
    return low


def test_report_compare_with_several_runs_shows_the_pooled_ladder(capsys, runs, tmp_path):
    out = tmp_path / "runs.md"
    status, _, err = run(capsys, "report", *(word for path in runs for word in ("--csv", path)), "--compare",
                         "--out", out)
    assert (status, err) == (0, ""), err
    text = out.read_text()
    assert "2 runs pooled (run1.csv, run2.csv)" in text and "Each run alone prefers: run1.csv" in text


def test_the_pooled_ladder_stacks_the_runs_with_their_own_bias():
    """compare_runs on two blocks equals an independent numpy least squares of the stacked rows with one bias column
    per run (the coulomb+bias model)."""
    from jointid.studies.ladder import compare_runs

    rng = np.random.default_rng(4)
    blocks, stacked_rows, targets = [], [], []
    kinds = [term.kind for term in ALL_COLUMNS.terms]
    for k, offset in enumerate((0.3, -0.2)):
        X = rng.normal(size=(200, ALL_COLUMNS.size))
        X[:, kinds.index("tau0")] = 1.0
        theta = np.array([0.8, 0.4, 0.15, 0.2, 0.0, 0.05])
        tau = X @ theta + offset + 0.01 * rng.normal(size=200)
        blocks.append((X, tau, None))
        own = np.zeros((200, 2))
        own[:, k] = 1.0
        columns = [kinds.index(kind) for kind in ("I", "h_c", "B", "Fc")]
        stacked_rows.append(np.column_stack([X[:, columns], own]))
        targets.append(tau)
    comparison = compare_runs(blocks)
    expected, *_ = np.linalg.lstsq(np.concatenate(stacked_rows), np.concatenate(targets), rcond=None)
    row = comparison.row("coulomb+bias")
    # The model's own columns (I, h, B, Fc, then the first run's bias), and the second run's bias after them.
    assert row.solution.estimate == pytest.approx(expected, rel=1e-9)
    assert comparison.samples == 400 and row.offsets == 1
