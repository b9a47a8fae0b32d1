"""Velocity and acceleration from sampled angles: Savitzky-Golay smoothing of q, then central differences.

The angle is smoothed by a Savitzky-Golay filter (a polynomial of degree
`order` fitted to the `window` samples around each instant, taken at the
centre), whose -3 dB point is put at three times the low-pass's cutoff, so it
is flat where the later low-pass passes; then differentiated twice by central
differences. Smoothing first removes the sample-to-sample noise of a
quantised angle (one count at 500 Hz is about 700 rad/s^2 twice
differenced) without shaping qdd differently from the torque in the band the
fit uses; a Savitzky-Golay differentiator of a window as short does not stay
that flat. At the ends the polynomial fitted to the first (last) window is
used, so no sample is trimmed: a 4 s log keeps all of its 4 s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from math import factorial

import numpy as np

from ..estimation.low_pass import correlated
from ..options import MAX_ORDER, MAX_WINDOW

METHOD = "savitzky-golay smoothing, central differences"
"""Name of the differentiation method, as results and JSON record it."""

SMOOTHING_MULTIPLE = 3.0
"""The automatic smoothing window puts its -3 dB point at this many times the low-pass's cutoff."""


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
            "cutoff_hz": None if self.choice is None else self.choice.cutoff,
        }

    @property
    def description(self) -> str:
        """One sentence for a person, e.g. in a note under the readouts."""
        names = " and ".join(self.estimated)
        why = "window given" if self.choice is None else self.choice.reason
        return (
            f"{names} estimated from q smoothed by Savitzky-Golay "
            f"(window {self.window} samples spanning {(self.window - 1) * self.step:.6g} s, order {self.order}; "
            f"{why}), then central differences; no sample trimmed."
        )


@dataclass(frozen=True, eq=False)
class WindowChoice:
    """An automatic window: the cutoff it follows and the sentence that says why."""

    window: int
    """Samples (odd)."""
    cutoff: float
    """The low-pass cutoff (Hz) the window follows."""
    reason: str
    """Why, for the note."""
    automatic: tuple[float, str] | None = None
    """The automatic cutoff (Hz) and its reason when the window followed it, so the fit's low-pass need not
    compute it again; None when the cutoff was given."""


def smoothing_window(step: float, cutoff: float, order: int, count: int,
                     automatic: tuple[float, str] | None = None) -> WindowChoice:
    """The automatic window: its smoothing's -3 dB point at SMOOTHING_MULTIPLE x `cutoff` (Schafer 2011:
    f_3dB / (rate / 2) is about (order + 1) / (3.2 M - 4.6) for a window of 2M + 1), odd, more than `order` + 1
    samples and at most MAX_WINDOW and the log's length."""
    corner = SMOOTHING_MULTIPLE * cutoff
    half = math.ceil(((order + 1) / (2 * corner * step) + 4.6) / 3.2)  # f_3dB as a share of the Nyquist frequency
    window = 2 * half + 1
    limits = []
    most = min(MAX_WINDOW, count if count % 2 else count - 1)
    if window > most:
        window, limits = most, [f"cut to {most} samples"]
    least = order + 2 if order % 2 else order + 3
    if window < least:
        window, limits = least, [f"raised to {least} samples, more than order + 1"]
    why = f"automatic: its -3 dB point near {SMOOTHING_MULTIPLE:g} x the cutoff {cutoff:.3g} Hz"
    return WindowChoice(window, cutoff, why + "".join(", " + limit for limit in limits), automatic)


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


def smooth(values: np.ndarray, window: int, order: int) -> np.ndarray:
    """(N,) Savitzky-Golay smoothing of (N,) values; at the ends the polynomial fitted to the first (last) window.

    Linear in the values, so smoothing torque and columns alike keeps their equation.
    """
    values = np.asarray(values, dtype=float)
    count, half = len(values), window // 2
    if count < window:
        raise ValueError(f"need at least {window} samples for a window of {window}; got {count}")
    weights = savgol_coefficients(window, order, 0)
    out = np.empty(count)
    if window <= 64:
        out[half: count - half] = np.correlate(values, weights, mode="valid")
    else:  # long windows by FFT: N log N rather than N x window
        out[half: count - half] = correlated(values, weights)
    offsets = np.arange(window, dtype=float)
    out[:half] = np.polyval(np.polyfit(offsets, values[:window], order), offsets[:half])
    out[count - half:] = np.polyval(np.polyfit(offsets, values[-window:], order), offsets[window - half:])
    return out


ROUNDING_FLOOR = 64 * np.finfo(float).eps
"""An estimated derivative whose largest value is below this times max|q| / dt (per derivative) is rounding: a
constant angle gives 1 to 5 times eps max|q| / dt^k, and any motion double precision resolves gives more."""


def differentiate(q: np.ndarray, step: float, window: int, order: int) -> tuple[np.ndarray, np.ndarray]:
    """Velocity and acceleration, each (N,): q smoothed (see `smooth`), then central differences (one-sided at
    the two ends); a derivative at the level of q's rounding is exactly zero (the joint did not move)."""
    velocity = np.gradient(smooth(q, window, order), step)
    acceleration = np.gradient(velocity, step)
    # Rounding noise scaled by 1/dt would otherwise be a column the fit scales up into a 'determined' parameter.
    floor = ROUNDING_FLOOR * float(np.max(np.abs(q))) if len(q) else 0.0
    if not np.max(np.abs(velocity), initial=0.0) > floor / step:
        velocity = np.zeros_like(velocity)
    # A speed at the level of rounding has no sign (Coulomb friction's column is sign qd): zero, on every CPU.
    velocity[np.abs(velocity) <= floor / step] = 0.0
    if not np.max(np.abs(acceleration), initial=0.0) > floor / step / step:
        acceleration = np.zeros_like(acceleration)
    return velocity, acceleration
