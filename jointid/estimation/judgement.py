"""One judgement per parameter: its reported error and verdict from everything that bears on it, and the reasons.

The noise-based relative standard error gives each parameter a first verdict
(jointid.estimation.uncertainty.verdict). The other checks widen that error or
weaken the verdict:

- a spread, when another reasonable analysis choice (the derivative window,
  the cutoff, the robust step, how a torque offset is explained) moves the
  estimate further than noise would: that move is added in quadrature to the
  error, which every face then reports, and the verdict is judged on it;
- a scatter, when stretches of the run (or runs of the joint) disagree by more
  than their standard errors allow: the error is widened by that ratio (a
  Birge ratio, as the Particle Data Group scales its averages), and the verdict
  is never "well determined";
- a finding, when a check moves the estimate in a way no error describes (a
  term the model lacks): never "well determined".

Every face (text, JSON, library, explorer, report, gains) shows these verdicts,
errors and reasons; the noise-only verdicts and errors stay in the JSON as
`noise_verdicts` and `noise_std_error`.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from types import MappingProxyType

from .uncertainty import AT_BOUND, WEAK, WELL_DETERMINED, verdict


@dataclass(frozen=True)
class Finding:
    """A check that moved one parameter beyond its error: its name and the reason in a few words."""

    name: str
    reason: str
    """E.g. 'moved by the derivative settings', 'moved 4.1 standard errors by --no-robust'."""


@dataclass(frozen=True)
class Scatter:
    """How far one parameter's pieces (stretches of a run, or runs) scatter beyond their standard errors."""

    name: str
    ratio: float
    """The scatter in units of what the standard errors allow (a Birge ratio: about 1 when they are honest)."""
    pieces: str
    """What scattered, e.g. 'halves of the run' or 'runs'."""

    @property
    def reason(self) -> str:
        """'its halves of the run scatter 2.4 times their errors'."""
        return f"its {self.pieces} scatter {self.ratio:.1f} times their errors"

    @property
    def choice(self) -> str:
        """'the scatter of its halves of the run (2.4 times their errors)': what widened an error."""
        return f"the scatter of its {self.pieces} ({self.ratio:.1f} times their errors)"


@dataclass(frozen=True)
class Spread:
    """How far one analysis choice moves one parameter beyond what noise makes: an error added in quadrature."""

    name: str
    error: float
    """The move beyond noise, in the parameter's unit (sqrt(move^2 - noise error^2), say)."""
    choice: str
    """What moved it, e.g. "the cutoff's choice" or 'the angle offset in place of the torque bias'."""


@dataclass(frozen=True, eq=False)
class Judgement:
    """Each parameter's verdict from every check, the noise-only verdict, and why they differ."""

    names: tuple[str, ...]
    noise_verdicts: tuple[str | None, ...]
    """From the noise-based relative standard error alone (None without a standard error)."""
    verdicts: tuple[str | None, ...]
    """The verdicts every face shows."""
    reasons: tuple[str, ...]
    """Per parameter, why its error or verdict differs from the noise's ('' when neither does)."""
    spread: tuple[float, ...] = ()
    """Per parameter, what widens its noise-based standard error, added in quadrature (0: nothing; () for none at
    all): jointid.estimation.uncertainty.ParameterUncertainty.spread."""
    ratio_spread: float = 0.0
    """What widens the noise-based error of h/I (FitResult.scale_ratio) in quadrature: the analysis choices' moves of
    the ratio beyond its noise, as `spread` for the parameters (0: nothing)."""

    def by_name(self) -> Mapping[str, str | None]:
        """The verdicts by parameter name (read-only)."""
        return MappingProxyType(dict(zip(self.names, self.verdicts)))

    def reason_of(self, name: str) -> str:
        """Why `name`'s error or verdict differs from the noise's, '' when neither does."""
        return self.reasons[self.names.index(name)] if name in self.names else ""

    @property
    def weakened(self) -> dict[str, str]:
        """{name: reason} of the parameters whose error another check widened or whose verdict it weakened."""
        return {name: reason for name, reason in zip(self.names, self.reasons) if reason}

    def widened(self, noise_errors) -> tuple[float, ...]:
        """(p,) The reported errors: `noise_errors` widened in quadrature by `spread`."""
        if not self.spread:
            return tuple(map(float, noise_errors))
        return tuple(float(math.hypot(error, extra)) if extra > 0 else float(error)
                     for error, extra in zip(noise_errors, self.spread))

    def to_dict(self) -> dict:
        """JSON-ready: the judged verdicts, the noise-only ones and the reasons, keyed by parameter."""
        return {"verdicts": dict(zip(self.names, self.verdicts)),
                "noise_verdicts": dict(zip(self.names, self.noise_verdicts)),
                "verdict_reasons": {name: reason for name, reason in zip(self.names, self.reasons) if reason}}


