"""The fast plotext helpers draw exactly what plotext's own draw, and charts do not depend on history."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jointid.present.charts import ChartData, heldout_chart, training_chart
from jointid.studies.experiment import run_experiment
from jointid.synthetic.settings import Settings
from tui.third_party import adapter as third_party
from tui.third_party import plotext_speedups
from tui.third_party.adapter import build_matrix, new_figure
from tui.widgets.charts import draw_torque_chart

LINE_RGB, DOTS_RGB = (200, 120, 40), (60, 140, 220)


@pytest.fixture(autouse=True, scope="module")
def fast_helpers():
    """Nothing installs the helpers on import: these tests, outside the app, activate them."""
    third_party.activate()
    assert third_party.active(third_party.PLOTEXT_HELPERS)


def install() -> None:
    """Put the fast helpers back after a comparison with plotext's own."""
    third_party.activate()
    assert third_party.active(third_party.PLOTEXT_HELPERS)


@pytest.fixture
def plotext_own():
    """Run a block with plotext's own helpers, then put the fast ones back."""
    third_party.uninstall()
    yield
    install()


def build(plt, data: ChartData, width: int, height: int, marker: str | None = None) -> list:
    """Draw a chart as the app does and return plotext's four cell matrices."""
    draw_torque_chart(plt, data, LINE_RGB, DOTS_RGB)
    if marker is not None and data.line is not None:  # the same chart with another line marker
        plt.clear_data()
        plt.plot(data.t, data.line, marker=marker, color=LINE_RGB)
        plt.scatter(data.t, data.dots, marker="●", color=DOTS_RGB)
    matrix = build_matrix(plt, width, height)
    return [[list(row) for row in grid]
            for grid in (matrix.marker, matrix.fullground, matrix.background, matrix.style)]


def fresh(data: ChartData, width: int, height: int, marker: str | None = None) -> list:
    return build(new_figure(), data, width, height, marker)


def random_chart(seed: int, samples: int, with_line: bool, flat: bool) -> ChartData:
    rng = np.random.default_rng(seed)
    t = np.sort(rng.uniform(0, 8, samples))
    dots = np.zeros(samples) if flat else rng.normal(0, rng.uniform(0.01, 20), samples)
    line = (dots + rng.normal(0, 0.5, samples)) if with_line else None
    return ChartData(titles=("t",), t=t, dots=dots, line=line, dots_label="d", line_label="l", summaries=("s",))


def test_the_fast_helpers_are_installed_on_the_pinned_plotext():
    import plotext._utility as utility

    assert utility.hd_group is plotext_speedups.hd_group
    assert utility.join is plotext_speedups.join
    assert utility.join is not plotext_speedups.ORIGINALS["join"]


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), samples=st.integers(2, 240), with_line=st.booleans(),
       flat=st.booleans(), width=st.integers(12, 160), height=st.integers(5, 40),
       marker=st.sampled_from([None, "hd", "fhd", "braille", "dot"]))
def test_random_charts_are_identical_with_and_without_the_fast_helpers(seed, samples, with_line, flat,
                                                                       width, height, marker):
    data = random_chart(seed, samples, with_line, flat)
    fast = fresh(data, width, height, marker)
    third_party.uninstall()
    try:
        own = fresh(data, width, height, marker)
    finally:
        install()
    assert fast == own


@pytest.mark.parametrize("motion", ["rich", "slow", "holds"])
@pytest.mark.parametrize("size", [(74, 14), (38, 6), (120, 30)])
def test_the_lessons_charts_are_identical_with_and_without_the_fast_helpers(motion, size, plotext_own):
    result = run_experiment(Settings(motion, 0.2, 24, 7))
    charts = (training_chart(result), heldout_chart(result))
    own = [fresh(chart, *size) for chart in charts]
    install()
    assert [fresh(chart, *size) for chart in charts] == own


@settings(max_examples=200, deadline=None)
@given(points=st.lists(st.tuples(st.floats(0, 400) | st.just(math.nan), st.floats(0, 200) | st.just(math.nan)),
                       min_size=1, max_size=60),
       factors=st.sampled_from([(2, 2), (2, 3), (2, 4), (1, 1)]), mixed=st.booleans())
def test_hd_group_matches_plotext(points, factors, mixed):
    x, y = [p[0] for p in points], [p[1] for p in points]
    xf, yf = [factors[0]] * len(x), [factors[1]] * len(x)
    if mixed and len(x) > 1:  # plotext's own code handles mixed resolutions
        xf[-1], yf[-1] = 2, 4
    assert outcome(plotext_speedups.hd_group, x, y, xf, yf) == outcome(
        plotext_speedups.ORIGINALS["hd_group"], x, y, xf, yf)


