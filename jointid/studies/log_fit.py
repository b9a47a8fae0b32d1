"""Fitting joint logs: load a training log and an optional held-out log, fit one, predict the other.

Both faces use this: `jointid fit --csv` and the explorer's log mode fit the
same way, so their readouts and JSON agree. The parallel low-pass
(jointid.estimation.low_pass) is applied here, to the model's regressor columns and
the torque alike, because it must act on the columns rather than on q; and the
sensitivity check (jointid.studies.sensitivity) refits here with the derivative window
and the cutoff halved and doubled.
"""

from __future__ import annotations

import contextlib
import math
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from types import MappingProxyType

import numpy as np

from ..checks import checked, flag, optional, pairs, real, text, whole
from ..estimation.exclusion import (ExclusionRequest, Exclusions, commanded_changes, explained_transients,
                                    outside_torques, standstill)
from ..estimation.fit import FitResult, fit_joint, with_judgement
from ..estimation.judgement import Finding, Judgement, Spread, judge, noise_judgement
from ..estimation.low_pass import (FilterRequest, FilterRequestError, ParallelFilter, choose_filter,
                                   low_passed_together, shared_size)
from ..estimation.omitted import OmittedTerms, omitted_terms_test
from ..estimation.solver import NonFiniteError
from ..logs.derivatives import MAX_WINDOW, smooth
from ..logs.pipeline import JointLog
from ..logs.request import HELDOUT, TRAINING, LoadRequest, load_joint_log
from ..logs.table import LoadCancelled, LogError
from ..memory import available_memory, in_words
from ..model.terms import CANDIDATE_TERMS, PLAIN, JointModel, Term, in_effort, model_argument, model_named
from ..norms import rms
from ..options import DEFAULT_ORDER, model_extras
from ..samples import JointData
from ..text_safety import shown_name
from ..threads import map_in_threads
from .angle_models import check_angle_model
from .refits import ROBUST_CHOICE, beyond_noise, is_exact, robust_refit, robust_spreads, stretch_scatter
from .sensitivity import FACTORS, SensitivityCheck, Variant, sensitivity_check


FIT_BUDGET = 400_000_000
"""Most work a log fit takes on, in samples fitted x (their correlation lag + ROBUST_COST): about ten seconds with
its refits, e.g. a million samples unfiltered or 200,000 at full rate under a long low-pass."""

ROBUST_COST = 250
"""The robust step's and the solver's work per fitted sample, in lags of the standard errors' correlation sum."""

FIT_BYTES_PER_SAMPLE = 800
"""Memory a log fit (refits and robust step included) takes per fitted sample beyond the loaded log: the peak
resident set of `fit --decimate 1` grew by 690 bytes a row from 250,000 to 500,000 rows (250 and 423 MB), with a
margin."""


