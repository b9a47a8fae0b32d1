"""`jointid watch`: identify a joint while it moves, from a growing CSV or NetworkTables 4, refitted several times a
second; the explorer's watch view on a terminal, one line (or one JSON object) per refresh elsewhere; what was
received is saved as a log when watching stops."""

from __future__ import annotations

import argparse
import json
import os
import sys
from typing import TYPE_CHECKING

from .arguments import UserError, add_model_argument, positive_number
from .commands import SUBCOMMANDS
from .effort_arguments import add_effort_arguments, check_gains_request
from .exit_status import ExitStatus
from .log_arguments import UNIT_CHOICES, _column_map, _effort_scale, _entry_map, add_reading_arguments

if TYPE_CHECKING:
    from ..present.watch import Saved
    from ..studies.watch_refresh import WatchRefresh
    from ..studies.watch_session import WatchSession

NAME = "watch"

NT4_PORT = 5810
"""NetworkTables 4's default port (live.network_tables.DEFAULT_PORT; not imported: help starts without numpy)."""

HIGHEST_REFRESH_HZ = 60.0
"""More refreshes a second than a terminal shows are refused rather than spent on fits nobody sees."""


def add_parser(subparsers) -> None:
    """Attach the `watch` subcommand."""
    parser = subparsers.add_parser(
        NAME, help=SUBCOMMANDS[NAME].summary,
        description="Fit the joint while it moves, from a CSV that is still being written or from NetworkTables 4, "
        "and say the moment each parameter becomes well determined and what motion the others still need. On a "
        "terminal it opens the explorer's watch view (q stops); elsewhere it prints one line per refresh "
        "(--json-lines: one JSON object). With --save, what was received is written as a CSV log when watching "
        "stops (q, Ctrl+C, --duration, or the source's end).")
    source = parser.add_argument_group("the live source (one of)")
    sources = source.add_mutually_exclusive_group(required=True)
    sources.add_argument("--csv", metavar="PATH",
                         help="a CSV log being appended (a bench logger, a serial capture): read as it grows, a "
                         "partial last line waited for")
    sources.add_argument("--nt", metavar="HOST[:PORT]",
                         help=f"a NetworkTables 4 server (the robot, or WPILib's simulator at 127.0.0.1); port "
                         f"{NT4_PORT} by default; name the topics with --entry (needs pip install 'jointid[nt]')")
    source.add_argument("--entry", type=_entry_map, metavar="MAP",
                        help="which topic gives which quantity, as for a data log: e.g. q=/Arm/Position,"
                        "qd=/Arm/Velocity,tau=/Arm/Voltage (quantities: q, qd, qdd, tau, and state for a SysId "
                        "test-state topic)")
    source.add_argument("--columns", type=_column_map, metavar="MAP",
                        help="which CSV column gives which quantity, e.g. t=time,q=posn,tau=effort; default: by name")
    source.add_argument("--units", choices=UNIT_CHOICES, default=None,
                        help="the topics' unit for q, qd and qdd when their properties name none; default radians")
    reading = parser.add_argument_group("how the samples are read and fitted (as for a log)")
    add_model_argument(reading)
    reading.add_argument("--effort-scale", type=_effort_scale, metavar="K",
                         help="the effort's unit per unit of the logged effort, e.g. 12 for a duty cycle; default 1")
    add_reading_arguments(reading)
    reading.add_argument("--no-robust", action="store_true",
                         help="keep every sample: do not look for outside torques to leave out")
    add_effort_arguments(reading)
    watching = parser.add_argument_group("watching")
    watching.add_argument("--refresh", type=refresh_rate, default=None, metavar="HZ",
                          help="refits a second, above 0 and at most 60; default 4")
    watching.add_argument("--duration", type=positive_number, default=None, metavar="S",
                          help="stop after S seconds of watching; default: until q, Ctrl+C or the source's end")
    watching.add_argument("--gone", type=positive_number, default=None, metavar="S",
                          help="with --nt: stop when the server has been gone S seconds; default: wait for it to "
                          "return (the gap is said, never bridged)")
    watching.add_argument("--save", metavar="PATH",
                          help="when watching stops, write every sample received to this CSV log (atomically), "
                          "which `jointid fit --csv PATH` fits; refused up front if PATH exists, unless --force")
    watching.add_argument("--force", action="store_true", help="let --save replace an existing regular file")
    watching.add_argument("--json-lines", action="store_true",
                          help="print one JSON object per refresh on stdout (the last says what was saved), and "
                          "no explorer")


