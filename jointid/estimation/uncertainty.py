"""How well a full-rank fit determines each parameter: standard errors, intervals, verdicts.

For y = X theta + e with independent errors of variance sigma^2 the estimate's
covariance is sigma^2 (X^T X)^-1. The factor (X^T X)^-1 comes from the pivoted
QR of the column-scaled regressor, X D^-1 P = Q R, as D^-1 P R^-1 R^-T P^T D^-1,
so X^T X is never formed. Two values of sigma^2 are used:

- empirical: s^2 = RSS / (N - p), available when N > p;
- expected: b^2 / 3, the variance of noise uniform on [-b, b], when the data are
  synthetic and the bound b is known.

Both are computed as sqrt(sigma^2 diag(R^-1 R^-T)) / column scale, with sigma
and each scale first split into a power of two and the rest: for ordinary data
that gives bit for bit the plain formula, and for data of extreme magnitude
(1e200 N m, say) standard errors rather than an overflow.

The verdict uses the expected standard error when the bound is known, because it
describes the experiment (motion, samples, noise level) rather than one seed's
luck, and the empirical one otherwise. Intervals are Student t with N - p
degrees of freedom around the empirical standard error.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..norms import power_of_two_scale
from .solver import PRODUCT_PIECE, LeastSquaresSolution, back_substitute
from .student_t import student_t_quantile

WELL_DETERMINED = "well determined"
WEAK = "weak"
NOT_DETERMINED = "not determined"
AT_BOUND = "at bound"
"""Not a verdict: a constrained fit held this parameter at its bound, so it has no standard error."""

WELL_DETERMINED_LIMIT = 10.0
"""Relative standard error (% of |estimate|) at or below which a parameter is well determined."""
WEAK_LIMIT = 30.0
"""Relative standard error (%) above which a parameter is not determined; between the limits it is weak."""

CONFIDENCE = 0.95
"""Coverage of the reported Student-t interval."""


def scaled_covariance_factor(solution: LeastSquaresSolution) -> np.ndarray:
    """(p, p) (R^T R)^-1 of the column-scaled regressor, in the original parameter order; needs full rank."""
    if not solution.is_full_rank:
        raise ValueError("(X^T X)^-1 exists only for a full-rank regressor")
    p = solution.column_count
    r_inverse = back_substitute(solution.r_factor, np.eye(p))
    pivoted = r_inverse @ r_inverse.T  # (R^T R)^-1 for the scaled, pivoted columns
    unpivoted = np.empty((p, p))
    unpivoted[np.ix_(solution.permutation, solution.permutation)] = pivoted
    return unpivoted


def covariance_factor(solution: LeastSquaresSolution) -> np.ndarray:
    """(p, p) (X^T X)^-1 in the original parameter order and units, from a full-rank R factor."""
    return scaled_covariance_factor(solution) / np.outer(solution.scales, solution.scales)


def standard_errors(sigma: float, divisor: float, scaled_diagonal: np.ndarray, scales: np.ndarray) -> np.ndarray:
    """(p,) sqrt(sigma**2 / divisor * scaled_diagonal / scales**2), without overflow in between.

    sigma and each scale are split into a power of two and a factor near 1 first.
    Those powers of two come out of the square root exactly, so the result equals
    the plain formula bit for bit whenever that formula stays in range.
    """
    sigma_scale, column_scale = power_of_two_scale(abs(sigma)), power_of_two_scale(scales)
    variance = (sigma / sigma_scale) ** 2 / divisor
    diagonal = scaled_diagonal / ((scales / column_scale) * (scales / column_scale))
    with np.errstate(over="ignore", under="ignore"):  # a standard error beyond double range is inf (or 0)
        return np.sqrt(variance * diagonal) * (sigma_scale / column_scale)


def verdict(relative_std_pct: float) -> str:
    """Well determined (<= 10 %), weak (<= 30 %) or not determined, from a relative standard error."""
    if relative_std_pct <= WELL_DETERMINED_LIMIT:
        return WELL_DETERMINED
    return WEAK if relative_std_pct <= WEAK_LIMIT else NOT_DETERMINED


@dataclass(frozen=True, eq=False)
class ParameterUncertainty:
    """Standard errors, relative errors, 95 % intervals and verdicts of one full-rank fit."""

    estimate: np.ndarray
    """(p,) The fitted parameters."""
    covariance_factor: np.ndarray
    """(p, p) (X^T X)^-1, which times the noise variance is the estimate's covariance (may over- or
    underflow for data of extreme magnitude; the standard errors do not use it)."""
    scaled_diagonal: np.ndarray
    """(p,) Diagonal of the column-scaled regressor's (R^T R)^-1, in parameter order."""
    scales: np.ndarray
    """(p,) The regressor's column norms: covariance_factor = scaled factor / outer(scales, scales)."""
    residual_norm: float
    """||y - X theta||, the square root of the residual sum of squares."""
    row_count: int
    """N, the number of samples fitted."""
    noise_bound: float | None
    """Known bound b of uniform noise on [-b, b], or None for measured data."""
    held: np.ndarray | None = None
    """(p,) True for parameters a constrained fit holds at their bounds (no standard error), or None."""
    correlated_covariance: np.ndarray | None = None
    """(p, p) Newey-West covariance when the residuals are correlated (a filtered log), or None: then the
    residual-based standard errors come from it, not from s^2 (X^T X)^-1."""
    effective_count: float | None = None
    """How many independent residuals the correlated ones are worth (None: independent, N)."""
    spread: np.ndarray | None = None
    """(p,) How far reasonable analysis choices move each parameter beyond what noise makes (a log fit's judgement,
    jointid.estimation.judgement), added in quadrature to the residual-based standard errors; None: the noise's
    errors alone."""

    @property
    def degrees_of_freedom(self) -> int:
        """N - p, the residual degrees of freedom (p counts only free parameters; may be zero or negative)."""
        held = 0 if self.held is None else int(self.held.sum())
        return self.row_count - len(self.estimate) + held

    @property
    def interval_degrees_of_freedom(self) -> float:
        """Degrees of freedom of the Student-t intervals: N - p, or the effective count less p when correlated."""
        if self.effective_count is None:
            return self.degrees_of_freedom
        return max(1.0, self.effective_count - (self.row_count - self.degrees_of_freedom))

    @cached_property
    def residual_variance(self) -> float | None:
        """s^2 = RSS / (N - p), or None when N - p <= 0 (inf if it overflows; std_error does not)."""
        if self.degrees_of_freedom <= 0:
            return None
        with np.errstate(over="ignore"):
            return float(np.square(self.residual_norm) / self.degrees_of_freedom)

    @cached_property
    def noise_std_error(self) -> np.ndarray | None:
        """(p,) Empirical standard errors from the residuals alone, sqrt(s^2 diag((X^T X)^-1)) or Newey-West's, or
        None when N - p <= 0."""
        if self.degrees_of_freedom <= 0:
            return None
        if self.correlated_covariance is not None:
            return self._without_held(np.sqrt(np.diag(self.correlated_covariance)))
        return self._without_held(
            standard_errors(self.residual_norm, self.degrees_of_freedom, self.scaled_diagonal, self.scales))

    @cached_property
    def residual_std_error(self) -> np.ndarray | None:
        """(p,) The reported standard errors: `noise_std_error`, widened in quadrature by `spread` when a log fit's
        analysis choices move the parameters beyond it; None when N - p <= 0."""
        noise = self.noise_std_error
        if noise is None or self.spread is None:
            return noise
        with np.errstate(over="ignore", invalid="ignore"):
            return np.where(self.spread > 0, np.hypot(noise, self.spread), noise)

    @cached_property
    def noise_bound_std_error(self) -> np.ndarray | None:
        """(p,) Standard errors the known noise bound implies, sqrt(b^2/3 diag((X^T X)^-1)), or None."""
        if self.noise_bound is None:
            return None
        return self._without_held(standard_errors(self.noise_bound, 3.0, self.scaled_diagonal, self.scales))

    def _without_held(self, errors: np.ndarray) -> np.ndarray:
        """Standard errors with NaN for the parameters held at their bounds."""
        return errors if self.held is None else np.where(self.held, np.nan, errors)

    @property
    def verdict_basis(self) -> str | None:
        """'expected' or 'empirical': which standard error drives the verdicts (None: neither exists)."""
        if self.noise_bound_std_error is not None:
            return "expected"
        return "empirical" if self.residual_std_error is not None else None

    @property
    def verdict_std_error(self) -> np.ndarray | None:
        """(p,) The standard errors the verdicts are judged on (see `verdict_basis`)."""
        return self.noise_bound_std_error if self.noise_bound_std_error is not None else self.residual_std_error

    @property
    def noise_verdict_std_error(self) -> np.ndarray | None:
        """(p,) The standard errors the noise-only verdicts are judged on (`verdict_std_error` before widening)."""
        return self.noise_bound_std_error if self.noise_bound_std_error is not None else self.noise_std_error

    @cached_property
    def relative_std_pct(self) -> np.ndarray | None:
        """(p,) verdict standard error as % of |estimate| (0 when the error is 0, inf when the estimate is)."""
        return _relative(self.verdict_std_error, self.estimate)

    @cached_property
    def noise_relative_std_pct(self) -> np.ndarray | None:
        """(p,) The noise-only verdict standard error as % of |estimate| (`relative_std_pct` before widening)."""
        return _relative(self.noise_verdict_std_error, self.estimate)

    @cached_property
    def verdicts(self) -> tuple[str, ...] | None:
        """The noise-only verdict per parameter, from `noise_relative_std_pct`, or None without any standard error
        (the judged verdicts every face shows are `FitResult.verdicts`)."""
        if self.noise_relative_std_pct is None:
            return None
        held = np.zeros(len(self.estimate), dtype=bool) if self.held is None else self.held
        return tuple(AT_BOUND if at_bound else verdict(float(value))
                     for value, at_bound in zip(self.noise_relative_std_pct, held))

    @cached_property
    def interval95(self) -> np.ndarray | None:
        """(p, 2) Student-t 95 % interval [low, high] from the empirical standard error, or None."""
        if self.residual_std_error is None:
            return None
        half = student_t_quantile(0.5 + CONFIDENCE / 2, self.interval_degrees_of_freedom) * self.residual_std_error
        return np.column_stack([self.estimate - half, self.estimate + half])


