"""How a live source's values become what is fitted, as a recorded log's are read: angles in radians (degrees
converted, a length kept in metres), the angle's convention applied, the effort as torque (scaled, or converted from
current) or as volts."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..logs.conventions import AngleConvention
from ..logs.effort import EffortReading

MOTION = ("q", "qd", "qdd")
"""The columns an angle unit and the angle's direction apply to."""


@dataclass(frozen=True)
class LiveReading:
    """How to read a live source's columns (`--degrees`, `--zero`, `--clockwise`, `--effort`, `--effort-scale`,
    `--gear`, `--kt`, `--efficiency`), as a CSV log's are read."""

    degrees: bool = False
    """True when q, qd, qdd arrive in degrees (a source whose units are not published)."""
    angle: AngleConvention = field(default_factory=AngleConvention)
    """Where the logged angle's 0 points and which way it grows."""
    effort: EffortReading = field(default_factory=EffortReading)
    """What tau measured: torque (times its scale), current (converted to torque) or voltage (volts)."""

    def with_effort_kind(self, kind: str) -> LiveReading:
        """The same reading with the effort read as `kind` (a SysId routine's effort is its motor's voltage)."""
        return LiveReading(self.degrees, self.angle, EffortReading(kind, self.effort.scale, self.effort.gear,
                                                                   self.effort.kt, self.effort.efficiency))

    @property
    def effort_kind(self) -> str:
        """What the converted tau holds: 'voltage' (V) or 'torque' (N m; a current's converted)."""
        return "voltage" if self.effort.kind == "voltage" else "torque"

    @property
    def effort_factor(self) -> float:
        """The converted tau per arriving unit: N m per N m or per ampere, or volts per volt."""
        factor = self.effort.current_factor if self.effort.kind == "current" else self.effort.scale
        if not math.isfinite(factor) or factor == 0:
            raise ValueError(f"the effort's factor {factor!r} must be a finite number other than 0")
        return factor

    def notes(self) -> tuple[str, ...]:
        """Sentences saying how the values are converted (none when they are used as they arrive)."""
        out = []
        if self.degrees:
            out.append("q, qd and qdd arrive in degrees: converted to radians.")
        note = self.angle.note("the logged angle")
        if note is not None:
            out.append(note)
        if self.effort.kind == "current":
            out.append(f"tau is motor current: torque = {self.effort_factor:.6g} N m/A × current (gear × kt × "
                       "efficiency).")
        elif self.effort.scale != 1.0:
            unit = "V" if self.effort.kind == "voltage" else "N m"
            out.append(f"tau = {self.effort.scale:g} × the arriving effort, in {unit}.")
        if self.effort.kind == "voltage":
            out.append("tau is motor voltage (V): kA, kG, kV, kS are gains in volts.")
        return tuple(out)

    def convert(self, columns: dict, factors: dict | None = None) -> dict:
        """The columns as fitted: q, qd, qdd times their unit's factor (`factors`, else degrees or 1), the angle's
        convention applied, tau times the effort's factor; 't' and 'state' as they are. New arrays."""
        out = dict(columns)
        scale = math.pi / 180 if self.degrees else 1.0
        sign = self.angle.sign
        for name in MOTION:
            if name in out:
                factor = (factors or {}).get(name, scale)
                out[name] = np.asarray(out[name], dtype=float) * (factor * sign)
        if "q" in out and self.angle.offset:
            out["q"] = out["q"] + self.angle.offset
        if "tau" in out:
            out["tau"] = np.asarray(out["tau"], dtype=float) * (self.effort_factor * sign)
        return out
