"""Ctrl+R (and the palette's Write report): the explorer writes `jointid report`'s page of what it shows into the
current folder, under a free name, and says where; a folder it cannot write to is a notification."""

from __future__ import annotations

import asyncio
import os

import html5lib
from support.bursts import MessageWatch
from support.tui_support import make_app
from textual.notifications import Notify

from jointid.present.text import format_number
from jointid.studies.experiment import run_experiment
from jointid.synthetic.settings import Settings


def page_text(path) -> str:
    """The page's text, parsed strictly (a parse error raises)."""
    with open(path, "rb") as handle:
        document = html5lib.HTMLParser(strict=True, namespaceHTMLElements=False).parse(handle)
    return " ".join("".join(document.itertext()).split())


def test_ctrl_r_writes_the_report_of_the_motion_on_screen_and_says_where(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "jointid-slow-0.20-24-7-report.html").write_text("an earlier report")  # kept: the next name is used
    written = tmp_path / "jointid-slow-0.20-24-7-report-2.html"

    async def body():
        watch = MessageWatch()
        app = make_app(Settings(motion="rich", noise=0.2))
        async with app.run_test(size=(120, 40), notifications=True, message_hook=watch) as pilot:
            await pilot.press("2")  # slow motion, as the lesson's third stop
            await pilot.pause()
            watch.record()
            await pilot.press("ctrl+r")
            await app.workers.wait_for_complete()
            await watch.handled_by(app, app, Notify, 2)
            return [(notice.title, notice.message) for notice in app._notifications]

    notices = asyncio.run(body())
    assert notices[-1] == ("Report written", f"Wrote {written}")
    assert (tmp_path / "jointid-slow-0.20-24-7-report.html").read_text() == "an earlier report"
    text = page_text(written)
    # The lesson's slow case, computed here apart from the app.
    result = run_experiment(Settings(motion="slow", noise=0.2))
    for value in (*result.estimate, result.training_rmse, result.heldout_rmse):
        assert format_number(value) in text
    assert "Slow motion, noise 0.20 N m, 24 samples, seed 7" in text and "the explorer (Ctrl+R)" in text


def test_the_palette_lists_write_report_and_an_unwritable_folder_is_a_notification(tmp_path, monkeypatch):
    folder = tmp_path / "gone"
    folder.mkdir()
    monkeypatch.chdir(folder)
    folder.rmdir()  # the current folder no longer exists: nothing can be written there

    async def body():
        watch = MessageWatch()
        app = make_app()
        async with app.run_test(size=(120, 40), notifications=True, message_hook=watch) as pilot:
            await pilot.pause()
            titles = [command.title for command in app.get_system_commands(app.screen)]
            watch.record()
            await pilot.press("ctrl+r")
            await app.workers.wait_for_complete()
            await watch.handled_by(app, app, Notify, 2)
            return titles, [(notice.title, notice.message, notice.severity) for notice in app._notifications]

    titles, notices = asyncio.run(body())
    assert "Write report" in titles
    title, message, severity = notices[-1]
    assert (title, severity) == ("No report written", "error")
    assert "no such folder" in message.lower() or "no such file" in message.lower()
    assert "\n" not in message
    os.chdir(tmp_path)  # leave a folder that exists for whatever runs next
