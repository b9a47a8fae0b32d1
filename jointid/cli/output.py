"""What the subcommands print as JSON (strict JSON only, never Infinity or NaN), and how a run's output ends."""

from __future__ import annotations

import os
import sys

from .arguments import UserError
from .exit_status import ExitStatus

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (2.5 ms of every --help)
if TYPE_CHECKING:
    from typing import NoReturn


def output_error_line(error: OSError) -> str:
    """The one line for an output stream that cannot be written."""
    return f"jointid: cannot write the output: {error.strerror or error}"


def end_process(status: int) -> NoReturn:
    """Flush what was printed and end the process at once with `status` (USER_ERROR if the output cannot be written).

    For the console script after a subcommand: every file it wrote is closed by then, and the interpreter's
    teardown (freeing every module's objects one by one) only does what the operating system does when the
    process ends; skipping it buys 0.10 of `jointid fit`'s start (bench_startup_budget end-process). A reader
    that left (`jointid fit | head -1`) is no error.
    """
    try:
        sys.stdout.flush()
    except BrokenPipeError:
        pass
    except OSError as error:
        status = ExitStatus.USER_ERROR
        print(output_error_line(error), file=sys.stderr)
    try:
        sys.stderr.flush()
    except OSError:
        pass
    os._exit(int(status))


def print_json(document) -> None:
    """Print a document as strict JSON; UserError (one line) if any value in it is not finite."""
    from ..present.documents import NonFiniteValue, json_text  # numpy-backed: only when printing

    try:
        text = json_text(document)
    except NonFiniteValue as error:
        # A value the documents did not already turn into null: refuse rather than print a
        # non-standard token that strict parsers reject.
        raise UserError(
            f"the result's {error.key} is not a finite number (it overflows double precision); "
            "no JSON printed: use smaller values"
        ) from None
    print(text)
