"""The live identification (studies.watch): simulated joints fed in blocks converge to their truth, declare a
parameter determined no earlier than an offline fit of the same samples allows, agree with that fit at the end,
and hold bounded state however long they run."""

from __future__ import annotations

import numpy as np
import pytest

from jointid.estimation.solver import solve_least_squares
from jointid.live.received import Received
from jointid.studies.log_fit import fit_log
from jointid.studies.watch import Watcher
from jointid.studies.watch_streams import NeweyWestSums
from tests.support.watched_joints import arm, flywheel


def watched(samples, size: int, **settings) -> tuple[Watcher, list]:
    """A Watcher fed the samples in blocks of `size`, and (samples through the newest fitted row, refresh) after
    each second of them (rows wait for the robust step's block, so the fit lags what was received)."""
    watcher = Watcher(**settings)
    refreshes = []
    per_second = max(1, int(round(1 / (samples.t[1] - samples.t[0]) / size)))
    for k, block in enumerate(samples.blocks(size)):
        watcher.add(Received(block))
        if (k + 1) % per_second == 0:
            refreshes.append((fitted_through(samples, watcher), watcher.refresh()))
    watcher.add(Received(ended=True))
    refreshes.append((len(samples.t), watcher.refresh()))
    return watcher, refreshes


def fitted_through(samples, watcher: Watcher) -> int:
    """The samples up to the newest row the watcher has fitted."""
    if watcher.fitted_until is None:
        return 0
    return int(np.searchsorted(samples.t, watcher.fitted_until, side="right"))


def offline(samples, count: int, watcher: Watcher, **settings):
    """jointid's log fit of the first `count` samples, with the low-pass, decimation and window the watcher chose
    (a log fit would choose them from the whole log, the watcher from its warm-up)."""
    columns = {"t": samples.t[:count], "q": samples.q[:count], "tau": samples.tau[:count]}
    return fit_log(columns, cutoff=watcher.filter.cutoff or 0.0, decimate=watcher.filter.decimation,
                   window=watcher.window, **settings)


@pytest.mark.parametrize("rate, size", [(50.0, 1), (1000.0, 50)])
def test_an_arm_converges_to_its_truth(rate, size):
    samples = arm(rate, 60.0)
    watcher, refreshes = watched(samples, size)
    final = refreshes[-1][1]
    fit = offline(samples, len(samples.t), watcher)
    verdicts = dict(zip(fit.result.model.names, fit.result.judgement.verdicts))
    assert list(verdicts.values()).count("well determined") >= 4, verdicts
    for trace in final.parameters:
        truth = samples.truth[trace.name]
        assert abs(trace.value - truth) <= 0.05 * abs(truth), trace
        # Judged as the offline fit of the same samples judges it (at 1 kHz its halves disagree on Fc).
        assert trace.verdict == verdicts[trace.name], (trace, verdicts)
        if trace.verdict == "well determined":
            assert trace.determined_at is not None and trace.determined_at < final.elapsed
        assert len(trace.history) >= 2


@pytest.mark.parametrize("rate, size", [(50.0, 5), (1000.0, 50)])
def test_a_flywheel_converges_to_its_gains(rate, size):
    samples = flywheel(rate, 60.0)
    _, refreshes = watched(samples, size, effort="voltage", mechanism="simple")
    final = refreshes[-1][1]
    assert [trace.name for trace in final.parameters] == ["kA", "kV", "kS"]
    for trace in final.parameters:
        truth = samples.truth[trace.name]
        assert abs(trace.value - truth) <= 0.05 * abs(truth), trace


CASES = [
    pytest.param(lambda: arm(1000.0, 60.0, noise=6.0), 50, {}, {}, id="arm-1kHz"),
    pytest.param(lambda: arm(50.0, 60.0, noise=3.0), 5, {}, {}, id="arm-50Hz"),
    pytest.param(lambda: flywheel(50.0, 60.0, noise=0.6), 5, {"effort": "voltage", "mechanism": "simple"},
                 {"effort": "voltage", "model": "simple"}, id="flywheel-50Hz"),
]


