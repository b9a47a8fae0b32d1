"""Key bursts delivered as one batch, and waiting on the app's own messages instead of sleeps or pauses.

`send_burst` hands several keys to the app at once, as key repeat or an SSH
connection batching keystrokes does: none is handled before all are queued.
`MessageWatch` is a `run_test(message_hook=...)`: after any message any part of
the app handles, it re-checks what a test waits for, so a wait ends at the
event itself, however loaded the machine.
"""

from __future__ import annotations

import asyncio
import functools
import inspect
from collections.abc import Callable

from support.tui_support import make_app
from textual import events
from textual._context import active_message_pump
from textual.keys import key_to_character

WAIT_LIMIT = 60.0
"""Seconds a wait may take before the test fails (a wait normally ends within a frame or two)."""
SIZE = (120, 40)
"""Terminal size of the apps `with_app` starts."""


def send_burst(app, *keys: str) -> None:
    """Queue key presses for the app all at once (Pilot.press waits for the app to settle after each)."""
    for key in keys:
        event = events.Key(key, key_to_character(key))
        event.set_sender(app)
        app._driver.send_message(event)


class MessageWatch:
    """A message hook for `App.run_test` that lets a test wait until a condition holds (see the module's notes)."""

    def __init__(self) -> None:
        self._waiting: list[tuple[Callable[[], bool], asyncio.Event]] = []
        self.handled: list[tuple[object, object]] = []
        """(message pump, message) of every message handled since `record` was last called with True."""
        self._recording = False

    def record(self, on: bool = True) -> None:
        """Start (clearing what was kept) or stop keeping every handled message in `handled`."""
        self._recording = on
        if on:
            self.handled = []

    def __call__(self, message) -> None:
        """Called by Textual as each message is dispatched: check the waits once its handler has run."""
        pump = active_message_pump.get(None)
        if self._recording:
            self.handled.append((pump, message))
        if self._waiting and pump is not None:
            pump.call_next(self._check)  # runs right after this message's handler

    def _check(self) -> None:
        for condition, done in self._waiting:
            if not done.is_set() and condition():
                done.set()

    async def until(self, app, condition: Callable[[], bool], what: str = "the condition") -> None:
        """Return once `condition()` is true; fail if the app crashes first or WAIT_LIMIT passes."""
        if condition():
            return
        done = asyncio.Event()
        self._waiting.append((condition, done))
        try:
            waits = [asyncio.ensure_future(done.wait()), asyncio.ensure_future(app._exception_event.wait())]
            await asyncio.wait(waits, timeout=WAIT_LIMIT, return_when=asyncio.FIRST_COMPLETED)
            for wait in waits:
                wait.cancel()
        finally:
            self._waiting.remove((condition, done))
        if app._exception is not None:
            raise AssertionError(f"the app crashed while waiting for {what}") from app._exception
        assert done.is_set(), f"{what} not reached within {WAIT_LIMIT} s"

    async def handled_by(self, app, pump, message_type, count: int = 1) -> None:
        """Return once `pump` has handled `count` messages of `message_type` since `record()`."""
        await self.until(app, lambda: self.count(pump, message_type) >= count,
                         f"{count} {message_type.__name__} handled by {pump}")

    def count(self, pump, message_type) -> int:
        """How many messages of `message_type` `pump` has handled since `record()`."""
        return sum(1 for where, message in self.handled if where is pump and isinstance(message, message_type))


def with_app(test=None, *, size: tuple[int, int] = SIZE, notifications: bool = False):
    """Run an async test body as test(pilot, app, watch, **fixtures) on a fresh explorer (watch: its MessageWatch),
    at `size`, with its notifications drawn when asked (`with_app(size=(80, 24), notifications=True)`)."""
    if test is None:
        return functools.partial(with_app, size=size, notifications=notifications)

    @functools.wraps(test)
    def run(**fixtures):
        async def body():
            watch = MessageWatch()
            app = make_app()
            async with app.run_test(size=size, message_hook=watch, notifications=notifications) as pilot:
                await test(pilot, app, watch, **fixtures)

        asyncio.run(body())

    signature = inspect.signature(test)
    run.__signature__ = signature.replace(parameters=list(signature.parameters.values())[3:])  # pytest's fixtures
    return run


async def closed(app, watch: MessageWatch, screen) -> None:
    """Wait until a dialog has closed and handled everything queued for it (its message pump stopped)."""
    await watch.until(app, lambda: not screen.is_running and screen not in app.screen_stack,
                      f"{type(screen).__name__} to close")
