"""Real logs you can trust: three measured runs of one real pendulum (../shared/real-logs), fitted with the
defaults and only --zero down, and a synthetic Coulomb joint with pushes.

The checks compute their own regressors with numpy and scipy: the torque and
the columns [qdd, g sin(position), qd, sign(qd), 1] low-passed at 3 Hz by a
zero-phase Butterworth filter (scipy.signal), outside the stretches jointid
reports as left out.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from support.coulomb_joint import coulomb_joint_log
from support.real_logs import REAL_LOGS, needs_real_logs, reference_pipeline

from jointid.cli import main

G = 9.81
LOGS = REAL_LOGS
RUNS = ("pd", "ddp", "energy_shaping")
PUBLISHED = {"I": 0.06259, "h": 0.1022, "B": 0.04707, "Fc": 0.1839, "tau0": -0.07586}
"""The repository's own identification of the pd run (its friction is Fc atan(100 qd))."""

pytestmark = needs_real_logs


def fitted(capsys, run: str, *options) -> dict:
    """`jointid fit --csv RUN --zero down --json`, parsed."""
    capsys.readouterr()
    assert main(["fit", "--csv", str(LOGS / f"pendulum_{run}.csv"), "--zero", "down", "--json", *options]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.fixture(scope="module")
def documents():
    """The three runs' JSON documents with the defaults (the module's capsys is not available: main's output is
    read through a pipe of its own)."""
    import contextlib
    import io

    found = {}
    for run in RUNS:
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            assert main(["fit", "--csv", str(LOGS / f"pendulum_{run}.csv"), "--zero", "down", "--json"]) == 0
        found[run] = json.loads(out.getvalue())
    return found


def test_each_run_is_within_ten_percent_of_the_three_runs_mean(documents):
    for name in ("I", "h"):
        values = np.array([documents[run]["estimate"][name] for run in RUNS])
        assert np.all(np.abs(values / values.mean() - 1) <= 0.10), (name, values)
    inertia = np.array([documents[run]["estimate"]["I"] for run in RUNS])
    assert 0.16 < inertia.mean() < 0.20  # the careful analysis: about 0.18 kg m^2
    for run in RUNS:
        assert documents[run]["model"] == "coulomb+bias"
        assert documents[run]["conventions"]["training"]["zero"] == "down"


def test_the_energy_shaping_runs_pushes_are_left_out_and_the_pd_run_keeps_its_motion(documents):
    def inside(document):
        return [(a, b) for a, b in document["excluded"] if a > 0.5 and b < 19.5]

    pushes = inside(documents["energy_shaping"])
    assert len(pushes) >= 3, documents["energy_shaping"]["excluded"]
    data = np.loadtxt(LOGS / "pendulum_energy_shaping.csv", delimiter=",", skiprows=1)
    t, position = data[:, 0], data[:, 1]
    for start, end in pushes[:3]:  # each push starts with the pendulum balanced upright, which then falls over
        at = np.searchsorted(t, start)
        upright = np.angle(np.exp(1j * (position[at] - np.pi)))
        assert abs(upright) < 0.1, (start, upright)
        later = np.searchsorted(t, end + 1.5)
        assert abs(position[later] - position[at]) > 2.0, (start, end)
    assert documents["pd"]["excluded"] == [] or all(b - a < 0.2 for a, b in documents["pd"]["excluded"])


def prediction_rmse(reference, run: str, excluded, theta, friction: str = "sign") -> float:
    """RMS of the torque less the prediction, both low-passed at 3 Hz by the reference (its own regressors:
    q smoothed and differenced, every column and the torque through a zero-phase Butterworth), outside the
    stretches jointid left out."""
    t, measured, predicted = reference.predict_filtered(reference.load_log(str(LOGS / f"pendulum_{run}.csv")),
                                                        theta, 3.0, friction)
    keep = np.ones(len(t), dtype=bool)
    for start, end in excluded:
        keep &= ~((t >= start) & (t <= end))
    return float(np.sqrt(np.mean((measured - predicted)[keep] ** 2)))


def test_a_fit_on_ddp_predicts_the_other_runs_better_than_the_published_parameters(documents):
    reference = reference_pipeline()
    ours = np.array([documents["ddp"]["estimate"][k] for k in ("I", "h", "B", "Fc", "tau0")])
    theirs = np.array([PUBLISHED[k] for k in ("I", "h", "B", "Fc", "tau0")])
    ratios = {run: prediction_rmse(reference, run, documents[run]["excluded"], ours)
              / prediction_rmse(reference, run, documents[run]["excluded"], theirs, "atan100")
              for run in ("pd", "energy_shaping")}
    # The issue asks for 0.5 on both: 0.49 on energy shaping (0.53 before the stretches inside a log were
    # widened by a quarter of the filter's support) and 0.82 on pd, whose floor is below.
    assert ratios["energy_shaping"] <= 0.5, ratios
    assert ratios["pd"] < 0.9, ratios
    # Half as badly is out of reach on pd: even pd's own fit at 3 Hz leaves more than half the published
    # parameters' error there (the floor the closing note reports).
    own = reference.identify(reference.load_log(str(LOGS / "pendulum_pd.csv")), cutoff=3.0)["theta"]
    floor = prediction_rmse(reference, "pd", documents["pd"]["excluded"], own)
    assert floor > 0.5 * prediction_rmse(reference, "pd", documents["pd"]["excluded"], theirs, "atan100")


def test_the_verdicts_on_real_logs_are_not_all_well_determined(documents):
    """The defaults' honesty: the short pendulum-like pd run cannot tell friction from its inertia scale."""
    assert documents["pd"]["verdicts"]["Fc"] != "well determined"
    assert any(documents["energy_shaping"]["moved_by_derivative_settings"]) or \
        documents["energy_shaping"]["verdicts"]["tau0"] != "well determined"


PUSHES = ((4.0, 0.5, 1.0), (9.0, 1.2, -1.0), (14.5, 2.0, 1.0))
TRUTH = {"I": 0.8, "h": 0.4, "B": 0.15, "Fc": 0.2}


@pytest.mark.parametrize("seed", [1, 2])
def test_a_coulomb_joint_with_three_pushes_is_recovered_and_the_pushes_left_out(seed):
    from jointid import fit_log

    logs = fit_log(coulomb_joint_log(seed, PUSHES), sensitivity=False)
    for name, true in TRUTH.items():
        value, error = logs.params[name], logs.bse[name]
        assert abs(value - true) <= max(0.03 * true, 3 * error), (name, value, error)
    stretches = logs.exclusions.excluded
    for start, length, _ in PUSHES:  # every push covered
        assert any(a <= start + 0.1 * length and b >= start + 0.9 * length for a, b in stretches), (start, stretches)
    t = logs.exclusions.since
    pushed = np.zeros(len(t), dtype=bool)
    for start, length, _ in PUSHES:
        pushed |= (t >= start) & (t <= start + length)
    beyond = float(np.mean(logs.exclusions.pushes & ~pushed))
    assert beyond <= 0.10, beyond


@pytest.mark.parametrize("seed", [1, 2])
def test_a_clean_coulomb_joint_loses_at_most_three_percent(seed):
    from jointid import fit_log

    logs = fit_log(coulomb_joint_log(seed), sensitivity=False)
    assert logs.exclusions.excluded_share <= 0.03
    for name, true in TRUTH.items():
        assert abs(logs.params[name] - true) <= max(0.03 * true, 3 * logs.bse[name]), name


def test_the_three_runs_pooled_land_within_three_percent_of_their_mean(documents, capsys):
    argv = ["fit", "--zero", "down", "--json"]
    for run in RUNS:
        argv += ["--csv", str(LOGS / f"pendulum_{run}.csv")]
    capsys.readouterr()
    assert main(argv) == 0
    pooled = json.loads(capsys.readouterr().out)
    assert [run["name"] for run in pooled["runs"]] == [f"pendulum_{run}.csv" for run in RUNS]
    for name in ("I", "h"):
        mean = np.mean([documents[run]["estimate"][name] for run in RUNS])
        assert abs(pooled["pooled"]["estimate"][name] / mean - 1) <= 0.03, name
        # each run as fitted alone is the single fit of that file
        assert [run["estimate"][name] for run in pooled["runs"]] == [documents[r]["estimate"][name] for r in RUNS]
    assert set(pooled["pooled"]["torque_bias"]) == {f"pendulum_{run}.csv" for run in RUNS}
    assert all(run["predicted_by_others_rmse"] > 0 for run in pooled["runs"])
    capsys.readouterr()
    assert main(argv[:-1 - 6] + argv[-6:]) == 0  # the same without --json
    text = capsys.readouterr().out
    assert "3 runs of one joint" in text and "Scatter between the runs" in text


def test_several_runs_take_no_heldout_log(capsys):
    status = main(["fit", "--zero", "down", "--csv", str(LOGS / "pendulum_pd.csv"), "--csv",
                   str(LOGS / "pendulum_ddp.csv"), "--heldout", str(LOGS / "pendulum_pd.csv")])
    out, err = capsys.readouterr()
    assert status == 2 and out == "" and len(err.splitlines()) == 1 and "each run is predicted by the others" in err


def test_an_exclude_window_outside_the_log_is_one_line_and_exit_2(capsys):
    status = main(["fit", "--zero", "down", "--csv", str(LOGS / "pendulum_pd.csv"), "--exclude", "10:12"])
    out, err = capsys.readouterr()
    assert (status, out) == (2, "") and len(err.splitlines()) == 1
    assert "--exclude 10:12 holds no sample; the log spans 0 to 3.89" in err


def test_an_exclude_window_by_hand_is_left_out_and_reported(documents, capsys):
    document = fitted(capsys, "ddp", "--exclude", "2:3", "--no-robust")
    assert document["excluded"][0][0] == pytest.approx(2.0, abs=0.02)
    assert document["excluded"][0][1] == pytest.approx(3.0, abs=0.02)
    assert document["exclusions"]["robust"] is False and document["exclusions"]["by_hand"] == [[2.0, 3.0]]
    assert document["estimate"]["I"] != documents["ddp"]["estimate"]["I"]


def test_runs_that_disagree_beyond_their_errors_are_said_not_refused(capsys):
    argv = ["fit", "--zero", "down", *sum((["--csv", str(LOGS / f"pendulum_{run}.csv")] for run in RUNS), [])]
    capsys.readouterr()
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert "Disagrees with the pooled fit beyond their combined noise errors: pendulum_ddp.csv" in text


def test_the_training_chart_shades_each_push_and_shows_its_torque_off_the_fitted_line():
    """The chart keeps every filtered sample: the ones left out faint, each push shaded, and there the measured
    torque sits about the push's 1 N m off the joint's line, while the kept samples follow it."""
    from jointid import fit_log
    from jointid.present.charts import log_training_chart

    logs = fit_log(coulomb_joint_log(1, PUSHES), sensitivity=False)
    chart = log_training_chart(logs)
    assert len(chart.t) == len(logs.exclusions.since) > logs.result.training.count
    assert np.array_equal(chart.left_out, ~logs.exclusions.kept)
    for start, length, size in PUSHES:
        assert any(a <= start + 0.1 * length and b >= start + 0.9 * length for a, b in chart.shaded), start
    departure = chart.dots - chart.line
    for start, length, size in PUSHES[1:]:  # the 0.5 s bump is partly above the cutoff, the longer two are not
        middle = np.abs(chart.t - (start + length / 2)) <= 0.1
        assert np.allclose(departure[middle], -size, atol=0.25), (start, departure[middle])
    kept = ~chart.left_out
    assert np.sqrt(np.mean(departure[kept] ** 2)) == pytest.approx(logs.result.training_rmse, rel=1e-9)
    assert np.sqrt(np.mean(departure[kept] ** 2)) < 0.1


def test_the_plain_fit_of_ddp_is_told_its_residuals_follow_the_friction_it_lacks(capsys):
    """The gear's Coulomb friction (about 0.15-0.20 N m, ../shared/real-logs/README.md) is in ddp's torque: the
    reference's own fit finds it, and jointid's plain fit is told its residuals follow sign(qd)."""
    document = fitted(capsys, "ddp", "--model", "plain")
    assert document["omitted_terms"]["found"] and document["omitted_terms"]["followed"] == ["Fc"]
    assert document["omitted_terms"]["candidates"]["Fc"]["t"] > 2 * document["omitted_terms"]["threshold"]
    reference = reference_pipeline()
    own = reference.identify(reference.load_log(str(LOGS / "pendulum_ddp.csv")), cutoff=3.0)["theta"]
    assert 0.1 < own[3] < 0.25  # [I, h, B, Fc, tau0]
