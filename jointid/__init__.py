"""jointid: identify a rotating joint's dynamic parameters from motion and torque, and judge the fit.

The lesson's model, `plain`, is tau = I*qdd + h*g*cos(q) + B*qd; other models
add terms (`jointid.model.terms`, e.g. ``Settings(model="bias")``). Typical use::

    import jointid
    result = jointid.run_experiment(jointid.Settings(motion="slow", noise=0.2))
    result.params["I"]     # -1.607788...
    result.bse["I"]        # 5.425077... (the ± `jointid fit` prints)
    result.heldout_rmse    # 2.261864...
    print(result.summary())

For a recorded log, `fit_log(path_or_arrays)` does what `jointid fit --csv` does (`fit_wpilog(path)` what
`jointid fit --wpilog` does); for samples of your own,
build a `JointData` and call `fit_joint` (with `model=` for another model). See docs/library.md.
"""

from __future__ import annotations

import importlib

_HOMES = {
    "JointData": "samples",
    "run_experiment": "studies.experiment",
    "training_data": "synthetic.samples",
    "validation_data": "synthetic.samples",
    "FitResult": "estimation.fit",
    "fit_joint": "estimation.fit",
    "G": "model.terms",
    "PARAMETER_NAMES": "model.terms",
    "PLAIN": "model.terms",
    "TRUE_PARAMETERS": "model.terms",
    "JointModel": "model.terms",
    "Term": "model.terms",
    "model_named": "model.terms",
    "predict_torque": "model.terms",
    "regressor": "model.terms",
    "torque_breakdown": "model.breakdown",
    "Settings": "synthetic.settings",
    "SettingsError": "options",
    "LeastSquaresSolution": "estimation.solver",
    "solve_least_squares": "estimation.solver",
    "fit_log": "studies.log_fit",
    "fit_wpilog": "studies.sysid",
    "LoadedLogs": "studies.log_fit",
    "LogError": "logs.table",
}
"""Each public name's module. They load on first use (PEP 562), so `import jointid` and the command
line's help need no numpy: that buys 0.67 of `jointid --help`'s start (bench_startup_budget lazy-package-names)."""

__all__ = [
    "PARAMETER_NAMES",
    "PLAIN",
    "TRUE_PARAMETERS",
    "FitResult",
    "G",
    "JointData",
    "JointModel",
    "LeastSquaresSolution",
    "LoadedLogs",
    "LogError",
    "Settings",
    "SettingsError",
    "Term",
    "fit_joint",
    "fit_log",
    "fit_wpilog",
    "model_named",
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
