"""Errors widened by other analysis choices: the gate, the arithmetic, the offset swap, and clean data left alone."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.stats
from support.coulomb_joint import coulomb_joint_log
from support.real_logs import REAL_LOGS, needs_real_logs

import jointid
from jointid.estimation.judgement import Scatter, Spread, judge
from jointid.estimation.uncertainty import WEAK, WELL_DETERMINED
from jointid.model.terms import model_named
from jointid.studies.log_fit import offset_alternative, refits_of
from jointid.studies.refits import CHOICE_MOVE, beyond_noise

G = 9.81


def test_a_move_counts_only_beyond_two_noise_errors_and_widens_by_what_noise_leaves_of_it():
    # Noise errors 0.1: I moves 0.3 (3 errors), h 0.1 (1 error), B 0.199 (just inside the gate), tau0 0.201.
    spreads = beyond_noise(("I", "h", "B", "tau0"), np.array([1.0, 2.0, 3.0, 0.0]), np.array([0.1, 0.1, 0.1, 0.1]),
                           [[1.3, 2.1, 3.199, 0.201]], "the cutoff's choice")
    assert CHOICE_MOVE == 2.0
    assert [spread.name for spread in spreads] == ["I", "tau0"]
    # What noise leaves of a 0.3 move with noise variance 0.01: sqrt(0.09 - 0.01).
    assert spreads[0].error == pytest.approx(math.sqrt(0.08), rel=1e-12)
    assert spreads[0].choice == "the cutoff's choice"


def test_of_several_refits_of_one_choice_the_largest_move_widens():
    spreads = beyond_noise(("I",), np.array([1.0]), np.array([0.1]), [[1.3], [0.5]], "the derivative window's choice")
    assert len(spreads) == 1 and spreads[0].error == pytest.approx(math.sqrt(0.25 - 0.01), rel=1e-12)


def test_a_refit_with_larger_errors_is_allowed_the_noise_of_their_difference():
    # Hausman: a refit using less information has noise error 0.2 against 0.1; their difference's variance is
    # 0.04 - 0.01 = 0.03, so a 0.3 move (1.73 of its errors) is noise; a 0.4 move (2.31) widens by sqrt(0.16 - 0.03).
    assert beyond_noise(("I",), np.array([1.0]), np.array([0.1]), [[1.3]], "x", [[0.2]]) == ()
    (spread,) = beyond_noise(("I",), np.array([1.0]), np.array([0.1]), [[1.4]], "x", [[0.2]])
    assert spread.error == pytest.approx(math.sqrt(0.13), rel=1e-12)
    # A refit with errors barely different is allowed the fit's own noise variance, never less.
    (spread,) = beyond_noise(("I",), np.array([1.0]), np.array([0.1]), [[1.3]], "x", [[0.1001]])
    assert spread.error == pytest.approx(math.sqrt(0.08), rel=1e-12)


def test_a_non_finite_refit_widens_nothing():
    assert beyond_noise(("I", "h"), np.array([1.0, 2.0]), np.array([0.1, 0.1]), [[np.nan, np.inf]], "x") == ()


def test_spreads_add_in_quadrature_to_the_noise_error_and_the_verdict_is_judged_on_the_sum():
    # I = 1 with noise error 0.02 (2 %: well determined by the noise alone); two choices move it beyond noise by
    # 0.04 and 0.08: reported error sqrt(0.02^2 + 0.04^2 + 0.08^2) = 0.091652, 9.2 %: still well determined.
    # h = 2 with error 0.02 (1 %) and a spread of 0.3: sqrt(0.02^2 + 0.3^2) = 0.300666, 15 %: weak.
    judged = judge(("I", "h"), [2.0, 1.0], None,
                   spreads=[Spread("I", 0.04, "the cutoff's choice"),
                            Spread("I", 0.08, "the derivative window's choice"),
                            Spread("h", 0.3, "the robust step's exclusions (--no-robust)")],
                   values=[1.0, 2.0], noise_errors=[0.02, 0.02])
    widened = judged.widened([0.02, 0.02])
    assert widened[0] == pytest.approx(math.sqrt(0.0004 + 0.0016 + 0.0064), rel=1e-12)
    assert widened[1] == pytest.approx(math.sqrt(0.0004 + 0.09), rel=1e-12)
    assert judged.noise_verdicts == (WELL_DETERMINED, WELL_DETERMINED)
    assert judged.verdicts == (WELL_DETERMINED, WEAK)
    # The reason names the larger move first, with the errors before and after.
    assert judged.reasons[0] == ("error widened from 0.02 to 0.0917 by the derivative window's choice, the cutoff's "
                                 "choice")
    assert judged.reasons[1] == "error widened from 0.02 to 0.301 by the robust step's exclusions (--no-robust)"


def test_a_scatter_and_a_spread_widen_together():
    # Birge ratio 2 on a noise error 0.02 adds 0.02 * sqrt(2^2 - 1) in quadrature; with a spread of 0.03 the
    # reported error is sqrt(0.02^2 + 3 * 0.02^2 + 0.03^2) = 0.05 exactly; 5 % is within 10 %, yet a scatter beyond
    # the errors is a finding: weak.
    judged = judge(("I",), [2.0], None, scatters=[Scatter("I", 2.0, "halves of the run")],
                   spreads=[Spread("I", 0.03, "the cutoff's choice")], values=[1.0], noise_errors=[0.02])
    assert judged.widened([0.02])[0] == pytest.approx(0.05, rel=1e-12)
    assert judged.verdicts == (WEAK,)
    assert judged.reasons[0] == ("error widened from 0.02 to 0.05 by the scatter of its halves of the run (2.0 "
                                 "times their errors), the cutoff's choice")


def test_nothing_beyond_noise_leaves_the_error_and_verdict_as_the_noise_says():
    judged = judge(("I",), [2.0], None, spreads=[Spread("I", 0.0, "the cutoff's choice")], values=[1.0],
                   noise_errors=[0.02])
    assert judged.spread == () and judged.widened([0.02]) == (0.02,) and judged.reasons == ("",)


def test_the_offset_swap_trades_a_torque_bias_for_an_angle_offset_and_back():
    swapped, choice = offset_alternative(model_named("coulomb+bias"))
    assert set(swapped.names) == {"I", "h", "q0", "B", "Fc"} and choice == "an angle offset in place of the torque bias"
    swapped, choice = offset_alternative(model_named("coulomb+angle-offset"))
    assert set(swapped.names) == {"I", "h", "B", "Fc", "tau0"}
    assert choice == "a torque bias in place of the angle offset"
    # With both or neither there is nothing to trade.
    assert offset_alternative(model_named("plain")) is None
    assert offset_alternative(model_named("bias+angle-offset")) is None


def hanging_swing(seed: int) -> dict:
    """A pendulum swinging about hanging down with a torque bias of 0.3 N m, its true derivatives given, noise
    0.05 N m: about one angle, the bias and an angle offset explain nearly the same torque."""
    rng = np.random.default_rng(seed)
    t = np.arange(0, 20, 1 / 200)
    q = -math.pi / 2 + 0.6 * np.sin(1.1 * t) + 0.2 * np.sin(2.9 * t)
    qd = 0.66 * np.cos(1.1 * t) + 0.58 * np.cos(2.9 * t)
    qdd = -0.726 * np.sin(1.1 * t) - 1.682 * np.sin(2.9 * t)
    tau = 0.5 * qdd + 0.4 * G * np.cos(q) + 0.1 * qd + 0.3 + 0.05 * rng.standard_normal(len(t))
    return {"t": t, "q": q, "qd": qd, "qdd": qdd, "tau": tau}


def test_the_offset_refit_is_the_least_squares_fit_with_an_angle_offset_and_widens_as_beyond_noise_says():
    data = hanging_swing(3)
    logs = jointid.fit_log(data, model="bias", cutoff=0, robust=False)
    choice, other, errors = logs.offset
    assert choice == "an angle offset in place of the torque bias"
    # The same rows fitted with g sin q in place of the constant: h = hypot(h_c, h_s) (numpy's own fit).
    X = np.column_stack([data["qdd"], G * np.cos(data["q"]), G * np.sin(data["q"]), data["qd"]])
    inertia, h_cos, h_sin, damping = np.linalg.lstsq(X, data["tau"], rcond=None)[0]
    names = logs.result.model.names
    expected = {"I": inertia, "h": math.hypot(h_cos, h_sin), "B": damping}
    for name, value in expected.items():
        assert other[names.index(name)] == pytest.approx(value, rel=1e-9)
    assert math.isnan(other[names.index("tau0")])
    # Each shared parameter widens by sqrt(move^2 - allowed) when the move is beyond 2 sqrt(allowed), allowed the
    # larger of the two noise variances' difference and the fit's own.
    widened = 0
    for name in expected:
        index = names.index(name)
        move = abs(other[index] - logs.params[name])
        noise = logs.noise_bse[name]
        allowed = max(noise**2, abs(errors[index] ** 2 - noise**2))
        extra = math.sqrt(move**2 - allowed) if move > 2 * math.sqrt(allowed) else 0.0
        assert logs.bse[name] == pytest.approx(math.hypot(noise, extra), rel=1e-9)
        widened += extra > 0
    assert widened  # the bias explained as an angle offset moves h and I far beyond their noise here
    assert "an angle offset in place of the torque bias" in logs.result.judgement.reason_of("h")


def test_a_widened_interval_is_the_same_student_t_on_the_widened_error():
    logs = jointid.fit_log(hanging_swing(3), model="bias", cutoff=0, robust=False)
    uncertainty = logs.result.uncertainty
    quantile = scipy.stats.t.ppf(0.975, uncertainty.interval_degrees_of_freedom)
    for name, (low, high) in logs.conf_int(0.05).items():
        assert (high - low) / 2 == pytest.approx(quantile * logs.bse[name], rel=1e-6)
        assert (low + high) / 2 == pytest.approx(logs.params[name], rel=1e-9)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_a_clean_synthetic_joint_keeps_its_noise_errors(seed):
    # The model holds the truth and nothing else moves it: every reported error is the noise's, every verdict too.
    # (The gate lets about 1 parameter in 20 through on such joints: benchmarks/verdict_study.py counts them.)
    logs = jointid.fit_log(coulomb_joint_log(seed))
    assert dict(logs.bse) == dict(logs.noise_bse)
    assert logs.result.judgement.verdicts == logs.result.judgement.noise_verdicts
    assert not logs.result.judgement.weakened



@needs_real_logs
def test_h_over_i_is_widened_by_the_choices_that_move_it_beyond_its_noise():
    """Energy shaping's h/I: the delta method's noise error, then each choice's largest move of the ratio (its
    sensitivity refits, the fit with the pushes kept in, the offset's refit), beyond 2 noise errors, adds
    sqrt(move^2 - noise^2) in quadrature, as for a parameter."""
    logs = jointid.fit_log(REAL_LOGS / "pendulum_energy_shaping.csv", zero="down")
    result = logs.result
    names = result.model.names
    inertia, gravity = names.index("I"), names.index("h")
    columns = [result.model.index_of("I"), result.model.index_of("h")]
    gradient = np.array([-result.estimate[gravity] / result.estimate[inertia] ** 2, 1 / result.estimate[inertia]])
    block = result.uncertainty.correlated_covariance[np.ix_(columns, columns)]
    noise = float(np.sqrt(gradient @ block @ gradient))

    def ratio(estimate):
        return estimate[gravity] / estimate[inertia]

    base = ratio(result.estimate)
    moves = {}
    for variant in logs.sensitivity.variants:
        moves.setdefault(variant.setting, []).append(abs(ratio(variant.estimate) - base))
    moves["robust"] = [abs(ratio(refits_of(logs)["--no-robust"].estimate) - base)]
    moves["offset"] = [abs(ratio(logs.offset[1]) - base)]
    extra = [math.sqrt(max(found) ** 2 - noise**2) for found in moves.values() if max(found) > 2 * noise]
    assert extra  # the pushes kept in move it 2.6 noise errors
    _, value, error = result.scale_ratio
    assert value == pytest.approx(base, rel=1e-12)
    assert error == pytest.approx(math.hypot(noise, math.sqrt(sum(value**2 for value in extra))), rel=1e-9)
    assert "(widened by the analysis choices too)" in logs.summary()
