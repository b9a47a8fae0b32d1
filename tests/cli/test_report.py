"""`jointid report`: one self-contained HTML page (and optionally Markdown) holding the numbers `jointid fit --json`
gives for the same input, with no reference to anything outside it; bad input is one line and exit status 2."""

from __future__ import annotations

import html
import importlib.util
import json
import os
import re
import struct
import zlib
from pathlib import Path
from xml.etree import ElementTree

import html5lib
import pytest
from support.headless_chromium import CHROMIUM, visit
from support.real_logs import REAL_LOGS, needs_real_logs

from jointid.cli import main
from jointid.present.text import format_number

SLOW_CASE = ["--motion", "slow", "--noise", "0.2"]
"""The lesson's slow motion: a unique fit whose inertia is not determined."""
REAL_LOG = ["--csv", str(REAL_LOGS / "pendulum_energy_shaping.csv"), "--zero", "down"]
"""A real run with hand pushes the fit leaves out (the excluded intervals' table)."""
EXTERNAL = re.compile(r"^\s*(?:[a-z][a-z0-9+.-]*:|//)", re.IGNORECASE)
"""A reference that leaves the page: any scheme (http:, https:, file:, data: ...) or a protocol-relative //host."""


@pytest.fixture(scope="module")
def pages(tmp_path_factory) -> dict[str, Path]:
    """The slow case's report and the real run's, written once for the tests that read them."""
    folder = tmp_path_factory.mktemp("reports")
    written = {"slow": folder / "slow.html"}
    assert main(["report", *SLOW_CASE, "--out", str(written["slow"])]) == 0
    if REAL_LOGS.is_dir():
        written["pushes"] = folder / "pushes.html"
        assert main(["report", *REAL_LOG, "--out", str(written["pushes"])]) == 0
    return written


def parsed(path) -> tuple[object, str]:
    """The page parsed strictly by html5lib (any parse error raises) and its text with entities decoded."""
    with open(path, "rb") as handle:
        document = html5lib.HTMLParser(strict=True, namespaceHTMLElements=False).parse(handle)
    return document, " ".join("".join(document.itertext()).split())


