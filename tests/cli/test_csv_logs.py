"""Command line for logs: simulate, fit --csv/--heldout round trips, option conflicts and a corpus of bad files."""

import json
import math
import subprocess
import sys

import numpy as np
import pytest
from support.log_files import CORPUS, HEADER, good_rows, rows_of, truth_states

from jointid.cli import main
from jointid.model.terms import TRUE_PARAMETERS, G
from jointid.synthetic.noise import torque_noise


def run(capsys, *argv):
    """(status, stdout, stderr) of one in-process command."""
    status = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def fit_json(capsys, *argv):
    status, out, err = run(capsys, "fit", *argv, "--json")
    assert (status, err) == (0, "")
    return json.loads(out)


def simulate(capsys, path, *argv):
    status, out, err = run(capsys, "simulate", "--out", path, *argv)
    assert (status, err) == (0, ""), err
    assert out.startswith(f"Wrote {path}")
    return path


def lstsq_fit(q, qd, qdd, tau):
    X = np.column_stack([qdd, G * np.cos(q), qd])
    return np.linalg.lstsq(X, tau, rcond=None)[0]


def test_noiseless_full_log_recovers_the_truth(capsys, tmp_path):
    path = simulate(capsys, tmp_path / "train.csv", "--samples", "500")
    document = fit_json(capsys, "--csv", path, "--model", "plain")
    estimate = np.array([document["estimate"][k] for k in "IhB"])
    np.testing.assert_allclose(estimate, TRUE_PARAMETERS, rtol=1e-6)  # the default low-pass keeps the model exact
    assert document["settings"] is None and document["derivatives"] is None
    assert document["source"] == {"training": str(path), "heldout": None}
    decimation = document["low_pass"]["decimation"]
    assert document["low_pass"]["cutoff_hz"] is not None and decimation > 1
    kept = range(0, 500, decimation)  # every D-th: the ends are extended, not trimmed; nothing stands out
    assert document["samples"] == len(kept) and document["rank"] == 3 and document["excluded"] == []
    assert document["heldout_rmse"] is None
    assert document["noise_bound_std_error"] is None
    assert "No held-out data" in document["message"]


def test_noisy_log_gives_the_least_squares_fit_of_its_own_numbers(capsys, tmp_path):
    path = simulate(capsys, tmp_path / "train.csv", "--noise", "0.2", "--seed", "11", "--samples", "300")
    t, q, qd, qdd, tau = truth_states("rich", 300)
    tau = tau + torque_noise(0.2, 300, 11)
    expected = lstsq_fit(q, qd, qdd, tau)
    document = fit_json(capsys, "--csv", path, "--cutoff", "0", "--model", "plain", "--no-robust")
    np.testing.assert_allclose([document["estimate"][k] for k in "IhB"], expected, rtol=1e-9)
    residual = np.column_stack([qdd, G * np.cos(q), qd]) @ expected - tau
    assert document["training_rmse"] == pytest.approx(math.sqrt(np.mean(residual**2)), rel=1e-9)
    assert document["std_error"]["I"] is not None


def test_heldout_log_is_predicted_and_scored_against_its_measured_torques(capsys, tmp_path):
    train = simulate(capsys, tmp_path / "train.csv", "--noise", "0.2", "--samples", "200")
    test = simulate(capsys, tmp_path / "test.csv", "--motion", "test", "--noise", "0.1", "--seed", "3",
                    "--samples", "40")
    # Unfiltered (--cutoff 0), the held-out log goes through the training log's pipeline unchanged: nothing to
    # low-pass, no standstill without friction, no outside torque in uniform noise.
    document = fit_json(capsys, "--csv", train, "--heldout", test, "--model", "plain", "--cutoff", "0")
    theta = np.array([document["estimate"][k] for k in "IhB"])
    _, q, qd, qdd, tau = truth_states("test", 40)
    measured = tau + torque_noise(0.1, 40, 3)
    predicted = np.column_stack([qdd, G * np.cos(q), qd]) @ theta
    assert document["heldout_rmse"] == pytest.approx(math.sqrt(np.mean((predicted - measured) ** 2)), rel=1e-9)
    assert document["source"] == {"training": str(train), "heldout": str(test)}
    assert "against measured torques, so it includes their measurement noise" in document["message"]


def test_text_output_names_the_logs_and_the_notes(capsys, tmp_path):
    path = tmp_path / "train.csv"
    _, q, qd, qdd, tau = truth_states("rich", 50)
    rows = ["t,q,qd,qdd,tau,motor_temp"] + rows_of(np.arange(50), q, qd, qdd, tau, np.full(50, 41.5))
    path.write_text("\n".join(rows) + "\n")
    status, out, err = run(capsys, "fit", "--csv", path, "--model", "plain")
    assert (status, err) == (0, "")
    assert out.splitlines()[0] == f"Training log {path}: 50 rows (radians), 50 samples, 50 fitted after the low-pass"
    assert "Fitted inertia (kg m²)          0.800000" in out
    assert f"Note: {path}: ignored columns 'motor_temp'." in out


