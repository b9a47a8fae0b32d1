"""jointid: identify a rotating joint's dynamic parameters from motion and torque, and judge the fit.

The lesson's model, `plain`, is tau = I*qdd + h*g*cos(q) + B*qd; other models
add terms (`jointid.model`, e.g. ``Settings(model="bias")``). Typical use::

    import jointid
    result = jointid.run_experiment(jointid.Settings(motion="slow", noise=0.2))
    result.estimate        # array([-1.607788..., 0.400093..., 0.109965...])
    result.heldout_rmse    # 2.261864...
    print(result.message)

For your own data, build a `JointData` and call `fit_joint` (with `model=` for another model).
"""

from .dataset import JointData
from .experiment import run_experiment, training_data, validation_data
from .fit import FitResult, fit_joint
from .model import (
    G,
    PARAMETER_NAMES,
    PLAIN,
    TRUE_PARAMETERS,
    JointModel,
    Term,
    model_named,
    predict_torque,
    regressor,
    torque_breakdown,
)
from .settings import Settings, SettingsError
from .solver import LeastSquaresSolution, solve_least_squares

__all__ = [
    "G",
    "PARAMETER_NAMES",
    "PLAIN",
    "JointModel",
    "Term",
    "model_named",
    "TRUE_PARAMETERS",
    "FitResult",
    "JointData",
    "LeastSquaresSolution",
    "Settings",
    "SettingsError",
    "fit_joint",
    "predict_torque",
    "regressor",
    "run_experiment",
    "solve_least_squares",
    "torque_breakdown",
    "training_data",
    "validation_data",
]
