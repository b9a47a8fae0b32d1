"""The texts and JSON of a controller's gains (`jointid fit ... --gains wpilib`) and of the motor behind a
voltage log (`--motor`): tables, constructor lines, SysId's direction beside jointid's."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..estimation.uncertainty import NOT_DETERMINED
from .text import format_number, text_table

if TYPE_CHECKING:
    from ..model.motors import MotorDrive
    from ..studies.gains import ArmGains, MotorParameters

GAIN_WORDS = {"kS": "static", "kG": "gravity", "kV": "velocity", "kA": "acceleration", "q0": "angle offset",
              "V0": "voltage bias"}


def _number(value: float) -> str:
    """Six significant digits, the way a constructor line is read and pasted."""
    return f"{value:.6g}"


CPP_DISTANCE = {"rotation": "units::turns", "radian": "units::radians", "meter": "units::meters"}
"""The C++ SimpleMotorFeedforward's distance unit for each constructor unit."""

PYTHON_SIMPLE = {"radian": "SimpleMotorFeedforwardRadians", "meter": "SimpleMotorFeedforwardMeters"}
"""robotpy's SimpleMotorFeedforward classes (it has none per rotation: per radian is given instead)."""


def constructor_lines(gains: ArmGains) -> tuple[str, str, str]:
    """One line each of Java, C++ and Python constructing the mechanism's WPILib feedforward with the gains in
    the constructor's unit (gains.constructor_unit; robotpy's SimpleMotorFeedforward has no per-rotation class, so
    its line is per radian for a log in rotations)."""
    order = gains.constructor_order
    values = [_number(gains.constructor_value(name)) for name in order]
    plain = ", ".join(values)
    volts = [f"units::volt_t{{{value}}}" for name, value in zip(order, values) if name in ("kS", "kG")]
    if gains.feedforward == "SimpleMotorFeedforward":
        unit = gains.constructor_unit
        cls = f"frc::SimpleMotorFeedforward<{CPP_DISTANCE.get(unit, 'units::meters')}>"
        python_class = PYTHON_SIMPLE.get(unit, "SimpleMotorFeedforwardRadians")
        python_values = plain if unit in PYTHON_SIMPLE else ", ".join(
            _number(gains.value(name)) for name in order)
        python = f"wpimath.controller.{python_class}({python_values})"
    else:
        cls = f"frc::{gains.feedforward}"
        python = f"wpimath.controller.{gains.feedforward}({plain})"
    kv, ka = values[-2], values[-1]
    cpp = (f"{cls}{{{', '.join(volts)}, units::unit_t<{cls}::kv_unit>{{{kv}}}, "
           f"units::unit_t<{cls}::ka_unit>{{{ka}}}}};")
    return f"new {gains.feedforward}({plain});", cpp, python


def gains_text(gains: ArmGains) -> str:
    """The gains with errors and verdicts in the log's units, SysId's direction beside them, the constructors, and
    what not to trust."""
    return "\n".join(part for part in gains_parts(gains) if part)


