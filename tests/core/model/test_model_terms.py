"""A model with more terms than the lesson's goes through the whole pipeline: fit, uncertainty,
identifiable subset, sweep, matrix, CLI JSON and the explorer's readouts.

Every expected value comes from a numpy reference built here from the model's
equation (a hand-made regressor and numpy.linalg.lstsq), never from jointid.
"""

from __future__ import annotations

import asyncio
import json

import numpy as np
import pytest
from support.tui_support import displayed_readouts, make_app

from jointid.cli import main
from jointid.model.terms import G, model_named
from jointid.options import ModelError, SettingsError
from jointid.present.readouts import readouts
from jointid.present.status import status_message
from jointid.studies.cross_excitation import cross_excitation
from jointid.studies.experiment import run_experiment
from jointid.studies.sweep import run_sweep
from jointid.synthetic.settings import Settings

TRUE = np.array([0.8, 0.4, 0.15])
MODULUS = 2**32


def lesson_noise(noise: float, count: int, seed: int) -> np.ndarray:
    """The lesson's LCG, sample by sample (the reference the product must match)."""
    values = []
    for _ in range(count):
        seed = (1664525 * seed + 1013904223) % MODULUS
        values.append(noise * (2 * seed / MODULUS - 1))
    return np.array(values)


def reference_problem(noise: float, samples: int = 24, seed: int = 7):
    """Rich motion's states, a hand-built [qdd, g cos q, qd, 1, sign(qd)] matrix and the noisy torques."""
    t = np.linspace(0.0, 8.0, samples)
    q = 0.7 * np.sin(1.3 * t) + 0.25 * np.sin(2.7 * t)
    qd = 0.7 * 1.3 * np.cos(1.3 * t) + 0.25 * 2.7 * np.cos(2.7 * t)
    qdd = -0.7 * 1.3**2 * np.sin(1.3 * t) - 0.25 * 2.7**2 * np.sin(2.7 * t)
    columns = {"I": qdd, "h": G * np.cos(q), "B": qd, "tau0": np.ones_like(t), "Fc": np.sign(qd)}
    tau = qdd * TRUE[0] + G * np.cos(q) * TRUE[1] + qd * TRUE[2] + lesson_noise(noise, samples, seed)
    return columns, tau


@pytest.mark.parametrize("name, names", [("bias", ("I", "h", "B", "tau0")),
                                         ("coulomb+bias", ("I", "h", "B", "Fc", "tau0")),
                                         ("bias+coulomb", ("I", "h", "B", "Fc", "tau0")),
                                         ("plain+coulomb", ("I", "h", "B", "Fc"))])
def test_a_model_with_extra_terms_fits_like_lstsq_on_the_hand_built_regressor(name, names):
    columns, tau = reference_problem(0.2)
    X = np.column_stack([columns[n] for n in names])
    expected = np.linalg.lstsq(X, tau, rcond=None)[0]
    result = run_experiment(Settings(noise=0.2, model=name))
    assert result.model.names == names and result.rank == len(names)
    np.testing.assert_allclose(result.estimate, expected, rtol=1e-9, atol=1e-12)
    # Expected standard errors: sqrt(b²/3 diag((XᵀX)⁻¹)), from the explicit inverse.
    covariance = np.linalg.inv(X.T @ X)
    np.testing.assert_allclose(result.uncertainty.noise_bound_std_error,
                               np.sqrt(0.2**2 / 3 * np.diag(covariance)), rtol=1e-8)
    residual = tau - X @ expected
    assert result.training_rmse == pytest.approx(np.sqrt(np.mean(residual**2)), rel=1e-9)


def test_model_names_are_checked_and_spelled_in_one_order():
    assert model_named("Coulomb+Bias").names == model_named("bias+coulomb").names
    for bad in ("", "viscous", "bias+bias", "plain+", "+bias"):
        with pytest.raises(ModelError):
            model_named(bad)
    with pytest.raises(SettingsError, match="unknown model 'friction'"):
        Settings(model="friction")


def test_a_zero_column_names_the_term_the_motion_cannot_see():
    # Holds: qd = 0 everywhere, so sign(qd) is zero too; the bias column is not.
    result = run_experiment(Settings(motion="holds", model="coulomb+bias"))
    assert result.estimate is None and result.rank == 1
    subset = result.identifiable
    assert list(subset.zero_columns) == [True, False, True, True, False]
    assert "Coulomb friction" in status_message(result) and "no velocity" in status_message(result)
    # h and tau0 share the constant column g*cos(0) = 9.81 and 1: neither is determined alone.
    assert subset.values == {}


