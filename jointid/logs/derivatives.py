"""Velocity and acceleration from sampled angles by Savitzky-Golay differentiation.

A Savitzky-Golay differentiator fits a polynomial of degree `order` to the
`window` samples around each instant by least squares and differentiates the
polynomial at the centre. Averaging over the window suppresses encoder
quantisation noise, which plain finite differences amplify by 1/dt^2. The
first and last (window - 1)/2 samples have no centred window: they are trimmed,
not extrapolated, so every kept estimate comes from the same filter.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from math import factorial

import numpy as np

from ..options import MAX_ORDER, MAX_WINDOW

METHOD = "savitzky-golay"
"""Name of the differentiation method, as results and JSON record it."""

BANDWIDTH_POWER = 0.999
"""The motion's bandwidth is the frequency below which this share of the (detrended) angle's power lies."""

PASSBAND_ERROR = 0.005
"""Longest useful span: the one whose filter passes the bandwidth's acceleration within this share (0.45
periods of it for order 4, 0.9 for order 6), and slower components better."""

NOISE_SHARE = 0.05
"""Shortest useful span: the one whose acceleration noise (from q's noise) is this share of the
acceleration's RMS, so errors in qdd bias the inertia by about its square (0.25 %)."""


FALLBACK_SPAN = 0.2
"""Window span (s) when the angle has no motion to measure a bandwidth on (a hold): 201 samples at 1 kHz."""

MAX_SPAN_SHARE = 0.25
"""An automatic window spans at most this share of the log, so trimming leaves most of it to fit."""


@dataclass(frozen=True, eq=False)
class DerivativeEstimate:
    """Which derivatives a log lacked and how they were estimated."""

    method: str
    """Always METHOD."""
    window: int
    """Samples in each centred window (odd)."""
    order: int
    """Degree of the fitted polynomial."""
    step: float
    """Sample interval dt (s), the median of the log's time steps."""
    trimmed: int
    """Samples dropped at the two ends, window - 1 in all."""
    estimated: tuple[str, ...]
    """Columns that were estimated, a subset of ("qd", "qdd")."""

    choice: WindowChoice | None = None
    """Why this window: the automatic choice from the motion's bandwidth, or None when it was given."""

    def to_dict(self) -> dict:
        """Plain JSON-ready values."""
        return {
            "method": self.method,
            "window": self.window,
            "order": self.order,
            "step": self.step,
            "trimmed_samples": self.trimmed,
            "estimated": list(self.estimated),
            "window_chosen": "given" if self.choice is None else "automatic",
            "bandwidth_hz": None if self.choice is None else self.choice.bandwidth,
        }

    @property
    def short_description(self) -> str:
        """A few words for a narrow status line."""
        how = "given" if self.choice is None else "automatic"
        return (f"{' and '.join(self.estimated)} by Savitzky-Golay, window {self.window} "
                f"({(self.window - 1) * self.step:.3g} s, {how}), order {self.order}")

    @property
    def description(self) -> str:
        """One sentence for a person, e.g. in a note under the readouts."""
        names = " and ".join(self.estimated)
        why = "window given" if self.choice is None else self.choice.reason
        return (
            f"{names} estimated from q by Savitzky-Golay differentiation "
            f"(window {self.window} samples spanning {(self.window - 1) * self.step:.6g} s, order {self.order}; "
            f"{why}); {self.trimmed} edge samples trimmed."
        )


@dataclass(frozen=True, eq=False)
class WindowChoice:
    """An automatic window: what it was chosen from and the sentence that says why."""

    window: int
    """Samples (odd)."""
    bandwidth: float | None
    """The angle's bandwidth (Hz), or None when it had no motion to measure."""
    reason: str
    """Why, for the note."""


@dataclass(frozen=True)
class MotionSpectrum:
    """What the angle's spectrum shows: bandwidth, the acceleration's RMS within it, and q's noise."""

    bandwidth: float
    """Hz below which BANDWIDTH_POWER of the detrended angle's power lies."""
    acceleration_rms: float
    """RMS of the acceleration the band implies (rad/s^2)."""
    noise: float
    """Standard deviation of q's white noise (rad), from its fourth differences: quantisation included."""


def motion_spectrum(q: np.ndarray, step: float) -> MotionSpectrum | None:
    """The bandwidth, band acceleration RMS and noise of angles q sampled every `step` s; None without motion.

    The straight line through q is removed first (a constant speed has no
    acceleration), and a Hann window keeps the log's ends from spreading power
    upward; its leakage only widens the band (so shortens the window: the safe
    side). The noise comes from fourth differences, where smooth motion
    vanishes (as step^4 times the fourth derivative) and white noise has
    variance 70 sigma^2.
    """
    spectrum = _angle_spectrum(q, with_mean_square=True)
    if spectrum is None:
        return None
    scale, mean_square, power, index = spectrum
    size = 2 * (len(power) - 1)
    band = slice(0, index + 1)
    # In cycles per sample first, so that a step like 1e-300 s cannot overflow the fourth power.
    cycles = np.fft.rfftfreq(size)[band]
    share = np.sum((2 * np.pi * cycles) ** 4 * power[band]) / power.sum()
    with np.errstate(over="ignore", under="ignore"):  # an inf acceleration just asks for the shortest window
        acceleration_rms = float(np.sqrt(mean_square * share) * scale / step / step)
        noise = float(np.sqrt(np.mean(np.diff(np.asarray(q, dtype=float) / scale, 4) ** 2) / 70.0) * scale)
    return MotionSpectrum(_frequency(index, size, step), acceleration_rms, noise)


def motion_bandwidth(q: np.ndarray, step: float) -> float | None:
    """Frequency (Hz) below which BANDWIDTH_POWER of the detrended angle's power lies, or None without motion.

    The same as motion_spectrum(q, step).bandwidth, without the acceleration and noise figures.
    """
    spectrum = _angle_spectrum(q)
    return None if spectrum is None else _frequency(spectrum[-1], 2 * (len(spectrum[-2]) - 1), step)


def _angle_spectrum(q: np.ndarray, with_mean_square: bool = False
                    ) -> tuple[float, float | None, np.ndarray, np.ndarray, int] | None:
    """(scale, mean square of the detrended q / scale when asked, the Hann-windowed power spectrum of that, the
    band's last bin), or None without motion (see motion_spectrum).

    Worked in place where it can: a million samples then peak at about three of their own size in temporaries.
    """
    q = np.asarray(q, dtype=float)
    count = len(q)
    if count < 8:
        return None
    scale = float(np.max(np.abs(q)))
    if not np.isfinite(scale) or scale == 0:
        return None
    detrended = q / scale  # squares of angles like 1e200 or 1e-200 stay in range; scaled back by the callers
    # The least-squares line in closed form (np.polyfit took 0.11 s on a million samples); x is 0 .. count-1.
    line = np.arange(count, dtype=float)
    line -= (count - 1) / 2.0
    slope = float(np.dot(line, detrended)) / (count * (count * count - 1.0) / 12.0)
    line *= slope
    line += float(np.mean(detrended))
    detrended -= line
    del line
    mean_square = float(np.mean(detrended**2)) if with_mean_square else None
    detrended *= _hann(count)
    # Zero-padded to a power of two: the same spectrum, finer, and fast (a million and one samples, 101 x 9901,
    # took 0.26 s unpadded).
    size = 1 << int(np.ceil(np.log2(count)))
    power = np.abs(np.fft.rfft(detrended, size))
    del detrended
    power *= power
    power[0] = 0.0
    total = power.sum()
    if not np.isfinite(total) or total <= 0:
        return None
    cumulative = np.cumsum(power)
    cumulative /= total
    index = min(int(np.searchsorted(cumulative, BANDWIDTH_POWER)), len(power) - 1)
    return scale, mean_square, power, index


def _hann(count: int) -> np.ndarray:
    """np.hanning(count), computed for its first half and mirrored (it is symmetric): half the cosines."""
    half = (count + 1) // 2
    window = np.empty(count)
    window[:half] = 0.5 + 0.5 * np.cos(np.pi * np.arange(1 - count, 2 * half - count, 2) / (count - 1))
    window[half:] = window[: count - half][::-1]
    return window


def _frequency(index: int, size: int, step: float) -> float:
    """Hz of bin `index` of a `size`-point real FFT of samples `step` s apart."""
    with np.errstate(over="ignore"):  # a denormal step: an infinite bandwidth, which asks for the shortest window
        return float(np.fft.rfftfreq(size, step)[index])


@lru_cache(maxsize=None)
def order_constants(order: int) -> tuple[float, float]:
    """(noise gain, longest periods) of an order-`order` second-derivative Savitzky-Golay filter.

    Its n-sample filter multiplies white noise by about gain / n^2.5 / step^2
    (94 for order 4, 212 for order 6, measured at n = 61), so the acceleration
    noise is gain sigma_q sqrt(step) / span^2.5; and it passes a sine within
    PASSBAND_ERROR up to a span of `periods` of the sine's period.
    """
    samples = 61 if order < 30 else 2 * order + 1
    noise_gain = float(np.sqrt(np.sum(savgol_coefficients(samples, order, 2) ** 2)) * samples**2.5)
    wide = 401
    half = wide // 2
    offsets = np.arange(-half, half + 1) / (wide - 1)  # the span is 1
    weights = savgol_coefficients(wide, order, 2, 1 / (wide - 1))
    periods = 0.05
    while periods < 5:
        w = 2 * np.pi * (periods + 0.01)
        if 1 - np.sum(weights * np.cos(w * offsets)) / -(w * w) > PASSBAND_ERROR:
            break
        periods += 0.01
    return noise_gain, periods


def choose_window(q: np.ndarray, step: float, order: int) -> WindowChoice:
    """The automatic window for angles q sampled every `step` s, from the motion's bandwidth and q's noise.

    Between the shortest span whose acceleration noise stays under NOISE_SHARE
    of the acceleration and the longest that passes the bandwidth within 0.5 %
    (LONGEST_PERIODS), the window takes their geometric mean: halving or
    doubling it (the sensitivity check) then stays inside that range whenever
    the range spans a factor of four. Clamped to at least order + 3 samples,
    at most MAX_WINDOW and MAX_SPAN_SHARE of the log; odd.
    """
    spectrum = motion_spectrum(q, step)
    if spectrum is None or spectrum.bandwidth <= 0 or spectrum.acceleration_rms <= 0:
        bandwidth = None
        span, why = FALLBACK_SPAN, f"automatic: {FALLBACK_SPAN:g} s, as q shows no motion to measure"
    else:
        bandwidth = spectrum.bandwidth
        noise_gain, periods = order_constants(order)
        longest = periods / bandwidth
        shortest = (noise_gain * spectrum.noise * np.sqrt(step) / (NOISE_SHARE * spectrum.acceleration_rms)) ** 0.4
        span = float(np.sqrt(shortest * longest))
        why = (f"automatic: geometric mean of {shortest:.3g} s, where q's noise ({spectrum.noise:.2g} rad) makes "
               f"{NOISE_SHARE:.0%} of the acceleration, and {longest:.3g} s, {periods:.2g} periods of the "
               f"motion's bandwidth {bandwidth:.3g} Hz")
    samples = int(round(span / step)) + 1
    limits = []
    most = min(MAX_WINDOW, int(MAX_SPAN_SHARE * len(q)))
    if samples > most:
        samples = most
        limits.append("cut to a quarter of the log" if most < MAX_WINDOW else f"cut to {MAX_WINDOW} samples")
    least = order + 3
    if samples < least:
        samples = least
        limits.append(f"raised to order + 3 = {least} samples")
    window = samples if samples % 2 else samples + 1
    if window > most:
        window -= 2
    window = max(window, least if least % 2 else least + 1)
    if limits:
        why += ", " + " and ".join(limits)
    return WindowChoice(window, bandwidth, why)


class FilterSettingError(ValueError):
    """A window or order the differentiator cannot use; `field` names which, `problem` says why."""

    def __init__(self, field: str, problem: str):
        super().__init__(f"{field} {problem}")
        self.field = field
        self.problem = problem


def check_filter(window: int | None, order: int) -> None:
    """Raise FilterSettingError unless `window` is odd, 3 to MAX_WINDOW, and 2 <= `order` < `window`, <= MAX_ORDER.

    A window of None (automatic) checks the order alone; the window chosen later always exceeds it.
    """
    if window is None:
        if not 2 <= order <= MAX_ORDER:
            raise FilterSettingError(
                "order", f"must be at least 2 (for acceleration) and at most {MAX_ORDER}; got {order}"
            )
        return
    if window < 3 or window % 2 == 0:
        raise FilterSettingError("window", f"must be an odd number of samples, at least 3; got {window}")
    if window > MAX_WINDOW:
        raise FilterSettingError(
            "window",
            f"must be at most {MAX_WINDOW} samples (wider costs time and smooths away the motion); got {window}",
        )
    if not 2 <= order < window:
        raise FilterSettingError(
            "order", f"must be less than the window {window} and at least 2 (for acceleration); got {order}"
        )
    if order > MAX_ORDER:
        raise FilterSettingError(
            "order", f"must be at most {MAX_ORDER} (higher orders follow the noise and cost time); got {order}"
        )


def savgol_coefficients(window: int, order: int, deriv: int, delta: float = 1.0) -> np.ndarray:
    """(window,) Weights w with sum(w * y[window]) = the deriv-th derivative at the window's centre."""
    check_filter(window, order)
    half = window // 2
    # Offsets scaled to [-1, 1] keep the Vandermonde matrix well conditioned.
    offsets = np.arange(-half, half + 1) / half
    vandermonde = np.vander(offsets, order + 1, increasing=True)
    fit = np.linalg.pinv(vandermonde)  # row j maps window samples to the x^j coefficient
    return fit[deriv] * factorial(deriv) / (half * delta) ** deriv


def differentiate(q: np.ndarray, step: float, window: int, order: int) -> tuple[np.ndarray, np.ndarray]:
    """Velocity and acceleration, each (N - window + 1,), at the samples window//2 .. N-1-window//2."""
    q = np.asarray(q, dtype=float)
    if len(q) < window:
        raise ValueError(f"need at least {window} samples for a window of {window}; got {len(q)}")
    velocity = np.correlate(q, savgol_coefficients(window, order, 1, step), mode="valid")
    acceleration = np.correlate(q, savgol_coefficients(window, order, 2, step), mode="valid")
    return velocity, acceleration
