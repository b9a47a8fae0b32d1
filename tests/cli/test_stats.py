"""Command line for issue 4: fit's uncertainty keys and lines, sweep, matrix, and their errors."""

import json
import subprocess
import sys

import numpy as np
import pytest

from jointid.cli import main
from jointid.estimation.fit import fit_joint
from jointid.present.documents import result_to_dict
from jointid.studies.experiment import run_experiment
from jointid.studies.sweep import run_sweep
from jointid.synthetic.settings import Settings

PER_PARAMETER_KEYS = ("std_error", "noise_bound_std_error", "relative_std_pct", "interval95", "verdicts")
LEGACY_KEYS = ("samples", "rank", "estimate", "training_rmse", "heldout_rmse", "accel_rms", "speed_rms",
               "sign_failures", "message")


def run_cli(*args):
    """Run `python -m jointid ARGS` in a fresh process: (exit status, stdout, stderr)."""
    done = subprocess.run([sys.executable, "-m", "jointid", *args], capture_output=True, text=True)
    return done.returncode, done.stdout, done.stderr


def fit_json(capsys, *args):
    assert main(["fit", "--json", *args]) == 0
    return json.loads(capsys.readouterr().out)


def test_fit_json_gains_uncertainty_keys_and_keeps_the_old_ones(capsys):
    document = fit_json(capsys, "--motion", "slow", "--noise", "0.2")
    assert all(key in document for key in LEGACY_KEYS)
    for key in PER_PARAMETER_KEYS:
        assert list(document[key]) == ["I", "h", "B"]
    expected = document["noise_bound_std_error"]
    assert (round(expected["I"], 6), round(expected["B"], 6)) == (5.425077, 1.013808)
    assert document["verdicts"] == {"I": "not determined", "h": "well determined", "B": "not determined"}
    low, high = document["interval95"]["I"]
    assert low < document["estimate"]["I"] < high
    assert round(document["condition_number"], 2) == 3.78
    assert document["identifiable"] == document["estimate"]
    assert any("inertia and damping are not determined" in w for w in document["warnings"])


def test_fit_json_for_holds_has_the_subset_and_null_errors(capsys):
    document = fit_json(capsys, "--motion", "holds")
    assert list(document["identifiable"]) == ["h"]
    assert document["identifiable"]["h"] == pytest.approx(0.4, abs=1e-12)
    for key in PER_PARAMETER_KEYS:
        assert document[key] == {"I": None, "h": None, "B": None}
    assert document["condition_number"] is None
    assert document["warnings"][0] == "Rank 1 of 3: no unique least-squares fit."


def test_expected_std_error_is_null_without_a_known_noise_bound():
    training = run_experiment(Settings(noise=0.2)).training
    document = result_to_dict(fit_joint(training))  # measured data: no bound
    assert document["noise_bound_std_error"] is None
    assert document["verdict_basis"] == "empirical"
    assert None not in document["std_error"].values()


def test_fit_text_shows_value_plus_minus_error_with_verdict_and_condition_number(capsys):
    assert main(["fit", "--motion", "slow", "--noise", "0.2"]) == 0
    out = capsys.readouterr().out
    assert "-1.607788 ± 5.425077  not determined" in out
    assert "0.109966 ± 1.013808  not determined" in out
    assert "Condition number (column-scaled regressor) 3.78: a modest value does not mean" in out


def test_sweep_json_matches_the_core(capsys):
    assert main(["sweep", "--motion", "slow", "--noise", "0.2", "--seeds", "500", "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    sweep = run_sweep(Settings(motion="slow", noise=0.2), 500)
    assert document["seeds"] == {"first": 7, "last": 506, "count": 500}
    assert document["statistics"]["I"]["mean"] == float(np.mean(sweep.estimates[0]))
    assert document["empirical_std"]["B"] == float(np.std(sweep.estimates[2], ddof=1))
    assert document["sign_failure_fraction"] == sweep.sign_failure_fraction


def test_sweep_default_is_1000_seeds_and_text_names_the_sign_failures(capsys):
    assert main(["sweep", "--motion", "slow", "--noise", "0.2"]) == 0
    out = capsys.readouterr().out
    assert "1000 seeds 7..1006" in out and "inertia fails its sign check" in out
    assert "std (empirical)" in out and "std (expected)" in out


def test_sweep_for_holds_says_there_are_no_estimates(capsys):
    assert main(["sweep", "--motion", "holds", "--seeds", "10"]) == 0
    assert "no estimates" in capsys.readouterr().out


def test_matrix_json_marks_training_entries(capsys):
    assert main(["matrix", "--noise", "0.2", "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    rows = {row["training_motion"]: row for row in document["rows"]}
    assert round(rows["slow"]["cells"]["test"]["rmse"], 6) == 2.261865
    assert rows["rich"]["cells"]["rich"]["training_data"] is True
    assert rows["rich"]["cells"]["test"]["training_data"] is False
    assert rows["holds"]["estimate"] is None
    assert all(cell["rmse"] is None for cell in rows["holds"]["cells"].values())


def test_matrix_text_marks_training_data_and_never_calls_it_heldout(capsys):
    assert main(["matrix", "--noise", "0.2"]) == 0
    out = capsys.readouterr().out
    assert "0.017032 *" in out and "2.261865" in out and "0.013273  " in out
    assert "* training data" in out and "held-out" not in out.replace("not a held-out test", "")


@pytest.mark.parametrize(
    "args",
    [
        ["sweep", "--seeds", "0"],
        ["sweep", "--seeds", "1000001"],
        ["sweep", "--seeds", "-5"],
        ["sweep", "--seeds", "1.5"],
        ["sweep", "--seeds", "many"],
        ["sweep", "--seed", "4294967296"],
        ["matrix", "--samples", "1"],
        ["matrix", "--noise", "nan"],
    ],
)
def test_bad_values_give_one_line_and_exit_status_2(args):
    status, out, err = run_cli(*args)
    assert status == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert err.startswith("jointid ")
