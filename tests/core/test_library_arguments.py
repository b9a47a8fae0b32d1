"""Every public entry point checks its arguments: a wrong type is a TypeError, a wrong value a ValueError, both
naming the function and the argument (they were AttributeErrors from deep inside, or silently wrong fits);
numpy's scalars are numbers like any other."""

from __future__ import annotations

import inspect
import math

import numpy as np
import pytest

import jointid
from jointid.samples import JointData

GOOD = jointid.training_data(jointid.Settings())
T = np.linspace(0.0, 8.0, 400)
LOG = {"t": T, "q": 0.7 * np.sin(1.3 * T), "tau": np.cos(T)}

BAD_CALLS = {
    "run_experiment": [
        (lambda: jointid.run_experiment(None), TypeError, "run_experiment()'s settings must be a Settings"),
        (lambda: jointid.run_experiment("rich"), TypeError, "got str"),
    ],
    "training_data": [(lambda: jointid.training_data(None), TypeError, "training_data()'s settings")],
    "validation_data": [(lambda: jointid.validation_data(None), TypeError, "validation_data()'s joint")],
    "fit_joint": [
        (lambda: jointid.fit_joint(None), TypeError, "fit_joint()'s training must be a JointData; got NoneType"),
        (lambda: jointid.fit_joint(GOOD, 5), TypeError, "fit_joint()'s heldout must be a JointData"),
        (lambda: jointid.fit_joint(GOOD, model=None), TypeError, "fit_joint()'s model must be a model name"),
        (lambda: jointid.fit_joint(GOOD, model="friction"), ValueError, "fit_joint()'s model: unknown model"),
        (lambda: jointid.fit_joint(GOOD, noise_bound=-1), ValueError, "noise_bound must be at least 0; got -1"),
        (lambda: jointid.fit_joint(GOOD, noise_bound=math.nan), ValueError, "noise_bound must be a finite"),
        (lambda: jointid.fit_joint(GOOD, constrained="no"), TypeError, "constrained must be True or False"),
        (lambda: jointid.fit_joint(GOOD, regressor=np.ones((24, 3)) * 1j), TypeError, "regressor must be real"),
    ],
    "fit_log": [
        (lambda: jointid.fit_log(None), TypeError, "a mapping of arrays"),
        (lambda: jointid.fit_log(LOG, cutoff=-1), ValueError, "fit_log()'s cutoff must be at least 0; got -1"),
        (lambda: jointid.fit_log(LOG, cutoff=math.nan), ValueError, "fit_log()'s cutoff must be a finite number"),
        (lambda: jointid.fit_log(LOG, decimate="2"), TypeError, "fit_log()'s decimate must be a whole number"),
        (lambda: jointid.fit_log(LOG, decimate=2.0), TypeError, "fit_log()'s decimate must be a whole number"),
        (lambda: jointid.fit_log(LOG, window=2), ValueError, "fit_log()'s window must be a whole number at least 3"),
        (lambda: jointid.fit_log(LOG, degrees="yes"), TypeError, "fit_log()'s degrees must be True or False"),
        (lambda: jointid.fit_log(LOG, constrained="no"), TypeError, "fit_log()'s constrained must be True or"),
        (lambda: jointid.fit_log(LOG, exclude=5), TypeError, "fit_log()'s exclude must be a sequence of"),
        (lambda: jointid.fit_log(LOG, exclude=[(2, 1)]), ValueError, "finite start at most the end"),
        (lambda: jointid.fit_log(LOG, model=3), TypeError, "fit_log()'s model must be a model name"),
        (lambda: jointid.fit_log({**LOG, "q": LOG["q"] + 0j}), jointid.LogError, "must be a 1-D array of real"),
        (lambda: jointid.fit_log({**LOG, "t": T[:5]}), jointid.LogError, "has 400 values where 't' has 5"),
    ],
    "fit_wpilog": [
        (lambda: jointid.fit_wpilog(None), TypeError, "fit_wpilog()'s source must be a file's path"),
        (lambda: jointid.fit_wpilog("arm.wpilog", cutoff=-1), ValueError, "fit_wpilog()'s cutoff must be at least 0"),
        (lambda: jointid.fit_wpilog("arm.wpilog", decimate="2"), TypeError, "decimate must be a whole number"),
        (lambda: jointid.fit_wpilog("arm.wpilog", sensitivity="yes"), TypeError, "sensitivity must be True or"),
        (lambda: jointid.fit_wpilog("arm.wpilog", units="furlongs"), ValueError, "units: one of 'rotations'"),
        (lambda: jointid.fit_wpilog("arm.wpilog", model=3), TypeError, "fit_wpilog()'s model must be a model name"),
    ],
    "model_named": [
        (lambda: jointid.model_named(5), TypeError, "model_named()'s name must be a str; got int"),
        (lambda: jointid.model_named("x"), ValueError, "unknown model 'x'"),
    ],
    "predict_torque": [
        (lambda: jointid.predict_torque(None, 0.0, 0.0), TypeError, "predict_torque()'s q must be an array"),
        (lambda: jointid.predict_torque(0.0, "fast", 0.0), TypeError, "predict_torque()'s qd must be real"),
        (lambda: jointid.predict_torque(0.0, 0.0, math.nan), ValueError, "predict_torque()'s qdd must be finite"),
        (lambda: jointid.predict_torque(0.0, 0.0, 0.0, model="bias+"), ValueError, "predict_torque()'s model"),
    ],
    "regressor": [
        (lambda: jointid.regressor(None, None, None), TypeError, "regressor()'s q must be an array"),
        (lambda: jointid.regressor([0.0, math.inf], [0, 0], [0, 0]), ValueError, "got inf at index 1"),
    ],
    "torque_breakdown": [
        (lambda: jointid.torque_breakdown(None, 1, 2), TypeError, "torque_breakdown()'s q must be an array"),
        (lambda: jointid.torque_breakdown(0, 1, 2, theta=[1, 2]), ValueError, "theta must be [I, h, B]"),
    ],
    "solve_least_squares": [
        (lambda: jointid.solve_least_squares(None, None), TypeError, "solve_least_squares()'s X must be an array"),
        (lambda: jointid.solve_least_squares(np.eye(3) + 1j, np.ones(3)), TypeError, "X must be real numbers"),
        (lambda: jointid.solve_least_squares(np.eye(3), np.ones(3), tolerance=math.nan), ValueError,
         "tolerance must be a finite number"),
        (lambda: jointid.solve_least_squares(np.eye(3), np.ones(3), tolerance=-1.0), ValueError,
         "tolerance must be at least 0"),
    ],
}


