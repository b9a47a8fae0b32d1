"""Run the command line as `python -m jointid`."""

from .cli import console_script

console_script()