def refresh_rate(text: str) -> float:
    """argparse type of --refresh: refreshes a second, above 0 and at most HIGHEST_REFRESH_HZ."""
    value = positive_number(text)
    if value > HIGHEST_REFRESH_HZ:
        raise argparse.ArgumentTypeError(f"must be above 0 and at most {HIGHEST_REFRESH_HZ:g} refreshes a second; "
                                         f"got {text!r}")
    return value


def check_flags(args: argparse.Namespace) -> None:
    """UserError (one line) for flags that do not go together or a --save that would replace a file."""
    if args.nt is not None:
        if args.entry is None:
            raise UserError("--nt needs --entry q=TOPIC,tau=TOPIC (and qd, qdd or state topics when published), "
                            "e.g. --entry q=/Arm/Position,tau=/Arm/Voltage")
        stray = [flag for flag, value in (("--columns", args.columns), ("--degrees", args.degrees)) if value]
        if stray:
            raise UserError(f"{', '.join(stray)}: only for --csv; name NetworkTables topics with --entry and their "
                            "unit with --units")
    else:
        stray = [flag for flag, value in (("--entry", args.entry), ("--units", args.units), ("--gone", args.gone))
                 if value]
        if stray:
            raise UserError(f"{', '.join(stray)}: only for --nt; name a CSV's columns with --columns")
    offline = [flag for flag, value in (("--constrained", args.constrained), ("--motor-inertia", args.motor_inertia))
               if value]
    if offline:  # the live fit has no constraint and no rotor split: refused rather than silently ignored
        raise UserError(f"{', '.join(offline)}: not while watching; --save PATH, then jointid fit --csv PATH "
                        f"{' '.join(offline)} ...")
    motor = [flag for flag, value in (("--motor", args.motor), ("--motor-r", args.motor_r), ("--motor-kt",
                                      args.motor_kt), ("--motor-kv", args.motor_kv),
                                      ("--motor-count", args.motor_count)) if value is not None]
    if motor and args.gains is None:  # a watch uses the motor only to turn a torque fit into gains
        raise UserError(f"{', '.join(motor)}: while watching, only to turn the fit into --gains wpilib; add it, or "
                        "fit the saved log (--save PATH) with jointid fit --csv PATH")
    check_gains_request(args)
    if args.mechanism is not None and args.model is not None:
        raise UserError(f"--mechanism {args.mechanism} and --model {args.model}: a mechanism is a model; give one")
    if args.force and args.save is None:
        raise UserError("--force: only with --save PATH (it lets the saved log replace an existing file)")
    if args.save is not None:
        check_save_path(args.save, args.force, args.csv)


def check_save_path(path: str, force: bool, watched: str | None) -> None:
    """UserError when --save could not write `path` when watching stops: checked before anything is watched, so
    nobody learns at the end of a run that its samples cannot be kept."""
    from ..files import ExportError, refuse_special_destination, shown_path

    if watched is not None and os.path.exists(path) and os.path.exists(watched) and os.path.samefile(path, watched):
        raise UserError(f"--save {shown_path(path)}: that is the CSV being watched; save to another file")
    try:
        refuse_special_destination(path)
    except ExportError as error:
        raise UserError(f"--save {error}") from None
    if os.path.lexists(path) and not force:
        raise UserError(f"--save {shown_path(path)}: already exists; add --force to replace it")
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise UserError(f"--save {shown_path(path)}: no folder {shown_path(folder)} to write it in")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise UserError(f"--save {shown_path(path)}: the folder {shown_path(folder)} is not writable")


