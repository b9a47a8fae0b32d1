"""Several runs of one joint: each prepared and fitted alone, then fitted together, and each predicted by the rest.

Each run goes through the whole log pipeline on its own (timing, derivatives,
its own cutoff, the robust step, standstill), because runs differ in rate,
motion and disturbances. The pooled fit stacks every run's filtered, kept
samples, each weighted by 1 / its own residual variance (a noisy run counts
for less), and shares the joint's parameters; a torque bias, when the model
has one, stays each run's own (a sensor's offset is not a property of the
joint). Its standard errors add each run's Newey-West sum (the runs are
independent, their samples are not). Leave-one-run-out: the other runs'
pooled fit predicts each run's filtered torque (the run's own offset fitted
to it), which says how well one run's joint is another's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from types import MappingProxyType

import numpy as np

from ..estimation.exclusion import ExclusionRequest
from ..estimation.judgement import Finding, Judgement, Spread, judge, relative_error_pct
from ..estimation.low_pass import FilterRequest
from ..estimation.solver import block_rows_for, solve_least_squares, triangle_of
from ..estimation.uncertainty import covariance_factor, newey_west_sum
from ..logs.pipeline import JointLog
from ..model.terms import JointModel
from .log_fit import LoadedLogs, fit_logs, refits_of
from .refits import beyond_noise, is_exact, run_scatter

BIAS = "tau0"
"""The model's torque bias term, which each run keeps for itself."""

OWN_FIT, POOLED_FIT = "own fit", "pooled fit"
"""How runs are weighted: by their own fit's residuals, or by their residuals against a first, equally weighted
pooled fit (a SysId test alone fits its constant voltage exactly, so its own residuals say nothing of its noise)."""

DISAGREEMENT = 3.0
"""A run disagrees when a shared parameter differs from the pooled one by more than this many combined errors."""


