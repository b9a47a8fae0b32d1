"""Command-line start-up: `jointid` commands as fresh processes against Python's own start and `import numpy`.

Run from the repository root: PYTHONPATH=. .venv/bin/python benchmarks/bench_cli_startup.py [ROUNDS]

Each command runs as a user runs it, through the `jointid` console script next
to this interpreter (or `python -m jointid` without one), output discarded.
Every round launches each command once right beside a launch of its
baseline (which of the two goes first alternates), in an order rotated from
round to round, and divides the command's wall time by that baseline's:

- `jointid --help` and every subcommand's `--help` (whatever
  `jointid.cli.SUBCOMMANDS` lists) by `python -c pass`; goal <= 2.0. The floor
  printed beside them is a script that builds an argparse parser and prints its
  help, which no help text can undercut.
- `jointid fit` for every training motion, as text and with --json, and
  `sweep`, `matrix` and `torque` with their defaults, by
  `python -c "import numpy"`; goal <= 1.3. The floor printed beside them is
  `python -c "import numpy, argparse, json, dataclasses"`, the stack any
  numeric command needs before its own code.

It prints min / median / max of the per-round ratios of wall time (the goals)
and, beside them, of CPU time (user + system of the child, which the other
work on this shared machine disturbs much less), and whether each wall
median meets its goal; the run exits 1 if one does not. Python may cache bytecode, as
on a user's machine (this VM sets PYTHONDONTWRITEBYTECODE; it is unset for the
runs, and one warm-up round writes the caches).
"""

from __future__ import annotations

import statistics
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from common import JOINTID, launch  # noqa: E402

from jointid.cli import SUBCOMMANDS  # noqa: E402
from jointid.options import TRAINING_MOTION_NAMES  # noqa: E402

ROUNDS = 9
HELP_GOAL = 2.0
COMMAND_GOAL = 1.3


PYTHON_START = [sys.executable, "-c", "pass"]
NUMPY_IMPORT = [sys.executable, "-c", "import numpy"]
HELP_FLOOR = [sys.executable, "-c", "import argparse; argparse.ArgumentParser(prog='x').print_help()"]
COMMAND_FLOOR = [sys.executable, "-c", "import numpy, argparse, json, dataclasses"]

HELPS = {"jointid --help": ["--help"]} | {f"jointid {name} --help": [name, "--help"] for name in SUBCOMMANDS}
COMMANDS = {
    **{f"jointid fit --motion {motion}{flag}": ["fit", "--motion", motion, *flag.split()]
       for motion in TRAINING_MOTION_NAMES for flag in ("", " --json")},
    "jointid sweep": ["sweep"],
    "jointid matrix": ["matrix"],
    "jointid torque --q 1 --qd 2 --qdd 3": ["torque", "--q", "1", "--qd", "2", "--qdd", "3"],
}


def spread(values: list[float]) -> str:
    """'min / median / max' of per-round ratios."""
    return f"{min(values):.2f} / {statistics.median(values):.2f} / {max(values):.2f}"


def main() -> int:
    """Time every command against its baseline, in adjacent pairs round by round, and print the ratios."""
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else ROUNDS
    help_runs = {"help floor (argparse help)": HELP_FLOOR} | {name: JOINTID + args for name, args in HELPS.items()}
    command_runs = {"command floor (numpy, argparse, json, dataclasses)": COMMAND_FLOOR} | {
        name: JOINTID + args for name, args in COMMANDS.items()}
    pairs = [(name, command, PYTHON_START) for name, command in help_runs.items()]
    pairs += [(name, command, NUMPY_IMPORT) for name, command in command_runs.items()]
    for _, command, baseline in pairs:  # warm-up: write bytecode caches, fill the page cache
        launch(command), launch(baseline)
    ratios: dict[str, list[float]] = {name: [] for name, _, _ in pairs}
    cpu_ratios: dict[str, list[float]] = {name: [] for name, _, _ in pairs}
    baselines: dict[str, list[float]] = {"pass": [], "numpy": []}
    for index in range(rounds):
        shift = index * len(pairs) // rounds
        for turn, (name, command, baseline) in enumerate(pairs[shift:] + pairs[:shift]):
            # Each command right beside its baseline, which goes first every other time.
            if (index + turn) % 2:
                base, own = launch(baseline), launch(command)
            else:
                own, base = launch(command), launch(baseline)
            ratios[name].append(own[0] / base[0])
            cpu_ratios[name].append(own[1] / base[1])
            baselines["pass" if baseline is PYTHON_START else "numpy"].append(base[0])

    print(f"jointid command-line start-up: {rounds} interleaved rounds, fresh processes, {' '.join(JOINTID)}")
    print(f"python -c pass: median {statistics.median(baselines['pass']) * 1e3:.0f} ms; import numpy: median "
          f"{statistics.median(baselines['numpy']) * 1e3:.0f} ms (for scale only: the goals are the ratios)")
    missed = []
    for title, runs, goal in ((f"ratio to python -c pass (goal <= {HELP_GOAL:.1f})", help_runs, HELP_GOAL),
                              (f"ratio to python -c 'import numpy' (goal <= {COMMAND_GOAL:.1f})", command_runs,
                               COMMAND_GOAL)):
        print()
        print(f"{title:<54}{'wall: min / median / max':<26}CPU: min / median / max")
        for position, name in enumerate(runs):
            values = ratios[name]
            verdict = ""
            if position:  # the first line is the floor, without a goal
                met = statistics.median(values) <= goal
                verdict = "  met" if met else "  MISSED"
                missed += [] if met else [name]
            print(f"  {name:<52}{spread(values):<26}{spread(cpu_ratios[name])}{verdict}")
    print()
    print("goals met: all" if not missed else f"goals missed: {', '.join(missed)}")
    return 1 if missed else 0


if __name__ == "__main__":
    raise SystemExit(main())
