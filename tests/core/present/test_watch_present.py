"""What every face of a watch says: the JSON object of a refresh keeps a log fit's keys and words, the text line and
the determination sentences read as the issue asks ('kA determined to 4.8 % after 12.4 s')."""

from __future__ import annotations

import json
import math

from support.watch_plans import scripted_refreshes

from jointid.present.documents import result_to_dict
from jointid.present.watch import (
    Saved,
    closing_lines,
    convergence_chart,
    determination_sentence,
    percent_text,
    recent_chart,
    refresh_line,
    refresh_object,
    saved_object,
    saved_sentence,
)
from jointid.studies.watch_refresh import ParameterTrace

REFRESHES = scripted_refreshes()


def test_a_refresh_object_has_the_verdicts_and_reasons_of_the_same_fit_as_a_log_fit_json_says_them():
    for refresh in REFRESHES:
        document = refresh_object(refresh)
        fit = result_to_dict(refresh.result)
        assert document["verdicts"] == fit["verdicts"]
        assert document["verdict_reasons"] == fit["verdict_reasons"]
        assert document["estimate"] == fit["estimate"]
        assert document["std_error"] == fit["std_error"]
        json.dumps(document, allow_nan=False)  # strict JSON


def test_the_determination_sentence_gives_the_error_then_and_the_seconds_watched():
    trace = ParameterTrace("kA", "acceleration gain", "V s²/rad", 0.02, 0.001, "well determined", None,
                           determined_at=12.4, determined_pct=4.8)
    assert determination_sentence(trace) == "kA determined to 4.8 % after 12.4 s"
    assert determination_sentence(ParameterTrace("kA", "", "", 0.02, 0.01, "weak", None)) is None


def test_percentages_keep_two_figures_below_ten():
    assert [percent_text(v) for v in (0.354, 4.81, 8.0, 12.4, 2000.0, None)] == [
        "0.35 %", "4.8 %", "8.0 %", "12 %", ">999 %", "—"]


def test_the_text_line_names_each_parameter_its_relative_error_and_verdict():
    last = REFRESHES[-1]
    line = refresh_line(last)
    assert line.startswith("8.0 s, 200 received, 200 fitted: ")
    for trace in last.parameters:
        pct = 100 * abs(trace.error / trace.value)
        assert f"{trace.name} {trace.value:#.4g} ± {percent_text(pct)} {trace.verdict}" in line


def test_closing_lines_say_what_is_not_determined_and_the_advice_while_it_is_not():
    early = REFRESHES[2]  # B still not determined at 12 samples
    lines = closing_lines(early)
    assert "Not well determined: B." in lines and "Move faster: B needs speed." in lines
    assert "B determined" not in " ".join(lines)
    assert any(line.startswith("B determined to") for line in closing_lines(REFRESHES[-1]))


def test_saved_says_what_was_written_or_why_not():
    assert saved_sentence(Saved("arm.csv", 620)) == "Wrote 620 samples to arm.csv (jointid fit --csv arm.csv fits them)."
    assert saved_sentence(Saved(None, 0, "no sample was received")) == "Nothing saved: no sample was received."
    assert saved_object(Saved("a\nb.csv", 3), "duration") == {
        "stopped_by": "duration", "saved": {"path": "a\\nb.csv", "samples": 3}, "not_saved": None}


def test_the_convergence_series_end_at_one_and_the_errors_fall():
    last = REFRESHES[-1]
    estimates = convergence_chart(last, "estimate")
    assert [name for name, _, _ in estimates.lines] == list(last.result.model.names)
    for _, seconds, shares in estimates.lines:
        assert math.isclose(shares[-1], 1.0) and seconds[-1] == last.elapsed
    for _, _, errors in convergence_chart(last, "error").lines:
        assert errors[-1] < errors[0]


def test_the_recent_chart_is_the_measured_effort_against_the_fit():
    chart = recent_chart(REFRESHES[-1])
    assert chart.y_label == "Torque (N m)" and chart.line is not None and len(chart.dots) == 200
    assert recent_chart(REFRESHES[-1], "voltage").y_label == "Voltage (V)"