def outcome(function, *arguments):
    """A call's result, or the type of error it raised (plotext's own hd_group fails on some mixed input)."""
    try:
        return function(*arguments)
    except Exception as error:  # noqa: BLE001 - the same failure is the expected outcome
        return type(error)


nested = st.recursive(st.one_of(st.integers(), st.text(max_size=2), st.tuples(st.integers())),
                      lambda children: st.lists(children, max_size=4), max_leaves=30)


@settings(max_examples=200, deadline=None)
@given(data=st.lists(nested, max_size=6))
def test_join_matches_plotext(data):
    assert plotext_speedups.join(data) == plotext_speedups.ORIGINALS["join"](data)


@settings(max_examples=200, deadline=None)
@given(data=st.lists(st.floats(-1e6, 1e6) | st.integers(-1000, 1000) | st.just(math.nan) | st.none(), max_size=40),
       lim=st.tuples(st.floats(-1e3, 1e3), st.floats(-1e3, 1e3)).filter(lambda lim: lim[0] != lim[1]),
       bins=st.integers(1, 600))
def test_get_matrix_data_matches_plotext(data, lim, bins):
    fast = outcome(plotext_speedups.get_matrix_data, data, list(lim), bins)
    own = outcome(plotext_speedups.ORIGINALS["get_matrix_data"], data, list(lim), bins)
    assert repr(fast) == repr(own)  # repr: nan equals nan, and 3 differs from 3.0


@settings(max_examples=200, deadline=None)
@given(cells=st.lists(st.tuples(st.integers(-3, 12), st.integers(-3, 8), st.sampled_from("ab─"),
                                st.sampled_from([None, "red", (1, 2, 3)]), st.sampled_from([None, "bold"]),
                                st.sampled_from([None, "blue"]), st.booleans()), max_size=30))
def test_insert_element_matches_plotext(cells):
    from plotext._matrix import matrix_class

    matrices = []
    for insert in (plotext_speedups.insert_element, plotext_speedups.ORIGINALS["insert_element"]):
        matrix = matrix_class()
        matrix.set_size(10, 6)
        matrix.set_canvas_area(2, 8, 1, 5)
        plotext_speedups.ORIGINALS["set_matrices"](matrix)
        for col, row, marker, fullground, style, background, check_canvas in cells:
            insert(matrix, col, row, marker, fullground, style, background, check_canvas)
        matrices.append((matrix.marker, matrix.fullground, matrix.style, matrix.background))
    assert matrices[0] == matrices[1]


def test_a_chart_does_not_depend_on_the_chart_drawn_before_it():
    """draw_torque_chart skips plotext's clear_figure: every setting is set again each time."""
    holds, slow = run_experiment(Settings("holds", 0.0, 24, 7)), run_experiment(Settings("slow", 0.3, 100, 9))
    log_like = ChartData(titles=("t",), t=np.arange(50.0), dots=np.linspace(-3, 3, 50),
                         line=np.linspace(-2.5, 2.5, 50), dots_label="d", line_label="l",
                         summaries=("s",), x_label="Sample")
    sequence = [training_chart(holds), log_like, heldout_chart(slow), training_chart(slow), heldout_chart(holds)]
    reused = new_figure()
    for chart in sequence:
        assert build(reused, chart, 74, 14) == fresh(chart, 74, 14)


def test_hd_group_places_dots_as_plotext_documents_braille_cells():
    """Braille cells are 2 dots wide and 4 high; a cell's pattern lists its rows top first.

    (0.5, 1.0) is in cell (0, 0), column 0, row 1 from the bottom: the third row
    from the top, so position 2 * 2 + 0 = 4. (3.2, 7.9) is in cell (1, 1),
    column 1, row 3 from the bottom: the top row, position 1. A NaN x keeps its
    own cell key and sets no dot.
    """
    x, y, dots = plotext_speedups.hd_group([0.5, 3.2, math.nan], [1.0, 7.9, 2.0], [2, 2, 2], [4, 4, 4])
    assert (x[:2], y[:2]) == ([0.0, 1.0], [0.0, 1.0])
    assert dots == [(0, 0, 0, 0, 1, 0, 0, 0), (0, 1, 0, 0, 0, 0, 0, 0), (0,) * 8]
