"""The command line under bad input: every bad invocation is one line on stderr and status 2; every --json is strict JSON.

Most invocations run in-process through `jointid.cli.main` (fast), with numpy's
RuntimeWarnings turned into errors so that a warning cannot hide behind the one
line; a few run as real processes to prove the installed entry point and its
stderr.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from jointid.cli import main
from jointid.model.terms import G
from jointid.options import WORK_BUDGET
from jointid.synthetic.motions import ALL_MOTIONS

CHECKOUT = Path(__file__).resolve().parents[2]
"""The checkout these tests belong to."""


def strict_json(text: str):
    """json.loads that refuses Infinity, -Infinity and NaN, as strict parsers do."""

    def refuse(constant):
        raise ValueError(f"not strict JSON: {constant}")

    return json.loads(text, parse_constant=refuse)


def run(capsys, argv):
    """(status, stdout, stderr) of `jointid ARGV` in-process; a RuntimeWarning fails the run."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        try:
            status = main([str(a) for a in argv])
        except SystemExit as stop:  # argparse's own errors and --help
            status = stop.code
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def run_process(*argv, timeout=60, cwd=None):
    """(status, stdout, stderr) of `python -m jointid ARGV` in a fresh process."""
    env = {**os.environ, "PYTHONPATH": str(CHECKOUT)}  # this checkout's jointid, wherever the process runs
    done = subprocess.run([sys.executable, "-m", "jointid", *map(str, argv)], capture_output=True, text=True,
                          timeout=timeout, cwd=cwd, env=env)
    return done.returncode, done.stdout, done.stderr


@pytest.fixture
def in_tmp(tmp_path, monkeypatch):
    """Run in tmp_path with a good log x.csv there; the explorer's app must never start."""
    monkeypatch.chdir(tmp_path)
    t = np.linspace(0.0, 8.0, 40)
    states = ALL_MOTIONS["rich"].states(t)
    tau = 0.8 * states.qdd + 0.4 * G * np.cos(states.q) + 0.15 * states.qd
    rows = "".join(f"{a!r},{b!r},{c!r},{d!r},{e!r}\n" for a, b, c, d, e in
                   zip(*(map(float, column) for column in (t, states.q, states.qd, states.qdd, tau))))
    (tmp_path / "x.csv").write_text("t,q,qd,qdd,tau\n" + rows)
    from tui.app import JointIdApp

    def started(self, *args, **kwargs):
        raise AssertionError("the explorer started on a bad invocation")

    monkeypatch.setattr(JointIdApp, "run", started)
    return tmp_path


# --- Bad invocations ---------------------------------------------------------------------------------------

NOT_NUMBERS = ["abc", "", "1e", "0x10", "0x1p3", "1_0", "1,5", "٣", "２", "１.５", "۵", "½", "--"]
"""Texts that are not ASCII decimal numbers (Arabic-Indic, full-width and Persian digits, a vulgar fraction)."""
NOT_FINITE = ["nan", "-nan", "NaN", "inf", "-inf", "Infinity", "-Infinity", "1e999", "-1e999"]
NOT_WHOLE = ["2.5", "1e3", "7.0", "99999999999999999999999"]


def cases_for(prefix: list[str], flag: str, values: list[str], suffix: list[str] = ()) -> list[list[str]]:
    """One invocation per value: PREFIX FLAG VALUE SUFFIX."""
    return [[*prefix, flag, value, *suffix] for value in values]


