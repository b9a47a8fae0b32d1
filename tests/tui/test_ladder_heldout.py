"""The explorer's ladder (l) scores a held-out log as `jointid compare` does: through the training log's pipeline."""

from __future__ import annotations

import json

import numpy as np
import pytest
from support.cli_support import run
from support.real_logs import REAL_LOGS, needs_real_logs, reference_pipeline
from support.tui_support import make_app, synchronous

import jointid
from tui.screens.ladder import LadderScreen

pytestmark = needs_real_logs

ENERGY, PD = REAL_LOGS / "pendulum_energy_shaping.csv", REAL_LOGS / "pendulum_pd.csv"


@synchronous
async def test_the_ladder_predicts_a_heldout_log_as_the_command_line_and_an_independent_pipeline_do(capsys):
    """Energy shaping's ladder predicts pd: each model's held-out RMSE is the command line's, and the default
    model's is within 1.5x of the numpy/scipy reference's (pd's columns and torque low-passed at 3 Hz alike);
    scored on pd's raw columns, as the view once did, it was several times pd's torque RMS."""
    logs = jointid.fit_log(ENERGY, PD, zero="down")
    app = make_app(logs=logs)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.pause()
        await pilot.press("l")
        await pilot.pause()
        assert isinstance(app.screen, LadderScreen)
        comparison = app.screen.comparison
    explorer = {row.model.name: row.heldout_rmse for row in comparison.rows}
    status, out, err = run(capsys, "compare", "--csv", ENERGY, "--heldout", PD, "--zero", "down", "--json")
    assert (status, err) == (0, "")
    command_line = {model["model"]: model["heldout_rmse"] for model in json.loads(out)["models"]}
    assert set(explorer) == set(command_line)
    for name, value in command_line.items():
        assert explorer[name] == pytest.approx(value, rel=1e-9), name
    reference = reference_pipeline()
    row = comparison.row("coulomb+bias")
    theta = dict(zip(row.model.names, row.solution.estimate))
    _, measured, predicted = reference.predict_filtered(reference.load_log(str(PD)),
                                                        [theta[name] for name in ("I", "h", "B", "Fc", "tau0")],
                                                        3.0, "sign")
    expected = float(np.sqrt(np.mean((measured - predicted) ** 2)))
    assert expected / 1.5 <= explorer["coulomb+bias"] <= 1.5 * expected, (explorer["coulomb+bias"], expected)
    assert explorer["coulomb+bias"] < 0.5 * float(np.sqrt(np.mean(measured**2)))  # far better than predicting 0
