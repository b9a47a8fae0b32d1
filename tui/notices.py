"""How long the explorer's notifications stay: routine refusals briefly, news and failures long enough to read."""

from __future__ import annotations

ROUTINE_SECONDS = 3.0
"""A refusal the user can fix at once (a value out of range, a key that does not apply here), and every warning:
short, so it leaves the charts soon; a repeat replaces it rather than stacking (JointIdApp.on_notify)."""
NEWS_SECONDS = 5.0
"""Anything else (a log loaded or not, files written): Textual's default, to read a path or a row number."""
