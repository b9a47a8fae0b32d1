"""How long the explorer's notifications stay: routine refusals briefly, news and failures long enough to read."""

from __future__ import annotations

ROUTINE_SECONDS = 3.0
"""A refusal the user can fix at once (a value out of range, a key that does not apply here), and every warning:
short, so it leaves the charts soon; a repeat replaces it rather than stacking (JointIdApp.on_notify)."""
NEWS_SECONDS = 5.0
"""Anything else (a log loaded or not, files written): Textual's default, to read a path or a row number."""

TOAST_WIDTH = (60, 0.5)
"""Textual's toast: 60 columns wide, at most half the screen's."""
TOAST_FRAME = 4
"""Columns of a toast that hold no text: its padding, its coloured left edge and the rack's margin (measured: 36 of
an 80-column screen's 40)."""


def toast_text_width(screen_width: int) -> int:
    """Columns of text in a notification on a screen `screen_width` columns wide."""
    columns, share = TOAST_WIDTH
    return max(1, min(columns, int(screen_width * share)) - TOAST_FRAME)


def fold_paths(message: str, width: int) -> str:
    """The message with each path too long for a line of `width` columns broken after its separators, so the
    notification wraps it between folders instead of mid-name (Textual folds a word wider than the line anywhere)."""
    import re

    def folded(match: re.Match) -> str:
        word = match.group(0)
        if len(word) <= width or "/" not in word:
            return word
        lines = [""]
        for part in re.findall(r"[^/]*/|[^/]+$", word):  # each folder with its separator, then the name
            if lines[-1] and len(lines[-1]) + len(part) > width:
                lines.append("")
            lines[-1] += part
        return "\n".join(lines)

    return re.sub(r"\S+", folded, message)
