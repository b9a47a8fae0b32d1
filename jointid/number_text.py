"""Numbers as a person types them: plain ASCII decimal notation only.

Python's float() and int() also accept other scripts' digits ('٣', '２') and
digit-group underscores ('1_000'). A typed setting or flag should mean exactly
what it shows in any terminal font, so only ASCII decimal notation is read
here; inf and nan are still read, so that range checks can say what is wrong.
"""

from __future__ import annotations

import re

_DECIMAL = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?|[+-]?(inf|infinity|nan)", re.ASCII | re.IGNORECASE)
_WHOLE = re.compile(r"[+-]?\d+", re.ASCII)


def parse_float(text: str) -> float:
    """float(text) for ASCII decimal notation, 'inf' and 'nan' included; ValueError for anything else."""
    text = text.strip()
    if not _DECIMAL.fullmatch(text):
        raise ValueError(f"not a decimal number: {text!r}")
    return float(text)


def parse_int(text: str) -> int:
    """int(text) for ASCII decimal digits with an optional sign; ValueError for anything else."""
    text = text.strip()
    if not _WHOLE.fullmatch(text):
        raise ValueError(f"not a whole number: {text!r}")
    return int(text)  # ValueError too beyond Python's 4300-digit limit