@pytest.mark.parametrize("make, size, settings, fitted_as", CASES)
def test_determination_is_no_earlier_than_an_offline_fit_allows(make, size, settings, fitted_as):
    # Noisy enough that the parameters become determined while the joint moves, not at the first refresh.
    samples = make()
    watcher, refreshes = watched(samples, size, **settings)
    moments = {}
    for count, refresh in refreshes:
        for trace in refresh.parameters:
            if trace.determined_at is not None and trace.name not in moments:
                moments[trace.name] = (count, trace.determined_pct)
    assert moments, "nothing became well determined"
    for name, (count, percent) in moments.items():
        fit = offline(samples, count, watcher, **fitted_as)
        relative = 100 * fit.bse[name] / abs(fit.params[name])
        # The same samples fitted offline determine it too, to the precision the watcher said: the same Newey-West
        # errors of about 15 % fewer rows (a stream does not fit each stretch's ends), equal to the precision a
        # standard error has (as in the last refresh's comparison below).
        assert relative <= 1.25 * percent, (name, count, relative, percent)


@pytest.mark.parametrize("make, size, settings, fitted_as", [
    pytest.param(lambda: arm(1000.0, 60.0), 50, {}, {}, id="arm-1kHz"),
    pytest.param(lambda: arm(50.0, 60.0), 5, {}, {}, id="arm-50Hz"),
    pytest.param(lambda: arm(50.0, 60.0, jitter=0.05), 5, {}, {}, id="arm-50Hz-jittered"),
    pytest.param(lambda: flywheel(50.0, 60.0), 5, {"effort": "voltage", "mechanism": "simple"},
                 {"effort": "voltage", "model": "simple"}, id="flywheel-50Hz"),
])
def test_the_last_refresh_matches_an_offline_fit_of_the_same_samples(make, size, settings, fitted_as):
    samples = make()
    watcher, refreshes = watched(samples, size, **settings)
    final = refreshes[-1][1]
    fit = offline(samples, len(samples.t), watcher, **fitted_as)
    # The live fit leaves out each stretch's ends (a stream cannot know the end polynomials) and judges standstill
    # and outside torques block by block: a few percent of the rows differ, so the estimates agree within their
    # standard error and the errors to the precision a standard error has.
    assert final.fitted >= 0.8 * fit.result.training.count
    noise = dict(zip(fit.result.model.names, fit.result.uncertainty.noise_std_error))
    live_noise = dict(zip(final.result.model.names, final.result.uncertainty.noise_std_error))
    for trace in final.parameters:
        error = fit.bse[trace.name]
        assert abs(trace.value - fit.params[trace.name]) <= 1.5 * error, (trace, fit.params[trace.name], error)
        # The noise's (Newey-West) errors agree to the precision a standard error has; the reported ones are
        # widened by the same analysis choices where those move the estimate (the halves' scatter, judged on
        # other rows, may differ).
        assert 0.8 <= live_noise[trace.name] / noise[trace.name] <= 1.25, (trace.name, live_noise, noise)
        assert trace.error >= live_noise[trace.name]
    assert final.result.params.keys() == fit.params.keys()
    assert dict(final.result.bse) == {trace.name: trace.error for trace in final.parameters}


def test_state_stays_bounded_over_ten_times_the_samples():
    # Ten minutes at 50 Hz, a refresh every two seconds: the state's size cycles (batches merge, histories thin,
    # rows wait for the robust step) but does not grow; a state that kept its rows would double from one half of
    # the run to the next.
    samples = arm(50.0, 600.0)
    watcher = Watcher()
    sizes = []
    for block in samples.blocks(100):
        watcher.add(Received(block))
        watcher.refresh()
        sizes.append(watcher.state_size)
    minute = len(sizes) // 10
    middle = (minute + len(sizes)) // 2
    first, second = max(sizes[minute:middle]), max(sizes[middle:])
    assert second <= 1.25 * first, (first, second)


