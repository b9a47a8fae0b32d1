"""`jointid watch`: every bad flag, value, file or host is one line and exit status 2 before anything is watched;
--save never replaces a file without --force; one JSON object per refresh on a CSV appended by a writer thread; the
saved log, read back by `jointid fit --csv`, fits to the last refresh's numbers."""

from __future__ import annotations

import pytest
from support.cli_support import refused, run


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
