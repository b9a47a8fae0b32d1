"""Atomic, no-clobber writing of exported files."""

import json
import os

import pytest

from jointid.files import ExportError, atomic_output, write_json, write_text


def test_write_json_creates_the_file_with_a_final_newline(tmp_path):
    path = tmp_path / "fit.json"
    write_json(path, {"I": 0.8, "label": "kg m²"})
    text = path.read_text(encoding="utf-8")
    assert text.endswith("}\n") and json.loads(text) == {"I": 0.8, "label": "kg m²"}
    assert os.listdir(tmp_path) == ["fit.json"]


def test_an_existing_file_is_never_replaced_without_overwrite(tmp_path):
    path = tmp_path / "fit.json"
    path.write_text("keep me")
    with pytest.raises(ExportError, match="already exists"):
        write_json(path, {"new": True})
    assert path.read_text() == "keep me"
    write_json(path, {"new": True}, overwrite=True)
    assert json.loads(path.read_text()) == {"new": True}
    assert os.listdir(tmp_path) == ["fit.json"]


def test_a_file_that_appears_while_writing_is_not_clobbered(tmp_path):
    path = tmp_path / "race.txt"
    with pytest.raises(ExportError, match="already exists"):
        with atomic_output(path) as handle:
            handle.write("ours")
            path.write_text("theirs")  # another program wins the race
    assert path.read_text() == "theirs"
    assert os.listdir(tmp_path) == ["race.txt"]


def test_an_error_while_writing_leaves_nothing_behind(tmp_path):
    path = tmp_path / "half.txt"
    with pytest.raises(RuntimeError):
        with atomic_output(path) as handle:
            handle.write("partial")
            raise RuntimeError("disk full, say")
    assert os.listdir(tmp_path) == []


def test_a_missing_folder_is_one_clear_error(tmp_path):
    with pytest.raises(ExportError, match="cannot write"):
        write_text(tmp_path / "no" / "such" / "file.txt", "x")
