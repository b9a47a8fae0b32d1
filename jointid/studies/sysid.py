"""A WPILib SysId routine log fitted as several runs of one joint: its quasistatic and dynamic tests.

The effort is the motor's voltage, and jointid's coulomb + angle-offset model
in volts is WPILib's arm feedforward V = kS sgn(v) + kG cos(theta + offset)
+ kV v + kA a: I is kA, h g is kG, B is kV, Fc is kS and q0 the offset.

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

from ..estimation.exclusion import ExclusionRequest
from ..estimation.low_pass import FilterRequest
from ..logs.pipeline import JointLog
from ..model.terms import JointModel, model_named
from .runs import POOLED_FIT, PooledRuns, fit_runs

SYSID_MODEL = "coulomb+angle-offset"
"""The model whose parameters are the arm feedforward's gains."""


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
                   sensitivity: bool = True) -> PooledRuns:
    """Fit a SysId log's tests alone and together (SYSID_MODEL unless another is given)."""
    return fit_runs(logs, model or model_named(SYSID_MODEL), sysid_filtering(filtering), exclusion, constrained,
                    sensitivity, weighting=POOLED_FIT)


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
    if len(logs) == 1:
        return fit_logs(logs[0], None, model, constrained, request.filtering)
    return fit_sysid_runs(logs, None, request.filtering, constrained=constrained)
