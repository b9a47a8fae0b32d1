"""The JSON documents `jointid ... --json` prints and the explorer exports.

Plain JSON-ready values at full float precision; None (null) where a value is
unavailable, infinite or NaN. Per-parameter values are objects keyed by the
model's term names, e.g. {"I": ..., "h": ..., "B": ...} for the plain model.
`json_text` turns any of them into strict JSON text: Python's json module
would otherwise write Infinity and NaN, which strict parsers reject.
"""

from __future__ import annotations

import json
import math
from typing import TYPE_CHECKING

from ..text_safety import shown_name
from ..estimation.uncertainty import finite_or_none
from .status import fit_warnings, status_message
from .tables import sweep_message

if TYPE_CHECKING:
    from ..estimation.fit import FitResult
    from ..studies.cross_excitation import CrossExcitationTable
    from ..studies.sweep import SweepResult
    from ..synthetic.settings import Settings


class NonFiniteValue(ValueError):
    """A document holds infinity or NaN, which strict JSON cannot carry; `key` says where."""

    def __init__(self, key: str):
        super().__init__(f"{key} is not a finite number")
        self.key = key


def json_text(document, *, ensure_ascii: bool = True) -> str:
    """The document as strict JSON text (indent 2); NonFiniteValue naming the first inf or NaN in it."""
    try:
        return json.dumps(document, indent=2, allow_nan=False, ensure_ascii=ensure_ascii)
    except ValueError:
        key = _non_finite_key(document)
        if key is None:
            raise
        raise NonFiniteValue(key) from None


def _non_finite_key(value, key: str = "") -> str | None:
    """The dotted key ('statistics.I.std', 'rows[1]') of the first inf or NaN float in nested dicts and lists."""
    if isinstance(value, float):
        return None if math.isfinite(value) else key or "the document"
    if isinstance(value, dict):
        items = ((f"{key}.{name}" if key else str(name), item) for name, item in value.items())
    elif isinstance(value, (list, tuple)):
        items = ((f"{key}[{index}]", item) for index, item in enumerate(value))
    else:
        return None
    return next((found for path, item in items if (found := _non_finite_key(item, path)) is not None), None)


def per_parameter(names: tuple[str, ...], values) -> dict:
    """JSON object keyed by parameter name from a (p,) sequence (floats, [low, high] pairs or strings); all None for None."""
    if values is None:
        return dict.fromkeys(names)
    return {name: _json_value(value) for name, value in zip(names, values)}


def _json_value(value):
    """A verdict string, a finite float, a [low, high] list, or None for inf/NaN (or no value)."""
    if value is None or isinstance(value, str):
        return value
    if getattr(value, "shape", ()) != ():
        return [finite_or_none(v) for v in value]
    return finite_or_none(value)


def estimate_object(result: FitResult) -> dict | None:
    """{"I": ..., "h": ..., "B": ...} of a unique fit, or None."""
    estimate = result.estimate
    return None if estimate is None else dict(zip(result.model.names, map(float, estimate)))


def settings_object(settings: Settings) -> dict:
    """The synthetic settings as a JSON object (a designed motion as its name plus its motion file's object)."""
    document = vars(settings).copy()
    if not isinstance(settings.motion, str):
        from ..synthetic.fourier import motion_document  # only a designed motion needs it

        document["motion"] = settings.motion_name
        document["designed_motion"] = motion_document(settings.motion)
    return document


def column_estimate_object(result: FitResult) -> dict:
    """{"column_estimate": {"h_c": ..., "h_s": ...}} for a model that reports other parameters than its
    columns (an angle offset: the raw coefficients behind h and q0); {} otherwise."""
    offset = result.model.angle_offset
    if offset is None:
        return {}
    estimate = result.column_estimate
    columns = [result.model.column_names[i] for i in (offset.cosine, offset.sine)]
    values = None if estimate is None else {name: float(estimate[result.model.column_names.index(name)])
                                            for name in columns}
    return {"column_estimate": values}


def constraint_object(result: FitResult) -> dict:
    """For a constrained fit: {"constrained": true, "at_bound": [...], "unconstrained_estimate": {...}}; {} otherwise."""
    if not result.constrained:
        return {}
    unconstrained = result.unconstrained_estimate
    return {
        "constrained": True,
        "at_bound": list(result.at_bound),
        "unconstrained_estimate": None if unconstrained is None
        else dict(zip(result.model.names, map(float, unconstrained))),
    }