@pytest.mark.parametrize("counts, tolerance", [(4096, 0.02), (65536, 0.005)])
def test_angle_only_quantised_log_lands_within_tolerance(capsys, tmp_path, counts, tolerance):
    """1 kHz encoder angles, derivatives by the default filter: 2 % at 12 bits, 0.5 % at 16 bits."""
    path = simulate(capsys, tmp_path / "enc.csv", "--rate", "1000", "--encoder-counts", counts)
    header = path.read_text().splitlines()[1]
    assert header == "t,q,tau"
    document = fit_json(capsys, "--csv", path, "--model", "plain")
    estimate = np.array([document["estimate"][k] for k in "IhB"])
    assert np.max(np.abs(estimate / TRUE_PARAMETERS - 1)) <= tolerance
    window, cutoff = document["derivatives"]["window"], document["low_pass"]["cutoff_hz"]
    assert document["derivatives"] == {
        "method": "savitzky-golay smoothing, central differences", "window": window, "order": 3,
        "step": pytest.approx(0.001), "trimmed_samples": 0, "estimated": ["qd", "qdd"],
        "window_chosen": "automatic", "cutoff_hz": cutoff,
    }
    assert 1.0 < cutoff < 1.8  # 3 x the band of rich motion's 0.21 and 0.43 Hz sines
    # Its -3 dB point near 3 x the cutoff (Schafer's formula for a cubic: f / (rate / 2) = 4 / (3.2 M - 4.6)).
    assert window == 2 * math.ceil((4 * 500 / (3 * cutoff) + 4.6) / 3.2) + 1  # f_3dB as a share of Nyquist
    # Only the log's ends may stand out (the smoothing's polynomial ends): nothing inside is left out.
    assert all(start == 0 or end >= 7.99 for start, end in document["excluded"]), document["excluded"]


def test_the_quantised_angles_are_whole_counts(capsys, tmp_path):
    path = simulate(capsys, tmp_path / "enc.csv", "--rate", "100", "--encoder-counts", "360")
    values = np.loadtxt(path, delimiter=",", skiprows=2)
    counts = values[:, 1] / (2 * math.pi / 360)
    np.testing.assert_allclose(counts, np.round(counts), atol=1e-9)
    assert len(values) == 801


def test_window_and_order_options_reach_the_filter(capsys, tmp_path):
    path = simulate(capsys, tmp_path / "enc.csv", "--rate", "1000", "--encoder-counts", "65536")
    document = fit_json(capsys, "--csv", path, "--window", "301", "--order", "5", "--cutoff", "0", "--no-robust",
                        "--model", "plain")
    assert (document["derivatives"]["window"], document["derivatives"]["order"]) == (301, 5)
    assert document["samples"] == 8001  # nothing trimmed


def test_degrees_flag_reads_degree_logs(capsys, tmp_path):
    t, q, qd, qdd, tau = truth_states("rich", 100)
    path = tmp_path / "deg.csv"
    lines = ["q,qd,qdd,tau"] + rows_of(q * 180 / math.pi, qd * 180 / math.pi, qdd * 180 / math.pi, tau)
    path.write_text("\n".join(lines) + "\n")
    document = fit_json(capsys, "--csv", path, "--degrees", "--model", "plain")
    np.testing.assert_allclose([document["estimate"][k] for k in "IhB"], TRUE_PARAMETERS, rtol=1e-6)
    radians = fit_json(capsys, "--csv", path, "--model", "plain")  # the same numbers taken as radians fit something else
    assert abs(radians["estimate"]["I"] - 0.8) > 0.01


def test_synthetic_json_gains_null_source_and_derivatives(capsys):
    document = fit_json(capsys)
    assert document["source"] is None and document["derivatives"] is None
    assert document["settings"] == {"motion": "rich", "noise": 0.0, "samples": 24, "seed": 7, "model": "plain",
                                    "true_coulomb": 0.0, "true_bias": 0.0, "true_angle_offset": 0.0,
                                    "constrained": False}


