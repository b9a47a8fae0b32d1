"""Which mechanism a SysId routine characterised: a simple motor, an elevator or an arm, each a model of terms.

A flywheel, roller or drive is a joint whose gravity term is zero (WPILib's
SimpleMotorFeedforward, V = kS sgn v + kV v + kA a); an elevator is one whose
gravity torque is the same at every position (ElevatorFeedforward: + kG); an
arm's follows the cosine of its angle (ArmFeedforward: + kG cos(q + q0)).

`--mechanism` says which; without it the log chooses by a stated comparison.
Preconditions first: a log in a length unit, or whose position was integrated
from its velocity, has no angle for a cosine, so it is no arm; neither is a
wheel that turned more than MANY_TURNS revolutions with no voltage following the
cosine of its angle (the arm's kG within SUPPORT standard errors of 0). Then
each remaining model is fitted to the tests (pooled) and compared by BIC on the
samples every fit kept, counting every test's samples, each test with its own
residual variance: BIC = sum_k n_k ln(RSS_k / n_k) + p ln(N). A model with a
gravity term is chosen over a simpler one only when its BIC is lower by more
than DECISIVE and its kG stands SUPPORT standard errors clear of zero.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..model.terms import JointModel, model_named
from ..options import MECHANISMS

SIMPLE, ELEVATOR, ARM = MECHANISMS
"""The mechanisms by name, simplest first."""

MODEL_NAMES = {SIMPLE: "simple", ELEVATOR: "elevator", ARM: "coulomb+angle-offset"}
"""Each mechanism's model."""

FEEDFORWARDS = {SIMPLE: "SimpleMotorFeedforward", ELEVATOR: "ElevatorFeedforward", ARM: "ArmFeedforward"}
"""WPILib's feedforward class of each mechanism."""

WORDS = {SIMPLE: "simple motor", ELEVATOR: "elevator", ARM: "arm"}
"""How a text names each mechanism."""

SUPPORT = 3.0
"""Standard errors a gravity gain must stand clear of zero for the data to support it."""

DECISIVE = 10.0
"""BIC lower by more than this (Kass and Raftery's 'very strong' evidence) is needed to add a gravity term: a log's
samples are correlated, so smaller differences are within what the fit's own settings move."""

MANY_TURNS = 2.0
"""Revolutions beyond which a joint whose voltage does not follow the cosine of its angle is a wheel, no arm."""

LINEAR_UNITS = ("meters", "metres", "meter", "metre", "m", "feet", "foot", "ft", "inches", "inch", "in",
                "centimeters", "millimeters", "cm", "mm")
"""Position units that are lengths: a linear coordinate has no angle for a cosine."""


class MechanismError(ValueError):
    """A mechanism the log cannot be (an arm in metres); the message is one line."""


def mechanism_model(name: str) -> JointModel:
    """The model of a mechanism ('simple', 'elevator' or 'arm')."""
    return model_named(MODEL_NAMES[name])


def mechanism_of(model: JointModel) -> str:
    """The mechanism a model describes: an arm with a cosine gravity term, an elevator with a constant one, else a
    simple motor."""
    kinds = {term.kind for term in model.terms}
    if kinds & {"h", "h_c"}:
        return ARM
    return ELEVATOR if "tauG" in kinds else SIMPLE


def position_unit(log) -> str | None:
    """The unit the log's position was read in ('rotations', 'radians', 'degrees', 'meters'...), or None."""
    table = None if log.source is None else log.source.table
    units = dict(getattr(table, "units", ()) or ())
    return units.get("q") or units.get("qd")


def is_linear_unit(unit: str | None) -> bool:
    """True for a length unit (a linear coordinate)."""
    return unit is not None and unit.strip().lower().replace(" per second", "") in LINEAR_UNITS


def integrated(log) -> bool:
    """True when the log's position was integrated from its logged velocity (a velocity-only log)."""
    table = None if log.source is None else log.source.table
    return getattr(table, "position_source", "logged") == "integrated velocity"


@dataclass(frozen=True)
class MechanismChoice:
    """The mechanism a SysId log was fitted as, and why: given, or chosen by BIC with its evidence."""

    mechanism: str
    given_by: str | None
    """'--mechanism' or '--model' when one said it, None when chosen from the log."""
    unit: str | None
    """The position's unit in the log."""
    bic: tuple[tuple[str, float], ...] = ()
    """(mechanism, BIC) of each model compared, in MECHANISMS order."""
    samples: int = 0
    """Samples the comparison counted (every test's, kept by every model)."""
    ruled_out: tuple[tuple[str, str], ...] = ()
    """(mechanism, why) of each the log cannot be."""
    gravity: tuple[tuple[str, float, float], ...] = ()
    """(mechanism, kG, its standard error) of each model with a gravity term that was fitted."""
    revolutions: float | None = None
    """The most a test turned (revolutions), for an angle log."""

    @property
    def feedforward(self) -> str:
        """WPILib's feedforward class for the mechanism."""
        return FEEDFORWARDS[self.mechanism]

    @property
    def words(self) -> str:
        """The mechanism in words ('simple motor')."""
        return WORDS[self.mechanism]

    def note(self) -> str:
        """One sentence: the mechanism and the evidence for it."""
        if self.given_by is not None:
            return f"Mechanism: {self.words} ({self.feedforward}), as {self.given_by} says."
        parts = []
        bic = dict(self.bic)
        best = bic[self.mechanism]
        others = [f"{WORDS[name]} {value - best:+.1f}" for name, value in self.bic if name != self.mechanism]
        if others:
            parts.append(f"BIC over the tests' {self.samples:,} samples against it: {', '.join(others)}")
        for name, value, error in self.gravity:
            supported = "supported" if abs(value) > SUPPORT * error else "not supported"
            parts.append(f"the {WORDS[name]}'s kG = {value:.3g} ± {error:.2g} V, {supported} by the data")
        turns = any("revolutions" in why for _, why in self.ruled_out)
        if self.revolutions is not None and not turns:
            parts.append(f"it turned {self.revolutions:.3g} revolutions")
        for name, why in self.ruled_out:
            parts.append(f"no {WORDS[name]}: {why}")
        return (f"Mechanism: {self.words} ({self.feedforward}), chosen from the log (--mechanism to say otherwise): "
                + "; ".join(parts) + ".")

    def to_dict(self) -> dict:
        """JSON-ready."""
        return {"mechanism": self.mechanism, "feedforward": self.feedforward, "given_by": self.given_by,
                "unit": self.unit, "bic": dict(self.bic), "samples": self.samples,
                "ruled_out": dict(self.ruled_out),
                "gravity_gain": {name: {"value": value, "std_error": error} for name, value, error in self.gravity},
                "revolutions": self.revolutions}


