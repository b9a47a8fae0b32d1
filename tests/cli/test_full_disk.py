"""Exports and simulated logs onto a full disk or a read-only folder: one line, nothing half-written.

A small tmpfs would need a root mount, so a full disk is injected: files opened
through `os.fdopen` for this module's temporaries get a raw file that accepts a
budget of bytes, then fails with ENOSPC as the kernel would (through Python's own
buffered and text layers, so the error surfaces wherever a real one would: on a
write, a flush or the close). A read-only folder is `chmod 0o500`, unless the
tests run as root, who may write there anyway; then creating files in it is made
to fail with EACCES instead.
"""

from __future__ import annotations

import asyncio
import errno
import io
import json
import os
import signal
import stat
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
from support.tui_support import make_app
from textual.widgets import Input

from jointid.cli import main
from jointid.files import TEMPORARY_SUFFIX, ExportError, atomic_output, write_json, write_text, write_texts
from tui.screens.export import write_export
from tui.screens.main import MainScreen

ROOT = Path(__file__).resolve().parents[2]


class FullDisk:
    """Stand-in for os.fdopen: this module's temporaries accept `room` bytes in all, then fail with ENOSPC."""

    def __init__(self, room: int) -> None:
        self.room = room
        self.real_fdopen = os.fdopen
        self.refused = 0

    def fdopen(self, fd, mode="r", buffering=-1, encoding=None, errors=None, newline=None, closefd=True):
        if not os.readlink(f"/proc/self/fd/{fd}").endswith(TEMPORARY_SUFFIX) or "w" not in mode:
            return self.real_fdopen(fd, mode, buffering, encoding, errors, newline, closefd)
        disk = self

        class NearlyFullFile(io.FileIO):
            def write(self, data) -> int:
                data = bytes(data)
                if disk.room <= 0:
                    disk.refused += 1
                    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
                part = data[:disk.room]  # a short write first, as the kernel does at the last block
                disk.room -= len(part)
                return super().write(part)

        raw = NearlyFullFile(fd, "w", closefd=closefd)
        return io.TextIOWrapper(io.BufferedWriter(raw), encoding=encoding, errors=errors, newline=newline)


@pytest.fixture
def full_disk(monkeypatch):
    """Make the disk full after a given number of bytes: full_disk(room) -> the FullDisk."""

    def install(room: int) -> FullDisk:
        disk = FullDisk(room)
        monkeypatch.setattr(os, "fdopen", disk.fdopen)
        return disk

    return install


@pytest.fixture
def read_only_folder(tmp_path, monkeypatch):
    """A folder no file can be created in: chmod 0o500, or (as root, who may write anyway) EACCES injected."""
    folder = tmp_path / "read-only"
    folder.mkdir()
    folder.chmod(0o500)
    probe = folder / "probe"
    try:
        probe.write_text("x")
    except PermissionError:
        pass  # the mode is honoured: nothing to inject
    else:
        probe.unlink()
        real_open = os.open

        def refuse_inside(path, flags, mode=0o777, *, dir_fd=None):
            if Path(os.fspath(path)).parent == folder and flags & os.O_CREAT:
                raise PermissionError(errno.EACCES, os.strerror(errno.EACCES), os.fspath(path))
            return real_open(path, flags, mode, dir_fd=dir_fd)

        monkeypatch.setattr(os, "open", refuse_inside)
    yield folder
    folder.chmod(0o700)


def names(folder: Path) -> list[str]:
    """Every entry of a folder, hidden temporaries included."""
    return sorted(os.listdir(folder))


def one_line(text: str) -> bool:
    return text.count("\n") <= 1 and "Traceback" not in text


# --- the core: atomic files and pairs ---------------------------------------------------


def test_a_full_disk_is_one_export_error_and_leaves_nothing(tmp_path, full_disk):
    disk = full_disk(100)
    with pytest.raises(ExportError) as caught:
        write_text(tmp_path / "big.txt", "x" * 100_000)
    assert disk.refused > 0
    assert str(caught.value) == f"{tmp_path / 'big.txt'}: cannot write: No space left on device"
    assert names(tmp_path) == []


def test_a_full_disk_showing_only_when_the_buffer_is_flushed_is_caught_too(tmp_path, full_disk):
    full_disk(10)
    with pytest.raises(ExportError, match="No space left"):
        write_text(tmp_path / "small.txt", "twenty bytes of text")  # fits the buffer; fails at flush
    assert names(tmp_path) == []


