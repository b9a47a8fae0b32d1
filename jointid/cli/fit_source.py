"""What `jointid export` starts from: the parameters and verdicts of a fit it runs as `jointid fit` would, or of
a fit's JSON (`jointid fit --json > fit.json`).

Either way the result is an `Identified`: the model's parameters by name, each
one's verdict, and the log's angle convention, so that the exported joint
reads its angle as the log did.
"""

from __future__ import annotations

import argparse
import json
import math
import os
from dataclasses import dataclass, field, replace

from .arguments import UserError, settings_from
from .log_arguments import fit_any_logs, has_log, with_default_settings

JSON_LIMIT = 64 * 1024 * 1024
"""Largest fit JSON read (bytes): a fit's document is a few kilobytes, several runs' a few hundred."""


@dataclass(frozen=True)
class Identified:
    """The identified joint an export describes."""

    parameters: dict[str, float]
    """The model's reported parameters by name, in its order (I, h, B, then Fc, tau0, q0 when it has them)."""
    model: str
    """The model's name, e.g. 'coulomb+bias'."""
    source: str
    """Where the fit came from, for the files' comment: 'a fit of pendulum_pd.csv (model coulomb+bias)'."""
    verdicts: dict[str, str | None] = field(default_factory=dict)
    """Each parameter's verdict ('well determined', 'weak', 'not determined'), None when it has none."""
    zero: str = "right"
    """Where the log's angle 0 pointed (--zero): the exported joint's 0 points there."""
    clockwise: bool = False
    """Whether the log's angle grew clockwise (--clockwise): the exported joint turns that way."""
    reflected_inertia: float | None = None
    """The motors' rotor inertia reflected through the gear (kg m²), part of I, when a voltage fit's motor gave it."""

    def not_determined(self, names) -> tuple[str, ...]:
        """Those of `names` the fit did not determine, in the model's order."""
        return tuple(name for name in self.parameters if name in names and self.verdicts.get(name) == NOT_DETERMINED)


NOT_DETERMINED = "not determined"
"""The verdict that earns a warning (jointid.estimation.uncertainty.NOT_DETERMINED, not imported: no numpy here)."""


def identified_from_fit(args: argparse.Namespace) -> Identified:
    """Fit as `jointid fit` would with the same flags (synthetic settings, --csv runs or --bag) and take its
    parameters and verdicts; UserError (one line) on any problem, or when the fit has no unique estimate."""
    if not has_log(args):
        from ..studies.experiment import run_experiment

        settings = settings_from(with_default_settings(args))
        result = run_experiment(settings)
        return _from_result(result, f"a fit of the synthetic {settings.motion_name} experiment",
                            f"noise {settings.noise:g} N m, {settings.samples} samples, seed {settings.seed}; ")
    zero, clockwise = getattr(args, "zero", None) or "right", bool(getattr(args, "clockwise", False))
    fitted = fit_any_logs(args)  # several runs (repeated --csv, a SysId log's tests) or one log
    if hasattr(fitted, "runs"):
        return _through_motor(_from_pooled(fitted, zero, clockwise), fitted, fitted.runs[0].result.model, args)
    logs = fitted
    identified = _from_result(logs.result, f"a fit of {logs.name}", zero=zero, clockwise=clockwise)
    return _through_motor(identified, logs, logs.result.model, args)


VOLTS_NEED_A_MOTOR = ("gives gains in volts (kA, kG, kV, kS), not a body's I, h, B: give the motor behind them "
                      "(--motor NAME --gear G, or --motor-r/--motor-kt/--motor-kv) to export the physical parameters")


