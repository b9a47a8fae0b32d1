"""A WPILib SysId routine log fitted as several runs of one joint: its quasistatic and dynamic tests.

The effort is the motor's voltage, and the mechanism's model in volts is its
WPILib feedforward (jointid.studies.mechanism): a simple motor's V = kS sgn(v)
+ kV v + kA a, an elevator's + kG, an arm's + kG cos(theta + offset) (the
coulomb + angle-offset model: I is kA, h g is kG, B is kV, Fc is kS and q0 the
offset). Without --mechanism the log chooses which.

Two choices differ from other runs of a joint, each for a reason of the
routine's own. No test alone separates the gains (a dynamic test's voltage is
constant, which its Coulomb column fits exactly; a quasistatic test barely
accelerates), so the runs are weighted by their residuals against a first,
equally weighted pooled fit rather than against their own. And each dynamic
test starts with a voltage step from rest, with no record before it for a
low-pass to start from: filtering across that edge biased kA high by 17 % (the
automatic 4.7 Hz) and 4 % (10 Hz) on the simulated routine of
tests/support/sysid_arm.py, against 0.5 % without, so the low-pass is off unless
--cutoff asks for it (the derivatives' own smoothing stays).
"""

from __future__ import annotations

from ..checks import checked, flag, optional, real, text, whole
from ..estimation.exclusion import ExclusionRequest
from ..estimation.low_pass import FilterRequest
from ..logs.pipeline import JointLog
from ..logs.table import LogError
from ..model.terms import SIMPLE_MOTOR, JointModel, model_argument, model_named
from .angle_models import check_angle_model, no_angle
from .runs import POOLED_FIT, PooledRuns, fit_runs

SYSID_MODEL = "coulomb+angle-offset"
"""The model whose parameters are the arm feedforward's gains (the arm mechanism's)."""


def sysid_model(logs: list[JointLog], model: JointModel | None) -> JointModel:
    """The model to fit a data log's runs with: the one asked for, else SYSID_MODEL, or SIMPLE_MOTOR where q is
    no angle; LogError when the model asked for takes cos(q) of a q that is no angle."""
    if no_angle(logs[0]) is None:
        return model or model_named(SYSID_MODEL)
    if model is None:
        return SIMPLE_MOTOR  # kA, kV, kS: no cos(q), which only an angle in radians can feed
    check_angle_model(logs[0], model)
    return model


def is_sysid_run(log: JointLog) -> bool:
    """True for a run read from a SysId test of a data log."""
    table = None if log.source is None else log.source.table
    return getattr(table, "run", None) is not None


def sysid_filtering(filtering: FilterRequest) -> FilterRequest:
    """The low-pass for SysId tests: off (cutoff 0) unless a cutoff was asked for."""
    if filtering.cutoff is not None:
        return filtering
    return FilterRequest(0.0, filtering.decimate)


def fit_sysid_runs(logs: list[JointLog], model: JointModel | None = None, filtering: FilterRequest = FilterRequest(),
                   exclusion: ExclusionRequest = ExclusionRequest(), constrained: bool = False,
                   sensitivity: bool = True, mechanism: str | None = None) -> PooledRuns:
    """Fit a SysId log's tests alone and together: with `model`, the mechanism's model (`mechanism`), or the
    mechanism the tests choose (studies.mechanism); MechanismError for a mechanism the log cannot be, LogError for
    an --exclude interval in no test."""
    return fit_sysid(logs, model, filtering, exclusion, constrained, sensitivity, mechanism)


def fit_sysid(logs: list[JointLog], model: JointModel | None = None, filtering: FilterRequest = FilterRequest(),
              exclusion: ExclusionRequest = ExclusionRequest(), constrained: bool = False, sensitivity: bool = True,
              mechanism: str | None = None, heldout: JointLog | None = None):
    """A voltage log's tests (or one voltage log) fitted as a mechanism, with the MechanismChoice attached: pooled
    runs for several tests, a LoadedLogs for one (predicting `heldout`)."""
    import dataclasses

    from .log_fit import fit_logs
    from .mechanism import MechanismChoice, check_mechanism, choose_mechanism, mechanism_model, mechanism_of, \
        position_unit

    def fit(chosen: JointModel, check: bool = sensitivity):
        if len(logs) == 1:
            return fit_logs(logs[0], heldout, chosen, constrained, filtering, check, exclusion)
        return fit_runs(logs, chosen, sysid_filtering(filtering), exclusion, constrained, check,
                        weighting=POOLED_FIT)

    check_exclusions(logs, exclusion)
    unit = position_unit(logs[0])
    if model is not None:
        fitted = fit(model)
        choice = MechanismChoice(mechanism_of(model), "--model", unit)
    elif mechanism is not None:
        check_mechanism(mechanism, logs)
        fitted = fit(mechanism_model(mechanism))
        choice = MechanismChoice(mechanism, "--mechanism", unit)
    else:
        chosen, choice = choose_mechanism(logs, lambda candidate: fit(candidate, False))
        fitted = fit(mechanism_model(chosen))
    return dataclasses.replace(fitted, mechanism=choice)


def check_exclusions(logs: list[JointLog], exclusion: ExclusionRequest) -> None:
    """LogError naming an --exclude interval that holds no sample of any test run (times: the log's own)."""
    import math

    import numpy as np

    for start, end in exclusion.by_hand:
        if any(np.any((log.data.t >= start) & (log.data.t <= end)) for log in logs):
            continue
        first, last = min(log.data.t[0] for log in logs), max(log.data.t[-1] for log in logs)
        raise LogError(logs[0].path, f"--exclude {start:g}:{'' if math.isinf(end) else f'{end:g}'} holds no sample "
                       f"of any test; the tests span {first:.6g} to {last:.6g} s of the data log's own time stamps "
                       "(jointid log-info lists each test's)")


