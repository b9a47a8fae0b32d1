"""Every reader's table becomes a log ready to fit here: values checked, time checked (resampled if
jittered), missing derivatives estimated, units converted."""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..model.effort import Effort, effort_named
from ..norms import all_finite
from ..options import DEFAULT_ORDER, DEFAULT_WINDOW
from ..samples import JointData
from ..text_safety import shown_name
from ..estimation.low_pass import automatic_cutoff
from .conventions import AngleReading, logged_angle_name
from .derivatives import METHOD, DerivativeEstimate, WindowChoice, check_filter, differentiate, smoothing_window
from .table import MIN_FIT_ROWS, LogError, LogTable
from .timing import TimeCheck, TimeProblem, check_times


@dataclass(frozen=True, eq=False)
class LogSource:
    """A table and its columns after the time checks (resampled if jittered): what differentiation starts from."""

    table: LogTable
    columns: dict
    """Name -> (N,) array, on a uniform grid when derivatives are estimated."""
    timing: TimeCheck | None


@dataclass(frozen=True, eq=False)
class JointLog:
    """A log ready to fit: joint data (SI units, trimmed) plus how it was obtained."""

    path: str
    """The file's path as given."""
    data: JointData
    """The samples to fit; rows trimmed by derivative estimation are gone."""
    ignored: tuple[str, ...]
    """Header names of unused columns."""
    derivatives: DerivativeEstimate | None
    """How missing qd/qdd were estimated, or None when the log had both."""
    degrees: bool
    """True when q, qd, qdd were read in degrees and converted."""
    rows: int
    """Data rows in the file, before any trimming."""
    timing: TimeCheck | None = None
    """What the time column showed (step, jitter, repeats dropped, resampling), or None without one."""
    read_notes: tuple[str, ...] = ()
    """Notes from reading the source (a bag's time source, a time window, an effort scale)."""
    read_text: str = ""
    """What was read, e.g. '1000 rows' or "joint 'j1' on /joint_states, 1000 messages"."""
    read_brief: str = ""
    """The same in a few words, e.g. '1000 rows' or "'j1', 1000 messages"."""
    source: LogSource | None = None
    """The checked columns before differentiation, so the log can be derived again with another window."""

    @property
    def name(self) -> str:
        """The log's name in lists: its file's name, or the SysId test a run of a data log is."""
        run = None if self.source is None else getattr(self.source.table, "run", None)
        return shown_name(run or os.path.basename(os.path.normpath(self.path)))  # any name: the file's or the log's

    def with_window(self, window: int | None, order: int | None = None) -> JointLog:
        """The same log with its missing derivatives estimated by another window (and order); self if none."""
        if self.source is None or self.derivatives is None:
            return self
        order = self.derivatives.order if order is None else order
        return _derive(self.source, degrees=self.degrees, window=window, order=order)

    @property
    def notes(self) -> tuple[str, ...]:
        """Sentences a person should read alongside the fit."""
        notes = [f"{self.path}: {note}" for note in self.read_notes]
        if self.ignored:
            notes.append(f"{self.path}: ignored columns " + ", ".join(repr(n) for n in self.ignored) + ".")
        if self.timing is not None:
            notes.extend(f"{self.path}: {text}" for text in self.timing.descriptions)
        if self.derivatives is not None:
            notes.append(f"{self.path}: {self.derivatives.description}")
        return tuple(notes)


    @property
    def origin(self) -> dict:
        """JSON-ready: the file, its format (with a bag's topic and joint), time window and effort scale."""
        if self.source is None:
            return {"path": shown_name(self.path), "format": "csv", "time_window": None, "effort_scale": 1.0}
        return self.source.table.origin

    @property
    def conventions(self) -> dict:
        """JSON-ready: which column gave each quantity, and how the logged angle became q (zero, direction, wraps
        undone, whole turns removed)."""
        table = None if self.source is None else self.source.table
        pairs = () if table is None else table.read_as
        reading = AngleReading() if table is None or table.angle is None else table.angle
        return {"columns": dict(pairs), **reading.to_dict(logged_angle_name(pairs))}

    @property
    def effort(self) -> Effort:
        """What the log's effort column holds once read: torque (N m; a current log's converted), or voltage (V)."""
        return effort_named("torque" if self.source is None else self.source.table.effort)

    @property
    def position_unit(self) -> str:
        """The unit q was logged in, in words: 'radians', 'degrees' (converted), or 'metres' (a length, kept)."""
        if getattr(None if self.source is None else self.source.table, "linear", False):
            return "metres"
        return "degrees" if self.degrees else "radians"

    @cached_property
    def angle_quantum(self) -> float:
        """The 1st percentile of the logged angle's steps between samples, leaving out those within rounding: its
        quantisation step when it has one; 0 when the angle never moves. Once per log (every refit reads it)."""
        q = self.data.q if self.source is None else self.source.columns["q"]
        steps = np.abs(np.diff(q))
        steps = steps[steps > 1e-9 * max(1.0, float(np.max(np.abs(q))))]
        return float(np.percentile(steps, 1)) if len(steps) else 0.0

    def source_text(self) -> str:
        """One line describing what was read, e.g. for the line above the readouts."""
        units = "degrees converted to radians" if self.position_unit == "degrees" else self.position_unit
        return f"{shown_name(self.path)}: {self.read_text or f'{self.rows} rows'} ({units}), {self.data.count} samples"



