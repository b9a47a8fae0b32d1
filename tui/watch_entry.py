"""`jointid watch` on a terminal: the explorer's watch view, reached through the `watch` entry point."""

from __future__ import annotations

from jointid.cli.arguments import UserError
from jointid.cli.exit_status import ExitStatus

from jointid.cli.watch_command import print_closing, watch_status

from .entry import Interrupt, exit_status


def watch_app(plan):
    """The explorer app opened on the watch view of `plan` (a jointid.cli.live_plan.WatchPlan)."""
    from .app import JointIdApp
    from .screens.watch import WatchScreen

    class WatchApp(JointIdApp):
        """The explorer with the watch view as its only screen."""

        SUB_TITLE = "Watching a joint move"

        def get_default_screen(self):
            """The watch view."""
            self.watch_screen = WatchScreen(plan)
            return self.watch_screen

    return WatchApp()


def watch(plan) -> int:
    """Run the watch view until the user leaves; print what was saved once the terminal is back; exit status.

    SIGINT (`kill -INT`) stops and saves as q does; the terminal's Ctrl+C is a key the view binds to the same.
    """
    from .app import NoTerminal

    app = watch_app(plan)
    app.restore_gc = False  # the process ends with the app (see JointIdApp.restore_gc)
    interrupt = StopOnInterrupt(app, plan)
    try:
        with interrupt.handling():
            app.run()
    except NoTerminal as error:
        plan.stop()
        raise UserError(str(error)) from None
    finally:
        plan.stop()  # the app may have ended by a crash: the watch thread must not outlive it
    saved = plan.save()  # the view saved already unless it crashed first; the first answer either way
    print_closing(plan, saved, plan.final_gains())
    status = exit_status(app, interrupted=interrupt.received)
    if status == ExitStatus.ERROR:
        return status
    return watch_status(plan, saved, interrupt.received)


class StopOnInterrupt(Interrupt):
    """SIGINT stops the watch and leaves once it is saved, as q does (exit status 130)."""

    def __init__(self, app, plan) -> None:
        """Handle SIGINT for `app` watching `plan`."""
        super().__init__(app)
        self.plan = plan

    def __call__(self, signum, frame) -> None:
        """Stop and save as q does, from the app's loop (or at once before it runs)."""
        self.received = True
        import asyncio

        try:
            loop = asyncio.get_running_loop()
        except RuntimeError:
            self.plan.stop()
            return
        loop.call_soon_threadsafe(self.app.watch_screen.action_stop)  # whichever screen is on top (the help)