def test_a_sysid_routine_watched_lists_its_tests_and_gives_its_gains():
    # A flywheel's routine as a state column: 10 s of one test, 1 s idle ('none': received, not fitted), then
    # another; the watcher counts each test's seconds and gives the feedforward's gains from its fit.
    samples = flywheel(50.0, 40.0)
    count = len(samples.t)
    state = np.array(["quasistatic-forward"] * 500 + ["none"] * 50 + ["dynamic-forward"] * (count - 550))
    watcher = Watcher(effort="voltage", mechanism="simple")
    for first in range(0, count, 5):
        block = {"t": samples.t[first:first + 5], "q": samples.q[first:first + 5],
                 "tau": samples.tau[first:first + 5], "state": state[first:first + 5]}
        watcher.add(Received(block))
    refresh = watcher.refresh()
    assert [name for name, _ in refresh.tests] == ["quasistatic-forward", "dynamic-forward"]
    seconds = dict(refresh.tests)
    assert seconds["quasistatic-forward"] == pytest.approx(500 * 0.02, rel=1e-9)
    assert seconds["dynamic-forward"] == pytest.approx((count - 550) * 0.02, rel=1e-9)
    assert refresh.received == count
    assert refresh.fitted < count - 50  # the idle second and each test's ends are not fitted
    gains = watcher.gains(refresh)
    assert gains.feedforward == "SimpleMotorFeedforward"
    for gain in ("kS", "kV", "kA"):
        assert gains[gain].value == pytest.approx(samples.truth[gain], rel=0.05)
        assert gains[gain].value == pytest.approx(dict(zip(refresh.result.model.names, refresh.result.estimate))[gain])


def test_advice_names_what_the_motion_lacks():
    # An arm that only swings one way slowly about a small angle: its inertia is not determined, and the advice
    # says which motion would determine it.
    t = np.arange(0, 30, 0.001)
    q = 0.05 * np.sin(2 * np.pi * 0.1 * t)
    qd = 0.05 * 2 * np.pi * 0.1 * np.cos(2 * np.pi * 0.1 * t)
    tau = 0.3 * 9.81 * np.cos(q) + 0.1 * qd + np.random.default_rng(4).normal(0, 0.2, len(t))
    watcher = Watcher(model="plain")
    for first in range(0, len(t), 100):
        watcher.add(Received({"t": t[first:first + 100], "q": q[first:first + 100], "tau": tau[first:first + 100]}))
    refresh = watcher.refresh()
    inertia = next(trace for trace in refresh.parameters if trace.name == "I")
    assert inertia.verdict != "well determined"
    assert any(line.startswith("I (inertia)") and "accelerate" in line for line in refresh.advice), refresh.advice


def test_newey_west_sums_give_the_direct_double_sum():
    # Rows arriving in uneven blocks, some left out (zeros: gaps in the grid) and one break between stretches;
    # the covariance from the sums equals the Newey-West double sum over pairs within the lag, computed directly.
    rng = np.random.default_rng(5)
    X = rng.normal(size=(300, 3))
    y = X @ np.array([1.0, -2.0, 0.5]) + np.convolve(rng.normal(size=304), np.ones(5) / 5, mode="valid")
    kept = rng.random(300) > 0.1
    sums = NeweyWestSums(3, 12)
    for first, last in ((0, 7), (7, 150), (150, 151), (151, 300)):
        if first == 150:
            sums.gap()
        rows = slice(first, last)
        sums.add(X[rows] * kept[rows, None], np.where(kept[rows], y[rows], 0.0))
    solution = solve_least_squares(X[kept], y[kept])
    covariance, effective = sums.covariance(solution, 6)
    theta = solution.estimate
    scores = X * (y - X @ theta)[:, None] * kept[:, None]
    stretch = np.arange(300) >= 150
    meat = np.zeros((3, 3))
    products = 0.0
    residuals = (y - X @ theta) * kept
    for i in range(300):
        for j in range(300):
            if abs(i - j) <= 6 and stretch[i] == stretch[j]:
                meat += (1 - abs(i - j) / 7) * np.outer(scores[i], scores[j])
                products += (1 - abs(i - j) / 7) * residuals[i] * residuals[j]
    inverse = np.linalg.inv(X[kept].T @ X[kept])
    count = int(kept.sum())
    expected = inverse @ meat @ inverse * count / (count - 3)
    np.testing.assert_allclose(covariance, expected, rtol=1e-9)
    assert effective == pytest.approx(count / max(products / np.sum(residuals ** 2), 1.0), rel=1e-9)


