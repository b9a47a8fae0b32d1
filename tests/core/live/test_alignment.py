"""Topics at their own times put on the base topic's: interpolated linearly, nothing extrapolated, gaps left out,
states taken as a data log's are."""

import numpy as np

from jointid.live.alignment import TopicAligner


def test_other_topics_are_interpolated_at_the_base_stamps_and_nothing_waits_beyond_them():
    base_t = np.arange(100) * 0.02
    effort_t = base_t + 0.0003  # published 0.3 ms after the position in each loop
    effort = np.sin(effort_t * 3)
    aligner = TopicAligner(("q", "tau"), "q")
    for t, e in zip(effort_t[:60], effort[:60]):
        aligner.add("tau", t, e)
    for t in base_t:
        aligner.add("q", t, 2 * t)
    rows, left_out = aligner.take()
    # Samples up to the last effort record are settled; the rest wait for later ones. The first precedes every
    # effort record, but by less than a tenth of a step: the same loop's, as a data log's reader keeps it.
    ready = base_t <= effort_t[59]
    np.testing.assert_array_equal(rows["t"], base_t[ready])
    np.testing.assert_allclose(rows["tau"], np.interp(base_t[ready], effort_t, effort), rtol=1e-12)
    assert left_out == 0
    for t, e in zip(effort_t[60:], effort[60:]):
        aligner.add("tau", t, e)
    rest, _ = aligner.take()
    np.testing.assert_array_equal(rest["t"], base_t[~ready])
    np.testing.assert_allclose(rest["tau"], np.interp(base_t[~ready], effort_t, effort), rtol=1e-12)


def test_a_sample_inside_another_topics_gap_is_left_out():
    times = np.arange(50) * 0.01
    aligner = TopicAligner(("q", "tau"), "q")
    for t in times:
        aligner.add("q", t, t)
        if not 0.2 < t < 0.3:  # the effort's records stop for 0.1 s: ten of its steps
            aligner.add("tau", t, 1.0)
    rows, left_out = aligner.take(final=True)
    missing = (times > 0.2) & (times < 0.3)
    assert left_out == int(missing.sum())
    np.testing.assert_array_equal(rows["t"], times[~missing])


def test_each_sample_takes_the_state_recorded_with_it():
    times = np.arange(10) * 0.001
    aligner = TopicAligner(("q", "tau"), "q", state=True)
    for k, t in enumerate(times):
        aligner.add("q", t, 0.0)
        aligner.add("tau", t, 0.0)
        aligner.add("state", t + 2e-5, "quasistatic-forward" if k < 5 else "none")
    rows, _ = aligner.take(final=True)
    assert rows["state"].tolist() == ["quasistatic-forward"] * 5 + ["none"] * 5
