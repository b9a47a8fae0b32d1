"""The command line: output, JSON schema, and one-line errors with exit status 2."""

import json
import subprocess
import sys

import pytest

from jointid.cli import main
from jointid.present.readouts import readouts
from jointid.present.status import status_message
from jointid.studies.experiment import run_experiment
from jointid.synthetic.settings import Settings


def run_cli(*args):
    """Run `python -m jointid ARGS` in a fresh process: (exit status, stdout, stderr)."""
    done = subprocess.run([sys.executable, "-m", "jointid", *args], capture_output=True, text=True)
    return done.returncode, done.stdout, done.stderr


def test_fit_text_prints_every_readout_and_the_status_sentence(capsys):
    assert main(["fit", "--motion", "slow", "--noise", "0.2"]) == 0
    out = capsys.readouterr().out
    result = run_experiment(Settings(motion="slow", noise=0.2))
    for readout in readouts(result):
        assert f"{readout.label}" in out and readout.text in out
    assert "Fitted inertia (kg m²)         -1.607788  fails I > 0" in out
    assert out.splitlines()[0] == "Slow motion, noise 0.20 N m, 24 samples, seed 7"
    assert status_message(result) in out


def test_fit_json_has_the_documented_keys_at_full_precision(capsys):
    assert main(["fit", "--motion", "rich", "--noise", "0.2", "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    result = run_experiment(Settings(motion="rich", noise=0.2))
    assert document["settings"] == {"motion": "rich", "noise": 0.2, "samples": 24, "seed": 7, "model": "plain",
                                    "true_coulomb": 0.0, "true_bias": 0.0, "true_angle_offset": 0.0,
                                    "constrained": False}
    assert document["samples"] == 24 and document["rank"] == 3
    assert document["estimate"] == dict(zip("IhB", result.estimate.tolist()))
    assert document["training_rmse"] == result.training_rmse
    assert document["heldout_rmse"] == result.heldout_rmse
    assert document["accel_rms"] == result.accel_rms and document["speed_rms"] == result.speed_rms
    assert document["sign_failures"] == [] and document["message"] == status_message(result)


def test_fit_json_for_holds_has_nulls(capsys):
    assert main(["fit", "--motion", "holds", "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert document["rank"] == 1
    assert document["estimate"] is None
    assert document["training_rmse"] is None and document["heldout_rmse"] is None


def test_defaults_are_rich_no_noise_24_samples_seed_7(capsys):
    main(["fit", "--json"])
    assert json.loads(capsys.readouterr().out)["settings"] == vars(Settings()).copy()


def test_python_dash_m_matches_the_console_entry_point(capsys):
    status, out, err = run_cli("fit", "--motion", "slow", "--noise", "0.2")
    main(["fit", "--motion", "slow", "--noise", "0.2"])
    assert status == 0 and err == ""
    assert out == capsys.readouterr().out


def test_torque_reproduces_exercise_two(capsys):
    assert main(["torque", "--q", "60", "--deg", "--qd", "-2", "--qdd", "3"]) == 0
    out = capsys.readouterr().out
    rows = {line[:32].strip(): line[32:].split() for line in out.splitlines()[2:]}
    assert rows == {
        "Inertia            I*qdd": ["2.400000", "N", "m"],
        "Gravity comp.      h*g*cos(q)": ["1.962000", "N", "m"],
        "Damping comp.      B*qd": ["-0.300000", "N", "m"],
        "Actuator torque": ["4.062000", "N", "m"],
        "Damper dissipates  B*qd²": ["0.600000", "W"],
    }


def test_torque_json_with_custom_parameters(capsys):
    assert main(["torque", "--q", "0", "--qd", "1", "--qdd", "2", "--I", "2", "--h", "0", "--B", "0.5", "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert document["total"] == pytest.approx(2 * 2 + 0.5 * 1)
    assert document["damper_power"] == pytest.approx(0.5)


ERROR_CASES = [
    (["fit", "--noise", "abc"], "--noise"),
    (["fit", "--noise", "-0.01"], "--noise"),
    (["fit", "--noise", "100.5"], "--noise"),
    (["fit", "--noise", "nan"], "--noise"),
    (["fit", "--noise", "inf"], "--noise"),
    (["fit", "--samples", "1"], "--samples"),
    (["fit", "--samples", "10000001"], "--samples"),
    (["fit", "--samples", "2.5"], "--samples"),
    (["fit", "--seed", "-1"], "--seed"),
    (["fit", "--seed", "4294967296"], "--seed"),
    (["fit", "--seed", "x"], "--seed"),
    (["fit", "--motion", "fast"], "--motion"),
    (["fit", "--noise"], "--noise"),
    (["fit", "--bogus"], "--bogus"),
    (["fly"], "fly"),
    (["torque", "--q", "1", "--qd", "0"], "--qdd"),
    (["torque", "--q", "nan", "--qd", "0", "--qdd", "0"], "--q"),
    (["torque", "--q", "1", "--qd", "0", "--qdd", "0", "--I", "big"], "--I"),
    (["--samples", "0"], "--samples"),
]


@pytest.mark.parametrize(("args", "flag"), ERROR_CASES, ids=[" ".join(a) for a, _ in ERROR_CASES])
def test_bad_input_gives_one_line_naming_the_flag_and_exit_two(args, flag):
    status, out, err = run_cli(*args)
    assert status == 2
    assert out == ""
    assert len(err.strip().splitlines()) == 1, err
    assert flag in err
    assert "Traceback" not in err


def test_range_errors_state_the_allowed_range():
    _, _, err = run_cli("fit", "--noise", "-1")
    assert "from 0 to 100" in err and "'-1'" in err
    _, _, err = run_cli("fit", "--seed", "4294967296")
    assert "from 0 to 4294967295" in err


def test_help_documents_every_flag_with_units():
    status, out, _ = run_cli("fit", "--help")
    assert status == 0
    for flag in ("--motion", "--noise", "--samples", "--seed", "--json"):
        assert flag in out
    assert "N m" in out
    status, out, _ = run_cli("torque", "--help")
    assert status == 0 and "rad/s²" in out and "kg m²" in out