def check_finite(table: LogTable) -> None:
    """Raise LogError at the first NaN or infinite value (earliest row, then leftmost column)."""
    first = None
    for name, values in table.columns.items():
        if not all_finite(values):
            index = int(np.flatnonzero(~np.isfinite(values))[0])
            if first is None or index < first[0] or (index == first[0] and table.positions[name] < table.positions[first[1]]):
                first = (index, name)
    if first is not None:
        index, name = first
        value = table.columns[name][index]
        kind = "NaN" if math.isnan(value) else "infinity"
        raise table.error(f"{kind} is not a measurement", index, name)


def check_time(table: LogTable, uniform: bool) -> tuple[dict, TimeCheck | None]:
    """The table's columns after the time checks of jointid.logs.timing (resampled when `uniform` is needed and
    the steps jitter), and what they showed; LogError naming the row and time of a problem.

    Without a t column there is nothing to check: (columns, None).
    """
    t = table.columns.get("t")
    if t is None:
        return table.columns, None
    try:
        return check_times(t, table.columns, uniform=uniform)
    except TimeProblem as problem:
        raise table.error(problem.problem, problem.index, "t") from None


def _check_estimates(table: LogTable, step: float, estimates, missing: tuple[str, ...]) -> None:
    """Raise LogError when an estimated derivative is not finite (a tiny time step, or a huge q)."""
    for name, values in estimates:
        if name in missing and not np.isfinite(values).all():
            raise table.error(
                f"{name} estimated from q at a time step of {step:.3g} s overflows double precision; "
                "give t in seconds and q in radians (or degrees with --degrees)",
                None,
                "t",
            )



def joint_log_from_table(
    table: LogTable, *, degrees: bool = False, window: int | None = DEFAULT_WINDOW, order: int = DEFAULT_ORDER,
    cutoff: float | None = None,
) -> JointLog:
    """Check a table's time column, estimate any missing qd/qdd, convert units: the log ready to fit.

    Every log source ends here, so all logs are checked and differentiated
    alike; LogError on any problem. A window of None follows the low-pass's
    cutoff (`cutoff`, or the automatic one when None or 0), as
    `derivatives.smoothing_window` says.
    """
    check_filter(window, order)
    missing = tuple(n for n in ("qd", "qdd") if n not in table.columns)
    columns, timing = check_time(table, uniform=bool(missing))
    return _derive(LogSource(table, columns, timing), degrees=degrees, window=window, order=order, cutoff=cutoff)


def _derive(source: LogSource, *, degrees: bool, window: int | None, order: int,
            cutoff: float | None = None) -> JointLog:
    """The JointLog of checked columns: missing derivatives estimated with `window` (None: from the cutoff), units
    SI."""
    table, columns, timing = source.table, source.columns, source.timing
    # Both or neither: a logged velocity went through the drive's own estimator, not the smoothing that qdd
    # gets, and columns that are filtered differently no longer satisfy the same equation.
    missing = ("qd", "qdd") if not {"qd", "qdd"} <= set(columns) else ()
    step = None if timing is None else timing.step
    count = len(columns["q"])
    scale = math.pi / 180 if degrees else 1.0
    q = columns["q"] * scale if degrees else columns["q"]
    choice = None
    if missing and window is None:
        window = order + 2 if order % 2 else order + 3  # too few rows for a motion: refused just below
        if count >= max(window, MIN_FIT_ROWS) and step is not None:
            automatic = None if cutoff else automatic_cutoff(q, step)
            follows = cutoff if cutoff else (automatic or (None,))[0]
            if follows:
                choice = smoothing_window(step, follows, order, count, automatic)
                window = choice.window
            else:
                choice = WindowChoice(window, 0.0, "automatic: the shortest for the order, as q shows no motion "
                                      "to follow")
    needed = max(MIN_FIT_ROWS, window if missing else 0)
    if count < needed:
        why = f"a window of {window} samples needs as many and " if missing else ""
        rows = f"{table.count} data rows" if count == table.count else f"{count} samples after the time checks"
        raise LogError(table.path, f"has {rows}; {why}fitting 3 parameters needs at least {needed}")
    estimate = None
    if missing:
        check_filter(window, order)
        # A step like 1e-302 s makes the filter's 1/dt^2 overflow: checked just below, by name.
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
            velocity, acceleration = differentiate(q, step, window, order)
        _check_estimates(table, step, (("qd", velocity), ("qdd", acceleration)), missing)
        qd, qdd = velocity, acceleration
        t, tau = columns["t"], columns["tau"]
        estimate = DerivativeEstimate(METHOD, window, order, step, 0, missing, choice)
    else:
        qd, qdd = columns["qd"], columns["qdd"]
        if degrees:
            qd, qdd = qd * scale, qdd * scale
        t, tau = columns.get("t"), columns["tau"]
    if table.angle is not None and not table.angle.convention.is_default:
        # Last, on the columns in SI units: everything before (resampling, the window's choice) saw the log's
        # own angle, and the offset is in radians.
        convention = table.angle.convention
        if convention.clockwise:
            q, qd, qdd, tau = convention.offset - q, -qd, -qdd, -tau
        else:
            q = q + convention.offset
    return JointLog(
        path=table.path,
        data=JointData(t=t, q=q, qd=qd, qdd=qdd, tau=tau),
        ignored=table.ignored,
        derivatives=estimate,
        degrees=degrees,
        rows=table.count,
        timing=timing,
        read_notes=table.notes + tuple(
            f"the logged {name} is not used: qd and qdd are both estimated from q, so that they are smoothed "
            "alike (a logged velocity went through the drive's own estimator)." for name in ("qd", "qdd")
            if name in columns and missing),
        read_text=table.description,
        read_brief=table.brief,
        source=source,
    )
