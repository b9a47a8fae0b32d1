"""A log fit's work is bounded: an automatic choice beyond FIT_BUDGET, or an explicit --decimate beyond the memory
available, is refused in one line that names the decimation that fits; an explicit one the machine can serve is fitted.

A million rows at --decimate 1 once took 12 GB and minutes, ten million a traceback; the mechanism is tested here
at small scale with the budget lowered and the available memory injected (no test allocates gigabytes).
"""

from __future__ import annotations

import io
import json
import re
import threading

import numpy as np
import pytest

from jointid.cli import main
from jointid.cli.progress import elapsed_on_terminal
from jointid.studies.log_fit import FIT_BYTES_PER_SAMPLE
from jointid.model.terms import G

pytestmark = pytest.mark.filterwarnings("error::RuntimeWarning")


def write_log(path, rate=200.0, duration=30.0, jitter=0.0):
    """A noisy log of the lesson's joint, t, q, qd, qdd, tau."""
    rng = np.random.default_rng(8)
    t = np.arange(int(duration * rate) + 1) / rate
    t = t + rng.uniform(-jitter, jitter, t.size) / rate
    q = 0.7 * np.sin(1.3 * t) + 0.25 * np.sin(2.7 * t)
    qd = 0.91 * np.cos(1.3 * t) + 0.675 * np.cos(2.7 * t)
    qdd = -1.183 * np.sin(1.3 * t) - 1.8225 * np.sin(2.7 * t)
    tau = 0.8 * qdd + 0.4 * G * np.cos(q) + 0.15 * qd + rng.normal(0, 0.2, t.size)
    path.write_text("t,q,qd,qdd,tau\n" + "".join(f"{a!r},{b!r},{c!r},{d!r},{e!r}\n" for a, b, c, d, e in
                                                zip(*(map(float, x) for x in (t, q, qd, qdd, tau)))))
    return path


def run(capsys, argv):
    try:
        status = main([str(a) for a in argv])
    except SystemExit as stop:
        status = stop.code
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def available(monkeypatch, size):
    """The machine made to have `size` bytes of memory available (what check_work reads)."""
    monkeypatch.setattr("jointid.studies.log_fit.available_memory", lambda: size)


def test_an_explicit_decimation_the_memory_allows_is_fitted_however_much_work(capsys, tmp_path, monkeypatch):
    path = write_log(tmp_path / "log.csv")
    monkeypatch.setattr("jointid.studies.log_fit.FIT_BUDGET", 300_000)  # the automatic choice's budget, exceeded
    available(monkeypatch, 6_001 * FIT_BYTES_PER_SAMPLE)  # exactly what 6,001 samples need
    status, out, err = run(capsys, ["fit", "--csv", path, "--decimate", "1", "--cutoff", "4", "--json"])
    assert (status, err) == (0, ""), err
    assert json.loads(out)["low_pass"]["decimation"] == 1


def test_an_explicit_decimation_beyond_the_memory_is_one_line_naming_the_least_that_fits(capsys, tmp_path,
                                                                                          monkeypatch):
    path = write_log(tmp_path / "log.csv")
    available(monkeypatch, 2_000 * FIT_BYTES_PER_SAMPLE)  # room for 2,000 of the 6,001 samples
    status, out, err = run(capsys, ["fit", "--csv", path, "--decimate", "1", "--cutoff", "4"])
    assert (status, out) == (2, "") and len(err.splitlines()) == 1, err
    needed, free = 6_001 * FIT_BYTES_PER_SAMPLE / 1e6, 2_000 * FIT_BYTES_PER_SAMPLE / 1e6
    assert f"6,001 samples to fit needs about {needed:.0f} MB of memory and {free:.0f} MB are available" in err, err
    least = int(re.search(r"decimate by ([\d,]+) or more \(--decimate (\d+)\)", err).group(2))
    assert least == 4 and "--train-window START:END" in err  # ceil(6,001 / 4) = 1,501 fit; ceil(6,001 / 3) not
    assert run(capsys, ["fit", "--csv", path, "--decimate", least, "--cutoff", "4", "--json"])[0] == 0
    assert "of memory" in run(capsys, ["fit", "--csv", path, "--decimate", least - 1, "--cutoff", "4"])[2]
    # Every path to a log fit has the same bound: compare, and several runs (--csv twice).
    for command in (["compare"], ["fit", "--csv", path]):
        status, out, err = run(capsys, [*command, "--csv", path, "--decimate", "1", "--cutoff", "4"])
        assert status == 2 and "of memory and" in err, err


def test_an_automatic_choice_beyond_the_budget_names_the_decimation_and_the_memory_of_every_sample(
        capsys, tmp_path, monkeypatch):
    path = write_log(tmp_path / "log.csv")
    monkeypatch.setattr("jointid.studies.log_fit.FIT_BUDGET", 300_000)
    status, out, err = run(capsys, ["fit", "--csv", path, "--cutoff", "0"])  # unfiltered: no decimation chosen
    assert (status, out) == (2, "") and len(err.splitlines()) == 1, err
    assert "6,001 samples to fit are about" in err and "times the work a fit takes on" in err
    least = int(re.search(r"decimate by ([\d,]+) or more \(--decimate (\d+)\)", err).group(2))
    assert least > 1 and f"--decimate 1 fits every sample (about {6_001 * FIT_BYTES_PER_SAMPLE / 1e6:.0f} MB" in err
    available(monkeypatch, 10**12)
    assert run(capsys, ["fit", "--csv", path, "--cutoff", "0", "--decimate", "1", "--json"])[0] == 0


def test_a_long_fit_shows_its_seconds_and_memory_on_a_terminal_and_clears_the_line(monkeypatch):
    ticked = threading.Event()

    class Terminal(io.StringIO):
        def isatty(self):
            return True

        def write(self, text):
            if text.endswith(": 1 s"):
                ticked.set()
            return super().write(text)

    terminal = Terminal()
    monkeypatch.setattr("jointid.cli.progress.FIRST_TICK", 0.0)
    with elapsed_on_terminal("jointid: fitting 6,001 samples (about 5 MB of memory)", terminal):
        assert ticked.wait(30)  # the ticker's first line, written by its own thread
    shown = terminal.getvalue()
    assert shown.startswith("\rjointid: fitting 6,001 samples (about 5 MB of memory): 1 s") and shown.endswith("\r")
    assert shown.rsplit("\r", 2)[-2].strip() == ""  # the line is blanked before the command's output
    piped = io.StringIO()  # not a terminal: nothing at all
    with elapsed_on_terminal("jointid: fitting", piped):
        pass
    assert piped.getvalue() == ""


def test_a_log_that_cannot_be_decimated_is_told_to_fit_a_stretch(capsys, tmp_path, monkeypatch):
    """Uneven times keep the samples as recorded (no filter, no decimation): only a shorter stretch helps."""
    path = write_log(tmp_path / "uneven.csv", jitter=0.3)
    monkeypatch.setattr("jointid.studies.log_fit.FIT_BUDGET", 100_000)
    status, out, err = run(capsys, ["fit", "--csv", path])
    assert status == 2 and "fit a stretch of it (--train-window START:END)" in err and "--decimate" not in err, err


def test_the_budget_takes_the_default_fit_of_a_long_log(capsys, tmp_path):
    """The automatic low-pass keeps about 20 samples per cutoff hertz: far inside the budget."""
    path = write_log(tmp_path / "long.csv", rate=1000.0, duration=60.0)
    assert run(capsys, ["fit", "--csv", path, "--json"])[0] == 0