def test_a_pair_whose_second_file_meets_the_full_disk_leaves_neither(tmp_path, full_disk):
    full_disk(5_000)  # room for the first file, not for the second
    with pytest.raises(ExportError):
        write_texts({tmp_path / "a.json": "{}\n" * 1000, tmp_path / "a.svg": "<svg/>" * 10_000})
    assert names(tmp_path) == []


def test_a_pair_is_refused_whole_when_its_second_name_is_taken(tmp_path):
    (tmp_path / "a.svg").write_text("theirs")
    with pytest.raises(ExportError, match="already exists"):
        write_texts({tmp_path / "a.json": "ours", tmp_path / "a.svg": "ours"})
    assert names(tmp_path) == ["a.svg"] and (tmp_path / "a.svg").read_text() == "theirs"


def test_a_read_only_folder_is_one_export_error(read_only_folder):
    with pytest.raises(ExportError) as caught:
        write_json(read_only_folder / "fit.json", {"I": 0.8})
    assert str(caught.value) == f"{read_only_folder / 'fit.json'}: cannot write: Permission denied"
    assert names(read_only_folder) == []


@pytest.mark.parametrize("umask, mode", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
def test_new_files_get_the_mode_the_umask_gives(tmp_path, umask, mode):
    old = os.umask(umask)
    try:
        write_text(tmp_path / "a.txt", "x")
        with atomic_output(tmp_path / "b.txt", overwrite=True) as handle:
            handle.write("y")
    finally:
        os.umask(old)
    for name in ("a.txt", "b.txt"):
        assert stat.S_IMODE((tmp_path / name).stat().st_mode) == mode


def test_a_temporary_left_by_a_killed_simulate_is_removed_by_the_next_write(tmp_path):
    """kill -9 during a large `jointid simulate` left its 32 MB temporary file behind for good."""
    big = tmp_path / "big.csv"
    writer = subprocess.Popen([sys.executable, "-m", "jointid", "simulate", "--samples", "3000000",
                               "--out", str(big)], cwd=ROOT, stdout=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:  # until it is half-way through writing
            parts = [p for p in tmp_path.iterdir() if p.name.endswith(TEMPORARY_SUFFIX)]
            if parts and parts[0].stat().st_size > 1_000_000:
                break
            time.sleep(0.01)
    finally:
        writer.send_signal(signal.SIGKILL)
        writer.wait()
    left = names(tmp_path)
    assert len(left) == 1 and left[0].startswith(".jointid.") and left[0].endswith(TEMPORARY_SUFFIX), left
    # A live writer's temporary is not touched.
    live = tmp_path / f".jointid.{os.getpid()}-0123abcd-0{TEMPORARY_SUFFIX}"
    live.write_text("in progress")
    assert main(["simulate", "--out", str(big)]) == 0
    assert names(tmp_path) == sorted(["big.csv", live.name])


def test_odd_names_in_the_output_folder_do_not_stop_a_write(tmp_path, capsys):
    """A stray temporary-like name with a 20-digit process id made every write fail ("not a finite number"), and
    a legal 254-character name failed ("File name too long": its temporary was longer)."""
    stray = tmp_path / ".a.99999999999999999999-deadbeef.jointid-part"
    stray.write_text("")
    longest = "r" * (os.pathconf(tmp_path, "PC_NAME_MAX") - 5) + ".csv"
    for name in ("run.csv", longest):
        assert main(["simulate", "--out", str(tmp_path / name)]) == 0, capsys.readouterr().err
    assert names(tmp_path) == sorted([stray.name, "run.csv", longest])


# --- jointid simulate ------------------------------------------------------------------------


def test_simulate_onto_a_full_disk_is_one_line_and_status_2(tmp_path, full_disk, capsys):
    full_disk(64 * 1024)
    out = tmp_path / "big.csv"
    assert main(["simulate", "--samples", "100000", "--out", str(out)]) == 2
    captured = capsys.readouterr()
    assert captured.err == f"jointid: {out}: cannot write: No space left on device\n"
    assert captured.out == ""
    assert names(tmp_path) == []


def test_simulate_into_a_read_only_folder_is_one_line_and_status_2(read_only_folder, capsys):
    out = read_only_folder / "log.csv"
    assert main(["simulate", "--out", str(out)]) == 2
    captured = capsys.readouterr()
    assert captured.err == f"jointid: {out}: cannot write: Permission denied\n"
    assert names(read_only_folder) == []


def test_simulate_onto_a_full_disk_in_a_fresh_process_prints_no_traceback(tmp_path):
    """The whole command, as a user runs it: a real write error (a file-size limit stands in for the disk)."""
    script = textwrap.dedent(f"""
        import resource, signal, sys
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # so the write fails with EFBIG instead of killing us
        resource.setrlimit(resource.RLIMIT_FSIZE, (65536, 65536))
        from jointid.cli import main
        sys.exit(main(["simulate", "--samples", "100000", "--out", {str(tmp_path / 'big.csv')!r}]))
    """)
    done = subprocess.run([sys.executable, "-c", script], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert done.returncode == 2
    assert done.stderr == f"jointid: {tmp_path / 'big.csv'}: cannot write: File too large\n"
    assert names(tmp_path) == []


# --- the explorer's Ctrl+S ---------------------------------------------------------------


def test_the_export_pair_onto_a_full_disk_writes_neither(tmp_path, full_disk):
    full_disk(2_000)  # the JSON fits, the SVG does not
    with pytest.raises(ExportError, match="No space left on device"):
        write_export(tmp_path, "train-fit", {"I": 0.8}, "<svg>" + "x" * 100_000 + "</svg>")
    assert names(tmp_path) == []


def test_a_dangling_symlink_makes_the_export_take_the_next_free_name(tmp_path):
    (tmp_path / "x-fit.json").symlink_to(tmp_path / "nowhere")
    json_path, svg_path = write_export(tmp_path, "x-fit", {"I": 0.8}, "<svg/>")
    assert (json_path.name, svg_path.name) == ("x-fit-2.json", "x-fit-2.svg")
    assert (tmp_path / "x-fit.json").is_symlink() and not (tmp_path / "nowhere").exists()


@pytest.mark.parametrize("folder, message", [
    ("missing", "{folder}: no such folder"),
    ("a-file", "{folder}: not a folder"),
])
def test_a_missing_folder_and_a_file_are_told_apart(tmp_path, folder, message):
    (tmp_path / "a-file").write_text("x")
    with pytest.raises(ExportError) as caught:
        write_export(tmp_path / folder, "x-fit", {}, "<svg/>")
    assert str(caught.value) == message.format(folder=tmp_path / folder)


async def press_ctrl_s_into(folder: Path) -> tuple[list, list]:
    """Export from a fresh explorer into a folder; the notifications and the app's screens afterwards."""
    app = make_app()
    async with app.run_test(size=(80, 24)) as pilot:
        await pilot.pause()
        await pilot.press("ctrl+s")
        pilot.app.screen.query_one("#export-folder", Input).value = str(folder)
        await pilot.press("enter")
        await pilot.pause()
        notifications = [(n.title, n.message, n.severity) for n in app._notifications]
        screens = [type(screen) for screen in app.screen_stack]
    return notifications, screens


def test_ctrl_s_onto_a_full_disk_is_a_notification_and_no_half_pair(tmp_path, full_disk):
    full_disk(3_000)  # the fit's JSON fits, the screenshot does not
    notifications, screens = asyncio.run(press_ctrl_s_into(tmp_path))
    assert screens[-1] is MainScreen  # still running, back on the explorer
    (title, message, severity), = notifications
    assert (title, severity) == ("Nothing exported", "error")
    assert message.endswith(": cannot write: No space left on device") and "\n" not in message
    assert names(tmp_path) == []


def test_ctrl_s_into_a_read_only_folder_is_a_notification(read_only_folder):
    notifications, screens = asyncio.run(press_ctrl_s_into(read_only_folder))
    assert screens[-1] is MainScreen
    (title, message, severity), = notifications
    assert (title, severity) == ("Nothing exported", "error")
    assert message.endswith(": cannot write: Permission denied")
    assert names(read_only_folder) == []


def test_ctrl_s_writes_the_pair_with_the_umasks_mode(tmp_path):
    old = os.umask(0o022)
    try:
        notifications, _ = asyncio.run(press_ctrl_s_into(tmp_path))
    finally:
        os.umask(old)
    assert notifications[0][0] == "Exported"
    assert names(tmp_path) == ["jointid-rich-0.00-24-7.json", "jointid-rich-0.00-24-7.svg"]
    assert {stat.S_IMODE(path.stat().st_mode) for path in tmp_path.iterdir()} == {0o644}
    json.loads((tmp_path / "jointid-rich-0.00-24-7.json").read_text())