def bad_invocations() -> list[list[str]]:
    """Every bad invocation, generated per subcommand and flag (with what each flag must refuse)."""
    cases: list[list[str]] = []
    noise = NOT_NUMBERS + NOT_FINITE + ["-0.01", "100.5", "1e3"]
    samples = NOT_NUMBERS + NOT_FINITE + NOT_WHOLE + ["1", "0", "-5", "10000001"]
    seed = NOT_NUMBERS + NOT_FINITE + ["2.5", "-1", "4294967296"]
    for command in (["fit"], ["sweep"], ["matrix"]):
        cases += cases_for(command, "--noise", noise)
        cases += cases_for(command, "--samples", samples[::2])  # every other one: the type is shared
        cases += cases_for(command, "--seed", seed[::3])
        cases += cases_for(command, "--model", ["friction", "bias+bias", "plain+", "", "coulomb+", "+"])
    cases += cases_for(["sweep"], "--seeds", NOT_NUMBERS[::2] + NOT_FINITE[::2] + ["0", "-5", "1000001", "1.5"])
    state = {"--q": "0.5", "--qd": "1", "--qdd": "2"}
    for flag in ("--q", "--qd", "--qdd", "--I", "--h", "--B"):
        others = [part for name, value in state.items() if name != flag for part in (name, value)]
        cases += cases_for(["torque", *others], flag, NOT_NUMBERS[::2] + NOT_FINITE)
    out = ["--out", "o.csv"]
    cases += cases_for(["simulate", *out], "--noise", ["abc", "nan", "-inf", "٣", "101"])
    cases += cases_for(["simulate", *out], "--seed", ["x", "-1", "٣", "2.5"])
    cases += cases_for(["simulate", *out], "--samples", ["1", "٣", "2.5", "inf", "10000001"])
    cases += cases_for(["simulate", *out], "--rate", ["0", "-5", "nan", "inf", "-inf", "٣", "1e308", "2e9"])
    cases += cases_for(["simulate", *out], "--duration", ["0", "-1", "nan", "inf", "1e308", "２", "1e7"])
    cases += cases_for(["simulate", *out], "--encoder-counts", ["1", "0", "-2", "2.5", "٣", "nan", "4294967297", "1" + "0" * 400])
    cases += cases_for(["simulate", *out], "--motion", ["fast", "", "RICH!"])
    cases += cases_for([], "--noise", ["٣", "-inf", "nan", "5", "1.5", "101"])  # the explorer: 0 to 1.00 N m
    cases += cases_for([], "--samples", ["1", "241", "1000", "٣"])  # the explorer: 2 to 240
    cases += cases_for([], "--seed", ["-1", "x", "4294967296"])
    export = ["export", "--mujoco", "o.xml"]
    cases += cases_for(export, "--mass", ["0", "-1", "nan", "inf", "٣", "x", "0.1"])  # 0.1 kg: below h²/I = 0.2
    cases += cases_for(export, "--com-distance", ["0", "-2", "nan", "2.5"])  # 2.5 m: beyond I/h = 2
    cases += cases_for([*export, "--mass", "2"], "--armature", ["-0.1", "nan", "0.8", "x"])
    cases += cases_for([*export, "--mass", "1"], "--length", ["0", "nan", "0.3"])  # r = 0.4 m: beyond 0.3
    cases += cases_for([*export, "--mass", "2"], "--name", ["", "a b", "1joint", "<x>"])
    cases += [["export"], ["export", "--mass", "2"], ["export", "--mas", "2", "--mujoco", "o.xml"],
              [*export, "--mass", "2", "--com-distance", "0.2"], [*export, "--mass", "2", "--motion", "holds"],
              [*export, "--mass", "2", "--from-json", "missing.json"], [*export, "--mass", "2", "--urdf", "o.xml"]]
    cases += cases_for(["fit", "--csv", "x.csv"], "--window", ["10", "2", "-3", "abc", "٣", "7001", "4003"])
    cases += cases_for(["fit", "--csv", "x.csv"], "--order", ["1", "-2", "x", "11", "6999", "２"])
    cases += [
        # Abbreviations and unknown flags, on every parser.
        ["fit", "--n", "5"], ["fit", "--nois", "5"], ["fit", "--mot", "slow"], ["fit", "--sam", "30"],
        ["fit", "--se", "3"], ["fit", "--js"], ["fit", "--cs", "x.csv"], ["fit", "--mod", "bias"],
        ["fit", "--csv", "x.csv", "--win", "11"], ["fit", "--csv", "x.csv", "--ord", "3"],
        ["fit", "--csv", "x.csv", "--held", "x.csv"], ["fit", "--csv", "x.csv", "--deg"],
        ["sweep", "--see", "30"], ["sweep", "--seeds", "5", "--for"], ["matrix", "--noi", "0.1"],
        ["torque", "--q", "1", "--qd", "1", "--qdd", "1", "--j"], ["torque", "--q", "1", "--qd", "1", "--qdd", "1", "--de"],
        ["simulate", "--o", "o.csv"], ["simulate", "--out", "o.csv", "--enc", "5"],
        ["simulate", "--out", "o.csv", "--dur", "2"], ["simulate", "--out", "o.csv", "--for"],
        ["--nois", "0.5"], ["--mot", "slow"], ["--cs", "x.csv"], ["--ver"],
        ["fit", "--bogus"], ["fit", "extra"], ["fly"], ["FIT"], ["fit", "-n", "5"], ["fit", "--noise=٣"],
        ["fit", "--json=yes"], ["fit", "--json", "-5"], ["sweep", "--force=1"], ["matrix", "--json", "x"],
        # Missing values and required flags.
        ["fit", "--noise"], ["fit", "--samples"], ["fit", "--seed"], ["fit", "--motion"], ["fit", "--model"],
        ["fit", "--csv"], ["sweep", "--seeds"], ["torque"], ["torque", "--q", "1"], ["torque", "--q", "1", "--qd", "1"],
        ["torque", "--qdd", "1", "--qd", "1", "--q"], ["simulate"], ["simulate", "--out"], ["--csv"], ["--noise"],
        # Choices and conflicts.
        ["fit", "--motion", "test"], ["fit", "--motion", "fast"], ["matrix", "--motion", "fast"],
        ["fit", "--csv", "x.csv", "--noise", "0.1"], ["fit", "--csv", "x.csv", "--samples", "24"],
        ["fit", "--window", "11"], ["fit", "--heldout", "x.csv"], ["fit", "--degrees"],
        ["fit", "--csv", "missing.csv"], ["fit", "--csv", "x.csv", "--heldout", "missing.csv"],
        ["fit", "--csv", "x.csv", "--window", "11", "--order", "11"], ["--csv", "missing.csv"],
        ["--csv", "x.csv", "--motion", "slow"], ["--window", "10"],
        ["simulate", "--out", "o.csv", "--rate", "100", "--samples", "10", "--duration", "8"],
        ["simulate", "--out", "o.csv", "--rate", "3", "--duration", "0.5"],
        # Work beyond the budget, values beyond double precision.
        ["sweep", "--samples", "1000000", "--seeds", "1000"], ["sweep", "--samples", "10000000", "--seeds", "1000000"],
        ["sweep", "--samples", "100001", "--seeds", "1000", "--json"],
        ["torque", "--q", "0", "--qd", "0", "--qdd", "0", "--h", "1e308", "--json"],
        ["torque", "--q", "0", "--qd", "1e200", "--qdd", "0", "--json"], ["torque", "--q", "0", "--qd", "1e200", "--qdd", "0"],
        ["torque", "--q", "0", "--qd", "0", "--qdd", "1e308", "--I", "10"],
        ["torque", "--q", "0", "--qd", "1e308", "--qdd", "1e308", "--I", "1", "--B", "1", "--json"],
        ["torque", "--q", "0", "--qd", "-1e300", "--qdd", "0", "--B", "1e10"],
        ["simulate", "--out", "o.csv", "--duration", "1e308", "--rate", "1e308"],
        ["simulate", "--out", "o.csv", "--samples", "2", "--duration", "1e308"],
        ["simulate", "--out", "o.csv", "--samples", "3", "--rate", "1e-300"],
        ["simulate", "--out", "o.csv", "--rate", "1e9", "--duration", "1e6"],
        ["simulate", "--out", "o.csv", "--rate", "1e-300", "--duration", "8"],
        # jointid report: fit's flags, and where it writes.
        ["report"], ["report", "--out"], ["report", "--out", "o.csv", "--noise", "nan"],
        ["report", "--out", "o.csv", "--csv", "missing.csv"], ["report", "--out", "o.csv", "--markdown", "o.csv"],
        ["report", "--out", "o.csv", "--csv", "x.csv", "--simulate"], ["report", "--out", "o.csv", "--comp"],
    ]
    return cases