def run(args: argparse.Namespace) -> int:
    """Watch the source until q, Ctrl+C, --duration or its end; save what was received (--save); exit status."""
    check_flags(args)
    from ..studies.watch_session import DEFAULT_REFRESH_HZ
    from .live_plan import open_watch

    plan = open_watch(args, DEFAULT_REFRESH_HZ if args.refresh is None else args.refresh)
    if not args.json_lines and _on_terminal():
        from .explorer_command import load_explorer

        return load_explorer("watch")(plan)
    return watch_in_text(plan, args.json_lines)


def _on_terminal() -> bool:
    """Whether the explorer can open: keys from a terminal, drawing on one."""
    return sys.stdin is not None and sys.stdin.isatty() and sys.stdout.isatty()


def watch_in_text(plan, json_lines: bool) -> int:
    """Print one line (or JSON object) per refresh until the watch stops; then what was saved. Ctrl+C stops it as
    q would, and what was received is still saved (exit status 130)."""
    from ..present.watch import refresh_line, refresh_object, saved_object

    def show(refresh: WatchRefresh) -> None:
        print(_json_line(refresh_object(refresh)) if json_lines else refresh_line(refresh), flush=True)

    with InterruptStops(plan.session) as interrupted:
        stopped_by = plan.watch(show)
    saved = plan.save()
    if plan.session.last is None and plan.session.failure is not None:
        return watch_status(plan, saved, bool(interrupted))  # the source failed before anything: its line alone
    gains = plan.final_gains()
    if json_lines:
        closing = saved_object(saved, "interrupt" if interrupted else stopped_by)
        if plan.gains_asked:
            from ..present.gains import gains_object

            closing["gains"] = None if gains is None else gains_object(gains)
        print(_json_line(closing), flush=True)
    else:
        print_closing(plan, saved, gains)
    return watch_status(plan, saved, bool(interrupted))


def print_closing(plan, saved: Saved, gains) -> None:
    """What a text watch (and the watch view, once the terminal is back) prints when it stops: the determinations,
    the advice, the gains asked for, and what was saved."""
    from ..present.watch import closing_lines, saved_sentence

    last = plan.session.last
    for line in (closing_lines(last) if last is not None else ()):
        print(line)
    if plan.gains_asked:
        from ..present.gains import gains_text

        print(gains_text(gains) if gains is not None else "No gains: the watch ended before a unique fit.")
    print(saved_sentence(saved), flush=True)


def watch_status(plan, saved: Saved, interrupted: bool) -> int:
    """The exit status once a watch stopped and saved: 2 (with the line why on stderr) when the source could not be
    read on or --save could not write what was received, 130 after Ctrl+C, else 0."""
    from .arguments import print_error_line

    if plan.session.failure is not None:
        print_error_line(f"jointid: {plan.session.failure}")
        return ExitStatus.USER_ERROR
    if saved.path is None and plan.save_path is not None and saved.samples:
        return ExitStatus.USER_ERROR  # --save's log could not be written (the output said why); none received is no error
    return ExitStatus.INTERRUPTED if interrupted else ExitStatus.SUCCESS


def _json_line(document: dict) -> str:
    """A document as one line of strict JSON (NaN and infinities are None already)."""
    return json.dumps(document, allow_nan=False, separators=(",", ":"))


class InterruptStops:
    """While the block runs, SIGINT (Ctrl+C) asks the session to stop instead of raising KeyboardInterrupt, so the
    last refresh is shown and the samples saved; the context value is a list that is true once it came."""

    def __init__(self, session: WatchSession) -> None:
        self.session = session
        self.received: list[bool] = []
        self.previous = None

    def __enter__(self) -> list[bool]:
        import signal
        import threading

        if threading.current_thread() is threading.main_thread():
            self.previous = signal.signal(signal.SIGINT, self._handle)
        return self.received

    def _handle(self, signum, frame) -> None:
        if self.received:  # a second Ctrl+C: the user means it
            raise KeyboardInterrupt
        self.received.append(True)
        self.session.stop()

    def __exit__(self, *exc) -> None:
        if self.previous is not None:
            import signal

            signal.signal(signal.SIGINT, self.previous)