@dataclass(frozen=True, eq=False)
class PooledRuns:
    """Each run's own fit, the fit of all of them together, and each run predicted by the others."""

    runs: tuple[LoadedLogs, ...]
    """Each run prepared and fitted on its own, in the order given."""
    shared: tuple[str, ...]
    """The parameters every run shares (the model's reported ones, less its torque bias: an angle offset's h and q0
    rather than its columns)."""
    estimate: np.ndarray
    """(s + b,) The pooled fit: the shared parameters, then each run's own bias when the model has one."""
    std_error: np.ndarray
    """(s + b,) Their standard errors (Newey-West within each run)."""
    weights: tuple[float, ...]
    """1 / each run's residual variance (N m)^-2."""
    predicted_by_others: tuple[float | None, ...]
    """RMS (N m) of each run's filtered torque less the other runs' pooled prediction (its offset its own), or
    None when the other runs have no unique fit together."""
    covariance: np.ndarray | None = None
    """(s + b, s + b) The covariance behind `std_error`, for parameters derived from several (an angle offset's
    h and q0, a controller's gains); None without a unique pooled fit."""
    weighting: str = OWN_FIT
    """OWN_FIT or POOLED_FIT: what the weights come from."""
    mechanism: object | None = None
    """The studies.mechanism.MechanismChoice a SysId log's tests were fitted as, or None for other runs."""

    @property
    def names(self) -> tuple[str, ...]:
        """The run files' names, without their folders."""
        return tuple(run.name for run in self.runs)

    @cached_property
    def _reported(self) -> tuple[np.ndarray, np.ndarray]:
        """(s,) The pooled shared parameters as the model reports them, and their standard errors (the delta method
        on the pooled covariance for an angle offset's h and q0)."""
        model = self.runs[0].result.model
        count = len(self.shared)
        columns = [j for j, term in enumerate(model.terms) if term.kind != BIAS]
        theta = np.zeros(model.size)
        theta[columns] = self.estimate[:count]
        jacobian = model.report_jacobian(theta) if np.all(np.isfinite(theta)) else None
        if jacobian is None:
            return np.asarray(self.estimate[:count], dtype=float), np.asarray(self.std_error[:count], dtype=float)
        reported = model.report(theta)[columns]
        if self.covariance is None:
            return reported, np.full(count, np.nan)
        block = jacobian[np.ix_(columns, columns)]
        return reported, np.sqrt(np.diag(block @ self.covariance[:count, :count] @ block.T))

    @cached_property
    def params(self) -> MappingProxyType:
        """The pooled shared parameters by name."""
        return MappingProxyType(dict(zip(self.shared, map(float, self._reported[0]))))

    @cached_property
    def bse(self) -> MappingProxyType:
        """Their reported standard errors by name: `noise_bse` widened as the judgement says (the runs' scatter, the
        analysis choices)."""
        return MappingProxyType(dict(zip(self.shared, self.judgement.widened(self._reported[1]))))

    @cached_property
    def judgement(self) -> Judgement:
        """Each shared parameter judged once: its pooled error widened by the scatter of the runs about it beyond
        their own noise errors and by what the analysis choices move (each run's, or the pooled refits' for runs
        that do not stand alone: see OWN_FIT), and weakened by what a check found in any run."""
        values, errors = self._reported
        relative = [relative_error_pct(float(value), float(error)) for value, error in zip(values, errors)]
        findings, scatters, spreads = [], (), []
        # Errors of rounding make no move or scatter count: a run's own (OWN_FIT), or every test's (a SysId dynamic
        # test alone fits its constant voltage exactly, whatever the noise).
        exact = (all if self.weighting == POOLED_FIT else any)(is_exact(run.result) for run in self.runs)
        if self.weighting == POOLED_FIT and not exact:
            spreads = list(pooled_refit_spreads(self))
        if self.weighting == OWN_FIT:
            for run in self.runs:
                findings += [Finding(name, f"{reason} in {run.name}") for name, reason in run.unsettled.items()
                             if name in self.shared]
            own = np.array([[run.params[name] for name in self.shared] for run in self.runs])
            own_errors = np.array([[run.noise_bse[name] for name in self.shared] for run in self.runs])
            scatters = () if exact else run_scatter(self.shared, own, own_errors, values)
            spreads = [] if exact else list(runs_spreads(self.shared, self.runs, own_errors))
        return judge(self.shared, relative, None, findings, scatters, spreads, values, errors)

    @cached_property
    def noise_bse(self) -> MappingProxyType:
        """The pooled standard errors from the noise alone (Newey-West within each run), by name."""
        return MappingProxyType(dict(zip(self.shared, map(float, self._reported[1]))))

    @property
    def verdicts(self) -> MappingProxyType:
        """The pooled parameters' verdicts by name, as the text, JSON and gains give them."""
        return self.judgement.by_name()

    @cached_property
    def scatter(self) -> dict[str, float]:
        """Each shared parameter's spread over the runs (standard deviation) in units of the runs' mean standard
        error: about 1 when the errors are honest, far above when the runs disagree beyond them."""
        out = {}
        for name in self.shared:
            values = [run.params[name] for run in self.runs]
            errors = [run.bse[name] for run in self.runs]
            mean_error = float(np.mean(errors))
            out[name] = float(np.std(values, ddof=1)) / mean_error if mean_error > 0 else math.inf
        return out

    @cached_property
    def disagreements(self) -> tuple[tuple[str, str, float], ...]:
        """(run, parameter, combined errors) where a run's own estimate differs from the pooled one by more than
        DISAGREEMENT of their combined noise-based standard errors (which the judgement then widens)."""
        found = []
        for run in self.runs:
            for name in self.shared:
                combined = math.hypot(run.noise_bse[name], self.noise_bse[name])  # the noise's: what they miss
                gap = abs(run.params[name] - self.params[name]) / combined if combined > 0 else 0.0
                if gap > DISAGREEMENT:
                    found.append((run.name, name, gap))
        return tuple(found)


POOLED_CHOICES = {"window halved": "the derivative window's choice", "window doubled": "the derivative window's choice",
                  "--no-robust": "the robust step's exclusions (--no-robust)"}
"""Each pooled refit, and what widened an error it moves beyond noise (the window halved and doubled are one choice,
which widens by the larger of their moves, as a single log fit's)."""


def pooled_refit_spreads(pooled: PooledRuns) -> tuple[Spread, ...]:
    """How far the pooled fit redone from every run's refit (window halved or doubled, --no-robust) moves the shared
    parameters beyond noise (refits.beyond_noise): for runs that do not stand alone (a SysId routine's tests),
    whose own checks say nothing of the pooled gains."""
    refits = [refits_of(run) for run in pooled.runs]
    values = np.array([pooled.params[name] for name in pooled.shared])
    noise = np.array([pooled.noise_bse[name] for name in pooled.shared])
    largest: dict[tuple[str, str], Spread] = {}
    for label, choice in POOLED_CHOICES.items():
        if not all(label in found for found in refits):
            continue
        redone = tuple(LoadedLogs(run.training, None, found[label]) for run, found in zip(pooled.runs, refits))
        again = pool_runs(redone, pooled.weighting)
        for spread in beyond_noise(pooled.shared, values, noise, [[again.params[name] for name in pooled.shared]],
                                   choice, [[again.noise_bse[name] for name in pooled.shared]]):
            key = (spread.name, spread.choice)
            if key not in largest or spread.error > largest[key].error:
                largest[key] = spread
    return tuple(largest.values())


