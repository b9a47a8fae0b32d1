"""The excitation designer and motion files, checked against an independent numpy model.

Standard errors, limits, condition numbers and sweeps are recomputed here from
the Fourier series formula and the lesson's LCG (tests/support/physics_reference.py),
not from jointid's solver or uncertainty code.
"""

import json
import math
import subprocess
import sys

import numpy as np
import pytest
from support.physics_reference import COLUMNS, MODELS, measured, noise, rich_states

from jointid.cli import main
from jointid.present.design import design_text
from jointid.studies.design import DesignCancelled, DesignError, DesignSpec, Limits, design_motion
from jointid.studies.experiment import run_experiment
from jointid.synthetic.fourier import FourierMotion, MotionFileError, load_motion, motion_text, save_motion
from jointid.synthetic.settings import Settings

SIGMA = 0.20 / math.sqrt(3.0)
"""Standard deviation of noise uniform on [-0.2, 0.2]."""


def fourier_states(motion: FourierMotion, t):
    """q, qd, qdd of the series written out term by term (not jointid's basis matrices)."""
    w = 2 * math.pi / motion.period
    q = np.full_like(t, motion.q_c)
    qd, qdd = np.zeros_like(t), np.zeros_like(t)
    for k, (a, b) in enumerate(zip(motion.a, motion.b), start=1):
        q += a / (k * w) * np.sin(k * w * t) - b / (k * w) * np.cos(k * w * t)
        qd += a * np.cos(k * w * t) + b * np.sin(k * w * t)
        qdd += -a * k * w * np.sin(k * w * t) + b * k * w * np.cos(k * w * t)
    return q, qd, qdd


def reference_regressor(q, qd, qdd, model="plain"):
    """(N, p) regressor from the reference columns."""
    return np.column_stack([COLUMNS[name](q, qd, qdd) for name in MODELS[model]])


def reference_std_errors(matrix):
    """(p,) sigma * sqrt(diag((X^T X)^-1)) formed plainly."""
    return SIGMA * np.sqrt(np.diag(np.linalg.inv(matrix.T @ matrix)))


def design_regressor(motion, samples=24, model="plain"):
    t = np.linspace(0.0, 8.0, samples)
    return reference_regressor(*fourier_states(motion, t), model)


def rich_regressor(samples=24, model="plain"):
    return reference_regressor(*rich_states(samples)[1:], model)


def scaled_condition(matrix):
    return np.linalg.cond(matrix / np.linalg.norm(matrix, axis=0))


@pytest.fixture(scope="module")
def d_plain():
    return design_motion(DesignSpec())


@pytest.fixture(scope="module")
def cond_plain():
    return design_motion(DesignSpec(criterion="cond"))


def test_fourier_states_match_the_series_written_out():
    motion = FourierMotion(8.0, 0.1, (0.5, -0.2, 0.3), (0.25, 0.1, -0.4))
    t = np.linspace(0.0, 11.0, 57)
    states = motion.states(t)
    for mine, theirs in zip((states.q, states.qd, states.qdd), fourier_states(motion, t)):
        np.testing.assert_allclose(mine, theirs, rtol=0, atol=1e-12)


def test_fourier_derivatives_are_the_derivatives_of_q():
    motion = FourierMotion(5.0, -0.2, (0.4, 0.1), (-0.3, 0.2))
    t, h = np.linspace(0.3, 4.7, 23), 1e-5
    ahead, behind, here = motion.states(t + h), motion.states(t - h), motion.states(t)
    np.testing.assert_allclose((ahead.q - behind.q) / (2 * h), here.qd, atol=1e-8)
    np.testing.assert_allclose((ahead.qd - behind.qd) / (2 * h), here.qdd, atol=1e-8)


def test_rich_motion_reference_is_the_lessons_2_1_percent():
    errors = reference_std_errors(rich_regressor())
    assert round(100 * errors[0] / 0.8, 1) == 2.1


