"""Text that a program prints compared as a reader reads it: the words exactly, the numbers at their precision.

A number's last bits depend on the CPU (OpenBLAS picks other kernels on another processor, and
`OPENBLAS_CORETYPE=Prescott` shows the drift on any machine), so a doc example or a snapshot that shows a computed
number pins it only as far as it is printed: a number shown in full (ten or more significant digits, as JSON and
repr print floats) within 1e-9 of its size, a number rounded for reading (a 6-decimal readout, a percentage) within
one unit of its last printed digit. Integers (counts, ranks, sizes) and every word still match exactly; runs of
spaces may differ in length only where a number's width changed (a table's column of `-0.000000` and `0.000000`).
"""

from __future__ import annotations

import html
import re

FULL_PRECISION = 1e-9
"""Relative tolerance of a number printed in full: far above a CPU's rounding drift, far below any rounding for
reading."""

FULL_DIGITS = 10
"""A number with this many significant digits or more is printed in full (repr, JSON), not rounded for reading."""

NUMBER = re.compile(r"(?<![\w.])[-+−]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?(?![\w.])")
"""A number standing alone: not the digits of a name (q0, pendulum_1.csv, 80x24) nor a version's parts."""


def _value(text: str) -> float:
    """The number's value (a typographic minus read as one)."""
    return float(text.replace("−", "-"))


def _is_integer(text: str) -> bool:
    """Whether the number is written without a decimal point or an exponent (a count: compared exactly)."""
    return re.fullmatch(r"[-+−]?\d+", text) is not None


def tolerance(printed: str, full: bool = False) -> float:
    """How far a computed number may be from the one printed as `printed`: 1e-9 of its size when printed in full
    (or `full`, as for every number of a JSON document), else one unit of its last printed digit."""
    mantissa, _, exponent = printed.replace("−", "-").lower().partition("e")
    digits = re.sub(r"\D", "", mantissa).lstrip("0")
    if full or len(digits) >= FULL_DIGITS:
        return FULL_PRECISION * abs(_value(printed))
    decimals = len(mantissa.partition(".")[2])
    return 10.0 ** (int(exponent or 0) - decimals) * (1 + 1e-9)  # the factor absorbs the decimal's own rounding


def numbers_agree(expected: str, actual: str, full: bool = False) -> bool:
    """Whether the printed `actual` is the printed `expected` at the precision `expected` is printed with."""
    if expected == actual:
        return True
    if _is_integer(expected) or _is_integer(actual):
        return False
    return abs(_value(actual) - _value(expected)) <= tolerance(expected, full)


def _split(line: str) -> tuple[list[str], list[str]]:
    """(the words between the numbers, whitespace runs made one space; the numbers), of one line."""
    words = [re.sub(r"\s+", " ", part) for part in NUMBER.split(line)]
    return words, NUMBER.findall(line)


def lines_agree(expected: str, actual: str, full: bool = False) -> bool:
    """Whether two printed lines say the same words and the same numbers at the expected line's precision."""
    if expected == actual:
        return True
    expected_words, expected_numbers = _split(expected)
    actual_words, actual_numbers = _split(actual)
    return (expected_words == actual_words and len(expected_numbers) == len(actual_numbers)
            and all(numbers_agree(e, a, full) for e, a in zip(expected_numbers, actual_numbers)))


CELL = re.compile(r'<text class="([\w-]+)" x="([\d.]+)" y="[\d.]+" textLength="[\d.]+" '
                  r'clip-path="url\(#terminal-line-(\d+)\)">([^<]*)</text>')
"""One run of a screenshot's characters: its style class, where it starts, its line, its text."""

BACKGROUND = re.compile(r'<rect fill="([^"]+)" x="([\d.]+)" y="([\d.]+)" width="([\d.]+)" height="24.65"[^>]*>')
"""One run of a line's background colour."""

STYLE = re.compile(r"\.(terminal-r\d+) \{([^}]*)\}")
"""A style class's definition (classes are numbered in order of first use, so a screen's numbers can differ)."""

CELL_WIDTH, LINE_HEIGHT, TOP = 12.2, 24.4, 1.5
"""Rich's SVG export: a character cell's width and a line's height (its font size 20), and the first line's top."""

CHART_GLYPHS = frozenset(chr(code) for code in range(0x2800, 0x2900)) | {"░", "●", " "}
"""What a plotext chart draws with: braille dots, the shading of what was left out, markers, and blank cells."""

CHART_CELLS = 8
"""Chart cells two screenshots may differ in: a point whose pixel falls on the other side of a pixel boundary on
another CPU moves a dot into the next cell (one such point changed two cells of the real log at 120x40)."""


def _cells(svg: str) -> dict[tuple[int, int], tuple[str, str, str]]:
    """(line, column) -> (character, its style, its background) of every cell a screenshot draws."""
    styles = {name: " ".join(rule.split()) for name, rule in STYLE.findall(svg)}
    cells: dict[tuple[int, int], list[str]] = {}
    for fill, x, y, width in BACKGROUND.findall(svg):
        line, first = round((float(y) - TOP) / LINE_HEIGHT), round(float(x) / CELL_WIDTH)
        for column in range(first, first + round(float(width) / CELL_WIDTH)):
            cells.setdefault((line, column), [" ", "", ""])[2] = fill
    for name, x, line, text in CELL.findall(svg):
        first = round(float(x) / CELL_WIDTH)
        for offset, character in enumerate(html.unescape(text).replace("\xa0", " ")):
            cell = cells.setdefault((int(line), first + offset), [" ", "", ""])
            cell[0], cell[1] = character, styles.get(name, name)
    return {place: tuple(cell) for place, cell in cells.items()}


def screens_agree(expected: str, actual: str, chart_cells: int = CHART_CELLS) -> bool:
    """Whether two screenshots show the same screen: every cell's character, style and background the same, but
    for the numbers of a line agreeing at their printed precision and at most `chart_cells` chart cells moved by a
    pixel; and everything else the SVG holds (its frame, title and size) the same."""
    if expected == actual:
        return True
    frame = lambda svg: STYLE.sub("", BACKGROUND.sub("", CELL.sub("", svg)))  # noqa: E731
    if frame(expected) != frame(actual):
        return False
    shown, drawn = _cells(expected), _cells(actual)
    blank = (" ", "", "")
    moved = 0
    lines = sorted({line for line, _ in shown} | {line for line, _ in drawn})
    for line in lines:
        width = 1 + max(column for (row, column) in (*shown, *drawn) if row == line)
        row_shown = [shown.get((line, column), blank) for column in range(width)]
        row_drawn = [drawn.get((line, column), blank) for column in range(width)]
        if row_shown == row_drawn:
            continue
        text_shown, text_drawn = [], []
        for (char_shown, *look_shown), (char_drawn, *look_drawn) in zip(row_shown, row_drawn):
            if (char_shown, look_shown) != (char_drawn, look_drawn) and {char_shown, char_drawn} <= CHART_GLYPHS:
                moved += 1
                char_shown = char_drawn = "\x00"  # a chart's pixel: counted, not read as text
            elif char_shown == char_drawn and look_shown != look_drawn:
                return False  # the same character in another colour or on another background
            text_shown.append(char_shown)
            text_drawn.append(char_drawn)
        if not lines_agree("".join(text_shown), "".join(text_drawn)):
            return False
    return moved <= chart_cells
