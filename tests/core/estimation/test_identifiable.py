"""Identifiable subset: which parameters the data determine alone, at any rank."""

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import settings as hypothesis_settings
from hypothesis import strategies as st

from jointid.estimation.identifiable import identifiable_subset
from jointid.estimation.solver import solve_least_squares
from jointid.model.terms import G
from jointid.present.status import status_message
from jointid.studies.experiment import run_experiment
from jointid.synthetic.settings import Settings


def test_holds_determine_exactly_h_equal_to_0_4():
    result = run_experiment(Settings(motion="holds"))
    values = result.identifiable.values
    assert list(values) == ["h"]
    assert values["h"] == pytest.approx(0.4, abs=1e-14)  # 3.924 / 9.81
    assert result.identifiable.undetermined == ("I", "B")


def test_noisy_holds_give_h_as_the_mean_holding_torque_over_g():
    result = run_experiment(Settings(motion="holds", noise=0.2))
    assert list(result.identifiable.values) == ["h"]
    expected = float(np.mean(result.training.tau)) / G
    assert result.identifiable.values["h"] == pytest.approx(expected, rel=1e-13)


def test_holds_message_says_what_is_determined_and_why_the_rest_is_not():
    message = status_message(run_experiment(Settings(motion="holds")))
    assert message.startswith(
        "Rank 1 of 3: no unique least-squares fit. Parameter and prediction readouts are unavailable."
    )
    assert "mass moment h = 0.400000 kg m on its own" in message
    assert "Inertia and damping are not determined: the data have no acceleration and no velocity." in message


def test_full_rank_determines_every_parameter_at_the_estimate():
    result = run_experiment(Settings(motion="slow", noise=0.2))
    assert list(result.identifiable.values) == ["I", "h", "B"]
    np.testing.assert_array_equal(list(result.identifiable.values.values()), result.estimate)


def test_null_space_is_orthonormal_and_annihilates_the_scaled_regressor():
    X = np.array([[1.0, 2.0, 0.0, 3.0], [4.0, 8.0, 0.0, 1.0], [2.0, 4.0, 0.0, 5.0], [7.0, 14.0, 0.0, 2.0]])
    solution = solve_least_squares(X, np.ones(4))
    subset = identifiable_subset(solution, ("a", "b", "c", "d"))
    basis = subset.null_basis
    assert basis.shape == (4, 2)
    np.testing.assert_allclose(basis.T @ basis, np.eye(2), atol=1e-12)
    np.testing.assert_allclose((X / solution.scales) @ basis, 0.0, atol=1e-12)
    assert list(subset.values) == ["d"]  # b = 2a and c = 0 leave only d alone
    assert subset.zero_columns.tolist() == [False, False, True, False]


@st.composite
def structured_problems(draw):
    """Columns that are fresh, zero, or a scaled copy of an earlier fresh column; and what is determined."""
    columns = draw(st.integers(1, 6))
    kinds, sources = [], []
    for j in range(columns):
        fresh = [i for i in range(j) if kinds[i] == "fresh"]
        options = ["fresh", "zero"] + (["copy"] if fresh else [])
        kind = draw(st.sampled_from(options))
        kinds.append(kind)
        sources.append(draw(st.sampled_from(fresh)) if kind == "copy" else None)
    seed = draw(st.integers(0, 2**32 - 1))
    extra_rows = draw(st.integers(0, 8))
    factors = draw(st.lists(st.floats(-4, 4), min_size=columns, max_size=columns))
    return kinds, sources, seed, extra_rows, factors


