"""`jointid` with no subcommand: the terminal explorer, on synthetic settings or on a --csv, --bag or --wpilog log.

The core never imports the terminal UI. The UI registers one entry function
under the `jointid.faces` entry-point group (see pyproject.toml); this command
parses and checks what the core can check, then hands everything to it. The
entry function checks the explorer's own, narrower ranges and raises
SettingsError for a value outside them.

The installed `jointid` command starts in the UI (tui/command.py), which hands
the entry function over itself, sparing the entry-point lookup that `python -m
jointid` still makes (tui/command.py has the figure).
"""

from __future__ import annotations

from ..options import SettingsError
from .arguments import UserError, settings_from
from .floating_point import strict_arithmetic
from .log_arguments import (
    LOG_ONLY_FLAGS,
    convention_options,
    derivative_options,
    filter_options,
    fit_any_logs,
    has_log,
    log_model,
    with_default_settings,
)
from .version import ENTRY_POINT_GROUP

ENTRY_POINT_NAME = "explorer"
"""The entry function's name in that group: explore(settings, logs, derivatives, filtering, conventions) -> exit
status."""


CHECK_ENTRY_POINT_NAME = "check-settings"
"""The function in that group that raises SettingsError for settings outside the explorer's (narrower) ranges."""


def load_explorer(name: str = ENTRY_POINT_NAME):
    """The registered explorer entry function (or another of the face's functions by name); UserError when no UI
    is installed."""
    from importlib.metadata import (
        entry_points,  # here: no subcommand needs it (version.py has the figure)
    )

    found = entry_points(group=ENTRY_POINT_GROUP, name=name)
    if not found:
        raise UserError("the terminal explorer is not installed; reinstall jointid with `pip install -e .`")
    return next(iter(found)).load()


def run(args, explore=None) -> int:
    """Open the explorer at the settings given by the flags, or on the --csv log; its exit status.

    `explore` is the explorer's entry function, or None to find it (load_explorer).
    """
    # A bad log is one line on stderr and status 2 before the app starts, as for `jointid fit --csv/--bag`.
    with strict_arithmetic():
        loaded = fit_any_logs(args) if has_log(args) else None
    derivatives = derivative_options(args)  # also for logs opened later with Ctrl+O
    filtering = filter_options(args)
    conventions = convention_options(args)  # before _defaults clears the log flags
    settings = settings_from(with_default_settings(args) if loaded is None else _defaults(args, loaded))
    if explore is None:
        explore = load_explorer()
    try:
        return explore(settings, loaded, derivatives, filtering, conventions)
    except SettingsError as error:  # outside the explorer's ranges: `jointid fit` takes more
        raise UserError(str(error)) from None


def _defaults(args, loaded):
    """The synthetic defaults behind a log (load_logs has refused any setting flag already)."""
    model = log_model(args)  # before the log flags (--effort) are cleared
    for name in LOG_ONLY_FLAGS:
        setattr(args, name, None)
    if args.model is None:  # the explorer refits the log with its model setting: the model it was fitted with
        runs = getattr(loaded, "runs", None)
        args.model = (runs[0] if runs else loaded).result.model.name if loaded is not None else model
        from ..options import ModelError, model_extras

        try:
            model_extras(args.model)
        except ModelError:  # a SysId log in metres: its model has no name the settings take (its refits say so)
            args.model = model
    return with_default_settings(args)
