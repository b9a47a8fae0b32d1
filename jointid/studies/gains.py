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

import math
from dataclasses import dataclass

import numpy as np

from ..estimation.uncertainty import WEAK, WELL_DETERMINED, verdict
from ..model.motors import MotorDrive, error_scale, gains_from_physical
from .log_fit import LoadedLogs

WPILIB_ORDER = ("kS", "kG", "kV", "kA")
"""ArmFeedforward's constructor order."""

UNITS = {"kS": "V", "kG": "V", "kV": "V s/rad", "kA": "V s²/rad", "q0": "rad", "V0": "V"}
PER_ROTATION_UNITS = {"kS": "V", "kG": "V", "kV": "V s/rot", "kA": "V s²/rot", "q0": "rot", "V0": "V"}
PER_ROTATION = {"kS": 1.0, "kG": 1.0, "kV": 2 * math.pi, "kA": 2 * math.pi, "q0": 1 / (2 * math.pi), "V0": 1.0}
"""Per-rotation value / per-radian value: V/(rot/s) = 2 pi V/(rad/s); an offset of q0 rad is q0/(2 pi) rot."""


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

    @property
    def unit(self) -> str:
        """Its unit per radian, e.g. 'V s/rad'."""
        return UNITS[self.name]

    @property
    def per_rotation(self) -> float:
        """Its value per rotation, as SysId shows gains of a log in rotations."""
        return self.value * PER_ROTATION[self.name]

    @property
    def per_rotation_error(self) -> float:
        """Its standard error per rotation."""
        return self.std_error * PER_ROTATION[self.name]

    @property
    def determined(self) -> bool:
        """True when well determined."""
        return self.verdict == WELL_DETERMINED


@dataclass(frozen=True, eq=False)
class ArmGains:
    """WPILib's ArmFeedforward gains of a fit (kS, kG, kV, kA, then q0 and V0 when the model has them)."""

    gains: tuple[Gain, ...]
    drive: MotorDrive | None
    """The motor drive a torque log's parameters were converted through, or None for a voltage log."""
    model_name: str

    def __getitem__(self, name: str) -> Gain:
        return next(gain for gain in self.gains if gain.name == name)

    @property
    def names(self) -> tuple[str, ...]:
        """The gains' names in order."""
        return tuple(gain.name for gain in self.gains)

    @property
    def missing(self) -> tuple[str, ...]:
        """ArmFeedforward gains the model lacks (kS without Coulomb friction): 0 in the constructor."""
        return tuple(name for name in WPILIB_ORDER if name not in self.names)

    @property
    def undetermined(self) -> tuple[str, ...]:
        """Gains not well determined (weak or not determined)."""
        return tuple(gain.name for gain in self.gains if not gain.determined)

    def value(self, name: str) -> float:
        """A constructor gain's value per radian (0 when the model lacks it)."""
        return self[name].value if name in self.names else 0.0


