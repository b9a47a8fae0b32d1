"""`jointid report` of a large log against `jointid fit --json` of the same log.

Run from the repository root: PYTHONPATH=. .venv/bin/python benchmarks/bench_report.py [ROUNDS [ROWS]]

It writes a 1,000,000-row log of t, q, qd, qdd, tau (the rich motion at 1 kHz,
as bench_log_load's) to a temporary directory, then runs interleaved rounds of
three fresh processes, in rotating order: `jointid fit --csv FILE --json`
(what a user runs to get the numbers), `jointid report --csv FILE --out
REPORT.html --force` (the same fit, written as a page with its charts; needs
`jointid[report]`), and the same report with its charts drawn in the one
process (chart_process.ChartProcess made to start nothing, as a report without
the child process would run). All are the console script next to this
interpreter, with every import. It prints min / median / max of the per-round
ratios of wall times to the fit's (goal: the report's median <= 1.5), then,
from one report, its size, how many points each long path draws (dots thinned
to report_charts.MAX_POINTS), and the split of the report's own extra time
(the fit with the child running, building the blocks, drawing in the child;
importing matplotlib and drawing here) measured in this process. Exits 1 if
the goal is missed.
"""

from __future__ import annotations

import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from common import ENVIRONMENT, JOINTID, write_log  # this folder is first on sys.path

ROUNDS = 9
ROWS = 1_000_000
GOAL = 1.5

IN_ONE_PROCESS = [sys.executable, "-c", (
    "import sys; import jointid.present.chart_process as charts; "
    "charts.ChartProcess.__init__ = lambda self: setattr(self, 'process', None); "
    "from jointid.cli import console_script; sys.argv[0] = 'jointid'; console_script()")]
"""`jointid` with the chart process turned off: the charts are drawn after the fit, in the same process."""


def wall(command: list[str]) -> float:
    """Wall seconds of one fresh process run to its end (status 0 required)."""
    start = time.perf_counter()
    done = subprocess.run(command, cwd=ROOT, env=ENVIRONMENT, stdout=subprocess.DEVNULL, check=False)
    seconds = time.perf_counter() - start
    if done.returncode:
        raise SystemExit(f"{command} exited with {done.returncode}")
    return seconds


def split_in_process(log: Path) -> dict[str, float]:
    """Seconds of the report's steps, in this process: the fit with the chart process starting beside it, the
    blocks, the drawing in the child; then matplotlib's import and the drawing here, for comparison."""
    from jointid.cli import parse
    from jointid.cli.log_arguments import fit_loaded_logs
    from jointid.present.chart_process import ChartProcess
    from jointid.present.report import draw, logs_report

    args = parse(["report", "--csv", str(log), "--out", "unused.html"])
    times = {}
    start = time.perf_counter()
    charts = ChartProcess()
    logs = fit_loaded_logs(args)
    times["fit (chart process starting beside it)"] = time.perf_counter() - start
    start = time.perf_counter()
    report = logs_report(logs)
    times["blocks"] = time.perf_counter() - start
    start = time.perf_counter()
    draw(report, charts)
    times["charts drawn by the child (its import done meanwhile)"] = time.perf_counter() - start
    start = time.perf_counter()
    from jointid.present import report_charts

    report_charts.preload()
    times["import matplotlib here"] = time.perf_counter() - start
    start = time.perf_counter()
    draw(report)
    times["charts drawn here"] = time.perf_counter() - start
    return times


def main() -> int:
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else ROUNDS
    rows = int(sys.argv[2]) if len(sys.argv) > 2 else ROWS
    with tempfile.TemporaryDirectory() as folder:
        log, page = Path(folder) / "log.csv", Path(folder) / "report.html"
        write_log(log, rows)
        report_arguments = ["report", "--csv", str(log), "--out", str(page), "--force"]
        commands = {"fit --json": [*JOINTID, "fit", "--csv", str(log), "--json"],
                    "report": [*JOINTID, *report_arguments],
                    "report, charts in one process": [*IN_ONE_PROCESS, *report_arguments]}
        for command in commands.values():
            wall(command)  # warm the file cache and the bytecode
        ratios = {name: [] for name in list(commands)[1:]}
        for number in range(rounds):
            names = list(commands)[number % 3:] + list(commands)[:number % 3]  # each goes first in turn
            seconds = {name: wall(commands[name]) for name in names}
            for name, values in ratios.items():
                values.append(seconds[name] / seconds["fit --json"])
            print(f"round {number + 1}: " + ", ".join(f"{name} {seconds[name]:.2f} s" for name in commands), flush=True)
        text = page.read_text(encoding="utf-8")
        median = statistics.median(ratios["report"])
        print(f"\n{rows:,}-row log, {rounds} interleaved rounds; wall time / jointid fit --json's, min / median / max")
        for name, values in ratios.items():
            print(f"  jointid {name}: {min(values):.2f} / {statistics.median(values):.2f} / {max(values):.2f}"
                  + (f"; goal <= {GOAL} {'met' if median <= GOAL else 'MISSED'}" if name == "report" else ""))
        drawn = [path.count("L ") for path in re.findall(r'<path d="([^"]{20000,})"', text)]
        print(f"report: {len(text) / 1e6:.2f} MB of HTML; points per long path (dots and lines): {drawn}")
        for name, seconds in split_in_process(log).items():
            print(f"  {name}: {seconds:.3f} s")
    return 0 if median <= GOAL else 1


if __name__ == "__main__":
    sys.exit(main())
