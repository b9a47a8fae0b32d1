"""What a log's effort column measured, and turning it into what is fitted: torque as it is (times any
--effort-scale), motor current into joint torque (gear x torque constant x efficiency per ampere), motor voltage
kept in volts (fitted by the same terms in volts)."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from ..model.effort import EFFORT_KINDS


@dataclass(frozen=True)
class EffortReading:
    """How to read a log's effort column (`--effort`, `--effort-scale`, `--gear`, `--kt`, `--efficiency`)."""

    kind: str = "torque"
    """'torque', 'current' or 'voltage'."""
    scale: float = 1.0
    """Torque (N m), or volts, per logged unit (`--effort-scale`); 1 for current, whose factor is below."""
    gear: float = 1.0
    """Motor turns per joint turn (the reduction), for a current log (`--gear`)."""
    kt: float | None = None
    """The motor's torque constant (N m/A) of the logged current (`--kt`); needed for a current log."""
    efficiency: float = 1.0
    """The gearbox's efficiency, 0 < e <= 1 (`--efficiency`)."""

    def __post_init__(self):
        if self.kind not in EFFORT_KINDS:
            raise ValueError(f"effort must be one of {', '.join(EFFORT_KINDS)}; got {self.kind!r}")
        if self.kind == "current" and self.kt is None:
            raise ValueError("a current log needs the motor's torque constant kt (N m/A)")

    @property
    def current_factor(self) -> float:
        """Joint torque (N m) per logged ampere: gear x kt x efficiency (a current log only)."""
        return self.gear * self.kt * self.efficiency


def read_effort(table, reading: EffortReading, bag: bool):
    """The table with its effort column as what is fitted (torque, or volts), and a note saying how."""
    from .table import LogError

    if reading.kind == "torque":
        return scale_torque(table, reading.scale, bag)
    source = "effort" if bag else "tau"
    if reading.kind == "voltage":
        if not math.isfinite(reading.scale) or reading.scale == 0:
            raise LogError(table.path, f"effort scale {reading.scale!r} must be a finite number other than 0")
        if reading.scale == 1.0:
            note = f"{source} read as motor voltage in V (--effort voltage): kA, kG, kV, kS are gains in volts."
            columns = table.columns
        else:
            note = (f"voltage = {reading.scale:g} × {source}, in V (--effort voltage --effort-scale {reading.scale:g}): "
                    "kA, kG, kV, kS are gains in volts.")
            columns = {**table.columns, "tau": table.columns["tau"] * reading.scale}
        return dataclasses.replace(table, columns=columns, notes=(*table.notes, note), effort="voltage",
                                   effort_scale=reading.scale)
    factor = reading.current_factor
    if not math.isfinite(factor) or factor == 0:
        raise LogError(table.path, f"torque per ampere {factor!r} (gear x kt x efficiency) must be a finite number "
                       "other than 0")
    note = (f"torque = {reading.gear:g} (gear) × {reading.kt:g} N m/A (kt) × {reading.efficiency:g} (efficiency) × "
            f"{source} in A = {factor:.6g} N m/A × {source}, in N m (--effort current).")
    columns = {**table.columns, "tau": table.columns["tau"] * factor}
    return dataclasses.replace(table, columns=columns, notes=(*table.notes, note), effort_scale=factor,
                               effort="current", current_to_torque=(reading.gear, reading.kt, reading.efficiency))


def scale_torque(table, scale: float, bag: bool):
    """The table with tau multiplied by `scale`, and a note saying which scale was used (always for a bag)."""
    if not math.isfinite(scale) or scale == 0:
        from .table import LogError

        raise LogError(table.path, f"effort scale {scale!r} must be a finite number other than 0")
    source = "effort" if bag else "tau"
    if scale == 1.0:
        if not bag:
            return table
        note = "effort read as torque in N m (--effort-scale 1)."
        return dataclasses.replace(table, notes=(*table.notes, note))
    note = f"torque = {scale:g} × {source}, in N m (--effort-scale {scale:g})."
    columns = {**table.columns, "tau": table.columns["tau"] * scale}
    return dataclasses.replace(table, columns=columns, notes=(*table.notes, note), effort_scale=scale)
