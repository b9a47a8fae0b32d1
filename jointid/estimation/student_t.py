"""Student-t quantiles in pure Python, so that intervals need no scipy.

Not importing ``scipy.special`` for one quantile per fit buys 0.54 of ``jointid
fit``'s start (bench_startup_budget student-t-quantile). This module uses only
the standard library.

Method
------
The distribution function comes from the regularized incomplete beta function
(Abramowitz & Stegun 26.7.1): with u = t^2 / nu and t >= 0,

    P(T > t)      = I_x(nu/2, 1/2) / 2,   x = 1 / (1 + u),
    P(0 < T <= t) = I_y(1/2, nu/2) / 2,   y = u / (1 + u),

each evaluated, where it converges fast, by the continued fraction of I with
the modified Lentz method (W. H. Press et al., *Numerical Recipes*, 3rd ed.,
2007, section 6.4). The quantile starts from Hill's approximation (G. W. Hill,
"Algorithm 396: Student's t-quantiles", Comm. ACM 13(10), 619-620, 1970) and
is refined by Newton steps on the distribution function with the t density,
kept inside a bracket by bisection.

One and two degrees of freedom have closed forms, which also bracket the
quantile in between. For many degrees of freedom the Cornish-Fisher expansion
around the normal quantile (Abramowitz & Stegun 26.7.5) is used instead, where
its truncation error is below rounding: there the tail's continued fraction,
whose x is within 1/nu of 1, would lose about nu * 1e-17 of relative accuracy.

Checked against a 60-digit evaluation of the same formulas, the relative error
is typically 2e-16 and below 3e-14 for tail probabilities down to 1e-100
(1e-13 beyond, where nu is near 1 and t near 1e300).
``scipy.stats.t.ppf`` agrees to 1e-14 except within about 0.01 of p = 1/2 for
few degrees of freedom, where scipy itself is off (by 1e-11 at nu = 4 and
p = 0.501, and it returns 0 for p = 1/2 + 1e-9).
"""

from __future__ import annotations

import math
import sys
_EXPANSION_MIN_DF = 2000.0
_EXPANSION_MAX_X2_PER_DF = 2e-3
"""The Cornish-Fisher expansion is used for nu >= 2000 and x^2 <= 2e-3 nu (x the normal quantile).

Its first omitted term, relative to x, is about 0.05 / nu^5 + (x^2 / (6 nu))^5
(estimated from the growth of the terms, checked against scipy), below 1e-17 there."""

_CF_TOLERANCE = 1e-15
"""Relative change of the continued fraction at which Lentz's method stops."""

_NEWTON_TOLERANCE = 1e-10
"""Newton step in log t after which the next one would be below rounding.

Newton converges quadratically: after a step s the error is about C s^2, with
C = |r''| / (2 r') of order one for both residuals (at most 1 near the centre,
about 1 for large nu in the tail, less in heavy tails where the residual is
nearly linear in log t). So once |s| <= 1e-10 the step just taken is the last."""


def student_t_quantile(probability: float, degrees_of_freedom: float) -> float:
    """The Student-t quantile t such that P(T <= t) = probability.

    Parameters
    ----------
    probability : float
        Lower-tail probability, strictly between 0 and 1.
    degrees_of_freedom : float
        nu, finite and >= 1; need not be an integer.

    Returns
    -------
    float
        The quantile: 0 at probability 0.5, and t(p) = -t(1 - p). It tends to
        the normal quantile as nu grows.

    Raises
    ------
    ValueError
        If probability is not in (0, 1) or degrees_of_freedom is not a finite number >= 1.
    """
    p = float(probability)
    nu = float(degrees_of_freedom)
    if not 0.0 < p < 1.0:  # also rejects NaN
        raise ValueError(f"probability must be strictly between 0 and 1, got {probability!r}")
    if not (math.isfinite(nu) and nu >= 1.0):
        raise ValueError(f"degrees_of_freedom must be a finite number >= 1, got {degrees_of_freedom!r}")
    if p == 0.5:
        return 0.0
    # Work with t > 0 and two targets, each exact in floating point (Sterbenz)
    # where it is used: the tail for p >= 0.5 and the centre for 1/4 <= p <= 3/4.
    sign = 1.0 if p > 0.5 else -1.0
    tail = min(p, 1.0 - p)
    centre = abs(p - 0.5)
    x = _upper_normal_quantile(tail)  # the normal quantile the t quantile tends to
    if nu == 1.0:
        t = _cauchy_quantile(tail, centre)
    elif nu == 2.0:
        t = _two_df_quantile(tail, centre)
    elif nu < 2.0:
        # Hill's approximation is not made for 1 < nu < 2 (it is 1e10 times too large
        # near the centre at nu = 1.0001), but the quantile lies between the closed
        # forms at nu = 2 and nu = 1: start from their geometric interpolation.
        low = _two_df_quantile(tail, centre)
        high = min(_cauchy_quantile(tail, centre), sys.float_info.max)  # inf for a subnormal tail
        start = math.exp((nu - 1.0) * math.log(low) + (2.0 - nu) * math.log(high))
        t = _newton(start, tail, centre, nu, low, high)
    elif nu >= _EXPANSION_MIN_DF and x * x <= _EXPANSION_MAX_X2_PER_DF * nu:
        t = _cornish_fisher(x, nu)
    else:
        t = _newton(_hill_start(x, tail, nu), tail, centre, nu)
    return sign * t


