"""`jointid watch`: every bad flag, value, file or host is one line and exit status 2 before anything is watched;
--save never replaces a file without --force; one JSON object per refresh on a CSV appended by a writer thread; the
saved log, read back by `jointid fit --csv`, fits to the last refresh's numbers."""

from __future__ import annotations

import json
import threading

import numpy as np
import pytest
from support.cli_support import fit_json, refused, run


@pytest.fixture
def in_folder(tmp_path, monkeypatch, capsys):
    """A folder with a finished simulated log, made current."""
    monkeypatch.chdir(tmp_path)
    assert run_ok(["simulate", "--noise", "0.1", "--samples", "400", "--out", "done.csv"])
    capsys.readouterr()
    return tmp_path


def run_ok(argv) -> bool:
    from jointid.cli import main

    return main(argv) == 0


@pytest.mark.parametrize("argv, says", [
    ([], "one of the arguments --csv --nt is required"),
    (["--csv", "done.csv", "--nt", "127.0.0.1"], "not allowed with"),
    (["--nt", "127.0.0.1"], "--nt needs --entry"),
    (["--nt", "127.0.0.1:99999", "--entry", "q=/a,tau=/b"], "port must be a whole number from 1 to 65535"),
    (["--nt", "robot/x", "--entry", "q=/a,tau=/b"], "expected a host name"),
    (["--nt", "[::1", "--entry", "q=/a,tau=/b"], "expected HOST, HOST:PORT"),
    (["--nt", "127.0.0.1", "--entry", "q=/a,tau=/b", "--columns", "t=time"], "--columns: only for --csv"),
    (["--csv", "done.csv", "--entry", "q=/a,tau=/b"], "--entry: only for --nt"),
    (["--csv", "done.csv", "--entry", "nonsense"], "argument --entry"),
    (["--csv", "done.csv", "--refresh", "0"], "argument --refresh"),
    (["--csv", "done.csv", "--refresh", "1000"], "at most 60"),
    (["--csv", "done.csv", "--duration", "-1"], "argument --duration"),
    (["--csv", "done.csv", "--force"], "--force: only with --save"),
    (["--csv", "done.csv", "--save", "done.csv", "--force"], "that is the CSV being watched"),
    (["--csv", "done.csv", "--save", "no/such/folder/x.csv"], "no folder"),
    (["--csv", "done.csv", "--save", "."], "not a regular file"),
    (["--csv", "done.csv", "--effort", "current"], "--effort current needs --kt"),
    (["--csv", "done.csv", "--mechanism", "arm", "--model", "plain"], "a mechanism is a model"),
    (["--csv", "missing.csv"], "missing.csv"),
])
def test_bad_input_is_one_line_and_status_2(capsys, in_folder, argv, says):
    line = refused(capsys, "watch", *argv)
    assert says in line, line


def test_save_over_an_existing_file_is_refused_up_front_and_the_file_kept(capsys, in_folder):
    (in_folder / "kept.csv").write_text("precious\n")
    line = refused(capsys, "watch", "--csv", "done.csv", "--save", "kept.csv", "--duration", "1")
    assert line == "jointid: --save kept.csv: already exists; add --force to replace it"
    assert (in_folder / "kept.csv").read_text() == "precious\n"


def test_help_lists_the_sources_and_the_save(capsys):
    status, out, _ = run(capsys, "watch", "--help")
    assert status == 0
    for flag in ("--csv PATH", "--nt HOST[:PORT]", "--entry MAP", "--refresh HZ", "--duration S", "--save PATH",
                 "--force", "--json-lines", "--motor NAME", "--mechanism"):
        assert flag in out


# ----------------------------------------------------------------------------- with the incremental fit

def needs_watcher():
    """Skip unless livefit's incremental fit (jointid.studies.watch) is in this build."""
    pytest.importorskip("jointid.studies.watch", reason="livefit's Watcher is not merged into this build yet")


def grow(source_path, target_path, lines_at_once: int, started: threading.Event) -> None:
    """Append the source log's lines to the target in bursts, a partial line left hanging between two of them,
    as a bench logger writes."""
    lines = source_path.read_text().splitlines(keepends=True)
    with open(target_path, "w") as out:
        out.write(lines[0])  # the header
        out.flush()
        started.set()
        for start in range(1, len(lines), lines_at_once):
            chunk = "".join(lines[start:start + lines_at_once])
            half = len(chunk) // 2
            out.write(chunk[:half])  # a line cut in two: the watch must wait for its end
            out.flush()
            out.write(chunk[half:])
            out.flush()


def test_json_lines_on_a_growing_csv_and_the_saved_log_fits_to_the_last_refresh(capsys, in_folder):
    needs_watcher()
    started = threading.Event()
    writer = threading.Thread(target=grow, args=(in_folder / "done.csv", in_folder / "growing.csv", 37, started))
    writer.start()
    started.wait()
    status, out, err = run(capsys, "watch", "--csv", "growing.csv", "--duration", "7.9", "--json-lines",
                           "--save", "saved.csv")
    writer.join()
    assert status == 0, err
    objects = [json.loads(line) for line in out.splitlines()]
    *refreshes, closing = objects
    assert refreshes and all(set(r) >= {"elapsed", "received", "verdicts", "verdict_reasons", "parameters"}
                             for r in refreshes)
    assert [r["received"] for r in refreshes] == sorted(r["received"] for r in refreshes)
    last = refreshes[-1]
    assert last["ended"] and closing["stopped_by"] == "source ended"
    saved = closing["saved"]
    assert saved["path"] == "saved.csv" and saved["samples"] == last["received"]
    # What was saved is what was received, and an offline fit of it says what the last refresh said.
    offline = fit_json(capsys, "--csv", "saved.csv")
    assert offline["samples"] == last["fitted"]
    assert offline["verdicts"] == last["verdicts"]
    for name, value in last["estimate"].items():
        assert value == pytest.approx(offline["estimate"][name], rel=1e-6, abs=1e-9 * abs(value) + 1e-12)


def test_text_lines_end_with_what_was_written(capsys, in_folder):
    needs_watcher()
    status, out, err = run(capsys, "watch", "--csv", "done.csv", "--duration", "5", "--save", "five.csv")
    assert status == 0, err
    lines = out.splitlines()
    assert lines[-1].startswith("Wrote ") and "five.csv" in lines[-1]
    assert lines[0].startswith(("0.", "1.", "2.", "3.", "4.", "5.")) and " received, " in lines[0]
    saved = np.loadtxt(in_folder / "five.csv", delimiter=",", skiprows=1)
    original = np.loadtxt(in_folder / "done.csv", delimiter=",", skiprows=2)
    assert np.array_equal(saved[:, 0], original[:len(saved), 0]) and saved[-1, 0] <= 5.0
