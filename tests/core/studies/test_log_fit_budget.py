"""A log fit's work is bounded: beyond FIT_BUDGET it is refused in one line that names the decimation that fits.

A million rows at --decimate 1 took 12 GB and minutes, ten million a traceback; the mechanism is tested here
at small scale with the budget lowered.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from jointid.cli import main
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


def test_work_beyond_the_budget_is_one_line_naming_the_least_decimation_that_fits(capsys, tmp_path, monkeypatch):
    path = write_log(tmp_path / "log.csv")
    monkeypatch.setattr("jointid.studies.log_fit.FIT_BUDGET", 300_000)
    status, out, err = run(capsys, ["fit", "--csv", path, "--decimate", "1", "--cutoff", "4"])
    assert (status, out) == (2, "") and len(err.splitlines()) == 1, err
    assert "6,001 samples to fit are about" in err and "times the work a fit takes on" in err
    least = int(re.search(r"decimate by ([\d,]+) or more \(--decimate (\d+)\)", err).group(2))
    assert least > 1 and "--train-window START:END" in err
    assert run(capsys, ["fit", "--csv", path, "--decimate", least, "--cutoff", "4", "--json"])[0] == 0
    assert "times the work" in run(capsys, ["fit", "--csv", path, "--decimate", least - 1, "--cutoff", "4"])[2]
    # Every path to a log fit has the same bound: compare, and several runs (--csv twice).
    for command in (["compare"], ["fit", "--csv", path]):
        status, out, err = run(capsys, [*command, "--csv", path, "--decimate", "1", "--cutoff", "4"])
        assert status == 2 and "times the work a fit takes on" in err, err


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
