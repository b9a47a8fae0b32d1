"""Time windows 'START:END' (seconds from a log's start; a data log's own time stamps) for --train-window and
--heldout-window; stdlib only."""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class TimeWindow:
    """The samples from `start` to `end` seconds after the log's first sample, or of a data log's own clock (both
    ends included)."""

    start: float = 0.0
    end: float = math.inf

    @property
    def text(self) -> str:
        """'2:10' or '2:' (to the end), as typed."""
        end = "" if math.isinf(self.end) else f"{self.end:g}"
        return f"{self.start:g}:{end}"

    def to_dict(self) -> dict:
        """JSON-ready seconds (end None when open)."""
        return {"start_s": self.start, "end_s": None if math.isinf(self.end) else self.end}


def parse_time_window(text: str) -> TimeWindow:
    """'START:END' in seconds from the log's start, either end may be left out; ValueError saying what is wrong."""
    start_text, colon, end_text = text.partition(":")
    if not colon:
        raise ValueError(f"{text!r} is not START:END (seconds from the log's start, e.g. 0:30)")
    try:
        start = float(start_text) if start_text.strip() else 0.0
        end = float(end_text) if end_text.strip() else math.inf
    except ValueError:
        raise ValueError(f"{text!r} is not START:END with numbers in seconds, e.g. 0:30") from None
    if not (math.isfinite(start) and start >= 0) or math.isnan(end):
        raise ValueError(f"{text!r}: START must be a finite number of seconds, 0 or more")
    if not end > start:
        raise ValueError(f"{text!r}: END must be later than START")
    return TimeWindow(start, end)
