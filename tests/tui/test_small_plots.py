"""The sweep's histograms and the residual chart: one seed, narrow and tall terminals, charts that cannot draw."""

from __future__ import annotations

import asyncio
from dataclasses import replace

import numpy as np
import pytest
from rich.text import Text
from support.tui_support import make_app, time_limit

from jointid.present.charts import HistogramData, sweep_histograms
from jointid.studies.sweep import run_sweep
from jointid.synthetic.settings import DEFAULT_SETTINGS
from tui.screens.sweep import SweepScreen
from tui.widgets.fitting import FittingLine
from tui.widgets.plot_guard import MIN_PLOT_SIZE, TOO_SMALL
from tui.widgets.small_plots import GuardedPlot, SmallPlot, histogram_bars


@pytest.fixture(autouse=True)
def no_freeze():
    """A frozen chart fails its test in 30 s instead of hanging the run (it spun for minutes)."""
    with time_limit(30):
        yield


RICH = DEFAULT_SETTINGS
SLOW_NOISY = replace(DEFAULT_SETTINGS, motion="slow", noise=0.2)


async def open_sweep(pilot) -> SweepScreen:
    """Press s and wait for the sweep."""
    await pilot.press("s")
    await pilot.app.workers.wait_for_complete()
    await pilot.pause()
    assert isinstance(pilot.app.screen, SweepScreen)
    return pilot.app.screen


async def settle(pilot) -> None:
    await pilot.app.workers.wait_for_complete()
    await pilot.pause()


def plots(screen) -> list[GuardedPlot]:
    return list(screen.query(GuardedPlot))


# --- one seed: a histogram of one value ----------------------------------------------------


@pytest.mark.parametrize("motion, noise", [("rich", 0.01), ("rich", 0.2), ("slow", 0.01), ("slow", 0.2),
                                           ("rich", 1.0), ("rich", 0.0)])
def test_a_sweep_of_one_seed_draws_its_histograms_at_once(motion, noise):
    """K 1000 -> 1 with noise spun plotext's fill code for minutes (860 MB) and Escape did nothing."""

    async def main():
        app = make_app(replace(DEFAULT_SETTINGS, motion=motion, noise=noise))
        async with app.run_test(size=(80, 24)) as pilot:
            screen = await open_sweep(pilot)
            await pilot.press("shift+left")  # K = 1000 - 1000, clamped to 1
            await settle(pilot)
            assert screen.result.seed_count == 1
            for plot in plots(screen):
                assert isinstance(plot.render(), Text) and plot.failure is None
            await pilot.press("escape")
            await pilot.pause()
            return type(app.screen).__name__

    assert asyncio.run(main()) == "MainScreen"


def test_the_reported_keys_tab_right_s_shift_left_leave_a_working_app():
    async def main():
        app = make_app()
        async with app.run_test(size=(80, 24)) as pilot:
            await pilot.pause()
            await pilot.press("tab", "right")  # noise 0.01
            screen = await open_sweep(pilot)
            await pilot.press("shift+left")
            await settle(pilot)
            await pilot.press("escape", "q")
            await pilot.pause()
            return screen.result.seed_count, app.is_running

    assert asyncio.run(main()) == (1, False)


@pytest.mark.parametrize("values, true_value", [
    ([0.8], 0.8),                       # one seed at noise 0
    ([0.79], 0.8),                      # one seed with noise
    ([0.8 + 1e-16] * 1000, 0.8),        # every seed the same
    ([1e9, 1e9], 1e9),                  # large and equal
    ([0.1, np.nan, np.inf, 0.3], 0.2),  # non-finite values are left out
    ([-5.0, 12.0], 0.8),
])
def test_every_histogram_bar_has_a_width_inside_the_range(values, true_value):
    bars = histogram_bars(np.array(values, dtype=float), true_value)
    assert bars.high > bars.low and bars.low <= true_value <= bars.high
    assert np.all(np.diff(bars.edges) > 0)
    assert bars.edges[0] == bars.low and bars.edges[-1] == bars.high
    assert bars.counts.sum() == np.isfinite(values).sum()


def test_no_finite_value_is_no_histogram():
    assert histogram_bars(np.array([np.nan, np.inf]), 0.8) is None


def test_histogram_headings_give_the_marker_as_a_legend_not_a_cut_off_title():
    data = sweep_histograms(run_sweep(RICH, 10))[0]
    headings = [heading.plain for heading in SmallPlot.headings(data)]
    assert headings == ["I (kg m²), 10 seeds  │ true 0.8", "I (kg m²)  │ true 0.8", "I  │ true 0.8"]
    assert not any(heading.endswith("│") for heading in headings)


