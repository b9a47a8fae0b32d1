"""Numbers as a person types them: plain ASCII decimal notation only.

Python's float() and int() also accept other scripts' digits ('٣', '２') and
digit-group underscores ('1_000'). A typed setting or flag should mean exactly
what it shows in any terminal font, so only ASCII decimal notation is read
here; inf and nan are still read, so that range checks can say what is wrong.
"""

from __future__ import annotations

import re

# Compiled on first use (re caches them): a command given no number should not pay 0.3 ms for them.
_DECIMAL = r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?|[+-]?(inf|infinity|nan)"
_WHOLE = r"[+-]?\d+"


def parse_float(text: str) -> float:
    """float(text) for ASCII decimal notation, 'inf' and 'nan' included; ValueError for anything else."""
    text = text.strip()
    if not re.fullmatch(_DECIMAL, text, re.ASCII | re.IGNORECASE):
        raise ValueError(f"not a decimal number: {text!r}")
    return float(text)


def parse_int(text: str) -> int:
    """int(text) for ASCII decimal digits with an optional sign; ValueError for anything else."""
    text = text.strip()
    if not re.fullmatch(_WHOLE, text, re.ASCII):
        raise ValueError(f"not a whole number: {text!r}")
    return int(text)  # ValueError too beyond Python's 4300-digit limit
