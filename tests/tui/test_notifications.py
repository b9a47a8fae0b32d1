"""Notifications: one box per kind, the newest replacing the last, and routine refusals leave the charts soon
(issue 24, item 8: three "Value refused" boxes stacked over the charts for 5 s)."""

from __future__ import annotations

import asyncio

from support.bursts import MessageWatch, send_burst
from support.tui_support import make_app
from textual.notifications import Notify
from textual.widgets._toast import Toast

from tui.notices import NEWS_SECONDS, ROUTINE_SECONDS
from tui.widgets.stepper import Stepper


def run(scenario):
    """scenario(pilot, app, watch) on an explorer at 80x24 that shows its notifications."""

    async def body():
        watch = MessageWatch()
        app = make_app()
        async with app.run_test(size=(80, 24), notifications=True, message_hook=watch) as pilot:
            await scenario(pilot, app, watch)

    asyncio.run(body())


def test_three_refused_values_are_one_short_box_and_another_kind_stays_beside_it():
    async def scenario(pilot, app, watch):
        watch.record()
        app.notify("Wrote a.json and a.svg", title="Exported")
        app.screen.query_one("#noise", Stepper).focus()
        for count, value in enumerate("123", start=2):  # each below 0.00 N m
            send_burst(app, "-", value, "enter")
            await watch.handled_by(app, app, Notify, count)
        shown = [(n.title, n.message.split(";")[-1], n.timeout) for n in app._notifications]
        assert shown == [("Exported", "Wrote a.json and a.svg", NEWS_SECONDS),
                         ("Value refused", " got '-3'. Kept 0.00.", ROUTINE_SECONDS)]
        await watch.until(app, lambda: len(app.screen.query(Toast)) == 2, "two boxes on screen")
        app.notify("A key that does not apply here", severity="warning")
        await watch.until(app, lambda: len(app.screen.query(Toast)) == 3, "a box of a third kind")
        assert [n.timeout for n in app._notifications][-1] == ROUTINE_SECONDS

    run(scenario)
