"""Argument types and the parser class shared by every subcommand (no numpy: help must start fast)."""

from __future__ import annotations

import argparse
import math
import os
import re
import sys
TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (2.5 ms of every --help)

from ..options import (
    FIELDS,
    LOG_MODEL,
    SETTING_DEFAULTS,
    TRAINING_MOTION_NAMES,
    VOLTAGE_LOG_MODEL,
    SettingsError,
    describe_models,
    parse_float,
    parse_int,
    parse_setting,
)
from .exit_status import ExitStatus

if TYPE_CHECKING:
    from ..synthetic.settings import Settings


class UserError(Exception):
    """A mistake in the user's input; main prints its message as one line and exits 2."""


def print_error_line(message: str) -> None:
    """Print an error message on stderr as exactly one line, whatever a path or value quoted in it holds.

    Every character that is not printable (a newline in a file name, a tab, a terminal escape) is written as its
    backslash escape, so a script reading stderr line by line, or a person, sees one message.
    """
    if not message.isprintable():
        message = "".join(c if c.isprintable() else repr(c)[1:-1] for c in message)
    print(message, file=sys.stderr)


_NEGATIVE_VALUE = re.compile(r"-(\d|\.\d|inf|nan)", re.IGNORECASE)
"""A token argparse would take for an option although it is a number: '-inf', '-nan', '-1e5' (and '-2')."""


def attach_negative_values(argv: list[str]) -> list[str]:
    """['--noise', '-inf'] -> ['--noise=-inf'], so that a negative number after a flag is its value.

    argparse reads only '-2'-like tokens as negative numbers; '-inf', '-nan' and
    '-1e5' would be unknown options, and the flag would seem to lack its value.
    """
    joined: list[str] = []
    for token in argv:
        previous = joined[-1] if joined else ""
        if previous.startswith("--") and previous != "--" and "=" not in previous and _NEGATIVE_VALUE.match(token):
            joined[-1] = f"{previous}={token}"
        else:
            joined.append(token)
    return joined


MAX_ARGUMENTS = 4096
"""Most command-line words a command takes: argparse before Python 3.13 scans every option's position for each
option it reads (quadratic: 20,000 repeats of a flag took 17 s), and a real command line needs far fewer."""


def terminal_columns() -> int:
    """shutil.get_terminal_size().columns (COLUMNS, else the terminal's width, else 80) without importing shutil,
    which loads zlib, bz2 and lzma: about 2 ms of every --help."""
    try:
        columns = int(os.environ["COLUMNS"])
    except (KeyError, ValueError):
        columns = 0
    if columns > 0:
        return columns
    try:
        return os.get_terminal_size(sys.__stdout__.fileno()).columns or 80
    except (AttributeError, ValueError, OSError):
        return 80


class HelpFormatter(argparse.HelpFormatter):
    """argparse's help formatter, as wide as argparse makes it (the terminal less 2), found by terminal_columns."""

    def __init__(self, prog, *args, width=None, **kwargs):
        super().__init__(prog, *args, width=terminal_columns() - 2 if width is None else width, **kwargs)


class OneLineParser(argparse.ArgumentParser):
    """An ArgumentParser whose errors are one line on stderr and exit status 2 (no usage dump).

    Whole option names only (`fit --n 5` must not mean --noise 5), also for the
    subcommands' parsers, which argparse builds from this class; a negative
    number after a flag is that flag's value.
    """

    def __init__(self, *args, allow_abbrev: bool = False, formatter_class=HelpFormatter, **kwargs):
        super().__init__(*args, allow_abbrev=allow_abbrev, formatter_class=formatter_class, **kwargs)

    def parse_known_args(self, args=None, namespace=None):
        """argparse's parse_known_args after `attach_negative_values`; at most MAX_ARGUMENTS words."""
        args = sys.argv[1:] if args is None else list(args)
        if len(args) > MAX_ARGUMENTS:
            self.error(f"{len(args):,} command-line arguments; at most {MAX_ARGUMENTS:,} (repeat a flag fewer "
                       "times)")
        return super().parse_known_args(attach_negative_values(args), namespace)

    def error(self, message: str):
        """Print `<prog>: <message>` and exit with status 2 (ExitStatus.USER_ERROR)."""
        print_error_line(f"{self.prog}: {message}")
        raise SystemExit(ExitStatus.USER_ERROR)

    def print_help(self, file=None):
        """argparse's help, whose write errors are not swallowed (argparse ignores them: `--help > /dev/full` would
        exit 0 having printed nothing); main turns them into one line and status 2."""
        self._write_out(self.format_help(), file)

    def print_usage(self, file=None):
        """argparse's usage line, with write errors raised as for `print_help`."""
        self._write_out(self.format_usage(), file)

    @staticmethod
    def _write_out(text: str, file) -> None:
        file = sys.stdout if file is None else file
        file.write(text)
        file.flush()  # a full disk only shows when the buffer is written out


