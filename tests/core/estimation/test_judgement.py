"""One judgement per parameter: checks weaken a verdict and say why; the library's intervals are the command line's."""

from __future__ import annotations

import math

import numpy as np
import pytest
from support.coulomb_joint import coulomb_joint_log

import jointid
from jointid.estimation.judgement import Finding, Scatter, judge
from jointid.estimation.uncertainty import AT_BOUND, NOT_DETERMINED, WEAK, WELL_DETERMINED
from jointid.studies.refits import chi_squared_quantile, scatter_ratios


def test_a_finding_weakens_only_a_well_determined_verdict_and_says_why():
    # Relative errors 2 %, 20 % and 50 %: well determined, weak and not determined by the noise alone.
    judged = judge(("I", "h", "B"), [2.0, 20.0, 50.0], None,
                   [Finding("I", "moved by the derivative settings"), Finding("h", "moved by a term the model lacks")])
    assert judged.noise_verdicts == (WELL_DETERMINED, WEAK, NOT_DETERMINED)
    assert judged.verdicts == (WEAK, WEAK, NOT_DETERMINED)
    # Only a verdict the checks lowered carries a reason: h was weak already.
    assert judged.reasons == ("moved by the derivative settings", "", "")
    assert judged.to_dict()["verdict_reasons"] == {"I": "moved by the derivative settings"}


def test_a_scatter_judges_on_the_widened_error_and_is_never_well_determined():
    # 4 % widened 3x is 12 %: weak by the 10 % limit; 9 % widened 4x is 36 %: not determined (the 30 % limit);
    # 1 % widened 2x is 2 %, still within the limit, yet a scatter beyond the errors is a finding in itself.
    judged = judge(("I", "h", "B"), [4.0, 9.0, 1.0], None,
                   scatters=[Scatter("I", 3.0, "halves of the run"), Scatter("h", 4.0, "runs"),
                             Scatter("B", 2.0, "runs")])
    assert judged.verdicts == (WEAK, NOT_DETERMINED, WEAK)
    assert judged.reasons[1] == "its runs scatter 4.0 times their errors"


def test_a_parameter_at_its_bound_stays_at_bound():
    judged = judge(("I", "B"), [2.0, math.nan], [False, True], [Finding("B", "moved by --no-robust")])
    assert judged.verdicts == (WELL_DETERMINED, AT_BOUND) and judged.reasons == ("", "")


@pytest.mark.parametrize("dof, exact", [(1, 6.634897), (2, 9.210340), (3, 11.344867), (10, 23.209251)])
def test_the_chi_squared_quantile_is_within_two_and_a_half_percent_of_the_table(dof, exact):
    # 99 % quantiles from a chi-squared table (scipy.stats.chi2.ppf(0.99, dof)).
    assert chi_squared_quantile(dof) == pytest.approx(exact, rel=0.025)


def test_scatter_ratios_are_birge_ratios_about_the_weighted_mean():
    values, errors = np.array([[1.0], [3.0]]), np.array([[1.0], [1.0]])
    ratios, significant = scatter_ratios(values, errors)
    # Mean 2, chi-squared (1 + 1) / 1 dof = 2: ratio sqrt(2), far below the 99 % quantile 6.63.
    assert ratios[0] == pytest.approx(math.sqrt(2)) and not significant[0]
    ratios, significant = scatter_ratios(np.array([[0.0], [10.0]]), errors)
    assert ratios[0] == pytest.approx(math.sqrt(50)) and significant[0]


def test_conf_int_is_interval95_exactly_on_a_filtered_log():
    """A low-passed log's intervals use the effective count's degrees of freedom; conf_int(0.05) must too."""
    logs = jointid.fit_log(coulomb_joint_log(1), sensitivity=False)
    intervals = logs.result.uncertainty.interval95
    assert logs.result.uncertainty.effective_count is not None  # the case where the two used to differ
    for name, (low, high) in zip(logs.result.model.names, intervals):
        assert logs.conf_int(0.05)[name] == (low, high)


def test_the_library_carries_the_judged_verdicts():
    logs = jointid.fit_log(coulomb_joint_log(2))
    assert dict(logs.verdicts) == dict(zip(logs.result.model.names, logs.result.judgement.verdicts))
    assert logs.result.verdicts is not None and set(logs.verdicts) == set(logs.params)
    # A synthetic fit has no other check: its verdicts are the noise's.
    result = jointid.run_experiment(jointid.Settings(motion="slow", noise=0.2))
    assert tuple(result.verdicts.values()) == result.uncertainty.verdicts
