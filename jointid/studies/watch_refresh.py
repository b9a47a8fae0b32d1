"""What a live identification shows at each refresh (studies/watch.py makes them; the explorer, `jointid watch
--json-lines` and the saved log's summary show them). Frozen like every result; fields may be added, not renamed."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping

import numpy as np

from ..estimation.fit import FitResult


@dataclass(frozen=True)
class ParameterTrace:
    """One parameter's estimate now, its history, and the moment it became well determined."""

    name: str
    """The model term's name, e.g. 'I' or 'kA'."""
    label: str
    unit: str
    value: float
    error: float
    """The reported standard error (the one the verdict judged)."""
    verdict: str | None
    """'well determined', 'weak', 'not determined' (as a log fit's judged verdict), or None before any fit."""
    reason: str | None
    """Why, when the verdict is weaker than the noise alone would give, as a log fit's verdict reason."""
    determined_at: float | None = None
    """Seconds watched when it first became well determined (and stayed so), or None."""
    determined_pct: float | None = None
    """Its relative error (%) at that moment: 'kA determined to 4.8 % after 12.4 s'."""
    history: tuple[tuple[float, float, float], ...] = ()
    """(seconds watched, value, error) at earlier refreshes, thinned so its length stays bounded."""


@dataclass(frozen=True)
class WatchRefresh:
    """Everything the faces show at one refresh of a live identification."""

    elapsed: float
    """Seconds of samples received (the source's clock, gaps not counted)."""
    received: int
    """Samples received so far."""
    fitted: int
    """Samples in the current fit (after derivatives, low-pass, decimation and exclusions)."""
    dropped: int
    """Samples lost so far because the source was faster than we could keep up (said, never hidden)."""
    parameters: tuple[ParameterTrace, ...]
    advice: tuple[str, ...] = ()
    """What the motion lacks while something is not determined: which parameter, and what motion would give it."""
    tests: tuple[tuple[str, float], ...] = ()
    """A SysId routine's tests seen so far: (test name, seconds of it received)."""
    events: tuple[str, ...] = ()
    """The source's events so far (connected, gone, reconnected after a gap), newest last, bounded."""
    recent: Mapping[str, np.ndarray] = field(default_factory=dict)
    """The last seconds for charts: 't', 'q', 'qd', 'tau' and 'predicted' (the current fit's effort)."""
    result: FitResult | None = None
    """The current fit, as a recorded log's (readouts, gains), or None before enough samples arrived."""
    ended: bool = False