def fit_json(capsys, arguments: list[str]) -> dict:
    """What `jointid fit ARGUMENTS --json` prints, parsed."""
    assert main(["fit", *arguments, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def number_texts(document: dict) -> list[str]:
    """Every number of a fit's JSON as the texts show it: parameters, their errors and intervals, the RMSEs and
    the motion's RMS (six decimals), the relative errors (one), the condition number (two)."""
    texts = [format_number(value) for value in document["estimate"].values()]
    for key in ("std_error", "noise_bound_std_error"):
        texts += [format_number(value) for value in (document[key] or {}).values() if value is not None]
    texts += [format_number(end) for interval in document["interval95"].values() for end in interval]
    texts += [format_number(document[key]) for key in ("training_rmse", "heldout_rmse", "accel_rms", "speed_rms")
              if document[key] is not None]
    texts += [f"{value:.1f} %" for value in document["relative_std_pct"].values()]
    texts.append(f"{document['condition_number']:.2f}")
    return texts


def assert_self_contained(document, path) -> None:
    """No element refers to anything outside the page: no src, href or xlink:href with a scheme or a host, no
    script, no linked style sheet, no @import, no url() but to an id in the page."""
    for element in document.iter():
        for name, value in element.attrib.items():
            if name in ("src", "href", "{http://www.w3.org/1999/xlink}href", "xlink:href", "srcset", "action"):
                assert not EXTERNAL.match(value), f"{element.tag} {name}={value}"
        assert element.tag not in ("script", "link", "iframe", "img", "object", "embed")
    text = path.read_text(encoding="utf-8")
    assert "@import" not in text
    assert not re.search(r"""url\(\s*["']?(?!#)""", text)  # clip paths refer to ids within the page only
    assert not re.search(r"""(?:src|href)\s*=\s*["']?\s*(?:https?:)?//""", text)


def test_a_report_replaces_a_file_only_with_force_and_is_the_same_bytes_each_time(pages, tmp_path, capsys):
    page = tmp_path / "slow.html"
    page.write_text("keep me")
    assert main(["report", *SLOW_CASE, "--out", str(page)]) == 2
    assert "already exists; not overwriting it (add --force to replace it)" in one_line_error(capsys)
    assert page.read_text() == "keep me"
    assert main(["report", *SLOW_CASE, "--out", str(page), "--force"]) == 0
    assert capsys.readouterr() == (f"Wrote {page}.\n", "")
    # No date, no random ids: the same bytes as another run, but for the command in the footer.
    text, other = page.read_text(encoding="utf-8"), pages["slow"].read_text(encoding="utf-8")
    assert text.split("<footer>")[0] == other.split("<footer>")[0]
    assert "<metadata>" not in text and "Date" not in text


def test_the_slow_case_report_holds_fit_json_numbers_and_nothing_external(pages, capsys):
    page = pages["slow"]
    document, text = parsed(page)
    fit = fit_json(capsys, SLOW_CASE)
    for number in number_texts(fit):
        assert number in text, number
    assert "-1.607788" in text and "2.261865" in text  # the lesson's table, read off the page
    assert fit["message"] in text  # the status sentence
    for verdict in set(fit["verdicts"].values()):
        assert verdict in text
    assert "Slow motion, noise 0.20 N m, 24 samples, seed 7" in text
    assert_self_contained(document, page)
    charts = document.findall(".//figure")
    assert [figure.get("id") for figure in charts] == ["chart-training", "chart-heldout", "chart-residuals"]
    svg_text = " ".join(" ".join(" ".join(chart.itertext()).split()) for chart in charts)
    for label in ("Time (s)", "Torque (N m)", "Residual (N m)", "Angle q (rad)", "Velocity qd (rad/s)",
                  "Acceleration qdd (rad/s²)", "measured", "fitted"):
        assert label in svg_text, label  # the charts' text is text: selectable and searchable


@needs_real_logs
def test_a_real_log_report_holds_fit_json_numbers_notes_and_left_out_stretches(pages, capsys):
    page = pages["pushes"]
    document, text = parsed(page)
    fit = fit_json(capsys, REAL_LOG)
    for number in number_texts(fit):
        assert number in text, number
    assert fit["message"] in text
    for note in fit["notes"]:
        assert " ".join(note.split()) in text
    assert fit["excluded"], "the energy-shaping run has pushes the robust fit leaves out"
    for start, end in fit["excluded"]:
        assert f"{start:.2f}" in text and f"{end:.2f}" in text
    assert "Sensitivity check" in text and "Left out of the fit" in text
    assert_self_contained(document, page)
    # The training chart draws the left-out samples faint and the pushes shaded, as the explorer does.
    training = document.find(".//figure[@id='chart-training']")
    assert "left out" in " ".join(training.itertext()) and "outside torque" in " ".join(training.itertext())


@pytest.mark.slow  # two runs pooled and the ladder: about 1.5 s
@needs_real_logs
def test_several_runs_and_the_ladder(tmp_path, capsys):
    page = tmp_path / "runs.html"
    runs = [REAL_LOGS / "pendulum_pd.csv", REAL_LOGS / "pendulum_ddp.csv"]
    arguments = [item for run in runs for item in ("--csv", str(run))] + ["--zero", "down"]
    assert main(["report", *arguments, "--compare", "--out", str(page)]) == 0
    capsys.readouterr()
    document, text = parsed(page)
    assert main(["fit", *arguments, "--json"]) == 0
    pooled = json.loads(capsys.readouterr().out)
    for name, value in pooled["pooled"]["estimate"].items():
        assert format_number(value) in text, name
    for run in pooled["runs"]:
        for value in run["estimate"].values():
            assert format_number(value) in text
    assert main(["compare", *arguments[:2], "--zero", "down", "--json"]) == 0
    ladder = json.loads(capsys.readouterr().out)
    assert ladder["message"] in text
    assert [figure.get("id") for figure in document.findall(".//figure")].count("chart-run2-training") == 1
    assert_self_contained(document, page)


def test_markdown_beside_with_its_charts_as_files(tmp_path, capsys):
    page, markdown = tmp_path / "slow.html", tmp_path / "notes" / "slow.md"
    markdown.parent.mkdir()
    assert main(["report", *SLOW_CASE, "--out", str(page), "--markdown", str(markdown)]) == 0
    assert "and 3 charts beside it" in capsys.readouterr().out
    text = markdown.read_text(encoding="utf-8")
    linked = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", text)
    assert linked == ["slow-training.svg", "slow-heldout.svg", "slow-residuals.svg"]
    for name in linked:
        svg = ElementTree.parse(markdown.parent / name).getroot()  # each is well-formed XML
        assert svg.tag == "{http://www.w3.org/2000/svg}svg"
        assert "prefers-color-scheme: dark" in (markdown.parent / name).read_text(encoding="utf-8")
    assert "| I (kg m²) | -1.607788 | ± 5.425077 |" in text
    assert "-1.607788" in text and "2.261865" in text


# Bad input: one line, exit status 2, nothing written or replaced ---------------------------------------------


def one_line_error(capsys) -> str:
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.count("\n") == 1
    return captured.err


def test_an_existing_chart_file_stops_the_whole_group(tmp_path, capsys):
    page, markdown = tmp_path / "slow.html", tmp_path / "slow.md"
    (tmp_path / "slow-heldout.svg").write_text("keep me")
    assert main(["report", *SLOW_CASE, "--out", str(page), "--markdown", str(markdown)]) == 2
    assert "slow-heldout.svg: already exists" in one_line_error(capsys)
    assert sorted(os.listdir(tmp_path)) == ["slow-heldout.svg"]  # nothing else written, no temporary left


@pytest.mark.parametrize("where, problem", [
    ("missing/slow.html", "missing/slow.html: cannot write: No such folder"),
    ("file.txt/slow.html", "Not a directory"),
    ("/dev/null", "a character device, not a regular file"),
    (".", "a directory, not a regular file"),
])
def test_an_unwritable_report_path_is_one_line(tmp_path, capsys, monkeypatch, where, problem):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "file.txt").write_text("")
    assert main(["report", *SLOW_CASE, "--out", where, "--force"]) == 2
    assert problem in one_line_error(capsys)


@pytest.mark.parametrize("arguments, problem", [
    (SLOW_CASE, "the following arguments are required: --out"),
    ([*SLOW_CASE, "--out", "a.html", "--markdown", "a.html"], "both name a.html"),
    ([*SLOW_CASE, "--out", "a.html", "--exclude", "1:2"], "only for fitting a log"),
    (["--csv", "log.csv", "--motion", "slow", "--out", "a.html"], "cannot apply to a log"),
    (["--out", "a.html", "--bogus"], "unrecognized arguments: --bogus"),
])
def test_bad_flags_are_one_line(tmp_path, capsys, monkeypatch, arguments, problem):
    monkeypatch.chdir(tmp_path)
    try:
        status = main(["report", *arguments])
    except SystemExit as stop:  # argparse's own errors end the parse
        status = stop.code
    assert status == 2
    assert problem in one_line_error(capsys)
    assert not (tmp_path / "a.html").exists()


def test_without_matplotlib_the_report_names_the_extra(tmp_path, capsys, monkeypatch):
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "matplotlib" else real(name, *a))
    assert main(["report", *SLOW_CASE, "--out", str(tmp_path / "a.html")]) == 2
    assert one_line_error(capsys) == ("jointid: writing a report needs the optional matplotlib package: "
                                      "pip install 'jointid[report]'\n")
    assert not (tmp_path / "a.html").exists()


