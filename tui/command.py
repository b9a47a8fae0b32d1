"""The installed `jointid` command: the core's command line, handed this package's explorer.

The core never imports the UI; without help it finds the explorer through the
`jointid.faces` entry point (jointid/cli/explorer_command.py), and that lookup
imports importlib.metadata, which benchmarks/bench_tui_startup.py shows as
`python -m jointid` starting slower than this command (benchmarks/README.md has
the figures). pip's `jointid` script starts here instead
(pyproject.toml) and passes the explorer in. A subcommand imports nothing of
the UI: the explorer's modules load only when it opens.
"""

from __future__ import annotations


def console_script() -> None:
    """`jointid`: jointid.cli.console_script with this package's explorer."""
    from jointid.cli import console_script as run_command_line

    run_command_line(explorer=explore)


def explore(*args, **kwargs) -> int:
    """tui.entry.explore, imported when the explorer opens (`jointid` with no subcommand)."""
    from .entry import explore as open_explorer

    return open_explorer(*args, **kwargs)