def test_a_histogram_title_is_chosen_by_the_chart_width_alone_not_by_the_seed_count():
    """The title switched between 'I (kg m²), 1000 seeds' and 'I (kg m²)' as the seed count gained a digit."""
    data = sweep_histograms(run_sweep(RICH, 5))[0]
    wider = replace(data, titles=(data.titles[0].replace("5 seeds", "10000 seeds"), *data.titles[1:]))
    for width in range(8, 60):
        shown = []
        for histogram in (data, wider):
            line = FittingLine()
            line.show(SmallPlot.headings(histogram), SmallPlot.headings(histogram, histogram.widest_titles))
            shown.append(SmallPlot.headings(histogram).index(line.pick(width)))
        assert shown[0] == shown[1], width


def test_the_histogram_keeps_its_place_when_the_seed_count_gains_digits():
    """The count labels ('5' -> '10000') widened and the plot shifted sideways."""

    async def main():
        app = make_app(RICH)
        async with app.run_test(size=(80, 24)) as pilot:
            screen = await open_sweep(pilot)
            plot = screen.query(SmallPlot).first()
            axes = []
            for count in (5, 10000):
                plot.show(HistogramData(("I",), np.full(count, 0.8) + np.linspace(0, 0.1, count), 0.8))
                await pilot.pause()
                lines = plot.query_one(GuardedPlot).render().plain.splitlines()
                axes.append({line.index("┤") for line in lines if "┤" in line})
            return axes

    few, many = asyncio.run(main())
    assert few and few == many and len(few) == 1


# --- narrow, tall terminals -------------------------------------------------------------------


@pytest.mark.parametrize("settings", [RICH, SLOW_NOISY], ids=["rich", "slow_0.20"])
@pytest.mark.parametrize("size", [(20, 80), (22, 80), (24, 80), (26, 80)])
def test_the_sweep_opens_at_narrow_tall_sizes(settings, size):
    """22x80, 24x80, 26x80 (20x80 on slow 0.2) raised ValueError: not enough values to unpack."""

    async def main():
        app = make_app(settings)
        async with app.run_test(size=size) as pilot:
            screen = await open_sweep(pilot)
            return [(plot.size.width, plot.failure) for plot in plots(screen)]

    for width, failure in asyncio.run(main()):
        assert failure == (TOO_SMALL if width < MIN_PLOT_SIZE[0] else None)
        assert width >= 16  # too narrow side by side, the histograms are stacked and draw


@pytest.mark.parametrize("width, stacked", [(50, True), (51, False), (80, False)])
def test_histograms_stack_when_side_by_side_they_could_not_draw(width, stacked):
    async def main():
        app = make_app(SLOW_NOISY)
        async with app.run_test(size=(width, 40)) as pilot:
            screen = await open_sweep(pilot)
            return screen.has_class("-stacked"), [plot.failure for plot in plots(screen)]

    assert asyncio.run(main()) == (stacked, [None] * 3)


def test_resizing_a_running_sweep_to_22x80_and_back():
    async def main():
        app = make_app(SLOW_NOISY)
        async with app.run_test(size=(80, 24)) as pilot:
            screen = await open_sweep(pilot)
            shown = []
            for size in [(22, 80), (80, 24), (22, 80), (120, 40)]:
                await pilot.resize_terminal(*size)
                await pilot.pause()
                shown.append([plot.failure for plot in plots(screen)])
            return shown

    narrow, wide, narrow_again, wider = asyncio.run(main())
    assert narrow == wide == narrow_again == wider == [None] * 3  # stacked at 22 columns, so they draw


def test_a_chart_that_fails_to_draw_shows_a_line_instead_of_crashing(monkeypatch):
    def broken(*args, **kwargs):
        raise ValueError("not enough values to unpack (expected 2, got 1)")

    async def main():
        app = make_app()
        async with app.run_test(size=(120, 40)) as pilot:
            screen = await open_sweep(pilot)
            plot = plots(screen)[0]
            monkeypatch.setattr(type(plot.plt), "build", broken)
            plot.refresh()
            await pilot.pause()
            rendered = plot.render()
            return str(rendered), plot.failure, app.is_running

    text, failure, running = asyncio.run(main())
    assert text == failure == "(chart not drawn: ValueError)" and running


def test_a_chart_whose_data_cannot_be_set_up_shows_a_line_instead_of_crashing():
    async def main():
        app = make_app()
        async with app.run_test(size=(120, 40)) as pilot:
            screen = await open_sweep(pilot)
            chart = screen.query(SmallPlot).first()
            chart.show(HistogramData(("I",), np.array(["not a number"]), true_value=0.8))
            await pilot.pause()
            return chart.query_one(GuardedPlot).failure

    assert asyncio.run(main()).startswith("(chart not drawn: ")


def test_tick_labels_take_the_digits_that_tell_them_apart():
    from tui.widgets.small_plots import tick_labels

    assert tick_labels([-13.1, 0.8, 11.9]) == ["-13.1", "0.8", "11.9"]
    assert tick_labels([0.79966, 0.8, 0.80001]) == ["0.79966", "0.8", "0.80001"]
    assert tick_labels([0.8, 0.8, 0.8]) == ["0.8", "0.8", "0.8"]
