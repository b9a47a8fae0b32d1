"""`jointid design` refuses work over its budget in one line naming what to lower, and shows progress on a terminal.

The budget is lowered here so the refusals and the designs they suggest run in well under a second.
"""

from __future__ import annotations

import re

import pytest

from jointid.cli import main
from jointid.studies import design

SMALL = ["--starts", "4", "--harmonics", "3", "--samples", "2000"]


def run(capsys, *argv):
    try:
        status = main(list(argv))
    except SystemExit as stop:
        status = stop.code
    out, err = capsys.readouterr()
    return status, out, err


def test_a_design_over_the_budget_is_one_line_naming_the_flags_and_never_starts(capsys, monkeypatch):
    monkeypatch.setattr(design, "DESIGN_BUDGET_SECONDS", 0.1)
    monkeypatch.setattr(design, "design_motion", lambda *a, **k: pytest.fail("a refused design was started"))
    status, out, err = run(capsys, "design", *SMALL)
    assert status == 2 and out == "" and err.count("\n") == 1, err
    assert err.startswith("jointid: a design of 4 starts x 3 harmonics x 2,000 samples for the 3-parameter plain "
                          "model is about "), err
    assert "over the 0.1 s budget; lower --samples, --harmonics or --starts (" in err
    assert re.search(r"--samples \d+", err) and re.search(r"--starts \d+", err), err


def test_each_suggested_value_fits_the_budget(capsys, monkeypatch):
    monkeypatch.setattr(design, "DESIGN_BUDGET_SECONDS", 0.1)
    _, _, err = run(capsys, "design", *SMALL)
    suggestions = re.findall(r"(--samples|--harmonics|--starts) (\d+)", err.split("(", 1)[1])
    assert suggestions, err
    for flag, value in suggestions:
        argv = list(SMALL)
        argv[argv.index(flag) + 1] = value
        status, _, err = run(capsys, "design", *argv, "--json")
        assert status == 0, (flag, value, err)


def test_the_issues_designs_are_refused_at_the_real_budget(capsys, monkeypatch):
    monkeypatch.setattr(design, "design_motion", lambda *a, **k: pytest.fail("a refused design was started"))
    for argv, flag in ((["--starts", "1000", "--harmonics", "10"], "--starts"), (["--samples", "10000000"], "--samples")):
        status, out, err = run(capsys, "design", *argv)
        assert status == 2 and err.count("\n") == 1 and f"{flag} " in err and "30 s budget" in err, err


def test_a_long_design_shows_its_starts_on_a_terminal_and_clears_the_line(capsys, monkeypatch):
    from jointid.cli import design_command

    monkeypatch.setattr(design_command, "PROGRESS_SECONDS", 0.0)
    monkeypatch.setattr(design_command.sys.stderr, "isatty", lambda: True)
    status, out, err = run(capsys, "design", "--starts", "2", "--json")
    assert status == 0 and out.startswith("{")
    assert "\rjointid design: start 1 of 2 done" in err and "start 2 of 2 done" in err and err.endswith("\r\033[K")