def test_d_optimal_design_beats_rich_motion_on_the_lessons_plain_model(d_plain):
    designed = reference_std_errors(design_regressor(d_plain.motion))
    rich = reference_std_errors(rich_regressor())
    assert 100 * designed[0] / 0.8 <= 0.8 * (100 * rich[0] / 0.8)  # I: at most 80 % of rich's 2.1 %
    assert np.all(designed <= rich)  # no parameter worse
    # jointid's own expected standard errors agree with the plain (X^T X)^-1 computation
    np.testing.assert_allclose(d_plain.design.noise_bound_std_error, designed, rtol=1e-9)
    np.testing.assert_allclose(d_plain.rich.noise_bound_std_error, rich, rtol=1e-9)
    assert d_plain.worse_than_rich == ()


@pytest.mark.parametrize("criterion", ["d", "cond"])
def test_every_limit_holds_on_4000_points(criterion, d_plain, cond_plain):
    motion = {"d": d_plain, "cond": cond_plain}[criterion].motion
    q, qd, qdd = fourier_states(motion, np.linspace(0.0, 8.0, 4000, endpoint=False))
    assert np.max(np.abs(q)) <= 0.95 and np.max(np.abs(qd)) <= 1.6 and np.max(np.abs(qdd)) <= 3.0


def test_design_reports_the_active_limit_and_its_margin(d_plain):
    q, qd, qdd = fourier_states(d_plain.motion, np.linspace(0.0, 8.0, 4000, endpoint=False))
    peaks = {"q_max": np.max(np.abs(q)), "qd_max": np.max(np.abs(qd)), "qdd_max": np.max(np.abs(qdd))}
    limits = {"q_max": 0.95, "qd_max": 1.6, "qdd_max": 3.0}
    for check in d_plain.checks:
        assert check.peak == pytest.approx(peaks[check.name], abs=1e-12)
        assert check.margin == pytest.approx(limits[check.name] - peaks[check.name], abs=1e-12)
        assert check.active == (limits[check.name] - peaks[check.name] <= 0.005 * limits[check.name])
    assert any(check.active for check in d_plain.checks)  # an optimum presses against some limit


def sweep_std(motion, seeds, samples=24):
    """Sample standard deviation of numpy lstsq estimates over seeds 7.. on the motion's regressor."""
    t = np.linspace(0.0, 8.0, samples)
    q, qd, qdd = fourier_states(motion, t)
    matrix = reference_regressor(q, qd, qdd)
    torques = measured(q, qd, qdd)[:, None] + noise(0.20, samples, np.arange(7, 7 + seeds)).T
    estimates = np.linalg.lstsq(matrix, torques, rcond=None)[0]
    return np.std(estimates, axis=1, ddof=1), matrix


def test_a_2000_seed_sweep_agrees_with_the_expected_standard_errors(d_plain):
    empirical, matrix = sweep_std(d_plain.motion, 2000)
    np.testing.assert_allclose(empirical, d_plain.design.noise_bound_std_error, rtol=0.10)
    np.testing.assert_allclose(empirical, reference_std_errors(matrix), rtol=0.10)


def test_coulomb_bias_design_beats_rich_motion_on_every_parameter():
    result = design_motion(DesignSpec(experiment=Settings(noise=0.2, model="coulomb+bias")))
    designed = reference_std_errors(design_regressor(result.motion, model="coulomb+bias"))
    rich = reference_std_errors(rich_regressor(model="coulomb+bias"))
    assert np.all(designed < rich)
    np.testing.assert_allclose(result.design.noise_bound_std_error, designed, rtol=1e-8)


def test_cond_design_is_near_1_and_the_printout_names_what_got_worse(cond_plain):
    matrix = design_regressor(cond_plain.motion)
    assert scaled_condition(matrix) < 1.1
    designed, rich = reference_std_errors(matrix), reference_std_errors(rich_regressor())
    worse = [name for name, mine, theirs in zip("IhB", designed, rich) if mine > theirs]
    assert worse  # the counter-example: balanced, yet less informative
    verdict = next(line for line in design_text(cond_plain).splitlines() if line.startswith("Worse than rich"))
    for name in worse:
        assert f"{name} (SE " in verdict
    assert "condition number near 1" in verdict


