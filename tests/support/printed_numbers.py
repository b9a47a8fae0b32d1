"""Text that a program prints compared as a reader reads it: the words exactly, the numbers at their precision.

A number's last bits depend on the CPU (OpenBLAS picks other kernels on another processor, and
`OPENBLAS_CORETYPE=Prescott` shows the drift on any machine), so a doc example or a snapshot that shows a computed
number pins it only as far as it is printed: a number shown in full (ten or more significant digits, as JSON and
repr print floats) within 1e-9 of its size, a number rounded for reading (a 6-decimal readout, a percentage) within
one unit of its last printed digit. Integers (counts, ranks, sizes) and every word still match exactly; runs of
spaces may differ in length only where a number's width changed (a table's column of `-0.000000` and `0.000000`).
"""

from __future__ import annotations

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


SVG_TEXT = re.compile(r">([^<]*)<")
"""The text between an SVG's tags: what the terminal showed; the tags around it are the layout."""


def svgs_agree(expected: str, actual: str) -> bool:
    """Whether two screenshots show the same layout (every tag and attribute exactly) and the same text, its
    numbers within their printed precision."""
    if expected == actual:
        return True
    expected_parts, actual_parts = SVG_TEXT.split(expected), SVG_TEXT.split(actual)
    if len(expected_parts) != len(actual_parts):
        return False
    # split() alternates tags (even places) and the text between them (odd places).
    return all(e == a if k % 2 == 0 else lines_agree(e.replace("&#160;", " "), a.replace("&#160;", " "))
               for k, (e, a) in enumerate(zip(expected_parts, actual_parts)))