BAD = bad_invocations()


def test_the_fuzz_list_is_long_and_covers_every_subcommand():
    assert len(BAD) >= 150
    first_words = {case[0] if case and not case[0].startswith("-") else "(explorer)" for case in BAD}
    assert {"fit", "sweep", "matrix", "torque", "simulate", "export", "(explorer)"} <= first_words


@pytest.mark.parametrize("argv", BAD, ids=[" ".join(case) or "(empty)" for case in BAD])
def test_a_bad_invocation_is_one_line_and_status_2(capsys, in_tmp, argv):
    status, out, err = run(capsys, argv)
    assert status == 2, err
    assert out == ""
    assert len(err.splitlines()) == 1 and err.endswith("\n"), err
    assert err.startswith("jointid") and "Traceback" not in err and "Warning" not in err
    assert not (in_tmp / "o.csv").exists() and not (in_tmp / "o.xml").exists()  # simulate and export wrote nothing


@pytest.mark.parametrize(
    "argv, words",
    [
        (["fit", "--n", "5"], "unrecognized arguments: --n"),  # was noise 5.00
        (["fit", "--noise", "٣"], "got '٣'"),  # was noise 3.00
        (["fit", "--noise", "２"], "got '２'"),
        (["--noise", "٣"], "got '٣'"),
        (["fit", "--noise", "-inf"], "must be a finite number from 0 to 100 (N m); got '-inf'"),  # was 'expected one argument'
        (["torque", "--q", "-nan", "--qd", "0", "--qdd", "0"], "argument --q: must be a finite number; got '-nan'"),
        (["torque", "--q", "0", "--qd", "0", "--qdd", "0", "--h", "1e308", "--json"], "gravity compensation h*g*cos(q) overflows"),
        (["torque", "--q", "0", "--qd", "1e200", "--qdd", "0", "--json"], "damper's power B*qd² overflows"),
        (["simulate", "--out", "o.csv", "--duration", "1e308", "--rate", "1e308"], "at most 1e+06"),
        (["simulate", "--out", "o.csv", "--samples", "3", "--rate", "1e-300"], "at most 1e+06 s"),
        (["sweep", "--samples", "1000000", "--seeds", "1000"], "add --force"),
        (["fit", "--csv", "x.csv", "--window", "7001", "--order", "6999"], "at most 4001"),
        (["fit", "--csv", "x.csv", "--window", "21", "--order", "15"], "at most 10"),
    ],
)
def test_each_reported_case_says_what_is_wrong(capsys, in_tmp, argv, words):
    status, out, err = run(capsys, argv)
    assert (status, out) == (2, "") and words in err, err