@pytest.mark.parametrize("joint, chosen", [("flywheel", "simple"), ("arm", "arm")])
def test_a_sysid_routine_chooses_its_mechanism_as_a_recorded_log(joint, chosen):
    # Without --mechanism, a voltage routine's mechanism is chosen from the data: a flywheel turns many times with
    # no voltage following cos q (simple motor); an arm's voltage follows the cosine of its angle (arm: kG = h g).
    samples = flywheel(50.0, 40.0) if joint == "flywheel" else arm(50.0, 40.0, bias=0.0)
    state = np.full(len(samples.t), "dynamic-forward")
    watcher = Watcher(effort="voltage")
    for first in range(0, len(samples.t), 5):
        rows = slice(first, first + 5)
        watcher.add(Received({"t": samples.t[rows], "q": samples.q[rows], "tau": samples.tau[rows],
                              "state": state[rows]}))
    refresh = watcher.refresh()
    assert watcher.mechanism_choice.mechanism == chosen
    assert watcher.mechanism_choice.given_by is None
    values = {trace.name: trace.value for trace in refresh.parameters}
    if chosen == "arm":
        assert values["kG"] == pytest.approx(samples.truth["h"] * 9.81, rel=0.05)
        assert values["kA"] == pytest.approx(samples.truth["I"], rel=0.05)
    else:
        assert set(values) == {"kA", "kV", "kS"}
        assert values["kV"] == pytest.approx(samples.truth["kV"], rel=0.05)


def test_advice_names_a_parameter_the_motion_cannot_separate():
    # A joint turning at one steady speed has no acceleration: its inertia cannot be told from the rest (the fit
    # is rank-deficient), and the advice says so and what would separate it.
    t = np.arange(0, 20, 0.001)
    q, qd = 0.5 * t, np.full(len(t), 0.5)
    tau = 0.3 * 9.81 * np.cos(q) + 0.1 * qd + np.random.default_rng(6).normal(0, 0.05, len(t))
    watcher = Watcher(model="plain")
    for first in range(0, len(t), 100):
        watcher.add(Received({"t": t[first:first + 100], "q": q[first:first + 100], "tau": tau[first:first + 100]}))
    refresh = watcher.refresh()
    assert refresh.result is not None and refresh.result.rank < 3
    assert any(line.startswith("I (inertia) is not separable") and "no acceleration" in line and "accelerate" in line
               for line in refresh.advice), refresh.advice


def test_a_wrapped_angle_is_unwrapped_as_it_arrives():
    # The same arm, its angle turned by 2.5 rad so that it crosses the seam at pi, reported wrapped to (-pi, pi]:
    # the watcher undoes the wraps, so it fits what it fits from the continuous angle.
    samples = arm(200.0, 30.0)
    turned = samples.q + 2.5
    wrapped = np.angle(np.exp(1j * turned))
    assert np.any(np.abs(np.diff(wrapped)) > np.pi)
    fits = []
    for angle in (turned, wrapped):
        watcher = Watcher(model="plain")
        for first in range(0, len(samples.t), 20):
            rows = slice(first, first + 20)
            watcher.add(Received({"t": samples.t[rows], "q": angle[rows], "tau": samples.tau[rows]}))
        fits.append([trace.value for trace in watcher.refresh().parameters])
    np.testing.assert_allclose(fits[1], fits[0], rtol=1e-6)


def test_samples_that_are_not_numbers_are_a_gap_said_and_not_bridged():
    samples = arm(200.0, 30.0)
    tau = samples.tau.copy()
    tau[3000] = np.nan
    watcher = Watcher()
    for first in range(0, len(samples.t), 20):
        rows = slice(first, first + 20)
        watcher.add(Received({"t": samples.t[rows], "q": samples.q[rows], "tau": tau[rows]}))
    refresh = watcher.refresh()
    assert refresh.received == len(samples.t)
    assert any("1 samples holding values that are not numbers were left out at 15 s" in event
               for event in refresh.events), refresh.events
    for trace in refresh.parameters:
        assert np.isfinite(trace.value) and abs(trace.value - samples.truth[trace.name]) <= 0.05 * samples.truth[trace.name]


