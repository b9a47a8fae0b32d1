"""Torque charts' axes: round, evenly spaced ticks; a plot that keeps its place when new data need longer labels."""

from __future__ import annotations

import re

import numpy as np

from jointid.present.charts import ChartData
from tui.third_party.adapter import new_figure
from tui.widgets.charts import draw_torque_chart


def chart(low: float, high: float) -> ChartData:
    t = np.linspace(0.0, 8.0, 40)
    dots = low + (high - low) * (0.5 + 0.5 * np.sin(t))
    return ChartData(titles=("t",), t=t, dots=dots, line=dots, dots_label="measured", line_label="fitted",
                     summaries=("s",))


def drawn(data: ChartData, size=(60, 14)) -> list[str]:
    plt = new_figure()
    plt.plot_size(*size)
    plt.theme("clear")
    draw_torque_chart(plt, data, (1, 2, 3), (4, 5, 6), size=size)
    return [re.sub(r"\x1b\[[0-9;]*m", "", line) for line in plt.build().splitlines()]


def test_ticks_are_round_and_even_and_the_plot_does_not_shift_with_longer_labels():
    small, signed = drawn(chart(0.7, 5.1)), drawn(chart(-1.1, 1.1))
    for lines in (small, signed):
        labels = [float(line.split("┤")[0]) for line in lines if "┤" in line]
        assert len(labels) >= 3 and np.allclose(np.diff(labels), np.diff(labels)[0])
        assert not any(line.split("┤")[0].strip() == "-0.0" for line in lines if "┤" in line)
    axis = [{line.index("┤") for line in lines if "┤" in line} for lines in (small, signed)]
    assert len(axis[0] | axis[1]) == 1  # '5' and '-0.5' leave the y axis in the same column


def test_a_thinned_chart_says_so_down_to_its_narrow_summaries():
    """200 held-out samples on 80 columns: every 3rd is drawn, and every summary down to the two shortest forms
    that still say it (the shortest keeps only range and RMSE) tells so."""
    from jointid.present.charts import torque_chart
    from jointid.studies.experiment import run_experiment
    from jointid.synthetic.settings import DEFAULT_SETTINGS

    result = run_experiment(DEFAULT_SETTINGS)
    data = result.training
    wide = np.repeat(data.tau, 9)  # 216 samples: thinned to 80 columns by 3
    thinned = type(data)(t=np.repeat(data.t, 9), q=np.repeat(data.q, 9), qd=np.repeat(data.qd, 9),
                         qdd=np.repeat(data.qdd, 9), tau=wide)
    chart = torque_chart(result, thinned, wide, 0.1, titles=("t",), what="measured", dots_label="measured",
                         line_label="fitted", columns=80)
    assert len(chart.t) == 72
    assert all("3rd" in summary or "1 in 3" in summary for summary in chart.summaries[:-1])
    assert chart.summaries[-2].endswith("1 in 3 shown")


def test_the_residual_and_design_charts_have_round_even_ticks_too():
    """They kept plotext's own labels (0.00110, 0.00073, 0.00037; 0.97, 0.64, 0.32); a round step of 1 then left
    only '0' on the design chart's ±0.97 axis."""
    import asyncio

    from support.tui_support import make_app

    from tui.widgets.small_plots import GuardedPlot

    async def main():
        app = make_app()
        labels = {}
        async with app.run_test(size=(80, 24)) as pilot:
            for key in ("e", "escape", "d"):
                await pilot.press(key)
                await pilot.pause()
                if key != "escape":
                    plot = app.screen.query(GuardedPlot).first()
                    lines = plot.render().plain.splitlines()
                    # '├' where the residuals' zero line meets the axis
                    labels[key] = [re.split("[┤├]", line)[0].strip() for line in lines if re.search("[┤├]", line)]
        return labels

    for key, found in asyncio.run(main()).items():
        values = [float(label) for label in found]
        steps = np.diff(values)
        assert len(values) >= 3 and np.allclose(steps, steps[0]), (key, found)
        mantissa = abs(steps[0]) / 10 ** np.floor(np.log10(abs(steps[0])))
        assert any(np.isclose(mantissa, m) for m in (1, 2, 2.5, 5)), (key, found)  # a round step
        assert not any(label.startswith("-0") and float(label) == 0 for label in found), (key, found)