def test_negative_numbers_after_a_flag_are_its_value(capsys):
    status, out, err = run(capsys, ["torque", "--q", "-1e5", "--qd", "-2", "--qdd", "-.5", "--json"])
    assert (status, err) == (0, "")
    assert strict_json(out)["state"] == {"q": -1e5, "qd": -2.0, "qdd": -0.5}


def test_forced_sweeps_run_beyond_the_budget(capsys, monkeypatch):
    monkeypatch.setattr("jointid.cli.sweep_command.WORK_BUDGET", 1000)
    assert run(capsys, ["sweep", "--seeds", "100"])[0] == 2  # 2,400 > 1,000
    status, out, err = run(capsys, ["sweep", "--seeds", "100", "--force", "--json"])
    assert (status, err) == (0, "") and strict_json(out)["seeds"]["count"] == 100
    assert WORK_BUDGET >= 24 * 1_000_000  # the lesson's 24 samples take every seed count without --force


# --- Good invocations: strict JSON ---------------------------------------------------------------------------

MODELS = ["plain", "bias", "coulomb", "coulomb+bias"]

GOOD_JSON = (
    [["fit", "--motion", motion, "--model", model, "--noise", "0.2"] for motion in ("rich", "slow", "holds")
     for model in MODELS]
    + [
        ["fit", "--samples", "2"], ["fit", "--samples", "3"], ["fit", "--samples", "4", "--model", "coulomb+bias"],
        ["fit", "--noise", "100", "--seed", "4294967295"], ["fit", "--noise", "0", "--motion", "holds"],
        ["sweep", "--seeds", "1"], ["sweep", "--seeds", "2", "--samples", "3"],
        ["sweep", "--motion", "slow", "--noise", "0.2", "--seeds", "50", "--model", "bias"],
        ["sweep", "--motion", "holds", "--seeds", "5", "--model", "coulomb+bias"],
        ["sweep", "--seed", "4294967290", "--seeds", "20", "--model", "coulomb"],
        ["matrix"], ["matrix", "--model", "bias", "--noise", "0.2"], ["matrix", "--model", "coulomb+bias", "--samples", "3"],
        ["torque", "--q", "60", "--deg", "--qd", "-2", "--qdd", "3"],
        ["torque", "--q", "0", "--qd", "0", "--qdd", "0", "--h", "1e300"],
        ["torque", "--q", "1e300", "--qd", "1e150", "--qdd", "-1e300", "--I", "1e-10"],
        ["torque", "--q", "-3", "--qd", "5e-324", "--qdd", "0"],
        ["fit", "--csv", "x.csv"], ["fit", "--csv", "x.csv", "--model", "bias"],
        ["fit", "--csv", "x.csv", "--heldout", "x.csv", "--model", "coulomb+bias"],
        ["fit", "--csv", "x.csv", "--degrees"],
        ["fit", "--csv", "enc.csv", "--heldout", "x.csv"], ["fit", "--csv", "enc.csv", "--window", "101", "--order", "3"],
        ["fit", "--csv", "big.csv"], ["fit", "--csv", "tiny.csv", "--model", "bias"],
    ]
)


