"""Fit [I, h, B] to joint data and judge the fit on held-out data."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .dataset import JointData, rms
from .model import PARAMETER_LABELS, PARAMETER_NAMES, PARAMETER_UNITS, SIGN_REQUIREMENTS, sign_failures
from .identifiable import IdentifiableSubset, identifiable_subset
from .solver import LeastSquaresSolution, solve_least_squares
from .uncertainty import NOT_DETERMINED, WEAK, WELL_DETERMINED, ParameterUncertainty, parameter_uncertainty

ZERO_COLUMN_REASONS = {"I": "no acceleration", "h": "no gravity torque", "B": "no velocity"}
"""Why a parameter cannot be seen when its regressor column is zero in every sample."""

MODEST_CONDITION = 100.0
"""Below this a condition number looks harmless, which is when it most needs its caveat."""
LARGE_CONDITION = 1e6
"""Above this the columns are so nearly dependent that rounding alone disturbs the fit."""


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
        return None if self.estimate is None else fitted_torque(self.training.regressor, self.estimate)

    @cached_property
    def heldout_predictions(self) -> np.ndarray | None:
        """(M,) Fitted torque at the held-out states, or None."""
        if self.estimate is None or self.heldout is None:
            return None
        return fitted_torque(self.heldout.regressor, self.estimate)

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
    def uncertainty(self) -> ParameterUncertainty | None:
        """Standard errors, intervals and verdicts per parameter, or None without a unique fit."""
        return parameter_uncertainty(self.solution, self.noise_bound)

    @cached_property
    def identifiable(self) -> IdentifiableSubset:
        """The parameters the training data determine on their own, at any rank."""
        return identifiable_subset(self.solution, PARAMETER_NAMES)

    @property
    def condition_number(self) -> float:
        """Condition number of the column-scaled training regressor (inf when rank-deficient)."""
        return self.solution.condition_number

    @cached_property
    def accuracy_sentences(self) -> tuple[str, ...]:
        """Plain sentences on what the fit does not determine; the status sentence ends with them."""
        if self.estimate is None:
            return self._subset_sentences()
        uncertainty = self.uncertainty
        sentences = []
        if uncertainty.std_error is None:
            sentences.append(
                f"With {self.training.count} samples and {self.parameter_count} parameters there are "
                "no residual degrees of freedom, so standard errors cannot be estimated from the residuals."
            )
        if uncertainty.verdicts is None:
            return tuple(sentences)
        judged = dict(zip(PARAMETER_NAMES, uncertainty.verdicts))
        errors = dict(zip(PARAMETER_NAMES, uncertainty.verdict_std_error))
        basis = uncertainty.verdict_basis

        def listing(verdict: str) -> tuple[str, str] | None:
            names = [name for name in PARAMETER_NAMES if judged[name] == verdict]
            if not names:
                return None
            values = ", ".join(f"{name} {format_number(errors[name])}" for name in names)
            plural = "s" if len(names) > 1 else ""
            return (
                f"{_join([PARAMETER_LABELS[name] for name in names])} {'are' if plural else 'is'}",
                f"({basis} standard error{plural} {values})",
            )

        if failed := listing(NOT_DETERMINED):
            subject, detail = failed
            sentences.append(f"A unique fit is not an accurate one here: {subject} not determined {detail}.")
        if weak := listing(WEAK):
            subject, detail = weak
            sentences.append(f"{_capitalise(subject)} only weakly determined {detail}.")
        return tuple(sentences)

    def _subset_sentences(self) -> tuple[str, ...]:
        """What a rank-deficient fit still determines, and why the rest is free."""
        subset = self.identifiable
        sentences = []
        if subset.values:
            known = _join(
                [
                    f"the {PARAMETER_LABELS[name]} {name} = {format_number(value)} {PARAMETER_UNITS[name]}"
                    for name, value in subset.values.items()
                ]
            )
            own = "its" if len(subset.values) == 1 else "their"
            sentences.append(f"The data still determine {known} on {own} own.")
        free = subset.undetermined
        zero = [name for name in free if subset.zero_columns[PARAMETER_NAMES.index(name)]]
        if zero:
            reasons = _join([ZERO_COLUMN_REASONS[name] for name in zero])
            subject = _join([PARAMETER_LABELS[name] for name in zero])
            verb = "are" if len(zero) > 1 else "is"
            sentences.append(f"{_capitalise(subject)} {verb} not determined: the data have {reasons}.")
        tangled = [name for name in free if name not in zero]
        if tangled:
            subject = _join([PARAMETER_LABELS[name] for name in tangled])
            sentences.append(
                f"{_capitalise(subject)} cannot be separated: their regressor columns are "
                "linearly dependent in these data."
            )
        return tuple(sentences)

    @cached_property
    def warnings(self) -> tuple[str, ...]:
        """Every caution about this fit, one sentence each (the accuracy ones and the conditioning)."""
        sentences = list(self.accuracy_sentences)
        condition = self.condition_number
        verdicts = self.uncertainty.verdicts if self.uncertainty is not None else None
        if self.estimate is None:
            sentences.insert(0, f"Rank {self.rank} of {self.parameter_count}: no unique least-squares fit.")
        elif condition > LARGE_CONDITION:
            sentences.append(
                f"The condition number {condition:.3g} is large: the columns are nearly dependent, "
                "so small torque errors move the parameters a lot."
            )
        elif condition < MODEST_CONDITION and verdicts and any(v != WELL_DETERMINED for v in verdicts):
            sentences.append(
                f"The condition number {condition:.2f} is modest, yet not every parameter is well "
                "determined: conditioning measures how distinct the columns are, not how far each "
                "parameter's signal rises above the noise."
            )
        return tuple(sentences)

    @cached_property
    def message(self) -> str:
        """The status sentence the lab shows under its readouts."""
        rank, total = self.rank, self.parameter_count
        if self.estimate is None:
            return " ".join(
                [
                    f"Rank {rank} of {total}: no unique least-squares fit.",
                    "Parameter and prediction readouts are unavailable.",
                    *self.accuracy_sentences,
                ]
            )
        parts = [f"Rank {rank} of {total}: a unique least-squares fit."]
        if self.heldout_rmse is None:
            parts.append("No held-out data, so predictions are untested.")
        else:
            # Measured held-out torques carry their own noise, which no fit can predict.
            measured = "" if self.heldout_is_noiseless else " against measured torques, so it includes their measurement noise"
            parts.append(f"Held-out torque RMSE is {format_number(self.heldout_rmse)} N m{measured}.")
        for name in self.sign_failures:
            value = self.estimate[PARAMETER_NAMES.index(name)]
            parts.append(
                f"Fitted {PARAMETER_LABELS[name]} {format_number(value)} {PARAMETER_UNITS[name]} "
                f"fails this joint model's requirement {SIGN_REQUIREMENTS[name]}."
            )
        if not self.sign_failures:
            parts.append("Positive parameter signs alone do not establish an accurate physical model.")
        parts.extend(self.accuracy_sentences)
        return " ".join(parts)


def fitted_torque(X: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """X theta: (N,) for theta (p,), or (K, N), one row per fit, for theta (p, K).

    Column terms are added one at a time in a fixed order, not by BLAS, so a fit
    predicted alone and the same fit among a seed sweep agree bit for bit.
    """
    theta = np.asarray(theta, dtype=float)
    total = np.zeros(theta.shape[1:] + X.shape[:1])
    for j in range(X.shape[1]):
        total = total + (theta[j][:, None] * X[:, j] if theta.ndim == 2 else theta[j] * X[:, j])
    return total


def _join(words: list[str]) -> str:
    """'a', 'a and b', 'a, b and c'."""
    return words[0] if len(words) == 1 else ", ".join(words[:-1]) + " and " + words[-1]


def _capitalise(text: str) -> str:
    """First letter upper case, the rest untouched."""
    return text[:1].upper() + text[1:]


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
