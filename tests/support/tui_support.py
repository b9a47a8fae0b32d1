"""Helpers shared by the explorer's pilot, readout and snapshot tests."""

from __future__ import annotations

import asyncio
import functools
import signal
from contextlib import contextmanager
from pathlib import Path

from jointid.synthetic.settings import DEFAULT_SETTINGS, Settings
from tui.app import JointIdApp
from tui.palette import TOUR
from tui.screens.main import MainScreen
from tui.widgets.readouts import ReadoutPanel

THEME = "textual-dark"
"""Fixed theme for every snapshot."""

CANONICAL_STATES = {
    "default": TOUR[0],
    "rich_0.20": TOUR[1],
    "slow_0.20": TOUR[2],
    "holds": TOUR[3],
}
"""The lesson's tour stops, by the name of their pinned files."""

READOUTS_DIR = Path(__file__).resolve().parents[2] / "snapshots" / "readouts"
"""Pinned readout texts, one file per canonical state."""

READOUT_SIZES = {"": (120, 40), "@80x24": (80, 24)}
"""Terminal sizes at which pinned readouts are read off the app, by file-name suffix
(120x40 shows the lab's labels, 80x24 the compact rows)."""


def pinned_readouts() -> dict[str, tuple[Settings, tuple[int, int]]]:
    """Every pinned readout file's stem, with the state and terminal size it is read at."""
    return {
        name + suffix: (settings, size)
        for name, settings in CANONICAL_STATES.items()
        for suffix, size in READOUT_SIZES.items()
    }


def make_app(settings: Settings | None = None, logs=None) -> JointIdApp:
    """An explorer with the fixed snapshot theme (on a loaded log, tui.log_source.LoadedLogs, if given)."""
    app = JointIdApp(DEFAULT_SETTINGS if settings is None else settings, logs)
    app.theme = THEME
    return app


def run_app(scenario, settings: Settings | None = None, size: tuple[int, int] = (120, 40)):
    """Run an async scenario(pilot, app) against a fresh app at a terminal size and return its result."""

    async def main():
        app = make_app(settings)
        async with app.run_test(size=size) as pilot:
            await pilot.pause()
            return await scenario(pilot, app)

    return asyncio.run(main())


def displayed_readouts(screen: MainScreen) -> str:
    """The readout lines and the status sentence exactly as the screen displays them."""
    panel = screen.query_one(ReadoutPanel)
    lines = [line.plain.rstrip() for line in panel.lines(panel.content_region.width)]
    status = str(screen.query_one("#status").render())
    return "\n".join(lines) + "\n\n" + status + "\n"


async def read_displayed(settings: Settings, size: tuple[int, int] = READOUT_SIZES[""]) -> str:
    """Open the app at settings and terminal size and return its displayed readouts."""
    app = make_app(settings)
    async with app.run_test(size=size) as pilot:
        await pilot.pause()
        return displayed_readouts(app.screen)


@contextmanager
def time_limit(seconds: float):
    """Raise TimeoutError in the main thread after `seconds`, and again every half second while an app runs.

    A frozen app then fails its test instead of hanging the run: a CPU-bound loop on the
    event loop's thread cannot be interrupted by asyncio, but a signal handler runs
    between two of its bytecodes. The repeats stop the app's shutdown (which paints
    once more) from freezing in the same loop; they stop once no event loop runs, so
    pytest's own code is never interrupted.
    """

    expired = []

    def expire(signum, frame):
        if expired and asyncio._get_running_loop() is None:  # the app has ended: nothing left to interrupt
            signal.setitimer(signal.ITIMER_REAL, 0)
            return
        expired.append(True)
        raise TimeoutError(f"still running after {seconds} s")

    previous = signal.signal(signal.SIGALRM, expire)
    signal.setitimer(signal.ITIMER_REAL, seconds, 0.5)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def regenerate_readouts() -> None:
    """Rewrite every pinned readout file from the app (run on purpose, then review the diff)."""
    READOUTS_DIR.mkdir(parents=True, exist_ok=True)
    for name, (settings, size) in pinned_readouts().items():
        text = asyncio.run(read_displayed(settings, size))
        (READOUTS_DIR / f"{name}.txt").write_text(text, encoding="utf-8")
        print(f"wrote {name}.txt")


if __name__ == "__main__":
    # Regenerate pinned readouts:  .venv/bin/python tests/support/tui_support.py
    regenerate_readouts()


def synchronous(test):
    """Run an async test body with asyncio.run (the suite has no async plugin); fixtures still apply."""

    @functools.wraps(test)
    def run(*args, **kwargs):
        return asyncio.run(test(*args, **kwargs))

    return run
