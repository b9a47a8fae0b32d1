"""The in-app help's numbers against the code they describe, so the help cannot drift from the defaults again."""

from __future__ import annotations

import re

from jointid.options import DEFAULT_ORDER, DEFAULT_WINDOW
from jointid.synthetic.settings import DEFAULT_SETTINGS
from tui.palette import PHYSICS_STOPS, TOUR
from tui.ranges import NOISE_RANGE, SAMPLES_RANGE, SEED_RANGE
from tui.screens.help import help_markdown
from tui.screens.main import MainScreen
from tui.screens.sweep import DEFAULT_SEED_COUNT, SEED_COUNT_RANGE

HELP = " ".join(help_markdown(MainScreen.BINDINGS).split())
"""The rendered help with its line breaks folded, so a phrase is found wherever the Markdown wraps it."""


def sentence_with(phrase: str) -> str:
    """The one sentence (up to a full stop and a space) of the help that holds `phrase`."""
    found = [s for s in re.split(r"(?<=[.)])\s+(?=[A-Z`*(-])", HELP) if phrase in s]
    assert len(found) == 1, (phrase, found)
    return found[0]


def test_the_derivative_filter_is_described_with_the_logs_defaults():
    sentence = sentence_with("Savitzky-Golay")
    assert f"order {DEFAULT_ORDER}" in sentence
    assert re.findall(r"\d+", sentence) == [str(DEFAULT_ORDER)], sentence  # no stray window or order number
    assert DEFAULT_WINDOW is None and "window chosen from the low-pass's cutoff" in sentence
    assert "trimmed" not in sentence.replace("no sample is trimmed", "")


def test_the_ranges_keep_their_units_and_match_the_controls():
    for steps in (NOISE_RANGE, SAMPLES_RANGE, SEED_RANGE):
        low, high = steps.format(steps.low), steps.format(steps.high)
        assert f"From {low} to {high}" in HELP
    assert "From 0.00 to 1.00 N m here" in HELP  # the unit as written, not str.capitalize's "n m"


def test_the_tour_and_the_reset_and_the_sweep_are_as_the_code_has_them():
    assert f"{len(TOUR) + len(PHYSICS_STOPS)} stops" in HELP and f"the lesson's {len(TOUR)}, then" in HELP
    reset = sentence_with("**Reset**")
    assert (f"{DEFAULT_SETTINGS.motion} motion, noise {DEFAULT_SETTINGS.noise:.2f}, "
            f"{DEFAULT_SETTINGS.samples} samples, seed {DEFAULT_SETTINGS.seed}") in reset
    sweep = sentence_with("to start;")
    assert f"K = {DEFAULT_SEED_COUNT} to start" in sweep
    assert f"change it by {SEED_COUNT_RANGE.step}, Shift by {SEED_COUNT_RANGE.big_step}" in sweep
    assert f"type {SEED_COUNT_RANGE.low} to {SEED_COUNT_RANGE.high}" in sweep


def test_the_browser_section_says_what_differs_as_the_code_does_it():
    from jointid.cli.serve_command import DEFAULT_IDLE_TIMEOUT
    from tui.web import NO_DATA_FOLDER

    assert "## In a browser" not in HELP  # a terminal's help is as it was
    section = " ".join(help_markdown(MainScreen.BINDINGS, web=True).split())
    section = section[section.index("## In a browser"):]
    assert "Ctrl+S** downloads the JSON and the SVG" in section
    assert "`jointid serve --data DIR`" in section and "without `--data`, Ctrl+O is off" in section
    assert "jointid serve --data DIR" in NO_DATA_FOLDER  # the notification names the same flag
    assert f"for {DEFAULT_IDLE_TIMEOUT // 60} minutes (the server's `--idle-timeout`)" in section


def test_the_joint_logs_section_says_once_what_a_log_hides_and_names_the_log_defaults_from_the_code():
    from jointid.logs.conventions import ZEROS
    from jointid.options import default_log_model

    section = HELP[HELP.index("## Joint logs"):HELP.index("## Precision")]
    assert "*from log*" not in section and "read from log" not in section  # the fields are hidden, not relabelled
    hidden = sentence_with("are hidden")
    assert all(name in hidden for name in ("noise, samples and seed fields", "Reset", "known synthetic parameters"))
    defaults = sentence_with("log defaults, as `jointid --csv`")
    assert f"model {default_log_model('torque')} ({default_log_model('voltage')} for a voltage log)" in defaults
    for option in ("**Zero right**", *(f"**{zero}**" for zero in ZEROS if zero != "right"), "**Degrees**",
                   "**Clockwise**", "**Current**", "`--zero`", "`--clockwise`", "`--kt`"):
        assert option in section, option