def runs_spreads(shared, runs, noise_errors: np.ndarray) -> tuple[Spread, ...]:
    """The runs' own analysis spreads carried to the pooled fit: their mean weighted as the pool weighs them (the
    same choices move every run alike, so averaging does not shrink them); `noise_errors` (k, s)."""
    spreads = []
    with np.errstate(all="ignore"):
        weights = 1.0 / np.square(noise_errors)
    for j, name in enumerate(shared):
        own = []
        for run in runs:
            spread = run.result.judgement.spread
            index = run.result.model.names.index(name)
            own.append(spread[index] if spread else 0.0)
        total = float(np.sum(weights[:, j] * np.array(own)) / np.sum(weights[:, j]))
        if math.isfinite(total) and total > 0:
            spreads.append(Spread(name, total, "the runs' analysis choices"))
    return tuple(spreads)


def fit_runs(logs: list[JointLog], model: JointModel, filtering: FilterRequest = FilterRequest(),
             exclusion: ExclusionRequest = ExclusionRequest(), constrained: bool = False,
             sensitivity: bool = True, weighting: str = OWN_FIT) -> PooledRuns:
    """Fit each run alone, then all together (weighted as `weighting` says); ValueError with fewer than two
    runs."""
    if len(logs) < 2:
        raise ValueError("pooling needs at least two runs")
    return judged(pool_runs(tuple(fit_logs(log, None, model, constrained, filtering, sensitivity, exclusion)
                                  for log in logs), weighting))


def judged(pooled: PooledRuns) -> PooledRuns:
    """The pooled runs with their judgement computed now, in the caller's worker: a SysId routine's refits take
    seconds, which the explorer must not spend when it first shows the verdicts."""
    _ = pooled.judgement
    return pooled


def add_run(current: LoadedLogs | PooledRuns, log: JointLog, model: JointModel, constrained: bool = False,
            sensitivity: bool = True) -> PooledRuns:
    """The runs so far (one fitted log, or pooled runs) with one more run, prepared and fitted as the first was
    (its low-pass request and exclusions), then all pooled again; the runs already fitted are not refitted."""
    runs = current.runs if isinstance(current, PooledRuns) else (current,)
    first = runs[0]
    added = fit_logs(log, None, model, constrained, first.filtering, sensitivity, first.exclusion)
    weighting = current.weighting if isinstance(current, PooledRuns) else OWN_FIT
    return judged(pool_runs((*runs, added), weighting))


def pool_runs(runs: tuple[LoadedLogs, ...], weighting: str = OWN_FIT) -> PooledRuns:
    """Runs each already fitted alone (with one model), fitted together and each predicted by the others."""
    model = runs[0].result.model
    everyone = tuple(range(len(runs)))
    weights = _own_weights(runs) if weighting == OWN_FIT else _pooled_weights(runs)
    triangles = _triangles(runs, weights)
    estimate, std_error, covariance = _pool(runs, everyone, triangles, weights)
    others = tuple(_predicted_by_others(runs, triangles, index, weights) for index in everyone)
    shared = tuple(name for name, term in zip(model.names, model.terms) if term.kind != BIAS)
    return PooledRuns(runs, shared, estimate, std_error, weights, others, covariance, weighting)


def _own_weights(runs: tuple[LoadedLogs, ...]) -> tuple[float, ...]:
    """1 / each run's residual variance in its own fit."""
    weights = []
    for run in runs:
        result = run.result
        residuals = result.training.tau - result.training_predictions
        weights.append(1.0 / max(float(np.mean(residuals**2)), 1e-300))
    return tuple(weights)


def _pooled_weights(runs: tuple[LoadedLogs, ...]) -> tuple[float, ...]:
    """1 / each run's residual variance against the runs' equally weighted pooled fit (its own bias fitted)."""
    equal = (1.0,) * len(runs)
    triangles = _triangles(runs, equal)
    estimate, _, _ = _pool(runs, tuple(range(len(runs))), triangles, equal)
    if not np.all(np.isfinite(estimate)):
        return _own_weights(runs)
    weights = []
    for k, (X, bias, tau, _, _, _) in enumerate(_blocks(runs, tuple(range(len(runs))), equal)):
        residuals = tau - X @ estimate[: X.shape[1]]
        if bias is not None:
            residuals = residuals - bias * estimate[X.shape[1] + k]
        weights.append(1.0 / max(float(np.mean(residuals**2)), 1e-300))
    return tuple(weights)


