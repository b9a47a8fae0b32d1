"""Fit a joint model's parameters to joint data and judge the fit on held-out data."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields, replace
from functools import cached_property
from types import MappingProxyType
from typing import TYPE_CHECKING

import numpy as np

from ..checks import checked, flag, instance_of, optional, real, real_array
from ..model.terms import PLAIN, JointModel, model_argument
from ..norms import rms
from ..samples import JointData
from .solver import LeastSquaresSolution, solve_least_squares
from .judgement import Judgement, noise_judgement
from .student_t import student_t_quantile
from .uncertainty import ParameterUncertainty, covariance_factor, newey_west, parameter_uncertainty

if TYPE_CHECKING:
    from ..synthetic.settings import Settings
    from .bounded import BoundedSolution
    from .identifiable import IdentifiableSubset


SCALE_CORRELATION = 0.95
"""Above this |correlation| of the acceleration and gravity columns, h/I is reported with its standard error."""


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
    training_regressor: np.ndarray
    """(N, p) The model's regressor at the training states."""
    model: JointModel = PLAIN
    """The fitted model: its terms name, order and judge the parameters."""
    constrained: bool = False
    """True for a fit subject to the model's sign rules (jointid.estimation.bounded)."""
    noise_bound: float | None = None
    """Known bound b of uniform torque noise on [-b, b] (synthetic data), else None."""
    settings: Settings | None = None
    """The synthetic experiment's settings that produced this fit, or None (a log, or data of your own)."""
    correlation: tuple[np.ndarray, int] | None = None
    """(positions, lag) when the training residuals are correlated (a filtered log): each sample's index on its
    evenly spaced grid (gaps where samples were left out) and the Newey-West lag in grid steps; None: independent."""
    judged: Judgement | None = None
    """The verdicts of every check a log fit ran (sensitivity, robust step, omitted terms, stretches), or None:
    then `judgement` is the noise verdicts alone (jointid.estimation.judgement). Its spread widens `uncertainty`'s
    reported errors and intervals (the noise-only ones stay as its `noise_std_error`)."""
    heldout_regressor: np.ndarray | None = None
    """(M, p) The model's regressor at the held-out states as the training log's went through the low-pass and
    exclusions (a log's held-out check), or None: the held-out states' own regressor."""

    def __repr__(self) -> str:
        shown = ", ".join(f"{name}={value:.6g}" for name, value in self.params.items())
        return f"<FitResult model={self.model.name!r} rank={self.rank}/{self.parameter_count} {shown}>"

    @cached_property
    def params(self) -> Mapping[str, float]:
        """Fitted parameters by name, in the model's order (`result.params["I"]`); NaN without a unique fit.

        Read-only. The names are the model's `names`: I, h, B, then Fc, tau0 or q0 for the terms it adds.
        """
        values = self.estimate if self.estimate is not None else np.full(len(self.model.names), np.nan)
        return MappingProxyType(dict(zip(self.model.names, map(float, values))))

    @cached_property
    def bse(self) -> Mapping[str, float]:
        """Standard error of each parameter: the ± that `jointid fit` prints and the verdicts judge (NaN if none).

        From the known noise bound when the data are synthetic (b^2/3, the uniform noise's variance), else
        from the residuals (RSS / (N - p)); see `uncertainty` for both.
        """
        errors = None if self.uncertainty is None else self.uncertainty.verdict_std_error
        if errors is None:
            errors = np.full(len(self.model.names), np.nan)
        return MappingProxyType(dict(zip(self.model.names, map(float, errors))))

    def conf_int(self, alpha: float = 0.05) -> Mapping[str, tuple[float, float]]:
        """Student-t interval of coverage 1 - alpha for each parameter, around its residual-based standard error.

        Parameters
        ----------
        alpha : float
            1 - coverage, between 0 and 1 (0.05: the 95 % interval `jointid fit --json` reports).

        Returns
        -------
        Mapping[str, tuple[float, float]]
            (low, high) by parameter name; (NaN, NaN) without residual degrees of freedom or a unique fit.

        Examples
        --------
        >>> import jointid
        >>> result = jointid.run_experiment(jointid.Settings(noise=0.2))
        >>> low, high = result.conf_int(0.05)["I"]
        >>> bool(low < 0.8 < high)
        True
        """
        if isinstance(alpha, bool) or not isinstance(alpha, (int, float)) or not 0 < alpha < 1:
            raise ValueError(f"alpha must be a number between 0 and 1; got {alpha!r}")
        u = self.uncertainty
        if u is None or u.residual_std_error is None:
            return MappingProxyType({name: (math.nan, math.nan) for name in self.model.names})
        # The degrees of freedom of `interval95` (the effective count's after a low-pass), so the two agree exactly.
        half = student_t_quantile(1 - alpha / 2, u.interval_degrees_of_freedom) * u.residual_std_error
        return MappingProxyType({name: (float(value - step), float(value + step))
                                 for name, value, step in zip(self.model.names, u.estimate, half)})

    @cached_property
    def judgement(self) -> Judgement:
        """Each parameter's verdict from every check that bears on it, the noise-only verdict, and the reasons."""
        if self.judged is not None:
            return self.judged
        return noise_judgement(self.model.names, self.uncertainty)

    @property
    def verdicts(self) -> Mapping[str, str | None]:
        """The verdict of each parameter by name, as every face shows it (`jointid fit`'s text and JSON's
        `verdicts`): 'well determined', 'weak', 'not determined', 'at bound', or None without a standard error."""
        return self.judgement.by_name()

    def summary(self) -> str:
        """The text `jointid fit` prints for this fit: the readouts, then how well each parameter is determined."""
        from ..present.summary import fit_summary  # presentation, loaded only when asked (as statsmodels does)

        return fit_summary(self)

    @property
    def rank(self) -> int:
        """Numerical rank of the training regressor."""
        return self.solution.rank

    @property
    def parameter_count(self) -> int:
        """p, the number of fitted parameters (the model's terms)."""
        return self.solution.column_count

    @cached_property
    def bounded(self) -> BoundedSolution | None:
        """The sign-constrained solution of a constrained full-rank fit, else None."""
        if not self.constrained or self.solution.estimate is None:
            return None
        from .bounded import bounded_least_squares, lower_bounds  # only constrained fits load it

        return bounded_least_squares(self.solution, lower_bounds(self.model))

    @property
    def column_estimate(self) -> np.ndarray | None:
        """(p,) Fitted coefficients of the regressor's columns (within bounds when constrained), or None below full rank."""
        return self.solution.estimate if self.bounded is None else self.bounded.estimate

    @property
    def unconstrained_estimate(self) -> np.ndarray | None:
        """(p,) The reported parameters of the plain least-squares fit (the same as `estimate` unconstrained)."""
        return None if self.solution.estimate is None else self.model.report(self.solution.estimate)

    @cached_property
    def at_bound(self) -> tuple[str, ...]:
        """Names of the parameters a constrained fit holds at their bounds (empty otherwise)."""
        if self.bounded is None:
            return ()
        return tuple(name for name, held in zip(self.model.names, self.bounded.active) if held)

    @cached_property
    def estimate(self) -> np.ndarray | None:
        """(p,) Fitted parameters as the model reports them (its `names`), or None when the rank is deficient.

        The same as `column_estimate` except for an angle offset's h and q0.
        """
        return None if self.column_estimate is None else self.model.report(self.column_estimate)

    @cached_property
    def training_predictions(self) -> np.ndarray | None:
        """(N,) Fitted torque at the training states, or None without a unique fit."""
        return None if self.estimate is None else fitted_torque(self.training_regressor, self.column_estimate)

    @cached_property
    def heldout_predictions(self) -> np.ndarray | None:
        """(M,) Fitted torque at the held-out states, or None."""
        if self.estimate is None or self.heldout is None:
            return None
        X = self.model.data_regressor(self.heldout) if self.heldout_regressor is None else self.heldout_regressor
        return fitted_torque(X, self.column_estimate)

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
        """Names of fitted parameters that break their terms' sign rules (never clipped)."""
        return () if self.estimate is None else self.model.sign_failures(self.estimate)

    @cached_property
    def uncertainty(self) -> ParameterUncertainty | None:
        """Standard errors, intervals and verdicts per parameter, or None without a unique fit."""
        correlated = None
        if self.correlation is not None and self.solution.is_full_rank and self.bounded is None:
            positions, lag = self.correlation
            residuals = self.training.tau - self.training_predictions
            with np.errstate(all="ignore"):  # data of extreme magnitude: checked just below
                correlated = newey_west(self.training_regressor, residuals, positions, lag,
                                        covariance_factor(self.solution))
            if not (np.isfinite(correlated[0]).all() and np.all(np.diag(correlated[0]) > 0)):
                correlated = None  # beyond double range: the residual-based errors, which never overflow
        found = parameter_uncertainty(self.solution, self.noise_bound, self.model, self.bounded, correlated)
        if found is not None and self.judged is not None and self.judged.spread:
            # The judgement's analysis choices widen the reported errors (and so the intervals) of a log fit.
            found = replace(found, spread=np.asarray(self.judged.spread, dtype=float))
        return found

    @cached_property
    def identifiable(self) -> IdentifiableSubset:
        """The parameters the training data determine on their own, at any rank."""
        from .identifiable import identifiable_subset  # loaded when asked (JSON, rank-deficient texts)

        return identifiable_subset(self.solution, self.model.column_names)

    @cached_property
    def scale_ratio(self) -> tuple[float, float, float] | None:
        """(corr, h/I, its standard error) when the acceleration and gravity columns correlate above
        SCALE_CORRELATION (a joint swinging near its natural frequency: h/I is determined, their common scale
        less so), else None."""
        i, h = self.model.index_of("I"), self.model.index_of("h")
        if i is None or h is None or self.uncertainty is None or self.estimate is None:
            return None
        corr = column_correlation(self.training_regressor, i, h)
        if not abs(corr) > SCALE_CORRELATION:
            return None
        covariance = self.uncertainty.correlated_covariance
        if covariance is None:
            covariance = covariance_factor(self.solution) * (self.uncertainty.residual_variance or 0.0)
        inertia, mass_moment = self.column_estimate[i], self.column_estimate[h]
        with np.errstate(all="ignore"):
            gradient = np.array([-mass_moment / inertia**2, 1 / inertia])
            block = covariance[np.ix_([i, h], [i, h])]
            ratio, error = float(mass_moment / inertia), float(np.sqrt(gradient @ block @ gradient))
        if self.judged is not None and self.judged.ratio_spread > 0:  # widened as the parameters' errors are
            error = math.hypot(error, self.judged.ratio_spread)
        return (corr, ratio, error) if np.isfinite(ratio) and np.isfinite(error) else None

    @property
    def condition_number(self) -> float:
        """Condition number of the column-scaled training regressor (inf when rank-deficient)."""
        return self.solution.condition_number



