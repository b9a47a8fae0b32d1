"""Every path the command line reads or writes: special files are refused in one line, never read or replaced.

A FIFO read as a log, a bag, a bag folder's file or a motion file would block
its open for ever (sqlite's open too, which no signal interrupts), so those
commands run in a process of their own with a time limit that turns a hang
into a failure. Writing with --force replaces only a regular file: a FIFO, a
symlink, a directory or a device node in its place is refused and left as it was.
"""

from __future__ import annotations

import os
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from jointid.cli import main

HANG_LIMIT = 60
"""Seconds after which a command still reading is taken to hang (a refusal takes a second or two)."""

needs_fifos = pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes on this system")


def run(capsys, *argv):
    """(status, stdout, stderr) of one in-process command."""
    status = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def one_line(status: int, out: str, err: str) -> str:
    """The one line a refused command printed, after checking it is one line, on stderr, with status 2."""
    assert (status, out) == (2, ""), err
    assert err.startswith("jointid: ") and err.endswith("\n") and err.count("\n") == 1, err
    return err.strip()


def refused(capsys, *argv) -> str:
    """The one line of an in-process command that must be refused."""
    return one_line(*run(capsys, *argv))


def refused_without_hanging(*argv) -> str:
    """The one line of a command run in its own process, which fails the test if it is still running at HANG_LIMIT."""
    try:
        done = subprocess.run([sys.executable, "-m", "jointid", *map(str, argv)], capture_output=True, text=True,
                              timeout=HANG_LIMIT, stdin=subprocess.DEVNULL, check=False)
    except subprocess.TimeoutExpired:
        pytest.fail(f"jointid {' '.join(map(str, argv))} still running after {HANG_LIMIT} s: it opened a special file")
    return one_line(done.returncode, done.stdout, done.stderr)


# Reading ------------------------------------------------------------------------------------------------


@pytest.fixture
def fifo(tmp_path):
    """A function making a named pipe at tmp_path/name (no writer ever opens it)."""

    def make(name: str) -> Path:
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        os.mkfifo(path)
        return path

    return make


@needs_fifos
@pytest.mark.parametrize("command", ["fit", "simulate"])
def test_a_fifo_as_a_motion_file_is_refused_in_one_line(fifo, tmp_path, command):
    path = fifo("motion.json")
    extra = ["--out", tmp_path / "out.csv"] if command == "simulate" else []
    line = refused_without_hanging(command, "--motion-file", path, *extra)
    assert line == f"jointid: {path}: cannot read the motion file (a named pipe (FIFO), not a regular file)"


@needs_fifos
@pytest.mark.parametrize("name", ["joint.bag", "joint.db3", "joint.mcap"])
def test_a_fifo_as_a_bag_file_is_refused_in_one_line(fifo, name):
    pytest.importorskip("rosbags")
    path = fifo(name)
    line = refused_without_hanging("fit", "--bag", path, "--joint", "shoulder")
    assert line == f"jointid: {path}: cannot read: a named pipe (FIFO), not a regular file"


@needs_fifos
@pytest.mark.parametrize("member", ["metadata.yaml", "arm_0.db3"])
def test_a_fifo_inside_a_bag_folder_is_refused_in_one_line(fifo, tmp_path, member):
    pytest.importorskip("rosbags")
    folder = tmp_path / "arm"
    folder.mkdir()
    if member != "metadata.yaml":
        (folder / "metadata.yaml").write_text("rosbag2_bagfile_information:\n  relative_file_paths: [arm_0.db3]\n")
    fifo(f"arm/{member}")
    line = refused_without_hanging("bag-info", folder)
    assert line == f"jointid: {folder}, file {member}: cannot read: a named pipe (FIFO), not a regular file"


@needs_fifos
def test_a_fifo_as_a_held_out_log_is_refused_in_one_line(capsys, fifo, tmp_path):
    train = tmp_path / "train.csv"
    assert run(capsys, "simulate", "--out", train)[0] == 0
    path = fifo("test.csv")
    line = refused_without_hanging("fit", "--csv", train, "--heldout", path)
    assert line == f"jointid: {path}: cannot read: a named pipe (FIFO), not a regular file"


# Writing ------------------------------------------------------------------------------------------------


