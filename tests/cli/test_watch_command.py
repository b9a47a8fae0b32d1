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


def numeric_rows(path) -> np.ndarray:
    """The rows of a CSV log as numbers: comment lines and the header row left out."""
    lines = [line for line in path.read_text().splitlines() if line and not line.startswith("#")]
    return np.loadtxt(lines[1:], delimiter=",", ndmin=2)


def run_ok(argv) -> bool:
    from jointid.cli import main

    return main(argv) == 0


@pytest.mark.parametrize("argv, says", [
    ([], "one of the arguments --csv --nt is required"),
    (["--csv", "done.csv", "--nt", "127.0.0.1"], "not allowed with"),
    (["--nt", "127.0.0.1"], "--nt needs --entry"),
    (["--nt", "127.0.0.1:99999", "--entry", "q=/a,tau=/b"], "is not a number from 1 to 65535"),
    (["--nt", ":5810", "--entry", "q=/a,tau=/b"], "give the server's HOST[:PORT]"),
    (["--nt", "127.0.0.1", "--entry", "qd=/a"], "no topic for tau"),
    (["--csv", "done.csv", "--gone", "3"], "--gone: only for --nt"),
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
    (["--csv", "done.csv", "--motor", "NEO"], "--motor: while watching, only to turn the fit into --gains wpilib"),
    (["--csv", "done.csv", "--gains", "wpilib"], "--gains wpilib needs volts"),
    (["--csv", "done.csv", "--gains", "wpilib", "--motor", "NoSuchMotor"], "--motor:"),
    (["--csv", "done.csv", "--constrained"], "--constrained: not while watching"),
    (["--csv", "done.csv", "--motor-inertia", "1e-4"], "--motor-inertia: not while watching"),
])
def test_bad_input_is_one_line_and_status_2(capsys, in_folder, argv, says):
    # A --duration first (the case's own comes later and wins), so a case that were not refused would end.
    line = refused(capsys, "watch", "--duration", "5", *argv)
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


class RefreshWatch:
    """Counts the samples each refresh of the watch had received (wrapping WatchSession._refresh), so a writer can
    wait until its burst was read before it writes the next: a bench logger paced by the watch, not by a clock."""

    def __init__(self, monkeypatch) -> None:
        from jointid.studies import watch_session

        self.received = 0
        self.ended = False
        self.changed = threading.Condition()
        original = watch_session.WatchSession._refresh

        def counted(session, blocks, on_refresh):
            original(session, blocks, on_refresh)
            with self.changed:
                self.received, self.ended = session.last.received, session.last.ended
                self.changed.notify_all()

        monkeypatch.setattr(watch_session.WatchSession, "_refresh", counted)

    def wait_for(self, count: int) -> None:
        """Until a refresh has received `count` samples or the watch ended (--duration); 10 s at most: a watch that
        stalls fails the test."""
        with self.changed:
            assert self.changed.wait_for(lambda: self.received >= count or self.ended, timeout=10), (self.received,
                                                                                                 count)


def grow(source_path, target_path, burst: int, refreshes: RefreshWatch) -> None:
    """Append the source log's lines to the target a burst at a time, each burst's middle line cut in two by a
    flush (the watch must wait for its end), the next burst only once a refresh has read this one."""
    comment, header, *rows = source_path.read_text().splitlines(keepends=True)
    with open(target_path, "a") as out:
        for start in range(0, len(rows), burst):
            chunk = "".join(rows[start:start + burst])
            half = len(chunk) // 2
            out.write(chunk[:half])
            out.flush()
            out.write(chunk[half:])
            out.flush()
            refreshes.wait_for(min(start + burst, len(rows)))