def _through_motor(identified: Identified, fit, model, args: argparse.Namespace) -> Identified:
    """A torque fit as it is; a voltage fit's gains turned into the physical I, h, B, Fc (q0) through the motor
    given (studies.gains.motor_parameters), with their verdicts; UserError without a motor."""
    if model.effort.is_torque:
        return identified
    from ..studies.gains import GainsError, motor_parameters
    from .effort_arguments import motor_drive

    drive = motor_drive(args)
    if drive is None:
        raise UserError(f"{identified.source} {VOLTS_NEED_A_MOTOR}")
    try:
        physical = motor_parameters(fit, drive)
    except GainsError as error:
        raise UserError(str(error)) from None
    return replace(identified, parameters={p.name: p.value for p in physical.parameters},
                   verdicts={p.name: p.verdict for p in physical.parameters},
                   source=f"{identified.source} through {drive.description()}",
                   reflected_inertia=drive.reflected_inertia)


def _from_result(result, described: str, details: str = "", *, zero: str = "right",
                 clockwise: bool = False) -> Identified:
    """The parameters and verdicts of one FitResult (`details` go before the model's name in parentheses)."""
    if result.estimate is None:
        raise UserError(f"{described} has no unique estimate (rank {result.rank} of {result.parameter_count}): "
                        "nothing to export; fit a motion that reveals every parameter")
    return Identified(dict(result.params), result.model.name, f"{described} ({details}model {result.model.name})",
                      dict(result.verdicts), zero, clockwise)


def _from_pooled(pooled, zero: str, clockwise: bool) -> Identified:
    """The pooled fit of several runs: its shared parameters with their judged verdicts."""
    model = pooled.runs[0].result.model.name
    return Identified(dict(pooled.params), model,
                      f"the pooled fit of {len(pooled.runs)} runs ({', '.join(pooled.names)}; model {model})",
                      dict(pooled.verdicts), zero, clockwise)


def _verdict_of(value: float, error: float, verdict) -> str | None:
    """The verdict of an estimate with a standard error, as a single fit judges it; None without an error."""
    if not math.isfinite(error):
        return None
    relative = math.inf if value == 0 and error > 0 else (0.0 if error == 0 else 100 * error / abs(value))
    return verdict(relative)


def identified_from_json(path: str) -> Identified:
    """The parameters and verdicts in a fit's JSON (`jointid fit --json`, one fit or several runs); UserError
    (one line naming the file) when it is not one."""
    from ..files import FileRefused, read_bytes, shown_path

    shown = shown_path(path)
    try:
        data = read_bytes(path, JSON_LIMIT)
    except FileRefused as error:
        raise UserError(str(error)) from None
    if len(data) > JSON_LIMIT:
        raise UserError(f"{shown}: larger than {JSON_LIMIT // 2**20} MB; a fit's JSON is a few kilobytes")
    try:
        document = json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, ValueError) as error:
        raise UserError(f"{shown}: not JSON ({_first_line(error)}); give what `jointid fit --json` prints") from None
    except RecursionError:  # the parser recurses per level: a few thousand brackets are past its stack
        raise UserError(f"{shown}: JSON nested too deeply; a fit's JSON is a few levels deep (give what `jointid "
                        "fit --json` prints)") from None
    if not isinstance(document, dict):
        raise UserError(f"{shown}: not a fit's JSON object; give what `jointid fit --json` prints")
    name = os.path.basename(os.path.normpath(path))
    if isinstance(document.get("pooled"), dict) and isinstance(document.get("runs"), list):
        return _from_runs_document(document, shown, name)
    return _from_fit_document(document, shown, name)


def _from_fit_document(document: dict, shown: str, name: str) -> Identified:
    """One fit's document: its model, estimate, verdicts and (for a log) the training log's conventions."""
    model = document.get("model")
    estimate = document.get("estimate")
    if not isinstance(model, str) or "estimate" not in document:
        raise UserError(f"{shown}: has no model and estimate; give what `jointid fit --json` prints")
    if estimate is None:
        raise UserError(f"{shown}: the fit has no unique estimate (rank {document.get('rank')}): nothing to export")
    parameters = _numbers(estimate, shown, "estimate")
    verdicts = document.get("verdicts") if isinstance(document.get("verdicts"), dict) else {}
    zero, clockwise = _conventions(document, shown)
    if (document.get("effort") or {}).get("name") == "voltage":  # the physical parameters its --motor gave
        parameters, verdicts, model = _through_motor_document(document, shown, model)
    return Identified(parameters, model, f"the fit in {name} (model {model})",
                      {key: value if isinstance(value, str) else None for key, value in verdicts.items()},
                      zero, clockwise)


