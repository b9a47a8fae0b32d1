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
from math import factorial

import numpy as np

from .choices import DEFAULT_ORDER, DEFAULT_WINDOW, MAX_ORDER, MAX_WINDOW  # noqa: F401  (also this module's API)

METHOD = "savitzky-golay"
"""Name of the differentiation method, as results and JSON record it."""

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

    def to_dict(self) -> dict:
        """Plain JSON-ready values."""
        return {
            "method": self.method,
            "window": self.window,
            "order": self.order,
            "step": self.step,
            "trimmed_samples": self.trimmed,
            "estimated": list(self.estimated),
        }

    @property
    def description(self) -> str:
        """One sentence for a person, e.g. in a note under the readouts."""
        names = " and ".join(self.estimated)
        return (
            f"{names} estimated from q by Savitzky-Golay differentiation "
            f"(window {self.window} samples spanning {(self.window - 1) * self.step:.6g} s, order {self.order}); "
            f"{self.trimmed} edge samples trimmed."
        )


class FilterSettingError(ValueError):
    """A window or order the differentiator cannot use; `field` names which, `problem` says why."""

    def __init__(self, field: str, problem: str):
        super().__init__(f"{field} {problem}")
        self.field = field
        self.problem = problem


def check_filter(window: int, order: int) -> None:
    """Raise FilterSettingError unless `window` is odd, 3 to MAX_WINDOW, and 2 <= `order` < `window`, <= MAX_ORDER."""
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