# In a real browser ---------------------------------------------------------------------------------------------

needs_chromium = pytest.mark.skipif(not CHROMIUM.exists(), reason="needs Debian's chromium (/usr/bin/chromium)")
"""Marks a test that opens a page in headless Chromium (.ci/run installs it)."""
LIGHT_BACKGROUND = (255, 255, 255)
DARK_BACKGROUND = (0x12, 0x12, 0x12)
"""The page's background in each scheme (report_writers.STYLE: the browser's white, and #121212)."""


def png_size_and_first_pixel(png: bytes) -> tuple[tuple[int, int], tuple[int, ...]]:
    """(width, height) and the top-left pixel's RGB of an 8-bit RGB or RGBA PNG, read with zlib alone: whatever
    the first row's filter, its first pixel is stored as it is (it has no left or upper neighbour)."""
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    width, height, depth, colour = struct.unpack(">IIBB", png[16:26])
    assert depth == 8 and colour in (2, 6)
    position, data = 8, b""
    while position < len(png):
        length, kind = struct.unpack(">I4s", png[position:position + 8])
        if kind == b"IDAT":
            data += png[position + 8:position + 8 + length]
        position += 12 + length
    first_row = zlib.decompressobj().decompress(data, 16)
    return (width, height), tuple(first_row[1:4])


