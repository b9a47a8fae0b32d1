"""Live identification: a joint's parameters refitted as its samples arrive, in bounded time and memory.

A `Watcher` takes the `Received` blocks of a live source (jointid.live) and gives a `WatchRefresh` whenever asked.
It runs a recorded log's pipeline as far as it can be run on samples as they arrive:

1. a warm-up (WARMUP_SECONDS) fixes what a log fit chooses from the whole log: the sampling step, the low-pass
   cutoff and decimation (jointid.estimation.low_pass.choose_filter, from the warm-up's motion) and the
   derivative window (jointid.logs.derivatives.smoothing_window); a SysId routine (a state column) is not
   low-passed unless a cutoff is given, as studies.sysid fits it;
2. each contiguous stretch (no gap, one SysId test) goes through the streaming derivatives and low-pass of
   jointid.studies.watch_streams, equal to the offline values away from the stretch's ends, which are not fitted;
3. the rows are judged in blocks of exactly ROBUST_SECONDS (however the samples arrived; the rest of a stretch at its
   end, and at the source's end): standstill (models with Coulomb friction) and outside torques
   (jointid.estimation.exclusion.outside_torques, from the current estimate) are left out;
4. the rows kept are added to bounded least-squares statistics (studies.watch_streams): the estimate is jointid's
   column-scaled least squares of every row kept (from the QR-updated triangle of [X | y]), its errors a log fit's
   Newey-West errors of the same rows (from sums over lags that hold for any estimate: NeweyWestSums), with the
   rows left out as gaps in the grid, as a log fit's positions;
5. the other analysis choices of a log fit run beside it: the derivative window and cutoff halved and doubled as
   parallel pipelines, the fit with the outside torques kept in, and a torque offset explained the other way (its
   columns streamed with the model's); their moves beyond noise widen the reported errors (refits.beyond_noise),
   the scatter of the run's halves (each fitted alone with its own Newey-West errors, from its batches'
   lagged sums) too, and the verdicts and errors come from
   estimation.judgement.judge, as studies.log_fit.judge_log gives a log fit's. Nothing is well determined before
   the halves can be compared.

Without a model or mechanism, a SysId routine's mechanism is chosen from its data at every refresh, as
studies.mechanism.choose_mechanism chooses a recorded log's: every candidate's columns are streamed.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, replace

import numpy as np

from ..estimation.exclusion import commanded_changes, explained_transients, outside_torques, runs, widened
from ..estimation.fit import FitResult, with_judgement
from ..estimation.judgement import Finding, judge, noise_judgement
from ..estimation.low_pass import FilterRequest, FilterRequestError, ParallelFilter, automatic_cutoff, choose_filter
from .watch_streams import BatchStatistics, DerivativeStream, LowPassStream, NeweyWestSums, SplineResampler
from ..estimation.uncertainty import WELL_DETERMINED, parameter_uncertainty
from ..logs.conventions import AngleConvention
from ..logs.derivatives import WindowChoice, check_filter, smoothing_window
from ..logs.timing import GAP_FACTOR, UNIFORM_TOLERANCE
from ..model.effort import effort_named
from ..model.terms import SIMPLE_MOTOR, JointModel, model_named
from ..options import DEFAULT_ORDER, default_log_model
from ..samples import JointData
from .refits import ROBUST_CHOICE, beyond_noise, is_exact, scatter_findings, scatter_ratios
from .sensitivity import FACTORS
from .watch_refresh import ParameterTrace, WatchRefresh

WARMUP_SECONDS = 5.0
"""Seconds of samples from which the step, the low-pass and the derivative window are chosen before fitting."""
WARMUP_SAMPLES = 64
"""At least this many samples in the warm-up."""
ROBUST_SECONDS = 5.0
"""Seconds of fitted rows judged together for standstill and outside torques."""
RECENT_SECONDS = 10.0
"""Seconds of fitted rows kept for the charts and the prediction."""
HALF_LAGS = 4
"""Each half of the run spans at least this many correlation lags before the halves are compared (as a log fit's
stretches, studies.refits.stretch_scatter): shorter halves share their residuals."""
HISTORY = 120
"""A trace's history is thinned to half when it reaches twice this many points."""
EVENTS = 50
"""Source events kept (the newest)."""
IDLE_STATES = ("", "none")
"""SysId test states that are no test (the routine is idle): their samples are received, not fitted."""
STANDSTILL_SHARE = 0.1
"""Speeds below this share of the RMS filtered speed so far count as standstill (as estimation.exclusion)."""
TOO_SHORT = "too few samples yet to compare the run's halves"
"""Why nothing is well determined before the halves' scatter can be judged."""
HALVES_HOURS = 1.0
"""The halves' Newey-West lag is a log fit's for this many hours of rows (the filter's support sets it unless the
filter is very short)."""


@dataclass(frozen=True)
class Pipeline:
    """One analysis of the stream: its derivative window and low-pass (the fit's own, or a sensitivity refit's)."""

    label: str
    """'' for the fit itself, else 'window' or 'cutoff'."""
    factor: float
    window: int | None
    chosen: ParallelFilter


def _candidates(effort, linear: bool) -> JointModel:
    """One model with every column of the mechanisms a SysId routine may be (simple, elevator, and arm unless q is a
    length), so each candidate's fit is a choice of its columns."""
    from .mechanism import ARM, ELEVATOR, SIMPLE, mechanism_model

    terms = {}
    for name in (SIMPLE, ELEVATOR) + (() if linear else (ARM,)):
        for term in mechanism_model(name).in_effort(effort).terms:
            terms.setdefault(term.name, term)
    return JointModel("mechanisms", tuple(terms.values()), None, effort)


def _rows(rows: dict, first: int, last: int) -> dict:
    """Rows first..last - 1 of waiting rows (their variants' too)."""
    part = {name: values[first:last] for name, values in rows.items() if name not in ("variants", "state")}
    part["variants"] = {pipeline: (X[first:last], tau[first:last]) for pipeline, (X, tau) in rows["variants"].items()}
    part["state"] = rows["state"]
    return part


