"""The library as a notebook user meets it: docs/library.md runs as written, summary() is `jointid fit`'s text,
and params, bse and conf_int agree with an independent numpy/scipy fit."""

from __future__ import annotations

import doctest
import math
import shutil
from pathlib import Path

import numpy as np
import pytest
from scipy import stats
from support.robot_logs import robot_log, write_log

import jointid
from jointid.cli import main

ROOT = Path(__file__).resolve().parents[2]


def test_the_library_page_runs_as_written(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # its example writes robot.csv, and reads the example SysId log from here
    shutil.copy(ROOT / "docs" / "examples" / "sysid_arm.wpilog", tmp_path)
    result = doctest.testfile(str(ROOT / "docs" / "library.md"), module_relative=False,
                              optionflags=doctest.ELLIPSIS)
    assert result.attempted >= 25 and result.failed == 0


def cli_text(capsys, *argv) -> str:
    capsys.readouterr()
    assert main(list(argv)) == 0
    return capsys.readouterr().out


@pytest.mark.parametrize("motion,noise", [("slow", 0.2), ("rich", 0.0), ("holds", 0.0)])
def test_summary_is_the_command_lines_text(capsys, motion, noise):
    result = jointid.run_experiment(jointid.Settings(motion=motion, noise=noise))
    assert result.summary() + "\n" == cli_text(capsys, "fit", "--motion", motion, "--noise", str(noise))


def test_a_logs_summary_is_the_command_lines_text(capsys, tmp_path):
    path = write_log(tmp_path / "robot.csv", robot_log(300, duration=10))
    logs = jointid.fit_log(path)
    assert logs.summary() + "\n" == cli_text(capsys, "fit", "--csv", str(path))
    assert logs.summary().endswith("\n".join(f"Note: {note}" for note in logs.notes()))


def independent_ols(settings: jointid.Settings):
    """Estimate, residual standard errors and t quantile of the lesson's regressor, by numpy and scipy only."""
    data = jointid.training_data(settings)
    X = np.column_stack([data.qdd, 9.81 * np.cos(data.q), data.qd])
    estimate, rss, _, _ = np.linalg.lstsq(X, data.tau, rcond=None)
    dof = len(data.tau) - 3
    covariance = rss[0] / dof * np.linalg.inv(X.T @ X)
    return estimate, np.sqrt(np.diag(covariance)), dof, np.linalg.inv(X.T @ X)


def test_params_bse_and_conf_int_agree_with_an_independent_fit():
    settings = jointid.Settings(motion="rich", noise=0.2)
    result = jointid.run_experiment(settings)
    estimate, residual_se, dof, factor = independent_ols(settings)
    assert list(result.params) == ["I", "h", "B"]
    np.testing.assert_allclose(list(result.params.values()), estimate, rtol=1e-9)
    # bse: the noise bound's standard error, sqrt(b^2/3 diag((X^T X)^-1)), for synthetic data
    np.testing.assert_allclose(list(result.bse.values()), np.sqrt(0.2**2 / 3 * np.diag(factor)), rtol=1e-9)
    np.testing.assert_allclose(result.uncertainty.residual_std_error, residual_se, rtol=1e-9)
    for alpha in (0.05, 0.32):
        half = stats.t.ppf(1 - alpha / 2, dof) * residual_se
        intervals = result.conf_int(alpha)
        np.testing.assert_allclose([intervals[n] for n in ("I", "h", "B")],
                                   np.column_stack([estimate - half, estimate + half]), rtol=1e-9)


def test_results_are_read_only_and_say_nothing_without_a_unique_fit():
    holds = jointid.run_experiment(jointid.Settings(motion="holds"))
    assert all(math.isnan(v) for v in holds.params.values()) and all(math.isnan(v) for v in holds.bse.values())
    assert all(math.isnan(low) and math.isnan(high) for low, high in holds.conf_int().values())
    with pytest.raises(TypeError):
        holds.params["I"] = 1.0
    with pytest.raises(ValueError, match="alpha must be a number between 0 and 1"):
        holds.conf_int(1.5)


def test_repr_is_one_short_line():
    text = repr(jointid.run_experiment(jointid.Settings()))
    assert text == "<FitResult model='plain' rank=3/3 I=0.8, h=0.4, B=0.15>"


@pytest.mark.parametrize("columns,message", [
    (dict(t=None, q=[0.0, 1.0], qd=None, qdd=None, tau=[1.0, 2.0]), "JointData needs qd and qdd"),
    (dict(t=None, q=[0.0, 1.0], qd=[0.0, 1.0], qdd=[0.0, 1.0], tau=None), "JointData needs tau"),
    (dict(t=None, q=[0.0, 1.0], qd=[0.0, 1.0], qdd=[0.0], tau=[1.0, 2.0]), "qdd has 1 values where q has 2"),
    (dict(t=[0.0], q=[0.0, 1.0], qd=[0.0, 1.0], qdd=[0.0, 1.0], tau=[1.0, 2.0]), "t has 1 values where q has 2"),
    (dict(t=None, q=[0j, 1j], qd=[0.0, 1.0], qdd=[0.0, 1.0], tau=[1.0, 2.0]), "q must be a 1-D array of real"),
    (dict(t=None, q=[[0.0, 1.0]], qd=[0.0, 1.0], qdd=[0.0, 1.0], tau=[1.0, 2.0]), "q must be a 1-D array"),
])
def test_joint_data_refuses_what_it_cannot_fit_naming_it(columns, message):
    with pytest.raises(ValueError, match=message):
        jointid.JointData(**columns)


def test_fit_log_takes_a_dataframe_and_names_what_is_missing():
    import pandas

    columns = robot_log(200, duration=8)
    frame = pandas.DataFrame({"time_s": columns["t"], **columns})
    from_frame = jointid.fit_log(frame)
    from_dict = jointid.fit_log(columns)
    assert list(from_frame.params.values()) == list(from_dict.params.values())
    assert from_frame.training.ignored == ("time_s",)
    with pytest.raises(jointid.LogError, match=r"^arrays: no tau column"):
        jointid.fit_log({"t": columns["t"], "q": columns["q"]})
    with pytest.raises(jointid.LogError, match=r"column 'tau': has 3 values where 't' has"):
        jointid.fit_log({"t": columns["t"], "q": columns["q"], "tau": [1.0, 2.0, 3.0]})
    with pytest.raises(TypeError, match="model must be a model name or a JointModel"):
        jointid.fit_log(columns, model=3)


def test_every_public_name_is_documented_and_its_examples_run():
    import importlib
    import inspect

    modules = set()
    for name in jointid.__all__:
        value = getattr(jointid, name)
        if not (inspect.isfunction(value) or inspect.isclass(value)):
            continue
        doc = inspect.getdoc(value) or ""
        assert doc, name
        if inspect.isfunction(value):
            assert "Parameters\n----------" in doc and "Returns\n-------" in doc, name
        modules.add(value.__module__)
    failed = {module: doctest.testmod(importlib.import_module(module), optionflags=doctest.ELLIPSIS).failed
              for module in sorted(modules)}
    assert failed == {module: 0 for module in failed}
