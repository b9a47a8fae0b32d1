"""The one place files are read and written: special files refused, atomic no-clobber writes, groups kept whole."""

import json
import os
import signal
import subprocess
import sys

import pytest

from jointid.files import (
    ExportError,
    FileRefused,
    NotRegularFile,
    atomic_output,
    check_readable,
    open_for_reading,
    read_bytes,
    remove_stale_temporaries,
    shown_path,
    write_json,
    write_text,
)


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


# Reading: one opener that refuses special files -------------------------------------------------------


def test_open_for_reading_reads_a_regular_file(tmp_path):
    path = tmp_path / "log.csv"
    path.write_bytes(b"t,q\n")
    with open_for_reading(path) as handle:
        assert handle.read() == b"t,q\n"
    assert read_bytes(path, 2) == b"t,q"  # one byte beyond the limit says the file is larger


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes on this system")
def test_a_fifo_is_refused_without_being_opened(tmp_path):
    path = tmp_path / "pipe.csv"
    os.mkfifo(path)  # no writer: an open() for reading would wait for ever
    with pytest.raises(FileRefused) as refused:
        open_for_reading(path)
    assert str(refused.value) == f"{path}: cannot read: a named pipe (FIFO), not a regular file"
    assert refused.value.reason == "a named pipe (FIFO), not a regular file"
    with pytest.raises(FileRefused):
        check_readable(path)


def test_a_folder_or_a_missing_file_is_refused_in_one_line(tmp_path):
    with pytest.raises(FileRefused, match="cannot read: a directory, not a regular file"):
        open_for_reading(tmp_path)
    with pytest.raises(FileRefused, match="cannot open: No such file or directory"):
        open_for_reading(tmp_path / "absent.csv")
    with pytest.raises(FileRefused, match="cannot open: embedded null byte"):
        open_for_reading(str(tmp_path / "nul\0.csv"))


def test_a_path_that_is_not_printable_is_shown_escaped_as_every_name_is():
    """A newline or an undecodable byte is written as the escape one types back (text_safety.typed_name)."""
    assert shown_path("logs/run 1 ²") == "logs/run 1 ²"
    assert shown_path("two\nlines.csv") == "two\\nlines.csv"
    assert shown_path(b"caf\xe9.csv") == "caf\\xe9.csv"
    assert "\n" not in str(FileRefused("two\nlines.csv", "cannot open", "No such file or directory"))


# Writing: only a regular file is ever replaced ----------------------------------------------------------


def test_overwrite_replaces_only_a_regular_file(tmp_path):
    target = tmp_path / "target.txt"
    target.write_text("keep me")
    link = tmp_path / "link.txt"
    link.symlink_to(target)
    folder = tmp_path / "folder.txt"
    folder.mkdir()
    for path, kind in ((link, "a symbolic link"), (folder, "a directory")):
        with pytest.raises(NotRegularFile, match=f"{kind}, not a regular file; not replacing it"):
            write_text(path, "new", overwrite=True)
    assert link.is_symlink() and target.read_text() == "keep me" and folder.is_dir()
    assert sorted(os.listdir(tmp_path)) == ["folder.txt", "link.txt", "target.txt"]


def test_a_destination_turned_special_while_writing_is_not_replaced(tmp_path):
    path = tmp_path / "out.txt"
    with pytest.raises(NotRegularFile), atomic_output(path, overwrite=True) as handle:
        handle.write("ours")
        path.symlink_to(tmp_path)  # appears between the first look and the rename
    assert path.is_symlink()


# A group killed between its links ----------------------------------------------------------------------


KILLED_BETWEEN_LINKS = """
import os, signal, sys
from jointid import files

real_link = os.link
def link_then_die(source, destination):
    real_link(source, destination)
    os.kill(os.getpid(), signal.SIGKILL)  # kill -9 after the first member's link
os.link = link_then_die
files.write_texts({sys.argv[1]: "{}", sys.argv[2]: "<svg/>"})
"""


def kill_between_links(folder) -> tuple:
    """(json, svg): a group write in another process, killed right after the JSON was linked into place."""
    json_path, svg_path = folder / "fit.json", folder / "fit.svg"
    done = subprocess.run([sys.executable, "-c", KILLED_BETWEEN_LINKS, str(json_path), str(svg_path)], check=False)
    assert done.returncode == -signal.SIGKILL
    assert json_path.exists() and not svg_path.exists()  # what kill -9 leaves: half of the pair
    return json_path, svg_path


def test_the_next_write_removes_a_group_killed_between_its_links(tmp_path):
    kill_between_links(tmp_path)
    write_text(tmp_path / "other.txt", "any write into the folder")
    assert sorted(os.listdir(tmp_path)) == ["other.txt"]


def test_a_file_put_in_place_by_someone_else_is_never_removed_as_an_orphan(tmp_path):
    json_path, _ = kill_between_links(tmp_path)
    json_path.unlink()
    json_path.write_text("the user's own file, by the same name")
    assert remove_stale_temporaries(str(tmp_path)) and json_path.read_text().startswith("the user's")
    assert sorted(os.listdir(tmp_path)) == ["fit.json"]


def test_a_group_killed_after_its_last_link_is_kept_whole(tmp_path):
    json_path, svg_path = tmp_path / "fit.json", tmp_path / "fit.svg"
    script = KILLED_BETWEEN_LINKS.replace("real_link(source, destination)\n    os.kill",
                                          "real_link(source, destination)\n    if destination.endswith('.svg'): os.kill")
    done = subprocess.run([sys.executable, "-c", script, str(json_path), str(svg_path)], check=False)
    assert done.returncode == -signal.SIGKILL and len(os.listdir(tmp_path)) == 4  # both, and both temporaries
    remove_stale_temporaries(str(tmp_path))
    assert sorted(os.listdir(tmp_path)) == ["fit.json", "fit.svg"]


# Odd names in the output folder -------------------------------------------------------------------------


def test_the_longest_legal_name_can_be_written(tmp_path):
    # The temporary beside it was longer than the name and so over the file system's limit (NAME_MAX).
    limit = os.pathconf(tmp_path, "PC_NAME_MAX")
    path = tmp_path / ("n" * (limit - 4) + ".txt")
    write_text(path, "whole")
    assert path.read_text() == "whole" and os.listdir(tmp_path) == [path.name]


@pytest.mark.parametrize("stray", [".a.99999999999999999999-deadbeef.jointid-part",
                                   ".jointid.9999999999-deadbeef-0.jointid-part",
                                   ".jointid.99999999999999999999-deadbeef-0.jointid-part"])
def test_a_stray_temporary_with_an_impossible_process_id_is_left_alone(tmp_path, stray):
    # Its process id overflowed os.kill, and every write into the folder failed ("not a finite number").
    (tmp_path / stray).write_text("not ours to judge")
    write_text(tmp_path / "out.txt", "written")
    assert sorted(os.listdir(tmp_path)) == sorted([stray, "out.txt"])