def test_readouts_and_sign_rules_come_from_the_terms():
    result = run_experiment(Settings(motion="slow", noise=0.2, model="bias"))
    labels = {r.key: r.label for r in readouts(result)}
    assert labels["tau0"] == "Fitted torque bias (N m)"
    assert [r.key for r in readouts(result)][:6] == ["rank", "I", "h", "B", "tau0", "training_rmse"]
    # tau0 has no sign rule, so only I, h, B can fail.
    failed = {r.key: r.failed_requirement for r in readouts(result) if r.sign_failure}
    assert failed and set(failed) <= {"I", "h", "B"}
    assert all(requirement.startswith(key) for key, requirement in failed.items())


def test_the_sweep_and_the_matrix_work_for_four_terms():
    sweep = run_sweep(Settings(noise=0.2, model="bias"), 200)
    assert sweep.estimates.shape == (4, 200)
    single = run_experiment(Settings(noise=0.2, seed=int(sweep.seeds[17]), model="bias"))
    np.testing.assert_array_equal(sweep.estimates[:, 17], single.estimate)
    assert set(sweep.sign_failure_fractions) == {"I", "h", "B", "tau0"}
    assert sweep.sign_failure_fractions["tau0"] == 0.0  # no sign rule, never a failure
    table = cross_excitation(Settings(noise=0.2, model="bias"))
    assert all(row.fit.model.names[-1] == "tau0" for row in table.rows)


def test_cli_json_keys_every_per_parameter_object_by_term_name(capsys):
    assert main(["fit", "--noise", "0.2", "--model", "coulomb+bias", "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    names = ["I", "h", "B", "Fc", "tau0"]
    assert document["model"] == "coulomb+bias" and document["settings"]["model"] == "coulomb+bias"
    for key in ("estimate", "std_error", "noise_bound_std_error", "relative_std_pct", "interval95", "verdicts"):
        assert list(document[key]) == names, key
    columns, tau = reference_problem(0.2)
    expected = np.linalg.lstsq(np.column_stack([columns[n] for n in names]), tau, rcond=None)[0]
    np.testing.assert_allclose([document["estimate"][n] for n in names], expected, rtol=1e-9)


def test_cli_sweep_and_matrix_json_name_the_model(capsys):
    assert main(["sweep", "--model", "bias", "--seeds", "20", "--json"]) == 0
    sweep = json.loads(capsys.readouterr().out)
    assert sweep["model"] == "bias" and list(sweep["noise_bound_std_error"]) == ["I", "h", "B", "tau0"]
    assert main(["matrix", "--model", "bias", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["model"] == "bias"


def test_an_unknown_model_is_one_line_and_exit_2(capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["fit", "--model", "viscous"])
    err = capsys.readouterr().err
    assert exit_info.value.code == 2 and len(err.strip().splitlines()) == 1
    assert "unknown model 'viscous'" in err


def test_the_explorer_shows_every_term_of_the_model():
    settings = Settings(noise=0.2, model="bias")

    async def scenario():
        app = make_app(settings)
        async with app.run_test(size=(120, 40)) as pilot:
            await pilot.pause()
            return displayed_readouts(app.screen)

    shown = asyncio.run(scenario())
    result = run_experiment(settings)
    columns, tau = reference_problem(0.2)
    X = np.column_stack([columns[n] for n in ("I", "h", "B", "tau0")])
    bias = np.linalg.lstsq(X, tau, rcond=None)[0][3]
    lines = shown.splitlines()
    assert lines[0].split() == ["Regressor", "rank", "4", "/", "4"]
    assert f"Fitted torque bias (N m)   {bias:.6f}" in lines
    assert status_message(result) in shown.replace("\n", " ")


def test_gravity_columns_are_zero_exactly_where_the_trigonometric_value_is_rounding():
    """g cos q and g sin q are 0 where |cos q| (|sin q|) <= 4 eps max(1, |q|), and np.cos (np.sin) elsewhere: on
    random angles, multiples of pi/2 up to large turns, and arrays of any shape."""
    from jointid.model.terms import rounded_cos, rounded_sin

    eps = np.finfo(float).eps
    rng = np.random.default_rng(3)
    angles = [rng.normal(size=20_000) * 30, np.arange(-400, 401) * (np.pi / 2), np.array([1e17, -1e300, 0.0]),
              np.full((3, 4), np.pi / 2), np.array(np.pi), np.array([])]
    for q in angles:
        for rounded, exact in ((rounded_cos, np.cos), (rounded_sin, np.sin)):
            expected = np.where(np.abs(exact(q)) <= 4 * eps * np.maximum(1.0, np.abs(q)), 0.0, exact(q))
            got = rounded(q)
            assert np.shape(got) == np.shape(q)
            np.testing.assert_array_equal(got, expected)
    assert not rounded_cos(np.arange(-401, 401, 2) * (np.pi / 2)).any()  # odd multiples of pi/2: no gravity
    assert np.all(np.abs(rounded_cos(np.arange(-400, 401, 2) * (np.pi / 2))) == 1.0)  # even ones: all of it
