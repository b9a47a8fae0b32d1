"""Small text helpers every presentation shares: numbers, word lists, aligned tables, settings headers."""

from __future__ import annotations

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing
if TYPE_CHECKING:
    from ..synthetic.settings import Settings

UNAVAILABLE = "unavailable"
"""Readout text when the rank gives no unique fit (or there is no held-out data)."""

COLUMN_GAP = "  "
"""Space between the columns of a text table."""

FIXED_POINT_RANGE = (1e-30, 1e15)
"""Nonzero magnitudes outside this range are written in scientific notation. Above: a 1e153 readout would
be 160 characters wide. Below: 1e-170 would read 0.000000, as if nothing moved; ordinary data's rounding
residues (about 1e-16 of their scale) stay well above it, so their zeros still read 0.000000."""


def ordinal(number: int) -> str:
    """2nd, 3rd, 4th, 11th, 21st ..."""
    suffix = "th" if 10 <= number % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(number % 10, "th")
    return f"{number}{suffix}"


def format_number(value: float, decimals: int = 6) -> str:
    """Fixed-point text with `decimals` places and no negative zero (scientific outside FIXED_POINT_RANGE)."""
    low, high = FIXED_POINT_RANGE
    if 0 < abs(value) < low or high <= abs(value) < float("inf"):
        return f"{value:.{decimals}e}"
    text = f"{value:.{decimals}f}"
    return text[1:] if text.startswith("-") and float(text) == 0 else text


def join_words(words: list[str]) -> str:
    """'a', 'a and b', 'a, b and c'."""
    return words[0] if len(words) == 1 else ", ".join(words[:-1]) + " and " + words[-1]


def capitalise(text: str) -> str:
    """First letter upper case, the rest untouched."""
    return text[:1].upper() + text[1:]


def text_table(header: list[str], rows: list[list[str]]) -> str:
    """Rows under a header; first column left-aligned, the others right-aligned so decimals line up.

    Plain aligned text reads the same in a terminal, a snapshot and a screen reader.
    """
    table = [header, *rows]
    widths = [max(len(row[i]) for row in table) for i in range(len(header))]
    lines = []
    for row in table:
        cells = [row[0].ljust(widths[0])] + [cell.rjust(width) for cell, width in zip(row[1:], widths[1:])]
        lines.append(COLUMN_GAP.join(cells).rstrip())
    return "\n".join(lines)


def settings_header(settings: Settings, *, motion: bool = True, seeds: str | None = None) -> str:
    """The experiment a text is about, e.g. 'Slow motion, noise 0.20 N m, 24 samples, seed 7'.

    Args:
        settings: The experiment.
        motion: Start with the training motion (False for texts that cover every motion).
        seeds: Replaces 'seed S', e.g. '1000 seeds 7..1006' for a sweep.
    """
    parts = [settings.training_motion.label] if motion else []
    parts += [f"noise {format_number(settings.noise, 2)} N m", f"{settings.samples} samples",
              seeds or f"seed {settings.seed}"]
    if settings.model != type(settings).model:  # the lesson's texts (the default model) stay as they were
        parts.append(f"model {settings.model}")
    if settings.constrained:
        parts.append("constrained")
    return ", ".join(parts + missing_physics(settings))


def missing_physics(settings: Settings) -> list[str]:
    """The synthetic joint's effects beyond the plain model, e.g. ['true Coulomb friction 0.3 N m'] ([] for none)."""
    joint = settings.true_joint
    named = [("Coulomb friction", joint.coulomb, "N m"), ("sensor bias", joint.bias, "N m"),
             ("encoder offset", joint.angle_offset, "rad")]
    return [f"true {name} {value:g} {unit}" for name, value, unit in named if value]
