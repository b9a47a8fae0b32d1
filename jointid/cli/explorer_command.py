"""`jointid` with no subcommand: the terminal explorer."""

from __future__ import annotations

from .arguments import UserError


def run(args) -> int:
    """Open the explorer (not built yet: say so)."""
    raise UserError("the terminal explorer is not available yet; use `jointid fit` (see --help)")
