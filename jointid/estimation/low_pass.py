"""Parallel filtering: one zero-phase low-pass applied alike to the measured torque and every regressor column.

The model is linear in its columns, tau = X theta, and a linear filter L gives
L(tau) = L(X) theta exactly, for any theta: filtering both sides keeps the
model while removing the torque noise and unmodelled vibration above the
cutoff. It has to be the regressor's columns that are filtered, not q: the
columns are nonlinear in q (g cos q, sign(qd)), and cos(L(q)) is not L(cos q).
So the filter belongs between building the regressor and solving, which is
why it lives beside the fit (jointid.studies.log_fit) rather than in the log reader.

The filter is a linear-phase FIR low-pass written with numpy: a sinc cut at
the cutoff (where it passes half the amplitude), shaped by a Kaiser window
(Kaiser's formulas for its shape and length): its gain stays within 0.1 % of 1
below the passband edge and under 0.1 % (60 dB down) beyond the stopband edge.
The transition band is the cutoff wide, centred on it (passband to half the
cutoff, stopband from 1.5 times it), narrower only where the Nyquist frequency
leaves less room; the taps sum to 1 (unit gain at 0 Hz). At D = rate / (2
cutoff) this costs about 8 taps per kept sample. Its taps are symmetric about
the middle one, so it adds no delay between columns and torque (zero phase).

After filtering, the samples are decimated: neighbouring samples of a
low-passed signal are correlated, and residual-based standard errors that
count them as independent would be too small by about sqrt(rate / (2 cutoff)).
Keeping every D-th sample, D = rate / (2 cutoff) rounded down, leaves samples
about one correlation length apart (the filtered signals are band-limited to
the cutoff, so nothing the fit uses is lost) and makes the fit faster.

Since only every D-th filtered sample is kept, only those are computed
(polyphase: one matrix product over the column cut into D-sample blocks), at
about taps / D multiply-adds per input sample and without full-rate copies;
no scipy is imported. The edges are trimmed rather than extended: a kept
sample needs a full window of measured samples on both sides, so the
(taps - 1) / 2 samples at each end only feed their neighbours. Trimming
invents nothing (an extension would be linear too, but its edge outputs mix
in reflected samples whose noise is the same noise counted twice), and the
decimated fit loses only about taps / D of its samples.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

FILTER_NAME = "Kaiser-windowed sinc"
"""What the low-pass is, for notes and JSON."""

ATTENUATION_DB = 60.0
"""The low-pass's promise: its gain stays within FLATNESS of 1 below the passband edge and under FLATNESS
beyond the stopband edge (60 dB down)."""

FLATNESS = 10 ** (-ATTENUATION_DB / 20)
"""0.001: the passband's largest departure from 1 and the stopband's largest gain."""

DESIGN_ATTENUATION_DB = 65.0
"""The attenuation the Kaiser formulas are given: 5 dB more than promised, because their length estimate
falls short for filters of a few dozen taps (60 dB asked gave 53 dB at 21 taps)."""

BANDWIDTH_MULTIPLE = 12.0
"""Automatic cutoff: this many times the motion's bandwidth, so the motion and the first harmonics of
cos q pass untouched while torque noise and vibration above them go."""

NYQUIST_SHARE = 0.8
"""An automatic cutoff at or above this share of the Nyquist frequency is pointless: the log is not filtered."""

MIN_DECIMATED = 50
"""Decimation never leaves fewer samples than this (a short log keeps more, correlated, samples)."""

PRODUCT_PIECE = 1 << 17
"""Multiply-adds per matrix product of the polyphase filter (OpenBLAS runs products below 2^18 on one thread)."""


@dataclass(frozen=True)
class LowPassDesign:
    """The taps of a zero-phase FIR low-pass for one cutoff and rate, and its band edges."""

    cutoff: float
    """Hz where the filter passes half the amplitude (the middle of the transition band)."""
    rate: float
    """Sample rate (Hz)."""

    @property
    def transition(self) -> float:
        """Width (Hz) of the transition band: the cutoff, or less where the Nyquist frequency is nearer."""
        return min(self.cutoff, 2.0 * (self.rate / 2.0 - self.cutoff))

    @property
    def passband_edge(self) -> float:
        """Hz up to which the gain stays within FLATNESS of 1."""
        return self.cutoff - self.transition / 2.0

    @property
    def stopband_edge(self) -> float:
        """Hz from which the gain stays below FLATNESS."""
        return self.cutoff + self.transition / 2.0

    @property
    def beta(self) -> float:
        """Kaiser window shape for DESIGN_ATTENUATION_DB (Kaiser's formula for attenuations above 50 dB)."""
        return 0.1102 * (DESIGN_ATTENUATION_DB - 8.7)

    @property
    def length(self) -> int:
        """Number of taps (odd): Kaiser's estimate for DESIGN_ATTENUATION_DB over the transition band."""
        width = 2.0 * math.pi * self.transition / self.rate  # radians per sample
        count = math.ceil((DESIGN_ATTENUATION_DB - 7.95) / (2.285 * width)) + 1
        return count + 1 - count % 2

    @property
    def half(self) -> int:
        """Samples on each side of the middle tap: those at each end of a log get no full window."""
        return (self.length - 1) // 2

    @cached_property
    def taps(self) -> np.ndarray:
        """(length,) The symmetric taps, summing to 1 (unit gain at 0 Hz)."""
        offsets = np.arange(-self.half, self.half + 1, dtype=float)
        share = 2.0 * self.cutoff / self.rate  # the cutoff as a share of the Nyquist frequency
        taps = share * np.sinc(share * offsets) * np.kaiser(self.length, self.beta)
        return taps / taps.sum()


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

    @cached_property
    def design(self) -> LowPassDesign | None:
        """The low-pass's taps and band edges, or None when the log is not filtered."""
        return None if self.cutoff is None else LowPassDesign(self.cutoff, self.rate)

    @property
    def edge(self) -> int:
        """Samples at each end of the log without a full filter window (0 unfiltered)."""
        return 0 if self.design is None else self.design.half

    def rows(self, count: int) -> np.ndarray:
        """Indices of the rows `apply` keeps out of `count`: every decimation-th from the first, with a full window."""
        first = -(-self.edge // self.decimation) * self.decimation  # the first multiple of D at or after the edge
        return np.arange(first, count - self.edge, self.decimation)

    def apply(self, columns: np.ndarray) -> np.ndarray:
        """(N, k) columns -> (M, k): each low-passed, at the `rows(N)` only."""
        if self.design is None:
            return columns[:: self.decimation]
        return np.column_stack([self.apply_column(columns[:, j]) for j in range(columns.shape[1])])

    def apply_column(self, column: np.ndarray) -> np.ndarray:
        """(N,) -> (M,): the low-passed column at the `rows(N)` only (polyphase, see the module docstring).

        With taps h (length 2c + 1) the output at row n is sum_j h[j] x[n - c + j].
        Padded with zeros to R blocks of D taps, h[rD + d] = H[d, r]; and with the
        column from row n_0 - c cut into D-sample blocks B[i, d], output m is
        sum_r (B H)[m + r, r]: one product over the column, then R diagonal sums.
        """
        if self.design is None:
            return column[:: self.decimation]
        taps, half, step = self.design.taps, self.design.half, self.decimation
        rows = self.rows(len(column))
        kept = len(rows)
        if kept == 0:
            return np.empty(0)
        blocks = -(-len(taps) // step)
        padded = np.zeros(blocks * step)
        padded[: len(taps)] = taps
        phases = padded.reshape(blocks, step).T  # (D, R): column r holds taps rD ... rD + D - 1
        start = rows[0] - half
        needed = kept - 1 + blocks  # blocks of the column the outputs reach (the last partly zero taps)
        whole = min(needed, (len(column) - start) // step)
        cut = column[start: start + whole * step].reshape(whole, step)
        products = np.empty((needed, blocks))
        # In pieces small enough that OpenBLAS keeps each on one thread: on this busy 2-core machine its
        # threads made one tall, narrow product of a million samples up to ten times slower.
        piece = max(1, PRODUCT_PIECE // (step * blocks))
        for first in range(0, whole, piece):
            last = min(first + piece, whole)
            np.matmul(cut[first:last], phases, out=products[first:last])
        if whole < needed:  # the last block runs past the log's end, where the taps are zero: pad it
            tail = np.zeros(step)
            rest = column[start + whole * step:]
            tail[: len(rest)] = rest
            products[whole] = tail @ phases
        out = products[:kept, 0].copy()
        for r in range(1, blocks):
            out += products[r: r + kept, r]
        return out

    def to_dict(self) -> dict:
        """Plain JSON-ready values."""
        design = self.design
        return {"cutoff_hz": self.cutoff, "filter": FILTER_NAME if design else None,
                "taps": design.length if design else None, "kaiser_beta": design.beta if design else None,
                "passband_flatness": FLATNESS if design else None,
                "stopband_attenuation_db": ATTENUATION_DB if design else None,
                "passband_edge_hz": design.passband_edge if design else None,
                "stopband_edge_hz": design.stopband_edge if design else None,
                "zero_phase": self.active, "edge_samples_dropped": self.edge,
                "decimation": self.decimation, "reason": self.reason}



def choose_filter(request: FilterRequest, step: float | None, uniform: bool, bandwidth: float | None,
                  count: int) -> ParallelFilter:
    """The low-pass and decimation for a log sampled every `step` s: as requested, or chosen from `bandwidth`.

    FilterRequestError when a requested cutoff is not below the Nyquist
    frequency or leaves fewer than MIN_DECIMATED samples with a full window,
    or a log without uniform times is asked to be filtered.
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
    design = LowPassDesign(cutoff, rate)
    usable = count - 2 * design.half
    if usable < MIN_DECIMATED:
        if request.cutoff is not None:
            raise FilterRequestError(f"{request.cutoff:g} Hz needs at least {2 * design.half + MIN_DECIMATED} "
                                     f"samples (its low-pass has {design.length} taps, and {MIN_DECIMATED} "
                                     f"samples must have a full window); this log has {count}")
        return ParallelFilter(None, rate, _decimation(request, None, rate, count),
                              f"{why}: its low-pass, {design.length} taps long, leaves fewer than "
                              f"{MIN_DECIMATED} of the log's {count} samples with a full window")
    decimation = _decimation(request, cutoff, rate, usable)
    if request.decimate is None and decimation > 1:
        why += f"; {rate / decimation:.3g} Hz, twice the cutoff, keeps residuals about independent"
    return ParallelFilter(cutoff, rate, decimation, why)


def _decimation(request: FilterRequest, cutoff: float | None, rate: float, count: int) -> int:
    """The requested decimation, or rate / (2 cutoff) rounded down (1 unfiltered), leaving >= MIN_DECIMATED of
    the `count` samples with a full window."""
    if request.decimate is not None:
        if request.decimate < 1:
            raise FilterRequestError(f"must be a whole number of samples, at least 1; got {request.decimate}")
        return request.decimate
    if cutoff is None:
        return 1
    factor = max(1, math.floor(rate / (2 * cutoff)))
    return max(1, min(factor, count // MIN_DECIMATED))
