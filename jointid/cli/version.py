"""`jointid --version`: this release, the versions of the stack, and whether the explorer's adapters apply."""

from __future__ import annotations

import argparse

from .exit_status import ExitStatus

ENTRY_POINT_GROUP = "jointid.faces"
"""Where the terminal UI registers its entry functions (see pyproject.toml)."""
ADAPTER_STATUS = "adapter-status"
"""The UI's function that reports which third-party adapters apply, one line each."""

STACK = ("numpy", "textual", "textual-plotext", "plotext")
"""Distributions whose versions the output names: the core's, then the explorer's."""


def _version(distribution: str) -> str:
    from importlib import metadata  # here, as only --version reads it: 0.11 of a fit's start (bench_startup_budget)

    try:
        return metadata.version(distribution)
    except metadata.PackageNotFoundError:
        return "not installed"


def version_text() -> str:
    """The lines `jointid --version` prints, read from package metadata (nothing is imported but the adapter table).

    Returns
    -------
    str
        `jointid <version>`, one line per package of the stack, and the
        explorer's third-party adapters as it would set them up at start.
    """
    from importlib import metadata

    lines = [f"jointid {_version('jointid')}"]
    lines += [f"{name} {_version(name)}" for name in STACK]
    # The UI registers its adapter report under the faces entry point (as it does the explorer), so
    # the core never imports it; the report reads versions from metadata and imports no UI package.
    found = metadata.entry_points(group=ENTRY_POINT_GROUP, name=ADAPTER_STATUS)
    try:
        status = next(iter(found)).load()()
    except (StopIteration, ImportError) as error:
        lines.append(f"explorer adapters: unavailable ({error or 'the terminal UI is not installed'})")
    else:
        lines.append("explorer adapters (the pinned versions' internals, else the stock path):")
        lines += [f"  {line}" for line in status]
    return "\n".join(lines)


class VersionAction(argparse.Action):
    """`--version`: print `version_text()` and exit 0, before any other argument is checked."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS, help=None):
        """Create the flag (it takes no value), as argparse's own version action does."""
        super().__init__(option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        """Print the versions and exit."""
        print(version_text())
        parser.exit(ExitStatus.SUCCESS)
