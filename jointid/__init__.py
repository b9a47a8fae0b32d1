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

from __future__ import annotations

import importlib

_HOMES = {
    "JointData": "dataset",
    "run_experiment": "experiment",
    "training_data": "experiment",
    "validation_data": "experiment",
    "FitResult": "fit",
    "fit_joint": "fit",
    "G": "model",
    "PARAMETER_NAMES": "model",
    "PLAIN": "model",
    "TRUE_PARAMETERS": "model",
    "JointModel": "model",
    "Term": "model",
    "model_named": "model",
    "predict_torque": "model",
    "regressor": "model",
    "torque_breakdown": "breakdown",
    "Settings": "settings",
    "SettingsError": "settings",
    "LeastSquaresSolution": "solver",
    "solve_least_squares": "solver",
}
"""Each public name's module. They load on first use (PEP 562), so `import jointid` and the command
line's help need no numpy."""

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


def __getattr__(name: str):
    """Import a public name's module on first use and keep the name here."""
    home = _HOMES.get(name)
    if home is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{home}", __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    """The module's own names and every public name, loaded or not."""
    return sorted({*globals(), *__all__})
