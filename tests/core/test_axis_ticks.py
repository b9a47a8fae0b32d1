"""Chart ticks: round numbers at even steps inside the axis, labels that read as their values, no '-0.0'."""

from __future__ import annotations

import numpy as np
import pytest

from jointid.present.charts import axis_ticks


@pytest.mark.parametrize("low, high, target", [(-1.13, 1.12, 5), (1.93, 5.02, 6), (0.0, 19.99, 6), (-0.05, 0.05, 4),
                                               (-9.9, 2.2, 5), (1e-7, 3e-7, 3), (-250.0, 1320.0, 8)])
def test_ticks_are_round_evenly_spaced_inside_and_their_labels_read_as_them(low, high, target):
    ticks, labels = axis_ticks(low, high, target)
    assert 2 <= len(ticks) <= 2 * target + 1
    assert low <= ticks[0] and ticks[-1] <= high
    steps = np.diff(ticks)
    assert np.allclose(steps, steps[0], rtol=1e-9)
    mantissa = steps[0] / 10 ** np.floor(np.log10(steps[0]))
    assert any(np.isclose(mantissa, m) for m in (1, 2, 2.5, 5, 10))
    assert [float(label) for label in labels] == pytest.approx(list(ticks), abs=steps[0] * 1e-6)
    assert len(set(labels)) == len(labels) and not any(label.startswith("-0") and float(label) == 0 for label in labels)


def test_no_ticks_for_an_empty_or_broken_range():
    assert axis_ticks(1.0, 1.0, 5) == ((), ())
    assert axis_ticks(0.0, float("nan"), 5) == ((), ())
