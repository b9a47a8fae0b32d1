"""Parallel filtering: one zero-phase low-pass applied alike to the measured torque and every regressor column.

The model is linear in its columns, tau = X theta, and a linear filter L gives
L(tau) = L(X) theta exactly, for any theta: filtering both sides keeps the
model while removing the torque noise and unmodelled vibration above the
cutoff. It has to be the regressor's columns that are filtered, not q: the
columns are nonlinear in q (g cos q, sign(qd)), and cos(L(q)) is not L(cos q).
So the filter belongs between building the regressor and solving, which is
why it lives beside the fit (jointid.logfit) rather than in the log reader.

The filter is a Butterworth low-pass of order ORDER run forward and backward
(scipy.signal.sosfiltfilt, imported only when a log is filtered), so it adds
no delay between columns and torque. Its edges are handled by the same odd
extension on both sides, which is linear too, so they stay exact.

After filtering, the samples are decimated: neighbouring samples of a
low-passed signal are correlated, and residual-based standard errors that
count them as independent would be too small by about sqrt(rate / (2 cutoff)).
Keeping every D-th sample, D = rate / (2 cutoff) rounded down, leaves samples
about one correlation length apart (the filtered signals are band-limited to
the cutoff, so nothing the fit uses is lost) and makes the fit faster.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

ORDER = 4
"""Butterworth order of each pass (the forward-backward filter has twice the roll-off)."""

BANDWIDTH_MULTIPLE = 12.0
"""Automatic cutoff: this many times the motion's bandwidth, so the motion and the first harmonics of
cos q pass untouched while torque noise and vibration above them go."""

NYQUIST_SHARE = 0.8
"""An automatic cutoff at or above this share of the Nyquist frequency is pointless: the log is not filtered."""

MIN_DECIMATED = 50
"""Decimation never leaves fewer samples than this (a short log keeps more, correlated, samples)."""


class FilterRequestError(ValueError):
    """A cutoff or decimation a log cannot use; str() says why (the CLI prefixes the flag)."""


@dataclass(frozen=True)
class FilterRequest:
    """What the user asked for: cutoff (Hz, None: automatic, 0: off) and decimation (None: automatic)."""

    cutoff: float | None = None
    decimate: int | None = None

    def scaled(self, factor: float) -> FilterRequest:
        """The same request with its cutoff multiplied by `factor` (for the sensitivity check)."""
        return self if self.cutoff in (None, 0) else FilterRequest(self.cutoff * factor, self.decimate)


@dataclass(frozen=True, eq=False)
class ParallelFilter:
    """A chosen low-pass and decimation for one log, and the sentence that says why."""

    cutoff: float | None
    """Cutoff (Hz), or None when the log is not filtered."""
    rate: float | None
    """The log's sample rate (Hz), or None without uniform times."""
    decimation: int
    """Keep every `decimation`-th sample after filtering (1: all)."""
    reason: str
    """Why this cutoff and decimation, or why none."""

    @property
    def active(self) -> bool:
        """True when columns are low-passed."""
        return self.cutoff is not None

    def apply(self, columns: np.ndarray) -> np.ndarray:
        """(N, k) columns -> (M, k): each low-passed forward and backward, then every decimation-th row kept."""
        if self.cutoff is None:
            return columns[:: self.decimation]
        from scipy.signal import butter, sosfiltfilt  # lazily: scipy.signal costs 0.7 s to import

        sos = butter(ORDER, self.cutoff, btype="low", fs=self.rate, output="sos")
        # Column by column, keeping only the decimated rows: sosfiltfilt holds several padded copies of what
        # it filters, so one column at a time bounds the peak memory by a few columns, not a few regressors.
        kept = np.empty((len(range(0, len(columns), self.decimation)), columns.shape[1]))
        for j in range(columns.shape[1]):
            kept[:, j] = sosfiltfilt(sos, columns[:, j])[:: self.decimation]
        return kept

    def rows(self, count: int) -> np.ndarray:
        """Indices of the rows `apply` keeps out of `count`."""
        return np.arange(0, count, self.decimation)

    def to_dict(self) -> dict:
        """Plain JSON-ready values."""
        return {"cutoff_hz": self.cutoff, "butterworth_order": ORDER if self.active else None,
                "zero_phase": self.active, "decimation": self.decimation, "reason": self.reason}

    @property
    def short_description(self) -> str:
        """A few words for a narrow status line."""
        if not self.active:
            return "not low-passed"
        kept = "" if self.decimation == 1 else f", every {self.decimation}th sample kept"
        return f"torque and regressor low-passed at {self.cutoff:.3g} Hz{kept}"

    @property
    def description(self) -> str:
        """One sentence for a person."""
        if not self.active:
            return f"torque and regressor columns not low-passed: {self.reason}."
        kept = "" if self.decimation == 1 else f", then every {self.decimation}th sample kept"
        return (f"torque and every regressor column low-passed alike at {self.cutoff:.3g} Hz (zero-phase "
                f"Butterworth, order {ORDER}){kept} ({self.reason}); the training RMSE is of the filtered torque.")


