"""Which joint log to load and how: a CSV file, one joint of a ROS bag or entries of a WPILib data log, its
columns and angle convention, cut to a time window, its effort read as torque (scaled, or converted from current)
or volts.

Every source is read into a checked table (csvlog.read_table,
bag.read_bag_table or wpilog.read_wpilog_table), cut and scaled here, and
then goes through csvlog.joint_log_from_table, so CSV logs, bags and data
logs get the same time checks, resampling and differentiation. A SysId
routine log holds several test runs of one joint: load_joint_logs gives one
log per run.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from ..estimation.low_pass import FilterRequest
from ..options import DEFAULT_ORDER, DEFAULT_WINDOW
from .conventions import AngleConvention, ColumnMap, EntryMap
from .effort import EffortReading
from .timewindow import TimeWindow

TRAINING, HELDOUT, RUN = "training", "heldout", "run"
"""The roles a log can be loaded in: the training log, the held-out log, or one more run of the joint."""

ROLE_WORDS = {TRAINING: "training", HELDOUT: "held-out", RUN: "training"}
"""How notes name each role."""


@dataclass(frozen=True)
class LoadRequest:
    """Which log to load, in which role, and how: angle unit, derivative filter, joint, time window, torque scale."""

    path: str
    role: str = TRAINING
    degrees: bool = False
    window: int | None = DEFAULT_WINDOW
    """Savitzky-Golay window, when the log lacks qd or qdd (`--window`); None: chosen from the motion."""
    order: int = DEFAULT_ORDER
    """Savitzky-Golay order (`--order`)."""
    filtering: FilterRequest = FilterRequest()
    """The parallel low-pass asked for (`--cutoff`, `--decimate`)."""
    joint: str | None = None
    """The joint to read from a ROS bag (`--joint`); None for a CSV log."""
    topic: str | None = None
    """The bag's JointState topic (`--topic`); None picks the only one, or /joint_states."""
    time_window: TimeWindow | None = None
    """Seconds from the log's start (a data log's: of its own time stamps) to keep (`--train-window`,
    `--heldout-window`); None keeps all."""
    effort_scale: float = 1.0
    """Torque (N m) per unit of the logged effort or tau (`--effort-scale`)."""
    columns: ColumnMap | None = None
    """Which CSV column gives which quantity (`--columns`); None: recognised by name."""
    angle: AngleConvention = AngleConvention()
    """Where the logged angle's 0 points and which way it grows (`--zero`, `--clockwise`)."""
    effort: EffortReading = EffortReading()
    """What the effort column measured (`--effort`, `--gear`, `--kt`, `--efficiency`); its scale is effort_scale."""
    wpilog: bool = False
    """True to read a WPILib data log (`--wpilog`)."""
    entries: EntryMap | None = None
    """Which data-log entry gives which quantity (`--entry`); None: a SysId routine's, recognised by name."""
    units: str | None = None
    """The data log's unit over its metadata's (`--units`): 'rotations', 'radians', 'degrees' or 'meters'."""
    sysid_motor: str | None = None
    """The SysId motor (or routine) to read (`--sysid-motor`); None: every motor of the log's routine, pooled."""
    sysid_runs: str = "all"
    """A test run more than once: 'all' its runs fitted, or 'first' (as SysId's analysis) (`--sysid-runs`)."""

    @property
    def is_bag(self) -> bool:
        """True when the request reads a joint from a ROS bag."""
        return self.joint is not None and not self.wpilog