@pytest.mark.parametrize("argv", GOOD_JSON, ids=[" ".join(case) for case in GOOD_JSON])
def test_every_good_json_output_parses_strictly(capsys, in_tmp, argv):
    if any(name in argv for name in ("enc.csv", "big.csv", "tiny.csv")):
        write_special_logs(capsys, in_tmp)
    status, out, err = run(capsys, [*argv, "--json"])
    assert (status, err) == (0, ""), err
    document = strict_json(out)
    if "--model" in argv:
        assert document["model"] == argv[argv.index("--model") + 1]


@pytest.mark.parametrize("argv", GOOD_JSON, ids=[" ".join(case) for case in GOOD_JSON])
def test_every_good_invocation_prints_text_without_an_error(capsys, in_tmp, argv):
    if any(name in argv for name in ("enc.csv", "big.csv", "tiny.csv")):
        write_special_logs(capsys, in_tmp)
    status, out, err = run(capsys, argv)
    assert (status, err) == (0, ""), err
    assert out and " nan" not in out and "inf " not in out


def write_special_logs(capsys, folder):
    """enc.csv (an encoder log, t, q, tau) and the x.csv log with qd, qdd and tau scaled by 1e154 and 1e-170."""
    assert run(capsys, ["simulate", "--rate", "200", "--duration", "4", "--encoder-counts", "4096",
                        "--noise", "0.1", "--out", folder / "enc.csv"])[0] == 0
    lines = (folder / "x.csv").read_text().splitlines()
    for name, scale in (("big.csv", 1e154), ("tiny.csv", 1e-170)):
        rows = []
        for line in lines[1:]:
            t, q, qd, qdd, tau = map(float, line.split(","))
            rows.append(f"{t!r},{q!r},{qd * scale!r},{qdd * scale!r},{tau * scale!r}")
        (folder / name).write_text("\n".join([lines[0], *rows]) + "\n")