def test_json_lines_on_a_growing_csv_and_the_saved_log_fits_to_the_last_refresh(capsys, in_folder, monkeypatch):
    needs_watcher()
    assert run_ok(["simulate", "--noise", "0.1", "--rate", "50", "--duration", "40", "--true-coulomb", "0.2",
                   "--out", "arm.csv"])
    capsys.readouterr()
    comment, header = (in_folder / "arm.csv").read_text().splitlines(keepends=True)[:2]
    (in_folder / "growing.csv").write_text(comment + header)
    refreshes = RefreshWatch(monkeypatch)
    writer = threading.Thread(target=grow, args=(in_folder / "arm.csv", in_folder / "growing.csv", 250, refreshes),
                              daemon=True)
    writer.start()
    status, out, err = run(capsys, "watch", "--csv", "growing.csv", "--duration", "39.9", "--refresh", "20",
                           "--json-lines", "--save", "saved.csv")
    writer.join(timeout=10)
    assert status == 0, err
    assert not writer.is_alive()
    *objects, closing = [json.loads(line) for line in out.splitlines()]
    assert all(set(o) >= {"elapsed", "received", "estimate", "verdicts", "verdict_reasons", "parameters", "events"}
               for o in objects)
    received = [o["received"] for o in objects]
    assert received == sorted(received) and len(set(received)) >= 6  # a refresh after each burst at least
    last = objects[-1]
    assert last["ended"] and not any(o["ended"] for o in objects[:-1])
    assert closing == {"stopped_by": "source ended", "saved": {"path": "saved.csv", "samples": last["received"]},
                       "not_saved": None}
    # The saved log holds exactly the samples received, as they were written.
    saved = numeric_rows(in_folder / "saved.csv")
    original = numeric_rows(in_folder / "arm.csv")
    assert len(saved) == last["received"] and np.array_equal(saved, original[:len(saved)])
    # Watching converged on the simulated joint's own truth (simulate's lesson joint with Coulomb friction 0.2),
    # within three of the last refresh's errors, over several fitted refreshes.
    fitted = [o for o in objects if o["estimate"] is not None]
    assert len(fitted) >= 3
    for name, truth in {"I": 0.8, "h": 0.4, "B": 0.15, "Fc": 0.2}.items():
        assert abs(last["estimate"][name] - truth) <= 3 * last["std_error"][name], name
    # An offline fit of the saved log gives the last refresh's numbers at the precision they have: the live fit
    # filters in blocks and leaves out its warm-up, so the samples behind the two differ a little, and the two
    # agree within the 95 % band of the live standard error (they differ by 0.3 to 1.4 of it here).
    offline = fit_json(capsys, "--csv", "saved.csv")
    for name, value in last["estimate"].items():
        assert abs(value - offline["estimate"][name]) <= 1.96 * last["std_error"][name], name
    assert set(offline["verdicts"]) == set(last["verdicts"])


def test_text_lines_end_with_what_was_written(capsys, in_folder):
    needs_watcher()
    status, out, err = run(capsys, "watch", "--csv", "done.csv", "--duration", "5", "--save", "five.csv")
    assert status == 0, err
    lines = out.splitlines()
    assert lines[-1].startswith("Wrote ") and "five.csv" in lines[-1]
    assert lines[0].startswith(("0.", "1.", "2.", "3.", "4.", "5.")) and " received, " in lines[0]
    saved = numeric_rows(in_folder / "five.csv")
    original = numeric_rows(in_folder / "done.csv")
    assert np.array_equal(saved[:, 0], original[:len(saved), 0]) and saved[-1, 0] <= 5.0


def test_ctrl_c_stops_the_watch_and_saves_what_arrived(in_folder):
    needs_watcher()
    import signal
    import subprocess
    import sys

    (in_folder / "still.csv").write_text((in_folder / "done.csv").read_text())  # complete, but nobody ends it
    watch = subprocess.Popen([sys.executable, "-m", "jointid", "watch", "--csv", "still.csv", "--save", "kept.csv"],
                             cwd=in_folder, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True)
    try:
        first = watch.stdout.readline()  # the first refresh: it is watching
        assert " received, " in first, first + watch.stderr.read()
        watch.send_signal(signal.SIGINT)
        rest, err = watch.communicate(timeout=30)
    finally:
        watch.kill()
    assert watch.returncode == 130, err
    assert "Traceback" not in err and err == ""
    assert rest.splitlines()[-1] == "Wrote 400 samples to kept.csv (jointid fit --csv kept.csv fits them)."
    saved = numeric_rows(in_folder / "kept.csv")
    original = numeric_rows(in_folder / "done.csv")
    assert np.array_equal(saved, original)


