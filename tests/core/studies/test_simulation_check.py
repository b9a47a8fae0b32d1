"""The simulation check against an independent fixed-step RK4 integration written here."""

from __future__ import annotations

import json

import numpy as np
import pytest
import support.physics_reference as ref

from jointid.cli import main
from jointid.studies.experiment import run_experiment
from jointid.studies.simulation import simulation_check
from jointid.synthetic.settings import Settings


def validation_at(t):
    """q, qd, qdd of the validation motion at time(s) t."""
    q = 0.6 * np.sin(0.9 * t) + 0.3 * np.cos(2.1 * t)
    qd = 0.54 * np.cos(0.9 * t) - 0.63 * np.sin(2.1 * t)
    qdd = -0.486 * np.sin(0.9 * t) - 1.323 * np.cos(2.1 * t)
    return q, qd, qdd


def reference_rmse(theta, horizon=1.0, coulomb_true=0.0, steps_per_second=4000):
    """RK4 of I qdd + h g cos q + B qd (+ Fc tanh(qd/0.01)) = true torque, restarted every horizon; RMS error."""
    inertia, mass_moment, damping, friction = (*theta, 0.0)[:4]

    def rates(t, q, qd):
        q_true, qd_true, qdd_true = validation_at(t)
        torque = ref.measured(q_true, qd_true, qdd_true, coulomb_true)
        rest = mass_moment * ref.G * np.cos(q) + damping * qd + friction * np.tanh(qd / 0.01)
        return qd, (torque - rest) / inertia

    errors, diverged = [], 0
    for start in np.arange(0.0, 8.0, horizon):
        stop = min(start + horizon, 8.0)
        count = int(round((stop - start) * steps_per_second))
        dt = (stop - start) / count
        q, qd, _ = validation_at(start)
        window, t = [0.0], start
        for step in range(count):
            k1 = rates(t, q, qd)
            k2 = rates(t + dt / 2, q + dt / 2 * k1[0], qd + dt / 2 * k1[1])
            k3 = rates(t + dt / 2, q + dt / 2 * k2[0], qd + dt / 2 * k2[1])
            k4 = rates(t + dt, q + dt * k3[0], qd + dt * k3[1])
            q += dt / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            qd += dt / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
            t += dt
            if (step + 1) % (steps_per_second // 100) == 0:
                window.append(q - validation_at(t)[0])
        window = np.array(window)
        if np.max(np.abs(window)) > 1.0 or not np.all(np.isfinite(window)):
            diverged += 1
        else:
            errors.append(window)
    return (float(np.sqrt(np.mean(np.concatenate(errors) ** 2))) if errors else None), diverged


def check(settings: Settings, horizon: float = 1.0):
    result = run_experiment(settings)
    return result, simulation_check(result, settings.true_joint, horizon)


def test_the_true_parameters_follow_the_motion():
    _, simulated = check(Settings())
    assert simulated.rmse < 1e-3 and simulated.diverged_windows == 0


def test_rich_motion_at_noise_020_matches_an_independent_rk4_and_stays_small():
    result, simulated = check(Settings(noise=0.2))
    expected, diverged = reference_rmse(result.estimate)
    assert diverged == 0 and simulated.diverged_windows == 0
    assert simulated.rmse == pytest.approx(expected, rel=1e-3)
    assert simulated.rmse < 0.015


def test_slow_motion_s_negative_inertia_diverges_and_errs_twenty_times_more_elsewhere():
    _, rich = check(Settings(noise=0.2))
    _, slow = check(Settings(motion="slow", noise=0.2))
    assert slow.diverged_windows >= 1
    assert slow.rmse >= 20 * rich.rmse


def test_on_the_coulomb_joint_the_plain_model_errs_ten_times_more_than_the_coulomb_model():
    plain_fit, plain = check(Settings(noise=0.05, true_coulomb=0.3))
    coulomb_fit, coulomb = check(Settings(noise=0.05, true_coulomb=0.3, model="coulomb"))
    assert plain.rmse >= 10 * coulomb.rmse and coulomb.smoothed and not plain.smoothed
    expected, _ = reference_rmse(plain_fit.estimate, coulomb_true=0.3)
    assert plain.rmse == pytest.approx(expected, rel=1e-2)  # the true torque's sign(qd) steps limit RK4's order


def test_a_full_horizon_run_of_the_rich_fit_is_diverged_not_scored():
    _, whole = check(Settings(noise=0.2), horizon=8.0)
    assert whole.diverged_windows == 1 and whole.rmse is None


def test_cli_reports_the_simulation_when_asked(capsys):
    assert main(["fit", "--motion", "slow", "--noise", "0.2", "--simulate", "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert document["simulation_diverged_windows"] >= 1 and document["simulation_windows"] == 8
    assert main(["fit", "--noise", "0.2", "--horizon", "2"]) == 0
    out = capsys.readouterr().out
    assert "Simulation error (H = 2 s)" in out and "of 4 windows diverged" in out
    assert main(["fit", "--noise", "0.2", "--json"]) == 0
    assert "simulation_rmse" not in json.loads(capsys.readouterr().out)  # only when asked: it needs scipy


def test_a_model_that_simulates_closer_but_predicts_torque_far_worse_is_explained():
    """Slow motion, noise 0.2: the angle-offset model's held-out torque is about 1500 times plain's, yet it simulates
    closer, because its fitted inertia (an independent least squares of its columns here) is thousands of times
    plain's: the sentence says so, with that ratio."""
    from dataclasses import replace

    from jointid.present.comparison import simulation_table
    from jointid.studies.ladder import compare_experiment
    from jointid.studies.simulation import simulate_model
    from jointid.synthetic.settings import DEFAULT_SETTINGS

    settings = replace(DEFAULT_SETTINGS, motion="slow", noise=0.2)
    comparison = compare_experiment(settings)
    checks = {row.model.name: simulate_model(row.model, row.solution.estimate, settings.true_joint)
              for row in comparison.rows}
    text = simulation_table(comparison, checks, 1.0)
    data = run_experiment(settings).training
    g = 9.81
    plain = np.linalg.lstsq(np.column_stack([data.qdd, g * np.cos(data.q), data.qd]), data.tau, rcond=None)[0]
    offset = np.linalg.lstsq(np.column_stack([data.qdd, g * np.cos(data.q), data.qd, g * np.sin(data.q)]),
                             data.tau, rcond=None)[0]
    ratio = offset[0] / plain[0]
    assert ratio > 100
    assert "angle-offset simulates closer than plain" in text
    assert f"its fitted inertia is {ratio:,.0f} times plain's" in text
    assert "bias simulates closer" not in text  # its held-out torque is as good as plain's: nothing to explain