def test_the_same_seed_gives_the_same_design_and_progress_counts_starts():
    seen = []
    first = design_motion(DesignSpec(starts=3, seed=5), progress=lambda done, total: seen.append((done, total)))
    again = design_motion(DesignSpec(starts=3, seed=5))
    assert first.motion == again.motion
    assert seen == [(1, 3), (2, 3), (3, 3)]


def test_a_cancelled_design_stops():
    calls = []

    def cancelled():
        calls.append(1)
        return len(calls) > 5  # partway through the first start

    with pytest.raises(DesignCancelled):
        design_motion(DesignSpec(starts=4), cancelled=cancelled)


def test_torque_limit_holds_on_4000_points():
    result = design_motion(DesignSpec(limits=Limits(tau_max=5.0), starts=3))
    q, qd, qdd = fourier_states(result.motion, np.linspace(0.0, 8.0, 4000, endpoint=False))
    assert np.max(np.abs(measured(q, qd, qdd))) <= 5.0


def test_a_design_round_trips_through_its_file_bit_for_bit(d_plain, tmp_path, capsys):
    path = tmp_path / "design.json"
    save_motion(d_plain.motion, path)
    loaded = load_motion(path)
    assert loaded == d_plain.motion and loaded.made == d_plain.motion.made
    assert np.array_equal(loaded.coefficients, d_plain.motion.coefficients)
    in_memory = run_experiment(Settings(motion=d_plain.motion, noise=0.2))
    from_file = run_experiment(Settings(motion=loaded, noise=0.2))
    assert np.array_equal(in_memory.estimate, from_file.estimate)
    assert main(["fit", "--noise", "0.2", "--json", "--motion-file", str(path)]) == 0
    document = json.loads(capsys.readouterr().out)
    assert list(document["estimate"].values()) == in_memory.estimate.tolist()
    assert document["settings"]["designed_motion"]["a"] == list(d_plain.motion.a)


