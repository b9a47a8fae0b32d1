"""The report's charts as SVG text, drawn by matplotlib's SVG backend (the optional `jointid[report]` extra).

Each chart draws what the explorer's does, from the same chart series
(`jointid.present.charts`): measured torques as dots, the fit as a line, the
samples the fit left out faint and the stretches of outside torque shaded.
Text and axes are drawn in `currentColor` on a transparent background, so a
chart inherits the page's text colour and reads on paper and in a dark browser
theme alike; the data colours (a blue and an orange) read on both. Text stays
text (selectable, searchable), and the output is byte-for-byte the same for the
same data: no date, no random ids, no creator link.

matplotlib is imported only when a report is drawn, through its SVG canvas
(no GUI toolkit, no pyplot state).
"""

from __future__ import annotations

import io
import re
from typing import TYPE_CHECKING

import numpy as np

from .charts import thin_stride
from .text import ordinal

if TYPE_CHECKING:
    from .charts import ChartData, ScatterData

EXTRA_HINT = "writing a report needs the optional matplotlib package: pip install 'jointid[report]'"
"""The one line a report gives when matplotlib is missing."""

MAX_POINTS = 2000
"""Most points a chart draws: a million dots would make a 100 MB page that no browser scrolls, and at a report's
width 2,000 already overlap; a thinned chart says so in its summary."""

TEXT_COLOUR = "#010203"
"""A colour no chart uses otherwise, drawn for text, axes and ticks and then replaced by currentColor."""
DOTS_COLOUR = "#2b83d0"
"""Measured torques: a blue of middle lightness, readable on white and on near-black."""
LINE_COLOUR = "#ff7f0e"
"""The fitted or predicted line (orange)."""
FAINT_ALPHA = 0.25
"""How strongly the dots the fit left out are drawn: as the explorer's muted colour."""
SHADE_COLOUR = "#d9a400"
"""Stretches left out for an outside torque (amber, as the explorer's warning colour), drawn light."""
SHADE_ALPHA = 0.22
MARGINS = {"left": 0.1, "right": 0.985, "bottom": 0.15, "top": 0.8}
"""The plot's place in the figure, as shares of its width and height."""
TITLE_HEIGHT = 1.13
"""Where a title sits, in shares of the plot's height: given, so matplotlib does not measure the tick labels
beneath it on every draw to place it (a tenth of the drawing time)."""
FIGURE_SIZE = (7.5, 3.2)
RESIDUALS_SIZE = (7.5, 5.4)
"""The residual views' figure: four plots, two by two."""
RESIDUALS_MARGINS = {"left": 0.1, "right": 0.985, "bottom": 0.09, "top": 0.93, "wspace": 0.2, "hspace": 0.38}
"""Inches at 72 points each: about 540 x 230 CSS pixels, scaled to the page's width."""


class ReportExtraMissing(ImportError):
    """matplotlib is not installed; str() is the one line naming the extra."""


def _matplotlib():
    """matplotlib's Figure and SVG canvas, with the settings every report chart uses; ReportExtraMissing without it."""
    try:
        import matplotlib
        from matplotlib.backends.backend_svg import FigureCanvasSVG
        from matplotlib.figure import Figure
    except ImportError:
        raise ReportExtraMissing(EXTRA_HINT) from None
    matplotlib.rcParams.update({
        "svg.fonttype": "none",  # text as <text>: selectable, and no font is embedded or fetched
        # Titles hold file names: "$5 and $6.csv" is text, not math (as math it lost its dollars, and "$\\foo$"
        # raised a ParseFatalException); no chart draws any math of its own.
        "text.parse_math": False, "text.usetex": False,
        "font.family": "sans-serif",
        "font.size": 9,
        "text.color": TEXT_COLOUR, "axes.edgecolor": TEXT_COLOUR, "axes.labelcolor": TEXT_COLOUR,
        "xtick.color": TEXT_COLOUR, "ytick.color": TEXT_COLOUR,
        "axes.facecolor": "none", "figure.facecolor": "none", "savefig.facecolor": "none",
        "savefig.transparent": True, "axes.spines.top": False, "axes.spines.right": False,
        "path.simplify": True,
    })
    return Figure, FigureCanvasSVG, matplotlib