def test_a_50_hz_arm_over_networktables_on_loopback_converges_and_is_saved(capsys, tmp_path, monkeypatch):
    needs_watcher()
    pytest.importorskip("ntcore")
    import contextlib
    import io

    from support.nt_publishers import LoopbackServer, wait_until
    from support.watched_joints import arm

    from jointid.cli import main

    monkeypatch.chdir(tmp_path)
    run_ = arm(rate=50.0, seconds=60.0)
    server = LoopbackServer(tmp_path)
    topics = {"/Arm/Position": "double", "/Arm/Torque": "double"}
    server.publish_topics(topics)
    out, err, status = io.StringIO(), io.StringIO(), []

    def watch():
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            status.append(main(["watch", "--nt", server.address, "--entry", "q=/Arm/Position,tau=/Arm/Torque",
                                "--duration", "59", "--json-lines", "--save", "nt.csv"]))

    watcher = threading.Thread(target=watch)
    try:
        watcher.start()
        wait_until(lambda: all(server.subscribed(name) for name in topics), what="the watch's subscriptions")
        server.stream(dict(zip(topics, (run_.q, run_.tau))), run_.t, speedup=20.0)
        watcher.join(timeout=60)
    finally:
        server.stop()
    assert not watcher.is_alive() and status == [0], err.getvalue()
    *objects, closing = [json.loads(line) for line in out.getvalue().splitlines()]
    last = objects[-1]
    assert len(objects) >= 3 and last["ended"] and closing["stopped_by"] == "source ended"
    assert f"connected to {server.address}" in last["events"]
    # Within 5 % of the simulation's own truth (not jointid's), or within three of its standard errors where 5 % is
    # tighter than what 60 s of this noise determine: tau0's error is 2.5-3.2 % of itself, and the blocks the
    # values arrive in (timing on loopback) move it by about one error (0.2065 to 0.2124 seen).
    for name, truth in run_.truth.items():
        estimate, error = last["estimate"][name], last["std_error"][name]
        assert abs(estimate - truth) <= max(0.05 * abs(truth), 3 * error), (name, estimate, error, truth)
        assert last["verdicts"][name] == "well determined"
        assert last["parameters"][name]["determined_at"] <= last["elapsed"]
    # Determined no earlier than the data allow: at its moment, its error was within the 'well determined' limit.
    assert all(p["determined_pct"] <= 10.0 for p in last["parameters"].values())
    saved = numeric_rows(tmp_path / "nt.csv")
    assert closing["saved"] == {"path": "nt.csv", "samples": len(saved)} and len(saved) == last["received"]
    np.testing.assert_array_equal(saved[:, 1], run_.q[:len(saved)])  # q as published, in radians
    offline = fit_json(capsys, "--csv", "nt.csv")
    for name, value in last["estimate"].items():  # the same samples: within the live error's 99.7 % band
        assert abs(value - offline["estimate"][name]) <= 3 * last["std_error"][name], name


def test_a_csv_whose_header_cannot_be_read_is_its_one_line_and_nothing_else(capsys, in_folder):
    needs_watcher()
    (in_folder / "notau.csv").write_text("t,q\n0,1\n")
    assert refused(capsys, "watch", "--csv", "notau.csv", "--duration", "5", "--save", "never.csv") == (
        "jointid: notau.csv, row 1: missing required column 'tau' in the header")
    assert not (in_folder / "never.csv").exists()


def test_a_csv_that_never_grows_ends_at_the_duration_with_nothing_to_save(capsys, in_folder):
    needs_watcher()
    (in_folder / "empty.csv").write_text("")
    status, out, err = run(capsys, "watch", "--csv", "empty.csv", "--duration", "0.3", "--json-lines",
                           "--save", "never.csv")
    assert (status, err) == (0, "")
    *refreshes, closing = [json.loads(line) for line in out.splitlines()]
    assert refreshes[-1]["received"] == 0 and refreshes[-1]["ended"]
    assert closing == {"stopped_by": "duration", "saved": None, "not_saved": "no sample was received"}
    assert sorted(path.name for path in in_folder.iterdir()) == ["done.csv", "empty.csv"]  # no temporary left


def write_sysid_flywheel(folder) -> None:
    """fly.csv: a flywheel's SysId routine (50 Hz, 40 s, four 10 s tests named in a state column), volts in tau."""
    from support.watched_joints import flywheel

    run_ = flywheel(50.0, 40.0)
    tests = ["quasistatic-forward", "quasistatic-reverse", "dynamic-forward", "dynamic-reverse"]
    rows = (f"{t!r},{q!r},{v!r},{tests[min(int(t // 10), 3)]}"
            for t, q, v in zip(run_.t.tolist(), run_.q.tolist(), run_.tau.tolist()))
    (folder / "fly.csv").write_text("t,q,tau,state\n" + "\n".join(rows) + "\n")


def test_gains_wpilib_end_a_sysid_watch_with_the_last_fit_as_a_controller_takes_it(capsys, tmp_path, monkeypatch):
    needs_watcher()
    monkeypatch.chdir(tmp_path)
    write_sysid_flywheel(tmp_path)
    argv = ["watch", "--csv", "fly.csv", "--effort", "voltage", "--mechanism", "simple", "--duration", "39.9",
            "--gains", "wpilib"]
    status, out, err = run(capsys, *argv, "--json-lines")
    assert (status, err) == (0, "")
    *objects, closing = [json.loads(line) for line in out.splitlines()]
    last = objects[-1]
    assert dict(last["tests"]) == pytest.approx({"quasistatic-forward": 10.0, "quasistatic-reverse": 10.0,
                                                 "dynamic-forward": 10.0, "dynamic-reverse": 9.9}, abs=0.05)
    gains = closing["gains"]
    assert gains["feedforward"] == "SimpleMotorFeedforward"
    for name in ("kS", "kV", "kA"):  # a voltage fit's gains are its own parameters, per radian
        assert gains["gains"][name]["value"] == last["estimate"][name]
        assert gains["gains"][name]["verdict"] == last["verdicts"][name]
    status, out, err = run(capsys, *argv)
    assert status == 0 and "Java:   new SimpleMotorFeedforward(" in out
    assert out.splitlines()[-1] == "Nothing saved: no --save PATH given."
