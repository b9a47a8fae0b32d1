"""Derivatives from angles: Savitzky-Golay coefficients, smoothing then central differences, and the evidence
for the defaults."""

import numpy as np
import pytest

from jointid.logs.derivatives import check_filter, differentiate, savgol_coefficients
from jointid.model.terms import TRUE_PARAMETERS, predict_torque
from jointid.studies.log_fit import fit_log
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


def test_smoothing_then_central_differences_is_exact_for_quadratics_to_the_ends():
    t = np.arange(400) * 0.01
    q = 0.3 - 1.2 * t + 0.7 * t**2
    qd, qdd = differentiate(q, 0.01, 21, 3)
    assert len(qd) == len(qdd) == 400  # nothing trimmed
    np.testing.assert_allclose(qd[1:-1], (-1.2 + 1.4 * t)[1:-1], rtol=0, atol=1e-9)
    np.testing.assert_allclose(qdd[2:-2], 1.4, rtol=0, atol=1e-7)


def test_a_sine_well_inside_the_smoothing_band_keeps_its_acceleration():
    """2 rad/s sampled at 1 kHz, window 101 (-3 dB near 12 Hz): qdd within 0.1 % of -4 sin 2t away from the ends."""
    t = np.arange(4000) / 1000
    _, qdd = differentiate(np.sin(2 * t), 1e-3, 101, 3)
    middle = slice(100, -100)
    assert np.max(np.abs(qdd[middle] + 4 * np.sin(2 * t[middle]))) < 4e-3


def test_a_long_window_flattens_a_fast_sine():
    """The same check fails when the smoothing's band is below the motion: the test above could fail."""
    t = np.arange(4000) / 1000
    _, qdd = differentiate(np.sin(20 * t), 1e-3, 801, 3)
    assert np.max(np.abs(qdd[800:-800] + 400 * np.sin(20 * t[800:-800]))) > 40


@pytest.mark.parametrize("window, order", [(4, 2), (1, 0), (2, 1), (5, 1), (5, 5), (7, 9)])
def test_bad_filters_are_refused(window, order):
    with pytest.raises(ValueError):
        check_filter(window, order)


def test_too_short_a_signal_is_refused():
    with pytest.raises(ValueError, match="at least 21"):
        differentiate(np.zeros(20), 0.01, 21, 4)


# The evidence for the defaults: 8 s at 1 kHz, angles quantised like an encoder, fitted as a log.
RICHER = Motion(
    "richer",
    "Four-sine motion",
    (SineTerm(0.5, 1.3), SineTerm(0.25, 2.7, 1.0), SineTerm(0.08, 6.1, 0.3), SineTerm(0.03, 11.0, 2.0)),
)
"""A richer multi-sine with components up to 11 rad/s (1.75 Hz)."""

RATE = 1000.0
DURATION = 8.0


def encoder_fit(motion: Motion, counts: int, noise: float, window: int | None) -> np.ndarray:
    """I, h, B of an angle-only log (quantised q at 1 kHz, torque from the exact states plus noise) fitted as
    `jointid fit --csv --model plain` would."""
    t = np.arange(int(DURATION * RATE) + 1) / RATE
    states = motion.states(t)
    tau = predict_torque(states.q, states.qd, states.qdd) + torque_noise(noise, len(t), 7)
    step = 2 * np.pi / counts
    q = np.round(states.q / step) * step
    logs = fit_log({"t": t, "q": q, "tau": tau}, model="plain", window=window, sensitivity=False)
    return np.array(list(logs.params.values()))


def worst_relative_error(estimate: np.ndarray) -> float:
    """Largest |fitted/true - 1| over I, h, B."""
    return float(np.max(np.abs(estimate / TRUE_PARAMETERS - 1)))


@pytest.mark.parametrize("motion", [TRAINING_MOTIONS["rich"], RICHER], ids=["rich", "richer"])
@pytest.mark.parametrize("counts", [4096, 65536])
@pytest.mark.parametrize("noise, tolerance", [(0.0, 0.02), (0.2, 0.03)])
def test_defaults_recover_the_parameters_from_encoder_angles(motion, counts, noise, tolerance):
    """The automatic window and order: within 2 % without torque noise, 3 % with the lesson's 0.2 N m."""
    assert worst_relative_error(encoder_fit(motion, counts, noise, None)) <= tolerance


@pytest.mark.parametrize("angle", [np.pi / 2, 1.0, 123.456, 6283.0])
@pytest.mark.parametrize("step, window", [(0.01, 7), (1e-3, 329), (1e-4, 4001)])
def test_a_constant_angle_has_exactly_zero_derivatives(angle, step, window):
    """Smoothing and differencing a constant leaves rounding of eps |q| / dt^k, which a fit would scale up into a
    parameter; the joint did not move, so both are zero."""
    qd, qdd = differentiate(np.full(5000, angle), step, window, 3)
    assert not qd.any() and not qdd.any()


def test_a_motion_double_precision_resolves_keeps_its_derivatives():
    """A swing of 1e-7 rad about pi/2 at 1 kHz is far above rounding (eps pi/2 is 3.5e-16): kept, and the
    analytic derivatives come back."""
    t = np.arange(20000) * 1e-3
    q = np.pi / 2 + 1e-7 * np.sin(1.3 * t)
    qd, qdd = differentiate(q, 1e-3, 101, 3)
    inner = slice(200, -200)
    np.testing.assert_allclose(qd[inner], 1.3e-7 * np.cos(1.3 * t[inner]), rtol=0, atol=2e-10)
    np.testing.assert_allclose(qdd[inner], -1.69e-7 * np.sin(1.3 * t[inner]), rtol=0, atol=2e-8)


def test_a_speed_at_the_level_of_rounding_is_zero_so_its_sign_is_not_a_cpus_choice():
    """A pendulum at rest between two swings: the smoothed, differentiated angle is zero up to rounding there, and
    the sign of such a speed (Coulomb friction's column) changed with the CPU's kernels and moved the real
    energy-shaping run's Fc by 5e-6 of its value; it is now exactly zero on every CPU."""
    step = 0.005
    t = np.arange(1200) * step
    swing = np.clip(np.sin(np.pi * (t - 2.0) / 2.0), 0.0, None) * ((t > 2.0) & (t < 4.0))
    q = 0.3 + 0.5 * swing  # at rest at 0.3 rad before 2 s and after 4 s
    velocity, _ = differentiate(q, step, 25, 3)
    rest = (t < 1.8) | (t > 4.2)
    reference = np.gradient(np.gradient(q, step), step)  # a closed-form check that the rest is a rest
    assert np.all(reference[rest] == 0)
    assert np.all(velocity[rest] == 0) and np.all(np.sign(velocity[rest]) == 0)
    assert np.max(np.abs(velocity)) > 0.1  # the swing keeps its speed