def gains_parts(gains: ArmGains) -> tuple[str, str, str, str]:
    """gains_text in its parts: the heading, the table, the constructor lines, the sentences (a narrow screen
    scrolls the table and the code sideways and wraps the sentences)."""
    from ..studies.gains import PER_ROTATION_UNITS

    rows = []
    for gain in gains.gains:
        sysid = "-" if gain.sysid_value is None else format_number(gain.sysid_value)
        row = [f"{gain.name} ({gain.unit})", format_number(gain.value), format_number(gain.std_error)]
        if not gains.linear:
            row.append(f"{format_number(gain.per_rotation)} {PER_ROTATION_UNITS[gain.name]}")
        rows.append([*row, gain.verdict, sysid])
    header = ["gain", "value", "±", *([] if gains.linear else ["per rotation"]), "verdict", "SysId's direction"]
    kind = "voltage" if gains.drive is None else "torque"
    source = f"the {kind} log's fit" if gains.runs == 1 else f"the pooled fit of {gains.runs} {kind} runs"
    if gains.drive is not None:
        source += f" through {gains.drive.description()}"
    java, cpp, python = constructor_lines(gains)
    heading = f"WPILib {gains.feedforward} gains from {source} ({_units_phrase(gains)}):"
    code = f"Java:   {java}\nC++:    {cpp}\nPython: {python}"
    lines = []
    if gains.missing:
        lines.append(f"The model has no {', '.join(gains.missing)}: 0 in the constructor (add its term to the "
                     "model to fit it).")
    if gains.feedforward == "SimpleMotorFeedforward":
        lines.append("No gravity gain: a flywheel, roller or drive is a joint whose gravity torque is zero.")
    if "q0" in gains.names and gains["q0"].determined:
        lines.append(f"ArmFeedforward takes the angle from horizontal: pass the measured angle + q0 "
                     f"({format_number(gains['q0'].value)} rad).")
    elif "q0" in gains.names and gains["q0"].verdict == NOT_DETERMINED:
        lines.append("q0 is not determined (its error is about as large as itself): the angle as measured is as "
                     "good as any, or fit without the offset (--model coulomb).")
    elif "q0" in gains.names:
        lines.append(f"q0 is {gains['q0'].verdict}: pass the measured angle + q0 "
                     f"({format_number(gains['q0'].value)} rad) to ArmFeedforward, but check the angle's zero.")
    if "V0" in gains.names:
        lines.append(f"{gains.feedforward} has no voltage bias: V0 is left out of the constructor.")
    undetermined = [gain for gain in gains.gains if not gain.determined and gain.name in ("kS", "kG", "kV", "kA")]
    if undetermined:
        lines.append("Not well determined, so not to be trusted in a controller as they are: " + ", ".join(
            f"{gain.name} ({gain.verdict})" for gain in undetermined) + ".")
    gaps = _direction_gaps(gains)
    same = all(abs(gain.sysid_value - gain.value) <= 1e-9 * max(1.0, abs(gain.value)) for gain in gains.gains
               if gain.sysid_value is not None)
    if gaps and same:
        lines.append("SysId's direction (acceleration regressed on voltage) gives the same gains to rounding: the "
                     "data are fitted exactly.")
    elif gaps:
        worst = max(gaps, key=lambda pair: pair[1])
        lines.append("SysId's direction (acceleration regressed on voltage) differs from jointid's by at most "
                     f"{worst[1]:.2g} standard errors ({worst[0]}): noise in the differentiated acceleration biases "
                     "jointid's kA low (a regressor here) but not SysId's (its dependent variable); noise in the "
                     "voltage does the reverse.")
    return heading, text_table(header, rows), code, "\n".join(lines)


def _units_phrase(gains: ArmGains) -> str:
    """How the heading says the gains' units: per radian from horizontal for an arm, else the log's own unit."""
    if gains.linear:
        return f"per {gains.constructor_unit}, the log's own unit"
    if gains.feedforward == "ArmFeedforward":
        return ("angle in radians from horizontal; per rotation as SysId shows a log in rotations: kV and kA times "
                "2 pi")
    if gains.constructor_unit == "rotation":
        python = "; robotpy's SimpleMotorFeedforwardRadians per radian" \
            if gains.feedforward == "SimpleMotorFeedforward" else ""
        return f"per rotation, the log's own unit{python}"
    return "per radian, the log's own unit" if gains.unit == "radians" else "per radian"


def _direction_gaps(gains: ArmGains) -> list[tuple[str, float]]:
    """(name, |jointid - SysId| in standard errors) for each gain with both values and an error."""
    return [(gain.name, abs(gain.value - gain.sysid_value) / gain.std_error) for gain in gains.gains
            if gain.sysid_value is not None and gain.std_error > 0]


