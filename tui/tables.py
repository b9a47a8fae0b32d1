"""Plain aligned text tables: they read the same in a terminal, a snapshot and a screen reader."""

from __future__ import annotations

COLUMN_GAP = "  "
"""Space between columns."""


def text_table(header: list[str], rows: list[list[str]]) -> str:
    """Rows under a header; first column left-aligned, the others right-aligned so decimals line up."""
    table = [header, *rows]
    widths = [max(len(row[i]) for row in table) for i in range(len(header))]
    lines = []
    for row in table:
        cells = [row[0].ljust(widths[0])] + [cell.rjust(width) for cell, width in zip(row[1:], widths[1:])]
        lines.append(COLUMN_GAP.join(cells).rstrip())
    return "\n".join(lines)
