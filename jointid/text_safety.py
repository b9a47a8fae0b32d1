"""Names the program did not choose (file names, entry names from a log), made safe to show anywhere.

A file name may hold bytes that are not UTF-8 (Python keeps them as lone
surrogates, which no UTF-8 output can encode), terminal controls (ESC[2J
clears a screen, an OSC sequence sets a window's title, BEL rings, CR
rewrites a line) or bidirectional overrides (U+202E shows a name backwards).
`shown_name` turns every such character into a backslash escape, so that a
name shows as one line of plain text and can be typed back (`typed_name`).
"""

from __future__ import annotations

import re

_SHORT_ESCAPES = {"\n": "\\n", "\r": "\\r", "\t": "\\t"}
"""Control characters with a well-known short escape."""

_ESCAPE = re.compile(r"\\(x[0-9a-fA-F]{2}|u[0-9a-fA-F]{4}|U[0-9a-fA-F]{8}|[nrt])")
"""One escape `shown_name` writes."""


def _escaped(character: str) -> str:
    """The backslash escape of one character that is not shown as it is."""
    code = ord(character)
    if character in _SHORT_ESCAPES:
        return _SHORT_ESCAPES[character]
    if 0xDC80 <= code <= 0xDCFF:  # a byte that was not UTF-8, kept by os.fsdecode as a lone surrogate
        return f"\\x{code - 0xDC00:02x}"
    if code < 0x80:  # \x80 to \xff stand for undecodable bytes only, so C1 controls take \u below
        return f"\\x{code:02x}"
    return f"\\u{code:04x}" if code < 0x10000 else f"\\U{code:08x}"


def shown_name(text: str) -> str:
    """`text` with every character that is not printable (controls, escapes, undecodable bytes, bidirectional
    overrides) written as a backslash escape; printable text, accents included, stays as it is.

    >>> shown_name("run 1.csv"), shown_name("a\\x1b[2Jb"), shown_name("caf\\udce9.csv")
    ('run 1.csv', 'a\\\\x1b[2Jb', 'caf\\\\xe9.csv')
    """
    if text.isprintable():
        return text
    return "".join(character if character.isprintable() else _escaped(character) for character in text)


def typed_name(text: str) -> str:
    """The name `shown_name` showed as `text`: its escapes turned back into characters, `\\x80`-`\\xff` into
    the undecodable bytes they stand for (so the name opens as os.fsdecode gave it).

    >>> typed_name("caf\\\\xe9.csv") == "caf\\udce9.csv"
    True
    """

    def character(match: re.Match) -> str:
        escape = match.group(1)
        if escape in ("n", "r", "t"):
            return {"n": "\n", "r": "\r", "t": "\t"}[escape]
        code = int(escape[1:], 16)
        return chr(0xDC00 + code) if escape[0] == "x" and code >= 0x80 else chr(code)

    return _ESCAPE.sub(character, text)
