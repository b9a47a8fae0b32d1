"""The pure-Python Student-t quantile against scipy, its symmetry, its input checks and its imports."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from support.import_check import packages_loaded

from jointid.estimation.student_t import student_t_quantile

DEGREES_OF_FREEDOM = [1, 2, 3, 4, 5, 7, 10, 21, 30, 50, 100, 1000, 10**4, 10**5, 10**6]
DEGREES_OF_FREEDOM += [1.5, 2.5, 3.7, 12.25, 1234.5]  # not integers
PROBABILITIES = [0.6, 0.75, 0.9, 0.95, 0.975, 0.99, 0.995, 0.999, 0.9999]
RELATIVE_TOLERANCE = 1e-10


@pytest.mark.parametrize("df", DEGREES_OF_FREEDOM)
def test_matches_scipy_on_the_grid(df):
    from scipy import stats

    assert student_t_quantile(0.5, df) == 0.0
    for p in PROBABILITIES:
        expected = float(stats.t.ppf(p, df))
        assert student_t_quantile(p, df) == pytest.approx(expected, rel=RELATIVE_TOLERANCE, abs=0), p


@pytest.mark.parametrize("df", DEGREES_OF_FREEDOM)
def test_lower_probabilities_mirror_the_upper_ones(df):
    from scipy import stats

    for p in PROBABILITIES:
        # 1 - p is exact for p >= 1/2, so the mirror image is exact too.
        assert student_t_quantile(1.0 - p, df) == -student_t_quantile(p, df)
    for p in [1e-6, 1e-12, 1e-30]:  # far tails, beyond the 1 - p that a double can hold
        expected = float(stats.t.ppf(p, df))
        assert student_t_quantile(p, df) == pytest.approx(expected, rel=RELATIVE_TOLERANCE, abs=0), p


@pytest.mark.parametrize("df", [1e7, 1e12, 1e300])
def test_approaches_the_normal_quantile_for_huge_degrees_of_freedom(df):
    from scipy import stats

    for p in [0.6, 0.975, 0.9999, 1e-10]:
        expected = float(stats.t.ppf(p, df)) if df < 1e20 else float(stats.norm.ppf(p))
        assert student_t_quantile(p, df) == pytest.approx(expected, rel=1e-14, abs=0), p


@settings(max_examples=200, deadline=None)
@given(
    df=st.integers(min_value=1, max_value=10**6) | st.floats(min_value=1.0, max_value=1e6),
    p=st.floats(min_value=0.5, max_value=0.9999),
)
def test_scipy_distribution_function_at_the_quantile_gives_back_the_probability(df, p):
    """F(t) = p to within 1e-10 of t f(t), that is t within 1e-10 relative.

    The check goes through scipy's incomplete beta rather than scipy.stats.t.ppf,
    which is itself off near p = 1/2 for few degrees of freedom (it returns 0 at
    df = 4, p = 1/2 + 1e-9). F(t) - p is formed without cancellation: from the
    central probability P(0 < T <= t) while t^2 <= df, from the tail beyond.
    """
    from scipy import special, stats

    t = student_t_quantile(p, df)
    if p == 0.5:
        assert t == 0.0
        return
    assert t > 0.0
    if t * t <= df:
        excess = 0.5 * special.betainc(0.5, df / 2, t * t / (df + t * t)) - (p - 0.5)
    else:
        excess = (1.0 - p) - 0.5 * special.betainc(df / 2, 0.5, df / (df + t * t))
    assert abs(excess) <= RELATIVE_TOLERANCE * t * stats.t.pdf(t, df)


@pytest.mark.parametrize("probability", [0.0, 1.0, -0.1, 1.5, math.nan, math.inf])
def test_rejects_a_probability_outside_the_open_unit_interval(probability):
    with pytest.raises(ValueError, match=r"probability must be strictly between 0 and 1, got"):
        student_t_quantile(probability, 10)


@pytest.mark.parametrize("df", [0, 0.5, -3, math.nan, math.inf])
def test_rejects_degrees_of_freedom_below_one_or_not_finite(df):
    with pytest.raises(ValueError, match=r"degrees_of_freedom must be a finite number >= 1, got"):
        student_t_quantile(0.975, df)


def test_import_leaves_scipy_out():
    assert packages_loaded("jointid.estimation.student_t", {"scipy"}) == []


def test_module_itself_needs_only_the_standard_library():
    """Loaded on its own, without the jointid package (which brings numpy), it adds only stdlib modules."""
    path = Path(__file__).resolve().parents[3] / "jointid" / "estimation" / "student_t.py"
    code = (
        "import importlib.util, json, sys; before = set(sys.modules); "
        f"spec = importlib.util.spec_from_file_location('student_t', {str(path)!r}); "
        "spec.loader.exec_module(importlib.util.module_from_spec(spec)); "
        "added = {m.split('.')[0] for m in set(sys.modules) - before}; "
        "print(json.dumps(sorted(added - set(sys.stdlib_module_names))))"
    )
    output = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert json.loads(output.stdout) == []


def test_a_fit_imports_no_scipy():
    loaded = packages_loaded("jointid.cli", {"scipy"},
                             run="jointid.cli.main(['fit', '--noise', '0.2', '--json'])")
    assert loaded == []


def test_the_kept_normal_quantiles_are_statistics_own():
    """The 95 % intervals' normal quantiles kept as numbers are NormalDist's to the last bit, and the quantiles
    built on them are scipy's."""
    from statistics import NormalDist

    from scipy.stats import t as student_t

    from jointid.estimation.student_t import KNOWN_UPPER_NORMAL_QUANTILES

    for tail, value in KNOWN_UPPER_NORMAL_QUANTILES.items():
        assert value == -NormalDist().inv_cdf(tail)
    for df in (3.0, 40.0, 2500.0, 1e7):
        assert student_t_quantile(0.975, df) == pytest.approx(student_t.ppf(0.975, df), rel=1e-12)
