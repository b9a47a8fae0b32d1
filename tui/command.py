"""The installed `jointid` command: the core's command line, handed this package's explorer.

The core never imports the UI; without help it finds the explorer through the
`jointid.faces` entry point (jointid/cli/explorer_command.py), a lookup that
imports importlib.metadata. Sparing it, with the adapters' versions read from
their dist-info folders, buys 0.04 of the explorer's start (bench_startup_budget
metadata-off-explorer-start): under the budget's 5 %, kept for the explorer's
1.10x start-up limit (benchmarks/README.md, "Start-up budget"). pip's `jointid`
script starts here instead (pyproject.toml) and passes the explorer in. A
subcommand imports nothing of the UI: the explorer's modules load only when it
opens.
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