def test_cli_design_writes_the_file_it_prints(tmp_path, capsys):
    path = tmp_path / "d.json"
    assert main(["design", "--starts", "2", "--out", str(path), "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert json.loads(path.read_text()) == document["motion"]
    assert document["motion"]["made"]["criterion"] == "d" and document["motion"]["made"]["starts"] == 2
    assert main(["design", "--starts", "2", "--out", str(path)]) == 2  # never over an existing file
    assert "already exists" in capsys.readouterr().err


def test_the_printout_names_the_active_limit_and_every_margin(d_plain, capsys):
    assert main(["design"]) == 0
    out = capsys.readouterr().out
    assert out == design_text(d_plain) + "\n"  # the default design, deterministic for seed 0
    q, qd, qdd = fourier_states(d_plain.motion, np.linspace(0.0, 8.0, 4000, endpoint=False))
    assert f"|qdd| (rad/s²)  {np.max(np.abs(qdd)):.4f}      3  {3 - np.max(np.abs(qdd)):.4f}  active" in out
    assert f"|q| (rad)       {np.max(np.abs(q)):.4f}   0.95  {0.95 - np.max(np.abs(q)):.4f}" in out
    assert "Active limit: |qdd| <= 3 rad/s²" in out


def test_every_synthetic_command_takes_a_motion_file(d_plain, tmp_path, capsys):
    path = tmp_path / "design.json"
    path.write_text(motion_text(d_plain.motion))
    for command in (["fit"], ["sweep", "--seeds", "10"], ["matrix"], ["compare"]):
        assert main([*command, "--noise", "0.2", "--motion-file", str(path)]) == 0
        assert "esigned motion" in capsys.readouterr().out
    out = tmp_path / "log.csv"
    assert main(["simulate", "--motion-file", str(path), "--out", str(out)]) == 0
    table = np.loadtxt(out, delimiter=",", skiprows=2)
    q, qd, qdd = fourier_states(d_plain.motion, table[:, 0])
    np.testing.assert_allclose(table[:, 1], q, atol=1e-12)


def run_cli(*args):
    done = subprocess.run([sys.executable, "-m", "jointid", *args], capture_output=True, text=True)
    return done.returncode, done.stdout, done.stderr


BAD_DESIGNS = [
    (["--q-max", "0"], "--q-max"),
    (["--qd-max", "-1"], "--qd-max"),
    (["--qdd-max", "nan"], "--qdd-max"),
    (["--q-max", "4"], "q-max"),
    (["--tau-max", "2"], "inconsistent"),
    (["--criterion", "e"], "--criterion"),
    (["--harmonics", "0"], "--harmonics"),
    (["--starts", "0"], "--starts"),
]


@pytest.mark.parametrize("flags, named", BAD_DESIGNS, ids=[" ".join(f) for f, _ in BAD_DESIGNS])
def test_bad_design_input_is_one_line_and_exit_2(flags, named, capsys):
    assert exit_status(["design", *flags]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and named in err and "Traceback" not in err


def exit_status(argv) -> int:
    """main's status, also when argparse exits on a bad flag."""
    try:
        return main(argv)
    except SystemExit as exited:
        return exited.code


GOOD = {"kind": "fourier", "period": 8.0, "q_c": 0.0, "a": [0.1, 0.2], "b": [0.0, 0.1], "made": {}}
BAD_FILES = [
    ("not json {", "not valid JSON"),
    (json.dumps([1, 2]), "not an object"),
    (json.dumps({k: v for k, v in GOOD.items() if k != "a"}), "missing key a"),
    (json.dumps({**GOOD, "extra": 1}), "unknown key 'extra'"),
    (json.dumps({**GOOD, "kind": "spline"}), "kind must be"),
    (json.dumps({**GOOD, "b": [0.1]}), "same length"),
    (json.dumps({**GOOD, "a": [0.1, "x"]}), "a[1] must be a number"),
    (json.dumps(GOOD).replace("0.2", "NaN"), "NaN"),
    (json.dumps({**GOOD, "period": 0}), "period must be"),
    (json.dumps({**GOOD, "a": [], "b": []}), "harmonics"),
    (json.dumps({**GOOD, "q_c": 10**400}), "q_c must be a finite number"),
]


@pytest.mark.parametrize("text, named", BAD_FILES, ids=[n for _, n in BAD_FILES])
def test_a_malformed_motion_file_is_one_line_and_exit_2(text, named, tmp_path, capsys):
    path = tmp_path / "bad.json"
    path.write_text(text)
    with pytest.raises(MotionFileError, match=named.replace("[", r"\[").replace("]", r"\]")):
        load_motion(path)
    assert main(["fit", "--motion-file", str(path)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and str(path) in err and named in err


def test_a_missing_motion_file_and_a_cli_run_are_one_line(tmp_path):
    status, out, err = run_cli("sweep", "--motion-file", str(tmp_path / "nowhere.json"))
    assert status == 2 and out == "" and len(err.strip().splitlines()) == 1 and "nowhere.json" in err
    status, _, err = run_cli("design", "--q-max", "0.5", "--tau-max", "3.0")
    assert status == 2 and len(err.strip().splitlines()) == 1 and "inconsistent" in err


def test_the_design_spec_refuses_what_the_cli_would():
    with pytest.raises(DesignError, match="unknown criterion"):
        DesignSpec(criterion="e-optimal")
    with pytest.raises(DesignError, match="q-max"):
        DesignSpec(limits=Limits(q_max=float("nan")))


@pytest.mark.parametrize("samples, period, model, words", [
    (2, 8.0, "plain", "3 parameters need samples at 3 different phases of the motion; 2 samples over 0..8 s give 1 "
                      "(use --samples 4 or more)"),
    (3, 8.0, "plain", "3 samples over 0..8 s give 2"),  # t = 0 and 8 s are one phase of a period of 8 s
    (4, 8.0 / 3.0, "plain", "4 samples over 0..8 s give 1 (use --samples 5 or more)"),
    (5, 8.0, "coulomb+bias", "5 parameters need samples at 5 different phases"),
])
def test_too_few_distinct_states_are_refused_naming_samples_not_the_limits(samples, period, model, words):
    """The optimiser could only fail, and then blamed the limits ('widen the limits or add harmonics')."""
    with pytest.raises(DesignError, match="^samples: ") as raised:
        DesignSpec(period=period, experiment=Settings(samples=samples, model=model))
    assert words in str(raised.value)