@hypothesis_settings(max_examples=200, deadline=None)
@given(problem=structured_problems())
@example(problem=(["fresh"] * 6, [None] * 6, 0, 0, [0.0, -4.0, 3.0, 0.0, 1.0, 0.0]))  # a square system, condition 5e7
def test_duplicated_and_zero_columns_give_the_right_subset(problem):
    kinds, sources, seed, extra_rows, factors = problem
    rng = np.random.default_rng(seed)
    fresh_count = kinds.count("fresh")
    rows = max(fresh_count, 1) + extra_rows
    X = np.zeros((rows, len(kinds)))
    for j, kind in enumerate(kinds):
        if kind == "fresh":
            X[:, j] = rng.normal(size=rows) * 10.0 ** factors[j]
        elif kind == "copy":
            sign = 1.0 if factors[j] >= 0 else -1.0
            X[:, j] = sign * 10.0 ** abs(factors[j]) * X[:, sources[j]]
    y = rng.normal(size=rows)
    copied = {s for s in sources if s is not None}
    expected = [kind == "fresh" and j not in copied for j, kind in enumerate(kinds)]
    names = tuple(f"p{j}" for j in range(len(kinds)))
    solution = solve_least_squares(X, y)
    subset = identifiable_subset(solution, names)
    assert solution.rank == fresh_count
    assert subset.determined.tolist() == expected
    assert subset.zero_columns.tolist() == [kind == "zero" for kind in kinds]
    # Determined values agree with a full-rank fit on one column per direction, its columns scaled to unit norm:
    # unscaled, columns 10^-4 to 10^4 make lstsq's own answer wrong in the 7th digit (condition 5e7, seed 0).
    keep = [j for j, kind in enumerate(kinds) if kind == "fresh"]
    if keep:
        norms = np.linalg.norm(X[:, keep], axis=0)
        reduced = np.linalg.lstsq(X[:, keep] / norms, y, rcond=None)[0] / norms
        for j, value in zip(keep, reduced):
            if expected[j]:
                assert subset.values[names[j]] == pytest.approx(value, rel=1e-7, abs=1e-9 / np.linalg.norm(X[:, j]))


@pytest.mark.parametrize("angle", [np.pi / 2, -np.pi / 2, 3 * np.pi / 2, 2001 * np.pi / 2])
def test_a_joint_held_where_gravity_has_no_arm_determines_the_bias_not_h(angle):
    """Held at q = pi/2, cos(fl(q)) is rounding (6e-17), which column scaling made a full column: the data were
    said to determine h = 8e13 kg m on its own. The reference is numpy: the bias is the mean torque, and the
    held joint shows no gravity torque, so h cannot be determined."""
    from jointid.estimation.fit import fit_joint
    from jointid.model.terms import model_named
    from jointid.samples import JointData

    tau = 0.3 + np.random.default_rng(1).uniform(-0.05, 0.05, 200)
    zeros = np.zeros_like(tau)
    result = fit_joint(JointData(t=None, q=np.full_like(tau, angle), qd=zeros, qdd=zeros, tau=tau),
                       model=model_named("bias"))
    assert result.rank == 1
    assert list(result.identifiable.values) == ["tau0"]
    assert result.identifiable.values["tau0"] == pytest.approx(float(np.mean(tau)), rel=1e-12)
    assert "h" in result.identifiable.undetermined


def test_a_held_log_with_derivatives_from_its_angle_determines_only_the_bias(tmp_path):
    """The same hold logged as t, q, tau: qd and qdd estimated from a constant angle are rounding scaled by 1/dt
    and 1/dt^2, which were fitted into I = -1.6e9 and B = 1.4e11 'determined alone'."""
    from jointid.studies.log_fit import fit_log

    t = np.arange(400) / 100.0
    tau = 0.3 + np.random.default_rng(1).uniform(-0.05, 0.05, t.size)
    logs = fit_log({"t": t, "q": np.full_like(t, np.pi / 2), "tau": tau}, model="bias", sensitivity=False)
    assert logs.result.rank == 1
    assert list(logs.result.identifiable.values) == ["tau0"]
    # The torque is smoothed like the angle its derivatives came from, which moves its mean a little at the ends.
    assert logs.result.identifiable.values["tau0"] == pytest.approx(float(np.mean(tau)), rel=1e-3)
