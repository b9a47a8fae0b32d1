"""Seed sweep (Monte Carlo): the same experiment under K noise seeds, solved at once.

Noise enters only the torques, so the regressor, its factorisation and its
rank are the same for every seed: one pivoted QR serves all K right-hand sides.
Seeds run from the experiment's seed upward and wrap past 2^32 - 1 to 0, which
is what the generator itself does (it reduces every state modulo 2^32), so a
sweep never refuses a start seed. Each seed's estimate and RMSEs equal, bit for
bit, those of `run_experiment` with that seed.

Seeds are processed in chunks that bound memory; an optional `progress(done,
total)` callback runs after each chunk and an optional `cancelled()` check
before each, so an app can run a sweep in a worker thread.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from ..estimation.fit import fitted_torque
from ..estimation.solver import solve_least_squares
from ..estimation.uncertainty import parameter_uncertainty
from ..model.terms import JointModel
from ..norms import row_rms
from ..options import DEFAULT_SEED_COUNT, SEED_COUNT_LIMITS
from ..synthetic.noise import MODULUS, torque_noise
from ..synthetic.samples import training_data, validation_data
from ..synthetic.settings import Settings

CHUNK_ELEMENTS = 2**21
"""Torque values (seeds x samples) handled per chunk: about 16 MB per array."""
RMSE_QUANTITIES = ("training_rmse", "heldout_rmse")
"""The per-seed errors a sweep summarises after the parameters."""


class SweepCancelled(Exception):
    """Raised inside `run_sweep` when its `cancelled()` check returns True."""


@dataclass(frozen=True, eq=False)
class Distribution:
    """Mean, sample standard deviation and 5/50/95 % percentiles of one quantity over the seeds."""

    mean: float
    std: float | None
    """Sample standard deviation (ddof 1), or None for a single seed."""
    p5: float
    p50: float
    p95: float


def percentiles(values: np.ndarray, levels=(5, 50, 95)) -> np.ndarray:
    """numpy.percentile(values, levels) of a 1-D float array, its default linear method written out.

    The same numbers (tests/core/studies/test_sweep.py checks), without the np.unique inside
    np.percentile, which imports numpy.ma: buys 0.07 of `jointid sweep`'s start (bench_startup_budget).
    """
    ordered = np.sort(values)
    if ordered.size == 0 or np.isnan(ordered[-1]):  # NaN sorts last; numpy then returns NaN throughout
        return np.full(len(levels), np.nan)
    virtual = (ordered.size - 1) * (np.asarray(levels, dtype=float) / 100)
    below = np.floor(virtual)
    weight = virtual - below
    below = below.astype(np.intp)
    low, high = ordered[below], ordered[np.minimum(below + 1, ordered.size - 1)]
    step = high - low
    # numpy's lerp: from the nearer end, so that a weight of 1 gives `high` exactly.
    return np.where(weight >= 0.5, high - step * (1 - weight), low + step * weight)


def describe(values: np.ndarray) -> Distribution:
    """Summarise a 1-D array of per-seed values."""
    values = np.asarray(values, dtype=float)
    p5, p50, p95 = percentiles(values)
    std = float(np.std(values, ddof=1)) if len(values) > 1 else None
    return Distribution(float(np.mean(values)), std, float(p5), float(p50), float(p95))


def sweep_work(settings: Settings, seed_count: int) -> int:
    """Samples x seeds: the torque values a sweep generates and fits, which its time grows with."""
    return settings.samples * seed_count


def sweep_seeds(first_seed: int, count: int) -> np.ndarray:
    """(count,) Seeds first_seed, first_seed + 1, ... wrapped modulo 2^32."""
    return (np.int64(first_seed) + np.arange(count, dtype=np.int64)) % MODULUS


@dataclass(frozen=True, eq=False)
class SweepResult:
    """Per-seed fits of one experiment and their statistics."""

    settings: Settings
    """Motion, noise, samples, the first seed and the fitted model."""
    seeds: np.ndarray
    """(K,) The seeds, in order."""
    rank: int
    """Rank of the training regressor (the same for every seed)."""
    condition_number: float
    """Condition number of the column-scaled regressor (inf when rank-deficient)."""
    estimates: np.ndarray | None
    """(p, K) Fitted parameters per seed (rows in the model's order), or None when rank-deficient."""
    training_rmse: np.ndarray | None
    """(K,) Training RMSE against each seed's noisy torques, or None."""
    heldout_rmse: np.ndarray | None
    """(K,) RMSE on the noiseless validation motion, or None."""
    noise_bound_std_error: np.ndarray | None
    """(p,) Standard errors the noise bound implies (the same for every seed), or None."""
    held: np.ndarray | None = None
    """(p, K) True where a constrained fit held a seed's parameter at its bound; None unconstrained."""

    @cached_property
    def constraint_active_fraction(self) -> float | None:
        """Fraction of seeds whose constrained fit holds at least one parameter at its bound (None unconstrained)."""
        if self.held is None:
            return None
        return float(np.mean(self.held.any(axis=0)))

    @property
    def model(self) -> JointModel:
        """The fitted model."""
        return self.settings.joint_model

    @property
    def quantities(self) -> tuple[str, ...]:
        """What the sweep summarises, in display order: the parameters, then both RMSEs."""
        return (*self.model.names, *RMSE_QUANTITIES)

    @property
    def seed_count(self) -> int:
        """K, the number of seeds."""
        return len(self.seeds)

    @property
    def is_full_rank(self) -> bool:
        """True when the motion gives a unique fit, so the sweep has estimates."""
        return self.estimates is not None

    def values(self, quantity: str) -> np.ndarray | None:
        """(K,) Per-seed values of a parameter, 'training_rmse' or 'heldout_rmse', or None."""
        if not self.is_full_rank:
            return None
        if quantity in self.model.names:
            return self.estimates[self.model.names.index(quantity)]
        return {"training_rmse": self.training_rmse, "heldout_rmse": self.heldout_rmse}[quantity]

    @cached_property
    def statistics(self) -> dict[str, Distribution]:
        """Distribution of each of `quantities`, keyed by name; empty when rank-deficient."""
        if not self.is_full_rank:
            return {}
        return {name: describe(self.values(name)) for name in self.quantities}

    @cached_property
    def empirical_std(self) -> np.ndarray | None:
        """(p,) Sample standard deviation of each parameter over the seeds (None: rank-deficient or K = 1)."""
        if not self.is_full_rank or self.seed_count < 2:
            return None
        return np.array([self.statistics[name].std for name in self.model.names])

    @cached_property
    def sign_failure_mask(self) -> np.ndarray | None:
        """(p, K) True where a seed's parameter breaks its sign rule, or None when rank-deficient."""
        if not self.is_full_rank:
            return None
        return self.model.sign_failure_mask(self.estimates)

    @cached_property
    def sign_failure_fraction(self) -> float | None:
        """Fraction of seeds whose fit fails at least one sign check, or None."""
        if self.sign_failure_mask is None:
            return None
        return float(np.mean(self.sign_failure_mask.any(axis=0)))

    @cached_property
    def sign_failure_fractions(self) -> dict[str, float] | None:
        """Fraction of seeds failing each parameter's own sign check, or None."""
        if self.sign_failure_mask is None:
            return None
        return {name: float(np.mean(row)) for name, row in zip(self.model.names, self.sign_failure_mask)}



def run_sweep(
    settings: Settings,
    seed_count: int = DEFAULT_SEED_COUNT,
    *,
    chunk_size: int | None = None,
    progress: Callable[[int, int], None] | None = None,
    cancelled: Callable[[], bool] | None = None,
) -> SweepResult:
    """Fit `settings`' experiment for seed_count seeds from settings.seed, one factorisation for all.

    `progress(done, total)` is called after each chunk of seeds and `cancelled()`
    before each; when it returns True the sweep stops with SweepCancelled.
    """
    low, high = SEED_COUNT_LIMITS
    if not isinstance(seed_count, int) or isinstance(seed_count, bool) or not low <= seed_count <= high:
        raise ValueError(f"seed count must be a whole number from {low} to {high}; got {seed_count!r}")
    seeds = sweep_seeds(settings.seed, seed_count)
    # Noise-free torques on the same states run_experiment builds (x + 0.0 is exact).
    truth = training_data(replace(settings, noise=0.0))
    model = settings.joint_model
    regressor, exact = model.data_regressor(truth), truth.tau
    validation = validation_data(settings.true_joint)
    validation_regressor = model.data_regressor(validation)
    base = solve_least_squares(regressor, exact)
    uncertainty = parameter_uncertainty(base, settings.noise, model)
    result = SweepResult(
        settings=settings,
        seeds=seeds,
        rank=base.rank,
        condition_number=base.condition_number,
        estimates=None,
        training_rmse=None,
        heldout_rmse=None,
        noise_bound_std_error=None if uncertainty is None else uncertainty.noise_bound_std_error,
    )
    if not base.is_full_rank:
        if progress is not None:
            progress(seed_count, seed_count)
        return result
    step = chunk_size or max(1, CHUNK_ELEMENTS // max(1, settings.samples))
    lower = None
    if settings.constrained:
        from ..estimation.bounded import bounded_least_squares, lower_bounds  # only constrained sweeps load it

        lower = lower_bounds(model)
    held = np.zeros((model.size, seed_count), dtype=bool) if settings.constrained else None
    estimates = np.empty((model.size, seed_count))
    training_rmse = np.empty(seed_count)
    heldout_rmse = np.empty(seed_count)
    for start in range(0, seed_count, step):
        if cancelled is not None and cancelled():
            raise SweepCancelled(f"sweep cancelled after {start} of {seed_count} seeds")
        stop = min(start + step, seed_count)
        measured = exact + torque_noise(settings.noise, settings.samples, seeds[start:stop])  # (k, N)
        solution = solve_least_squares(regressor, measured.T)
        theta = solution.estimate  # (p, k)
        if lower is not None:
            bounded = bounded_least_squares(solution, lower)
            theta, held[:, start:stop] = bounded.estimate, bounded.active
        estimates[:, start:stop] = model.report(theta)
        training_rmse[start:stop] = row_rms(fitted_torque(regressor, theta) - measured)
        heldout_rmse[start:stop] = row_rms(fitted_torque(validation_regressor, theta) - validation.tau)
        if progress is not None:
            progress(stop, seed_count)
    return replace(result, estimates=estimates, training_rmse=training_rmse, heldout_rmse=heldout_rmse, held=held)
