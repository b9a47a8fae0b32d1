"""`jointid serve` in a real browser: headless Chromium opens the page, types `2`, presses Ctrl+S, and takes a
screenshot.

The page draws the terminal on a canvas, so what it shows is checked two ways: the terminal output the page
received (a script added before the page's own records its WebSocket's frames) holds the readouts, and the
screenshot is saved for a person to look at (the test leaves it in its tmp_path as served.png).
"""

from __future__ import annotations

import asyncio
import json

import aiohttp
import pytest

from tests.support.chromium import PAINTED, RECORD_FRAMES, Chromium
from tests.support.serve_support import ServedExplorer


@pytest.fixture(scope="module")
def server():
    """`jointid serve --noise 0.2` on a free port."""
    served = ServedExplorer("--noise", "0.2")
    yield served
    served.stop()


def test_chromium_shows_the_explorer_types_2_and_downloads_the_export(server, tmp_path):
    browser = Chromium()
    downloads = tmp_path / "downloads"
    downloads.mkdir()

    async def scenario():
        async with aiohttp.ClientSession() as http:
            page = await browser.page(http)
            await page.send("Page.enable")
            await page.send("Page.addScriptToEvaluateOnNewDocument", source=RECORD_FRAMES)
            await page.send("Browser.setDownloadBehavior", behavior="allow", downloadPath=str(downloads),
                            eventsEnabled=True)
            await page.send("Page.navigate", url=server.url + "/")
            assert await page.evaluate("terminalShows('0.793312')")  # rich motion at noise 0.20
            await page.evaluate("document.querySelector('.xterm-helper-textarea').focus()")
            await page.send("Input.dispatchKeyEvent", type="keyDown", key="2", code="Digit2", text="2")
            await page.send("Input.dispatchKeyEvent", type="keyUp", key="2", code="Digit2")
            assert await page.evaluate("terminalShows('-1.607788')")  # slow motion's inertia
            await page.evaluate(PAINTED)
            picture = await page.screenshot(tmp_path / "served.png")
            await page.send("Input.dispatchKeyEvent", type="keyDown", key="s", code="KeyS", modifiers=2,
                            windowsVirtualKeyCode=83)
            await page.send("Input.dispatchKeyEvent", type="keyUp", key="s", code="KeyS", modifiers=2,
                            windowsVirtualKeyCode=83)
            done = await page.wait_for_events("Browser.downloadProgress",
                                              lambda params: params["state"] == "completed", count=2)
            started = {event["params"]["guid"]: event["params"]["suggestedFilename"]
                       for event in page.events if event["method"] == "Browser.downloadWillBegin"}
            await page.close()
            return picture, sorted(started[event["params"]["guid"]] for event in done)

    try:
        picture, names = asyncio.run(scenario())
    finally:
        browser.close()
    assert picture.startswith(b"\x89PNG") and len(picture) > 20_000  # a drawn page, not a blank one
    assert names == ["jointid-slow-0.20-24-7.json", "jointid-slow-0.20-24-7.svg"]
    saved = {path.name: path for path in downloads.iterdir()}
    document = json.loads(next(path for name, path in saved.items() if name.endswith(".json")).read_text())
    assert document["estimate"]["I"] == pytest.approx(-1.607788, abs=5e-7)