def with_judgement(result: FitResult, judgement: Judgement) -> FitResult:
    """The same fit carrying `judgement`; its statistics already computed carry over (they do not depend on it)."""
    judged = replace(result, judged=judgement)
    carried = {key: value for key, value in vars(result).items() if key not in {f.name for f in fields(result)}}
    carried.pop("judgement", None)
    if judgement.spread:  # the reported errors are widened: recomputed from the noise's, with the spread
        carried.pop("uncertainty", None), carried.pop("bse", None)
    if judgement.ratio_spread:  # and so is h/I's
        carried.pop("scale_ratio", None)
    vars(judged).update(carried)
    return judged


def column_correlation(X: np.ndarray, i: int, j: int) -> float:
    """Pearson's correlation of columns i and j of X (N, p), as np.corrcoef gives it; 0 with fewer than 3 rows or
    a constant column. Each column is scaled by its largest magnitude first (extreme values would overflow the
    sums), centred in place and summed by einsum: no (2, N) stack, a fifth of np.corrcoef's time on 1e6 rows."""
    if len(X) < 3:
        return 0.0
    with np.errstate(all="ignore"):  # columns of extreme magnitude: scaled first, checked below
        a, b = X[:, i] / np.max(np.abs(X[:, i])), X[:, j] / np.max(np.abs(X[:, j]))
        a -= np.mean(a)
        b -= np.mean(b)
        aa, bb = np.einsum("i,i->", a, a), np.einsum("i,i->", b, b)
        if not (aa > 0 and bb > 0):
            return 0.0
        corr = float(np.einsum("i,i->", a, b) / np.sqrt(aa * bb))
    return min(max(corr, -1.0), 1.0) if math.isfinite(corr) else 0.0