def preload() -> None:
    """Import everything drawing needs (matplotlib, its patches and lines), e.g. in a process started early."""
    _matplotlib()
    from matplotlib.lines import Line2D  # noqa: F401  the legend's keys
    from matplotlib.patches import PathPatch  # noqa: F401  the dots


def _svg_text(figure, name: str) -> str:
    """The figure as an SVG element: deterministic ids salted by `name` (unique within a page), no prologue, no
    metadata, text and axes in currentColor."""
    _, FigureCanvasSVG, matplotlib = _matplotlib()
    FigureCanvasSVG(figure)
    buffer = io.StringIO()
    with matplotlib.rc_context({"svg.hashsalt": f"jointid-{name}"}):
        figure.savefig(buffer, format="svg", metadata={"Date": None, "Creator": None, "Type": None,
                                                          "Format": None})
    text = buffer.getvalue()
    text = text[text.index("<svg"):]  # no XML declaration or DOCTYPE (its DTD address) inside a page
    text = re.sub(r"<metadata>.*?</metadata>\s*", "", text, flags=re.DOTALL)
    return text.replace(TEXT_COLOUR, "currentColor").strip() + "\n"


def _new_figure():
    Figure, _, _ = _matplotlib()
    figure = Figure(figsize=FIGURE_SIZE)
    # Fixed margins rather than a layout engine: constrained layout measured every text twice, a third of the
    # drawing time; these leave room for tick labels like -10.00 and a title with the legend beside it.
    figure.subplots_adjust(**MARGINS)
    return figure, figure.add_subplot()


def shown_stride(count: int) -> int:
    """Every how many-th of `count` points a chart draws (1: all of them)."""
    return thin_stride(count, MAX_POINTS)


def thinned_note(count: int) -> str:
    """'' when every point is drawn, else 'every 500th of 1000000 drawn'."""
    stride = shown_stride(count)
    return "" if stride == 1 else f"every {ordinal(stride)} of {count} drawn"


def dot_size(count: int) -> float:
    """Dot diameter (points): large for a few dozen samples, small where thousands would merge."""
    return 3.8 if count <= 200 else 2.6 if count <= 1000 else 2.0


def _dots(axes, x: np.ndarray, y: np.ndarray, size: float, alpha: float = 1.0, zorder: float = 4):
    """Draw dots as one SVG path of zero-length strokes with round caps (a browser draws each as a disc).

    matplotlib's scatter writes one <use> element per dot from Python: 2,000 dots cost about 30 ms a chart,
    half a million-row report's drawing (benchmarks/bench_report.py); one path's text is formatted in C.
    """
    from matplotlib.patches import PathPatch
    from matplotlib.path import Path

    points = np.repeat(np.column_stack([x, y]), 2, axis=0)
    codes = np.tile(np.array([Path.MOVETO, Path.LINETO], dtype=Path.code_type), len(x))
    path = Path(points, codes)
    path.should_simplify = False  # simplification would drop the zero-length strokes, the dots themselves
    patch = PathPatch(path, fill=False, edgecolor=DOTS_COLOUR, alpha=alpha, linewidth=size, capstyle="round",
                      zorder=zorder, transform=axes.transData)
    axes.add_artist(patch)  # not add_patch: its limits update walks every dot in Python; callers set the limits


def _padded(values: np.ndarray) -> tuple[float, float]:
    """An axis range around `values` with 5 % to spare on each side (as matplotlib's own margins)."""
    low, high = float(np.min(values)), float(np.max(values))
    pad = 0.05 * (high - low) or max(abs(low) * 0.05, 0.1)
    return low - pad, high + pad


def _dot_key(size: float, label: str, alpha: float = 1.0):
    """A legend entry for `_dots`."""
    from matplotlib.lines import Line2D

    return Line2D([], [], linestyle="none", marker="o", markersize=max(size, 3.0), markeredgewidth=0,
                  color=DOTS_COLOUR, alpha=alpha, label=label)


