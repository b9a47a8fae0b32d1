"""Deterministic watches for the faces' tests: a scripted sequence of refreshes made from real fits of the lesson's
joint on more and more samples (so the estimates converge and the verdicts change as a live fit's would), and a
plan that hands them over as `jointid watch`'s WatchPlan does."""

from __future__ import annotations

import threading
from dataclasses import replace

import numpy as np

from jointid.estimation.uncertainty import WELL_DETERMINED
from jointid.present.watch import Saved
from jointid.studies.experiment import run_experiment
from jointid.studies.watch_refresh import ParameterTrace, WatchRefresh
from jointid.studies.watch_session import SOURCE_ENDED, STOPPED
from jointid.synthetic.settings import Settings

RATE_HZ = 25.0
"""The scripted source's sample rate: elapsed seconds are samples / RATE_HZ."""


def scripted_refreshes(counts=(6, 8, 12, 16, 24, 32, 48, 64, 96, 128, 160, 200), noise: float = 0.2,
                       motion: str = "rich", events: tuple[str, ...] = ()) -> list[WatchRefresh]:
    """One refresh per sample count: the fit of that many samples, each parameter's history and the moment it
    became well determined and stayed so (the last refresh has `ended`); `events` arrive with the second refresh."""
    fits = [run_experiment(Settings(motion=motion, noise=noise, samples=n, seed=7)) for n in counts]
    names = fits[0].model.names
    refreshes, histories = [], {name: [] for name in names}
    for index, (count, result) in enumerate(zip(counts, fits)):
        elapsed = count / RATE_HZ
        traces = []
        for k, name in enumerate(names):
            value, error = float(result.estimate[k]), float(result.uncertainty.residual_std_error[k])
            histories[name].append((elapsed, value, error))
            verdict, reason = result.judgement.verdicts[k], result.judgement.reasons[k] or None
            traces.append(ParameterTrace(name, result.model.parameters[k].label, result.model.parameters[k].unit,
                                         value, error, verdict, reason, history=tuple(histories[name])))
        refreshes.append(WatchRefresh(
            elapsed=elapsed, received=count, fitted=count, dropped=0, parameters=tuple(traces),
            advice=("Move faster: B needs speed.",) if traces[2].verdict != WELL_DETERMINED else (),
            events=events if index >= 1 else (),
            recent={"t": result.training.t, "q": result.training.q, "qd": result.training.qd,
                    "tau": result.training.tau, "predicted": result.training_predictions},
            result=result, ended=index == len(counts) - 1))
    return with_determination(refreshes)


def with_determination(refreshes: list[WatchRefresh]) -> list[WatchRefresh]:
    """Each trace's determined_at/pct: the first refresh from which it stays well determined to the end."""
    out = list(refreshes)
    for k in range(len(refreshes[0].parameters)):
        since = None
        for index, refresh in enumerate(refreshes):
            if refresh.parameters[k].verdict != WELL_DETERMINED:
                since = None
            elif since is None:
                since = index
        for index in range(len(out)):
            if since is not None and index >= since:
                first = refreshes[since].parameters[k]
                trace = replace(out[index].parameters[k], determined_at=refreshes[since].elapsed,
                                determined_pct=100 * abs(first.error / first.value))
                out[index] = replace(out[index], parameters=(*out[index].parameters[:k], trace,
                                                             *out[index].parameters[k + 1:]))
    return out


class ScriptedSession:
    """The session part of a plan: `last` and `stop()`."""

    def __init__(self) -> None:
        self.last: WatchRefresh | None = None


class ScriptedPlan:
    """A WatchPlan stand-in handing over scripted refreshes; with `hold`, it waits after the refreshes until
    stopped (a source still connected), else it ends as a finished source does."""

    description = "scripted source: q=/Arm/Position, tau=/Arm/Torque"
    effort = "torque"

    def __init__(self, refreshes: list[WatchRefresh], hold: bool = False, save_path: str | None = None) -> None:
        self.refreshes = refreshes
        self.hold = hold
        self.save_path = save_path
        self.session = ScriptedSession()
        self.stopped = threading.Event()
        self.saves = 0
        self.delivered = threading.Event()
        """Set once every refresh was handed over."""

    def watch(self, on_refresh) -> str:
        for refresh in self.refreshes:
            self.session.last = refresh
            on_refresh(refresh)
        self.delivered.set()
        if self.hold:
            self.stopped.wait()
            return STOPPED
        return SOURCE_ENDED

    def stop(self) -> None:
        self.stopped.set()

    def save(self) -> Saved:
        self.saves += 1
        received = self.session.last.received if self.session.last else 0
        if self.save_path is None:
            return Saved(None, received, "no --save PATH given")
        return Saved(self.save_path, received)


def chart_is_converging(refreshes: list[WatchRefresh]) -> bool:
    """Whether every parameter's relative error at the end is below its error at the start (a sanity check)."""
    first, last = refreshes[0].parameters, refreshes[-1].parameters
    return all(abs(b.error / b.value) < abs(a.error / a.value) for a, b in zip(first, last))



