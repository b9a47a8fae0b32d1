"""One judgement per parameter: its verdict from everything that bears on it, and the reasons.

The noise-based relative standard error gives each parameter a first verdict
(jointid.estimation.uncertainty.verdict). Other checks can only weaken it:

- a finding, when another reasonable analysis moves the estimate beyond its
  error (the sensitivity check's derivative window and cutoff, the robust
  step's exclusions, a term the model lacks): never "well determined";
- a scatter, when stretches of the run (or runs of the joint) disagree by more
  than their standard errors allow: never "well determined" either, and judged
  on the error widened by that ratio.

Every face (text, JSON, library, explorer, report, gains) shows these verdicts
and reasons; the noise-only verdict stays in the JSON as `noise_verdicts`.
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


@dataclass(frozen=True, eq=False)
class Judgement:
    """Each parameter's verdict from every check, the noise-only verdict, and why they differ."""

    names: tuple[str, ...]
    noise_verdicts: tuple[str | None, ...]
    """From the noise-based relative standard error alone (None without a standard error)."""
    verdicts: tuple[str | None, ...]
    """The verdicts every face shows."""
    reasons: tuple[str, ...]
    """Per parameter, why its verdict is below its noise verdict ('' when it is not)."""

    def by_name(self) -> Mapping[str, str | None]:
        """The verdicts by parameter name (read-only)."""
        return MappingProxyType(dict(zip(self.names, self.verdicts)))

    def reason_of(self, name: str) -> str:
        """Why `name`'s verdict is below its noise verdict, '' when it is not."""
        return self.reasons[self.names.index(name)] if name in self.names else ""

    @property
    def weakened(self) -> dict[str, str]:
        """{name: reason} of the parameters another check weakened."""
        return {name: reason for name, reason in zip(self.names, self.reasons) if reason}

    def to_dict(self) -> dict:
        """JSON-ready: the judged verdicts, the noise-only ones and the reasons, keyed by parameter."""
        return {"verdicts": dict(zip(self.names, self.verdicts)),
                "noise_verdicts": dict(zip(self.names, self.noise_verdicts)),
                "verdict_reasons": {name: reason for name, reason in zip(self.names, self.reasons) if reason}}


def judge(names: Iterable[str], relative_pct, held=None, findings: Iterable[Finding] = (),
          scatters: Iterable[Scatter] = ()) -> Judgement:
    """The judgement of parameters with noise-based relative errors `relative_pct` (% of |estimate|, None when no
    standard error exists), `held` at a bound (no error), weakened by `findings` and widened by `scatters`."""
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
    noise, judged, reasons = [], [], []
    for name, relative, at_bound in zip(names, relative_pct, held):
        if at_bound:
            noise.append(AT_BOUND), judged.append(AT_BOUND), reasons.append("")
            continue
        first = verdict(float(relative))
        scatter = widened.get(name)
        # A significant scatter widens the error the verdict is judged on, and is a finding in itself.
        now = first if scatter is None else verdict(float(relative) * scatter.ratio)
        because = ([] if scatter is None else [scatter.reason]) + moved.get(name, [])
        if now == WELL_DETERMINED and because:
            now = WEAK
        why = because if now != first else []
        noise.append(first), judged.append(now), reasons.append(", ".join(why))
    return Judgement(names, tuple(noise), tuple(judged), tuple(reasons))


def noise_judgement(names: Iterable[str], uncertainty) -> Judgement:
    """The judgement of a fit with no other check (synthetic data, samples of your own): its noise verdicts."""
    names = tuple(names)
    if uncertainty is None:
        return judge(names, None)
    return judge(names, uncertainty.relative_std_pct, uncertainty.held)


def relative_error_pct(value: float, error: float) -> float:
    """error as % of |value| (0 when the error is 0, inf when the value is 0 and the error is not)."""
    if error == 0:
        return 0.0
    return math.inf if value == 0 or not math.isfinite(value) else 100.0 * abs(error) / abs(value)