def torque_svg(chart: ChartData, name: str, thinned: str = "") -> str:
    """A torque chart (training or held-out) as SVG: dots, the fit's line, left-out samples faint, pushes shaded.

    `chart` should already be thinned to about MAX_POINTS (the chart series' `columns`), so that its summary
    says what was drawn; `thinned` (e.g. 'every 500th of 1000000 drawn') is added to the title.
    """
    figure, axes = _new_figure()
    t, dots = np.asarray(chart.t, dtype=float), np.asarray(chart.dots, dtype=float)
    left_out = chart.left_out
    kept = slice(None) if left_out is None or left_out.all() else ~left_out
    # The kept samples set the torque axis, as in the explorer: a push's torque runs off it at the edge.
    low, high = float(dots[kept].min()), float(dots[kept].max())
    if chart.line is not None:
        low, high = min(low, float(chart.line[kept].min())), max(high, float(chart.line[kept].max()))
    pad = max(0.05 * (high - low), 0.1)
    axes.set_ylim(low - pad, high + pad)
    span = float(t[-1] - t[0]) or 1.0
    axes.set_xlim(float(t[0]) - 0.01 * span, float(t[0]) + 1.01 * span)  # the end dots whole
    for number, (start, end) in enumerate(chart.shaded):
        axes.axvspan(start, end, color=SHADE_COLOUR, alpha=SHADE_ALPHA, linewidth=0,
                     label="outside torque (left out)" if number == 0 else None)
    if chart.line is not None:
        axes.plot(t, np.clip(chart.line, low - pad, high + pad), color=LINE_COLOUR, linewidth=1.4,
                  label=chart.line_label, zorder=2)
    clipped = np.clip(dots, low - pad, high + pad)
    size = dot_size(len(t))
    keys = [_dot_key(size, chart.dots_label)]
    if left_out is not None and left_out.any():
        _dots(axes, t[left_out], clipped[left_out], size, FAINT_ALPHA, zorder=3)
        _dots(axes, t[~left_out], clipped[~left_out], size)
        keys.append(_dot_key(size, "left out", FAINT_ALPHA))
    else:
        _dots(axes, t, clipped, size)
    axes.set_xlabel(chart.x_label)
    axes.set_ylabel(chart.y_label)
    axes.set_title(chart.titles[0] + (f" ({thinned})" if thinned else ""), loc="left", fontsize=10,
                   fontweight="bold", y=TITLE_HEIGHT)
    axes.grid(True, color=TEXT_COLOUR, alpha=0.12, linewidth=0.6)
    # Between the title and the plot: inside it would hide data, and beside a log's long title it would not fit.
    handles, _ = axes.get_legend_handles_labels()
    axes.legend(handles=[*handles, *keys], loc="lower left", bbox_to_anchor=(-0.01, 0.99), fontsize=8,
                frameon=False, ncols=5, borderaxespad=0.1, handletextpad=0.4, columnspacing=1.2)
    return _svg_text(figure, name)


def residuals_svg(scatters: list[ScatterData], name: str, thinned: str = "", unit: str = "N m") -> str:
    """The training residuals against each axis (time, angle, velocity, acceleration), two by two in one SVG,
    each around a zero line. The scatters should already be thinned to about MAX_POINTS (`thin_scatter`);
    `thinned` says how, in the heading."""
    Figure, _, _ = _matplotlib()
    figure = Figure(figsize=RESIDUALS_SIZE)
    figure.subplots_adjust(**RESIDUALS_MARGINS)
    figure.text(0.01, 0.985, f"Training residuals ({unit})" + (f" ({thinned})" if thinned else ""), fontsize=10,
                fontweight="bold", va="top")
    for index, scatter in enumerate(scatters):
        axes = figure.add_subplot(2, 2, index + 1)
        x, y = np.asarray(scatter.x, dtype=float), np.asarray(scatter.y, dtype=float)
        axes.axhline(0.0, color=TEXT_COLOUR, linewidth=0.8, alpha=0.6)
        _dots(axes, x, y, dot_size(len(x)))
        axes.set_xlim(*_padded(x))
        axes.set_ylim(*_padded(y))
        axes.set_xlabel(scatter.x_label)
        if index % 2 == 0:
            axes.set_ylabel(scatter.y_label)
        axes.locator_params(axis="x", nbins=5)  # half a page wide: long tick labels such as -0.012 would touch
        axes.grid(True, color=TEXT_COLOUR, alpha=0.12, linewidth=0.6)
    return _svg_text(figure, name)


def thin_scatter(scatter: ScatterData) -> ScatterData:
    """The scatter with every k-th point only, at most MAX_POINTS (the same one when it has no more)."""
    import dataclasses

    stride = shown_stride(len(scatter.x))
    if stride == 1:
        return scatter
    return dataclasses.replace(scatter, x=scatter.x[::stride], y=scatter.y[::stride])