def result_to_dict(result: FitResult) -> dict:
    """The fit as plain JSON-ready values, full float precision, None where unavailable."""
    return {
        "model": result.model.name,
        "samples": result.training.count,
        "rank": result.rank,
        "estimate": estimate_object(result),
        **column_estimate_object(result),
        **constraint_object(result),
        "training_rmse": result.training_rmse,
        "heldout_rmse": result.heldout_rmse,
        "accel_rms": result.accel_rms,
        "speed_rms": result.speed_rms,
        "sign_failures": list(result.sign_failures),
        "message": status_message(result),
        **uncertainty_to_dict(result),
    }


def uncertainty_to_dict(result: FitResult) -> dict:
    """Standard errors, intervals, verdicts (objects keyed by parameter; None where unavailable), conditioning, subset, warnings."""
    uncertainty = result.uncertainty
    names = result.model.names
    return {
        # The reported errors (the noise's widened by the other analysis choices, as the verdicts say); the noise's
        # alone under a name that says so.
        "std_error": per_parameter(names, uncertainty and uncertainty.residual_std_error),
        "noise_std_error": per_parameter(names, uncertainty and uncertainty.noise_std_error),
        # The issues' schema: null, not an object of nulls, when no noise bound is known (logs).
        "noise_bound_std_error": (
            None if result.noise_bound is None
            else per_parameter(names, uncertainty and uncertainty.noise_bound_std_error)
        ),
        "relative_std_pct": per_parameter(names, uncertainty and uncertainty.relative_std_pct),
        "interval95": per_parameter(names, uncertainty and uncertainty.interval95),
        # The judged verdicts every face shows; the noise's alone under a name that says so.
        "verdicts": per_parameter(names, uncertainty and result.judgement.verdicts),
        "noise_verdicts": per_parameter(names, uncertainty and uncertainty.verdicts),
        "verdict_reasons": {name: reason for name, reason in zip(names, result.judgement.reasons) if reason},
        "verdict_basis": uncertainty and uncertainty.verdict_basis,
        "condition_number": finite_or_none(result.condition_number),
        "identifiable": result.identifiable.values,
        "warnings": list(fit_warnings(result)),
    }


def simulation_object(check) -> dict:
    """{"simulation_horizon", "simulation_rmse", "simulation_diverged_windows", "simulation_windows"} (simulation.SimulationCheck or None)."""
    if check is None:
        return {"simulation_horizon": None, "simulation_rmse": None, "simulation_diverged_windows": None,
                "simulation_windows": None}
    return {"simulation_horizon": check.horizon, "simulation_rmse": check.rmse,
            "simulation_diverged_windows": check.diverged_windows, "simulation_windows": len(check.window_errors)}


def fit_document(result: FitResult, *, settings: Settings | None = None, source=None, derivatives=None,
                 **extra) -> dict:
    """The command line's JSON object for one fit: `settings` (None for a log), `source`, `derivatives`, the fit.

    `source` is {"training": path, "heldout": path or None} for logs and None for
    synthetic data; `derivatives` says how missing qd/qdd were estimated, or None.
    """
    return {
        "settings": None if settings is None else settings_object(settings),
        "source": source,
        "derivatives": derivatives,
        **extra,
        **result_to_dict(result),
    }


def log_fit_document(result: FitResult, training, heldout=None, low_pass=None, sensitivity=None,
                     notes=None) -> dict:
    """fit_document for a fit of logs (csvlog.JointLog objects): source paths, the columns read and the angle's
    conventions, derivatives, timing, the parallel low-pass (parallel_filter.ParallelFilter), the sensitivity check and notes."""
    return fit_document(
        result,
        source={"training": shown_name(training.path), "heldout": None if heldout is None else shown_name(heldout.path)},
        logs={"training": training.origin, "heldout": None if heldout is None else heldout.origin},
        conventions={"training": training.conventions, "heldout": None if heldout is None else heldout.conventions},
        derivatives=None if training.derivatives is None else training.derivatives.to_dict(),
        heldout_derivatives=None if heldout is None or heldout.derivatives is None else heldout.derivatives.to_dict(),
        timing=None if training.timing is None else training.timing.to_dict(),
        heldout_timing=None if heldout is None or heldout.timing is None else heldout.timing.to_dict(),
        low_pass=None if low_pass is None else low_pass.to_dict(),
        sensitivity=None if sensitivity is None else sensitivity.to_dict(),
        notes=list(notes) if notes is not None else [*training.notes, *(heldout.notes if heldout is not None else ())],
    )


