"""What `bag-info` and `log-info` share: a parser of one path and --json, and the survey printed as text or JSON."""

from __future__ import annotations

from .arguments import UserError
from .commands import SUBCOMMANDS
from .exit_status import ExitStatus


def add_survey_parser(subparsers, name: str, description: str, metavar: str, what: str) -> None:
    """Attach a subcommand `name` that surveys the file at PATH (`metavar`, `what` it is) and takes --json."""
    parser = subparsers.add_parser(name, help=SUBCOMMANDS[name].summary, description=description)
    parser.add_argument("path", metavar=metavar, help=what)
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of text")


def print_survey(survey, path: str, text, as_json: bool) -> int:
    """Print `survey(path)` as `text(info)` or its JSON; exit status 0, a UserError (one line) for an unreadable
    file."""
    from ..logs.table import LogError
    from .output import print_json

    try:
        info = survey(path)
    except LogError as error:
        raise UserError(str(error)) from None
    if as_json:
        print_json(info.to_dict())
    else:
        print(text(info))
    return ExitStatus.SUCCESS
