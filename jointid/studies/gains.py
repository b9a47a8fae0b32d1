"""The gains a controller takes, from a fit of logs: WPILib's ArmFeedforward kS, kG, kV, kA (and the offset SysId
reports), each with its standard error and verdict, and the same gains by SysId's direction of regression.

A voltage log's fit is in these gains already. A torque (or current) log's I, h, B, Fc become gains through a
motor drive (jointid.model.motors): kA = I/c, kG = h g/c, kV = B/c + G/Kv, kS = Fc/c.

SysId regresses acceleration on voltage, velocity, sign and the cosine and sine of the angle
(allwpilib tools/sysid/src/main/native/cpp/analysis/FeedforwardAnalysis.cpp) and solves kA = 1/beta,
kV = -alpha/beta, ...; jointid regresses voltage on acceleration, velocity, sign and cosine. With exact data
both give the same gains; with noise each direction is biased by the errors in its regressors (noise in a
differentiated acceleration biases jointid's kA, noise in the voltage biases SysId's), so both are computed here
on the same filtered, kept samples and their difference reported.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from ..estimation.uncertainty import WEAK, WELL_DETERMINED, verdict
from ..model.motors import MotorDrive, error_scale, gains_from_physical

WPILIB_ORDER = ("kS", "kG", "kV", "kA")
"""ArmFeedforward's and ElevatorFeedforward's constructor order (SimpleMotorFeedforward's without kG)."""

CONSTRUCTOR_ORDER = {"SimpleMotorFeedforward": ("kS", "kV", "kA"), "ElevatorFeedforward": WPILIB_ORDER,
                     "ArmFeedforward": WPILIB_ORDER}
"""Each WPILib feedforward's constructor arguments in order (wpimath's Java, C++ and Python alike)."""

UNITS = {"kS": "V", "kG": "V", "kV": "V s/rad", "kA": "V s²/rad", "q0": "rad", "V0": "V"}
PER_ROTATION_UNITS = {"kS": "V", "kG": "V", "kV": "V s/rot", "kA": "V s²/rot", "q0": "rot", "V0": "V"}
PER_ROTATION = {"kS": 1.0, "kG": 1.0, "kV": 2 * math.pi, "kA": 2 * math.pi, "q0": 1 / (2 * math.pi), "V0": 1.0}
"""Per-rotation value / per-radian value: V/(rot/s) = 2 pi V/(rad/s); an offset of q0 rad is q0/(2 pi) rot."""


def linear_units(unit: str) -> dict[str, str]:
    """The gains' units per a length unit ('m'): kV in V s/m, kA in V s²/m."""
    return {"kS": "V", "kG": "V", "kV": f"V s/{unit}", "kA": f"V s²/{unit}", "q0": unit, "V0": "V"}


class GainsError(ValueError):
    """Gains cannot be given for this fit (no volts, no unique fit); the message says why in one line."""


@dataclass(frozen=True)
class Gain:
    """One gain: its value and error per radian, its verdict, and SysId's direction's value."""

    name: str
    value: float
    std_error: float
    verdict: str
    sysid_value: float | None
    """The same gain by regressing acceleration on voltage (SysId's direction), or None when it fails."""
    length: str | None = None
    """The length unit ('m') of a linear log's gains, which are per that unit; None for an angle's, per radian."""

    @property
    def unit(self) -> str:
        """Its unit as fitted, e.g. 'V s/rad' (or 'V s/m' for a linear log)."""
        return UNITS[self.name] if self.length is None else linear_units(self.length)[self.name]

    @property
    def per_rotation(self) -> float | None:
        """Its value per rotation, as SysId shows gains of a log in rotations (None for a linear log)."""
        return None if self.length is not None else self.value * PER_ROTATION[self.name]

    @property
    def per_rotation_error(self) -> float | None:
        """Its standard error per rotation (None for a linear log)."""
        return None if self.length is not None else self.std_error * PER_ROTATION[self.name]

    @property
    def determined(self) -> bool:
        """True when well determined."""
        return self.verdict == WELL_DETERMINED


@dataclass(frozen=True, eq=False)
class ArmGains:
    """A WPILib feedforward's gains of a fit (kS, kG, kV, kA as the mechanism has them, then q0 and V0 when the
    model has them): ArmFeedforward's, ElevatorFeedforward's or SimpleMotorFeedforward's."""

    gains: tuple[Gain, ...]
    drive: MotorDrive | None
    """The motor drive a torque log's parameters were converted through, or None for a voltage log."""
    model_name: str
    runs: int = 1
    """How many runs were pooled into the gains (1: one log's fit)."""
    feedforward: str = "ArmFeedforward"
    """WPILib's class: 'SimpleMotorFeedforward', 'ElevatorFeedforward' or 'ArmFeedforward'."""
    unit: str | None = "radians"
    """The log's own position unit ('rotations', 'radians', 'degrees', or a length such as 'meters')."""

    @property
    def constructor_order(self) -> tuple[str, ...]:
        """The feedforward's constructor arguments in order."""
        return CONSTRUCTOR_ORDER[self.feedforward]

    @property
    def linear(self) -> bool:
        """True for a log in a length unit (gains per metre, say)."""
        return any(gain.length is not None for gain in self.gains)

    @property
    def constructor_unit(self) -> str:
        """The unit the constructor lines' gains are per: the log's own ('rotation', 'radian', 'meter'), except an
        ArmFeedforward's, which takes radians, and a degrees log's, given per radian."""
        if self.linear:
            named = (self.unit or "unit").strip().lower()
            return {"metres": "meter", "metre": "meter", "m": "meter", "feet": "foot"}.get(named, named.rstrip("s"))
        if self.feedforward == "ArmFeedforward" or self.unit != "rotations":
            return "radian"
        return "rotation"

    def constructor_value(self, name: str) -> float:
        """A constructor gain's value per constructor_unit (0 when the model lacks it)."""
        if name not in self.names:
            return 0.0
        gain = self[name]
        return gain.per_rotation if self.constructor_unit == "rotation" else gain.value

    def __getitem__(self, name: str) -> Gain:
        return next(gain for gain in self.gains if gain.name == name)

    @property
    def names(self) -> tuple[str, ...]:
        """The gains' names in order."""
        return tuple(gain.name for gain in self.gains)

    @property
    def missing(self) -> tuple[str, ...]:
        """Constructor gains the model lacks (kS without Coulomb friction): 0 in the constructor."""
        return tuple(name for name in self.constructor_order if name not in self.names)

    @property
    def undetermined(self) -> tuple[str, ...]:
        """Gains not well determined (weak or not determined)."""
        return tuple(gain.name for gain in self.gains if not gain.determined)

    def value(self, name: str) -> float:
        """A constructor gain's value per radian (0 when the model lacks it)."""
        return self[name].value if name in self.names else 0.0


@dataclass(frozen=True)
class FittedParameters:
    """What gains are made from: a fit's reported parameters, errors and verdicts by name, and the same parameters
    by SysId's direction of regression."""

    model: object
    """The fitted model.JointModel."""
    values: dict[str, float]
    errors: dict[str, float]
    verdicts: dict[str, str]
    sysid: dict[str, float] | None


def fitted_parameters(fit) -> FittedParameters:
    """The FittedParameters of one fit of logs (a LoadedLogs) or of several runs pooled (a studies.runs.PooledRuns);
    GainsError without a unique fit."""
    if hasattr(fit, "runs"):
        return _pooled_parameters(fit)
    result = fit.result
    model = result.model
    if result.estimate is None or result.uncertainty is None:
        raise GainsError(f"no gains: rank {result.rank} of {result.parameter_count}, the fit is not unique")
    # The verdicts the fit's text gives (jointid.estimation.judgement): every check's, not the noise's alone.
    verdicts = dict(fit.verdicts)
    sysid = _sysid_direction(model, [(result.training_regressor, result.training.tau)])
    return FittedParameters(model, dict(result.params), dict(result.bse), verdicts, sysid)


def _pooled_parameters(pooled) -> FittedParameters:
    """Several runs' pooled parameters as the model reports them (each run's own bias left out: ArmFeedforward has
    none), their verdicts, and SysId's direction over every run's samples."""
    model = pooled.runs[0].result.model
    if pooled.covariance is None or not np.all(np.isfinite(pooled.estimate)):
        raise GainsError("no gains: the runs pooled have no unique fit")
    values, errors = dict(pooled.params), dict(pooled.bse)
    verdicts = dict(pooled.verdicts)  # the pooled judgement: its errors, the runs' scatter, their checks
    blocks = [(run.result.training_regressor, run.result.training.tau) for run in pooled.runs]
    sysid = _sysid_direction(model, blocks)
    return FittedParameters(model, values, errors, verdicts,
                            None if sysid is None else {name: sysid[name] for name in values})


def arm_gains(fit, drive: MotorDrive | None = None) -> ArmGains:
    """The ArmFeedforward gains of a fit of logs (a LoadedLogs, or several runs pooled): as fitted for a voltage
    log, through `drive` for a torque log; GainsError when the fit is not unique or a torque log has no drive."""
    fitted = fitted_parameters(fit)
    model = fitted.model
    if model.index_of("I") is None or model.index_of("B") is None:
        raise GainsError("no gains: the model lacks acceleration or velocity")
    volts = not model.effort.is_torque
    if not volts and drive is None:
        raise GainsError("--gains wpilib needs volts: fit a voltage log (--effort voltage), or give the motor "
                         "(--motor NAME --gear G, or --motor-r/--motor-kt/--motor-kv) to convert this torque log")
    if volts:
        values, sysid_values = fitted.values, fitted.sysid
        gain_errors, gain_verdicts = fitted.errors, fitted.verdicts
    else:
        values = gains_from_physical(drive, fitted.values)
        sysid_values = None if fitted.sysid is None else gains_from_physical(drive, fitted.sysid)
        back = {gain: name for name, gain in zip(fitted.values, gains_from_physical(drive, fitted.values))}
        gain_errors = {gain: fitted.errors[name] * error_scale(drive, name, to_physical=False)
                       for gain, name in back.items()}
        gain_verdicts = {}
        for gain, name in back.items():
            relative = 100 * gain_errors[gain] / abs(values[gain]) if values[gain] else math.inf
            judged = verdict(relative)
            # A parameter another check moved stays no better than weak in any units.
            gain_verdicts[gain] = (WEAK if judged == WELL_DETERMINED and fitted.verdicts[name] != WELL_DETERMINED
                                   else judged)
    from .mechanism import FEEDFORWARDS, is_linear_unit, mechanism_of, position_unit

    first = fit.runs[0] if hasattr(fit, "runs") else fit
    unit = position_unit(first.training)
    length = _length_symbol(unit) if is_linear_unit(unit) else None
    order = [name for name in (*WPILIB_ORDER, "q0", "V0") if name in values]
    gains = tuple(Gain(name, float(values[name]), float(gain_errors[name]), gain_verdicts[name],
                       None if sysid_values is None else float(sysid_values[name]), length) for name in order)
    return ArmGains(gains, None if volts else drive, model.name, len(fit.runs) if hasattr(fit, "runs") else 1,
                    FEEDFORWARDS[mechanism_of(model)], unit or "radians")


feedforward_gains = arm_gains
"""The gains of the mechanism's WPILib feedforward (the name arm_gains predates the simple motor and elevator)."""


def _length_symbol(unit: str) -> str:
    """A length unit's symbol: 'm' for meters, else the unit as named."""
    symbols = {"meters": "m", "meter": "m", "metres": "m", "metre": "m", "m": "m", "feet": "ft", "foot": "ft",
               "inches": "in", "inch": "in", "centimeters": "cm", "millimeters": "mm"}
    return symbols.get(unit.strip().lower(), unit)


def _sysid_direction(model, blocks) -> dict[str, float] | None:
    """The model's parameters by regressing the acceleration column on the effort and the other columns, over the
    fits' own (filtered, kept) samples of every block (regressor, effort), stacked unweighted as SysId stacks its
    tests, each block with its own bias when the model has one; None when that regression is singular."""
    X = np.concatenate([regressor for regressor, _ in blocks])
    effort = np.concatenate([values for _, values in blocks])
    a, bias = model.index_of("I"), model.index_of("tau0")
    others = [j for j in range(model.size) if j not in (a, bias)]
    columns = [effort, *(X[:, j] for j in others)]
    if bias is not None:  # one offset per block, as the pooled fit has
        edges = np.cumsum([0, *(len(values) for _, values in blocks)])
        for start, end in itertools.pairwise(edges):
            columns.append(np.where((np.arange(len(X)) >= start) & (np.arange(len(X)) < end), 1.0, 0.0))
    Z = np.column_stack(columns)
    coefficients, _, rank, _ = np.linalg.lstsq(Z, X[:, a], rcond=None)
    beta = coefficients[0]
    if rank < Z.shape[1] or not beta or not np.all(np.isfinite(coefficients)):
        return None
    theta = np.zeros(model.size)
    theta[a] = 1.0 / beta
    theta[others] = -coefficients[1:1 + len(others)] / beta
    if bias is not None:
        theta[bias] = -coefficients[1 + len(others)] / beta  # the first block's, as a single fit has one
    return dict(zip(model.names, map(float, model.report(theta))))


@dataclass(frozen=True)
class PhysicalParameter:
    """One physical parameter behind a voltage log's gains, through a motor drive."""

    name: str
    unit: str
    value: float
    std_error: float
    verdict: str


@dataclass(frozen=True, eq=False)
class MotorParameters:
    """The physical I, h, B, Fc (tau0, q0) behind a voltage log's gains, and the motor's share of I and kV."""

    drive: MotorDrive
    parameters: tuple[PhysicalParameter, ...]

    def __getitem__(self, name: str) -> PhysicalParameter:
        return next(parameter for parameter in self.parameters if parameter.name == name)

    @property
    def load_inertia(self) -> float | None:
        """I less the rotors' reflected inertia (kg m²), or None when the rotor inertia is not known."""
        reflected = self.drive.reflected_inertia
        if reflected is None or "I" not in [p.name for p in self.parameters]:
            return None
        return self["I"].value - reflected


def motor_parameters(fit, drive: MotorDrive) -> MotorParameters:
    """I, h, B, Fc (and tau0, q0) behind a voltage log's fitted gains (one fit, or several runs pooled), with
    standard errors and verdicts; GainsError for a torque log or a fit that is not unique."""
    from ..model.motors import PHYSICAL_FROM_GAIN, physical_from_gains
    from ..model.terms import ANGLE_OFFSET, MASS_MOMENT, TORQUE_TERMS

    fitted = fitted_parameters(fit)
    if fitted.model.effort.is_torque:
        raise GainsError("the physical parameters of a torque log are its fit; a motor converts them to gains "
                         "(--gains wpilib)")
    values = physical_from_gains(drive, fitted.values)
    units = {**{name: term.unit for name, term in TORQUE_TERMS.items()}, "h": MASS_MOMENT.unit,
             "q0": ANGLE_OFFSET.unit}
    parameters = []
    for name, value in values.items():
        gain = PHYSICAL_FROM_GAIN[name]
        error = fitted.errors[gain] * error_scale(drive, gain, to_physical=True)
        relative = 100 * error / abs(value) if value else math.inf
        judged = verdict(relative)
        if judged == WELL_DETERMINED and fitted.verdicts[gain] != WELL_DETERMINED:
            judged = WEAK  # another check moved the gain: the parameter behind it is no better
        parameters.append(PhysicalParameter(name, units[name], float(value), float(error), judged))
    return MotorParameters(drive, tuple(parameters))