def judge(names: Iterable[str], relative_pct, held=None, findings: Iterable[Finding] = (),
          scatters: Iterable[Scatter] = (), spreads: Iterable[Spread] = (), values=None, noise_errors=None
          ) -> Judgement:
    """The judgement of parameters with noise-based relative errors `relative_pct` (% of |estimate|, None when no
    standard error exists), `held` at a bound (no error), weakened by `findings`, widened by `scatters` and by
    `spreads` (which need the `values` and their `noise_errors`, both (p,))."""
    names = tuple(names)
    if relative_pct is None:
        nothing = (None,) * len(names)
        return Judgement(names, nothing, nothing, ("",) * len(names))
    held = (False,) * len(names) if held is None else tuple(bool(h) for h in held)
    moved: dict[str, list[str]] = {}
    for finding in findings:
        moved.setdefault(finding.name, [])
        if finding.reason not in moved[finding.name]:
            moved[finding.name].append(finding.reason)
    widened = {scatter.name: scatter for scatter in scatters if scatter.ratio > 1}
    choices: dict[str, list[Spread]] = {}
    for spread in spreads:
        if spread.error > 0 and math.isfinite(spread.error):
            choices.setdefault(spread.name, []).append(spread)
    noise, judged, reasons, extra = [], [], [], []
    for index, (name, relative, at_bound) in enumerate(zip(names, relative_pct, held)):
        if at_bound:
            noise.append(AT_BOUND), judged.append(AT_BOUND), reasons.append(""), extra.append(0.0)
            continue
        first = verdict(float(relative))
        scatter = widened.get(name)
        error = None if noise_errors is None else float(noise_errors[index])
        # A scatter widens the error by its ratio, sqrt(ratio^2 - 1) errors more in quadrature; each choice by its
        # move beyond noise; the verdict is judged on the widened error.
        parts = [] if scatter is None or error is None else [error * math.sqrt(scatter.ratio ** 2 - 1)]
        mine = sorted(choices.get(name, ()), key=lambda spread: -spread.error) if error is not None else []
        parts += [spread.error for spread in mine]
        total = math.sqrt(sum(part * part for part in parts)) if parts else 0.0
        if error is not None and error > 0 and math.isfinite(error):
            now_relative = float(relative) * math.hypot(error, total) / error
        elif scatter is not None:
            now_relative = float(relative) * scatter.ratio
        else:
            now_relative = float(relative)
        if error == 0 and total > 0 and values is not None:
            now_relative = relative_error_pct(float(values[index]), total)
        now = verdict(now_relative)
        because = []
        if mine or (scatter is not None and error is not None):
            because.append(f"error widened from {error:.3g} to {math.hypot(error, total):.3g} by "
                           + ", ".join(([scatter.choice] if scatter is not None else [])
                                       + [spread.choice for spread in mine]))
        elif scatter is not None:
            because.append(scatter.reason)
        because += moved.get(name, [])
        # A scatter beyond the errors, or a check no error describes, is a finding in itself.
        if now == WELL_DETERMINED and (scatter is not None or moved.get(name)):
            now = WEAK
        why = because if (now != first or mine or (scatter is not None and error is not None)) else []
        noise.append(first), judged.append(now), reasons.append(", ".join(why)), extra.append(total)
    return Judgement(names, tuple(noise), tuple(judged), tuple(reasons),
                     tuple(extra) if any(extra) else ())


def noise_judgement(names: Iterable[str], uncertainty) -> Judgement:
    """The judgement of a fit with no other check (synthetic data, samples of your own): its noise verdicts."""
    names = tuple(names)
    if uncertainty is None:
        return judge(names, None)
    return judge(names, uncertainty.noise_relative_std_pct, uncertainty.held)


def relative_error_pct(value: float, error: float) -> float:
    """error as % of |value| (0 when the error is 0, inf when the value is 0 and the error is not)."""
    if error == 0:
        return 0.0
    return math.inf if value == 0 or not math.isfinite(value) else 100.0 * abs(error) / abs(value)