KNOWN_UPPER_NORMAL_QUANTILES = {1 - 0.975: 1.9599639845400536, 0.025: 1.9599639845400538}
"""-NormalDist().inv_cdf(tail) for the tails of 95 % intervals, which every fit asks for (the test of this module
checks them against statistics): statistics, with fractions, decimal and random, is then imported only for other
levels, sparing a few ms of each command's start."""


def _upper_normal_quantile(tail: float) -> float:
    """x with P(Z > x) = tail for a standard normal Z, 0 < tail <= 1/2 (statistics' Wichura AS 241)."""
    known = KNOWN_UPPER_NORMAL_QUANTILES.get(tail)
    if known is not None:
        return known
    from statistics import NormalDist

    return -NormalDist().inv_cdf(tail)


def _cauchy_quantile(tail: float, centre: float) -> float:
    """The upper quantile for nu = 1, tan(pi (p - 1/2)), written without the pole at p -> 1."""
    return math.tan(math.pi * centre) if centre <= 0.25 else 1.0 / math.tan(math.pi * tail)


def _two_df_quantile(tail: float, centre: float) -> float:
    """The upper quantile for nu = 2: F(t) = 1/2 + t / (2 sqrt(2 + t^2)) solved for t."""
    return 2.0 * centre / math.sqrt(2.0 * tail * (1.0 - tail))


def _cornish_fisher(x: float, nu: float) -> float:
    """The t quantile from the normal one, x, and four terms in 1/nu (A&S 26.7.5)."""
    x2 = x * x
    g1 = (x2 + 1.0) * x / 4.0
    g2 = ((5.0 * x2 + 16.0) * x2 + 3.0) * x / 96.0
    g3 = (((3.0 * x2 + 19.0) * x2 + 17.0) * x2 - 15.0) * x / 384.0
    g4 = ((((79.0 * x2 + 776.0) * x2 + 1482.0) * x2 - 1920.0) * x2 - 945.0) * x / 92160.0
    return x + (g1 + (g2 + (g3 + g4 / nu) / nu) / nu) / nu


def _hill_start(x: float, tail: float, nu: float) -> float:
    """Hill's (1970) approximation to the upper quantile from the normal one, x, and P(T > t)."""
    two_tail = 2.0 * tail  # Hill's P is the two-sided P(|T| > t)
    a = 1.0 / (nu - 0.5)
    b = 48.0 / (a * a)
    c = ((20700.0 * a / b - 98.0) * a - 16.0) * a + 96.36
    d = ((94.5 / (b + c) - 3.0) / b + 1.0) * math.sqrt(a * math.pi / 2.0) * nu
    log_d_two_tail = math.log(d) + math.log(two_tail)
    y = math.exp(2.0 / nu * log_d_two_tail)
    if y < 1e-100:
        # So far out (P below about 10^(-50 nu)) that the leading term t = sqrt(nu / y)
        # is the start, computed from logs: y underflows, and t may exceed the floats.
        log_t = 0.5 * math.log(nu) - log_d_two_tail / nu
        return math.exp(log_t) if log_t < 709.0 else math.inf
    if y > 0.05 + a:
        # Centre and moderate tails: an expansion around the normal quantile.
        x = -x  # Hill's normal deviate is the lower one
        y = x * x
        if nu < 5.0:
            c += 0.3 * (nu - 4.5) * (x + 0.6)
        c += (((0.05 * d * x - 5.0) * x - 7.0) * x - 2.0) * x + b
        y = (((((0.4 * y + 6.3) * y + 36.0) * y + 94.5) / c - y - 3.0) / b + 1.0) * x
        y = math.expm1(a * y * y)
    else:
        # Far tail for few degrees of freedom: the tail's own asymptotic series.
        y = ((1.0 / (((nu + 6.0) / (nu * y) - 0.089 * d - 0.822) * (nu + 2.0) * 3.0)
              + 0.5 / (nu + 4.0)) * y - 1.0) * (nu + 1.0) / (nu + 2.0) + 1.0 / y
    return math.sqrt(nu * y)


