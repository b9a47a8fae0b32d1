"""One verdict in every face, a held-out check done as the fit is, and runs that disagree, on the real pendulum's
runs (../shared/real-logs, --zero down).

The held-out and run-to-run checks compute their own regressors with numpy and scipy
(benchmarks/real_logs_reference/pipeline.py: q smoothed and differenced, every column and the torque through a
zero-phase Butterworth at 3 Hz).
"""

from __future__ import annotations

import numpy as np
import pytest
from support.cli_support import fit_json, run
from support.real_logs import REAL_LOGS, needs_real_logs, reference_pipeline
from support.tui_support import make_app, synchronous

import jointid
from jointid.present.report import parameter_table
from jointid.studies.runs import fit_runs
from tui.widgets.readouts import ReadoutPanel

pytestmark = needs_real_logs

ENERGY, PD = REAL_LOGS / "pendulum_energy_shaping.csv", REAL_LOGS / "pendulum_pd.csv"
WIDENED = "error widened from 0.00331 to 0.0318 by the robust step's exclusions (--no-robust), the cutoff's choice"


@pytest.fixture(scope="module")
def energy():
    """The energy-shaping run fitted by the library, as `jointid fit --csv ... --zero down` fits it."""
    return jointid.fit_log(ENERGY, zero="down")


@synchronous
async def test_text_json_library_explorer_and_report_give_the_weakened_verdict_alike(energy, capsys):
    """Keeping the pushes in (--no-robust) and the cutoff move the energy-shaping run's I far beyond its 1.8 % noise
    error: every face reports the widened error and interval, says weak, and why; the JSON keeps the noise's own
    error and verdict under names that say so."""
    library = energy.verdicts["I"]
    status, text, _ = run(capsys, "fit", "--csv", ENERGY, "--zero", "down")
    line = next(line for line in text.splitlines() if line.startswith("I (kg m²)"))
    document = fit_json(capsys, "--csv", ENERGY, "--zero", "down")
    app = make_app(logs=energy)
    async with app.run_test(size=(120, 40)) as pilot:
        await pilot.pause()
        notes = app.screen.query_one(ReadoutPanel).precision.notes
        explorer = next(note.verdict for note in notes if note.key == "I")
    report = next(row for row in parameter_table(energy.result).rows if row[0].startswith("I "))[5]
    assert status == 0
    assert library == document["verdicts"]["I"] == explorer == "weak"
    assert f"± 0.031794  weak (17.2 %, {WIDENED})" in line and report.startswith("weak (") and WIDENED in report
    assert document["noise_verdicts"]["I"] == "well determined"
    assert document["std_error"]["I"] == pytest.approx(0.031794, abs=5e-7)
    assert document["noise_std_error"]["I"] == pytest.approx(0.00331, abs=5e-6)
    assert energy.conf_int(0.05)["I"] == tuple(document["interval95"]["I"])  # the widened interval, alike
    assert WIDENED in document["verdict_reasons"]["I"]
    assert "Less certain than their noise alone says: I (" in document["message"]


def test_the_heldout_log_is_predicted_as_the_training_log_was_fitted(energy, capsys):
    """Energy shaping's parameters predict pd: jointid's held-out RMSE (pd through the training log's pipeline)
    within 1.5x of the reference's (pd's columns and torque low-passed at 3 Hz alike); predicted raw it was
    4.90 N m, twice pd's torque RMS."""
    document = fit_json(capsys, "--csv", ENERGY, "--zero", "down", "--heldout", PD)
    theta = [document["estimate"][name] for name in ("I", "h", "B", "Fc", "tau0")]
    reference = reference_pipeline()
    _, measured, predicted = reference.predict_filtered(reference.load_log(str(PD)), theta, 3.0, "sign")
    expected = float(np.sqrt(np.mean((measured - predicted) ** 2)))
    assert expected / 1.5 <= document["heldout_rmse"] <= 1.5 * expected, (document["heldout_rmse"], expected)
    assert document["heldout_rmse"] < 0.5 * float(np.sqrt(np.mean(measured**2)))  # far better than predicting 0
    assert any("predicted as the training log was fitted" in note for note in document["notes"])


def test_runs_that_differ_beyond_their_errors_are_not_well_determined_pooled():
    """The reference's own fit of each run (3 Hz, robust, Coulomb and bias) puts ddp's I several percent from the
    other two; jointid's pooled fit of the three runs then calls neither I nor h well determined, saying the runs
    scatter beyond their errors."""
    reference = reference_pipeline()
    inertia = {run: reference.identify(reference.load_log(str(REAL_LOGS / f"pendulum_{run}.csv")),
                                       cutoff=3.0)["theta"][0] for run in ("pd", "ddp", "energy_shaping")}
    spread = max(inertia.values()) / min(inertia.values()) - 1
    assert spread > 0.05, inertia  # the runs' own structure: more than a well-determined 1 % error allows
    from jointid.logs.conventions import AngleConvention
    from jointid.logs.request import TRAINING, LoadRequest, load_joint_log
    from jointid.model.terms import model_named

    down = AngleConvention("down", False)
    logs = [load_joint_log(LoadRequest(str(REAL_LOGS / f"pendulum_{run}.csv"), TRAINING, angle=down))
            for run in ("pd", "ddp", "energy_shaping")]
    pooled = fit_runs(logs, model_named("coulomb+bias"))
    for name in ("I", "h"):
        noise = dict(zip(pooled.shared, pooled.judgement.noise_verdicts))
        assert noise[name] == "well determined"  # its pooled error alone is below 1 %
        assert pooled.verdicts[name] != "well determined"
        assert "the scatter of its runs" in pooled.judgement.reason_of(name)
        assert pooled.bse[name] > 4 * pooled.noise_bse[name]  # the reported error widened by that scatter
