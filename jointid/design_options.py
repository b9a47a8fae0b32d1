"""The excitation designer's options, defaults and ranges, without numpy: the command line's --help reads them.

See `jointid.design` for the designer and `jointid.fourier` for the motions it makes.
"""

from __future__ import annotations

CRITERIA = {
    "d": "D-optimal (maximise log det of the information matrix in relative units)",
    "a": "A-optimal (minimise the sum of relative variances)",
    "cond": "cond (minimise the column-scaled condition number)",
}
"""The design criteria by name, with what each optimises."""
DEFAULT_CRITERION = "d"
DEFAULT_HARMONICS = 3
DEFAULT_STARTS = 8
DEFAULT_SEED = 0
"""Seed of the random starts (not of the torque noise)."""
DEFAULT_NOISE = 0.20
"""The lesson's noise bound (N m): the expected standard errors are shown at it."""
DEFAULT_PERIOD = 8.0
"""Period T (s) of a designed motion: the lesson's 8 s window holds one period."""
PERIOD_LIMITS = (0.1, 1000.0)
"""Allowed period (s)."""
HARMONIC_LIMITS = (1, 20)
"""Allowed number of harmonics K."""
STARTS_LIMITS = (1, 1000)
"""Allowed number of random starts."""
RICH_ENVELOPE = {"q_max": 0.95, "qd_max": 1.6, "qdd_max": 3.0}
"""Rich motion's envelope, the default limits: |q| <= 0.95 rad, |qd| <= 1.6 rad/s, |qdd| <= 3.0 rad/s²."""
LIMIT_RANGES = {"q_max": (3.141592653589793, "rad"), "qd_max": (100.0, "rad/s"), "qdd_max": (1000.0, "rad/s²"),
                "tau_max": (1000.0, "N m")}
"""Largest value of each limit and its unit (the lower end, 0, is excluded)."""
LIMIT_SYMBOLS = {"q_max": "|q|", "qd_max": "|qd|", "qdd_max": "|qdd|", "tau_max": "|tau|"}
"""How a printout names the quantity each limit bounds."""