class _Segment:
    """The streaming stages of one contiguous stretch of samples (no gap, one SysId test)."""

    def __init__(self, watcher: Watcher, state: str):
        """The stages of every pipeline of `watcher` for a stretch of SysId test `state` ('' without one)."""
        self.state = state
        self.derivatives = {}
        self.filters = {}
        for pipeline in watcher.pipelines:
            if pipeline.window not in self.derivatives:
                self.derivatives[pipeline.window] = DerivativeStream(watcher.union.terms, watcher.step,
                                                                     pipeline.window, watcher.order)
            self.filters[pipeline] = LowPassStream(pipeline.chosen)
        self.outputs = {pipeline: [] for pipeline in watcher.pipelines}
        self.watcher = watcher
        self.resampler = SplineResampler(watcher.step) if watcher.resampled else None

    @property
    def size(self) -> int:
        """Numbers its buffers hold."""
        stages = [*self.derivatives.values(), *self.filters.values()]
        return sum(stage.size for stage in stages) + (0 if self.resampler is None else self.resampler.size)

    def add(self, columns: dict[str, np.ndarray]) -> dict | None:
        """Feed raw samples; return the rows every pipeline has produced since (aligned), or None."""
        if self.resampler is not None:
            columns = self.resampler.add(columns)
            if columns is None:
                return None
        produced = {window: stream.add(columns) for window, stream in self.derivatives.items()}
        for pipeline, stream in self.filters.items():
            out = produced[pipeline.window]
            if out is None:
                continue
            main = pipeline is self.watcher.pipelines[0]
            values = [out["X"], out["tau"][:, None]]
            if main:
                values += [out["q"][:, None], out["qd"][:, None], out["qdd"][:, None], out["t"][:, None]]
            rows, filtered = stream.add(np.hstack(values), int(out["index"][0]))
            if len(rows):
                self.outputs[pipeline].append((rows, filtered))
        return self._aligned()

    def _aligned(self) -> dict | None:
        """The rows every pipeline has, as arrays; rows only some have wait (those before all began are lost)."""
        spans = {}
        for pipeline, pieces in self.outputs.items():
            if not pieces:
                return None
            spans[pipeline] = (int(pieces[0][0][0]), int(pieces[-1][0][-1]))
        first = max(span[0] for span in spans.values())
        last = min(span[1] for span in spans.values())
        if last < first:
            return None
        p = self.watcher.union.size
        aligned = {}
        for pipeline, pieces in self.outputs.items():
            rows = np.concatenate([piece[0] for piece in pieces])
            values = np.concatenate([piece[1] for piece in pieces])
            inside = (rows >= first) & (rows <= last)
            aligned[pipeline] = values[inside]
            later = rows > last
            self.outputs[pipeline] = [(rows[later], values[later])] if later.any() else []
        main = aligned[self.watcher.pipelines[0]]
        return {"X": main[:, :p], "tau": main[:, p], "q": main[:, p + 1], "qd": main[:, p + 2],
                "qdd": main[:, p + 3], "t": main[:, p + 4], "state": self.state,
                "variants": {pipeline: (aligned[pipeline][:, :p], aligned[pipeline][:, p])
                             for pipeline in self.watcher.pipelines[1:]}}