def _newton(
    t: float, tail: float, centre: float, nu: float, low: float = 0.0, high: float = math.inf
) -> float:
    """Solve F(t) = p for t > 0 by Newton steps in log t from t, falling back on bisection in [low, high].

    Steps are in log t because far in a heavy tail f(t) underflows while t f(t)
    does not, and because there log P(T > t) is nearly linear in log t.
    """
    if t == math.inf:
        return t
    for _ in range(100):
        residual, slope = _residual(t, tail, centre, nu)
        if residual == 0.0:
            return t
        if residual > 0.0:
            high = t
        else:
            low = t
        step = residual / slope if slope > 0.0 else math.copysign(math.inf, residual)
        if abs(step) <= _NEWTON_TOLERANCE:
            return t * math.exp(-step)
        new = t * math.exp(min(max(-step, -700.0), 700.0))  # exp raises beyond 709
        if not low < new < high:
            # Newton left the bracket (F is concave for t > 0, so from above it can
            # overshoot): bisect, doubling while there is no upper end yet.
            new = 2.0 * t if high == math.inf else 0.5 * (low + high)
        t = new
    return t


def _residual(t: float, tail: float, centre: float, nu: float) -> tuple[float, float]:
    """A residual with the sign of F(t) - p, and its derivative in log t, for t > 0.

    p = 1/2 + centre = 1 - tail. The residual is taken from whichever probability
    the continued fraction gives at t, so that it never suffers cancellation:
    P(0 < T <= t) - centre near the centre, log(tail / P(T > t)) in the tail,
    the latter from logarithms so that it survives where P(T > t) underflows.
    """
    a = 0.5 * nu
    s = t / math.sqrt(nu)
    u = s * s  # t^2 / nu; inf only for t beyond 1e154, in a tail of P < 1e-150
    log1p_u = math.log1p(u) if u < 1e300 else 2.0 * math.log(s)
    # t f(t) = Gamma(a + 1/2) / (Gamma(a) sqrt(pi)) x^a sqrt(y); it is also the
    # factor in front of both continued fractions (I's x^a (1 - x)^b / (a B(a, b))).
    log_density_times_t = (
        math.log(_gamma_ratio(a) / math.sqrt(math.pi)) - a * log1p_u + math.log(s / math.hypot(1.0, s))
    )
    # Numerical Recipes' choice of argument: I_x(a, b) directly when
    # x < (a + 1) / (a + b + 2), which for b = 1/2 is u > 3 / (nu + 2). Beyond
    # it the centre's fraction would also lose accuracy, not just speed.
    if u > 3.0 / (nu + 2.0):
        ratio = _beta_fraction(a, 0.5, 1.0 / (1.0 + u)) / nu  # P(T > t) / (t f(t))
        return math.log(tail) - log_density_times_t - math.log(ratio), 1.0 / ratio
    density_times_t = math.exp(log_density_times_t)
    central = density_times_t * _beta_fraction(0.5, a, u / (1.0 + u))
    return central - centre, density_times_t


def _gamma_ratio(a: float) -> float:
    """Gamma(a + 1/2) / Gamma(a) to rounding, for a >= 1/2.

    lgamma(a + 1/2) - lgamma(a) would carry lgamma's absolute error, 1e-9 at a = 5e5.
    Instead a is raised to 25 or more by Gamma(a + 3/2) / Gamma(a + 1) =
    (a + 1/2) / a * Gamma(a + 1/2) / Gamma(a), where the Stirling series of the
    log ratio (Bernoulli polynomials, B_k(1/2) - B_k(0)) is exact to 1e-16.
    """
    factor = 1.0
    while a < 25.0:
        factor *= a / (a + 0.5)
        a += 1.0
    r = 1.0 / (a * a)
    series = (-1.0 / 8.0 + r * (1.0 / 192.0 + r * (-1.0 / 640.0 + r * (17.0 / 14336.0)))) / a
    return factor * math.sqrt(a) * math.exp(series)


def _beta_fraction(a: float, b: float, x: float) -> float:
    """The continued fraction of I_x(a, b) by the modified Lentz method (Numerical Recipes 6.4).

    I_x(a, b) = x^a (1 - x)^b / (a B(a, b)) times this value. It converges
    quickly for x < (a + 1) / (a + b + 2).
    """
    tiny = 1e-300  # stands in for a zero denominator, as Lentz's method prescribes
    c = 1.0
    d = 1.0 - (a + b) * x / (a + 1.0)
    d = 1.0 / (d if abs(d) > tiny else tiny)
    fraction = d
    for m in range(1, 10_000):
        for coefficient in (
            m * (b - m) * x / ((a + 2 * m - 1.0) * (a + 2 * m)),  # even term d_2m
            -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1.0)),  # odd term d_2m+1
        ):
            d = 1.0 + coefficient * d
            d = 1.0 / (d if abs(d) > tiny else tiny)
            c = 1.0 + coefficient / c
            c = c if abs(c) > tiny else tiny
            fraction *= d * c
        if abs(d * c - 1.0) < _CF_TOLERANCE:
            break
    return fraction