def sweep_document(sweep: SweepResult) -> dict:
    """`jointid sweep --json`: the settings and the sweep's statistics (None where unavailable)."""
    names = sweep.model.names
    statistics = dict.fromkeys(sweep.quantities)
    for name, distribution in sweep.statistics.items():
        statistics[name] = vars(distribution).copy()
    return {
        "settings": settings_object(sweep.settings),
        "model": sweep.model.name,
        "seeds": {"first": int(sweep.seeds[0]), "last": int(sweep.seeds[-1]), "count": sweep.seed_count},
        "rank": sweep.rank,
        "condition_number": finite_or_none(sweep.condition_number),
        "statistics": statistics,
        "empirical_std": per_parameter(names, sweep.empirical_std),
        "noise_bound_std_error": per_parameter(names, sweep.noise_bound_std_error),
        "sign_failure_fraction": sweep.sign_failure_fraction,
        "sign_failure_fractions": sweep.sign_failure_fractions,
        **({} if sweep.held is None else {"constraint_active_fraction": sweep.constraint_active_fraction}),
        "message": sweep_message(sweep),
    }


def matrix_document(table: CrossExcitationTable) -> dict:
    """`jointid matrix --json`: one object per row, cells keyed by prediction motion."""
    rows = []
    for row in table.rows:
        rows.append(
            {
                "training_motion": row.training_motion,
                "rank": row.fit.rank,
                "estimate": estimate_object(row.fit),
                "cells": {
                    cell.prediction_motion: {"rmse": cell.rmse, "training_data": cell.is_training_data}
                    for cell in row.cells
                },
            }
        )
    return {
        "settings": settings_object(table.settings),
        "model": table.settings.model,
        "prediction_motions": list(table.prediction_motions),
        "rows": rows,
    }


def comparison_document(comparison, *, settings: Settings | None = None, source=None) -> dict:
    """`jointid compare --json`: one object per ladder model, BIC's choice and the sentences (ladder.Comparison)."""
    from .comparison import comparison_sentences  # the sentences live beside the table they explain

    models = []
    for row in comparison.rows:
        uncertainty = row.uncertainty
        names = row.model.names
        perfect = row.bic == -math.inf
        worst = row.worst_determined
        models.append({
            "model": row.model.name,
            "terms": list(names),
            "rank": row.rank,
            "estimate": None if row.estimate is None else dict(zip(names, map(float, row.estimate))),
            "std_error": per_parameter(names, uncertainty and uncertainty.verdict_std_error),
            "training_rmse": row.training_rmse,
            "heldout_rmse": row.heldout_rmse,
            "bic": None if perfect else row.bic,
            **({"bic_note": "zero residual: BIC is minus infinity"} if perfect else {}),
            "condition_number": finite_or_none(row.condition_number),
            "worst_determined": None if worst is None else {"name": worst[0], "relative_std_pct": worst[1]},
        })
    preferred = comparison.preferred
    return {
        "settings": None if settings is None else settings_object(settings),
        "source": source,
        "samples": comparison.samples,
        "preferred": None if preferred is None else preferred.model.name,
        **({"run_preferences": [{"run": run, "preferred": name} for run, name in comparison.run_preferences]}
           if comparison.run_preferences else {}),
        "models": models,
        "message": " ".join(comparison_sentences(comparison)),
    }


def logs_document(logs) -> dict:
    """The JSON document of `jointid fit --csv ... --json` for a studies.log_fit.LoadedLogs."""
    from .notes import exclusion_object, log_notes, omitted_object, omitted_sentence
    from .sensitivity import sensitivity_warning

    document = log_fit_document(logs.result, logs.training, logs.heldout, logs.filter, logs.sensitivity,
                                log_notes(logs))
    # The checks' sentences the text prints beside the verdicts they weaken, so a program is told what a person is.
    checks = (None if logs.sensitivity is None else sensitivity_warning(logs.sensitivity), omitted_sentence(logs))
    document["warnings"] = [*document["warnings"], *(sentence for sentence in checks if sentence)]
    return {**document, **exclusion_object(logs),
            "moved_by_derivative_settings": list(logs.moved_by_settings),
            "omitted_terms": omitted_object(logs),
            "moved_by_omitted_terms": list(logs.decided_by_omitted), **effort_object(logs.result.model),
            **({} if getattr(logs, "mechanism", None) is None else {"mechanism": logs.mechanism.to_dict()})}


def effort_object(model) -> dict:
    """JSON-ready: the effort and the parameters' units when the fit is not in torque (a torque fit's document keeps
    its keys as before)."""
    if model.effort.is_torque:
        return {}
    return {"effort": {"name": model.effort.name, "unit": model.effort.unit},
            "units": {parameter.name: parameter.unit for parameter in model.parameters}}