def gains_object(gains: ArmGains) -> dict:
    """JSON-ready: each gain per radian and per rotation with its error and verdict, SysId's direction and the
    difference, the drive a torque fit went through, and the constructor lines."""
    from ..studies.gains import PER_ROTATION_UNITS

    java, cpp, python = constructor_lines(gains)
    return {
        "controller": f"wpilib.{gains.feedforward}",
        "feedforward": gains.feedforward,
        "log_unit": gains.unit,
        "constructor_unit": gains.constructor_unit,
        "constructor_values": {name: gains.constructor_value(name) for name in gains.constructor_order},
        "gains": {gain.name: {"value": gain.value, "std_error": gain.std_error, "unit": gain.unit,
                              "per_rotation": gain.per_rotation, "per_rotation_std_error": gain.per_rotation_error,
                              "per_rotation_unit": None if gains.linear else PER_ROTATION_UNITS[gain.name],
                              "verdict": gain.verdict,
                              "sysid_direction": gain.sysid_value,
                              "sysid_minus_jointid": (None if gain.sysid_value is None
                                                      else gain.sysid_value - gain.value)}
                  for gain in gains.gains},
        "not_in_model": list(gains.missing),
        "not_well_determined": list(gains.undetermined),
        "converted_through": None if gains.drive is None else drive_object(gains.drive),
        "constructors": {"java": java, "cpp": cpp, "python": python},
    }


def drive_object(drive: MotorDrive) -> dict:
    """JSON-ready: the motor drive's constants and what they give at the joint."""
    return {"motor": drive.name, "count": drive.count, "gear": drive.gear, "efficiency": drive.efficiency,
            "resistance_ohm": drive.resistance, "kt_n_m_per_a": drive.torque_constant,
            "kv_rad_per_s_per_v": drive.speed_constant, "torque_per_volt_n_m_per_v": drive.torque_per_volt,
            "back_emf_v_s_per_rad": drive.back_emf, "electrical_damping_n_m_s_per_rad": drive.electrical_damping,
            "rotor_inertia_kg_m2": drive.rotor_inertia, "reflected_inertia_kg_m2": drive.reflected_inertia}


def motor_text(motor: MotorParameters) -> str:
    """The physical parameters behind a voltage log's gains, with the motor's share named apart."""
    return "\n".join(motor_parts(motor))


def motor_parts(motor: MotorParameters) -> tuple[str, str, str]:
    """motor_text in its parts: the heading, the table, the sentences."""
    drive = motor.drive
    rows = [[f"{p.name} ({p.unit})", format_number(p.value), format_number(p.std_error), p.verdict]
            for p in motor.parameters]
    heading = (f"Physical parameters behind the gains, through {drive.description()}: joint torque = "
               f"{format_number(drive.torque_per_volt, 4)} N m/V x (V - {format_number(drive.back_emf, 4)} V s/rad "
               "x qd):")
    table = text_table(["parameter", "value", "±", "verdict"], rows)
    lines = []
    reflected = drive.reflected_inertia
    if reflected is None:
        lines.append("I includes the rotors' inertia reflected through the gear (motors x gear² x rotor inertia): "
                     "WPILib's DCMotor does not publish a rotor's inertia, so it cannot be separated from the load's "
                     "here (give --motor-inertia KG_M2 to separate it).")
    else:
        lines.append(f"Of I, the rotors' reflected inertia is {format_number(reflected)} kg m² "
                     f"({drive.count} x {drive.gear:g}² x {drive.rotor_inertia:g}); the load's is "
                     f"{format_number(motor.load_inertia)} kg m².")
    lines.append(f"B is the mechanical damping: the back-EMF adds {format_number(drive.electrical_damping)} N m s/rad "
                 f"more when the motor is driven by a voltage ({format_number(drive.back_emf)} V s/rad of kV).")
    damping = next((p for p in motor.parameters if p.name == "B"), None)
    if damping is not None and damping.value + 2 * damping.std_error < 0:  # no joint damps negatively
        lines.append(f"B is negative by more than two standard errors, which no joint is: the fitted kV is below "
                     f"the back-EMF of the drive described ({format_number(drive.back_emf)} V s/rad). Check the "
                     f"gear (--gear, {drive.gear:g}:1 here), the motor and their count.")
    return heading, table, "\n".join(lines)


def motor_object(motor: MotorParameters) -> dict:
    """JSON-ready: the drive, and each physical parameter with its error, unit and verdict."""
    return {**drive_object(motor.drive),
            "parameters": {p.name: {"value": p.value, "std_error": p.std_error, "unit": p.unit,
                                    "verdict": p.verdict} for p in motor.parameters},
            "load_inertia_kg_m2": motor.load_inertia}
