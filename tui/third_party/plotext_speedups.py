"""Faster drop-ins for five plotext 5.3.2 internals, so a torque chart builds in half the time.

A key press rebuilds both torque charts, and most of plotext's build is spent in
helpers written for generality rather than speed:

- `_utility.hd_group` groups the braille line's points into cells: it built a
  list of lists per point and flattened each with a recursive `join`;
- `_utility.join` flattens nested lists by recursion with a list per element;
- `matrix_class.set_matrices` coloured every cell of a fresh matrix through a
  lambda call and two range lookups;
- `matrix_class.insert_element` writes one cell through five method calls;
- `_utility.get_matrix_data` maps each point through two lambdas.

The versions here compute the same values in plain loops and slices, which buys
0.17 of a key press's latency (median; bench_tui_keys --adapter plotext-helpers).
`tests/tui/test_plotext_speedups.py` builds many random figures with and without
them and requires every character and colour to be equal.
Nothing here is installed on import: `tui.third_party.adapter.activate()` puts them in
place (when the app starts) only on the plotext release they were written
against, and `tui.third_party.adapter.uninstall()` restores plotext's own.
"""

from __future__ import annotations

import math

from plotext import _matrix as plotext_matrix
from plotext import _utility as plotext_utility

ORIGINALS = {
    "hd_group": plotext_utility.hd_group,
    "join": plotext_utility.join,
    "set_matrices": plotext_matrix.matrix_class.set_matrices,
    "insert_element": plotext_matrix.matrix_class.insert_element,
    "get_matrix_data": plotext_utility.get_matrix_data,
}
"""plotext's own functions, kept to fall back on and to compare against in tests."""


def hd_group(x, y, xf, yf):
    """plotext's hd_group: the cells high-resolution markers fall in, and each cell's dot pattern.

    Returns the cells' x and y (in order of first appearance) and per cell a
    tuple of 0/1 over its sub-dots, top row first. Mixed marker resolutions in
    one signal (never drawn here) go to plotext's own version.
    """
    if not x or min(xf) != max(xf) or min(yf) != max(yf):
        return ORIGINALS["hd_group"](x, y, xf, yf)
    columns, rows = xf[0], yf[0]
    numerical = plotext_utility.numerical
    cells: dict[tuple, list[int]] = {}
    for xi, yi in zip(x, y):
        x_ok, y_ok = numerical(xi), numerical(yi)
        key = (xi // columns if x_ok else xi, yi // rows if y_ok else yi)
        dots = cells.get(key)
        if dots is None:
            dots = cells[key] = [0] * (columns * rows)
        if x_ok and y_ok:
            dots[(rows - 1 - math.floor(yi % rows)) * columns + math.floor(xi % columns)] = 1
    return [key[0] for key in cells], [key[1] for key in cells], [tuple(dots) for dots in cells.values()]


def join(data):
    """plotext's join: flatten nested lists (only `list`, as plotext does) into one list."""
    flat = []
    for item in data:
        if type(item) == list:  # noqa: E721 - exactly plotext's test: tuples are not flattened
            flat.extend(join(item))
        else:
            flat.append(item)
    return flat


def set_matrices(self) -> None:
    """plotext's matrix_class.set_matrices: blank markers, no colours, the canvas background inside its area."""
    space, no_color = plotext_utility.space, plotext_utility.no_color
    cols = self.cols
    canvas_row = [self.canvas_color if col in self.Cols_canvas else self.axes_color for col in self.Cols]
    outside_row = [self.axes_color] * cols
    self.marker = [[space] * cols for _ in self.Rows]
    self.fullground = [[no_color] * cols for _ in self.Rows]
    self.background = [list(canvas_row if row in self.Rows_canvas else outside_row) for row in self.Rows]
    self.style = [[no_color] * cols for _ in self.Rows]


def insert_element(self, col, row, marker, fullground=None, style=None, background=None, check_canvas=False):
    """plotext's matrix_class.insert_element: one cell's marker and colours, when inside the matrix (and canvas).

    The same tests and assignments without plotext's five helper calls a cell
    (every axis character, label letter and data point comes through here).
    """
    if check_canvas is not False and not (col in self.Cols_canvas and row in self.Rows_canvas):
        return
    if col in self.Cols and row in self.Rows:
        self.marker[row][col] = marker
        if fullground is not None:
            self.fullground[row][col] = fullground
        if background is not None:
            self.background[row][col] = background
        if style is not None:
            self.style[row][col] = style


def get_matrix_data(data, lim, bins):
    """plotext's get_matrix_data: data to canvas cells, the same arithmetic in a loop instead of two lambdas a point."""
    low, scale, span = lim[0], bins - 1, lim[1] - lim[0]
    isnan, floor, rounded = math.isnan, math.floor, plotext_utility.round
    cells = []
    for el in data:
        if not (el is None or isnan(el)) or isinstance(el, str):  # plotext's `numerical`, evaluated alike
            cells.append(floor(rounded(0.5 + scale * (el - low) / span, 8)))
        else:
            cells.append(el)
    return cells


FAST = {"hd_group": hd_group, "join": join, "set_matrices": set_matrices, "insert_element": insert_element,
        "get_matrix_data": get_matrix_data}
"""The drop-ins, by the name of the plotext function each replaces."""

OWNERS = {
    "hd_group": plotext_utility,
    "join": plotext_utility,
    "set_matrices": plotext_matrix.matrix_class,
    "insert_element": plotext_matrix.matrix_class,
    "get_matrix_data": plotext_utility,
}
"""Where plotext looks each function up when it calls it (a module or a class)."""
