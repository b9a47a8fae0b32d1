"""Several runs of one joint in words: each run's own fit beside the pooled one, the scatter, who disagrees."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..studies.runs import POOLED_FIT
from .text import format_number, text_table

if TYPE_CHECKING:
    from ..studies.runs import PooledRuns


SHORT_VERDICTS = {"well determined": "well det.", "not determined": "not det."}
"""The pooled verdicts as the runs table shows them, as narrow as its numbers (the JSON spells them out)."""


def runs_text(pooled: PooledRuns) -> str:
    """The per-run table with the pooled row, then the scatter against the errors and any disagreement."""
    heading, table, *sentences = runs_parts(pooled)
    return "\n".join((heading, table, *sentences))


def runs_parts(pooled: PooledRuns) -> tuple[str, ...]:
    """runs_text in its parts: the heading, the table, then one sentence a line (a narrow screen scrolls the
    table sideways and wraps the sentences)."""
    shared = pooled.shared
    model = pooled.runs[0].result.model
    bias_index = model.index_of("tau0")
    bias = bias_index is not None
    bias_name = None if bias_index is None else model.column_names[bias_index]
    unit = model.effort.unit
    header = ["run", "samples", "cutoff", "left out", *shared, *([bias_name] if bias else []), "others predict"]
    rows = []
    for k, run in enumerate(pooled.runs):
        left = run.exclusions
        share = "-" if left is None else f"{1 - left.kept.mean():.0%}"
        cutoff = "-" if run.filter is None or not run.filter.active else f"{run.filter.cutoff:.3g} Hz"
        other = pooled.predicted_by_others[k]
        unknown = not_determined(run, shared)
        rows.append([run.name, str(run.result.training.count), cutoff, share,
                     *(NOT_SHOWN if name in unknown else format_number(run.params[name]) for name in shared),
                     *([format_number(run.params[bias_name])] if bias else []),
                     "-" if other is None else f"{format_number(other)} {unit}"])
    offsets = pooled.estimate[len(shared):]
    rows.append(["pooled", str(sum(run.result.training.count for run in pooled.runs)), "", "",
                 *(format_number(pooled.params[name]) for name in shared), *(["own"] if bias else []), ""])
    widened = "widened" if pooled.judgement.spread else "Newey-West"  # the analysis choices or the runs' scatter
    rows.append([f"± ({widened})", "", "", "", *(format_number(pooled.bse[name]) for name in shared),
                 *([""] if bias else []), ""])
    rows.append(["verdict", "", "", "", *(SHORT_VERDICTS.get(pooled.verdicts[name], pooled.verdicts[name] or "-")
                                          for name in shared), *([""] if bias else []), ""])
    against = " against an equally weighted pooled fit" if pooled.weighting == POOLED_FIT else ""
    sysid = _is_sysid(pooled)
    routine = _sysid_routine(pooled)
    what = (f"SysId tests of routine {routine!r}" if routine else "SysId tests") if sysid else "runs of one joint"
    lines = [f"{len(pooled.runs)} {what}, each prepared and fitted alone, then together (model "
             f"{model.name}; weights 1/σ² of each run's residuals{against}"
             + (f"; each run keeps its own {model.effort.name} bias" if bias else "") + "):",
             text_table(header, rows)]
    weakened = pooled.judgement.weakened
    if weakened:
        lines.append("Pooled values less certain than their noise alone says: "
                     + "; ".join(f"{name} ({reason})" for name, reason in weakened.items()) + ".")
    if bias:
        lines.append(f"Pooled {model.effort.name} bias of each run: " + ", ".join(
            f"{name} {format_number(value)}" for name, value in zip(pooled.names, offsets)) + f" {unit}.")
    if any(not_determined(run, shared) for run in pooled.runs):
        lines.append(f"{NOT_SHOWN}: not determined by that {'test' if sysid else 'run'} alone (its fit is not "
                     f"unique, its {model.effort.name} constant but for noise, or the error as large as the value); the JSON says "
                     "why.")
    if pooled.mechanism is not None:
        lines.append(pooled.mechanism.note())
    if sysid:
        lines.extend(sysid_reading(pooled))
        lines.append("No SysId test alone separates the gains (a dynamic test's voltage is constant, which its "
                     "Coulomb term fits exactly; a quasistatic test barely accelerates): read the pooled fit. The "
                     "low-pass is off unless --cutoff asks for it, as each dynamic test starts with a step from rest.")
        lines.append("Others predict: the RMS error of each test's effort predicted by the pooled fit of the other "
                     "tests.")
        return tuple(lines)
    lines.append("Scatter between the runs in their reported standard errors (about 1 when the errors are honest): "
                 + ", ".join(f"{name} {value:.1f}" for name, value in pooled.scatter.items()) + ".")
    if pooled.disagreements:
        worst = {}
        for run, name, gap in pooled.disagreements:
            worst.setdefault(run, []).append(f"{name} {gap:.1f}")
        lines.append("Disagrees with the pooled fit beyond their combined noise errors: " + "; ".join(
            f"{run} ({', '.join(parts)} errors)" for run, parts in worst.items())
            + ". The runs do not share one joint within their noise errors: the pooled ± is widened by their scatter.")
    else:
        lines.append("Every run agrees with the pooled fit within its noise errors.")
    lines.append(f"Others predict: the RMS error of each run's filtered {model.effort.name} predicted by the pooled "
                 "fit of the other runs (its own offset).")
    return tuple(lines)


NOT_SHOWN = "—"
"""What the per-run table shows for a parameter that run alone does not determine."""

CONSTANT_EFFORT = 1e-6
"""An effort whose spread is below this share of its magnitude is constant (a dynamic test's step)."""
NOISE_SPREAD = 2.0
"""An effort whose spread is at most this many times the fit's residual RMS is constant but for noise: the fit
explains none of it, and its gains are noise's (a q0 of -2.9 on one machine, 0 on another)."""


def not_determined(run, names) -> dict[str, str]:
    """{parameter: why} for each of `names` that one run's own fit does not determine: no unique fit, an effort
    that does not vary (a constant voltage is fitted exactly by the constant column, whatever the gains), or a
    standard error as large as the value (a number there differs between machines in its rounding)."""
    from ..estimation.uncertainty import NOT_DETERMINED

    result = run.result
    if result.estimate is None or result.uncertainty is None:
        return {name: f"the fit is not unique (rank {result.rank} of {result.parameter_count})" for name in names}
    effort = result.training.tau
    spread = float(np.std(effort)) if len(effort) else 0.0
    residual = float(np.sqrt(np.mean((effort - result.training_predictions) ** 2))) if len(effort) else 0.0
    if spread <= max(CONSTANT_EFFORT * float(np.max(np.abs(effort), initial=0.0)), NOISE_SPREAD * residual):
        return {name: f"its {result.model.effort.name} is constant but for noise, which says nothing of the gains"
                for name in names}
    verdicts = dict(zip(result.model.names, result.uncertainty.verdicts or ()))
    return {name: "its standard error is about as large as itself" for name in names
            if verdicts.get(name) == NOT_DETERMINED}


def _is_sysid(pooled: PooledRuns) -> bool:
    """True when the runs are the tests of a SysId routine log."""
    source = pooled.runs[0].training.source
    return getattr(None if source is None else source.table, "run", None) is not None


def _sysid_routine(pooled: PooledRuns) -> str | None:
    """The SysId routine the runs are the tests of, or None for runs of other logs."""
    table = pooled.runs[0].training.source
    routine = getattr(None if table is None else table.table, "routine", None)
    return None if routine is None else routine.routine


def sysid_reading(pooled: PooledRuns) -> list[str]:
    """What reading a SysId log decided (motors pooled, units, repeated tests, the velocity's lag, tests left out),
    each sentence once across the runs."""
    lines: list[str] = []
    for run in pooled.runs:
        source = run.training.source
        for note in getattr(None if source is None else source.table, "sysid_notes", ()):
            if note not in lines:
                lines.append(note)
    return lines


def runs_document(pooled: PooledRuns) -> dict:
    """The JSON of several runs: each run's own document summary, the pooled fit, the scatter, disagreements."""
    from .documents import logs_document  # each run as `jointid fit --csv RUN --json` prints it

    return {
        "model": pooled.runs[0].result.model.name,
        "weighting": pooled.weighting,
        "sysid_routine": _sysid_routine(pooled),
        "sysid_reading": sysid_reading(pooled),
        "mechanism": None if pooled.mechanism is None else pooled.mechanism.to_dict(),
        "runs": [{**logs_document(run), "name": run.name, "predicted_by_others_rmse": other,
                  "weight": weight,
                  "own_estimate": {name: None if name in not_determined(run, pooled.shared) else run.params[name]
                                   for name in pooled.shared},
                  "not_determined": not_determined(run, pooled.shared)}
                 for run, other, weight in zip(pooled.runs, pooled.predicted_by_others, pooled.weights)],
        "pooled": {"estimate": dict(pooled.params), "std_error": dict(pooled.bse),
                   "noise_std_error": dict(pooled.noise_bse), **pooled.judgement.to_dict(),
                   "torque_bias": dict(zip(pooled.names, map(float, pooled.estimate[len(pooled.shared):])))},
        "scatter_std_errors": pooled.scatter,
        "disagreements": [{"run": run, "parameter": name, "combined_std_errors": gap}
                          for run, name, gap in pooled.disagreements],
    }