def check_mechanism(mechanism: str, logs) -> None:
    """MechanismError when the logs cannot be this mechanism: an arm needs an angle."""
    if mechanism != ARM:
        return
    unit = position_unit(logs[0])
    if is_linear_unit(unit):
        raise MechanismError(f"--mechanism arm: {logs[0].path} holds its position in {unit}, a length; an arm "
                             "needs an angle (use --mechanism simple or elevator)")
    if any(integrated(log) for log in logs):
        raise MechanismError(f"--mechanism arm: {logs[0].path}'s position was integrated from its velocity, so its "
                             "angle is unknown; an arm needs a logged angle (use --mechanism simple or elevator)")


def _revolutions(logs) -> float | None:
    """The most any test turned, in revolutions, for an angle log (None for a linear one)."""
    if is_linear_unit(position_unit(logs[0])):
        return None
    return max(float(np.ptp(log.data.q)) for log in logs) / (2 * math.pi)


def choose_mechanism(logs, fit) -> tuple[str, MechanismChoice]:
    """(mechanism, the choice with its evidence) for SysId tests; `fit(model)` fits them pooled (no sensitivity
    check) and returns a studies.runs.PooledRuns."""
    unit = position_unit(logs[0])
    ruled_out = []
    candidates = [SIMPLE, ELEVATOR, ARM]
    if is_linear_unit(unit):
        ruled_out.append((ARM, f"the log is in {unit}, a length"))
    elif any(integrated(log) for log in logs):
        ruled_out.append((ARM, "its position was integrated from its velocity"))
    revolutions = _revolutions(logs) if not ruled_out else None
    fits = {}
    for name in candidates:
        if name in dict(ruled_out):
            continue
        try:
            fits[name] = fit(mechanism_model(name))
        except ValueError:  # a model the tests cannot fit (nothing left after exclusions): not a candidate
            continue
    gravity = []
    for name in (ELEVATOR, ARM):
        pooled = fits.get(name)
        if pooled is not None and "kG" in pooled.params:
            gravity.append((name, float(pooled.params["kG"]), float(pooled.bse["kG"])))
    supported = {name: abs(value) > SUPPORT * error for name, value, error in gravity}
    if ARM in fits and revolutions is not None and revolutions > MANY_TURNS and not supported.get(ARM, False):
        ruled_out.append((ARM, f"the wheel turned {revolutions:.3g} revolutions with no voltage following the "
                          "cosine of its angle"))
        del fits[ARM]
    bic, samples = _bic(fits)
    chosen = SIMPLE if SIMPLE in bic else next(iter(bic), SIMPLE)
    for name in (ELEVATOR, ARM):
        if name in bic and bic[name] < bic[chosen] - DECISIVE and supported.get(name, False):
            chosen = name
    choice = MechanismChoice(chosen, None, unit, tuple(bic.items()), samples, tuple(ruled_out),
                             tuple(gravity), revolutions)
    return chosen, choice


def _runs(fit) -> tuple:
    """The fitted runs of pooled runs, or a single fit as one."""
    return fit.runs if hasattr(fit, "runs") else (fit,)


def _bic(fits: dict) -> tuple[dict[str, float], int]:
    """(BIC of each pooled fit on the samples every fit kept, the count of those samples)."""
    if not fits:
        return {}, 0
    first = next(iter(fits.values()))
    count = len(_runs(first))
    common = []
    for k in range(count):
        masks = [_runs(pooled)[k].exclusions.kept for pooled in fits.values()
                 if _runs(pooled)[k].exclusions is not None]
        if len(masks) != len(fits) or len({len(mask) for mask in masks}) != 1:
            return {}, 0
        common.append(np.logical_and.reduce(masks))
    total = int(sum(mask.sum() for mask in common))
    out = {}
    for name, pooled in fits.items():
        model = _runs(pooled)[0].result.model
        theta = (pooled.result.column_estimate if not hasattr(pooled, "runs") else pooled.estimate[:model.size])
        if theta is None or not np.all(np.isfinite(theta)):
            continue
        value = 0.0
        for run, mask in zip(_runs(pooled), common):
            left = run.exclusions
            residuals = left.torque[mask] - left.regressor[mask] @ theta
            n = int(mask.sum())
            value += n * math.log(max(float(np.mean(residuals**2)), 1e-300)) if n else 0.0
        out[name] = value + model.size * math.log(max(total, 1))
    return out, total
