"""Savitzky-Golay differentiation: coefficients, exactness, and the evidence for the defaults."""

import numpy as np
import pytest

from jointid.estimation.fit import fit_joint
from jointid.logs.derivatives import check_filter, choose_window, differentiate, savgol_coefficients
from jointid.model.terms import TRUE_PARAMETERS, predict_torque
from jointid.options import DEFAULT_ORDER
from jointid.samples import JointData
from jointid.synthetic.motions import TRAINING_MOTIONS, Motion, SineTerm
from jointid.synthetic.noise import torque_noise


@pytest.mark.parametrize("window, order", [(5, 2), (11, 3), (21, 4), (201, 4), (51, 5)])
@pytest.mark.parametrize("deriv", [1, 2])
@pytest.mark.parametrize("delta", [1.0, 1e-3, 0.25])
def test_coefficients_match_scipy(window, order, deriv, delta):
    signal = pytest.importorskip("scipy.signal")
    expected = signal.savgol_coeffs(window, order, deriv=deriv, delta=delta, use="dot")
    ours = savgol_coefficients(window, order, deriv, delta)
    scale = np.max(np.abs(expected))
    assert np.max(np.abs(ours - expected)) <= 1e-9 * scale


def test_differentiation_is_exact_for_polynomials_up_to_the_order():
    t = np.arange(400) * 0.01
    q = 0.3 - 1.2 * t + 0.7 * t**2 - 0.05 * t**3 + 0.004 * t**4
    qd_true = -1.2 + 1.4 * t - 0.15 * t**2 + 0.016 * t**3
    qdd_true = 1.4 - 0.3 * t + 0.048 * t**2
    qd, qdd = differentiate(q, 0.01, 21, 4)
    assert len(qd) == len(qdd) == 400 - 20
    np.testing.assert_allclose(qd, qd_true[10:-10], rtol=0, atol=1e-9)
    np.testing.assert_allclose(qdd, qdd_true[10:-10], rtol=0, atol=1e-7)


def test_a_quartic_is_not_exact_for_order_two():
    t = np.arange(200) * 0.01
    q = t**4
    _, qdd = differentiate(q, 0.01, 41, 2)
    assert np.max(np.abs(qdd - 12 * t[20:-20] ** 2)) > 1e-3  # the test above could fail


@pytest.mark.parametrize("window, order", [(4, 2), (1, 0), (2, 1), (5, 1), (5, 5), (7, 9)])
def test_bad_filters_are_refused(window, order):
    with pytest.raises(ValueError):
        check_filter(window, order)


def test_too_short_a_signal_is_refused():
    with pytest.raises(ValueError, match="at least 21"):
        differentiate(np.zeros(20), 0.01, 21, 4)


# The evidence for the defaults: 8 s at 1 kHz, angles quantised like an encoder.
RICHER = Motion(
    "richer",
    "Four-sine motion",
    (SineTerm(0.5, 1.3), SineTerm(0.25, 2.7, 1.0), SineTerm(0.08, 6.1, 0.3), SineTerm(0.03, 11.0, 2.0)),
)
"""A richer multi-sine with components up to 11 rad/s (1.75 Hz): curvature that biases short windows."""

RATE = 1000.0
DURATION = 8.0


def encoder_fit(motion: Motion, counts: int, noise: float, window: int, order: int) -> np.ndarray:
    """Fit I, h, B to an angle-only log: quantised q at 1 kHz, torque from the exact states plus noise."""
    t = np.arange(int(DURATION * RATE) + 1) / RATE
    states = motion.states(t)
    tau = predict_torque(states.q, states.qd, states.qdd) + torque_noise(noise, len(t), 7)
    step = 2 * np.pi / counts
    q = np.round(states.q / step) * step
    if window is None:  # the automatic choice, from the quantised angles alone
        window = choose_window(q, 1 / RATE, order).window
    qd, qdd = differentiate(q, 1 / RATE, window, order)
    keep = slice(window // 2, len(t) - window // 2)
    return fit_joint(JointData(t=t[keep], q=q[keep], qd=qd, qdd=qdd, tau=tau[keep])).estimate


def worst_relative_error(estimate: np.ndarray) -> float:
    """Largest |fitted/true - 1| over I, h, B."""
    return float(np.max(np.abs(estimate / TRUE_PARAMETERS - 1)))


@pytest.mark.parametrize("motion", [TRAINING_MOTIONS["rich"], RICHER], ids=["rich", "richer"])
@pytest.mark.parametrize("counts", [4096, 65536])
@pytest.mark.parametrize("noise, tolerance", [(0.0, 0.02), (0.2, 0.03)])
def test_defaults_recover_the_parameters_from_encoder_angles(motion, counts, noise, tolerance):
    """The automatic window and order 4: within 2 % without torque noise, 3 % with the lesson's 0.2 N m."""
    estimate = encoder_fit(motion, counts, noise, None, DEFAULT_ORDER)
    assert worst_relative_error(estimate) <= tolerance


def test_a_short_window_lets_12_bit_quantisation_through():
    """Window 51 (0.05 s) amplifies 4096-count steps into qdd noise that biases I by more than 10 %."""
    estimate = encoder_fit(TRAINING_MOTIONS["rich"], 4096, 0.0, 51, DEFAULT_ORDER)
    assert worst_relative_error(estimate) > 0.10


def test_a_low_order_over_a_long_window_flattens_the_faster_sines():
    """Order 2 over 0.4 s underestimates the 11 rad/s term's acceleration: more than 10 % off."""
    estimate = encoder_fit(RICHER, 65536, 0.0, 401, 2)
    assert worst_relative_error(estimate) > 0.10


def test_order_two_at_the_default_window_is_worse_than_the_default_on_the_richer_motion():
    t = np.arange(int(DURATION * RATE) + 1) / RATE
    step = 2 * np.pi / 4096
    window = choose_window(np.round(RICHER.states(t).q / step) * step, 1 / RATE, DEFAULT_ORDER).window
    default = worst_relative_error(encoder_fit(RICHER, 4096, 0.0, window, DEFAULT_ORDER))
    lower = worst_relative_error(encoder_fit(RICHER, 4096, 0.0, window, 2))
    assert lower > 0.04 and default < lower / 10
