"""Running `jointid ARGV` in the test's own process, as the command-line tests do."""

from __future__ import annotations

import json

from jointid.cli import main


def run(capsys, *argv):
    """(exit status, stdout, stderr) of `jointid ARGV` in this process; argparse's refusals included."""
    try:
        status = main([str(word) for word in argv])
    except SystemExit as stop:  # argparse's own refusals end with SystemExit
        status = stop.code
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def fit_json(capsys, *argv) -> dict:
    """The document `jointid fit ARGV --json` prints, which must succeed without a word on stderr."""
    status, out, err = run(capsys, "fit", *argv, "--json")
    assert (status, err) == (0, ""), err
    return json.loads(out)


def refused(capsys, *argv) -> str:
    """The one line of a refusal: exit 2, nothing on stdout, no traceback."""
    status, out, err = run(capsys, *argv)
    assert status == 2 and out == "", (status, out, err)
    assert err.count("\n") == 1 and "Traceback" not in err and err.startswith("jointid"), err
    return err.strip()