def test_the_good_list_covers_every_json_command():
    assert len(GOOD_JSON) >= 30
    assert {case[0] for case in GOOD_JSON} == {"fit", "sweep", "matrix", "torque"}


def test_a_log_scaled_by_1e154_is_a_full_fit_with_finite_readouts(capsys, in_tmp):
    write_special_logs(capsys, in_tmp)
    status, out, err = run(capsys, ["fit", "--csv", "big.csv", "--json", "--model", "plain"])
    document = strict_json(out)
    assert document["rank"] == 3 and "no acceleration" not in document["message"]
    assert document["estimate"]["I"] == pytest.approx(0.8) and document["estimate"]["B"] == pytest.approx(0.15)
    assert document["estimate"]["h"] == pytest.approx(0.4e154)
    assert document["accel_rms"] == pytest.approx(1e154 * document_rms(in_tmp / "x.csv", 3))
    status, out, err = run(capsys, ["fit", "--csv", "big.csv", "--model", "plain"])
    assert "Rank 3 of 3" in out and " inf" not in out


def document_rms(path, column):
    values = np.loadtxt(path, delimiter=",", skiprows=1)[:, column]
    return float(np.sqrt(np.mean(values**2)))


# --- Real processes ------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "argv",
    [
        ["torque", "--q", "0", "--qd", "1e200", "--qdd", "0", "--json"],  # printed a numpy RuntimeWarning too
        ["torque", "--q", "0", "--qd", "0", "--qdd", "0", "--h", "1e308", "--json"],
        ["fit", "--noise", "-inf"],
        ["fit", "--n", "5"],
        ["sweep", "--samples", "10000000", "--seeds", "1000000"],  # printed nothing for days
        ["--noise", "5"],  # the explorer refuses before it starts
        ["simulate", "--duration", "1e308", "--rate", "1e308", "--out", "never.csv"],
    ],
)
def test_a_real_process_refuses_in_one_line(tmp_path, argv):
    status, out, err = run_process(*argv, timeout=60, cwd=tmp_path)
    assert (status, out) == (2, "")
    assert len(err.splitlines()) == 1 and "Traceback" not in err and "Warning" not in err, err
    assert not (tmp_path / "never.csv").exists()


def test_a_real_process_prints_strict_json():
    status, out, err = run_process("fit", "--model", "coulomb+bias", "--motion", "slow", "--noise", "0.2", "--json")
    assert (status, err) == (0, "")
    assert strict_json(out)["model"] == "coulomb+bias"