def choose_filter(request: FilterRequest, step: float | None, uniform: bool, bandwidth: float | None,
                  count: int) -> ParallelFilter:
    """The low-pass and decimation for a log sampled every `step` s: as requested, or chosen from `bandwidth`.

    FilterRequestError when a requested cutoff is not below the Nyquist
    frequency or a log without uniform times is asked to be filtered.
    """
    off = request.cutoff == 0
    if step is None or not uniform:
        if request.cutoff not in (None, 0) or request.decimate not in (None, 1):
            raise FilterRequestError("needs uniformly sampled times (a t column; logs with qd and qdd keep "
                                     "their times as recorded, so they must be evenly spaced to be filtered)")
        why = "no time column" if step is None else "its time steps are not uniform (kept as recorded)"
        return ParallelFilter(None, None, 1, why)
    rate = 1.0 / step
    nyquist = rate / 2
    if off:
        return ParallelFilter(None, rate, _decimation(request, None, rate, count), "turned off (--cutoff 0)")
    if request.cutoff is not None:
        if request.cutoff >= nyquist:
            raise FilterRequestError(f"must be below the Nyquist frequency {nyquist:.6g} Hz of this log; "
                                     f"got {request.cutoff:g}")
        cutoff, why = request.cutoff, "cutoff given"
    elif bandwidth is None or bandwidth <= 0:
        return ParallelFilter(None, rate, _decimation(request, None, rate, count),
                              "automatic: q shows no motion to take a bandwidth from")
    else:
        cutoff = BANDWIDTH_MULTIPLE * bandwidth
        if cutoff >= NYQUIST_SHARE * nyquist:
            return ParallelFilter(None, rate, _decimation(request, None, rate, count),
                                  f"automatic: {BANDWIDTH_MULTIPLE:g} times the motion's bandwidth "
                                  f"{bandwidth:.3g} Hz reaches the Nyquist frequency {nyquist:.6g} Hz")
        why = f"automatic: {BANDWIDTH_MULTIPLE:g} times the motion's bandwidth {bandwidth:.3g} Hz"
    decimation = _decimation(request, cutoff, rate, count)
    if request.decimate is None and decimation > 1:
        why += f"; {rate / decimation:.3g} Hz, twice the cutoff, keeps residuals about independent"
    return ParallelFilter(cutoff, rate, decimation, why)


def _decimation(request: FilterRequest, cutoff: float | None, rate: float, count: int) -> int:
    """The requested decimation, or rate / (2 cutoff) rounded down (1 unfiltered), leaving >= MIN_DECIMATED rows."""
    if request.decimate is not None:
        if request.decimate < 1:
            raise FilterRequestError(f"must be a whole number of samples, at least 1; got {request.decimate}")
        return request.decimate
    if cutoff is None:
        return 1
    factor = max(1, math.floor(rate / (2 * cutoff)))
    return max(1, min(factor, count // MIN_DECIMATED))