def setting_type(field: str):
    """An argparse type that parses and range-checks one experiment setting."""

    def parse(text: str):
        try:
            return parse_setting(field, text)
        except SettingsError as error:
            raise argparse.ArgumentTypeError(_without_field(str(error), field)) from None

    parse.__name__ = field  # argparse names the type in some messages
    return parse


def _without_field(message: str, field: str) -> str:
    """'noise must be ...' -> 'must be ...', since argparse already names the flag."""
    return message[len(field) + 1 :] if message.startswith(field + " ") else message


def finite_float(text: str) -> float:
    """An argparse type for any finite real number in ASCII decimal notation."""
    try:
        value = parse_float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a finite number; got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be a finite number; got {text!r}")
    return value


def bounded_number(low: float, high: float):
    """An argparse type for a finite number from `low` to `high`."""

    def parse(text: str) -> float:
        value = finite_float(text)
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(f"must be a number from {low:g} to {high:g}; got {text!r}")
        return value

    return parse


def positive_number(text: str) -> float:
    """An argparse type for a finite number greater than zero."""
    value = finite_float(text)
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be a finite number greater than 0; got {text!r}")
    return value


def whole_number(low: int, high: int | None = None):
    """An argparse type for an integer of at least `low` (and at most `high`, when given)."""
    allowed = f"at least {low}" if high is None else f"from {low} to {high:,}"

    def parse(text: str) -> int:
        try:
            value = parse_int(text)
        except ValueError:
            value = None
        if value is None or value < low or (high is not None and value > high):
            raise argparse.ArgumentTypeError(f"must be a whole number {allowed}; got {text!r}")
        return value

    return parse


def add_model_argument(parser: argparse.ArgumentParser) -> None:
    """Add --model and --constrained, how to fit (for synthetic experiments and logs alike)."""
    parser.add_argument("--model", type=setting_type("model"), default=None, metavar="NAME",
                        help=f"fitted model: {describe_models()}; default {SETTING_DEFAULTS['model']} "
                        f"(the lesson's), {LOG_MODEL} for a log (real joints have friction and sensor bias), and "
                        f"{VOLTAGE_LOG_MODEL} for a voltage log (SysId's arm)")
    parser.add_argument("--constrained", action="store_true",
                        help="fit subject to the sign rules (I at least 1e-6 kg m², h, B, Fc at least 0), "
                        "beside the unconstrained fit; off by default")


def add_settings_arguments(parser: argparse.ArgumentParser) -> None:
    """Add --motion, --noise, --samples, --seed and the synthetic joint's --true-* physics, with the lesson's defaults."""
    defaults = SETTING_DEFAULTS
    flags = {
        "motion": (
            "{" + ",".join(TRAINING_MOTION_NAMES) + "}",
            "training motion: rich (two sines), slow (one small slow sine) or holds "
            f"(q = qd = qdd = 0); default {defaults['motion']}",
        ),
        "noise": (
            "X",
            f"bound of the uniform training-torque noise, 0 to 100 N m; default {defaults['noise']:.2f}",
        ),
        "samples": ("N", f"training samples over 0..8 s, 2 to 10000000; default {defaults['samples']}"),
        "seed": ("S", f"noise seed, 0 to 4294967295; default {defaults['seed']}"),
        "true_coulomb": ("FC", "the synthetic joint's Coulomb friction: it adds FC*sign(qd), 0 to 10 N m; "
                               "default 0"),
        "true_bias": ("TAU0", "the torque sensor reads TAU0 too much on every sample, -10 to 10 N m; default 0"),
        "true_angle_offset": ("Q0", "the encoder's zero is off: the logged angle is q_true - Q0, -0.5 to 0.5 rad; "
                                    "default 0"),
    }
    motions = parser.add_mutually_exclusive_group()  # --motion and --motion-file: one training motion
    for field, (metavar, help_text) in flags.items():
        (motions if field == "motion" else parser).add_argument(
            f"--{field.replace('_', '-')}",
            dest=field,
            type=setting_type(field),
            default=defaults[field],
            metavar=metavar,
            help=help_text,
        )
    add_motion_file_argument(motions)


def add_motion_file_argument(parser) -> None:
    """Add --motion-file FILE: train on a motion file that `jointid design --out` wrote."""
    parser.add_argument("--motion-file", metavar="FILE", default=None,
                        help="train on this motion file (JSON, from jointid design --out) instead of --motion")


def motion_from_file(path: str):
    """The FourierMotion a --motion-file names; UserError (one line naming the file and the problem) if it is bad."""
    from ..synthetic.fourier import MotionFileError, load_motion

    try:
        return load_motion(path)
    except MotionFileError as error:
        raise UserError(str(error)) from None


def settings_from(args: argparse.Namespace) -> Settings:
    """The Settings named by the parsed synthetic-setting arguments (and --model, where the command has it)."""
    from ..synthetic.settings import Settings  # dataclasses: only once a command runs

    values = {field: SETTING_DEFAULTS[field] if getattr(args, field, None) is None else getattr(args, field)
              for field in FIELDS}
    if getattr(args, "motion_file", None) is not None:
        values["motion"] = motion_from_file(args.motion_file)
    return Settings(**values)