def load_training_request(request, model: JointModel, constrained: bool = False, progress=None, cancel=None):
    """A training log request fitted as the explorer's Ctrl+O fits it: a SysId data log's tests as pooled runs (with
    SYSID_MODEL), anything else as log_fit.load_request; LogError/LoadCancelled as load_joint_log."""
    from ..logs.request import load_joint_logs
    from ..logs.table import LoadCancelled
    from .log_fit import fit_logs, load_request

    if not request.wpilog:
        return load_request(request, None, model, constrained, progress, cancel)
    logs = load_joint_logs(request, progress, cancel)
    if cancel is not None and cancel():  # the fit cannot stop part-way: no fit is started after an Escape
        raise LoadCancelled(request.path)
    if len(logs) == 1 and logs[0].effort.is_torque:
        return fit_logs(logs[0], None, sysid_model(logs, model), constrained, request.filtering)
    return fit_sysid(logs, None, request.filtering, constrained=constrained)


@checked(entry=optional(text), units=optional(text), model=optional(model_argument), cutoff=optional(real(0.0)),
         decimate=optional(whole(1)), sensitivity=flag, mechanism=optional(text), motor=optional(text), runs=text)
def fit_wpilog(source, *, entry: str | None = None, units: str | None = None, model: str | JointModel | None = None,
               cutoff: float | None = None, decimate: int | None = None, sensitivity: bool = True,
               mechanism: str | None = None, motor: str | None = None, runs: str = "all"):
    """Fit a WPILib data log as `jointid fit --wpilog` does.

    Parameters
    ----------
    source : str or os.PathLike
        The .wpilog file's path (named as fit_log's is).
    entry : str, optional
        Which entries give which quantity, e.g. ``"q=/Arm/Position,tau=/Arm/Volts"`` (`--entry`); None reads a
        SysId routine's entries by their names.
    units : {'rotations', 'radians', 'degrees', 'meters'}, optional
        The position's unit over the entries' metadata (`--units`); a length is read in metres.
    model : str or JointModel, optional
        A model by name over the mechanism's (e.g. 'coulomb+angle-offset', WPILib's arm feedforward).
    mechanism : {'simple', 'elevator', 'arm'}, optional
        What the routine characterised: a simple motor (flywheel, roller, drive: SimpleMotorFeedforward), an
        elevator (ElevatorFeedforward) or an arm (ArmFeedforward); None chooses from the log by BIC and says why
        (the fit's `mechanism.note()`).
    cutoff, decimate : float, int
        The low-pass (`--cutoff`, `--decimate`); a SysId routine's tests are not low-passed unless a cutoff is
        given, since each dynamic test starts with a step.
    sensitivity : bool
        Refit with the derivative window and the cutoff halved and doubled.
    motor : str, optional
        One motor (or routine) of a SysId routine to fit (`--sysid-motor`); None pools every motor of the routine.
    runs : {'all', 'first'}
        A test run more than once: every run fitted, or each test's first, as SysId's analysis (`--sysid-runs`).

    Returns
    -------
    PooledRuns or LoadedLogs
        A SysId routine's tests fitted alone and pooled (`params` and `bse` are the pooled gains: kA, kV, kS, and kG
        for an elevator, kG and the offset q0 for an arm; `names` the tests); any other log's one fit.

    Raises
    ------
    LogError
        A problem with the log (one line naming the file), as the command line reports it.
    """
    import os

    from ..logs.conventions import ColumnMapError, EntryMap
    from ..logs.request import LoadRequest, load_joint_logs
    from .log_fit import fit_logs

    if not isinstance(source, (str, os.PathLike)):
        raise TypeError(f"fit_wpilog()'s source must be a file's path (str or os.PathLike); got "
                        f"{type(source).__name__}")
    try:
        entries = None if entry is None else EntryMap.parse(entry, "entry")
    except ColumnMapError as error:
        raise ValueError(str(error)) from None
    if units not in (None, "rotations", "radians", "degrees", "meters"):
        raise ValueError(f"units: one of 'rotations', 'radians', 'degrees', 'meters'; got {units!r}")
    if runs not in ("all", "first"):
        raise ValueError(f"runs: one of 'all', 'first'; got {runs!r}")
    from ..options import MECHANISMS

    if mechanism not in (None, *MECHANISMS):
        raise ValueError(f"mechanism: one of {', '.join(map(repr, MECHANISMS))}; got {mechanism!r}")
    filtering = FilterRequest(cutoff, decimate)
    request = LoadRequest(os.fspath(source), wpilog=True, entries=entries, units=units, filtering=filtering,
                          sysid_motor=motor, sysid_runs=runs)
    logs = load_joint_logs(request)
    chosen = model_named(model) if isinstance(model, str) else model
    if len(logs) == 1 and logs[0].effort.is_torque:
        return fit_logs(logs[0], None, sysid_model(logs, chosen), filtering=filtering,
                        sensitivity=sensitivity)
    from .mechanism import MechanismError

    try:
        return fit_sysid(logs, chosen, filtering, sensitivity=sensitivity, mechanism=mechanism)
    except MechanismError as error:
        raise ValueError(str(error)) from None
