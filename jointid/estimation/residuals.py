"""Training residuals (measured - fitted torque) against time, q, qd and qdd, for a residual view.

Least-squares residuals are orthogonal to every regressor column, so a straight
trend against any of the model's columns cannot remain; what can remain is
structure the model has no column for. Each axis comes with a one-line note
on what such structure would mean. A rank-deficient fit still has residuals:
every least-squares solution gives the same fitted torque, so the basic one is
used.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .fit import FitResult, fitted_torque

AXES = ("t", "q", "qd", "qdd")
"""The horizontal axes a residual view can switch between, in order."""

AXIS_LABELS = {
    "t": "time (s)",
    "q": "angle q (rad)",
    "qd": "velocity qd (rad/s)",
    "qdd": "acceleration qdd (rad/s²)",
}
"""Axis titles with units."""

AXIS_NOTES = {
    "t": "A drift or trend over time would mean something changes during the run "
    "(warm-up, a drifting torque sensor); bounded noise looks like a flat band.",
    "q": "A wave against angle would mean gravity is modelled wrong (a centre-of-mass angle "
    "offset adds a sin q term); a constant offset would mean a torque sensor bias.",
    "qd": "A step at qd = 0 would mean Coulomb friction, which B*qd cannot take; "
    "curvature would mean damping that is not proportional to speed.",
    "qdd": "A bend or a fan against acceleration would mean load-dependent effects "
    "(compliance, a time lag between torque and state); a line cannot remain after the fit.",
}
"""What structure in the residuals against each axis would mean, one line each."""


@dataclass(frozen=True, eq=False)
class ResidualData:
    """Training residuals and the values of every axis at the same samples."""

    residuals: np.ndarray
    """(N,) Measured minus fitted training torque (N m)."""
    axes: dict[str, np.ndarray]
    """(N,) arrays keyed by AXES; 't' is the sample index when the data had no times."""
    has_times: bool
    """False when 't' holds sample indices because the source had no time column."""
    unique_fit: bool
    """False when the residuals come from the basic solution of a rank-deficient fit."""
    unit: str = "N m"
    """The residuals' unit: the fitted effort's (N m, or V for a voltage log)."""

    def note(self, axis: str) -> str:
        """What structure in the residuals against `axis` would mean."""
        return AXIS_NOTES[axis]


def residual_data(result: FitResult) -> ResidualData:
    """The training residuals of a fit, with their time, angle, velocity and acceleration."""
    data = result.training
    theta = result.column_estimate if result.column_estimate is not None else result.solution.basic_estimate
    residuals = data.tau - fitted_torque(result.training_regressor, theta)
    axes = {"t": data.time_axis, "q": data.q, "qd": data.qd, "qdd": data.qdd}
    return ResidualData(
        residuals=residuals,
        axes=axes,
        has_times=data.t is not None,
        unique_fit=result.estimate is not None,
        unit=result.model.effort.unit,
    )
