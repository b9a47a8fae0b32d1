"""Run the command line as `python -m jointid`."""

from .cli import main

raise SystemExit(main())
