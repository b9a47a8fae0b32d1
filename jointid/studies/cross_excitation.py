"""Cross-excitation table: fit on each training motion, predict every motion against truth.

Each row fits one training motion (rich, slow, holds) at the current noise,
samples and seed; each column predicts one motion's noiseless torque. The rich
and slow columns use the experiment's sample count at the same instants as
training (t_i = 8 i/(N-1)), so the entry on a row's own motion is evaluated at
the very states the fit saw: it is marked training data, never held out. The
validation (`test`) column uses its 16 states, as the lab does.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from ..estimation.fit import FitResult, fitted_torque
from ..samples import JointData, rms
from ..synthetic.motions import TRAINING_MOTIONS, VALIDATION_MOTION
from ..synthetic.samples import training_data, validation_data
from ..synthetic.settings import Settings
from .experiment import run_experiment

PREDICTION_MOTIONS = ("rich", "slow", VALIDATION_MOTION.name)
"""Column order: the two moving training motions, then the validation motion."""


@dataclass(frozen=True, eq=False)
class CrossExcitationCell:
    """Prediction RMSE of one row's fit on one motion's noiseless torque."""

    training_motion: str
    prediction_motion: str
    rmse: float | None
    """RMS of (predicted - true) torque (N m), or None when the row has no unique fit."""
    is_training_data: bool
    """True when the prediction motion is the one the row was fitted on (not a held-out test)."""


@dataclass(frozen=True, eq=False)
class CrossExcitationRow:
    """One training motion's fit and its predictions on every motion."""

    training_motion: str
    fit: FitResult
    cells: tuple[CrossExcitationCell, ...]
    label: str = ""
    """The training motion's label, e.g. 'Rich motion' or 'Designed motion'."""

    @property
    def available(self) -> bool:
        """True when the training motion gives a unique fit."""
        return self.fit.estimate is not None


@dataclass(frozen=True, eq=False)
class CrossExcitationTable:
    """Rows per training motion (rich, slow, holds, and a designed motion's), columns per prediction motion."""

    settings: Settings
    """Noise, samples and seed used for every row (its motion is the one the user had chosen)."""
    rows: tuple[CrossExcitationRow, ...]

    @property
    def prediction_motions(self) -> tuple[str, ...]:
        """Column names in order."""
        return PREDICTION_MOTIONS

    def cell(self, training_motion: str, prediction_motion: str) -> CrossExcitationCell:
        """The entry for a training motion's fit predicting a motion."""
        row = next(r for r in self.rows if r.training_motion == training_motion)
        return row.cells[PREDICTION_MOTIONS.index(prediction_motion)]

    @cached_property
    def rmse_matrix(self) -> np.ndarray:
        """(rows, columns) RMSE by training and prediction motion, NaN where unavailable."""
        return np.array(
            [[np.nan if c.rmse is None else c.rmse for c in row.cells] for row in self.rows]
        )


def prediction_data(motion: str, settings: Settings) -> JointData:
    """Noiseless states and torque of a motion on the settings' joint: 16 validation states for `test`,
    else the settings' sample count."""
    if motion == VALIDATION_MOTION.name:
        return validation_data(settings.true_joint)
    return training_data(replace(settings, motion=motion, noise=0.0))


def cross_excitation(settings: Settings) -> CrossExcitationTable:
    """Fit each training motion at the settings' noise, samples and seed, and predict every motion."""
    model = settings.joint_model
    targets = {motion: prediction_data(motion, settings) for motion in PREDICTION_MOTIONS}
    regressors = {motion: model.data_regressor(target) for motion, target in targets.items()}
    rows = []
    training = dict(zip(TRAINING_MOTIONS, TRAINING_MOTIONS))
    if not isinstance(settings.motion, str):  # a designed motion gets a row of its own, after the lesson's
        training[settings.motion_name] = settings.motion
    for training_motion, motion in training.items():
        row_settings = replace(settings, motion=motion)
        fit = run_experiment(row_settings)
        cells = tuple(
            CrossExcitationCell(
                training_motion=training_motion,
                prediction_motion=motion,
                rmse=None
                if fit.estimate is None
                else rms(fitted_torque(regressors[motion], fit.column_estimate) - target.tau),
                is_training_data=motion == training_motion,
            )
            for motion, target in targets.items()
        )
        rows.append(CrossExcitationRow(training_motion, fit, cells, row_settings.training_motion.label))
    return CrossExcitationTable(settings=settings, rows=tuple(rows))
