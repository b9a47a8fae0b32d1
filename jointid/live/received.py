"""What a live source hands over at each poll: the samples that arrived since the last one, and what happened to
the source meanwhile. Every live source (NetworkTables, a growing CSV) speaks this one shape."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping, Protocol

import numpy as np


@dataclass(frozen=True, eq=False)
class Received:
    """Samples that arrived since the last poll, in the log's units after conversion (SI; metres kept for a
    linear mechanism), on the source's own clock in seconds."""

    columns: Mapping[str, np.ndarray] = field(default_factory=dict)
    """'t' always (when any sample arrived); any of 'q', 'qd', 'qdd', 'tau'; 'state' (str array: the SysId test
    under way at each sample, as a data log's test-state entry). Every array has the same length."""
    events: tuple[str, ...] = ()
    """One sentence per thing that happened, in order: 'connected to 127.0.0.1:5810', 'source gone at 12.3 s',
    'reconnected after a 2.1 s gap (not bridged)'."""
    dropped: int = 0
    """Samples the source received but could not keep since the last poll (it was too fast to keep up)."""
    ended: bool = False
    """True when the source is finished for good (the file's writer closed it, --duration reached)."""
    breaks: tuple[int, ...] = ()
    """Rows of this block where a new stretch starts (a reconnection after a gap, a file truncated or replaced):
    nothing may be interpolated or differentiated across one. 't' still grows across it (see live.stretches)."""

    @property
    def count(self) -> int:
        """Samples in this block."""
        t = self.columns.get("t")
        return 0 if t is None else len(t)


class LiveSource(Protocol):
    """A source of samples read while the joint moves."""

    description: str
    """One line naming it, e.g. "NetworkTables 127.0.0.1:5810: q=/Arm/Position, tau=/Arm/Voltage"."""
    effort: str
    """What 'tau' holds: 'torque' (N m, a current log's converted) or 'voltage' (V), as a recorded log's effort."""
    linear: bool
    """True when q is a length in metres (an elevator, a drivetrain), as a recorded log's `linear`."""

    def poll(self, timeout: float) -> Received:
        """Wait up to timeout seconds for samples, then return what arrived (possibly nothing)."""

    def close(self) -> None:
        """Stop reading and release the connection or file."""