def _relative(std: np.ndarray | None, estimate: np.ndarray) -> np.ndarray | None:
    """(p,) `std` as % of |estimate| (0 when the error is 0, inf when the estimate is), or None without errors."""
    if std is None:
        return None
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        return np.where(std == 0, 0.0, 100.0 * std / np.abs(estimate))


def newey_west_sum(X: np.ndarray, residuals: np.ndarray, positions: np.ndarray, lag: int
                   ) -> tuple[np.ndarray, float]:
    """(S, autocorrelation sum) for residuals correlated over `lag` steps of an evenly spaced grid, the fitted
    samples at `positions` on it: S = sum over pairs within the lag of Bartlett weights (1 - k/(lag + 1))
    u_i u_j^T of the scores u_i = x_i e_i, and 1 + 2 sum of the weighted autocorrelations (N / it: the
    effective count)."""
    count, p = X.shape
    size = int(positions[-1]) + 1 if count else 0
    if size == 0:
        return np.zeros((p, p)), 1.0
    # The weighted sum over lags is one banded quadratic form, G^T (K G) with K the Bartlett kernel, K G computed
    # by FFT for every column at once: two small products per lag woke OpenBLAS's threads each time (on this
    # busy 2-core machine a log fit's four calls took 0.3-2.2 s instead of 0.01 s), and a direct convolution
    # per column took 3 ms a call, 0.4 s of pooling ten runs.
    reach = min(lag, size - 1)
    kernel = 1 - np.abs(np.arange(-reach, reach + 1)) / (lag + 1)
    grid = np.zeros((p + 1, size))  # a row per column: contiguous for the FFTs
    grid[:p, positions] = (X * residuals[:, None]).T
    grid[p, positions] = residuals
    length = 1 << math.ceil(math.log2(size + 2 * reach))
    smeared = np.fft.irfft(np.fft.rfft(grid, length) * np.fft.rfft(kernel, length), length)[:, reach: reach + size]
    meat = np.zeros((p, p))
    # In pieces below 2^18 multiply-adds, which OpenBLAS runs on one thread (see PRODUCT_PIECE).
    piece = max(1, PRODUCT_PIECE // (p * p))
    for first in range(0, size, piece):
        meat += smeared[:p, first: first + piece] @ grid[:p, first: first + piece].T
    meat = (meat + meat.T) / 2  # symmetric in exact arithmetic; rounding made it differ in the last bits
    c0 = float(np.einsum("i,i->", residuals, residuals))
    autocorrelation = float(np.einsum("i,i->", smeared[p, positions], residuals)) / c0 if c0 > 0 else 1.0
    return meat, max(autocorrelation, 1.0)


def newey_west(X: np.ndarray, residuals: np.ndarray, positions: np.ndarray, lag: int,
               factor: np.ndarray) -> tuple[np.ndarray, float]:
    """(The Newey-West covariance of a least-squares estimate, the effective sample count); `factor` is
    (X^T X)^-1, and the covariance factor S factor is scaled by N / (N - p) (see newey_west_sum)."""
    count, p = X.shape
    meat, autocorrelation = newey_west_sum(X, residuals, positions, lag)
    return factor @ meat @ factor * count / max(count - p, 1), count / autocorrelation


def parameter_uncertainty(
    solution: LeastSquaresSolution, noise_bound: float | None = None, model=None, bounded=None,
    correlated: tuple[np.ndarray, float] | None = None,
) -> ParameterUncertainty | None:
    """Uncertainty of a single-RHS fit's estimate, or None when the rank gives no unique fit.

    With a `model` (jointid.model.terms.JointModel) whose reported parameters differ
    from its columns (an angle offset's h and q0), the estimate is reported and
    the covariance factor carried over by the delta method, J (X^T X)^-1 J^T.
    With `bounded` (a jointid.estimation.bounded.BoundedSolution), the estimate is the
    constrained one and the covariance that of the free parameters with the held
    ones fixed at their bounds, (M_F^T M_F)^-1; held parameters have none.
    With `correlated` (a Newey-West covariance of the columns' coefficients and the effective sample count),
    the residual-based standard errors come from that covariance.
    """
    if solution.estimate is None:
        return None
    scaled = scaled_covariance_factor(solution)
    with np.errstate(over="ignore", under="ignore", divide="ignore"):  # extreme scales: see the field's docstring
        unscaled = scaled / np.outer(solution.scales, solution.scales)
    estimate, diagonal, scales = solution.estimate, np.diag(scaled).copy(), solution.scales
    residual, held = float(solution.residual_norm), None
    if bounded is not None and bounded.active.any():
        estimate, held, residual = bounded.estimate, bounded.active, float(bounded.residual_norm)
        unscaled = free_covariance_factor(solution, ~held)
        diagonal, scales = np.diag(unscaled).copy(), np.ones_like(scales)
    jacobian = None if model is None else model.report_jacobian(estimate)
    if jacobian is not None:
        # Each row divided by a power of two near its size, which becomes that parameter's scale: q0's row is
        # 1/h, and its square (1e-600 for h near 1e300) would underflow to a standard error of 0.
        rows = power_of_two_scale(np.max(np.abs(jacobian), axis=1))
        normalised = jacobian / rows[:, None]
        estimate, reduced = model.report(estimate), normalised @ unscaled @ normalised.T
        diagonal, scales = np.diag(reduced).copy(), 1.0 / rows
        with np.errstate(over="ignore", under="ignore"):
            unscaled = reduced * np.outer(rows, rows)
    return ParameterUncertainty(
        estimate=estimate,
        covariance_factor=unscaled,
        scaled_diagonal=diagonal,
        scales=scales,
        residual_norm=residual,
        row_count=solution.row_count,
        noise_bound=noise_bound,
        held=held,
        correlated_covariance=None if correlated is None else (
            correlated[0] if jacobian is None else jacobian @ correlated[0] @ jacobian.T),
        effective_count=None if correlated is None else correlated[1],
    )


def free_covariance_factor(solution: LeastSquaresSolution, free: np.ndarray) -> np.ndarray:
    """(p, p) (X_F^T X_F)^-1 on the free columns and zeros elsewhere (held parameters vary with nothing)."""
    from .bounded import reduced_matrix  # only constrained fits get here

    matrix = reduced_matrix(solution)[:, free]
    r_free = np.linalg.qr(matrix, mode="r")
    inverse = back_substitute(r_free, np.eye(r_free.shape[1]))
    factor = np.zeros((solution.column_count, solution.column_count))
    factor[np.ix_(free, free)] = inverse @ inverse.T
    return factor


def finite_or_none(value: float) -> float | None:
    """A float for JSON, or None when it is infinite or NaN (strict JSON has neither)."""
    value = float(value)
    return value if math.isfinite(value) else None