def arm_gains(logs: LoadedLogs, drive: MotorDrive | None = None) -> ArmGains:
    """The ArmFeedforward gains of a fit of logs: as fitted for a voltage log, through `drive` for a torque log;
    GainsError when the fit is not unique or a torque log has no drive."""
    result = logs.result
    model = result.model
    if result.estimate is None or result.uncertainty is None:
        raise GainsError(f"no gains: rank {result.rank} of {result.parameter_count}, the fit is not unique")
    if model.index_of("I") is None or model.index_of("B") is None:
        raise GainsError("no gains: the model lacks acceleration or velocity")
    volts = not model.effort.is_torque
    if not volts and drive is None:
        raise GainsError("--gains wpilib needs volts: fit a voltage log (--effort voltage), or give the motor "
                         "(--motor NAME --gear G, or --motor-r/--motor-kt/--motor-kv) to convert this torque log")
    # The verdicts the fit's text gives: a parameter another check moved is never called well determined.
    unsettled = logs.unsettled
    verdicts = {name: WEAK if name in unsettled and judged == WELL_DETERMINED else judged
                for name, judged in zip(model.names, result.uncertainty.verdicts)}
    fitted = dict(result.params)
    errors = dict(result.bse)
    sysid = _sysid_direction(result)
    if volts:
        values, sysid_values = fitted, sysid
        gain_errors = errors
        gain_verdicts = verdicts
    else:
        values = gains_from_physical(drive, fitted)
        sysid_values = None if sysid is None else gains_from_physical(drive, sysid)
        back = {gain: name for name, gain in zip(fitted, gains_from_physical(drive, fitted))}
        gain_errors = {gain: errors[name] * error_scale(drive, name, to_physical=False) for gain, name in back.items()}
        gain_verdicts = {}
        for gain, name in back.items():
            relative = 100 * gain_errors[gain] / abs(values[gain]) if values[gain] else math.inf
            judged = verdict(relative)
            # A parameter another check moved stays no better than weak in any units.
            gain_verdicts[gain] = WEAK if judged == WELL_DETERMINED and verdicts[name] != WELL_DETERMINED else judged
    order = [name for name in (*WPILIB_ORDER, "q0", "V0") if name in values]
    gains = tuple(Gain(name, float(values[name]), float(gain_errors[name]), gain_verdicts[name],
                       None if sysid_values is None else float(sysid_values[name])) for name in order)
    return ArmGains(gains, None if volts else drive, model.name)


def _sysid_direction(result) -> dict[str, float] | None:
    """The model's parameters by regressing the acceleration column on the effort and the other columns, on the
    fit's own (filtered, kept) samples; None when that regression is singular."""
    model = result.model
    X = result.training_regressor
    effort = result.training.tau
    a = model.index_of("I")
    others = [j for j in range(model.size) if j != a]
    Z = np.column_stack([effort, X[:, others]])
    coefficients, _, rank, _ = np.linalg.lstsq(Z, X[:, a], rcond=None)
    beta = coefficients[0]
    if rank < Z.shape[1] or not beta or not np.all(np.isfinite(coefficients)):
        return None
    theta = np.empty(model.size)
    theta[a] = 1.0 / beta
    theta[others] = -coefficients[1:] / beta
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


def motor_parameters(logs: LoadedLogs, drive: MotorDrive) -> MotorParameters:
    """I, h, B, Fc (and tau0, q0) behind a voltage log's fitted gains, with standard errors and verdicts;
    GainsError for a torque log or a fit that is not unique."""
    from ..model.motors import physical_from_gains
    from ..model.terms import ANGLE_OFFSET, MASS_MOMENT, TORQUE_TERMS

    result = logs.result
    if result.model.effort.is_torque:
        raise GainsError("the physical parameters of a torque log are its fit; a motor converts them to gains "
                         "(--gains wpilib)")
    if result.estimate is None or result.uncertainty is None:
        raise GainsError(f"no physical parameters: rank {result.rank} of {result.parameter_count}, the fit is not "
                         "unique")
    unsettled = logs.unsettled
    gains = dict(result.params)
    errors = dict(result.bse)
    values = physical_from_gains(drive, gains)
    units = {**{name: term.unit for name, term in TORQUE_TERMS.items()}, "h": MASS_MOMENT.unit,
             "q0": ANGLE_OFFSET.unit}
    from ..model.motors import PHYSICAL_FROM_GAIN

    parameters = []
    for name, value in values.items():
        gain = PHYSICAL_FROM_GAIN[name]
        error = errors[gain] * error_scale(drive, gain, to_physical=True)
        relative = 100 * error / abs(value) if value else math.inf
        judged = verdict(relative)
        if judged == WELL_DETERMINED and gain in unsettled:
            judged = WEAK
        parameters.append(PhysicalParameter(name, units[name], float(value), float(error), judged))
    return MotorParameters(drive, tuple(parameters))
