"""Sensitivity check: do the derivative window and the low-pass cutoff decide the estimate?

A log fit depends on settings the data do not fix: the Savitzky-Golay window
that estimates qd and qdd, and the cutoff of the parallel low-pass. The check
refits with each halved and doubled, one at a time, and compares every
parameter's move with its standard error in the fit at the chosen settings.
A move of more than THRESHOLD standard errors is more than noise would make:
the settings, not the data, decide that estimate.

Noise-free data fitted exactly (a simulated log with its true derivatives)
have standard errors made of rounding: every move would then count as many
"standard errors" of nothing, so such a fit is marked exact and flags nothing.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

THRESHOLD = 2.0
"""A parameter is flagged when a variant moves it by more than this many of its standard errors."""

FACTORS = (0.5, 2.0)
"""Each setting is tried halved and doubled."""

EXACT_FIT = 1e-9
"""A fit whose training RMSE is at most this fraction of the torque's RMS is exact: its residuals are
rounding, and so are its standard errors (double precision leaves about 1e-16 of each number)."""


@dataclass(frozen=True, eq=False)
class Variant:
    """One refit: which setting changed, to what, and the estimate it gave."""

    setting: str
    """'window' or 'cutoff'."""
    factor: float
    """0.5 or 2 (times the chosen setting)."""
    window: int | None
    """Savitzky-Golay window (samples) of this fit, or None when nothing was differentiated."""
    cutoff: float | None
    """Low-pass cutoff (Hz) of this fit, or None unfiltered."""
    estimate: np.ndarray
    """(p,) The reported parameters."""
    std_error: np.ndarray | None = None
    """(p,) Their noise-based standard errors, or None (say how far noise alone moves one fit from another)."""

    @property
    def label(self) -> str:
        """'window halved (13 samples)', 'cutoff doubled (4.2 Hz)', or 'chosen settings'."""
        if not self.setting:
            return "chosen settings"
        how = "halved" if self.factor < 1 else "doubled"
        value = f"{self.window} samples" if self.setting == "window" else f"{self.cutoff:.3g} Hz"
        return f"{self.setting} {how} ({value})"

    def to_dict(self, names) -> dict:
        """Plain JSON-ready values."""
        return {"setting": self.setting or None, "factor": self.factor, "window": self.window,
                "cutoff_hz": self.cutoff, "estimate": dict(zip(names, map(_finite, self.estimate)))}


@dataclass(frozen=True, eq=False)
class SensitivityCheck:
    """The fit at the chosen settings, its refits with each setting halved and doubled, and the flags."""

    names: tuple[str, ...]
    """Parameter names (the model's)."""
    base: Variant
    """The fit at the chosen settings."""
    std_error: np.ndarray
    """(p,) Standard errors of the base fit."""
    variants: tuple[Variant, ...]
    """The refits, window ones first."""
    exact: bool = False
    """True when the base fit reproduced its torques to rounding (noise-free data): nothing is flagged."""

    @cached_property
    def moves(self) -> np.ndarray:
        """(k, p) |variant - base| in base standard errors (inf where a standard error is zero)."""
        if not self.variants:
            return np.zeros((0, len(self.names)))
        difference = np.abs(np.array([v.estimate for v in self.variants]) - self.base.estimate)
        with np.errstate(divide="ignore", invalid="ignore"):
            moves = difference / self.std_error
        return np.where(difference == 0, 0.0, moves)

    @cached_property
    def flags(self) -> tuple[bool, ...]:
        """Per parameter: True when some variant moves it by more than THRESHOLD standard errors."""
        if not self.variants or self.exact:
            return (False,) * len(self.names)
        return tuple(bool(m) for m in (self.moves > THRESHOLD).any(axis=0))

    @property
    def flagged(self) -> bool:
        """True when any parameter is flagged."""
        return any(self.flags)

    def worst(self, index: int) -> tuple[Variant, float]:
        """The variant that moves parameter `index` most, and by how many standard errors."""
        k = int(np.argmax(self.moves[:, index]))
        return self.variants[k], float(self.moves[k, index])

    @cached_property
    def relative_moves(self) -> np.ndarray:
        """(p,) Each parameter's largest |variant - base| over |base| (inf where base is zero and it moved)."""
        if not self.variants:
            return np.zeros(len(self.names))
        difference = np.abs(np.array([v.estimate for v in self.variants]) - self.base.estimate).max(axis=0)
        with np.errstate(divide="ignore", invalid="ignore"):
            moves = difference / np.abs(self.base.estimate)
        return np.where(difference == 0, 0.0, moves)

    def to_dict(self) -> dict:
        """Plain JSON-ready values: the settings tried, each parameter's estimates, and the flags.

        For an exact fit the moves in standard errors are None (they would be ratios of rounding) and
        `exact_fit` says why.
        """
        return {
            "threshold_std_errors": THRESHOLD,
            "exact_fit": self.exact,
            "settings": [self.base.to_dict(self.names), *(v.to_dict(self.names) for v in self.variants)],
            "std_error": dict(zip(self.names, map(_finite, self.std_error))),
            "largest_move_std_errors": {name: None if self.exact else _finite(self.moves[:, j].max()
                                                                              if len(self.variants) else 0.0)
                                        for j, name in enumerate(self.names)},
            "largest_relative_move": dict(zip(self.names, map(_finite, self.relative_moves))),
            "flags": dict(zip(self.names, self.flags)),
            "flagged": self.flagged,
        }


def sensitivity_check(names, base: Variant, std_error, variants, *, rmse: float, torque_rms: float) -> SensitivityCheck:
    """Collect the base fit and its variants (those that gave a unique fit) into a check.

    `rmse` and `torque_rms`: the base fit's training RMSE and its torque's RMS, which say whether it is exact.
    """
    kept = tuple(v for v in variants if v.estimate is not None and np.all(np.isfinite(v.estimate)))
    exact = rmse <= EXACT_FIT * torque_rms
    return SensitivityCheck(tuple(names), base, np.asarray(std_error, dtype=float), kept, exact)


def _finite(value) -> float | None:
    """A float for JSON, None when not finite (a move over a zero standard error)."""
    value = float(value)
    return value if np.isfinite(value) else None