def keep(name: str, png: bytes) -> None:
    """Save a screenshot in the folder $JOINTID_SCREENSHOTS names, for a person to look at."""
    folder = os.environ.get("JOINTID_SCREENSHOTS")
    if folder:
        Path(folder, name).write_bytes(png)


@needs_chromium
def test_chromium_opens_the_reports_without_any_request_but_their_own_files(pages):
    for (case, page), opened in zip(pages.items(), visit(list(pages.values()))):
        assert opened.requests == (page.resolve().as_uri(),)
        (width, height), corner = png_size_and_first_pixel(opened.screenshot)
        assert width == 1200 and height > 2000  # the whole page: its charts and tables take well over a screen
        assert corner == LIGHT_BACKGROUND
        keep(f"{case}.png", opened.screenshot)


@pytest.mark.slow  # a second start of Chromium, about 2 s
@needs_chromium
def test_the_report_follows_a_dark_browser_theme(pages):
    opened, = visit([pages["slow"]], dark=True)
    assert opened.requests == (pages["slow"].resolve().as_uri(),)
    _, corner = png_size_and_first_pixel(opened.screenshot)
    assert corner == DARK_BACKGROUND
    keep("slow-dark.png", opened.screenshot)


# The charts' second process ---------------------------------------------------------------------------------


def slow_case_report():
    from jointid.present.report import synthetic_report
    from jointid.studies.experiment import run_experiment
    from jointid.synthetic.settings import Settings

    settings = Settings(motion="slow", noise=0.2)
    return synthetic_report(run_experiment(settings), settings)


def drawn_charts(report, process=None) -> list[str]:
    from jointid.present.report import draw

    return [block.svg for block in draw(report, process).blocks if hasattr(block, "svg")]


def test_a_chart_process_that_died_leaves_the_charts_to_this_one(pages):
    from jointid.present.chart_process import ChartProcess

    broken = ChartProcess()
    broken.process.kill()  # died before it was asked
    charts = drawn_charts(slow_case_report(), broken)
    assert len(charts) == 3 and all(svg.startswith("<svg") for svg in charts)
    page = pages["slow"].read_text(encoding="utf-8")
    assert all(svg.split(">", 1)[1] in page for svg in charts)  # as the command's child drew them


@pytest.mark.slow  # waits for a child to import matplotlib, about 2 s
def test_the_chart_process_draws_what_this_process_would():
    from jointid.present.chart_process import ChartProcess

    report = slow_case_report()
    assert drawn_charts(report, ChartProcess()) == drawn_charts(report)