def special_destinations(tmp_path: Path) -> dict[str, Path]:
    """Each kind of file --force must not replace, made in tmp_path, by the kind it is said to be."""
    target = tmp_path / "target.csv"
    target.write_text("the symlink's target\n")
    made = {"a symbolic link": tmp_path / "link.csv", "a directory": tmp_path / "folder.csv"}
    made["a symbolic link"].symlink_to(target)
    made["a directory"].mkdir()
    if hasattr(os, "mkfifo"):
        made["a named pipe (FIFO)"] = tmp_path / "pipe.csv"
        os.mkfifo(made["a named pipe (FIFO)"])
    if os.geteuid() == 0:  # only root may make a device node; it is made here, never looked for in /dev
        made["a character device"] = tmp_path / "null.csv"
        os.mknod(made["a character device"], 0o600 | stat.S_IFCHR, os.makedev(1, 3))
    return made


def snapshot(path: Path) -> tuple:
    """What a destination is: its lstat's kind, inode and size, and a symlink's target."""
    info = os.lstat(path)
    return stat.S_IFMT(info.st_mode), info.st_ino, info.st_size, os.readlink(path) if path.is_symlink() else None


@pytest.mark.parametrize("force", [[], ["--force"]])
def test_simulate_never_replaces_anything_but_a_regular_file(capsys, tmp_path, force):
    for kind, path in special_destinations(tmp_path).items():
        before = snapshot(path)
        line = refused(capsys, "simulate", "--out", path, *force)
        assert line == f"jointid: {path}: {kind}, not a regular file; not replacing it"
        assert snapshot(path) == before
    assert not [name for name in os.listdir(tmp_path) if name.startswith(".")]  # no temporary left


def test_design_never_replaces_anything_but_a_regular_file(capsys, tmp_path):
    for kind, path in special_destinations(tmp_path).items():
        before = snapshot(path)
        line = refused(capsys, "design", "--samples", "24", "--starts", "1", "--out", path, "--force")
        assert line == f"jointid: {path}: {kind}, not a regular file; not replacing it"
        assert snapshot(path) == before


def test_force_still_replaces_a_regular_file(capsys, tmp_path):
    path = tmp_path / "log.csv"
    path.write_text("old\n")
    assert run(capsys, "simulate", "--out", path, "--force")[0] == 0
    assert path.read_text().startswith("# jointid simulate")


# One line for any path ----------------------------------------------------------------------------------


@pytest.mark.parametrize("flag", ["--csv", "--bag", "--motion-file"])
def test_a_path_holding_a_newline_is_escaped_in_a_one_line_error(capsys, tmp_path, flag):
    if flag == "--bag":
        pytest.importorskip("rosbags")
    path = tmp_path / "two\nlines.csv"
    extra = ["--joint", "shoulder"] if flag == "--bag" else []
    line = refused(capsys, "fit", flag, path, *extra)
    assert str(path).replace("\n", "\\n") in line


def test_a_written_path_holding_a_newline_is_escaped_in_a_one_line_error(capsys, tmp_path):
    path = tmp_path / "two\nlines.csv"
    path.write_text("taken\n")
    line = refused(capsys, "simulate", "--out", path)
    shown = str(path).replace("\n", "\\n")
    assert line == f"jointid: {shown}: already exists; not overwriting it (add --force to replace it)"


def test_any_other_error_text_with_a_newline_is_printed_on_one_line(capsys, tmp_path):
    line = refused(capsys, "fit", "--csv", tmp_path / "train.csv", "--heldout", "two\nlines.bag")
    assert line.startswith("jointid: --heldout two\\nlines.bag: a bag")


# Output that cannot be written --------------------------------------------------------------------------


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full here")
@pytest.mark.parametrize("argv", [["--help"], ["fit", "--help"]])
def test_help_onto_a_full_disk_is_one_line_and_status_2(argv):
    with open("/dev/full", "w") as full:  # every write to it fails with ENOSPC
        done = subprocess.run([sys.executable, "-m", "jointid", *argv], stdout=full, stderr=subprocess.PIPE,
                              text=True, timeout=HANG_LIMIT, check=False)
    assert (done.returncode, done.stderr) == (2, "jointid: cannot write the output: No space left on device\n")
