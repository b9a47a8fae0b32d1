"""The model ladder: fit every model of `model.LADDER` on the same data and let BIC choose.

Every model of the ladder is `plain` plus some of the columns sign(qd), 1 and
g*sin(q), so one pass over the data serves them all: the triangular factor R
of the column-scaled [X_all | y] (X_all holding every column once) gives each
model's least-squares problem exactly, ||y - X_S theta|| = ||r_y - R_S theta||,
and column norms are the same in R as in X, so the pivoted factorisation of
R_S makes the rank decisions the full data would. Only R (7 x 7) is kept.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from ..estimation.fit import fitted_torque
from ..estimation.solver import LeastSquaresSolution, solve_least_squares, triangle_of
from ..estimation.uncertainty import ParameterUncertainty, parameter_uncertainty
from ..model.effort import TORQUE, Effort
from ..model.terms import JointModel, model_named
from ..options import LADDER
from ..samples import JointData, rms
from ..synthetic.samples import training_data, validation_data
from ..synthetic.settings import Settings

ALL_COLUMNS = model_named("coulomb+bias+angle-offset")
"""A model with every column any ladder model uses, each once (h_c is the plain model's h column)."""


def column_indices(model: JointModel) -> list[int]:
    """Where each of a model's columns sits in ALL_COLUMNS (the plain h column is h_c there; a voltage model's
    columns by the torque terms they stand for)."""
    kinds = [term.kind for term in ALL_COLUMNS.terms]
    return [kinds.index("h_c" if term.kind == "h" else term.kind) for term in model.terms]


@dataclass(frozen=True, eq=False)
class LadderRow:
    """One model's fit: its solution, reported estimate and uncertainty, errors and BIC."""

    model: JointModel
    solution: LeastSquaresSolution
    """The model's least-squares solution (row_count is the data's N)."""
    training_rmse: float | None
    heldout_rmse: float | None
    uncertainty: ParameterUncertainty | None
    independent: float | None = None
    """How many independent samples the N are worth (low-passed samples closer than 1 / (2 cutoff) are not), or
    None: all N."""
    offsets: int = 0
    """Parameters beyond the model's own columns: each pooled run's own bias after the first (counted in BIC)."""

    @property
    def rank(self) -> int:
        """Numerical rank of the model's regressor."""
        return self.solution.rank

    @property
    def estimate(self) -> np.ndarray | None:
        """(p,) Reported parameters, or None below full rank."""
        if self.solution.estimate is None:
            return None
        return self.model.report(self.solution.estimate[: self.model.size])

    @property
    def condition_number(self) -> float:
        """Condition number of the column-scaled regressor (inf when rank-deficient)."""
        return self.solution.condition_number

    @cached_property
    def bic(self) -> float | None:
        """n ln(RSS/N) + k ln n (k parameters, n the independent samples, N all), -inf for a perfect fit; None
        without a unique fit. Counting correlated samples as independent would let every term pay for itself."""
        if self.solution.estimate is None:
            return None
        count, norm = self.solution.row_count, float(self.solution.residual_norm)
        independent = count if self.independent is None else self.independent
        # ln(RSS/N) from the norm: its square overflows for torques beyond 1e154 that a fit handles.
        fit_term = -math.inf if norm == 0 else independent * (2 * math.log(norm) - math.log(count))
        return fit_term + (self.model.size + self.offsets) * math.log(independent)

    @cached_property
    def worst_determined(self) -> tuple[str, float] | None:
        """(name, relative standard error %) of the least well determined parameter, or None."""
        if self.uncertainty is None or self.uncertainty.relative_std_pct is None:
            return None
        relative = self.uncertainty.relative_std_pct[: self.model.size]  # not the pooled runs' other offsets
        index = int(np.argmax(relative))
        return self.model.names[index], float(relative[index])


@dataclass(frozen=True, eq=False)
class Comparison:
    """Every ladder model fitted to the same training data (and scored on the same held-out data)."""

    rows: tuple[LadderRow, ...]
    samples: int
    """N, the training samples every model saw."""
    run_preferences: tuple[tuple[str, str | None], ...] = ()
    """(run, the model BIC prefers for it alone) of each pooled run; () for one log or an experiment."""

    def row(self, name: str) -> LadderRow:
        """The row of the model named `name`."""
        return next(row for row in self.rows if row.model.name == name)

    @cached_property
    def preferred(self) -> LadderRow | None:
        """The model with the lowest BIC (the simpler one on a tie), or None when no model has a unique fit."""
        ranked = [row for row in self.rows if row.bic is not None]
        return min(ranked, key=lambda row: (row.bic, row.model.size)) if ranked else None


def compare_models(training: JointData, heldout: JointData | None = None, *, noise_bound: float | None = None,
                   models: tuple[str, ...] = LADDER, low_pass=None, kept=None, regressor=None,
                   effort: Effort = TORQUE, heldout_regressor: np.ndarray | None = None) -> Comparison:
    """Fit each named model to the training data from one factorisation, and score it on the held-out data.

    `low_pass` (a low_pass.ParallelFilter) filters every column and the torque
    alike before the fits, as a log fit does; `kept` (after the filter and
    decimation) leaves out what a log fit's robust step and standstill found,
    so that pushes do not decide the model. `regressor` (N, columns + 1)
    replaces ALL_COLUMNS' regressor with the torque as its last column (a
    log's, smoothed like its derivatives). `effort`: what the torque column holds (a voltage log's models are
    fitted in volts). `heldout_regressor` (M, columns) replaces ALL_COLUMNS' regressor of the held-out states (a
    held-out log through the training log's pipeline, with `heldout.tau` filtered alike).
    """
    every = ALL_COLUMNS.in_effort(effort)
    if regressor is None:
        X, tau = every.data_regressor(training), training.tau
    else:
        X, tau = regressor[:, :-1], regressor[:, -1]
    if low_pass is not None and (low_pass.active or low_pass.decimation > 1):
        X, tau = low_pass.apply(X), low_pass.apply_column(tau)
    if kept is not None:
        X, tau = X[kept], tau[kept]
    count = len(tau)
    independent = None
    if low_pass is not None and low_pass.active:
        independent = count * min(1.0, 2.0 * low_pass.cutoff * low_pass.decimation / low_pass.rate)
    factor = triangle_of(X, tau)
    heldout_X = heldout_regressor if heldout_regressor is not None or heldout is None else every.data_regressor(heldout)
    rows = []
    for name in models:
        model = model_named(name).in_effort(effort)
        columns = column_indices(model)
        small = solve_least_squares(factor[:, columns], factor[:, -1])
        solution = replace(small, row_count=count)
        heldout_rmse = None
        if heldout_X is not None and solution.estimate is not None:
            heldout_rmse = rms(fitted_torque(heldout_X[:, columns], solution.estimate) - heldout.tau)
        training_rmse = None
        if solution.estimate is not None:
            training_rmse = float(solution.residual_norm) / math.sqrt(count)
        rows.append(LadderRow(model, solution, training_rmse, heldout_rmse,
                              parameter_uncertainty(solution, noise_bound, model), independent))
    return Comparison(tuple(rows), count)


def compare_log(logs, *, models: tuple[str, ...] = LADDER) -> Comparison:
    """The ladder on a fitted log (a jointid.studies.log_fit.LoadedLogs), as `jointid compare --csv` and the
    explorer's ladder build it: the log's smoothed columns through its fit's low-pass, less the pushes its robust
    step found (standstill decides no model), and its held-out log through the training log's pipeline (as the
    fit's own held-out check), or as it is when the pipeline cannot take it."""
    from .log_fit import heldout_as_fitted, smoothed_regressor  # the log path loads only for a log

    training, heldout = logs.training, logs.heldout
    every = ALL_COLUMNS.in_effort(training.effort)
    kept = None if logs.exclusions is None else ~logs.exclusions.pushes
    predicted = None if heldout is None else heldout_as_fitted(training, heldout, every, logs.filter,
                                                               logs.exclusion, None)
    return compare_models(training.data, None if heldout is None else heldout.data if predicted is None else
                          predicted[0], models=models, low_pass=logs.filter, kept=kept,
                          regressor=smoothed_regressor(training, every), effort=training.effort,
                          heldout_regressor=None if predicted is None else predicted[1])


def compare_runs(blocks, *, models: tuple[str, ...] = LADDER, effort: Effort = TORQUE) -> Comparison:
    """The ladder on several runs' samples stacked: `blocks` holds each run's (ALL_COLUMNS regressor, torque,
    independent samples or None) already filtered and kept as its own fit did. A model with a bias gives each run
    its own (as the pooled fit does), counted in BIC; BIC's n is every run's independent samples together."""
    every = ALL_COLUMNS.in_effort(effort)
    bias = [term.kind for term in every.terms].index("tau0")
    sizes = [len(tau) for _, tau, _ in blocks]
    edges = np.cumsum([0, *sizes])
    X = np.concatenate([regressor for regressor, _, _ in blocks])
    tau = np.concatenate([values for _, values, _ in blocks])
    # The bias column becomes the first run's own; each other run's is a column of its own after ALL_COLUMNS'.
    indicators = np.zeros((len(tau), len(blocks)))
    for k, (first, last) in enumerate(zip(edges[:-1], edges[1:])):
        indicators[first:last, k] = 1.0
    X[:, bias] = indicators[:, 0]
    stacked = np.column_stack([X, indicators[:, 1:]])
    counts = [independent for _, _, independent in blocks]
    independent = None if all(c is None for c in counts) else float(
        sum(size if c is None else c for size, c in zip(sizes, counts)))
    factor = triangle_of(stacked, tau)
    extra = list(range(X.shape[1], stacked.shape[1]))
    count = len(tau)
    rows = []
    for name in models:
        model = model_named(name).in_effort(effort)
        offsets = extra if model.index_of("tau0") is not None else []
        solution = replace(solve_least_squares(factor[:, column_indices(model) + offsets], factor[:, -1]),
                           row_count=count)
        training_rmse = None if solution.estimate is None else float(solution.residual_norm) / math.sqrt(count)
        # Offsets of other runs have no reported form: the uncertainty is of the columns (no angle offset with a
        # bias in the ladder).
        uncertainty = parameter_uncertainty(solution, None, None if offsets else model)
        rows.append(LadderRow(model, solution, training_rmse, None, uncertainty, independent, len(offsets)))
    return Comparison(tuple(rows), count)


def compare_pooled(runs) -> Comparison:
    """The ladder on pooled runs (studies.runs.PooledRuns' LoadedLogs, each filtered and left out as its own fit
    was), with each run's own preferred model beside it."""
    from .log_fit import filtered_regressors  # the log pipeline, loaded only for logs

    effort = runs[0].result.model.effort
    every = ALL_COLUMNS.in_effort(effort)
    blocks = []
    for run in runs:
        (X, tau), = filtered_regressors(run.training, every, (run.filter,))
        kept = np.ones(len(tau), dtype=bool) if run.exclusions is None else ~run.exclusions.pushes
        chosen = run.filter
        independent = None
        if chosen.active:  # as compare_models counts a low-passed log's samples
            independent = int(kept.sum()) * min(1.0, 2.0 * chosen.cutoff * chosen.decimation / chosen.rate)
        blocks.append((X[kept], tau[kept], independent))
    alone = tuple((run.name, _preferred_name(compare_runs([block], effort=effort)))
                  for run, block in zip(runs, blocks))
    return replace(compare_runs(blocks, effort=effort), run_preferences=alone)


def _preferred_name(comparison: Comparison) -> str | None:
    """The name of the model BIC prefers, or None."""
    return None if comparison.preferred is None else comparison.preferred.model.name


def compare_experiment(settings: Settings) -> Comparison:
    """The ladder on a synthetic experiment's training data, scored on its noiseless validation motion."""
    return compare_models(training_data(settings), validation_data(settings.true_joint), noise_bound=settings.noise)