@pytest.mark.parametrize(
    "argv, words",
    [
        (["fit", "--csv", "x.csv", "--motion", "slow"], "synthetic settings (--motion) cannot apply"),
        (["fit", "--csv", "x.csv", "--noise", "0.2", "--seed", "3"], "(--noise, --seed)"),
        (["fit", "--csv", "x.csv", "--samples", "24"], "(--samples)"),
        (["fit", "--heldout", "x.csv"], "--heldout: only for fitting a log"),
        (["fit", "--degrees"], "--degrees: only for fitting a log"),
        (["fit", "--window", "11"], "--window: only for fitting a log"),
        (["fit", "--csv", "x.csv", "--window", "10"], "must be an odd number"),
        (["fit", "--csv", "x.csv", "--window", "11", "--order", "11"], "must be less than the window 11"),
        (["fit", "--csv", "x.csv", "--order", "1"], "at least 2"),
        (["simulate"], "--out"),
        (["simulate", "--out", "o.csv", "--motion", "wobble"], "must be one of rich, slow, holds, test"),
        (["simulate", "--out", "o.csv", "--rate", "0"], "greater than 0"),
        (["simulate", "--out", "o.csv", "--rate", "100", "--samples", "10", "--duration", "8"], "contradicts --rate 100 Hz"),
        (["simulate", "--out", "o.csv", "--rate", "3", "--duration", "0.5"], "not a whole number"),
        (["simulate", "--out", "o.csv", "--rate", "2000000", "--duration", "8"], "samples must be"),
        (["simulate", "--out", "o.csv", "--encoder-counts", "1"], "at least 2"),
        (["simulate", "--out", "no/such/dir/o.csv"], "cannot write"),
    ],
)
def test_option_mistakes_are_one_line_and_status_2(capsys, tmp_path, monkeypatch, argv, words):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "x.csv").write_text("q,qd,qdd,tau\n0,0,0,1\n1,1,1,2\n2,1,0,3\n")
    try:
        status = main(argv)
    except SystemExit as stop:  # argparse's own errors
        status = stop.code
    captured = capsys.readouterr()
    assert status == 2 and captured.out == ""
    assert len(captured.err.splitlines()) == 1 and words in captured.err
    assert not (tmp_path / "o.csv").exists()


def test_simulate_timing_resolves_any_two_of_samples_rate_duration(capsys, tmp_path):
    for argv, samples, last in (
        ([], 24, 8.0),
        (["--rate", "10"], 81, 8.0),
        (["--samples", "11", "--rate", "10"], 11, 1.0),
        (["--duration", "2", "--rate", "50"], 101, 2.0),
        (["--duration", "2", "--samples", "5"], 5, 2.0),
        (["--duration", "2", "--samples", "201", "--rate", "100"], 201, 2.0),
    ):
        path = simulate(capsys, tmp_path / f"s{len(argv)}_{samples}.csv", *argv)
        values = np.loadtxt(path, delimiter=",", skiprows=2)
        assert len(values) == samples and values[-1, 0] == pytest.approx(last)


def test_simulate_never_overwrites_without_force_and_leaves_no_temporary_files(capsys, tmp_path):
    path = tmp_path / "log.csv"
    path.write_text("precious\n")
    status, out, err = run(capsys, "simulate", "--out", path)
    assert status == 2 and out == "" and "already exists" in err and "--force" in err
    assert path.read_text() == "precious\n"
    simulate(capsys, path, "--force", "--samples", "30")
    assert len(np.loadtxt(path, delimiter=",", skiprows=2)) == 30
    assert sorted(p.name for p in tmp_path.iterdir()) == ["log.csv"]


@pytest.mark.parametrize("name", sorted(CORPUS) + ["absent.csv", "a_directory"])
@pytest.mark.parametrize("role", ["training", "heldout"])
def test_every_bad_file_exits_2_with_one_line_naming_it(capsys, tmp_path, name, role):
    good = tmp_path / "good.csv"
    good.write_text("\n".join([HEADER, *good_rows()]) + "\n")
    bad = tmp_path / name
    if name == "a_directory":
        bad.mkdir()
    elif name in CORPUS:
        bad.write_bytes(CORPUS[name].encode("latin-1"))
    argv = ["fit", "--csv", bad] if role == "training" else ["fit", "--csv", good, "--heldout", bad]
    status, out, err = run(capsys, *argv)
    assert status == 2 and out == ""
    assert len(err.splitlines()) == 1 and err.startswith(f"jointid: {bad}")
    assert "Traceback" not in err


ROW_AND_COLUMN = {
    "word.csv": ("row 7", "column 2 (q)"),
    "nan.csv": ("row 7", "column 3 (qd)"),
    "inf.csv": ("row 7", "column 5 (tau)"),
    "short_row.csv": ("row 7", None),
    "time_backwards.csv": ("row 7", "column 1 (t)"),
    "uneven_time.csv": ("row 252", "column 1 (t)"),
}


@pytest.mark.parametrize("name", sorted(ROW_AND_COLUMN))
def test_bad_cells_are_located(capsys, tmp_path, name):
    bad = tmp_path / name
    bad.write_text(CORPUS[name])
    _, _, err = run(capsys, "fit", "--csv", bad)
    row, column = ROW_AND_COLUMN[name]
    assert f", {row}" in err
    if column:
        assert f", {column}:" in err


def test_a_real_process_prints_one_line_and_no_traceback(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text(CORPUS["nan.csv"])
    done = subprocess.run(
        [sys.executable, "-m", "jointid", "fit", "--csv", str(bad), "--json"],
        capture_output=True, text=True, timeout=60,
    )
    assert done.returncode == 2 and done.stdout == ""
    assert done.stderr == f"jointid: {bad}, row 7, column 3 (qd): NaN is not a measurement\n"
