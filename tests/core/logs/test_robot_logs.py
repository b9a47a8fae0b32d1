"""Acceptance on logs as robots record them: jittered stamps, 12-bit encoder angles, noisy torque, 50 Hz to 1 kHz.

The logs are generated here from the lesson's joint in closed form, independent
of jointid: q = 0.7 sin(1.3 t) + 0.25 sin(2.7 t) with its exact derivatives,
tau = I qdd + h g cos q + B qd with I = 0.8, h = 0.4, B = 0.15, g = 9.81.
Each sample is taken at a jittered instant (the stamp is the true instant,
off its nominal tick by up to +-10 % of a step), the angle is quantised to
4096 counts per turn, and the torque gets Gaussian noise with a standard
deviation of 10 % of the torque's RMS. Fits use jointid's defaults only.
"""

from __future__ import annotations

import json
import re

import pytest
from support.robot_logs import TRUE, robot_log, write_log

from jointid.cli import main


def fit_document(capsys, path, *options) -> dict:
    """`jointid fit --csv PATH --json OPTIONS`, parsed."""
    capsys.readouterr()
    assert main(["fit", "--csv", str(path), "--json", *options]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("rate", [50, 300, 1000])
def test_defaults_recover_the_joint_at_every_rate_and_the_sensitivity_check_stays_quiet(capsys, tmp_path, rate):
    document = fit_document(capsys, write_log(tmp_path / f"robot_{rate}.csv", robot_log(rate)))
    assert document["timing"]["resampled"] and 0.05 < document["timing"]["max_jitter"] <= 0.2
    for name, true in TRUE.items():
        estimate, error = document["estimate"][name], document["std_error"][name]
        assert abs(estimate - true) <= max(0.03 * true, 3 * error), (name, estimate, error)
    assert document["derivatives"]["window_chosen"] == "automatic"
    assert document["low_pass"]["cutoff_hz"] is not None
    assert document["sensitivity"]["flagged"] is False
    assert not any(document["sensitivity"]["flags"].values())


def test_the_automatic_window_spans_about_the_same_time_at_every_rate(capsys, tmp_path):
    spans = []
    for rate in (50, 300, 1000):
        document = fit_document(capsys, write_log(tmp_path / f"robot_{rate}.csv", robot_log(rate)))
        derivatives = document["derivatives"]
        spans.append((derivatives["window"] - 1) * derivatives["step"])
    # In samples the windows differ twentyfold; in time they stay within a factor 1.5 of each other, and
    # under 0.92 periods of the motion's band (0.5 Hz here), where the order-6 filter starts to flatten it.
    assert max(spans) / min(spans) < 1.5 and max(spans) < 0.92 / 0.5, spans


def test_a_deliberately_high_cutoff_biases_inertia_low_and_raises_the_sensitivity_flag(capsys, tmp_path):
    """20 Hz at 300 Hz lets 12-bit quantisation, twice differenced, into qdd: noise in the inertia's column pulls I
    low (errors in variables), and halving or doubling the cutoff moves it far: the check says so."""
    path = write_log(tmp_path / "robot_300.csv", robot_log(300))
    document = fit_document(capsys, path, "--cutoff", "20", "--model", "plain")
    assert document["estimate"]["I"] < 0.9 * TRUE["I"]
    sensitivity = document["sensitivity"]
    assert sensitivity["flagged"] is True and sensitivity["flags"]["I"] is True
    assert sensitivity["largest_move_std_errors"]["I"] > 2
    cutoffs = [s["cutoff_hz"] for s in sensitivity["settings"] if s["setting"] in (None, "cutoff")]
    assert cutoffs == [20.0, 10.0, 40.0]
    # The move is what the refits gave, in the chosen fit's standard errors.
    base = sensitivity["settings"][0]["estimate"]["I"]
    moves = [abs(s["estimate"]["I"] - base) / sensitivity["std_error"]["I"] for s in sensitivity["settings"][1:]]
    assert max(moves) == pytest.approx(sensitivity["largest_move_std_errors"]["I"], rel=1e-9)
    capsys.readouterr()
    assert main(["fit", "--csv", str(path), "--cutoff", "20", "--model", "plain"]) == 0
    text = capsys.readouterr().out
    assert re.search(r"Your derivative settings decide this estimate: with the (cutoff|window) \w+ \([^)]*\), "
                     r"I moves \d+\.\d\d noise standard errors", text)
    line = next(line for line in text.splitlines() if line.startswith("I (kg m²)"))
    # The cutoff's move widens I's error to cover the truth its bias misses: no longer called well determined.
    assert "error widened from" in line and "by the cutoff's choice" in line and "well determined" not in line
    assert document["std_error"]["I"] > 0.1 * max(abs(s["estimate"]["I"] - base) for s in sensitivity["settings"])
    assert abs(document["estimate"]["I"] - TRUE["I"]) < 2 * document["std_error"]["I"]


def test_the_text_output_states_what_was_chosen_and_why(capsys, tmp_path):
    path = write_log(tmp_path / "robot_50.csv", robot_log(50))
    capsys.readouterr()
    assert main(["fit", "--csv", str(path)]) == 0
    out = capsys.readouterr().out
    assert "resampled by cubic spline interpolation onto a uniform" in out
    assert "automatic: its -3 dB point near 3 x the cutoff" in out
    assert "low-passed alike at" in out and "below which 95% of the motion's power lies" in out
    assert "Sensitivity check (window" in out and "each halved and doubled" in out
    assert "Your derivative settings decide" not in out
