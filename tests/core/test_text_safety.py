"""shown_name: the one escaping of names the program did not choose (file names, a log's entry names)."""

from __future__ import annotations

import os

import pytest

from jointid.text_safety import shown_name, typed_name


@pytest.mark.parametrize("name, shown", [
    ("run 1 (final).csv", "run 1 (final).csv"),  # printable: as it is
    ("mesure d'été.csv", "mesure d'été.csv"),  # accents are printable
    ("\x1b[2Jclear.csv", "\\x1b[2Jclear.csv"),  # clears a terminal if shown raw
    ("\x1b]0;owned\x07.csv", "\\x1b]0;owned\\x07.csv"),  # sets a window title, rings
    ("a\rb\nc\td.csv", "a\\rb\\nc\\td.csv"),  # rewrites or breaks a line
    ("x\u202egpj.csv", "x\\u202egpj.csv"),  # shows the rest backwards
    (os.fsdecode(b"caf\xe9.csv"), "caf\\xe9.csv"),  # a byte that is not UTF-8
    ("\x85next", "\\u0085next"),  # a C1 control, told apart from the byte 0x85
])
def test_a_name_shows_as_printable_text_and_types_back_to_itself(name, shown):
    assert shown_name(name) == shown
    assert shown.isprintable() and shown.encode("utf-8")  # one line, encodable anywhere
    assert typed_name(shown) == name
