"""What `jointid watch` shows of each refresh: a JSON-ready object, one text line, the moments parameters became
well determined, and the series of the watch view's charts. Every face of a watch takes its words from here."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..estimation.uncertainty import WELL_DETERMINED, finite_or_none
from ..text_safety import shown_name
from .charts import ChartData
from .text import format_number

if TYPE_CHECKING:
    from ..studies.watch_refresh import ParameterTrace, WatchRefresh

NO_FIT_YET = "no fit yet"
"""A parameter's verdict word before enough samples arrived for a fit."""


def relative_error_pct(trace: ParameterTrace) -> float | None:
    """The trace's error as a percentage of its value's size, or None when it has no finite one."""
    if not (math.isfinite(trace.value) and math.isfinite(trace.error)) or trace.value == 0:
        return None
    return 100.0 * abs(trace.error) / abs(trace.value)


def seconds_text(seconds: float) -> str:
    """'12.4 s' (one decimal: a refresh comes several times a second)."""
    return f"{seconds:.1f} s"


def percent_text(value: float | None) -> str:
    """'4.8 %', '0.35 %', '12 %', '>999 %' or '—' (two significant figures below 10, whole above)."""
    if value is None:
        return "—"
    if value >= 1000:
        return ">999 %"
    if value < 1:
        return f"{value:.2g} %"
    return f"{value:.1f} %" if value < 10 else f"{value:.0f} %"


def determination_sentence(trace: ParameterTrace) -> str | None:
    """'kA determined to 4.8 % after 12.4 s', or None while it has not become well determined."""
    if trace.determined_at is None:
        return None
    pct = "" if trace.determined_pct is None else f" to {percent_text(trace.determined_pct)}"
    return f"{trace.name} determined{pct} after {seconds_text(trace.determined_at)}"


def determination_sentences(refresh: WatchRefresh) -> tuple[str, ...]:
    """One determination sentence per parameter that has become well determined, in the model's order."""
    return tuple(sentence for trace in refresh.parameters if (sentence := determination_sentence(trace)))


def verdict_word(trace: ParameterTrace) -> str:
    """The trace's verdict, or 'no fit yet' before the first fit."""
    return trace.verdict or NO_FIT_YET


def parameter_text(trace: ParameterTrace, digits: int = 4) -> str:
    """'I 0.8000 ± 3.8 % well determined' (value to `digits` significant figures, zeros kept; '—' without a fit)."""
    if trace.verdict is None or not math.isfinite(trace.value):
        return f"{trace.name} — {verdict_word(trace)}"
    return f"{trace.name} {trace.value:#.{digits}g} ± {percent_text(relative_error_pct(trace))} {verdict_word(trace)}"


def counts_text(refresh: WatchRefresh) -> str:
    """'12.4 s, 620 received, 580 fitted' (and the samples dropped when any were)."""
    text = f"{seconds_text(refresh.elapsed)}, {refresh.received:,} received, {refresh.fitted:,} fitted"
    return text + (f", {refresh.dropped:,} dropped (too fast to keep up)" if refresh.dropped else "")


def refresh_line(refresh: WatchRefresh) -> str:
    """One line per refresh for a pipe or a file: the counts, then each parameter with its error and verdict."""
    return f"{counts_text(refresh)}: " + "; ".join(map(parameter_text, refresh.parameters))


def tests_text(refresh: WatchRefresh) -> str | None:
    """'Tests: quasistatic-forward 8.1 s, dynamic-forward 2.0 s' for a SysId routine watched, else None."""
    if not refresh.tests:
        return None
    return "Tests: " + ", ".join(f"{shown_name(name)} {seconds_text(seconds)}" for name, seconds in refresh.tests)


def closing_lines(refresh: WatchRefresh) -> tuple[str, ...]:
    """What a text watch prints after its last refresh: the moments of determination, what is still not
    determined with the advice on the motion, the SysId tests seen."""
    lines = list(determination_sentences(refresh))
    undetermined = [trace.name for trace in refresh.parameters if trace.verdict != WELL_DETERMINED]
    if undetermined:
        lines.append(f"Not well determined: {', '.join(undetermined)}.")
        lines.extend(refresh.advice)
    tests = tests_text(refresh)
    if tests:
        lines.append(tests)
    return tuple(lines)


def trace_object(trace: ParameterTrace) -> dict:
    """One parameter of a refresh as JSON-ready values (None where there is none)."""
    return {
        "label": trace.label,
        "unit": trace.unit,
        "value": finite_or_none(trace.value) if trace.verdict is not None else None,
        "std_error": finite_or_none(trace.error) if trace.verdict is not None else None,
        "relative_std_pct": relative_error_pct(trace) if trace.verdict is not None else None,
        "verdict": trace.verdict,
        "reason": trace.reason,
        "determined_at": trace.determined_at,
        "determined_pct": trace.determined_pct,
    }


