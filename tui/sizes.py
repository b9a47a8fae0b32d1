"""The terminal sizes the explorer's layout is built for, and the size classes its screens style themselves by."""

from __future__ import annotations

MIN_SIZE = (70, 22)
"""Smallest (width, height) the layout stays readable at; below it the screen asks for more."""
COMPACT_BELOW = (110, 32)
"""Narrower or shorter than this (width, height), readouts and known parameters use compact rows."""


def size_classes(width: int, height: int) -> dict[str, bool]:
    """The screen's size classes: -narrow/-wide, -short/-tall, -compact when either is small, -too-small."""
    narrow, short = width < COMPACT_BELOW[0], height < COMPACT_BELOW[1]
    return {
        "-narrow": narrow, "-wide": not narrow, "-short": short, "-tall": not short,
        "-compact": narrow or short, "-too-small": width < MIN_SIZE[0] or height < MIN_SIZE[1],
    }