def public_functions() -> list[str]:
    """The names in jointid.__all__ that are functions (the classes check their own fields)."""
    return sorted(name for name in jointid.__all__ if inspect.isfunction(getattr(jointid, name)))


def test_every_public_function_checks_its_arguments_and_is_tried_here():
    assert set(BAD_CALLS) == set(public_functions())
    for name in public_functions():
        function = getattr(jointid, name)
        assert function.checked_arguments, name  # declared through jointid.checks.checked
        parameters = set(inspect.signature(function).parameters)
        # Every argument a caller gives is checked, except those fit_log reads itself (its source and columns).
        unchecked = parameters - set(function.checked_arguments) - {"source", "heldout", "columns", "settings",
                                                                   "correlation"}
        assert not unchecked, (name, unchecked)


CASES = [(name, *case) for name, cases in BAD_CALLS.items() for case in cases]


@pytest.mark.parametrize("name, call, error, words", CASES, ids=[f"{c[0]}-{i}" for i, c in enumerate(CASES)])
def test_a_bad_argument_is_a_type_or_value_error_naming_it(name, call, error, words):
    with pytest.raises(error) as raised:
        call()
    assert words in str(raised.value) and "\n" not in str(raised.value)


def test_numpy_scalars_are_numbers_and_stored_as_python_ones():
    settings = jointid.Settings(samples=np.int64(24), noise=np.float32(0.2), seed=np.uint32(7),
                                true_bias=np.float64(0.1), constrained=np.bool_(False))
    assert (type(settings.samples), type(settings.noise), type(settings.seed)) == (int, float, int)
    assert settings.constrained is False and settings.noise == float(np.float32(0.2))
    result = jointid.run_experiment(settings)
    assert result.training.count == 24
    logs = jointid.fit_log(LOG, decimate=np.int64(2), cutoff=np.float32(5.0), degrees=np.bool_(False),
                           sensitivity=False)
    assert logs.filter.decimation == 2 and type(logs.filter.decimation) is int
    assert jointid.fit_joint(GOOD, noise_bound=np.float32(0.2), constrained=np.bool_(True)).constrained


@pytest.mark.parametrize("value", [True, "24", 24.0, None])
def test_settings_refuse_what_is_not_a_whole_number_of_samples(value):
    with pytest.raises(jointid.SettingsError, match="samples must be a whole number"):
        jointid.Settings(samples=value)


def test_joint_data_refuses_values_that_are_not_finite_naming_them():
    zeros = np.zeros(5)
    with pytest.raises(ValueError, match="JointData's qd must be finite numbers; got nan at index 2"):
        JointData(t=None, q=zeros, qd=np.array([0, 0, math.nan, 0, 0]), qdd=zeros, tau=zeros)