class Watcher:
    """A joint identified while it moves: `add` each Received block, `refresh` for what to show."""

    def __init__(self, *, model: str | JointModel | None = None, mechanism: str | None = None,
                 effort: str = "torque", linear: bool = False, zero: str = "right", clockwise: bool = False,
                 window: int | None = None, order: int = DEFAULT_ORDER, cutoff: float | None = None,
                 decimate: int | None = None, robust: bool = True, sensitivity: bool = True,
                 warmup: float = WARMUP_SECONDS, recent: float = RECENT_SECONDS):
        """Configured as a log fit: `model` (a name or JointModel) or `mechanism` ('simple', 'elevator', 'arm'),
        `effort` ('torque' or 'voltage', the source's), `linear` (q in metres), the angle's `zero` and `clockwise`
        convention, the derivative `window` and `order`, the low-pass `cutoff` (Hz; 0 off) and `decimate`, the
        robust step and the sensitivity check; `warmup` seconds choose the filters, `recent` seconds are charted."""
        if effort not in ("torque", "voltage"):
            raise ValueError(f"effort must be 'torque' or 'voltage' (a source converts current); got {effort!r}")
        check_filter(window, order)
        if cutoff is not None and cutoff < 0:
            raise ValueError(f"cutoff must be at least 0 Hz; got {cutoff}")
        if decimate is not None and decimate < 1:
            raise ValueError(f"decimate must be at least 1; got {decimate}")
        from ..options import MECHANISMS

        if mechanism is not None and mechanism not in MECHANISMS:
            raise ValueError(f"mechanism must be one of {', '.join(MECHANISMS)}; got {mechanism!r}")
        self.effort = effort_named(effort)
        self.convention = AngleConvention(zero, bool(clockwise))
        self.linear = bool(linear)
        self._asked_model, self._asked_mechanism = model, mechanism
        self.window_asked, self.order = window, order
        self.request = FilterRequest(cutoff, decimate)
        self.robust, self.sensitivity = bool(robust), bool(sensitivity)
        self.warmup, self.recent_seconds = float(warmup), float(recent)
        self.model: JointModel | None = None
        if model is not None or mechanism is not None or effort == "torque":
            self.model = self._model_for(sysid=False)
        # What the warm-up fixes.
        self.step: float | None = None
        self.resampled = False
        """True when the source's jitter is resampled onto a uniform grid (as a log's, logs.timing)."""
        self.window: int | None = None
        self.window_choice: WindowChoice | None = None
        self.filter: ParallelFilter | None = None
        self.pipelines: tuple[Pipeline, ...] = ()
        self._warm: list[dict[str, np.ndarray]] = []
        # Counts and the source's story.
        self.received = 0
        self.dropped = 0
        self.elapsed = 0.0
        self.ended = False
        self.events: deque[str] = deque(maxlen=EVENTS)
        self.tests: dict[str, float] = {}
        self._last_t: float | None = None
        self._segment: _Segment | None = None
        self._last_angle: float | None = None
        self._turns = 0.0
        """Whole turns added to a wrapped source's angle so far."""
        self._unwraps = 0
        """Wraps undone so far."""
        self._fed: tuple[float, str | None] | None = None
        """The last sample streamed: its time and SysId state."""
        self._sysid = False
        # Fitted statistics.
        self.statistics: BatchStatistics | None = None
        self.variant_statistics: dict[Pipeline, BatchStatistics] = {}
        self.newey_west: NeweyWestSums | None = None
        """The filtered fit's Newey-West sums (None unfiltered: a log fit's errors are then independent's)."""
        self.union: JointModel | None = None
        """The model whose columns are streamed: the fitted model's, or every candidate mechanism's while the
        mechanism is chosen from the data."""
        self.columns: list[int] = []
        """The fitted model's columns among the union's."""
        self.choosing = False
        """True while a SysId routine's mechanism is chosen from its data at each refresh."""
        self.mechanism_choice = None
        """The studies.mechanism.MechanismChoice of a SysId routine, or None."""
        self.alternative: tuple[JointModel, str] | None = None
        """The model with the torque offset explained the other way and what that is (a log fit's refit)."""
        self.test_statistics: dict[str, BatchStatistics] = {}
        self.all_moving: BatchStatistics | None = None
        """Every moving row, outside torques kept in: the --no-robust refit's statistics."""
        self._pending: list[dict] = []
        self._pending_rows = 0
        self._speed_squares = 0.0
        self._speed_count = 0
        self._resolution = 0.0
        self._range = [math.inf, -math.inf]
        self._directions = [0, 0]
        self._recent: deque[dict] = deque()
        self._history: dict[str, list[tuple[float, float, float]]] = {}
        self._determined: dict[str, tuple[float, float] | None] = {}

    # -- configuration --------------------------------------------------------------------------------------------

    def _model_for(self, sysid: bool) -> JointModel:
        """The model to fit: as asked, else the mechanism's, else a log's default for the effort (a SysId routine's
        arm model, a simple motor's for a linear one)."""
        from .mechanism import mechanism_model

        asked = self._asked_model
        if asked is not None:
            model = model_named(asked) if isinstance(asked, str) else asked
            if not isinstance(model, JointModel):
                raise TypeError(f"model must be a model name or a JointModel; got {type(asked).__name__}")
        elif self._asked_mechanism is not None:
            model = mechanism_model(self._asked_mechanism)
        elif sysid:
            from .sysid import SYSID_MODEL

            model = SIMPLE_MOTOR if self.linear else model_named(SYSID_MODEL)
        else:
            model = model_named(default_log_model(self.effort.name))
        model = model.in_effort(self.effort)
        kinds = {term.kind for term in model.terms}
        if self.linear and kinds & {"h", "h_c", "h_s"}:
            raise ValueError(f"the model {model.name!r} takes cos(q), but q is a length in metres: fit it as a "
                             f"simple motor or an elevator")
        return model

    def _start(self) -> None:
        """Fix the step, the filters and the pipelines from the warm-up's samples, then feed them."""
        warm = {name: np.concatenate([block[name] for block in self._warm]) for name in self._warm[0]}
        t, q = warm["t"], warm["q"]
        steps = np.diff(t)
        self.step = float(np.median(steps[steps > 0]))
        missing = not {"qd", "qdd"} <= set(warm)
        jitter = float(np.max(np.abs(steps[steps <= GAP_FACTOR * self.step] / self.step - 1)))
        uniform = jitter <= UNIFORM_TOLERANCE
        # As a log: jitter is resampled when derivatives are estimated; given ones keep their times, unfiltered.
        self.resampled = missing and not uniform
        self._sysid = "state" in warm
        if self.model is None or (self._sysid and self._asked_model is None and self._asked_mechanism is None):
            self.model = self._model_for(self._sysid)
        self.union, self.columns = self.model, list(range(self.model.size))
        self.alternative = None
        if not self._sysid:
            from .log_fit import offset_alternative

            alternative = offset_alternative(self.model)
            kinds = set() if alternative is None else {term.kind for term in alternative[0].terms}
            if alternative is not None and not (self.linear and kinds & {"h", "h_c", "h_s"}):
                # A log fit refits with its torque offset explained the other way: those columns are streamed too.
                self.alternative = alternative
                extra = tuple(term for term in alternative[0].terms if term.name not in self.model.column_names)
                self.union = JointModel(self.model.name, self.model.terms + extra, None, self.effort)
        if self._sysid and self.effort.name == "voltage" and self._asked_model is None \
                and self._asked_mechanism is None:
            # As a recorded SysId log: the mechanism is chosen from the data at each refresh, so every candidate's
            # columns are streamed.
            self.union, self.choosing = _candidates(self.effort, self.linear), True
            self._choose_mechanism()
        elif self._sysid:
            from .mechanism import MechanismChoice, mechanism_of

            given = "--model" if self._asked_model is not None else "--mechanism"
            self.mechanism_choice = MechanismChoice(mechanism_of(self.model), given if self._asked_model or
                                                    self._asked_mechanism else "the default",
                                                    "meters" if self.linear else "radians")
        request = self.request
        if self._sysid and request.cutoff is None:
            request = FilterRequest(0.0, request.decimate)  # as studies.sysid.sysid_filtering
        automatic = None
        if missing:
            window = self.window_asked
            if window is None:
                window = self.order + 2 if self.order % 2 else self.order + 3
                automatic = None if request.cutoff else automatic_cutoff(q, self.step)
                follows = request.cutoff if request.cutoff else (automatic or (None,))[0]
                if follows:
                    self.window_choice = smoothing_window(self.step, follows, self.order, len(q), automatic)
                    window = self.window_choice.window
            self.window = window
        # Decimation as for a long log (a warm-up's count would cap it); the cutoff from the warm-up's motion.
        long = max(len(q), int(3600 / self.step))
        try:
            self.filter = choose_filter(request, self.step, uniform or self.resampled, q, long, automatic)
        except FilterRequestError as error:
            raise ValueError(f"the low-pass cannot apply: {error}") from None
        pipelines = [Pipeline("", 1.0, self.window, self.filter)]
        if self.sensitivity:
            if self.window is not None:
                from .log_fit import _scaled_window

                for factor in FACTORS:
                    other = _scaled_window(self.window, factor, self.order, 10 ** 9)
                    if other is not None and other != self.window:
                        pipelines.append(Pipeline("window", factor, other, self.filter))
            if self.filter.active:
                for factor in FACTORS:
                    try:
                        other = choose_filter(FilterRequest(self.filter.cutoff * factor, self.filter.decimation),
                                              self.step, True, q, long)
                    except FilterRequestError:  # a doubled cutoff beyond the Nyquist frequency: skipped
                        continue
                    pipelines.append(Pipeline("cutoff", factor, self.window, other))
        self.pipelines = tuple(pipelines)
        p = self.union.size
        self.halves_lag = None
        if self.filter.active:
            from .log_fit import correlation_lag

            self.halves_lag = correlation_lag(int(HALVES_HOURS * 3600 * self.fitted_rate), self.filter)
        self.statistics = BatchStatistics(p, self._batch_rows(), self.halves_lag)
        self.variant_statistics = {pipeline: BatchStatistics(p, 10 ** 12) for pipeline in self.pipelines[1:]}
        self.all_moving = BatchStatistics(p, 10 ** 12)
        if self.filter.active:
            # Lags for up to ten hours of rows: a log fit's lag grows with its rows (the Newey-West rule).
            from .log_fit import correlation_lag

            self.newey_west = NeweyWestSums(p, correlation_lag(int(36000 * self.fitted_rate), self.filter))
            counts = np.abs(np.diff(q))
            counts = counts[counts > 1e-9 * max(1.0, float(np.max(np.abs(q))))]
            if len(counts):  # one encoder count over half a cutoff period (estimation.exclusion's resolution)
                self._resolution = float(np.percentile(counts, 1)) * 2 * self.filter.cutoff
        self._warm = []
        self._feed(warm)

    def _choose_mechanism(self) -> None:
        """The mechanism a SysId routine's samples so far support, as studies.mechanism.choose_mechanism decides it:
        gravity gains SUPPORT standard errors clear of zero, BIC (each test with its own residual variance) lower by
        DECISIVE; the fitted model and its columns follow."""
        from .mechanism import (ARM, DECISIVE, ELEVATOR, MANY_TURNS, SIMPLE, SUPPORT, MechanismChoice,
                                mechanism_model)

        unit = "meters" if self.linear else "radians"
        candidates = {name: mechanism_model(name).in_effort(self.effort)
                      for name in (SIMPLE, ELEVATOR, ARM) if not (name == ARM and self.linear)}
        ruled_out = [(ARM, f"the source's position is in {unit}, a length")] if self.linear else []
        span = self._range[1] - self._range[0]
        revolutions = span / (2 * math.pi) if math.isfinite(span) and not self.linear else None
        statistics = self.statistics
        fits, gravity = {}, []
        for name, model in candidates.items():
            columns = [self.union.column_names.index(column) for column in model.column_names]
            solution = None if statistics is None or not statistics.count else statistics.solution(columns=columns)
            if solution is None or solution.estimate is None:
                continue
            fits[name] = (model, columns, solution)
            if "kG" in model.names:
                uncertainty = parameter_uncertainty(solution, None, model, None, None)
                k = model.names.index("kG")
                if uncertainty.residual_std_error is not None:
                    gravity.append((name, float(uncertainty.estimate[k]), float(uncertainty.residual_std_error[k])))
        supported = {name: abs(value) > SUPPORT * error for name, value, error in gravity}
        if ARM in fits and revolutions is not None and revolutions > MANY_TURNS and not supported.get(ARM, False):
            ruled_out.append((ARM, f"the wheel turned {revolutions:.3g} revolutions with no voltage following the "
                              "cosine of its angle"))
            del fits[ARM]
        total = sum(test.count for test in self.test_statistics.values())
        bic = {}
        for name, (model, columns, solution) in fits.items():
            value = 0.0
            a = np.append(-solution.estimate, 1.0)
            for test in self.test_statistics.values():
                if test.count:
                    residuals = test.triangle[:, [*columns, self.union.size]] @ a
                    value += test.count * math.log(max(float(residuals @ residuals) / test.count, 1e-300))
            bic[name] = value + model.size * math.log(max(total, 1))
        chosen = SIMPLE
        for name in (ELEVATOR, ARM):
            if name in bic and SIMPLE in bic and bic[name] < bic[chosen] - DECISIVE and supported.get(name, False):
                chosen = name
        self.model = candidates[chosen]
        self.columns = [self.union.column_names.index(column) for column in self.model.column_names]
        self.mechanism_choice = MechanismChoice(chosen, None, unit, tuple(bic.items()), total, tuple(ruled_out),
                                                tuple(gravity), revolutions)

    def _batch_rows(self) -> int:
        """The shortest batch (grid rows): the run's halves are split at batch ends, so short ones split it finely."""
        return max(self.support, 4 * self.union.size, 16)

    @property
    def support(self) -> int:
        """The filter's support in fitted rows (0 unfiltered)."""
        chosen = self.filter
        if chosen is None or not chosen.active:
            return 0
        return max(1, math.ceil(chosen.support * chosen.rate / chosen.decimation))

    @property
    def fitted_rate(self) -> float:
        """Fitted rows per second."""
        return 1.0 / (self.step * self.filter.decimation)

    # -- samples in -------------------------------------------------------------------------------------------------

    def add(self, received) -> None:
        """Take one Received block: its samples, events, drops and end."""
        self.events.extend(received.events)
        self.dropped += int(received.dropped)
        if received.count:
            self._add_samples(received)
        if received.ended and not self.ended and self.step is not None:
            self._finish_segment()  # the source is done: the rows waiting for the robust step are judged
        self.ended = self.ended or bool(received.ended)

    def _add_samples(self, received) -> None:
        """A block's samples: checked, cut at the source's breaks, a sample that is no number taken as a gap, the
        rest streamed."""
        columns = {name: np.asarray(values) for name, values in received.columns.items()}
        for name in columns:
            if name != "state":
                columns[name] = np.asarray(columns[name], dtype=float)
        if "t" not in columns or "q" not in columns or "tau" not in columns:
            raise ValueError("a live source must give t, q and tau to be watched")
        # A break the source marks (a reconnection, a file truncated or replaced) starts a stretch, as a gap does,
        # even where the times run on or go back: nothing is differentiated or filtered across it.
        edges = sorted({0, received.count, *(int(row) for row in received.breaks if 0 <= row < received.count)})
        for first, last in zip(edges[:-1], edges[1:]):
            if first in received.breaks:
                self._fed = None
            self._add_stretch_piece({name: values[first:last] for name, values in columns.items()})

    def _add_stretch_piece(self, columns: dict[str, np.ndarray]) -> None:
        """Samples with no break inside: a sample that is no number taken as a gap, the rest streamed."""
        count = len(columns["t"])
        finite = np.ones(count, dtype=bool)
        for name, values in columns.items():
            if name != "state":
                finite &= np.isfinite(values)
        if not finite.all():  # a sample that is no number is a gap: the stretches either side are not bridged
            self.received += int((~finite).sum())
            times = columns["t"][~finite]
            times = times[np.isfinite(times)]
            where = f" at {float(times[0]):.6g} s" if len(times) else ""
            self.events.append(f"{int((~finite).sum())} samples holding values that are not numbers were left "
                               f"out{where} (a gap, not bridged)")
            for first, last in runs(finite):
                self._fed = None
                self._take({name: values[first:last + 1] for name, values in columns.items()})
            return
        self._take(columns)

    def _take(self, columns: dict[str, np.ndarray]) -> None:
        """Samples that are all numbers: unwrapped, in jointid's angle convention, counted, then streamed."""
        if not self.linear:
            columns["q"] = self._unwrapped(columns["q"])
        sign, offset = self.convention.sign, self.convention.offset
        if not self.convention.is_default:  # as a log's convention: in radians, after the source's units
            columns["q"] = sign * columns["q"] + offset
            for name in ("qd", "qdd", "tau"):
                if name in columns:
                    columns[name] = sign * columns[name]
        self.received += len(columns["t"])
        self._count_time(columns["t"])
        if self.step is None:
            # The warm-up is the samples up to the first one WARMUP seconds in (and WARMUP_SAMPLES), however they
            # arrive in blocks: the rest of the block is fed after the filters are chosen.
            before = sum(len(block["t"]) for block in self._warm)
            t0 = (self._warm[0] if self._warm else columns)["t"][0]
            late = (columns["t"] - t0 >= self.warmup) & (before + np.arange(1, len(columns["t"]) + 1) >= WARMUP_SAMPLES)
            if not late.any():
                self._warm.append(columns)
                return
            end = int(np.argmax(late)) + 1
            self._warm.append({name: values[:end] for name, values in columns.items()})
            self._start()
            columns = {name: values[end:] for name, values in columns.items()}
            if not len(columns["t"]):
                return
        self._feed(columns)

    def _unwrapped(self, q: np.ndarray) -> np.ndarray:
        """The angle with a wrapped source's jumps undone, as logs.angles does a log's: a step of more than half a
        turn, within a quarter turn of a whole one, between angles inside (-pi, pi] or [0, 2 pi)."""
        previous = self._last_angle
        self._last_angle = float(q[-1])
        joined = q if previous is None else np.concatenate([[previous], q])
        steps = np.diff(joined)
        turn = 2 * math.pi
        jumps = (np.abs(steps) > turn / 2) & (np.abs(np.abs(steps) - turn) <= turn / 4)
        inside = -math.pi - 1e-9 <= float(np.min(joined)) and float(np.max(joined)) <= turn + 1e-9
        if jumps.any() and inside:
            self._unwraps += int(jumps.sum())
            added = -np.cumsum(np.where(jumps, np.sign(steps), 0.0)) * turn  # after each step
            if previous is None:
                added = np.concatenate([[0.0], added])
            unwrapped = q + self._turns + added
            self._turns += float(added[-1])
            return unwrapped
        return q + self._turns if self._turns else q

    def _count_time(self, t: np.ndarray) -> None:
        """Seconds of samples received, gaps not counted."""
        previous = self._last_t
        steps = np.diff(t) if previous is None else np.diff(np.concatenate([[previous], t]))
        if self.step is not None:
            steps = steps[steps <= GAP_FACTOR * self.step]
        self.elapsed += float(np.sum(steps[steps > 0]))
        self._last_t = float(t[-1])

    def _feed(self, columns: dict[str, np.ndarray]) -> None:
        """Cut samples into contiguous stretches (at gaps and SysId test changes) and stream each."""
        t = columns["t"]
        state = columns.get("state")
        if state is not None:
            state = np.asarray(state).astype(str)
            self._count_tests(state)
        before = np.concatenate([[math.nan if self._fed is None else self._fed[0]], t[:-1]])
        breaks = ~(np.diff(np.concatenate([[before[0]], t])) <= GAP_FACTOR * self.step)  # NaN: a first sample
        if state is not None:
            breaks |= state != np.concatenate([[None if self._fed is None else self._fed[1]], state[:-1]])
        starts = np.flatnonzero(breaks)
        edges = [0, *(int(k) for k in starts if k > 0), len(t)]
        for first, last in zip(edges[:-1], edges[1:]):
            piece = {name: values[first:last] for name, values in columns.items() if name != "state"}
            if breaks[first]:
                self._finish_segment()
                name = "" if state is None else str(state[first])
                idle = state is not None and name.strip().lower() in IDLE_STATES
                self._segment = None if idle else _Segment(self, name)
            if self._segment is not None:
                rows = self._segment.add(piece)
                if rows is not None:
                    self._pending.append(rows)
                    self._pending_rows += len(rows["tau"])
        self._fed = (float(t[-1]), None if state is None else str(state[-1]))
        self._judge_pending(final=False)

    def _count_tests(self, state: np.ndarray) -> None:
        """Seconds of each SysId test received."""
        names, first, counts = np.unique(state, return_index=True, return_counts=True)
        for k in np.argsort(first):  # in the order they came, however the samples were cut into blocks
            name, count = names[k], counts[k]
            if str(name).strip().lower() not in IDLE_STATES:
                self.tests[str(name)] = self.tests.get(str(name), 0.0) + float(count) * self.step

    def _finish_segment(self) -> None:
        """Close the current stretch: its unfinished ends are not fitted; what waits is judged."""
        self._segment = None
        self._judge_pending(final=True)
        if self.newey_west is not None:
            self.newey_west.gap()
            self.statistics.gap()

    # -- rows judged and fitted -----------------------------------------------------------------------------------

    def _judge_pending(self, final: bool) -> None:
        """Judge the rows waiting for standstill and outside torques in blocks of exactly ROBUST_SECONDS (the rest
        of a stretch at its end), whatever blocks they arrived in, and add the kept rows to the statistics."""
        enough = max(int(ROBUST_SECONDS * self.fitted_rate) if self.step else 0, 8 * (self.union.size + 1))
        if not self._pending_rows or (self._pending_rows < enough and not final):
            return
        pending = self._pending
        names = ("X", "tau", "q", "qd", "qdd", "t")
        waiting = {name: np.concatenate([rows[name] for rows in pending]) for name in names}
        waiting["variants"] = {pipeline: tuple(np.concatenate([rows["variants"][pipeline][j] for rows in pending])
                                               for j in (0, 1)) for pipeline in self.pipelines[1:]}
        waiting["state"] = pending[0]["state"]
        count = self._pending_rows
        first = 0
        while count - first >= enough or (final and first < count):
            last = count if final and count - first < enough else first + enough
            self._judge_block(_rows(waiting, first, last), waiting["state"])
            first = last
        rest = _rows(waiting, first, count)
        self._pending, self._pending_rows = ([rest] if count > first else []), count - first

    def _judge_block(self, block: dict, state: str) -> None:
        """Judge one block of rows for standstill and outside torques and add it to the statistics."""
        variants = block["variants"]
        still, pushes = self._exclusions(block)
        kept = ~(still | pushes)
        when = self.elapsed
        self.statistics.add(block["X"], block["tau"], when, kept)
        self.all_moving.add(block["X"][~still], block["tau"][~still], when)
        if self.choosing:  # each test's own residual variance, for the mechanism's BIC
            test = self.test_statistics.setdefault(state, BatchStatistics(self.union.size, 10 ** 12))
            test.add(block["X"][kept], block["tau"][kept], when)
        if self.newey_west is not None:  # the rows left out are gaps in the grid, as a log fit's positions
            self.newey_west.add(block["X"] * kept[:, None], np.where(kept, block["tau"], 0.0))
        for pipeline, (X, tau) in variants.items():
            self.variant_statistics[pipeline].add(X[kept], tau[kept], when)
        self._remember(block, kept)

    def _exclusions(self, block: dict) -> tuple[np.ndarray, np.ndarray]:
        """(standstill, outside torques) of a block of rows, as a log fit finds them (estimation.exclusion)."""
        X, tau = block["X"][:, self.columns], block["tau"]
        size = len(tau)
        still = np.zeros(size, dtype=bool)
        rest = still
        model = self.model
        support = self.support
        coulomb, speed_index = model.index_of("Fc"), model.index_of("B")
        if coulomb is not None and speed_index is not None:
            speed = X[:, speed_index]
            self._speed_squares += float(np.dot(speed, speed))
            self._speed_count += size
            threshold = max(STANDSTILL_SHARE * math.sqrt(self._speed_squares / self._speed_count),
                            3.0 * self._resolution)
            slow = np.abs(speed) < threshold
            rest = np.zeros(size, dtype=bool)
            for first, last in runs(slow):
                if last - first + 1 >= max(2, support):
                    rest[first:last + 1] = True
            rest = widened(rest, support)
            still = slow | rest
            if (~still).sum() <= 4 * X.shape[1]:
                still = rest = np.zeros(size, dtype=bool)
        pushes = np.zeros(size, dtype=bool)
        usable = ~still
        if not self.robust or usable.sum() <= 4 * X.shape[1]:
            return still, pushes
        start = None
        solution = self.statistics.solution(columns=self.columns)
        if solution is not None and solution.estimate is not None:
            start = solution.estimate
        lag = max(4, 2 * support)
        with np.errstate(all="ignore"):
            flagged, level, _ = outside_torques(X, tau, usable, rest, coulomb, support, lag, start)
            if not model.effort.is_torque:  # a voltage step's response is the signal, not an outside torque
                reach = (self.window or 0) + 2 * support + 2
                flagged = explained_transients(X, tau, flagged, usable, commanded_changes(tau, reach), level)
        return still, flagged

    def _remember(self, block: dict, kept: np.ndarray) -> None:
        """Keep the recent rows for the charts, the prediction and the advice's view of the motion."""
        q, qd = block["q"][kept], block["qd"][kept]
        if len(q):
            self._range = [min(self._range[0], float(np.min(q))), max(self._range[1], float(np.max(q)))]
            self._directions[0] += int(np.sum(qd > 0))
            self._directions[1] += int(np.sum(qd < 0))
        self._recent.append({name: block[name][kept] for name in ("t", "q", "qd", "qdd", "tau", "X")})
        newest = block["t"][-1]
        while self._recent and len(self._recent[0]["t"]) and self._recent[0]["t"][-1] < newest - self.recent_seconds:
            self._recent.popleft()
        while self._recent and not len(self._recent[0]["t"]):
            self._recent.popleft()

    # -- refresh ----------------------------------------------------------------------------------------------------

    def refresh(self) -> WatchRefresh:
        """What to show now: each parameter's estimate, error, verdict and history, the advice, the tests seen."""
        result = self._fit()
        parameters = self._traces(result)
        return WatchRefresh(
            elapsed=self.elapsed,
            received=self.received,
            fitted=0 if self.statistics is None else self.statistics.count,
            dropped=self.dropped,
            parameters=parameters,
            advice=self._advice(parameters, result),
            tests=tuple(self.tests.items()),
            events=tuple(self.events),
            recent=self._recent_columns(result),
            result=result,
            ended=self.ended,
        )

    def gains(self, refresh: WatchRefresh, drive=None):
        """The mechanism's WPILib feedforward gains from a refresh's fit, as for a recorded SysId log
        (studies.gains.arm_gains: a voltage fit's own, a torque fit's through the motor `drive`), or None without a
        unique fit (or, for torque, without a drive)."""
        from types import SimpleNamespace

        from .gains import GainsError, arm_gains

        if refresh.result is None:
            return None
        unit = "meters" if self.linear else "radians"
        # What arm_gains reads of a log fit: its result, verdicts and the position's unit.
        log = SimpleNamespace(source=SimpleNamespace(table=SimpleNamespace(units=(("q", unit),))))
        fit = SimpleNamespace(result=refresh.result, verdicts=refresh.result.verdicts, training=log)
        try:
            return arm_gains(fit, drive)
        except GainsError:
            return None

    def _fit(self) -> FitResult | None:
        """The current fit as a FitResult carrying the whole run's statistics and the judged verdicts."""
        statistics = self.statistics
        if statistics is None or statistics.count <= self.union.size or not self._recent:
            return None
        if self.newey_west is not None and statistics.count < 2 * self.support:
            return None  # fewer rows than the filter correlates: no Newey-West error is meaningful yet
        if self.choosing:
            self._choose_mechanism()
        solution = statistics.solution(columns=self.columns)
        recent = self._recent_rows()
        training = JointData(t=recent["t"], q=recent["q"], qd=recent["qd"], qdd=recent["qdd"], tau=recent["tau"])
        result = FitResult(training=training, heldout=None, heldout_is_noiseless=False, solution=solution,
                           training_regressor=recent["X"][:, self.columns], model=self.model)
        correlated = None
        if self.newey_west is not None and solution.estimate is not None:
            from .log_fit import correlation_lag

            correlated = self.newey_west.covariance(solution, correlation_lag(solution.row_count, self.filter),
                                                    self.columns)
        uncertainty = parameter_uncertainty(solution, None, self.model, None, correlated)
        # The whole run's statistics, not the recent rows' the result carries for its charts.
        vars(result)["uncertainty"] = uncertainty
        vars(result)["training_rmse"] = float(solution.residual_norm) / math.sqrt(solution.row_count)
        judgement = self._judgement(result, statistics)
        judged = with_judgement(result, judgement)
        if judgement.spread and uncertainty is not None:  # the analysis choices widen the reported errors
            vars(judged)["uncertainty"] = replace(uncertainty, spread=np.asarray(judgement.spread, dtype=float))
            vars(judged).pop("bse", None)
        return judged

    def _judgement(self, result: FitResult, statistics: BatchStatistics):
        """The verdicts and reported errors as a log fit's (studies.log_fit.judge_log): the noise errors widened by
        the other analysis choices' moves and the halves' scatter."""
        names = self.model.names
        uncertainty = result.uncertainty
        if uncertainty is None or uncertainty.noise_relative_std_pct is None:
            return noise_judgement(names, None)
        findings = []
        if self.filter.active and self._halves() is None:
            # A log fit compares its halves; until the run is long enough for that, nothing is called well
            # determined (early refreshes would otherwise judge a few seconds on the noise alone).
            findings += [Finding(name, TOO_SHORT) for name in names]
        exact = is_exact(result)
        return judge(names, uncertainty.noise_relative_std_pct, None, findings,
                     () if exact else self._halves_scatter(result), () if exact else self._spreads(result),
                     result.estimate, uncertainty.noise_std_error)

    def _spreads(self, result: FitResult):
        """How far the other analysis choices move the parameters beyond noise, as studies.log_fit.log_spreads: the
        derivative window and cutoff halved and doubled (the parallel pipelines), the robust step's exclusions,
        and a torque offset explained the other way (its columns streamed beside the model's)."""
        from .log_fit import SETTING_CHOICES

        model, estimate, noise = self.model, result.estimate, result.uncertainty.noise_std_error
        if noise is None:
            return ()
        names = model.names
        # A refit's noise errors: its independent-residual errors scaled as the fit's Newey-West ones are to its own.
        alone = parameter_uncertainty(result.solution, None, model).noise_std_error
        with np.errstate(all="ignore"):
            scale = np.where(alone > 0, noise / alone, 1.0)
        spreads = []
        for setting, choice in SETTING_CHOICES.items():
            others, errors = [], []
            for pipeline, statistics in self.variant_statistics.items():
                solution = statistics.solution(columns=self.columns)
                if pipeline.label != setting or solution is None or solution.estimate is None:
                    continue
                refit = parameter_uncertainty(solution, None, model)
                others.append(refit.estimate)
                errors.append(None if refit.noise_std_error is None else refit.noise_std_error * scale)
            spreads += beyond_noise(names, estimate, noise, others, choice, errors)
        moving = self.all_moving
        if self.robust and moving.count != self.statistics.count:
            solution = moving.solution(columns=self.columns)
            if solution is not None and solution.estimate is not None:
                spreads += beyond_noise(names, estimate, noise, [model.report(solution.estimate)], ROBUST_CHOICE)
        spreads += self._offset_spreads(estimate, noise)
        return tuple(spreads)

    def _offset_spreads(self, estimate: np.ndarray, noise: np.ndarray):
        """The spread of a torque offset explained the other way (a bias <-> an angle offset), as a log fit's."""
        if self.alternative is None:
            return ()
        other, choice = self.alternative
        columns = [self.union.column_names.index(name) for name in other.column_names]
        solution = self.statistics.solution(columns=columns)
        if solution is None or solution.estimate is None:
            return ()
        correlated = None
        if self.newey_west is not None:
            from .log_fit import correlation_lag

            correlated = self.newey_west.covariance(solution, correlation_lag(solution.row_count, self.filter),
                                                    columns)
        with np.errstate(all="ignore"):
            refit = parameter_uncertainty(solution, None, other, None, correlated)
        errors = refit.noise_std_error
        if errors is None or not (np.all(np.isfinite(refit.estimate)) and np.all(np.isfinite(errors))):
            return ()
        by_name = dict(zip(other.names, zip(refit.estimate, errors)))
        found = np.array([by_name.get(name, (np.nan, np.nan)) for name in self.model.names], dtype=float)
        shared = np.isfinite(found[:, 0])
        return beyond_noise(self.model.names, estimate, noise, [np.where(shared, found[:, 0], estimate)], choice,
                            [np.where(shared, found[:, 1], noise)])

    def _halves(self):
        """The run's two halves (lists of batches, split at the batch end nearest the middle of the grid), or None
        while either spans fewer than HALF_LAGS correlation lags (as a log fit's halves)."""
        batches = self.statistics.batches
        if not self.filter.active or len(batches) < 2:
            return None
        grid = np.cumsum([batch.grid for batch in batches])
        middle = int(np.argmin(np.abs(grid[:-1] - grid[-1] / 2)))
        first, second = batches[:middle + 1], batches[middle + 1:]
        if min(grid[middle], grid[-1] - grid[middle]) < HALF_LAGS * self.halves_lag:
            return None
        return first, second

    def _halves_scatter(self, result: FitResult):
        """The scatter of the run's two halves (each fitted alone, with its own Newey-West errors) beyond their
        errors, as a log fit's (studies.refits.stretch_scatter)."""
        halves = self._halves()
        if halves is None:
            return ()
        values, errors = [], []
        for half in halves:
            if sum(batch.count for batch in half) <= 4 * len(self.columns):
                return ()
            solution = self.statistics.solution(half, self.columns)
            if solution.estimate is None:
                return ()
            correlated = self.statistics.lagged_covariance(solution, half, self.columns)
            with np.errstate(all="ignore"):
                uncertainty = parameter_uncertainty(solution, None, self.model, None, correlated)
            error = uncertainty.noise_std_error
            if error is None or not np.all(np.isfinite(error)) or not np.all(error > 0):
                return ()
            values.append(uncertainty.estimate), errors.append(error)
        ratios, significant = scatter_ratios(np.array(values), np.array(errors))
        return scatter_findings(self.model.names, ratios, significant, "halves of the run")

    def _traces(self, result: FitResult | None) -> tuple[ParameterTrace, ...]:
        """Each parameter's trace: now, its thinned history and when it became well determined."""
        if self.model is None:
            return ()
        traces = []
        judgement = None if result is None else result.judgement
        for k, parameter in enumerate(self.model.parameters):
            name = parameter.name
            value = error = math.nan
            verdict = reason = None
            if result is not None and result.estimate is not None:
                value = float(result.estimate[k])
                error = float(result.bse[name])
                verdict = judgement.verdicts[k]
                reason = judgement.reasons[k] or None
                history = self._history.setdefault(name, [])
                if not history or history[-1][0] < self.elapsed:
                    history.append((self.elapsed, value, error))
                    if len(history) >= 2 * HISTORY:
                        del history[1:-1:2]  # every other point, the first and the newest kept
            if verdict == WELL_DETERMINED:
                if self._determined.get(name) is None:
                    self._determined[name] = (self.elapsed, 100.0 * error / abs(value))
            else:
                self._determined[name] = None
            since = self._determined.get(name)
            traces.append(ParameterTrace(name, parameter.label, parameter.unit, value, error, verdict, reason,
                                         None if since is None else since[0], None if since is None else since[1],
                                         tuple(self._history.get(name, ()))))
        return tuple(traces)

    def _advice(self, traces: tuple[ParameterTrace, ...], result: FitResult | None) -> tuple[str, ...]:
        """What motion would determine what is not determined yet: each such parameter, why (its verdict and
        reason, a column the motion leaves dependent on the others, a sign its rule forbids) and what motion would
        excite it."""
        if self.model is None or self.step is None:
            return (f"Waiting for {self.warmup:g} s of samples to choose the filters.",)
        if self.statistics is None or not self.statistics.count:
            return ("Waiting for the first fitted samples.",)
        advice = []
        undetermined = () if result is None or result.estimate is not None else result.identifiable.undetermined
        failures = () if result is None else result.sign_failures
        for trace, parameter in zip(traces, self.model.parameters):
            if trace.verdict == WELL_DETERMINED and trace.name not in failures:
                continue
            kind = self.model.term(self.model.columns_behind(trace.name)[0]).kind
            motion = self._motion_for(kind)
            if result is not None and result.estimate is None:
                if trace.name not in undetermined and not set(self.model.columns_behind(trace.name)) & set(
                        undetermined):
                    continue
                columns = [self.model.column_names.index(name) for name in self.model.columns_behind(trace.name)]
                zero = bool(np.all(result.identifiable.zero_columns[columns]))
                why = f"{parameter.invisible_when} so far" if zero else "its column has followed the others'"
                state = f"not separable from the others yet ({why})"
            elif trace.name in failures:
                state = f"{trace.value:.3g} {trace.unit}, against its sign rule ({parameter.requirement})"
            elif trace.verdict is None:
                state = "not judged yet (too few stretches of data)"
            elif trace.reason:
                state = f"{trace.verdict} ({trace.reason})"
            else:
                state = f"{trace.verdict} at {100 * trace.error / abs(trace.value):.0f} %" \
                    if trace.value and math.isfinite(trace.error) else trace.verdict
            advice.append(f"{trace.name} ({trace.label}) is {state}: {motion}.")
        return tuple(advice)

    def _motion_for(self, kind: str) -> str:
        """The motion that excites a term of kind `kind` (its torque term's name), given what was seen."""
        both = self._directions[0] > 0 and self._directions[1] > 0
        turn = "" if both else "move in both directions, and "
        span = self._range[1] - self._range[0]
        if kind == "I":
            return "accelerate and brake harder (quick reversals or steps)"
        if kind == "B":
            return turn + "move at more different speeds, faster ones too"
        if kind in ("Fc", "tau0"):
            return "move in both directions" if not both else "move slowly as well as fast, in both directions"
        if kind in ("h", "h_c", "h_s", "q0"):
            return f"swing through more of the angle range (so far {math.degrees(span):.0f} degrees)" \
                if math.isfinite(span) else "swing through more of the angle range"
        if kind == "tauG":
            return "move up and down at steady speeds"
        return "move more, and more variedly"

    def _recent_rows(self) -> dict[str, np.ndarray]:
        """The recent fitted rows as arrays."""
        return {name: np.concatenate([rows[name] for rows in self._recent]) for name in self._recent[0]}

    def _recent_columns(self, result: FitResult | None) -> dict[str, np.ndarray]:
        """'t', 'q', 'qd', 'tau' and 'predicted' of the last seconds, for the charts."""
        if not self._recent:
            return {}
        rows = self._recent_rows()
        recent = {name: rows[name] for name in ("t", "q", "qd", "tau")}
        if result is not None and result.column_estimate is not None:
            recent["predicted"] = rows["X"][:, self.columns] @ result.column_estimate
        return recent

    @property
    def fitted_until(self) -> float | None:
        """The source's time of the newest fitted row (rows wait for the robust step's block), or None."""
        fitted = [rows["t"] for rows in self._recent if len(rows["t"])]
        return float(fitted[-1][-1]) if fitted else None

    @property
    def state_size(self) -> int:
        """Numbers the watcher holds (statistics, buffers, recent rows, histories): bounded however long it runs."""
        total = 0
        total += 0 if self.newey_west is None else self.newey_west.size
        for statistics in (self.statistics, self.all_moving, *self.variant_statistics.values()):
            total += 0 if statistics is None else statistics.size
        total += sum(values.size for rows in self._recent for values in rows.values())
        total += sum(len(history) * 3 for history in self._history.values())
        total += 0 if self._segment is None else self._segment.size
        total += sum(rows["X"].size for rows in self._pending)
        return total
