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

After filtering, the samples are decimated to about 20 per cutoff hertz
(every D-th, D = rate / (20 cutoff) rounded down): the filtered signals are
band-limited to the cutoff, so nothing the fit uses is lost, the fit is
faster, and enough samples remain for the robust step to tell an outside push
from noise. Neighbouring kept samples are still correlated; the standard
errors of a filtered fit account for that (jointid.estimation.uncertainty).

Since only every D-th filtered sample is kept, only those are computed, the
cheaper of two ways: polyphase (one matrix product over the column cut into
D-sample blocks, about taps / D multiply-adds per input sample), or by FFT
over overlapping blocks about four times the taps long (overlap-save: each
block's spectrum times the taps', then back, and every D-th sample kept; about
log2 of the block per sample whatever the taps' length), which wins for the
long filters of low cutoffs. The two give the same outputs to rounding (about
1e-14 of the column's size). Several filters at one decimation (a log fit's
cutoff and its sensitivity check's half and double) share each block's
spectrum instead, decimating in the frequency domain (low_passed_together):
one forward FFT per block for all of them, about half the work of three
filters apart. No scipy is imported. The ends are extended rather than trimmed, so a short
log keeps every sample (a 4 s log lost 2 s to a trimmed filter): each column
is continued past each end by its odd reflection about a straight line fitted
to its last half cutoff period (about the line, not about one end sample,
whose noise would otherwise be mirrored over the whole extension). The
extension is linear in the column, so torque and columns are still filtered
alike and L(X) theta = L(X theta) holds at the ends too.

The automatic cutoff follows the motion, not the sampling rate: three times
the frequency below which 95 % of the power of the unit vector (cos q, sin q)
lies. The rigid-body torque is a function of the motion, so its columns live
in the motion's band and its first harmonics (the third keeps cos q's
nonlinearity of large swings); far above it a real log holds stick-slip torque
spikes and encoder quantisation in qdd, which bias I and h low. (cos q, sin q)
rather than q stays bounded when the joint turns over many times, and 95 %
rather than 99 % is not pulled up by a hit. The cutoff is also kept where the
angle's white noise floor, differentiated twice, stays below 1 % of the
acceleration's power (errors in variables), and within 4 / duration and a
tenth of the sampling rate.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..threads import map_in_threads
from .solver import PRODUCT_PIECE

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

BANDWIDTH_MULTIPLE = 3.0
"""Automatic cutoff: this many times the motion's bandwidth, so the motion and cos q's first harmonics pass."""

BANDWIDTH_SHARE = 0.95
"""The motion's bandwidth: the frequency below which this share of the power of (cos q, sin q) lies."""

NOISE_SHARE = 0.01
"""The automatic cutoff keeps the angle's noise floor, differentiated twice, below this share of qdd's power."""

NOISE_BAND = (0.25, 0.45)
"""Where the angle's noise floor is read, as shares of the sampling rate (far above any joint's motion)."""

MIN_PERIODS = 4.0
"""The automatic cutoff is at least this many cycles per log duration."""

RATE_SHARE = 0.1
"""The automatic cutoff is at most this share of the sampling rate."""

SAMPLES_PER_CUTOFF = 20.0
"""Decimation keeps about this many samples per cutoff hertz."""

MIN_DECIMATED = 50
"""Decimation never leaves fewer samples than this (a short log keeps more, correlated, samples)."""


FFT_COST = 3.6
"""Polyphase multiply-adds that cost as much as one FFT sample-octave (size log2 size per block): measured on a
million samples at 1 kHz, the 3081 taps of a 1.29 Hz cutoff took 11.6 ms polyphase and 9.1 ms by FFT blocks, the
6161 taps of 0.645 Hz 30 ms and 9.7 ms, the 1541 of 2.58 Hz 5.0 ms and 8.7 ms."""

FFT_LEAST_BITS = 10
"""FFT blocks are at least 2^10 samples."""

FFT_GROUP = 1 << 18
"""Samples transformed per call: blocks in groups that stay in cache (2^16 to 2^18 ran fastest)."""


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
    """A cutoff or decimation a log cannot use; str() says why, `setting` which ('cutoff' or 'decimation')."""

    def __init__(self, message: str, setting: str = "cutoff"):
        super().__init__(message)
        self.setting = setting


@dataclass(frozen=True)
class FilterRequest:
    """What the user asked for: cutoff (Hz, None: automatic, 0: off) and decimation (None: automatic)."""

    cutoff: float | None = None
    decimate: int | None = None


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
    def extension(self) -> int:
        """Samples each end of a column is extended by (the filter's half length; 0 unfiltered)."""
        return 0 if self.design is None else self.design.half

    @cached_property
    def support(self) -> float:
        """Seconds either side of a sample within which the filter holds 95 % of its weight (0 unfiltered): how
        far a push or a rest spreads into the filtered samples."""
        if self.design is None:
            return 0.0
        weights = np.abs(self.design.taps)
        half = self.design.half
        reach = np.cumsum(weights[half:] + weights[half::-1]) - weights[half]
        return float(np.searchsorted(reach, 0.95 * weights.sum())) / self.rate

    def rows(self, count: int) -> range:
        """Indices of the rows `apply` keeps out of `count`: every decimation-th from the first (a range: its
        length alone is most often wanted, and an index array of a million rows cost 2.5 ms)."""
        return range(0, count, self.decimation)

    def apply(self, columns: np.ndarray) -> np.ndarray:
        """(N, k) columns -> (M, k): each low-passed, at the `rows(N)` only."""
        if self.design is None:
            return columns[:: self.decimation]
        return np.column_stack([self.apply_column(columns[:, j]) for j in range(columns.shape[1])])

    def apply_column(self, column: np.ndarray) -> np.ndarray:
        """(N,) -> (M,): the low-passed column at the `rows(N)` only: polyphase or by FFT blocks, whichever costs
        less (see the module docstring)."""
        if self.design is None:
            return column[:: self.decimation]
        taps, half, step = self.design.taps, self.design.half, self.decimation
        kept = len(self.rows(len(column)))
        if kept == 0:
            return np.empty(0)
        if column[0] == column[-1] and not np.any(column != column[0]):
            # A constant (a torque bias's column): the taps sum to 1 and its extension is the same constant, so
            # the output is the constant itself, which filtering would give to rounding.
            return np.full(kept, column[0])
        fitted = self.fitted
        plan = _fft_plan(len(taps), step, kept, len(column) + 2 * half)
        if plan is None:
            return _polyphase(extended(column, half, fitted), taps, step, kept)
        size, advance, blocks = plan
        padded = extended(column, half, fitted, (blocks - 1) * advance + size)
        return _by_fft_blocks(padded, taps, step, kept, size, advance, blocks)

    @property
    def fitted(self) -> int:
        """Samples at each end that the extension's line is fitted to: half a cutoff period, at least 3."""
        return max(3, int(round(0.5 * self.rate / self.cutoff)))

    @cached_property
    def _kernel_spectra(self) -> dict[int, np.ndarray]:
        """The taps' real spectra by transform size, filled by `kernel_spectrum`."""
        return {}

    def kernel_spectrum(self, size: int) -> np.ndarray:
        """(size // 2 + 1,) The taps' spectrum as a circular kernel of `size` samples centred on sample 0: real,
        since the taps are symmetric, and computed once per size."""
        spectrum = self._kernel_spectra.get(size)
        if spectrum is None:
            taps, half = self.design.taps, self.design.half
            kernel = np.zeros(size)
            kernel[: half + 1] = taps[half:]
            kernel[size - half:] = taps[:half]
            spectrum = self._kernel_spectra[size] = np.fft.rfft(kernel).real
        return spectrum

    def to_dict(self) -> dict:
        """Plain JSON-ready values."""
        design = self.design
        return {"cutoff_hz": self.cutoff, "filter": FILTER_NAME if design else None,
                "taps": design.length if design else None, "kaiser_beta": design.beta if design else None,
                "passband_flatness": FLATNESS if design else None,
                "stopband_attenuation_db": ATTENUATION_DB if design else None,
                "passband_edge_hz": design.passband_edge if design else None,
                "stopband_edge_hz": design.stopband_edge if design else None,
                "zero_phase": self.active, "edge_extension_samples": self.extension,
                "decimation": self.decimation, "reason": self.reason}



def line_ends(column: np.ndarray, fitted: int) -> tuple[float, float]:
    """The values at the first and the last sample of the lines fitted to the column's first and last `fitted`
    samples: what `extended` reflects each end about."""
    size = len(column)
    fitted = min(fitted, size)
    offsets = np.arange(fitted, dtype=float) - (fitted - 1) / 2.0
    spread = float(np.dot(offsets, offsets)) or 1.0
    first, last = column[:fitted], column[size - fitted:]
    start = first.mean() - np.dot(offsets, first) / spread * (fitted - 1) / 2.0  # the line at sample 0
    end = last.mean() + np.dot(offsets, last) / spread * (fitted - 1) / 2.0  # and at the last sample
    return start, end


def extended(column: np.ndarray, count: int, fitted: int, total: int = 0) -> np.ndarray:
    """The column continued `count` samples past each end by its odd reflection about a line fitted to its first
    (last) `fitted` samples: linear in the column, and no end sample's noise mirrored over the extension; then
    zeros up to `total` samples in all when that is longer."""
    size = len(column)
    start, end = line_ends(column, fitted)
    out = np.empty(max(size + 2 * count, total))
    out[size + 2 * count:] = 0.0
    out[count: count + size] = column
    reach = min(count, size - 1)
    out[count - reach: count] = 2.0 * start - column[reach:0:-1]
    out[count + size: count + size + reach] = 2.0 * end - column[size - 2: size - 2 - reach: -1]
    out[: count - reach] = out[count - reach]  # a log shorter than the filter: held beyond one reflection
    out[count + size + reach: size + 2 * count] = out[count + size + reach - 1]
    return out


MIN_SHARED_BLOCKS = 8
"""Filters share a spectrum only for a column at least this many blocks long: over fewer the saving is a few ms,
and a shorter log (every real log so far) keeps the outputs of filtering apart bit for bit."""

SHARED_LARGEST_FACTOR = 101
"""Shared blocks are a multiple of the decimation long: one with a prime factor beyond this makes their FFTs
slower than filtering apart (a factor 997 took 9 times a power of two's time, 101 1.8 times)."""


def shared_size(filters, count: int) -> int | None:
    """The block size `low_passed_together` uses for `count` samples through `filters`, or None when they cannot
    share one spectrum: not all active at one rate and decimation, a log shorter than MIN_SHARED_BLOCKS blocks, or
    a decimation with a large prime factor.

    The size is the decimation D times a number of the form 2^a 3^b 5^c (which FFTs take quickly), at least four
    times the longest filter, as `_fft_plan`'s blocks.
    """
    if not filters or not all(chosen.active for chosen in filters):
        return None
    step, rate = filters[0].decimation, filters[0].rate
    if any(chosen.decimation != step or chosen.rate != rate for chosen in filters):
        return None
    half = max(chosen.design.half for chosen in filters)
    if count < half + 2 or _largest_factor(step) > SHARED_LARGEST_FACTOR:  # its ends held, not only reflected
        return None
    least = -(-max(4 * (2 * half + 1), 1 << FFT_LEAST_BITS) // step)
    size = step * min(value for value in _smooth_numbers(least) if value >= least)
    return size if count >= MIN_SHARED_BLOCKS * size else None


def _smooth_numbers(least: int):
    """Numbers 2^a 3^b 5^c from `least` to twice it (a power of two among them)."""
    fives = 1
    while fives < 2 * least:
        threes = fives
        while threes < 2 * least:
            value = threes
            while value < least:
                value *= 2
            yield value
            threes *= 3
        fives *= 5


def _largest_factor(number: int) -> int:
    """The largest prime factor of `number` (1 for 1)."""
    largest, factor = 1, 2
    while factor * factor <= number:
        while number % factor == 0:
            largest, number = factor, number // factor
        factor += 1
    return max(largest, number)


def low_passed_together(column: np.ndarray, filters, size: int | None) -> list[np.ndarray]:
    """[chosen.apply_column(column) for chosen in filters], to rounding, from one spectrum of each block of the
    column when `size` is `shared_size(filters, len(column))` (None: each filter apart).

    The column, reflected at each end about zero as far as the longest filter
    reaches, is cut into overlapping blocks of `size` = D P samples, each
    transformed once (overlap-save, as `_by_fft_blocks`); each filter's kernel
    spectrum multiplies it, and the decimation is done in the frequency domain
    (every D-th sample of a block is the inverse FFT of its spectrum's D bands
    of P bins summed), so each filter costs a product, a sum and FFTs of P
    points. The lines `extended` reflects about are added afterwards: a filter
    of half h sees 2 x (the line's end value) over the h samples past an end,
    which reaches the outputs within h samples of that end as that value
    times a cumulative sum of the taps.
    """
    if size is None or (column[0] == column[-1] and not np.any(column != column[0])):
        return [chosen.apply_column(column) for chosen in filters]
    count, step = len(column), filters[0].decimation
    half = max(chosen.design.half for chosen in filters)
    bands, kept, bins = size // step, -(-count // step), size // 2 + 1
    first = -(-half // step)  # the first sample of a block every filter's taps fit in, in steps of D
    per_block = (size - 1 - half) // step - first + 1
    blocks = -(-kept // per_block)
    pad = first * step - half  # zeros before the reflection, so that the column's sample 0 is a kept sample
    signal = np.zeros(max((blocks - 1) * per_block * step + size, pad + count + 2 * half))
    signal[pad + half: pad + half + count] = column
    signal[pad: pad + half] = -column[half:0:-1]
    signal[pad + half + count: pad + count + 2 * half] = -column[count - 2: count - 2 - half: -1]
    outs = [np.empty(blocks * per_block) for _ in filters]
    group = max(1, FFT_GROUP // size)
    itemsize = signal.strides[0]
    for start in range(0, blocks, group):
        stop = min(start + group, blocks)
        windows = np.lib.stride_tricks.as_strided(signal[start * per_block * step:], shape=(stop - start, size),
                                                  strides=(per_block * step * itemsize, itemsize),
                                                  writeable=False)
        spectra = np.fft.rfft(windows, axis=1)
        product = np.zeros((stop - start, -(-bins // bands) * bands), dtype=complex)
        for out, chosen in zip(outs, filters):
            np.multiply(spectra, chosen.kernel_spectrum(size), out=product[:, :bins])
            every = np.fft.irfft(_folded(product, size, bands)[:, : bands // 2 + 1], bands, axis=1)
            out[start * per_block: stop * per_block] = every[:, first: first + per_block].ravel()
    results = []
    for out, chosen in zip(outs, filters):
        out = out[:kept]
        out /= step
        start, end = line_ends(column, chosen.fitted)
        reach = chosen.design.half
        near = np.cumsum(chosen.design.taps[:reach])[::-1]  # near[n]: the taps' weight past an end n samples away
        rows = np.arange(0, min(reach, count), step)
        out[: len(rows)] += 2.0 * start * near[rows]
        last = np.arange((kept - 1) * step, max(count - 1 - reach, -1), -step)
        out[len(out) - len(last):] += (2.0 * end * near[count - 1 - last])[::-1]
        results.append(out)
    return results


def _folded(product: np.ndarray, size: int, bands: int) -> np.ndarray:
    """(blocks, bands) For each row of spectra of `size` points (their first size // 2 + 1 bins, zeros beyond),
    the sums over every `bands`-th bin of the whole Hermitian spectrum: those up to half the size directly, those
    above as the conjugates of their mirror bins below it, summed likewise and read backwards."""
    below = product.reshape(len(product), -1, bands).sum(axis=1)
    mirrored = below.copy()  # the bins 1 to (size - 1) // 2, each mirrored by one above half the size
    mirrored[:, 0] -= product[:, 0]
    if size % 2 == 0:
        mirrored[:, (size // 2) % bands] -= product[:, size // 2]
    return below + np.conj(np.roll(mirrored[:, ::-1], 1, axis=1))


def _polyphase(column: np.ndarray, taps: np.ndarray, step: int, kept: int) -> np.ndarray:
    """(kept,) Outputs sum_j taps[j] column[mD + j] of an extended column, m < kept, D = `step` (polyphase).

    Padded with zeros to R blocks of D taps, h[rD + d] = H[d, r]; and with the
    column cut into D-sample blocks B[i, d], output m is sum_r (B H)[m + r, r]:
    one product over the column, then R diagonal sums.
    """
    blocks = -(-len(taps) // step)
    padded = np.zeros(blocks * step)
    padded[: len(taps)] = taps
    phases = padded.reshape(blocks, step).T  # (D, R): column r holds taps rD ... rD + D - 1
    needed = kept - 1 + blocks  # blocks of the column the outputs reach (the last partly zero taps)
    whole = min(needed, len(column) // step)
    cut = column[: whole * step].reshape(whole, step)
    products = np.empty((needed, blocks))
    # In pieces small enough that OpenBLAS keeps each on one thread: on this busy 2-core machine its
    # threads made one tall, narrow product of a million samples up to ten times slower.
    piece = max(1, PRODUCT_PIECE // (step * blocks))
    for first in range(0, whole, piece):
        last = min(first + piece, whole)
        np.matmul(cut[first:last], phases, out=products[first:last])
    if whole < needed:  # the last block runs past the column's end, where the taps are zero: pad it
        tail = np.zeros(step)
        rest = column[whole * step:]
        tail[: len(rest)] = rest
        products[whole] = tail @ phases
    out = products[:kept, 0].copy()
    for r in range(1, blocks):
        out += products[r: r + kept, r]
    return out


def _fft_plan(length: int, step: int, kept: int, extended_size: int) -> tuple[int, int, int] | None:
    """(FFT size, block advance, blocks) for `_by_fft_blocks`, or None when the polyphase product costs less.

    Blocks of a power-of-two size about four times the taps (one block when the column is shorter) advance
    by a whole number of decimation steps, each giving the outputs its full windows reach (overlap-save).
    """
    size = 1 << max(FFT_LEAST_BITS, math.ceil(math.log2(4 * length)))
    size = min(size, 1 << max(FFT_LEAST_BITS, math.ceil(math.log2(extended_size))))
    advance = (size - length + 1) // step * step
    if advance < step:
        return None
    blocks = -(-kept // (advance // step))
    if kept * length < FFT_COST * blocks * size * math.log2(size):
        return None
    return size, advance, blocks


def correlated(values: np.ndarray, taps: np.ndarray) -> np.ndarray:
    """(N - L + 1,) sum_j taps[j] values[n + j] for every n where the L taps fit (np.correlate's 'valid'), by FFT
    blocks: one FFT of a million samples took 25 ms, blocks a few times the taps long 9 ms."""
    kept = len(values) - len(taps) + 1
    size = 1 << max(FFT_LEAST_BITS, math.ceil(math.log2(4 * len(taps))), 0)
    size = min(size, 1 << max(FFT_LEAST_BITS, math.ceil(math.log2(len(values)))))
    advance = size - len(taps) + 1
    blocks = -(-kept // advance)
    padded = np.zeros((blocks - 1) * advance + size)
    padded[: len(values)] = values
    return _by_fft_blocks(padded, taps, 1, kept, size, advance, blocks)


def _by_fft_blocks(column: np.ndarray, taps: np.ndarray, step: int, kept: int, size: int, advance: int,
                   blocks: int) -> np.ndarray:
    """(kept,) The outputs `_polyphase` gives, from `blocks` overlapping blocks of `size` samples `advance`
    apart (their spectra times the taps', then back): about log2(size) operations per sample whatever the
    taps' length. `column` is extended and zero-padded to (blocks - 1) advance + size samples."""
    response = np.conj(np.fft.rfft(taps, size))  # a correlation: the taps are applied unreversed
    per_block = advance // step
    out = np.empty(blocks * per_block)
    group = max(1, FFT_GROUP // size)
    itemsize = column.strides[0]
    for first in range(0, blocks, group):
        last = min(first + group, blocks)
        windows = np.lib.stride_tricks.as_strided(column[first * advance:], shape=(last - first, size),
                                                  strides=(advance * itemsize, itemsize), writeable=False)
        spectra = np.fft.rfft(windows, axis=1)
        spectra *= response
        filtered = np.fft.irfft(spectra, size, axis=1)
        out[first * per_block: last * per_block] = filtered[:, :advance:step].ravel()
    return out[:kept]


def choose_filter(request: FilterRequest, step: float | None, uniform: bool, q: np.ndarray | None,
                  count: int, automatic: tuple[float, str] | None = None) -> ParallelFilter:
    """The low-pass and decimation for a log sampled every `step` s: as requested, or chosen from its angle `q`
    (`automatic`: `automatic_cutoff(q, step)` when already computed).

    FilterRequestError when a requested cutoff is not below the Nyquist
    frequency or the log is shorter than its filter, or a log without uniform
    times is asked to be filtered.
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
    else:
        automatic = automatic if automatic is not None else automatic_cutoff(q, step)
        if automatic is None:
            return ParallelFilter(None, rate, _decimation(request, None, rate, count),
                                  "automatic: q shows no motion to take a bandwidth from")
        cutoff, why = automatic
    design = LowPassDesign(cutoff, rate)
    if count <= design.half:
        if request.cutoff is not None:
            raise FilterRequestError(f"{request.cutoff:g} Hz needs more than {design.half} samples (its "
                                     f"low-pass has {design.length} taps); this log has {count}")
        return ParallelFilter(None, rate, _decimation(request, None, rate, count),
                              f"{why}: its low-pass, {design.length} taps long, is longer than twice the log")
    decimation = _decimation(request, cutoff, rate, count)
    if request.decimate is None and decimation > 1:
        why += f"; kept {rate / decimation:.3g} Hz, about {SAMPLES_PER_CUTOFF:g} samples per cutoff hertz"
    return ParallelFilter(cutoff, rate, decimation, why)


def automatic_cutoff(q: np.ndarray, step: float) -> tuple[float, str] | None:
    """The automatic cutoff (Hz) for a log of angles `q` sampled every `step` s and the sentence that says why
    (see the module docstring), or None when q does not move."""
    count = len(q)
    if count < 8 or not np.ptp(q) > 0:
        return None
    rate, size = 1.0 / step, 1 << int(np.ceil(np.log2(count)))
    window = hann(count)

    def spectrum(which: str) -> np.ndarray:
        if which == "q":
            return detrended_power(q, window, size)
        part = np.cos(q) if which == "cos" else np.sin(q)
        part -= part.mean()
        part *= window
        return _power(np.fft.rfft(part, size))

    # The three spectra on the machine's cores at once: on a million samples they are most of this function.
    cos_power, sin_power, q_power = map_in_threads(spectrum, ("cos", "sin", "q"))
    power = cos_power + sin_power
    total = np.cumsum(power)
    if not total[-1] > 0:
        return None
    frequencies = np.fft.rfftfreq(size, step)
    bandwidth = float(frequencies[min(np.searchsorted(total / total[-1], BANDWIDTH_SHARE), len(power) - 1)])
    cutoff = BANDWIDTH_MULTIPLE * bandwidth
    why = (f"automatic: {BANDWIDTH_MULTIPLE:g} x {bandwidth:.3g} Hz, below which {BANDWIDTH_SHARE:.0%} of "
           f"the motion's power lies (of cos q and sin q)")
    cap = max(noise_cap(q, step, cutoff, frequencies, window, size, q_power), bandwidth)  # never below the motion itself
    if cap < cutoff:
        cutoff, why = cap, why + f", lowered to {cap:.3g} Hz where q's noise floor would reach 1 % of qdd's power"
    low, high = MIN_PERIODS / (count * step), RATE_SHARE * rate
    if not low <= cutoff <= high:
        cutoff = min(max(cutoff, low), high)
        why += f", held to {cutoff:.3g} Hz ({MIN_PERIODS:g} cycles per log to {RATE_SHARE:.0%} of the rate)"
    return cutoff, why


def hann(count: int) -> np.ndarray:
    """np.hanning(count), its cosines computed for the first half only (the window is symmetric)."""
    if count < 3:
        return np.hanning(count)
    half = (count + 1) // 2
    window = np.empty(count)
    window[:half] = 0.5 + 0.5 * np.cos(
        np.pi * np.arange(1 - count, 2 * half - count, 2) / (count - 1))
    window[count - half:] = window[:half][::-1]
    return window


def _power(spectrum: np.ndarray) -> np.ndarray:
    """|spectrum|^2 as real^2 + imag^2 (np.abs takes a square root only to have it squared)."""
    power = spectrum.real ** 2
    power += spectrum.imag ** 2
    return power


def detrended_power(q: np.ndarray, window: np.ndarray, size: int) -> np.ndarray:
    """The power spectrum (`size` points) of the angle less its least-squares line, windowed: what `noise_cap`
    reads the angle's noise floor from."""
    # The least-squares line in closed form (np.polyfit took most of this function's time on a million samples).
    offsets = np.arange(len(q), dtype=float)
    offsets -= (len(q) - 1) / 2.0
    # numpy's own loop, not BLAS's dot, which wakes OpenBLAS's threads for a million samples.
    slope = float(np.einsum("i,i->", offsets, q)) / float(np.einsum("i,i->", offsets, offsets))
    detrended = q - q.mean() - slope * offsets
    detrended *= window
    return _power(np.fft.rfft(detrended, size))


def noise_cap(q: np.ndarray, step: float, cutoff: float, frequencies: np.ndarray, window: np.ndarray,
              size: int, spectrum: np.ndarray | None = None) -> float:
    """The cutoff at which the angle's white noise floor, twice differentiated, reaches NOISE_SHARE of qdd's
    power below `cutoff` (errors in variables: noise in the qdd column biases I low); inf without a floor.
    `spectrum`: detrended_power(q, window, size) when already computed."""
    spectrum = detrended_power(q, window, size) if spectrum is None else spectrum
    rate = 1.0 / step
    band = (frequencies > NOISE_BAND[0] * rate) & (frequencies < NOISE_BAND[1] * rate)
    floor = float(np.median(spectrum[band])) if band.any() else 0.0
    if not floor > 0:
        return math.inf
    below = frequencies <= cutoff
    cycles = frequencies[below] * step  # cycles per sample: no overflow for any step
    signal = float(np.sum(cycles**4 * (spectrum[below] / floor)))
    # Noise power below f: floor * sum of f^4 over the bins, about floor * f^5 / (5 spacing).
    return (5.0 * NOISE_SHARE * signal / size) ** 0.2 / step


def _decimation(request: FilterRequest, cutoff: float | None, rate: float, count: int) -> int:
    """The requested decimation, or rate / (SAMPLES_PER_CUTOFF cutoff) rounded down (1 unfiltered), leaving at
    least MIN_DECIMATED of the `count` samples."""
    if request.decimate is not None:
        if request.decimate < 1:
            raise FilterRequestError(f"must be a whole number of samples, at least 1; got {request.decimate}",
                                     "decimation")
        # A decimation that keeps too few samples would be reported as data that show no motion.
        kept = -(-count // request.decimate)
        if request.decimate > 1 and kept < MIN_DECIMATED:
            most = max(1, count // MIN_DECIMATED)
            raise FilterRequestError(f"it keeps {kept:,} of its {count:,} samples, and a fit needs at least "
                                     f"{MIN_DECIMATED}: decimate by at most {most:,}", "decimation")
        return request.decimate
    if cutoff is None:
        return 1
    factor = max(1, math.floor(rate / (SAMPLES_PER_CUTOFF * cutoff)))
    return max(1, min(factor, count // MIN_DECIMATED))