def test_compare_takes_torques_near_1e300_as_fit_does(capsys, in_tmp):
    """compare squared the residual norm (BIC) and h (the angle offset's standard errors), which overflow beyond
    1e154, so it refused a log that fit takes; both must give the plain model numpy's least squares, scaled."""
    rng = np.random.default_rng(3)
    t = np.linspace(0.0, 8.0, 400)
    states = ALL_MOTIONS["rich"].states(t)
    tau = 0.8 * states.qdd + 0.4 * G * np.cos(states.q) + 0.15 * states.qd + rng.uniform(-0.2, 0.2, t.size)
    reference = np.linalg.lstsq(np.column_stack([states.qdd, G * np.cos(states.q), states.qd]), tau, rcond=None)[0]
    documents = {}
    for scale in (1.0, 1e300):
        rows = "".join(f"{a!r},{b!r},{c!r},{d!r},{e!r}\n" for a, b, c, d, e in
                       zip(*(map(float, column) for column in (t, states.q, states.qd, states.qdd, tau * scale))))
        (in_tmp / "scaled.csv").write_text("t,q,qd,qdd,tau\n" + rows)
        options = ["--csv", "scaled.csv", "--cutoff", "0", "--no-robust", "--json"]
        status, out, err = run(capsys, ["fit", *options, "--model", "plain"])
        assert (status, err) == (0, "")
        np.testing.assert_allclose(list(strict_json(out)["estimate"].values()), reference * scale, rtol=1e-9)
        status, out, err = run(capsys, ["compare", *options])
        assert (status, err) == (0, ""), err
        documents[scale] = {row["model"]: row for row in strict_json(out)["models"]}
        np.testing.assert_allclose(list(documents[scale]["plain"]["estimate"].values()), reference * scale, rtol=1e-9)
    small, large = documents[1.0], documents[1e300]
    assert min(small, key=lambda name: small[name]["bic"]) == min(large, key=lambda name: large[name]["bic"])
    # Every model's BIC moves by the same 2 n ln(1e300), so their differences stay.
    differences = [large[name]["bic"] - small[name]["bic"] for name in small]
    np.testing.assert_allclose(differences, differences[0], rtol=1e-9)
    assert large["angle-offset"]["estimate"]["h"] == pytest.approx(small["angle-offset"]["estimate"]["h"] * 1e300)
    assert large["angle-offset"]["std_error"]["q0"] == pytest.approx(small["angle-offset"]["std_error"]["q0"],
                                                                     rel=1e-6)


def test_a_flag_repeated_ten_thousand_times_is_one_line_and_two_thousand_runs_parse_in_order(capsys):
    """argparse before Python 3.13 reads a command line in time quadratic in its options (20,000 repeats took
    17 s): a command line beyond MAX_ARGUMENTS words is refused at once; below it every repeat counts."""
    from jointid.cli import parse
    from jointid.cli.arguments import MAX_ARGUMENTS

    status, out, err = run(capsys, ["fit", *["--noise", "0.1"] * 10_000])
    assert (status, out) == (2, "") and len(err.splitlines()) == 1
    assert f"20,001 command-line arguments; at most {MAX_ARGUMENTS:,}" in err
    names = [f"run{i}.csv" for i in range(2000)]
    args = parse(["fit", *(word for name in names for word in ("--csv", name))])
    assert args.runs == names and args.csv == "run0.csv"
    args = parse(["fit", "--csv", "x.csv", *["--exclude", "1:2"] * 1000])
    assert len(args.exclude) == 1000


@pytest.mark.parametrize("intervals", [["0:8"], ["0:4", "4:8"], ["0:"], ["0:7.9"]])
def test_exclude_covering_every_sample_is_one_clear_line(capsys, in_tmp, intervals):
    """It printed numpy's 'Mean of empty slice' and then 'a result is not a finite number' (the robust step took the
    median of no residual)."""
    argv = ["fit", "--csv", "x.csv", *(word for interval in intervals for word in ("--exclude", interval))]
    status, out, err = run(capsys, argv)
    assert (status, out) == (2, "") and len(err.splitlines()) == 1, err
    assert err.startswith("jointid: x.csv: --exclude leaves ") and "samples to fit" in err, err


def test_every_wrote_line_shows_an_odd_output_name_escaped(capsys, in_tmp):
    """An ESC or a BEL in an output name reached the terminal raw in simulate's, export's and design's 'Wrote'."""
    from jointid.text_safety import shown_name

    for argv, name in ((["simulate", "--out"], "a\x1b[2Jb.csv"), (["export", "--mass", "1", "--urdf"], "j\x07.urdf"),
                       (["design", "--samples", "24", "--out"], "m\u202e.json")):
        status, out, err = run(capsys, [*argv, name])
        assert (status, err) == (0, ""), err
        assert f"Wrote {shown_name(name)}" in out and not {c for c in out if not c.isprintable() and c != "\n"}
