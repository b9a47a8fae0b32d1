"""The report's charts drawn in a second process, started before the fit, so that importing matplotlib overlaps it.

Importing matplotlib takes about a quarter of a second, a third of what a
report adds to a million-row fit; started first, a child process has it
imported by the time the fit is done (on the machine's other core), and the
parent sends it the chart series and reads back the SVG texts. Anything going
wrong with the child (it could not start, matplotlib is missing, it died) only
means the charts are drawn here instead, where a missing matplotlib gives its
one line.

The protocol is one pickle each way over the child's stdin and stdout: a list
of (function name in `report_charts`, arguments) in, a list of SVG texts (or
an exception) out.
"""

from __future__ import annotations

import os
import pickle
import subprocess
import sys

DRAWINGS = ("torque_svg", "residuals_svg")
"""The `report_charts` functions a request may name."""


class ChartProcess:
    """A child process that imports matplotlib at once and then draws the charts it is sent."""

    def __init__(self) -> None:
        try:
            self.process = subprocess.Popen([sys.executable, "-m", __name__], stdin=subprocess.PIPE,
                                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
        except OSError:
            self.process = None

    def draw(self, requests: list[tuple[str, tuple]]) -> list[str] | None:
        """The SVG text of each (function name, arguments) request, or None when the child could not draw them."""
        if self.process is None:
            return None
        try:
            answer, _ = self.process.communicate(pickle.dumps(requests, pickle.HIGHEST_PROTOCOL))
            result = pickle.loads(answer)
        except (OSError, EOFError, pickle.UnpicklingError):
            return None
        finally:
            self.close()
        return result if isinstance(result, list) else None

    def close(self) -> None:
        """End the child if it still runs (the parent stopped early: a bad log, Ctrl+C)."""
        if self.process is not None and self.process.poll() is None:
            self.process.kill()
            self.process.wait()


def draw_charts(requests: list[tuple[str, tuple]], process: ChartProcess | None = None) -> list[str]:
    """Each request's SVG text: from `process` when it can, else drawn here (ReportExtraMissing without
    matplotlib)."""
    drawn = None if process is None or not requests else process.draw(requests)
    if drawn is not None and len(drawn) == len(requests):
        return drawn
    from . import report_charts

    return [getattr(report_charts, name)(*arguments) for name, arguments in requests]


def serve() -> None:
    """The child: import matplotlib now, then draw what stdin asks for and write the SVG texts to stdout."""
    from . import report_charts

    try:
        report_charts.preload()
        requests = pickle.load(sys.stdin.buffer)
        answer = [getattr(report_charts, name)(*arguments) for name, arguments in requests if name in DRAWINGS]
    except Exception as error:  # noqa: BLE001  any failure: the parent draws the charts itself
        answer = repr(error)
    sys.stdout.buffer.write(pickle.dumps(answer, pickle.HIGHEST_PROTOCOL))
    sys.stdout.flush()
    os._exit(0)  # at once: the parent waits for the end of the output, and freeing matplotlib's modules takes a while


if __name__ == "__main__":
    serve()
