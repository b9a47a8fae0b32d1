"""What a log's effort column measures, and the unit everything fitted to it is reported in.

A torque log is fitted as it is; a current log is turned into torque when it is read (gear x torque constant x
efficiency per ampere), so it is a torque log from then on; a voltage log is fitted as it is, by the same terms
with the effort in volts (the WPILib arm feedforward V = kS sgn(qd) + kG cos(q + q0) + kV qd + kA qdd).
"""

from __future__ import annotations

from dataclasses import dataclass

EFFORT_KINDS = ("torque", "current", "voltage")
"""The --effort choices."""


@dataclass(frozen=True)
class Effort:
    """The quantity a fit's effort column holds once read: its name and unit."""

    name: str
    """'torque' or 'voltage'."""
    unit: str
    """'N m' or 'V'."""

    @property
    def is_torque(self) -> bool:
        """True for torque (the lesson's and jointid's default)."""
        return self.name == "torque"

    @property
    def label(self) -> str:
        """A chart's axis label, e.g. 'Torque (N m)'."""
        return f"{self.name.capitalize()} ({self.unit})"


TORQUE = Effort("torque", "N m")
VOLTAGE = Effort("voltage", "V")


def effort_named(name: str) -> Effort:
    """The Effort a fit is made in for a logged effort kind: torque for torque and current, voltage for voltage."""
    return VOLTAGE if name == "voltage" else TORQUE
