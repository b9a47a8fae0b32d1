"""DC motors and a geared drive of them: the link between an arm's voltage gains (WPILib's kS, kG, kV, kA) and
its physical parameters (I, h, B, Fc).

A motor's winding has resistance R, torque constant kt (N m/A) and speed constant Kv ((rad/s)/V, so its back-EMF
is omega/Kv). n motors geared G:1 (G motor turns per joint turn) through a gearbox of efficiency eta give the
joint

    torque = c (V - (G/Kv) qd),     c = eta G n kt / R    (N m/V, R of one motor)

and the joint's tau = I qdd + h g cos(q + q0) + B qd + Fc sgn(qd) in volts is

    V = (I/c) qdd + (h g/c) cos(q + q0) + (B/c + G/Kv) qd + (Fc/c) sgn(qd)
      =  kA qdd   +   kG cos(q + q0)    +      kV qd      +   kS sgn(qd)

so I = c kA, h = c kG / g, B = c (kV - G/Kv), Fc = c kS. The back-EMF's share of kV, G/Kv, is the motor's
electrical damping (c G/Kv in N m s/rad at the joint). I includes the rotors' inertia reflected through the gear,
n G^2 J_rotor: WPILib's DCMotor does not publish J_rotor, so it is separated only when given.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from .terms import G


def _rpm(value: float) -> float:
    """Revolutions per minute in rad/s (WPILib's Units.rotationsPerMinuteToRadiansPerSecond)."""
    return value * 2 * math.pi / 60


@dataclass(frozen=True)
class DCMotor:
    """One DC motor as WPILib's DCMotor describes it: nominal voltage, stall torque and current, free current and
    speed; R, Kv and kt derived the way its constructor derives them."""

    name: str
    nominal_voltage: float
    """V at which the constants were measured."""
    stall_torque: float
    """N m."""
    stall_current: float
    """A."""
    free_current: float
    """A."""
    free_speed: float
    """rad/s."""

    @property
    def resistance(self) -> float:
        """R (ohm) = V_nominal / I_stall."""
        return self.nominal_voltage / self.stall_current

    @property
    def speed_constant(self) -> float:
        """Kv ((rad/s)/V) = free speed / (V_nominal - R I_free)."""
        return self.free_speed / (self.nominal_voltage - self.resistance * self.free_current)

    @property
    def torque_constant(self) -> float:
        """kt (N m/A) = stall torque / stall current."""
        return self.stall_torque / self.stall_current


# The constants of WPILib's DCMotor factories (getNEO, getNeo550, ...), as published in allwpilib's
# wpimath/src/main/java/org/wpilib/math/system/DCMotor.java (read at commit caf0fb2d, August 2026): 12 V nominal
# (the Romi's 4.5 V), stall torque (N m), stall current (A), free current (A), free speed (rpm).
WPILIB_MOTORS = tuple(
    DCMotor(name, volts, torque, stall, free, _rpm(rpm)) for name, volts, torque, stall, free, rpm in (
        ("CIM", 12, 2.42, 133, 2.7, 5310),
        ("775pro", 12, 0.71, 134, 0.7, 18730),
        ("NEO", 12, 2.6, 105, 1.8, 5676),
        ("MiniCIM", 12, 1.41, 89, 3, 5840),
        ("BAG", 12, 0.43, 53, 1.8, 13180),
        ("AM RS775-125", 12, 0.28, 18, 1.6, 5800),
        ("BaneBots RS775", 12, 0.72, 97, 2.7, 13050),
        ("AM 9015", 12, 0.36, 71, 3.7, 14270),
        ("BaneBots RS550", 12, 0.38, 84, 0.4, 19000),
        ("NEO 550", 12, 0.97, 100, 1.4, 11000),
        ("Falcon 500", 12, 4.69, 257, 1.5, 6380),
        ("Falcon 500 FOC", 12, 5.84, 304, 1.5, 6080),
        ("Romi", 4.5, 0.1765, 1.25, 0.13, 150),
        ("Kraken X60", 12, 7.09, 366, 2, 6000),
        ("Kraken X60 FOC", 12, 9.37, 483, 2, 5800),
        ("Kraken X44", 12, 4.11, 279, 2, 7758),
        ("Kraken X44 FOC", 12, 5.01, 329, 2, 7368),
        ("Minion", 12, 3.17, 211, 2, 7704),
        ("NEO Vortex", 12, 3.60, 211, 3.6, 6784),
    ))
"""WPILib's DC motors, in DCMotor.java's order."""


def _key(name: str) -> str:
    """'Falcon 500' and 'falcon-500' -> 'falcon500': motor names compared without case, spaces or dashes."""
    return re.sub(r"[^a-z0-9]", "", str(name).lower())


MOTORS_BY_KEY = {_key(motor.name): motor for motor in WPILIB_MOTORS}


class UnknownMotor(ValueError):
    """A motor name that is not one of WPILIB_MOTORS; its message lists them."""


def motor_named(name: str) -> DCMotor:
    """The WPILib motor a name stands for (case, spaces and dashes ignored); UnknownMotor listing the known ones."""
    motor = MOTORS_BY_KEY.get(_key(name))
    if motor is None:
        known = ", ".join(motor.name for motor in WPILIB_MOTORS)
        raise UnknownMotor(f"unknown motor {name!r}; known (WPILib's DCMotor): {known}")
    return motor


@dataclass(frozen=True)
class MotorDrive:
    """n motors geared G:1 onto the joint through a gearbox of efficiency eta: what turns volts into torque."""

    name: str
    """The motor's name ('NEO'), or 'custom' for --motor-r/--motor-kt/--motor-kv."""
    resistance: float
    """R of one motor (ohm)."""
    torque_constant: float
    """kt of one motor (N m/A)."""
    speed_constant: float
    """Kv of one motor ((rad/s)/V): its back-EMF is omega/Kv."""
    count: int = 1
    gear: float = 1.0
    """Motor turns per joint turn."""
    efficiency: float = 1.0
    rotor_inertia: float | None = None
    """One rotor's inertia (kg m²) when known; WPILib does not publish it."""

    @classmethod
    def of(cls, motor: DCMotor, count: int = 1, gear: float = 1.0, efficiency: float = 1.0,
           rotor_inertia: float | None = None) -> MotorDrive:
        """A drive of `count` of a WPILib motor."""
        return cls(motor.name, motor.resistance, motor.torque_constant, motor.speed_constant, count, gear,
                   efficiency, rotor_inertia)

    @property
    def torque_per_volt(self) -> float:
        """c = eta G n kt / R (N m/V): the joint torque one volt gives at standstill."""
        return self.efficiency * self.gear * self.count * self.torque_constant / self.resistance

    @property
    def back_emf(self) -> float:
        """G/Kv (V s/rad): the volts the motors' back-EMF takes per rad/s of the joint."""
        return self.gear / self.speed_constant

    @property
    def electrical_damping(self) -> float:
        """c G/Kv (N m s/rad): the damping the back-EMF adds at the joint when driven by a voltage."""
        return self.torque_per_volt * self.back_emf

    @property
    def reflected_inertia(self) -> float | None:
        """n G² J_rotor (kg m²): the rotors' inertia at the joint, or None when J_rotor is not known."""
        return None if self.rotor_inertia is None else self.count * self.gear**2 * self.rotor_inertia

    def description(self) -> str:
        """e.g. '2 x NEO, gear 50:1, efficiency 1 (R 0.114 ohm, kt 0.0248 N m/A, Kv 49.5 (rad/s)/V each)'."""
        motors = f"{self.count} x {self.name}" if self.count != 1 else self.name
        return (f"{motors}, gear {self.gear:g}:1, efficiency {self.efficiency:g} (R {self.resistance:.4g} ohm, "
                f"kt {self.torque_constant:.4g} N m/A, Kv {self.speed_constant:.4g} (rad/s)/V each)")


PHYSICAL_FROM_GAIN = {"I": "kA", "h": "kG", "B": "kV", "Fc": "kS", "tau0": "V0", "q0": "q0"}
"""The volt gain each physical parameter comes from."""


def physical_from_gains(drive: MotorDrive, gains: dict[str, float]) -> dict[str, float]:
    """I, h, B, Fc (and tau0, q0) from the volt gains kA, kG, kV, kS (V0, q0) present in `gains`."""
    c = drive.torque_per_volt
    convert = {"kA": lambda v: c * v, "kG": lambda v: c * v / G, "kV": lambda v: c * (v - drive.back_emf),
               "kS": lambda v: c * v, "V0": lambda v: c * v, "q0": lambda v: v}
    return {name: convert[gain](gains[gain]) for name, gain in PHYSICAL_FROM_GAIN.items() if gain in gains}


def gains_from_physical(drive: MotorDrive, params: dict[str, float]) -> dict[str, float]:
    """kA, kG, kV, kS (V0, q0) from the physical I, h, B, Fc (tau0, q0) present in `params`."""
    c = drive.torque_per_volt
    convert = {"I": lambda v: v / c, "h": lambda v: v * G / c, "B": lambda v: v / c + drive.back_emf,
               "Fc": lambda v: v / c, "tau0": lambda v: v / c, "q0": lambda v: v}
    return {PHYSICAL_FROM_GAIN[name]: convert[name](value) for name, value in params.items()
            if name in PHYSICAL_FROM_GAIN}


def error_scale(drive: MotorDrive, name: str, to_physical: bool) -> float:
    """The factor a standard error is multiplied by in the conversion of parameter or gain `name` (all are
    affine: the back-EMF shifts kV without widening it)."""
    if name in ("q0",):
        return 1.0
    c = drive.torque_per_volt
    factor = c / G if name in ("kG", "h") else c
    return factor if to_physical else 1.0 / factor
