"""Missing physics and the model ladder, against the independent numpy model in physics_reference.py.

The acceptance numbers of the missing-physics issue: Coulomb friction, an
encoder offset and a sensor bias, each seen by the model that has its term
and missed by the plain model.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import support.physics_reference as ref

from jointid.cli import main
from jointid.options import SettingsError
from jointid.present.status import status_message
from jointid.studies.experiment import run_experiment
from jointid.studies.ladder import compare_experiment
from jointid.studies.sweep import run_sweep
from jointid.synthetic.settings import Settings


def test_default_settings_have_no_missing_physics_and_the_lesson_numbers_stay():
    result = run_experiment(Settings(motion="slow", noise=0.2))
    assert [round(v, 6) for v in result.estimate] == [-1.607788, 0.400094, 0.109966]
    assert round(result.heldout_rmse, 6) == 2.261865


def test_the_synthetic_joint_adds_each_effect_as_defined():
    settings = Settings(noise=0.0, true_coulomb=0.3, true_bias=0.2, true_angle_offset=0.1)
    result = run_experiment(settings)
    t, q_true, qd, qdd = ref.rich_states(24)
    np.testing.assert_allclose(result.training.q, q_true - 0.1, rtol=0, atol=1e-15)
    np.testing.assert_allclose(result.training.tau, ref.measured(q_true, qd, qdd, 0.3, 0.2), rtol=1e-13)
    t, q_true, qd, qdd = ref.validation_states()
    np.testing.assert_allclose(result.heldout.tau, ref.measured(q_true, qd, qdd, 0.3, 0.2), rtol=1e-13)
    np.testing.assert_allclose(result.heldout.q, q_true - 0.1, atol=1e-15)


def test_coulomb_joint_at_noise_0_coulomb_recovers_it_and_plain_absorbs_it_in_damping():
    coulomb = run_experiment(Settings(true_coulomb=0.3, model="coulomb"))
    np.testing.assert_allclose(coulomb.estimate, [0.8, 0.4, 0.15, 0.3], rtol=0, atol=1e-9)
    plain = run_experiment(Settings(true_coulomb=0.3))
    t, q, qd, qdd = ref.rich_states(24)
    X = ref.regressor("plain", q, qd, qdd)
    expected = np.linalg.lstsq(X, ref.measured(q, qd, qdd, 0.3), rcond=None)[0]
    np.testing.assert_allclose(plain.estimate, expected, rtol=1e-10)
    assert plain.estimate[2] == pytest.approx(0.449, abs=0.001)
    vt, vq, vqd, vqdd = ref.validation_states()
    heldout = ref.regressor("plain", vq, vqd, vqdd) @ expected - ref.measured(vq, vqd, vqdd, 0.3)
    assert plain.heldout_rmse == pytest.approx(np.sqrt(np.mean(heldout**2)), rel=1e-10)
    assert plain.heldout_rmse == pytest.approx(0.23, abs=0.005)


SEEDS = np.arange(7, 7 + 2000)


@pytest.fixture(scope="module")
def coulomb_data():
    """240 rich samples of the Coulomb joint (FC = 0.3) and of the plain joint, 2000 seeds, noise 0.05."""
    t, q, qd, qdd = ref.rich_states(240)
    noise = ref.noise(0.05, 240, SEEDS).T  # (240, 2000)
    return q, qd, qdd, ref.measured(q, qd, qdd, 0.3)[:, None] + noise, ref.measured(q, qd, qdd)[:, None] + noise


def test_coulomb_estimates_over_2000_seeds_are_unbiased_and_their_spread_matches_the_standard_error(coulomb_data):
    q, qd, qdd, with_friction, _ = coulomb_data
    sweep = run_sweep(Settings(samples=240, noise=0.05, true_coulomb=0.3, model="coulomb"), len(SEEDS))
    X = ref.regressor("coulomb", q, qd, qdd)
    reference = np.linalg.lstsq(X, with_friction, rcond=None)[0]
    np.testing.assert_allclose(sweep.estimates, reference, rtol=1e-8, atol=1e-12)
    friction = reference[3]
    assert abs(friction.mean() / 0.3 - 1) < 0.005
    # The spread over seeds within 10 % of the reported (expected) standard error, b²/3 (XᵀX)⁻¹ by hand.
    expected = np.sqrt(0.05**2 / 3 * np.diag(np.linalg.inv(X.T @ X)))[3]
    assert sweep.noise_bound_std_error[3] == pytest.approx(expected, rel=1e-9)
    assert abs(friction.std(ddof=1) / expected - 1) < 0.10


def test_bic_finds_coulomb_friction_when_it_is_there_and_keeps_plain_when_it_is_not(coulomb_data):
    q, qd, qdd, with_friction, without = coulomb_data

    def picks(tau):
        scores = np.stack([ref.bic(name, q, qd, qdd, tau) for name in ref.MODELS])
        return np.array(list(ref.MODELS))[np.argmin(scores, axis=0)]

    with_picks, without_picks = picks(with_friction), picks(without)
    assert np.mean(["coulomb" in name for name in with_picks]) >= 0.97
    assert np.mean(without_picks == "plain") >= 0.90
    # jointid's compare makes the same choice as the reference, seed by seed (a sample of them).
    for index in range(0, len(SEEDS), 97):
        seed = int(SEEDS[index])
        assert compare_experiment(Settings(samples=240, noise=0.05, seed=seed, true_coulomb=0.3)).preferred.model.name \
            == with_picks[index]
        assert compare_experiment(Settings(samples=240, noise=0.05, seed=seed)).preferred.model.name \
            == without_picks[index]


def test_an_angle_offset_is_found_by_its_model_and_pushes_the_plain_inertia_up():
    settings = Settings(noise=0.05, true_angle_offset=0.1)
    offset = run_experiment(Settings(**{**vars(settings), "model": "angle-offset"}))
    t, q_true, qd, qdd = ref.rich_states(24)
    q = q_true - 0.1
    tau = ref.measured(q_true, qd, qdd) + ref.noise(0.05, 24, [7])[0]
    h_c, h_s = np.linalg.lstsq(ref.regressor("angle-offset", q, qd, qdd), tau, rcond=None)[0][[1, 3]]
    assert offset.estimate[3] == pytest.approx(np.arctan2(-h_s, h_c), rel=1e-9)
    assert abs(offset.estimate[3] - 0.1) < 0.005
    assert abs(offset.estimate[1] / 0.4 - 1) < 0.01
    assert run_experiment(settings).estimate[0] >= 1.1 * 0.8


def test_delta_method_standard_errors_of_h_and_q0():
    result = run_experiment(Settings(noise=0.05, true_angle_offset=0.1, model="angle-offset"))
    t, q_true, qd, qdd = ref.rich_states(24)
    X = ref.regressor("angle-offset", q_true - 0.1, qd, qdd)
    covariance = 0.05**2 / 3 * np.linalg.inv(X.T @ X)
    h_c, h_s = result.column_estimate[[1, 3]]
    h = np.hypot(h_c, h_s)
    gradient_h = np.array([0, h_c / h, 0, h_s / h])
    gradient_q0 = np.array([0, h_s / h**2, 0, -h_c / h**2])
    expected = [np.sqrt(g @ covariance @ g) for g in (gradient_h, gradient_q0)]
    np.testing.assert_allclose(result.uncertainty.noise_bound_std_error[[1, 3]], expected, rtol=1e-8)


def test_a_sensor_bias_is_ill_conditioned_on_rich_motion_and_its_errors_are_explained():
    result = run_experiment(Settings(noise=0.05, true_bias=0.2, model="bias"))
    assert result.condition_number > 10
    errors = result.uncertainty.noise_bound_std_error
    assert abs(result.estimate[1] - 0.4) <= 3 * errors[1]
    assert abs(result.estimate[3] - 0.2) <= 3 * errors[3]


def test_compare_json_names_every_ladder_model_and_bic_s_choice(capsys):
    assert main(["compare", "--true-coulomb", "0.3", "--noise", "0.05", "--json"]) == 0
    document = json.loads(capsys.readouterr().out, parse_constant=lambda c: pytest.fail(f"non-finite {c}"))
    assert [m["model"] for m in document["models"]] == list(ref.MODELS)
    assert document["preferred"] == "coulomb"
    assert "coulomb" in document["message"] and "damping" in document["message"]
    t, q, qd, qdd = ref.rich_states(24)
    tau = ref.measured(q, qd, qdd, 0.3) + ref.noise(0.05, 24, [7])[0]
    for model in document["models"]:
        assert model["bic"] == pytest.approx(float(ref.bic(model["model"], q, qd, qdd, tau)), rel=1e-9)


def test_compare_text_marks_the_choice_and_says_what_the_plain_model_does(capsys):
    assert main(["compare", "--true-coulomb", "0.3", "--noise", "0.05"]) == 0
    out = capsys.readouterr().out
    assert "coulomb ←" in out and "BIC prefers coulomb" in out and "plain moves its damping" in out


def test_a_model_whose_extra_column_is_zero_names_the_term_the_motion_cannot_see():
    result = run_experiment(Settings(motion="holds", model="coulomb"))
    assert result.estimate is None
    assert "Coulomb friction" in status_message(result) and "no velocity" in status_message(result)


@pytest.mark.parametrize("flag, value", [("--true-coulomb", "-0.1"), ("--true-coulomb", "11"),
                                         ("--true-bias", "nan"), ("--true-bias", "x"),
                                         ("--true-angle-offset", "0.6"), ("--true-angle-offset", "inf"),
                                         ("--model", "viscous"), ("--model", "coulomb+coulomb")])
def test_bad_physics_flags_are_one_line_and_exit_2(flag, value, capsys):
    for command in (["fit"], ["compare"], ["sweep"], ["matrix"]):
        if command == ["compare"] and flag == "--model":
            continue
        with pytest.raises(SystemExit) as exit_info:
            main([*command, flag, value])
        err = capsys.readouterr().err
        assert exit_info.value.code == 2 and len(err.strip().splitlines()) == 1, (command, flag, value)
        assert "Traceback" not in err


def test_settings_refuse_physics_outside_its_range():
    with pytest.raises(SettingsError, match="true_angle_offset must be a number from -0.5 to 0.5"):
        Settings(true_angle_offset=0.7)


def test_compare_on_a_long_log_agrees_with_each_model_fitted_alone():
    # Above the solver's DIRECT_ROWS the ladder's one pass goes through the blocked reduction.
    from jointid.estimation.fit import fit_joint
    from jointid.model.terms import model_named
    from jointid.samples import JointData
    from jointid.studies.ladder import compare_models

    t, q, qd, qdd = ref.rich_states(20_000)
    tau = ref.measured(q, qd, qdd, 0.3) + np.random.default_rng(3).uniform(-0.05, 0.05, t.size)
    data = JointData(t=t, q=q, qd=qd, qdd=qdd, tau=tau)
    for row in compare_models(data).rows:
        alone = fit_joint(data, model=model_named(row.model.name))
        np.testing.assert_allclose(row.estimate, alone.estimate, rtol=1e-10)
        assert row.training_rmse == pytest.approx(alone.training_rmse, rel=1e-10)


def test_simulate_writes_missing_physics_that_compare_finds_in_the_log(tmp_path, capsys):
    path = tmp_path / "friction.csv"
    assert main(["simulate", "--noise", "0.05", "--rate", "100", "--true-coulomb", "0.3", "--out", str(path)]) == 0
    assert "Coulomb friction 0.3 N m" in path.read_text().splitlines()[0]
    capsys.readouterr()
    assert main(["compare", "--csv", str(path), "--json"]) == 0  # with the default low-pass
    assert json.loads(capsys.readouterr().out)["preferred"] == "coulomb"
    assert main(["compare", "--csv", str(path), "--json", "--cutoff", "0"]) == 0  # the numbers as logged
    document = json.loads(capsys.readouterr().out)
    assert document["preferred"] == "coulomb" and "unavailable" not in document["message"]
    t = np.linspace(0.0, 8.0, 801)
    q = 0.7 * np.sin(1.3 * t) + 0.25 * np.sin(2.7 * t)
    qd = 0.91 * np.cos(1.3 * t) + 0.675 * np.cos(2.7 * t)
    qdd = -1.183 * np.sin(1.3 * t) - 1.8225 * np.sin(2.7 * t)
    tau = ref.measured(q, qd, qdd, 0.3) + ref.noise(0.05, 801, [7])[0]
    expected = np.linalg.lstsq(ref.regressor("coulomb", q, qd, qdd), tau, rcond=None)[0]
    coulomb = next(m for m in document["models"] if m["model"] == "coulomb")
    np.testing.assert_allclose([coulomb["estimate"][n] for n in ("I", "h", "B", "Fc")], expected, rtol=1e-6)
