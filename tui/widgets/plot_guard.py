"""What a plotext chart shows instead of itself when it cannot be drawn: too small, or plotext failed.

plotext's layout code was written for charts of ordinary sizes; at a few
columns it can have no canvas left after the tick labels and fail (a sweep
histogram at 22x80 raised `ValueError: not enough values to unpack`). A chart
is never worth a crash: below `MIN_PLOT_SIZE` it is not attempted, and any
error while building one becomes a line of text in its place, logged.
"""

from __future__ import annotations

MIN_PLOT_SIZE = (16, 4)
"""Smallest (width, height) in cells a chart is drawn at: tick labels take up to 8 columns and the
x axis two rows, so anything smaller would be mostly axes (and plotext may have no canvas left)."""
TOO_SMALL = "(too small to draw the chart)"
"""Shown in place of a chart below MIN_PLOT_SIZE."""


def too_small(width: int, height: int) -> bool:
    """Whether a chart of this size is not drawn at all."""
    return width < MIN_PLOT_SIZE[0] or height < MIN_PLOT_SIZE[1]


def failure_text(error: BaseException) -> str:
    """The line shown in place of a chart whose drawing raised `error`."""
    return f"(chart not drawn: {type(error).__name__})"