def test_settings_a_log_fit_refuses_are_refused_naming_the_argument():
    for settings, word in (({"effort": "current"}, "effort"), ({"mechanism": "flywheel"}, "mechanism"),
                           ({"window": 4}, "window"), ({"cutoff": -1.0}, "cutoff"), ({"decimate": 0}, "decimate"),
                           ({"zero": "sideways"}, "zero"), ({"mechanism": "arm", "linear": True}, "metres")):
        with pytest.raises(ValueError, match=word):
            Watcher(**settings)


def test_streamed_derivatives_and_low_pass_equal_the_offline_ones_away_from_the_ends():
    # The claim of studies.watch_streams: blocks of any size give, wherever the whole window has arrived, what the
    # log path's Savitzky-Golay derivatives (logs.derivatives) and parallel low-pass (estimation.low_pass) give.
    from jointid.estimation.low_pass import FilterRequest, choose_filter
    from jointid.logs.derivatives import differentiate, smooth
    from jointid.model.terms import model_named
    from jointid.studies.watch_streams import DerivativeStream, LowPassStream

    samples = arm(500.0, 20.0, noise=0.5)
    step, window, order = 0.002, 41, 3
    model = model_named("coulomb+bias")
    qd, qdd = differentiate(samples.q, step, window, order)
    offline = np.column_stack([qdd, smooth(9.81 * np.cos(samples.q), window, order), qd,
                               smooth(np.sign(qd), window, order), np.ones(len(qd)),
                               smooth(samples.tau, window, order)])
    chosen = choose_filter(FilterRequest(4.0, 5), step, True, samples.q, len(samples.q))
    filtered = np.column_stack([chosen.apply_column(offline[:, j]) for j in range(offline.shape[1])])
    derivatives, low_pass = DerivativeStream(model.terms, step, window, order), LowPassStream(chosen)
    rows, values = [], []
    first, sizes = 0, [3, 11, 7, 200, 1]
    while first < len(samples.t):
        part = slice(first, first + sizes[0])
        first, sizes = first + sizes[0], sizes[1:] + sizes[:1]
        out = derivatives.add({"t": samples.t[part], "q": samples.q[part], "tau": samples.tau[part]})
        if out is None:
            continue
        kept, low = low_pass.add(np.column_stack([out["X"], out["tau"]]), int(out["index"][0]))
        rows.append(kept), values.append(low)
    rows, values = np.concatenate(rows), np.concatenate(values)
    assert rows[0] * 5 >= window + chosen.extension and len(rows) > 0.8 * len(filtered)
    scale = np.max(np.abs(filtered), axis=0)
    np.testing.assert_allclose(values / scale, filtered[rows] / scale, atol=1e-10)


def test_a_break_the_source_marks_starts_a_stretch_even_where_time_runs_on():
    """A reconnection or a replaced file is a break (Received.breaks) whatever the times say: the stretches either
    side end there, as at a gap (a sample that is no number), so the rows that would need samples across it are
    not fitted; the estimates still converge."""
    samples = arm(200.0, 30.0)
    middle = 3010  # mid-block: a break need not fall on a block's first row

    def fed(how: str) -> Watcher:
        watcher = Watcher()
        tau = samples.tau.copy()
        if how == "gap":
            tau[middle - 1] = np.nan  # the sample before the break's row left out: the next stretch starts there
        for first in range(0, len(samples.t), 20):
            rows = slice(first, first + 20)
            marked = (middle - first,) if how == "break" and first <= middle < first + 20 else ()
            watcher.add(Received({"t": samples.t[rows], "q": samples.q[rows], "tau": tau[rows]}, breaks=marked))
        watcher.add(Received(ended=True))
        return watcher

    joined, broken, gap = (fed(how).refresh() for how in ("joined", "break", "gap"))
    assert joined.received == broken.received == gap.received == len(samples.t)
    assert broken.fitted < joined.fitted  # the rows either side of the break that need samples across it
    # As the gap: the same rows to within the decimation's phase (the gap's stretch before it is a sample shorter),
    # and the same estimates to far below their errors.
    assert abs(broken.fitted - gap.fitted) <= 0.01 * gap.fitted
    for trace, at_gap in zip(broken.parameters, gap.parameters):
        assert trace.name == at_gap.name
        assert abs(trace.value - at_gap.value) <= 1e-3 * abs(at_gap.value)
        assert abs(trace.value - samples.truth[trace.name]) <= 0.05 * samples.truth[trace.name]