def fit_memory(count: int, decimation: int) -> int:
    """Bytes a fit of `count` samples decimated by `decimation` needs beyond the loaded log."""
    return -(-count // decimation) * FIT_BYTES_PER_SAMPLE


@dataclass(frozen=True, eq=False)
class LoadedLogs:
    """The training log, the optional held-out log, and the fit of one to the other."""

    training: JointLog
    heldout: JointLog | None
    result: FitResult
    filter: ParallelFilter | None = None
    """The low-pass and decimation the training data went through, or None when not applied."""
    filtering: FilterRequest = FilterRequest()
    """The request the filter was chosen from, kept for refits (another model)."""
    sensitivity: SensitivityCheck | None = None
    """The refits with the window and cutoff halved and doubled, or None without a unique fit."""
    exclusions: Exclusions | None = None
    """What the fit left out of the training log (standstill, outside torques), or None without times."""
    exclusion: ExclusionRequest = ExclusionRequest()
    """The request the exclusions were made from, kept for refits (another model)."""
    omitted: OmittedTerms | None = None
    """The test of terms the model lacks (friction, bias, angle offset, drag) against the residuals, or None."""
    mechanism: object | None = None
    """The studies.mechanism.MechanismChoice a SysId test was fitted as, or None for other logs."""
    heldout_pipeline: tuple[Exclusions | None, ParallelFilter] | None = None
    """What the held-out log's check left out and the low-pass it went through, as the training log's fit did;
    None without a held-out log, or when it was predicted as it is (too short for the filter, say)."""
    offset: tuple[str, np.ndarray, np.ndarray] | None = None
    """(what it is, e.g. 'an angle offset in place of the torque bias', the reported estimate and its noise-based
    errors by the fitted model's names, NaN where it has no such parameter) of the refit that explains a torque
    offset the other way; None when the model has not exactly one of the two or the refit failed."""

    def __repr__(self) -> str:
        return f"<LoadedLogs {self.name!r} {self.result!r}>"

    @property
    def params(self) -> Mapping[str, float]:
        """Fitted parameters by name, as `FitResult.params`."""
        return self.result.params

    @property
    def bse(self) -> Mapping[str, float]:
        """Standard errors by name, as `FitResult.bse` (from the residuals: a log has no known noise bound)."""
        return self.result.bse

    @property
    def noise_bse(self) -> Mapping[str, float]:
        """The standard errors from the noise alone, by name, before the judgement widened them (`bse`)."""
        errors = None if self.result.uncertainty is None else self.result.uncertainty.noise_std_error
        values = np.full(len(self.result.model.names), np.nan) if errors is None else errors
        return MappingProxyType(dict(zip(self.result.model.names, map(float, values))))

    def conf_int(self, alpha: float = 0.05) -> Mapping[str, tuple[float, float]]:
        """(low, high) intervals by name, as `FitResult.conf_int`."""
        return self.result.conf_int(alpha)

    def notes(self) -> tuple[str, ...]:
        """How each log was read, timed, differentiated and low-passed: the `Note:` lines of `jointid fit --csv`."""
        from ..present.summary import log_notes  # presentation, loaded only when asked

        return log_notes(self)

    def summary(self) -> str:
        """The text `jointid fit --csv` prints for these logs."""
        from ..present.summary import log_fit_summary  # presentation, loaded only when asked

        return log_fit_summary(self)

    @property
    def moved_by_settings(self) -> tuple[str, ...]:
        """Parameters the sensitivity check moved beyond its threshold."""
        check = self.sensitivity
        if check is None:
            return ()
        return tuple(name for name, flagged in zip(check.names, check.flags) if flagged)

    @property
    def decided_by_omitted(self) -> tuple[str, ...]:
        """Parameters a term the model lacks would move beyond MOVE standard errors (the residuals follow it)."""
        if self.omitted is None:
            return ()
        model = self.result.model
        decided = set(self.omitted.decided)
        return tuple(name for name, column in zip(model.names, model.column_names) if column in decided)

    @property
    def unsettled(self) -> dict[str, str]:
        """Parameters a check moved in a way no error describes (a term the model lacks), each with why: not well
        determined, whatever their error."""
        reasons: dict[str, str] = {}
        for finding in log_findings(self):
            reasons.setdefault(finding.name, finding.reason)
        return reasons

    @property
    def verdicts(self) -> Mapping[str, str | None]:
        """Each parameter's verdict from every check, by name, as the text and JSON give it (`FitResult.verdicts`)."""
        return self.result.verdicts

    @property
    def judgement(self) -> Judgement:
        """The verdicts, the noise-only verdicts and why they differ (`FitResult.judgement`)."""
        return self.result.judgement

    @property
    def name(self) -> str:
        """The training file's name (a data log's SysId test), e.g. for the explorer's motion list."""
        return self.training.name

    @property
    def heldout_name(self) -> str | None:
        """The held-out file's name, or None."""
        return None if self.heldout is None else shown_name(os.path.basename(os.path.normpath(self.heldout.path)))

    @property
    def logs(self) -> tuple[JointLog, ...]:
        """The training log, then the held-out log when there is one."""
        return (self.training,) if self.heldout is None else (self.training, self.heldout)

    def source_lines(self) -> tuple[str, ...]:
        """What was read: 'Training log PATH: N rows ...' and the same for the held-out log."""
        roles = ("Training log", "Held-out log")
        return tuple(f"{role} {text}" for role, text in zip(roles, self.source_texts()))

    def source_texts(self) -> tuple[str, ...]:
        """Each log's source_text, the training log's with the samples fitted, and what left the others out: one
        count in every face ('1170 samples, 351 fitted after the low-pass, decimation and what was left out')."""
        texts = [log.source_text() for log in self.logs]
        chosen, left = self.filter, self.exclusions
        left_out = left is not None and not left.kept.all()
        texts[0] += f", {self.result.training.count} fitted"
        if chosen is not None and (chosen.active or chosen.decimation > 1 or left_out):
            steps = [step for step, used in (("the low-pass", chosen.active), ("decimation", chosen.decimation > 1),
                                             ("what was left out", left_out)) if used]
            texts[0] += f" after {', '.join(steps[:-1])}{' and ' if len(steps) > 1 else ''}{steps[-1]}"
        if self.heldout_pipeline is not None:
            texts[1] += f", {self.result.heldout.count} predicted after the same pipeline"
        return tuple(texts)



def fit_logs(training: JointLog, heldout: JointLog | None = None, model: JointModel = PLAIN,
             constrained: bool = False, filtering: FilterRequest = FilterRequest(),
             sensitivity: bool = True, exclusion: ExclusionRequest = ExclusionRequest()) -> LoadedLogs:
    """Fit the training log (subject to the sign rules when `constrained`) and score it on the held-out log.

    The training regressor and torque are low-passed alike as `filtering` asks
    (automatic by default); with `sensitivity`, the fit is repeated with the
    derivative window and the cutoff halved and doubled (the stretches left out
    for outside torques kept as found). `exclusion` says what to leave out
    (the robust step by default). LogError when the
    numbers leave double precision (an estimate or an RMSE that overflows would
    otherwise be shown as if it were a result) or the filter cannot apply.
    """
    model = model.in_effort(training.effort)
    check_angle_model(training, model)  # every face fits here: no cos(q) of metres, nor of a velocity's sum
    if heldout is not None and heldout.effort != training.effort:
        raise LogError(heldout.path, f"holds {heldout.effort.name} ({heldout.effort.unit}) but the training log "
                       f"{training.effort.name} ({training.effort.unit}); read both alike (--effort)")
    chosen = low_pass_for(training, filtering)
    check_work(training, chosen, explicit=filtering.decimate is not None)
    others = _cutoff_variants(training, chosen) if sensitivity else []
    # Each full-rate column is built once and low-passed by the chosen filter and the sensitivity check's
    # cutoff refits' alike, so no full-rate regressor is held.
    candidates = _candidates(model) if chosen.active else ()  # the test needs the low-pass's correlation
    # The offset refit's model shares most columns (column functions) with this one and the candidates: only its
    # others are added.
    alternative = offset_alternative(model) if sensitivity else None
    known = {term.column for term in (*model.terms, *candidates)}
    extras = candidates + tuple(term for term in (() if alternative is None else alternative[0].terms)
                                if term.column not in known)
    filtered = filtered_regressors(training, model, (chosen, *(other for _, _, other in others)), extras)
    extra_columns = filtered.pop()[0] if extras else np.empty((0, 0))
    candidate_columns = extra_columns[:, :len(candidates)] if candidates else None
    through_chosen = {term.column: column for term, column in zip((*model.terms, *extras),
                                                                   (*filtered[0][0].T, *extra_columns.T))}
    result, exclusions = _fit(training, heldout, model, constrained, chosen, filtered[0], exclusion)
    predicted = None if heldout is None else heldout_as_fitted(
        training, heldout, model, chosen, exclusion, None if exclusions is None else exclusions.estimate)
    if predicted is not None:
        result = replace(result, heldout=predicted[0], heldout_regressor=predicted[1])
    with np.errstate(over="ignore", invalid="ignore"):  # checked here, with the file named
        scores = ((training, result.training_rmse), (heldout, result.heldout_rmse))
    for log, rmse in scores:
        if rmse is not None and not math.isfinite(rmse):
            raise LogError(
                log.path, "its predicted torques overflow double precision; rescale its columns (other units)"
            )
    check = _sensitivity(training, model, constrained, chosen, result, zip(others, filtered[1:]), exclusion,
                         exclusions) if sensitivity else None
    omitted = _omitted_terms(model, candidates, candidate_columns, result, exclusions)
    offset = _offset_refit(training, model, constrained, chosen, result, exclusion, exclusions,
                           (through_chosen, filtered[0][1])) if sensitivity else None
    logs = LoadedLogs(training, heldout, result, chosen, filtering, check, exclusions, exclusion, omitted,
                      heldout_pipeline=None if predicted is None else predicted[2:], offset=offset)
    return replace(logs, result=with_judgement(result, judge_log(logs)))


TERM_MOVED = "moved by a term the model lacks"
"""Why the omitted-terms test weakens a verdict (its sentence names the term)."""

SETTING_CHOICES = {"window": "the derivative window's choice", "cutoff": "the cutoff's choice"}
"""What widened an error that the sensitivity check's refits of each setting move beyond noise."""


def log_findings(logs: LoadedLogs) -> tuple[Finding, ...]:
    """What the log fit's checks found against its parameters that no error describes: the omitted-terms test's
    moves."""
    return tuple(Finding(name, TERM_MOVED) for name in logs.decided_by_omitted)


def log_spreads(logs: LoadedLogs) -> tuple[Spread, ...]:
    """How far the log fit's other reasonable analysis choices move its parameters beyond noise: the derivative
    window and the cutoff halved and doubled, the robust step's exclusions, a torque offset explained the other
    way (each choice's largest move, less one noise standard error in quadrature: refits.beyond_noise)."""
    result = logs.result
    if result.estimate is None or result.uncertainty is None or is_exact(result):
        return ()
    names, estimate, noise = result.model.names, result.estimate, result.uncertainty.noise_std_error
    if noise is None:
        return ()
    spreads: list[Spread] = []
    check = logs.sensitivity
    if check is not None:
        for setting, choice in SETTING_CHOICES.items():
            variants = [variant for variant in check.variants if variant.setting == setting]
            spreads += beyond_noise(names, estimate, noise, [variant.estimate for variant in variants], choice,
                                    [variant.std_error for variant in variants])
    left = logs.exclusions
    if left is not None and left.regressor is not None:
        spreads += robust_spreads(result, left, _by_hand(logs))
    if logs.offset is not None:
        choice, other, errors = logs.offset
        shared = np.isfinite(other)
        spreads += beyond_noise(names, estimate, noise, [np.where(shared, other, estimate)], choice,
                                [np.where(shared, errors, noise)])
    return tuple(spreads)


def _by_hand(logs: LoadedLogs) -> np.ndarray:
    """(kept,) The filtered samples left out by hand (--exclude), which every refit leaves out too."""
    left = logs.exclusions
    by_hand = np.zeros(len(left.since), dtype=bool)
    for start, end in logs.exclusion.by_hand:
        by_hand |= (left.since >= start) & (left.since <= end)
    return by_hand


def ratio_spread(logs: LoadedLogs) -> float:
    """How far the log fit's analysis choices (as log_spreads) move h/I beyond its noise error, in quadrature over
    the choices; 0 when the fit states no ratio (FitResult.scale_ratio) or nothing moves it beyond noise."""
    result = logs.result
    scale = result.scale_ratio
    if scale is None or result.estimate is None or is_exact(result):
        return 0.0
    model = result.model
    inertia, gravity = (model.names.index(model.terms[model.index_of(kind)].name) for kind in ("I", "h"))

    def ratio(estimate) -> float:
        return float(estimate[gravity] / estimate[inertia])

    moved: dict[str, list[float]] = {}
    for variant in () if logs.sensitivity is None else logs.sensitivity.variants:
        moved.setdefault(SETTING_CHOICES[variant.setting], []).append(ratio(variant.estimate))
    left = logs.exclusions
    kept_in = None if left is None or left.regressor is None else robust_refit(result, left, _by_hand(logs))
    if kept_in is not None:
        moved[ROBUST_CHOICE] = [ratio(kept_in)]
    if logs.offset is not None:
        moved[logs.offset[0]] = [ratio(logs.offset[1])]
    with np.errstate(all="ignore"):
        found = [spread.error for choice, ratios in moved.items() for spread in beyond_noise(
            ("h/I",), np.array([ratio(result.estimate)]), np.array([scale[2]]), [[value] for value in ratios], choice)]
    return math.sqrt(sum(error * error for error in found))


def judge_log(logs: LoadedLogs) -> Judgement:
    """Each parameter of a log fit judged once: its noise-based error widened by the other analysis choices'
    moves and the scatter of the run's stretches, and weakened by the checks' findings."""
    result = logs.result
    uncertainty = result.uncertainty
    if uncertainty is None:
        return noise_judgement(result.model.names, None)
    judged = judge(result.model.names, uncertainty.noise_relative_std_pct, uncertainty.held, log_findings(logs),
                   () if is_exact(result) else stretch_scatter(result), log_spreads(logs), result.estimate,
                   uncertainty.noise_std_error)
    return replace(judged, ratio_spread=ratio_spread(logs))


def offset_alternative(model: JointModel) -> tuple[JointModel, str] | None:
    """The model with its torque offset explained the other way (a torque bias <-> an angle offset, which a joint
    swinging about one angle can hardly tell apart) and what that is, or None when it has not exactly one of
    them."""
    try:
        extras = set(model_extras(model.name))
    except ValueError:  # a mechanism's model (simple, elevator) or one of the caller's own
        return None
    if ("bias" in extras) == ("angle-offset" in extras):
        return None
    if "bias" in extras:
        swapped, choice = (extras - {"bias"}) | {"angle-offset"}, "an angle offset in place of the torque bias"
    else:
        swapped, choice = (extras - {"angle-offset"}) | {"bias"}, "a torque bias in place of the angle offset"
    return model_named("+".join(sorted(swapped))).in_effort(model.effort), choice


def _offset_refit(training: JointLog, model: JointModel, constrained: bool, chosen: ParallelFilter,
                  result: FitResult, exclusion: ExclusionRequest, exclusions: Exclusions | None,
                  low_passed: tuple[dict, np.ndarray] | None = None) -> tuple[str, np.ndarray, np.ndarray] | None:
    """(what it is, the reported estimate and its noise-based errors by `model`'s names, NaN where the other model
    has no such parameter) of the fit with a torque offset explained the other way, leaving out what the fit left
    out; None without one. `low_passed`: (columns by their column function, torque) already through `chosen`, when
    they hold the other model's every column."""
    alternative = offset_alternative(model)
    if alternative is None or result.estimate is None or result.bounded is not None:
        return None
    other, choice = alternative
    columns, torque = ({}, None) if low_passed is None else low_passed
    X = np.column_stack([columns[term.column] for term in other.terms]) if all(
        term.column in columns for term in other.terms) else None
    try:
        check_angle_model(training, other)
        found = None if exclusions is None else exclusions.excluded
        # Columns of extreme magnitude can leave double precision in the other model's angle offset: no choice.
        with np.errstate(all="ignore"):
            fit, _ = _fit(training, None, other, constrained, chosen, None if X is None else (X, torque), exclusion,
                          found)
            errors = _noise_errors(fit)
    except (LogError, FloatingPointError):  # nothing left to fit with it, say: no such choice
        return None
    if fit.estimate is None or errors is None or not (np.all(np.isfinite(fit.estimate))
                                                      and np.all(np.isfinite(errors))):
        return None
    by_name = dict(zip(other.names, zip(fit.estimate, errors)))
    found = np.array([by_name.get(name, (np.nan, np.nan)) for name in model.names], dtype=float)
    return choice, found[:, 0], found[:, 1]


def _candidates(model: JointModel) -> tuple[Term, ...]:
    """The candidate terms the model lacks, in its effort, for the omitted-terms test."""
    kinds = {term.kind for term in model.terms}
    return in_effort(tuple(term for term in CANDIDATE_TERMS if term.name not in kinds), model.effort)


def _omitted_terms(model: JointModel, candidates: tuple[Term, ...], Z: np.ndarray | None, result: FitResult,
                   exclusions: Exclusions | None) -> OmittedTerms | None:
    """The test of the `candidates` the model lacks, their columns `Z` through the fit's low-pass, against the
    fit's filtered, kept samples; None without a unique low-passed fit on times, or without candidates."""
    if (exclusions is None or exclusions.regressor is None or result.estimate is None
            or result.correlation is None or not candidates):
        return None
    # A column beyond double precision (qd |qd| of a log in huge units) is not a candidate: the fit stands alone.
    usable = [j for j in range(Z.shape[1]) if np.all(np.isfinite(Z[:, j]))]
    if not usable:
        return None
    kept = exclusions.kept
    positions, lag = result.correlation
    try:
        with np.errstate(all="ignore"):
            return omitted_terms_test(exclusions.regressor[kept], Z[kept][:, usable], exclusions.torque[kept],
                                      positions, lag, model.column_names, tuple(candidates[j].name for j in usable))
    except (NonFiniteError, np.linalg.LinAlgError):  # a test that leaves double precision says nothing
        return None


def low_pass_for(log: JointLog, request: FilterRequest) -> ParallelFilter:
    """The low-pass for a log: as requested, or from its motion; LogError when it cannot apply."""
    timing = log.timing
    step = None if timing is None else timing.step
    uniform = timing is not None and timing.uniform
    estimate = log.derivatives
    # The derivative window followed the automatic cutoff: the same q up to the angle convention's rotation of
    # (cos q, sin q), which leaves its power spectrum as it was.
    known = None if estimate is None or estimate.choice is None else estimate.choice.automatic
    try:
        return choose_filter(request, step, uniform, log.data.q, log.data.count, known)
    except FilterRequestError as error:
        if error.setting == "decimation":
            raise LogError(log.path, f"cannot be decimated by {request.decimate:,}: {error}") from None
        raise LogError(log.path, f"cannot be low-passed: the cutoff {error}") from None


def correlation_lag(count: int, chosen: ParallelFilter, decimation: int | None = None) -> int:
    """Samples over which the residuals of `count` fitted samples are correlated: the filter's support on both
    sides (at `decimation`, by default the filter's own), at least the Newey-West rule of thumb."""
    decimation = chosen.decimation if decimation is None else decimation
    support = 0 if not chosen.active else max(1, math.ceil(chosen.support * chosen.rate / decimation))
    return max(int(4 * (count / 100) ** (2 / 9)), 2 * support)


def check_work(log: JointLog, chosen: ParallelFilter, explicit: bool = False) -> None:
    """LogError, saying how to fit less, when fitting the log as `chosen` asks is beyond FIT_BUDGET (about ten
    seconds) and the decimation was chosen automatically, or, when the user asked for it (`explicit`), beyond the
    memory available now (an explicit request the machine can serve is served, however long it takes)."""
    count = log.data.count

    def work(decimation: int) -> int:
        kept = -(-count // decimation)
        return kept * (correlation_lag(kept, chosen, decimation) + ROBUST_COST)

    if explicit:
        available = available_memory()
        if fit_memory(count, chosen.decimation) <= available:
            return
        too_much = lambda decimation: fit_memory(count, decimation) > available  # noqa: E731
        why = (f"needs about {in_words(fit_memory(count, chosen.decimation))} of memory and "
               f"{in_words(available)} are available")
    else:
        if work(chosen.decimation) <= FIT_BUDGET:
            return
        too_much = lambda decimation: work(decimation) > FIT_BUDGET  # noqa: E731
        why = f"are about {work(chosen.decimation) / FIT_BUDGET:.0f} times the work a fit takes on unasked (ten " \
              f"seconds or so)"
    kept = -(-count // chosen.decimation)
    every = "" if chosen.decimation == 1 else f", every {chosen.decimation:,}th of {count:,}"
    stretch = "fit a stretch of it (--train-window START:END)"
    advice = stretch
    if chosen.rate is not None:  # evenly sampled: it can be decimated
        low, high = chosen.decimation, chosen.decimation
        while too_much(high) and high < count:
            low, high = high, 2 * high
        while high - low > 1:
            middle = (low + high) // 2
            low, high = (middle, high) if too_much(middle) else (low, middle)
        advice = f"decimate by {high:,} or more (--decimate {high}), or {stretch}"
        if not explicit:
            advice += f"; --decimate 1 fits every sample (about {in_words(fit_memory(count, 1))} of memory)"
    raise LogError(log.path, f"{kept:,} samples to fit{every} {why}; {advice}")


def _fit(training: JointLog, heldout: JointLog | None, model: JointModel, constrained: bool,
         chosen: ParallelFilter, low_passed: tuple[np.ndarray, np.ndarray] | None = None,
         exclusion: ExclusionRequest = ExclusionRequest(), found: tuple[tuple[float, float], ...] | None = None,
         start: np.ndarray | None = None) -> tuple[FitResult, Exclusions | None]:
    """The fit of the training log's regressor and torque after the parallel low-pass and decimation, leaving out
    what `exclusion` asks, and those exclusions (None when the log has no times to place them on).

    `low_passed`: the training log's regressor and torque through `chosen`, when already computed (see
    `filtered_regressors`). `found`: outside-torque intervals (s from the log's
    start) already found on this log, to leave out again instead of running the robust step.
    """
    fitted, X, exclusions = _prepared(training, model, chosen, low_passed, exclusion, found, start)
    correlation = None
    kept = np.ones(fitted.count, dtype=bool) if exclusions is None else exclusions.kept
    if chosen.active:
        correlation = (np.flatnonzero(kept), correlation_lag(int(kept.sum()), chosen))
    try:
        result = fit_joint(fitted, None if heldout is None else _without_polynomial_ends(heldout), model=model,
                           constrained=constrained, heldout_is_noiseless=False, regressor=X, correlation=correlation)
    except NonFiniteError as error:
        raise LogError(training.path, f"cannot be fitted: {error}; rescale its columns (other units)") from None
    return result, exclusions


def _prepared(log: JointLog, model: JointModel, chosen: ParallelFilter,
              low_passed: tuple[np.ndarray, np.ndarray] | None, exclusion: ExclusionRequest,
              found: tuple[tuple[float, float], ...] | None, start: np.ndarray | None
              ) -> tuple[JointData, np.ndarray, Exclusions | None]:
    """(the kept samples with their filtered torque, their filtered regressor, the exclusions) of a log through
    `chosen`, leaving out what `exclusion` asks: the samples a fit uses, or a held-out check predicts."""
    data = log.data
    filtered, tau = filtered_regressors(log, model, (chosen,))[0] if low_passed is None else low_passed
    rows = slice(None, None, chosen.decimation)  # the rows `chosen` keeps, as views: indexing would copy them
    t = None if data.t is None else data.t[rows]
    exclusions = None if t is None else _exclusions(log, model, chosen, filtered, tau, t, exclusion, found, start)
    kept = None if exclusions is None or exclusions.kept.all() else exclusions.kept
    pick = (lambda values: values) if kept is None else (lambda values: values[kept])  # noqa: E731
    fitted = JointData(t=None if t is None else pick(t), q=pick(data.q[rows]), qd=pick(data.qd[rows]),
                       qdd=pick(data.qdd[rows]), tau=pick(tau))
    return fitted, pick(filtered), exclusions


def heldout_as_fitted(training: JointLog, heldout: JointLog, model: JointModel, chosen: ParallelFilter,
                       exclusion: ExclusionRequest, start: np.ndarray | None
                       ) -> tuple[JointData, np.ndarray, Exclusions | None, ParallelFilter] | None:
    """The held-out log through the training log's pipeline: its derivatives over the same span of time, the same
    low-pass and rate, its own outside torques (from the training fit's robust estimate) and standstill left out;
    (its kept samples, their filtered regressor). A log the pipeline cannot take (too short for the filter, a
    cutoff above its Nyquist frequency) gives None: it is predicted as it is, less its polynomial ends."""
    try:
        log = _same_derivative_span(training, heldout)
        same_rate = (training.timing is not None and heldout.timing is not None
                     and math.isclose(training.timing.step, heldout.timing.step, rel_tol=0.01))
        request = FilterRequest(chosen.cutoff if chosen.active else 0, chosen.decimation if same_rate else None)
        # Outside torques are the held-out log's own, found as the training log's were; times given by hand
        # (--exclude) are the training log's.
        other = low_pass_for(log, request)
        fitted, X, left = _prepared(log, model, other, None, ExclusionRequest(exclusion.robust, ()), None, start)
    except LogError:
        return None
    return fitted, X, left, other


def _same_derivative_span(training: JointLog, heldout: JointLog) -> JointLog:
    """The held-out log with its missing derivatives estimated over the training log's window in seconds."""
    mine, theirs = training.derivatives, heldout.derivatives
    if mine is None or theirs is None:
        return heldout
    window = int(round((mine.window - 1) * mine.step / theirs.step)) + 1
    window += 1 - window % 2
    window = min(max(window, mine.order + 2 - mine.order % 2), MAX_WINDOW)
    if window == theirs.window or window + 3 > heldout.data.count + theirs.window - 1:
        return heldout
    return heldout.with_window(window, mine.order)


def _without_polynomial_ends(log: JointLog) -> JointData:
    """The log's samples less the half window at each end where its derivatives come from the smoothing's end
    polynomials, which do not match the torque (a held-out log is predicted, not filtered)."""
    data, estimate = log.data, log.derivatives
    if estimate is None or data.count <= estimate.window:
        return data
    keep = slice(estimate.window // 2, data.count - estimate.window // 2)
    return JointData(t=None if data.t is None else data.t[keep], q=data.q[keep], qd=data.qd[keep],
                     qdd=data.qdd[keep], tau=data.tau[keep])


def filtered_regressors(log: JointLog, model: JointModel, filters,
                        candidates: tuple[Term, ...] = ()) -> list[tuple[np.ndarray, np.ndarray]]:
    """(M, p) regressor and (M,) torque of the log through each of `filters`: as `smoothed_regressor` low-passed
    and decimated, built one full-rate column at a time (each filtered by all, from one spectrum when they can
    share it: low_pass.low_passed_together) rather than as one (N, p + 1) matrix. With `candidates`, one more pair
    follows: their (M, k) columns through the first filter (each finite or not: double precision may not hold
    them) and an empty torque."""
    data, estimate = log.data, log.derivatives
    size = shared_size(filters, data.count) if len(filters) > 1 else None  # one filter alone: its own blocks
    outs = [np.empty((len(chosen.rows(data.count)), model.size), order="F") for chosen in filters]
    torques = [np.empty(0) for _ in filters]
    extra = np.empty((len(filters[0].rows(data.count)), len(candidates)))

    terms = (*model.terms, None, *candidates)

    def through_filters(j: int) -> None:
        """Column j (the torque at model.size) through the filters, into its place in the outputs."""
        term, candidate = terms[j], j > model.size
        with np.errstate(all="ignore") if candidate else contextlib.nullcontext():
            column = data.tau if term is None else np.asarray(term.column(data.q, data.qd, data.qdd), dtype=float)
            if estimate is not None and (term is None or not term.from_derivatives):
                column = smooth(column, estimate.window, estimate.order)
            low_passed = low_passed_together(column, filters[:1] if candidate else filters, size)
        for k, out in enumerate(low_passed):
            if candidate:
                extra[:, j - model.size - 1] = out
            elif term is None:
                torques[k] = out
            else:
                outs[k][:, j] = out

    map_in_threads(through_filters, range(len(terms)))  # on the machine's cores at once: FFTs leave the GIL
    return list(zip(outs, torques)) + ([(extra, np.empty(0))] if candidates else [])


def smoothed_regressor(log: JointLog, model: JointModel) -> np.ndarray:
    """(N, p + 1) The model's regressor with the torque as its last column; when qd and qdd were estimated from
    smoothed angles, every other column and the torque get the same smoothing, so all are filtered alike."""
    data = log.data
    X = np.column_stack([model.data_regressor(data), data.tau])
    estimate = log.derivatives
    if estimate is not None:
        for j, term in enumerate((*model.terms, None)):
            if term is None or not term.from_derivatives:
                X[:, j] = smooth(X[:, j], estimate.window, estimate.order)
    return X


def _exclusions(training: JointLog, model: JointModel, chosen: ParallelFilter, X: np.ndarray, tau: np.ndarray,
                t: np.ndarray, request: ExclusionRequest, found, start=None) -> Exclusions:
    """What the fit of a filtered log leaves out: standstill (with a Coulomb term), outside torques found by the
    robust step (or `found` before; `start`: its estimate on another filter of this log), and the intervals given
    by hand."""
    origin = None if training.source is None else training.source.table.start_time
    since = t - (training.data.t[0] if origin is None else origin)
    support = 0 if not chosen.active else max(1, math.ceil(chosen.support * chosen.rate / chosen.decimation))
    coulomb = model.index_of("Fc")
    still = rest = np.zeros(len(t), dtype=bool)
    threshold = None
    if coulomb is not None:
        speed = X[:, model.index_of("B")]
        still, rest, threshold = standstill(speed, _speed_resolution(training, chosen), support)
        if (~still).sum() <= 4 * X.shape[1]:  # hardly ever moving: too little left to leave standstill out
            still = rest = np.zeros(len(t), dtype=bool)
            threshold = None
    pushes = np.zeros(len(t), dtype=bool)
    for start, end in request.by_hand:
        inside = (since >= start) & (since <= end)
        table = None if training.source is None else training.source.table
        if not inside.any() and getattr(table, "run", None) is None:  # a SysId test's: checked against every test
            from ..logs.request import time_base

            base = "from the log's start" if table is None else time_base(table)
            span = f"{float(since[0]):.6g} to {float(since[-1]):.6g} s"
            raise LogError(training.path, f"--exclude {start:g}:{'' if math.isinf(end) else f'{end:g}'} holds no "
                           f"sample; " + (f"the log spans {span} from its start" if base == "from the log's start"
                                          else f"the samples span {span} {base}"))
        pushes |= inside
    left = int((~pushes).sum())
    if request.by_hand and left < X.shape[1]:  # said here: the robust step would take the median of nothing
        raise LogError(training.path, f"--exclude leaves {left or 'none'} of its {len(t)} samples to fit; the "
                       f"model's {X.shape[1]} parameters need at least as many (the log spans 0 to "
                       f"{float(since[-1]):.6g} s from its start)")
    level = estimate = None
    if found is not None:
        for start, end in found:
            pushes |= (since >= start) & (since <= end)
    elif request.robust and (~still & ~pushes).sum() > 4 * X.shape[1]:
        lag = correlation_lag(len(t), chosen)
        flagged, level, estimate = outside_torques(X, tau, ~still & ~pushes, rest, coulomb, support, lag, start)
        if not model.effort.is_torque:  # a voltage step's response is the signal, not an outside torque
            window = 0 if training.derivatives is None else training.derivatives.window
            reach = window + 2 * support + 2
            flagged = explained_transients(X, tau, flagged, ~still & ~pushes, commanded_changes(tau, reach), level)
        pushes |= flagged
    if not (~(pushes | still)).any():
        raise LogError(training.path, "leaves no sample to fit after leaving out standstill and outside torques; "
                       "fit it with --no-robust or --model plain")
    return Exclusions(pushes, still, threshold, level, since, estimate, t, X, tau)


def _speed_resolution(log: JointLog, chosen: ParallelFilter) -> float:
    """The speed (rad/s) one step of the angle's quantisation makes over half a cutoff period (0 unquantised)."""
    return log.angle_quantum * 2 * chosen.cutoff if chosen.active else 0.0


def _cutoff_variants(training: JointLog, chosen: ParallelFilter) -> list[tuple[float, float, ParallelFilter]]:
    """(factor, cutoff, low-pass) of each cutoff refit of the sensitivity check that the log allows."""
    variants = []
    if chosen.active:
        for factor in FACTORS:
            # The same decimation, so the refits keep the same grid of samples (a few more or fewer at the
            # ends, where the filter windows differ in length) and differ only by the cutoff.
            request = FilterRequest(chosen.cutoff * factor, chosen.decimation)
            try:
                variants.append((factor, request.cutoff, low_pass_for(training, request)))
            except LogError:  # a doubled cutoff beyond the Nyquist frequency: skipped
                continue
    return variants


def _sensitivity(training: JointLog, model: JointModel, constrained: bool, chosen: ParallelFilter,
                 result: FitResult, cutoffs, exclusion: ExclusionRequest,
                 exclusions: Exclusions | None) -> SensitivityCheck | None:
    """Refits with the derivative window, then the cutoff, halved and doubled; None without a unique fit.

    `cutoffs`: ((factor, cutoff, low-pass), (regressor, torque) through it) for each cutoff refit.
    """
    if result.estimate is None or result.uncertainty is None or result.uncertainty.residual_std_error is None:
        return None
    estimate = training.derivatives
    window = None if estimate is None else estimate.window
    base = Variant("", 1.0, window, chosen.cutoff, result.estimate)
    same = FilterRequest(chosen.cutoff if chosen.active else 0, chosen.decimation)
    variants = []
    if estimate is not None:
        for factor in FACTORS:
            other = _scaled_window(window, factor, estimate.order, training.data.count + window - 1)
            if other is None or other == window:
                continue
            try:
                log = training.with_window(other)
                # Another window has other polynomial ends: the robust step looks again, from the chosen fit's
                # robust estimate (the same joint) rather than a new high-breakdown search.
                start = None if exclusions is None else exclusions.estimate
                fit, _ = _fit(log, None, model, constrained, low_pass_for(log, same), None, exclusion, None, start)
            except LogError:  # too short for the wider window: that variant is skipped
                continue
            variants.append(Variant("window", factor, other, chosen.cutoff, fit.estimate, _noise_errors(fit)))
    for (factor, cutoff, other), low_passed in cutoffs:
        try:
            found = None if exclusions is None else exclusions.excluded
            fit, _ = _fit(training, None, model, constrained, other, low_passed, exclusion, found)
        except LogError:  # nothing left to fit, say: that variant is skipped
            continue
        variants.append(Variant("cutoff", factor, window, cutoff, fit.estimate, _noise_errors(fit)))
    return sensitivity_check(model.names, base, result.uncertainty.residual_std_error, variants,
                             rmse=result.training_rmse, torque_rms=rms(result.training.tau))


def _noise_errors(fit: FitResult) -> np.ndarray | None:
    """(p,) A refit's noise-based standard errors, or None without them."""
    return None if fit.uncertainty is None else fit.uncertainty.noise_std_error


def refits_of(logs: LoadedLogs) -> dict[str, FitResult]:
    """The log's fit redone as the judgement's checks vary it, by label: the derivative window halved and doubled
    ('window halved', 'window doubled', when its derivatives were estimated) and without the robust step
    ('--no-robust', when it ran); for judging a pooled fit from its runs' refits (studies.runs)."""
    training, result, chosen = logs.training, logs.result, logs.filter
    model, constrained = result.model, result.constrained
    refits = {}
    estimate = training.derivatives
    if estimate is not None and chosen is not None:
        same = FilterRequest(chosen.cutoff if chosen.active else 0, chosen.decimation)
        for factor in FACTORS:
            other = _scaled_window(estimate.window, factor, estimate.order, training.data.count + estimate.window - 1)
            if other is None or other == estimate.window:
                continue
            try:
                log = training.with_window(other)
                start = None if logs.exclusions is None else logs.exclusions.estimate
                refits[f"window {'halved' if factor < 1 else 'doubled'}"], _ = _fit(
                    log, None, model, constrained, low_pass_for(log, same), None, logs.exclusion, None, start)
            except LogError:  # too short for that window: no such refit
                continue
    if logs.exclusion.robust and chosen is not None:
        try:
            refits["--no-robust"], _ = _fit(training, None, model, constrained, chosen, None,
                                            ExclusionRequest(False, logs.exclusion.by_hand))
        except LogError:
            pass
    return refits


def _scaled_window(window: int, factor: float, order: int, samples: int) -> int | None:
    """An odd window spanning `factor` times as long, longer than the order and at most MAX_WINDOW; None if none
    fits the log."""
    other = int(round((window - 1) * factor)) + 1
    other += 1 - other % 2
    least = order + 1
    other = max(other, least + 1 - least % 2)
    other = min(other, MAX_WINDOW)
    return other if other + 3 <= samples else None


def load_request(
    request: LoadRequest,
    current: LoadedLogs | None = None,
    model: JointModel = PLAIN,
    constrained: bool = False,
    progress: Callable[[int, int], None] | None = None,
    cancel: Callable[[], bool] | None = None,
    exclusion: ExclusionRequest | None = None,
) -> LoadedLogs:
    """Load one log into its role beside the current other log and refit (leaving out what `exclusion` asks, by
    default what the current fit's request did); LogError/LoadCancelled as load_log."""
    log = load_joint_log(request, progress=progress, cancel=cancel)
    if cancel is not None and cancel():  # the fit cannot stop part-way, so an Escape after reading must not start it
        raise LoadCancelled(request.path)
    if exclusion is None:
        exclusion = ExclusionRequest() if current is None else current.exclusion
    if request.role == HELDOUT:
        if current is None:
            raise ValueError("a held-out log needs a training log")
        return fit_logs(current.training, log, model, constrained, current.filtering, exclusion=exclusion)
    return fit_logs(log, None if current is None else current.heldout, model, constrained, request.filtering,
                    exclusion=exclusion)


@checked(model=optional(model_argument), degrees=flag, window=optional(whole(3)), order=whole(2),
         cutoff=optional(real(0.0)), decimate=optional(whole(1)), constrained=flag, joint=optional(text), zero=text,
         clockwise=flag, sensitivity=flag, robust=flag, exclude=pairs, effort=text, gear=real(0.0, above=True),
         kt=optional(real(0.0, above=True)), efficiency=real(0.0, 1.0, above=True))
def fit_log(
    source,
    heldout=None,
    *,
    model: str | JointModel | None = None,
    degrees: bool = False,
    window: int | None = None,
    order: int = DEFAULT_ORDER,
    cutoff: float | None = None,
    decimate: int | None = None,
    constrained: bool = False,
    joint: str | None = None,
    columns=None,
    zero: str = "right",
    clockwise: bool = False,
    sensitivity: bool = True,
    robust: bool = True,
    exclude: tuple[tuple[float, float], ...] = (),
    effort: str = "torque",
    gear: float = 1.0,
    kt: float | None = None,
    efficiency: float = 1.0,
) -> LoadedLogs:
    """Fit a joint log as `jointid fit --csv` does: the same time checks, resampling, derivatives, low-pass and
    sensitivity check.

    Parameters
    ----------
    source : str, os.PathLike or mapping of arrays
        A CSV file's path, a ROS bag's (with `joint`), or the columns themselves: a dict or a pandas DataFrame
        with q and tau and any of t, qd, qdd (missing derivatives are estimated from q, which needs t).
    heldout : same kinds as `source`, optional
        A log the fit never sees, to predict.
    model : str or JointModel, optional
        'coulomb+bias' by default (real joints have friction, sensors a bias), 'coulomb+angle-offset' (WPILib
        SysId's arm) for a voltage log; 'plain' is the lesson's I, h, B.
    degrees : bool
        q (and qd, qdd) given in degrees rather than radians.
    window, order : int
        Savitzky-Golay window (None: chosen from the motion) and order, for derivatives estimated from q.
    cutoff, decimate : float, int
        The low-pass cutoff in hertz (None: automatic, 0: none) and the decimation (None: automatic).
    constrained : bool
        Fit subject to the model's sign rules.
    joint : str
        The joint to read from a ROS bag.
    columns : mapping or str, optional
        Which column gives which quantity, e.g. ``{"q": "posn", "tau": "effort"}`` or ``"q=posn,tau=effort"``; the
        columns it leaves out are recognised by name (t/time/timestamp, q/position/pos/angle, qd/velocity/vel,
        qdd/acceleration/accel, tau/torque/effort). Not for a ROS bag.
    zero : {'right', 'up', 'left', 'down'}
        Where the log's angle 0 points; 'right' is jointid's own q = 0.
    clockwise : bool
        The log's angle grows clockwise (q, qd, qdd and the torque change sign).
    sensitivity : bool
        Refit with the derivative window and the cutoff halved and doubled.
    robust : bool
        Find and leave out stretches where an outside torque acts (pushes, collisions).
    exclude : tuple of (start, end)
        Seconds from the log's start to leave out as well.
    effort : {'torque', 'current', 'voltage'}
        What the effort (tau) column holds: joint torque (N m), motor current (A; torque = gear x kt x efficiency x
        current) or motor voltage (V; fitted as WPILib's arm gains kA, kG, kV, kS).
    gear, kt, efficiency : float
        A current log's reduction (motor turns per joint turn), torque constant (N m/A, required) and gearbox
        efficiency.

    Returns
    -------
    LoadedLogs
        `params`, `bse`, `conf_int()`, `summary()` (the command line's text), `notes()`, and the fit as `result`.

    Raises
    ------
    LogError
        A problem with the log (one line naming the file, row and column), as the command line reports it.
    ValueError, TypeError
        A `columns` or `zero` that cannot be one, naming the argument.

    Examples
    --------
    A pendulum logged as time, position (0 hanging down), velocity, torque:

    >>> fit = fit_log("pendulum.csv", zero="down")  # doctest: +SKIP
    >>> fit.notes()[0]  # doctest: +SKIP
    'pendulum.csv: columns read as t=time, q=position, qd=velocity, tau=torque.'
    """
    from ..logs.angles import read_angle
    from ..logs.arrays import read_arrays
    from ..logs.conventions import AngleConvention, ColumnMap
    from ..logs.derivatives import check_filter
    from ..logs.pipeline import check_finite, joint_log_from_table
    from ..model.terms import model_named

    from ..logs.effort import EffortReading, read_effort
    from ..options import default_log_model

    try:
        reading = EffortReading(effort, 1.0, gear, kt, efficiency)
    except ValueError as error:
        raise ValueError(f"fit_log(): {error}") from None
    if model is None:
        model = default_log_model(effort)
    fitted_model = model_named(model) if isinstance(model, str) else model
    if not isinstance(fitted_model, JointModel):
        raise TypeError(f"model must be a model name or a JointModel; got {type(model).__name__}")
    check_filter(window, order)
    filtering = FilterRequest(cutoff, decimate)
    column_map = ColumnMap.of(columns, "columns")
    angle = AngleConvention(zero, bool(clockwise))

    def load(given, role: str) -> JointLog:
        if isinstance(given, (str, os.PathLike)):
            return load_joint_log(LoadRequest(os.fspath(given), role, degrees=degrees, window=window, order=order,
                                              filtering=filtering, joint=joint, columns=column_map, angle=angle,
                                              effort=reading))
        table = read_arrays(given, "arrays" if role == TRAINING else "held-out arrays", column_map)
        check_finite(table)
        table = read_effort(table, reading, bag=False)
        table = read_angle(table, angle, degrees)
        return joint_log_from_table(table, degrees=degrees, window=window, order=order, cutoff=cutoff)

    training = load(source, TRAINING)
    return fit_logs(training, None if heldout is None else load(heldout, HELDOUT), model=fitted_model,
                    constrained=constrained, filtering=filtering, sensitivity=sensitivity,
                    exclusion=ExclusionRequest(robust, tuple((float(a), float(b)) for a, b in exclude)))