def _from_runs_document(document: dict, shown: str, name: str) -> Identified:
    """Several runs' document: the pooled estimate, judged by its standard errors, and the first run's
    conventions (every run is read alike)."""
    from ..estimation.uncertainty import verdict

    pooled = document["pooled"]
    model = document.get("model")
    if not isinstance(model, str):
        raise UserError(f"{shown}: has no model; give what `jointid fit --json` prints")
    parameters = _numbers(pooled.get("estimate"), shown, "pooled.estimate")
    errors = pooled.get("std_error") if isinstance(pooled.get("std_error"), dict) else {}
    given = pooled.get("verdicts") if isinstance(pooled.get("verdicts"), dict) else {}
    # The document's judged verdicts; an older document without them is judged by its errors alone.
    verdicts = {key: given[key] if isinstance(given.get(key), str) else
                _verdict_of(value, float(errors[key]), verdict) if _is_number(errors.get(key)) else None
                for key, value in parameters.items()}
    if "I" not in parameters and "kA" in parameters:  # runs in volts: the physical parameters their --motor gave
        parameters, verdicts, model = _through_motor_document(document, shown, model)
    runs = document["runs"]
    zero, clockwise = _conventions(runs[0], shown) if runs and isinstance(runs[0], dict) else ("right", False)
    return Identified(parameters, model, f"the pooled fit of {len(runs)} runs in {name} (model {model})",
                      verdicts, zero, clockwise)


def _through_motor_document(document: dict, shown: str, model: str) -> tuple[dict[str, float], dict, str]:
    """(parameters, verdicts, model) of a voltage fit's document from the physical parameters its --motor gave;
    UserError when it was fitted without a motor."""
    motor = document.get("motor") if isinstance(document.get("motor"), dict) else {}
    physical = motor.get("parameters")
    if not isinstance(physical, dict):
        raise UserError(f"{shown}: a voltage log's fit {VOLTS_NEED_A_MOTOR.split(': give')[0]}: fit it with "
                        "its motor (--motor NAME --gear G) and export that JSON")
    parameters = _numbers({k: v.get("value") if isinstance(v, dict) else v for k, v in physical.items()},
                          shown, "motor.parameters")
    verdicts = {k: v.get("verdict") for k, v in physical.items() if isinstance(v, dict)}
    return parameters, verdicts, f"{model} through {motor.get('motor', 'a motor')}"


def _numbers(values, shown: str, key: str) -> dict[str, float]:
    """{name: finite number} of a document's estimate; UserError when it is not one."""
    if not isinstance(values, dict) or not values or not all(_is_number(value) for value in values.values()):
        raise UserError(f"{shown}: {key} is not an object of numbers; give what `jointid fit --json` prints")
    return {str(key): float(value) for key, value in values.items()}


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _conventions(document: dict, shown: str) -> tuple[str, bool]:
    """(zero, clockwise) of a log fit's training log, ('right', False) for a synthetic fit."""
    from ..logs.conventions import ZEROS

    training = (document.get("conventions") or {}).get("training") if isinstance(document.get("conventions"), dict) \
        else None
    if not isinstance(training, dict):
        return "right", False
    zero, clockwise = training.get("zero", "right"), training.get("clockwise", False)
    if zero not in ZEROS or not isinstance(clockwise, bool):
        raise UserError(f"{shown}: conventions.training holds zero {zero!r} and clockwise {clockwise!r}; "
                        f"zero is one of {', '.join(ZEROS)}")
    return zero, clockwise


def _first_line(error: Exception) -> str:
    return str(error).splitlines()[0] if str(error) else type(error).__name__