def _blocks(runs: tuple[LoadedLogs, ...], chosen: tuple[int, ...], weights: tuple[float, ...]):
    """Each chosen run's kept, filtered rows: (shared columns, bias column or None, torque, positions, lag,
    weight)."""
    for index in chosen:
        result = runs[index].result
        X = result.training_regressor
        shared = [j for j, term in enumerate(result.model.terms) if term.kind != BIAS]
        bias = result.model.index_of(BIAS)
        weight = weights[index]
        positions, lag = result.correlation if result.correlation is not None else (np.arange(len(X)), 0)
        yield X[:, shared], None if bias is None else X[:, bias], result.training.tau, positions, lag, weight


def _pool(runs: tuple[LoadedLogs, ...], chosen: tuple[int, ...], triangles: list[np.ndarray],
          weights: tuple[float, ...]):
    """(estimate, standard errors, covariance) of the fit of the chosen runs together with their `weights`,
    solved from their `triangles` (see `_triangles`); the covariance is None without a unique fit."""
    blocks = list(_blocks(runs, chosen, weights))
    shared, has_bias = blocks[0][0].shape[1], blocks[0][1] is not None
    solution = solve_least_squares(*_stacked([triangles[index] for index in chosen], shared, has_bias))
    if solution.estimate is None:
        size = solution.column_count
        return np.full(size, np.nan), np.full(size, np.nan), None
    factor = covariance_factor(solution)
    meat = np.zeros_like(factor)
    for k, (X, bias, tau, positions, lag, weight) in enumerate(blocks):
        # Each run's Newey-West sum over its own columns only (the shared ones and its bias): the other runs'
        # bias columns are zero in its rows.
        columns = list(range(shared)) + ([shared + k] if has_bias else [])
        scale = math.sqrt(weight)
        own = (X if bias is None else np.column_stack([X, bias])) * scale
        meat[np.ix_(columns, columns)] += newey_west_sum(own, tau * scale - own @ solution.estimate[columns],
                                                         positions, lag)[0]
    covariance = factor @ meat @ factor
    return solution.estimate, np.sqrt(np.diag(covariance)), covariance


def _stacked(triangles: list[np.ndarray], shared: int, has_bias: bool) -> tuple[np.ndarray, np.ndarray]:
    """(rows, targets) of the pooled least squares from the runs' triangles: the shared columns, then each run's
    bias in a column of its own."""
    offsets = len(triangles) if has_bias else 0
    rows = np.zeros((sum(len(triangle) for triangle in triangles), shared + offsets))
    targets = np.empty(len(rows))
    first = 0
    for position, triangle in enumerate(triangles):
        block = slice(first, first + len(triangle))
        rows[block, :shared], targets[block] = triangle[:, :shared], triangle[:, -1]
        if has_bias:
            rows[block, shared + position] = triangle[:, shared]
        first += len(triangle)
    return rows, targets


def _triangles(runs: tuple[LoadedLogs, ...], weights: tuple[float, ...]) -> list[np.ndarray]:
    """Each run's weighted rows reduced to the triangle of [shared columns | its bias column, if any | torque]
    (see triangle_of): every leave-one-run-out pool is solved from the other runs' triangles, the same least
    squares in a few dozen rows, where stacking their tens of thousands of rows again took most of pooling."""
    out = []
    for X, bias, tau, _, _, weight in _blocks(runs, tuple(range(len(runs))), weights):
        scale = math.sqrt(weight)
        columns = (X if bias is None else np.column_stack([X, bias])) * scale
        # Blocked above one block's rows: LAPACK's QR of a whole run (thousands of rows) woke OpenBLAS's
        # threads, 3.5 ms a run against 0.1 ms.
        out.append(triangle_of(columns, tau * scale, direct_rows=block_rows_for(columns.shape[1])))
    return out


def _predicted_by_others(runs: tuple[LoadedLogs, ...], triangles: list[np.ndarray], index: int,
                         weights: tuple[float, ...]) -> float | None:
    """RMS of run `index`'s filtered torque less the other runs' pooled prediction, its offset its own
    (`triangles`: each run's, see `_triangles`)."""
    X, bias, tau, _, _, _ = next(_blocks(runs, (index,), weights))
    others = [triangle for k, triangle in enumerate(triangles) if k != index]
    estimate = solve_least_squares(*_stacked(others, X.shape[1], bias is not None)).estimate
    if estimate is None or not np.all(np.isfinite(estimate)):
        return None
    residual = tau - X @ estimate[:X.shape[1]]
    return float(np.sqrt(np.mean((residual - residual.mean()) ** 2)))