def test_every_text_is_escaped_a_file_name_with_markup_included(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    name = 'run <b>1<i> & "2".csv'
    assert main(["simulate", "--out", name]) == 0
    assert main(["report", "--csv", name, "--out", "run.html", "--markdown", "run.md"]) == 0
    capsys.readouterr()
    document, text = parsed(tmp_path / "run.html")
    assert f"Training log {name}" in text  # shown as written
    assert document.find(".//b") is None and document.find(".//i") is None  # and never read as markup
    assert 'run \\<b\\>1\\<i\\> & "2".csv' in (tmp_path / "run.md").read_text(encoding="utf-8")


# Names the program did not choose: math, markup, terminal escapes and bidi overrides ---------------------------

HOSTILE = "x\x1b[2J\x07\u202e ````\n<img src=x onerror=alert(1)>.csv"
"""A file name with a terminal escape, a bell, a right-to-left override, a code fence and an HTML tag."""


def raw_controls(text: str) -> set[str]:
    """The characters of `text` a face must never show as they are: not printable, other than newline and tab."""
    return {c for c in text if not c.isprintable() and c not in "\n\t"}


def test_a_file_name_is_drawn_as_text_not_as_math(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    name = "cost $5 and $6 $\\foo$.csv"  # was a ParseFatalException (exit 1), and lost its dollars
    assert main(["simulate", "--out", name]) == 0
    assert main(["report", "--csv", name, "--out", "run.html"]) == 0, capsys.readouterr().err
    document, _ = parsed(tmp_path / "run.html")
    svg_texts = ["".join(node.itertext()) for node in document.iter() if str(node.tag).endswith("text")]
    assert f"Fit the training log {name}" in svg_texts


def test_hostile_names_are_escaped_alike_in_every_face_and_markdown_links_resolve(tmp_path, capsys, monkeypatch):
    from urllib.parse import unquote

    from markdown_it import MarkdownIt

    from jointid.text_safety import shown_name

    monkeypatch.chdir(tmp_path)
    other = "plain.csv"
    for name in (HOSTILE, other):
        assert main(["simulate", "--out", name, "--motion", "rich"]) == 0
    capsys.readouterr()
    markdown = "my report (final).md"  # an ordinary name whose links broke on the space and the parentheses
    status = main(["report", "--csv", HOSTILE, "--csv", other, "--motor", "NEO\x1b\x07", "--gear", "10", "--out",
                   "run.html", "--markdown", markdown])
    out, err = capsys.readouterr()
    assert status == 0, err
    page = (tmp_path / "run.html").read_text(encoding="utf-8")
    text = (tmp_path / markdown).read_text(encoding="utf-8")
    for face in (out, page, text):
        assert raw_controls(face) == set(), raw_controls(face)
    _, page_text = parsed(tmp_path / "run.html")  # strict: a raw ESC or BEL is a parse error
    shown = shown_name(HOSTILE)  # how every face shows a name it did not choose
    rendered = MarkdownIt("commonmark").render(text)
    assert shown in page_text and shown in html.unescape(rendered)  # the Markdown reads as the name, escaped
    assert "onerror" not in re.sub(r"&lt;img src=x onerror=alert\(1\)&gt;", "", rendered)
    targets = re.findall(r'<img src="([^"]*)"', rendered)
    charts = sorted(path.name for path in tmp_path.glob("*.svg"))
    assert len(charts) == 4 and sorted(unquote(target) for target in targets) == charts
    assert all(name.startswith("my report (final)-") for name in charts)


def test_markdown_fences_hold_any_text_and_chart_links_take_any_file_name(tmp_path):
    """A preformatted text (a table of run names) cannot close its fence and inject HTML, whatever backticks it
    holds; a chart file beside 'my report (final).md' is linked so that the link reaches it."""
    from urllib.parse import unquote

    from markdown_it import MarkdownIt

    from jointid.present.report import Chart, Preformatted, Report
    from jointid.present.report_writers import markdown_files

    inside = "run    rows\n````\n<img src=x onerror=alert(1)>\n`````` 24"
    report = Report("title", "subject", (Preformatted(inside), Chart("training", "Fit", "caption", ("", ()),
                                                                      svg="<svg></svg>")))
    markdown = str(tmp_path / "my report (final).md")
    files = markdown_files(report, markdown, "footer")
    tokens = MarkdownIt("commonmark").parse(files[markdown])
    fences = [token for token in tokens if token.type == "fence"]
    assert [token.content for token in fences] == [inside + "\n"]  # the text whole, in one fence
    assert not [token for token in tokens if token.type.startswith("html")]
    (image,) = [child for token in tokens if token.children for child in token.children if child.type == "image"]
    assert unquote(image.attrs["src"]) == "my report (final)-training.svg"
    assert str(tmp_path / "my report (final)-training.svg") in files
