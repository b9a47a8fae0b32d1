"""Numbers at the edges of double precision: norms, the solver, standard errors, JSON text and typed numbers."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import settings as hypothesis_settings
from hypothesis import strategies as st

from jointid.estimation.fit import fit_joint
from jointid.estimation.solver import NonFiniteError, solve_least_squares
from jointid.estimation.uncertainty import parameter_uncertainty
from jointid.logs.derivatives import MAX_ORDER, MAX_WINDOW, FilterSettingError, check_filter
from jointid.norms import all_finite, column_norms, power_of_two_scale, rms, row_norms, row_rms
from jointid.options import SettingsError, parse_float, parse_int, parse_setting
from jointid.present.documents import NonFiniteValue, json_text
from jointid.present.status import status_message
from jointid.present.text import format_number
from jointid.samples import JointData

ordinary = st.one_of(st.just(0.0), st.floats(1e-6, 1e6), st.floats(-1e6, -1e-6))
"""Values of ordinary size (a 1e-168 would be an extreme one: its square underflows)."""


@hypothesis_settings(max_examples=200, deadline=None)
@given(st.lists(ordinary, min_size=1, max_size=40), st.integers(1, 4))
def test_norms_of_ordinary_data_are_the_plain_formulas_bit_for_bit(values, width):
    values = np.array(values)
    rows = np.resize(values, (width, len(values)))
    assert rms(values) == float(np.sqrt(np.mean(np.square(values))))
    np.testing.assert_array_equal(row_rms(rows), np.sqrt(np.mean(np.square(rows), axis=1)))
    np.testing.assert_array_equal(row_norms(rows), np.sqrt(np.square(rows).sum(axis=1)))
    np.testing.assert_array_equal(column_norms(rows.T), np.sqrt(np.einsum("ij,ij->j", rows.T, rows.T)))


@pytest.mark.parametrize("scale", [1e154, 1e200, 1e300, 1e-170, 1e-300, 1e-310, 5e-324])
def test_norms_of_extreme_data_are_accurate_not_inf_or_zero(scale):
    values = np.array([0.3, -1.7, 2.2, 0.0, 1.1]) * scale
    expected = math.hypot(*values)  # Python's hypot scales internally
    assert column_norms(values[:, None])[0] == pytest.approx(expected, rel=1e-12)
    assert row_norms(values[None, :])[0] == pytest.approx(expected, rel=1e-12)
    assert rms(values) == pytest.approx(expected / math.sqrt(len(values)), rel=1e-12)
    assert row_rms(values[None, :])[0] == rms(values)  # a row alone and among rows agree


def test_power_of_two_scale_brackets_the_value_and_ignores_zero_and_nonfinite():
    scales = power_of_two_scale([3.0, 4.0, 1e-320, 0.0, np.inf, np.nan])
    np.testing.assert_array_equal(scales, [4.0, 8.0, 2.0 ** math.frexp(1e-320)[1], 1.0, 1.0, 1.0])


def problem(rows=30, seed=3):
    rng = np.random.default_rng(seed)
    return rng.normal(size=(rows, 3)) * [1.0, 10.0, 0.1], rng.normal(size=rows)


@pytest.mark.parametrize("column_power, target_power", [(600, 0), (-600, 0), (0, 700), (0, -700), (900, 900),
                                                        (-900, -500), (500, -500)])
def test_the_solver_is_exactly_scale_invariant_under_powers_of_two(column_power, target_power):
    """Scaling X by 2^k and y by 2^m scales the estimate by 2^(m-k) bit for bit, even where squares overflow."""
    X, y = problem()
    base = solve_least_squares(X, y)
    scaled = solve_least_squares(np.ldexp(X, column_power), np.ldexp(y, target_power))
    assert scaled.rank == 3
    np.testing.assert_array_equal(scaled.estimate, np.ldexp(base.estimate, target_power - column_power))
    assert scaled.residual_norm == math.ldexp(base.residual_norm, target_power)
    ours, theirs = parameter_uncertainty(base, 0.2), parameter_uncertainty(scaled, math.ldexp(0.2, target_power))
    np.testing.assert_array_equal(theirs.residual_std_error, np.ldexp(ours.residual_std_error, target_power - column_power))
    np.testing.assert_array_equal(theirs.noise_bound_std_error,
                                  np.ldexp(ours.noise_bound_std_error, target_power - column_power))
    assert theirs.verdicts == ours.verdicts


@pytest.mark.parametrize("where", ["X", "y"])
@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_the_solver_refuses_values_that_are_not_finite(where, bad):
    X, y = problem()
    (X if where == "X" else y)[4, ...] = bad  # a NaN once passed for a full-rank column: "Rank 3" with NaNs
    with pytest.raises(NonFiniteError, match="not finite"):
        solve_least_squares(X, y)


def test_the_solver_takes_finite_columns_whose_sum_overflows():
    """The finite check's one-pass sum overflows here; every value is finite, so the solve goes on, and scaling
    a column by 2^1020 scales its estimate by 2^-1020 bit for bit."""
    X, y = problem()
    X[:, 0] = np.abs(X[:, 0]) + 1.0  # one sign: the sum of 30 values near 2^1021 exceeds double precision
    base = solve_least_squares(X, y)
    huge = X.copy()
    huge[:, 0] = np.ldexp(X[:, 0], 1020)
    with np.errstate(over="ignore"):
        assert np.isinf(huge.sum()) and np.isfinite(huge).all()
    with np.errstate(over="raise", invalid="raise", divide="raise"):  # as on the command line
        scaled = solve_least_squares(huge, y)
    assert scaled.rank == 3
    np.testing.assert_array_equal(scaled.estimate, base.estimate * [2.0 ** -1020, 1.0, 1.0])


def test_the_solver_refuses_opposite_infinities_whose_sum_is_nan():
    X, y = problem()
    X[3, 0], X[7, 2] = np.inf, -np.inf
    with np.errstate(over="raise", invalid="raise", divide="raise"), pytest.raises(NonFiniteError, match="not finite"):
        solve_least_squares(X, y)


def test_the_solver_refuses_an_estimate_that_overflows():
    X, y = problem()
    X[:, 0] *= 1e-300
    with pytest.raises(NonFiniteError, match="overflows"):
        solve_least_squares(X, y * 1e300)


def test_a_fit_of_huge_motion_has_full_rank_and_finite_readouts():
    t = np.linspace(0, 8, 24)
    q = 0.7 * np.sin(1.3 * t)
    qd, qdd = 0.91 * np.cos(1.3 * t) * 1e200, -1.183 * np.sin(1.3 * t) * 1e200
    data = JointData(t=t, q=q, qd=qd, qdd=qdd, tau=0.8 * qdd + 0.4e200 * 9.81 * np.cos(q) + 0.15 * qd)
    result = fit_joint(data)
    assert result.rank == 3 and "no acceleration" not in status_message(result)
    np.testing.assert_allclose(result.estimate, [0.8, 0.4e200, 0.15], rtol=1e-12)
    assert math.isfinite(result.speed_rms) and math.isfinite(result.accel_rms) and result.speed_rms > 1e199
    assert all(map(math.isfinite, result.uncertainty.residual_std_error))


def test_json_text_is_strict_and_names_what_is_not_finite():
    assert json.loads(json_text({"a": [1.5, None]})) == {"a": [1.5, None]}
    with pytest.raises(NonFiniteValue) as raised:
        json_text({"statistics": {"I": {"mean": 1.0, "std": math.inf}}})
    assert raised.value.key == "statistics.I.std"
    with pytest.raises(NonFiniteValue, match=r"rows\[1\] is not a finite number"):
        json_text({"rows": [0.0, math.nan]})


@pytest.mark.parametrize("text", ["٣", "２", "1_000", "0x10", "1e", "", "١.٥", "+-1", "1 2"])
def test_typed_numbers_are_ascii_decimal_only(text):
    with pytest.raises(ValueError):
        parse_float(text)
    with pytest.raises(ValueError):
        parse_int(text)


def test_typed_numbers_accept_ordinary_spellings():
    assert [parse_float(t) for t in (" 0.5 ", "-1e-3", ".5", "5.", "+2E3")] == [0.5, -1e-3, 0.5, 5.0, 2000.0]
    assert math.isnan(parse_float("nan")) and parse_float("-Infinity") == -math.inf
    assert [parse_int(t) for t in ("7", " -3 ", "+12")] == [7, -3, 12]


@pytest.mark.parametrize("field, text", [("noise", "٣"), ("noise", "２"), ("samples", "٢٤"), ("seed", "７")])
def test_settings_typed_in_the_explorer_refuse_non_ascii_digits(field, text):
    with pytest.raises(SettingsError, match=f"got '{text}'"):
        parse_setting(field, text)


def test_a_non_finite_noise_is_called_that():
    with pytest.raises(SettingsError, match="must be a finite number from 0 to 100"):
        parse_setting("noise", "-inf")


def test_readouts_of_extreme_values_are_short_and_ordinary_ones_unchanged():
    assert format_number(0.793312285) == "0.793312" and format_number(-0.0) == "0.000000"
    assert format_number(1e-17) == "0.000000"  # an ordinary fit's rounding residue still reads as zero
    assert format_number(4e153) == "4.000000e+153" and format_number(-1.4e-170) == "-1.400000e-170"
    assert format_number(math.inf) == "inf"


def test_the_filter_is_bounded():
    check_filter(MAX_WINDOW, MAX_ORDER)
    with pytest.raises(FilterSettingError, match=f"at most {MAX_WINDOW}"):
        check_filter(MAX_WINDOW + 2, 4)
    with pytest.raises(FilterSettingError, match=f"at most {MAX_ORDER}"):
        check_filter(201, MAX_ORDER + 1)


@pytest.mark.parametrize("special", [np.nan, np.inf, -np.inf, 1e300, -1e300, 1.5e154, 5e-324, 0.0])
@pytest.mark.parametrize("where", [0, 500, 999])
def test_all_finite_is_the_elementwise_test_even_where_the_squares_overflow(special, where):
    values = np.linspace(-1.0, 1.0, 1000)
    values[where] = special
    expected = bool(np.isfinite(values).all())
    assert all_finite(values) is expected
    assert all_finite(values[::3]) is bool(np.isfinite(values[::3]).all())
    with np.errstate(over="ignore"):
        huge = values * 1e200  # every square overflows: the dot product is inf even without a special value
    assert all_finite(huge) is bool(np.isfinite(huge).all())


def test_all_finite_of_an_empty_column_is_true():
    assert all_finite(np.empty(0)) is True
