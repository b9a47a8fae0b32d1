"""Fit [I, h, B] to joint data and judge the fit on held-out data."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .dataset import JointData, rms
from .model import PARAMETER_LABELS, PARAMETER_NAMES, PARAMETER_UNITS, SIGN_REQUIREMENTS, sign_failures
from .solver import LeastSquaresSolution, solve_least_squares


@dataclass(frozen=True, eq=False)
class FitResult:
    """Everything one identification yields: the fit, its errors and its status sentence."""

    training: JointData
    """The data the parameters were fitted to (torques as measured)."""
    heldout: JointData | None
    """Data the fit never saw, or None."""
    heldout_is_noiseless: bool
    """True when held-out torques are exact truth (synthetic), False when measured."""
    solution: LeastSquaresSolution
    """The pivoted QR factorisation and rank of the training regressor."""
    noise_bound: float | None = None
    """Known bound b of uniform torque noise on [-b, b] (synthetic data), else None."""

    @property
    def rank(self) -> int:
        """Numerical rank of the training regressor."""
        return self.solution.rank

    @property
    def parameter_count(self) -> int:
        """Number of fitted parameters (3)."""
        return self.solution.column_count

    @property
    def estimate(self) -> np.ndarray | None:
        """(3,) Fitted [I, h, B], or None when the rank is deficient."""
        return self.solution.estimate

    @cached_property
    def training_predictions(self) -> np.ndarray | None:
        """(N,) Fitted torque at the training states, or None without a unique fit."""
        return None if self.estimate is None else self.training.regressor @ self.estimate

    @cached_property
    def heldout_predictions(self) -> np.ndarray | None:
        """(M,) Fitted torque at the held-out states, or None."""
        if self.estimate is None or self.heldout is None:
            return None
        return self.heldout.regressor @ self.estimate

    @cached_property
    def training_rmse(self) -> float | None:
        """RMS of (fitted - measured) training torque (N m), or None without a unique fit."""
        if self.training_predictions is None:
            return None
        return rms(self.training_predictions - self.training.tau)

    @cached_property
    def heldout_rmse(self) -> float | None:
        """RMS of (fitted - held-out) torque (N m), or None."""
        if self.heldout_predictions is None:
            return None
        return rms(self.heldout_predictions - self.heldout.tau)

    @property
    def accel_rms(self) -> float:
        """RMS training acceleration (rad/s^2)."""
        return self.training.accel_rms

    @property
    def speed_rms(self) -> float:
        """RMS training speed (rad/s)."""
        return self.training.speed_rms

    @cached_property
    def sign_failures(self) -> tuple[str, ...]:
        """Names of fitted parameters that break I > 0, h >= 0, B >= 0 (never clipped)."""
        return () if self.estimate is None else sign_failures(self.estimate)

    @cached_property
    def message(self) -> str:
        """The status sentence the lab shows under its readouts."""
        rank, total = self.rank, self.parameter_count
        if self.estimate is None:
            return (
                f"Rank {rank} of {total}: no unique least-squares fit. "
                "Parameter and prediction readouts are unavailable."
            )
        parts = [f"Rank {rank} of {total}: a unique least-squares fit."]
        if self.heldout_rmse is None:
            parts.append("No held-out data, so predictions are untested.")
        else:
            parts.append(f"Held-out torque RMSE is {format_number(self.heldout_rmse)} N m.")
        for name in self.sign_failures:
            value = self.estimate[PARAMETER_NAMES.index(name)]
            parts.append(
                f"Fitted {PARAMETER_LABELS[name]} {format_number(value)} {PARAMETER_UNITS[name]} "
                f"fails this joint model's requirement {SIGN_REQUIREMENTS[name]}."
            )
        if not self.sign_failures:
            parts.append("Positive parameter signs alone do not establish an accurate physical model.")
        return " ".join(parts)


def format_number(value: float, decimals: int = 6) -> str:
    """Fixed-point text with `decimals` places and no negative zero."""
    text = f"{value:.{decimals}f}"
    return text[1:] if text.startswith("-") and float(text) == 0 else text


def fit_joint(
    training: JointData,
    heldout: JointData | None = None,
    *,
    heldout_is_noiseless: bool = False,
    noise_bound: float | None = None,
) -> FitResult:
    """Fit [I, h, B] to the training data by pivoted QR and evaluate on the held-out data."""
    solution = solve_least_squares(training.regressor, training.tau)
    return FitResult(
        training=training,
        heldout=heldout,
        heldout_is_noiseless=heldout_is_noiseless,
        solution=solution,
        noise_bound=noise_bound,
    )
