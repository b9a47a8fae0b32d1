"""A log fit low-passes each column once: the sensitivity check's cutoffs share its spectrum, and the omitted-terms
candidates and the offset refit's columns come from the same pass; each must equal what filtering apart gives."""

from __future__ import annotations

import numpy as np
import pytest

from jointid import threads
from jointid.estimation import low_pass
from jointid.estimation.low_pass import FilterRequest
from jointid.logs.pipeline import joint_log_from_table
from jointid.logs.table import LogTable
from jointid.model.terms import G, model_named
from jointid.studies import log_fit

RATE = 200.0


def long_log(seconds: float) -> LogTable:
    """t, q, qd, qdd and a noisy tau (friction and a bias) of a joint swinging at two frequencies."""
    rng = np.random.default_rng(8)
    t = np.arange(int(seconds * RATE)) / RATE
    q = 0.7 * np.sin(1.3 * t) + 0.25 * np.sin(2.7 * t)
    qd = 0.91 * np.cos(1.3 * t) + 0.675 * np.cos(2.7 * t)
    qdd = -1.183 * np.sin(1.3 * t) - 1.8225 * np.sin(2.7 * t)
    tau = 0.8 * qdd + 0.4 * G * np.cos(q) + 0.15 * qd + 0.2 * np.sign(qd) + 0.05 + rng.normal(0, 0.3, t.size)
    columns = {"t": t, "q": q, "qd": qd, "qdd": qdd, "tau": tau}
    return LogTable("log.csv", columns, {name: i + 1 for i, name in enumerate(columns)}, (), ((0, 0),))


@pytest.mark.parametrize("seconds", [20.0, 90.0], ids=["filtered apart", "sharing one spectrum"])
def test_shared_and_reused_columns_give_what_filtering_apart_gives(seconds):
    log = joint_log_from_table(long_log(seconds))
    chosen = log_fit.low_pass_for(log, FilterRequest(5.0))
    others = [log_fit.low_pass_for(log, FilterRequest(5.0 * factor, chosen.decimation)) for factor in (0.5, 2.0)]
    shared = low_pass.shared_size([chosen, *others], log.data.count) is not None
    assert shared == (seconds > 60)  # the long log is the one over MIN_SHARED_BLOCKS blocks
    logs = log_fit.fit_logs(log, model=model_named("coulomb+bias"), filtering=FilterRequest(5.0))
    assert logs.omitted is not None and logs.offset is not None and logs.sensitivity is not None
    # The offset refit and the candidates, each filtered apart through the chosen filter.
    apart = log_fit._offset_refit(log, logs.result.model, False, logs.filter, logs.result, logs.exclusion,
                                  logs.exclusions)
    assert apart[0] == logs.offset[0]
    candidates = log_fit._candidates(logs.result.model)
    (Z, _), = log_fit.filtered_regressors(log, log_fit.JointModel("candidates", candidates), (logs.filter,))
    again = log_fit._omitted_terms(logs.result.model, candidates, Z, logs.result, logs.exclusions)
    if shared:  # one spectrum against blocks apart: the same to rounding
        np.testing.assert_allclose(logs.offset[1], apart[1], rtol=1e-9)
        np.testing.assert_allclose(logs.offset[2], apart[2], rtol=1e-9)
        np.testing.assert_allclose([c.t for c in logs.omitted.candidates], [c.t for c in again.candidates],
                                   rtol=1e-8)
    else:  # the same filter on the same column: bit for bit
        np.testing.assert_array_equal(logs.offset[1], apart[1])
        np.testing.assert_array_equal(logs.offset[2], apart[2])
        assert [c.t for c in logs.omitted.candidates] == [c.t for c in again.candidates]
    # Each cutoff refit from the shared pass against its own filter applied apart.
    columns = log_fit.filtered_regressors(log, logs.result.model, (logs.filter, *others))
    for other, (X, tau) in zip(others, columns[1:]):
        (X_apart, tau_apart), = log_fit.filtered_regressors(log, logs.result.model, (other,))
        np.testing.assert_allclose(X, X_apart, rtol=0, atol=1e-12 * np.max(np.abs(X_apart)))
        np.testing.assert_allclose(tau, tau_apart, rtol=0, atol=1e-12 * np.max(np.abs(tau_apart)))


def test_columns_filtered_on_several_threads_equal_one_thread_bit_for_bit(monkeypatch):
    """The columns go through their filters side by side (jointid.threads); each lands in its own place."""
    log = joint_log_from_table(long_log(90.0))
    model = model_named("coulomb+bias")
    chosen = log_fit.low_pass_for(log, FilterRequest(5.0))
    others = [log_fit.low_pass_for(log, FilterRequest(5.0 * factor, chosen.decimation)) for factor in (0.5, 2.0)]
    candidates = log_fit._candidates(model)
    monkeypatch.setattr(threads.os, "cpu_count", lambda: 1)
    alone = log_fit.filtered_regressors(log, model, (chosen, *others), candidates)
    monkeypatch.setattr(threads.os, "cpu_count", lambda: 4)
    side_by_side = log_fit.filtered_regressors(log, model, (chosen, *others), candidates)
    assert len(alone) == len(side_by_side) == 4
    for (X, tau), (X_threads, tau_threads) in zip(alone, side_by_side):
        np.testing.assert_array_equal(X_threads, X)
        np.testing.assert_array_equal(tau_threads, tau)
    assert all(np.isfinite(X).all() for X, _ in alone[:3])