def refresh_object(refresh: WatchRefresh) -> dict:
    """A refresh as one JSON-ready object: counts, each parameter, and the verdicts and their reasons under the
    keys a log fit's JSON uses ("estimate", "std_error", "verdicts", "verdict_reasons")."""
    traces = refresh.parameters
    fitted = [trace for trace in traces if trace.verdict is not None]
    return {
        "elapsed": refresh.elapsed,
        "received": refresh.received,
        "fitted": refresh.fitted,
        "dropped": refresh.dropped,
        "ended": refresh.ended,
        "estimate": {trace.name: finite_or_none(trace.value) for trace in fitted} or None,
        "std_error": {trace.name: finite_or_none(trace.error) for trace in fitted} or None,
        "verdicts": {trace.name: trace.verdict for trace in traces},
        "verdict_reasons": {trace.name: trace.reason for trace in traces if trace.reason},
        "parameters": {trace.name: trace_object(trace) for trace in traces},
        "determined": list(determination_sentences(refresh)),
        "advice": list(refresh.advice),
        "tests": {shown_name(name): seconds for name, seconds in refresh.tests},
        "events": list(refresh.events),
    }


@dataclass(frozen=True)
class Saved:
    """What became of the received samples when watching stopped: written to `path`, or why not."""

    path: str | None
    """The log written, or None when none was."""
    samples: int
    """Samples in it (or received, when none was written)."""
    why_not: str | None = None
    """Why nothing was written: no --save, no sample received, or the error that stopped the write."""


def saved_sentence(saved: Saved) -> str:
    """'Wrote 620 samples to arm.csv (jointid fit --csv arm.csv fits them).' or why nothing was written."""
    if saved.path is None:
        return f"Nothing saved: {saved.why_not}."
    name = shown_name(saved.path)
    return f"Wrote {saved.samples:,} samples to {name} (jointid fit --csv {name} fits them)."


def saved_brief(saved: Saved) -> str:
    """'wrote 620 samples to arm.csv' or 'nothing saved (no --save PATH given)': the status line's short form."""
    if saved.path is None:
        return f"nothing saved ({saved.why_not})"
    return f"wrote {saved.samples:,} samples to {shown_name(saved.path)}"


def saved_object(saved: Saved, stopped_by: str) -> dict:
    """The last JSON line of a watch: how it stopped and what was saved."""
    return {"stopped_by": stopped_by,
            "saved": None if saved.path is None else {"path": shown_name(saved.path), "samples": saved.samples},
            "not_saved": saved.why_not}


def recent_chart(refresh: WatchRefresh, effort: str = "torque") -> ChartData | None:
    """The last seconds' measured effort (dots) against the current fit's (line), as a log's torque chart; None
    before any sample."""
    recent = refresh.recent
    t, measured = recent.get("t"), recent.get("tau")
    if t is None or measured is None or len(t) < 2:
        return None
    predicted = recent.get("predicted")
    if predicted is not None and (len(predicted) != len(t) or not np.isfinite(predicted).all()):
        predicted = None
    volts = effort == "voltage"
    quantity, unit = ("Voltage", "V") if volts else ("Torque", "N m")
    span = float(t[-1] - t[0])
    return ChartData(
        titles=(f"{quantity} of the last {span:.0f} s: measured and the current fit", f"Last {span:.0f} s", "Recent"),
        t=np.asarray(t, dtype=float), dots=np.asarray(measured, dtype=float),
        line=None if predicted is None else np.asarray(predicted, dtype=float),
        dots_label="measured", line_label="fit",
        summaries=(f"{len(t)} samples from {format_number(float(t[0]), 1)} to {format_number(float(t[-1]), 1)} s",),
        y_label=f"{quantity} ({unit})")


@dataclass(frozen=True, eq=False)
class ConvergenceData:
    """Each parameter's history for the watch view's chart: x (seconds watched) and y per parameter, (M,) each."""

    titles: tuple[str, ...]
    lines: tuple[tuple[str, np.ndarray, np.ndarray], ...]
    """(parameter name, seconds watched, values) per parameter with a history."""
    y_label: str
    x_label: str = "Seconds watched"

    def key(self) -> tuple:
        """Equal for charts that draw the same (the histories only grow, so their ends and lengths tell)."""
        return (self.titles, self.y_label,
                tuple((name, len(x), float(x[-1]), float(y[-1])) for name, x, y in self.lines))


CONVERGENCE_KINDS = ("estimate", "error")
"""What the convergence chart can show: each estimate relative to its latest, or each relative error."""


def convergence_chart(refresh: WatchRefresh, kind: str = "estimate") -> ConvergenceData:
    """Each parameter's estimate over time as a ratio to its latest value (converging to 1), or its relative error
    (%) over time (falling): the parameters' units differ, so both are shown without them."""
    lines = []
    for trace in refresh.parameters:
        history = np.asarray(trace.history, dtype=float).reshape(-1, 3)
        if len(history) < 2:
            continue
        seconds, values, errors = history.T
        if kind == "error":
            with np.errstate(divide="ignore", invalid="ignore"):
                y = 100.0 * np.abs(errors) / np.abs(values)
        else:
            latest = trace.value if math.isfinite(trace.value) and trace.value != 0 else values[-1]
            y = values / latest if latest else values
        keep = np.isfinite(y)
        if keep.sum() >= 2:
            lines.append((trace.name, seconds[keep], y[keep]))
    waiting = () if lines else (f"{kind.capitalize()}s over time: drawn from the second fitted refresh on",
                                "Drawn from the second refresh", "")
    if kind == "error":
        return ConvergenceData(waiting or ("Relative error (%) of each parameter over time", "Error (%) over time",
                                           "Error %"), tuple(lines), "Error (%)")
    return ConvergenceData(waiting or ("Each estimate over time, as a share of its latest (1 = now)",
                                       "Estimate / latest", "Estimates"), tuple(lines), "Share of latest")