def fitted_torque(X: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """X theta: (N,) for theta (p,), or (K, N), one row per fit, for theta (p, K).

    Column terms are added one at a time in a fixed order, not by BLAS, so a fit
    predicted alone and the same fit among a seed sweep agree bit for bit.
    """
    theta = np.asarray(theta, dtype=float)
    if X.shape[1] == 0:
        return np.zeros(theta.shape[1:] + X.shape[:1])

    def term(j: int) -> np.ndarray:
        return theta[j][:, None] * X[:, j] if theta.ndim == 2 else theta[j] * X[:, j]

    total = term(0)
    for j in range(1, X.shape[1]):
        total += term(j)  # in place: a fresh sum per column cost a third of this on 1e6 rows
    return total


@checked(training=instance_of(JointData, "a JointData"), heldout=optional(instance_of(JointData, "a JointData")),
         model=model_argument, constrained=flag, heldout_is_noiseless=flag, noise_bound=optional(real(0.0)),
         regressor=optional(real_array(2, finite=False)))
def fit_joint(
    training: JointData,
    heldout: JointData | None = None,
    *,
    model: JointModel = PLAIN,
    constrained: bool = False,
    heldout_is_noiseless: bool = False,
    noise_bound: float | None = None,
    regressor: np.ndarray | None = None,
    settings: Settings | None = None,
    correlation: tuple[np.ndarray, int] | None = None,
) -> FitResult:
    """Fit `model`'s parameters to the training data by pivoted QR (subject to their sign rules when
    `constrained`) and evaluate on the held-out data.

    Parameters
    ----------
    training : JointData
        The samples to fit.
    heldout : JointData, optional
        Samples the fit never sees, to predict.
    model : JointModel
        The model (default the lesson's plain I, h, B); `model_named("coulomb")` and the like for others.
    constrained : bool
        Fit subject to the terms' sign rules.
    heldout_is_noiseless : bool
        The held-out torques are exact (synthetic), not measured.
    noise_bound : float, optional
        Known bound b of uniform torque noise; the standard errors then come from it.
    regressor : numpy.ndarray, optional
        (N, p) replaces the model's regressor of the training states, e.g. low-pass filtered in parallel with
        `training.tau` (jointid.estimation.low_pass).
    settings : Settings, optional
        The synthetic experiment behind the data, recorded on the result for its summary.
    correlation : (numpy.ndarray, int), optional
        The samples' positions on their evenly spaced grid and the lag over which their residuals correlate
        (a filtered log): standard errors then come from the Newey-West covariance.

    Returns
    -------
    FitResult
        `params`, `bse`, `conf_int()`, `summary()`, the readouts and the factorisation.
    """
    X = model.data_regressor(training) if regressor is None else regressor
    return FitResult(
        training=training,
        heldout=heldout,
        heldout_is_noiseless=heldout_is_noiseless,
        solution=solve_least_squares(X, training.tau),
        training_regressor=X,
        model=model,
        constrained=constrained,
        noise_bound=noise_bound,
        settings=settings,
        correlation=correlation,
    )