def load_joint_log(request: LoadRequest, progress=None, cancel=None):
    """The request's log ready to fit (csvlog.JointLog); LogError on any problem, LoadCancelled if cancelled."""
    from .angles import read_angle
    from .csv_reader import read_table
    from .derivatives import check_filter
    from .effort import read_effort
    from .pipeline import joint_log_from_table

    check_filter(request.window, request.order)
    if request.wpilog:
        logs = load_joint_logs(request, progress, cancel)
        if len(logs) > 1:
            from .table import LogError

            raise LogError(request.path, f"is a SysId log of {len(logs)} test runs, fitted as runs of one joint "
                           "(jointid fit --wpilog), not as one log")
        return logs[0]
    if request.is_bag:
        from .bag import read_bag_table
        from .table import LogError

        if request.columns is not None:
            raise LogError(request.path, f"{request.columns.flag}: only for a CSV log or arrays; a bag's JointState "
                           "gives position, velocity and effort by name")
        table = read_bag_table(request.path, request.joint, request.topic, progress=progress, cancel=cancel)
    else:
        table = read_table(request.path, progress=progress, cancel=cancel, column_map=request.columns)
    # Before the time window and the time checks: a wrap must be undone before anything interpolates across it.
    table = read_angle(table, request.angle, request.degrees)
    if request.time_window is not None:
        table = cut_time_window(table, request.time_window, request.role)
    table = read_effort(table, dataclasses.replace(request.effort, scale=request.effort_scale), request.is_bag)
    return joint_log_from_table(table, degrees=request.degrees, window=request.window, order=request.order,
                                cutoff=request.filtering.cutoff)


def load_joint_logs(request: LoadRequest, progress=None, cancel=None) -> list:
    """The request's logs ready to fit: one per SysId test run of a data log with a test-state entry, else the one
    log of load_joint_log; LogError on any problem."""
    if not request.wpilog:
        return [load_joint_log(request, progress, cancel)]
    from .angles import read_angle
    from .derivatives import check_filter
    from .effort import read_effort
    from .pipeline import joint_log_from_table
    from .wpilog import read_wpilog_tables

    check_filter(request.window, request.order)
    if request.columns is not None:
        from .table import LogError

        raise LogError(request.path, f"{request.columns.flag}: only for a CSV log; a data log's entries are named "
                       "with --entry")
    units = request.units or ("degrees" if request.degrees else None)
    read = read_wpilog_tables(request.path, request.entries, units, motor=request.sysid_motor,
                              repeats=request.sysid_runs, progress=progress, cancel=cancel)
    tables = []
    for table in read:  # one per motor of a SysId routine (several pooled as runs of one mechanism)
        if request.time_window is not None:
            table = cut_time_window(table, request.time_window, request.role)
        # Each test on its own: a run's wraps and whole turns are its own, and its time checks see no other test.
        tables += table.run_tables() if table.runs else [table]
    effort = dataclasses.replace(request.effort, scale=request.effort_scale)
    if (read[0].routine is not None or read[0].runs) and effort.kind == "torque":
        effort = dataclasses.replace(effort, kind="voltage")  # a SysId routine's effort is its motor's voltage
    logs = []
    for part in tables:
        part = read_angle(part, request.angle, False)  # already in radians (or metres)
        part = read_effort(part, effort, False)
        logs.append(joint_log_from_table(part, degrees=False, window=request.window, order=request.order,
                                         cutoff=request.filtering.cutoff))
    return logs


def cut_time_window(table, window: TimeWindow, role: str = TRAINING):
    """The table's samples from window.start to window.end seconds after its start (a data log's: its own time
    stamps); LogError if none."""
    import numpy as np

    from .table import LogError

    t = table.columns.get("t")
    if t is None:
        raise LogError(table.path, f"a time window ({window.text}) needs the log's t column")
    since = t - table.start_time
    base = time_base(table)
    inside = np.flatnonzero((since >= window.start) & (since <= window.end))
    if len(inside) == 0:
        span = f"{float(np.min(since)):.6g} to {float(np.max(since)):.6g} s"
        raise LogError(table.path, f"no samples in the {ROLE_WORDS[role]} window {window.text} s; " + (
            f"the log spans {span} from its start" if base == "from the log's start" else
            f"the samples span {span} {base}"))
    rows = slice(int(inside[0]), int(inside[-1]) + 1)
    kept = rows.stop - rows.start
    note = (f"{ROLE_WORDS[role]} window {window.text} s {base}: {kept} of {table.count} samples "
            f"(t = {float(since[rows.start]):.6g} to {float(since[rows.stop - 1]):.6g} s).")
    return dataclasses.replace(table.sliced(rows, note), time_window=window, time_origin=table.start_time)


def time_base(table) -> str:
    """How a table's times count, for messages: a data log's own time stamps, or seconds from the log's start."""
    from .wpilog import WpilogTable

    return "of the data log's own time stamps" if isinstance(table, WpilogTable) else "from the log's start"
