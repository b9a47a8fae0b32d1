"""The excitation designer's texts and JSON: the design beside rich motion, the limits, and the verdict.

`jointid design` prints `design_text`; the explorer's Design view shows the
same table, limits and verdict (`design_table`, `limits_table`, `design_verdict`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..options import CRITERIA, LIMIT_RANGES, LIMIT_SYMBOLS
from ..studies.design import ACTIVE_SHARE, CHECK_GRID, DesignResult
from ..synthetic.fourier import motion_document
from ..synthetic.motions import DURATION, TRAINING_MOTIONS
from .text import capitalise, format_number, join_words, text_table

NOT_APPLICABLE = "-"
"""A relative error of a parameter the true joint does not have (its value is 0)."""

DESIGN_INTRO = (
    "Which motion reveals the parameters best, and how much better is it than rich motion? The designer "
    "optimises a 3-harmonic Fourier series over 8 s within these limits (rich motion's envelope to start) "
    "for the criterion: D-optimal maximises the information, A-optimal minimises the summed relative "
    "variances, and cond only balances the columns: the counter-example, whose condition number reaches 1 "
    "while some standard errors get worse than rich motion's."
)
"""What the design view is for, shown until a design runs."""

COND_CAVEAT = ("A condition number near 1 says the scaled columns are balanced, not that the motion is informative: "
               "a small, well-balanced motion carries little information.")
"""Why the `cond` criterion is the counter-example."""


def significant(value: float, digits: int = 4) -> str:
    """A number with `digits` significant digits, e.g. 0.01128 or 2.779e-05."""
    return "inf" if not math.isfinite(value) else f"{value:.{digits}g}"


def percent(value: float) -> str:
    """'1.41 %', or NOT_APPLICABLE for NaN."""
    return NOT_APPLICABLE if math.isnan(value) else f"{value:.2f} %"


def design_heading(result: DesignResult) -> str:
    """Two lines: the criterion, then the motion's form and the experiment it is for."""
    spec, settings = result.spec, result.spec.experiment
    return (f"Designed motion, {CRITERIA[spec.criterion]}\n"
            f"{spec.harmonics} harmonics over T = {spec.period:g} s for model {settings.model}, "
            f"{settings.samples} samples, noise {format_number(settings.noise, 2)} N m; "
            f"best of {spec.starts} starts from seed {spec.seed} ({result.converged} met the limits)")


def design_table(result: DesignResult) -> str:
    """Expected standard error and relative % of every parameter under the design and under rich motion,
    their ratio, then both condition numbers."""
    header = ["parameter", "designed SE", "rel", "rich SE", "rel", "ratio"]
    rows = []
    design, rich = result.design, result.rich
    for index, parameter in enumerate(result.model.parameters):
        if design.noise_bound_std_error is None or rich.noise_bound_std_error is None:
            break
        mine, theirs = float(design.noise_bound_std_error[index]), float(rich.noise_bound_std_error[index])
        ratio = mine / theirs if theirs > 0 else math.nan
        rows.append([parameter.symbol_with_unit, significant(mine), percent(float(design.relative_std_pct[index])),
                     significant(theirs), percent(float(rich.relative_std_pct[index])),
                     NOT_APPLICABLE if math.isnan(ratio) else f"{ratio:.2f}"])
    rows.append(["condition number", f"{design.condition_number:.3f}", "", f"{rich.condition_number:.3f}", "",
                 ""])
    return text_table(header, rows)


def limits_table(result: DesignResult) -> str:
    """Each limit, the design's peak on the check grid, the margin, and 'active' where the peak reaches it."""
    header = ["limit", "peak", "limit", "margin", ""]
    rows = [[f"{LIMIT_SYMBOLS[check.name]} ({LIMIT_RANGES[check.name][1]})", f"{check.peak:.4f}",
             f"{check.limit:g}", f"{check.margin:.4f}", "active" if check.active else ""]
            for check in result.checks]
    return text_table(header, rows)


def active_sentence(result: DesignResult) -> str:
    """Which limits shape the design, e.g. 'Active limit: |qdd| <= 3 rad/s² (margin 0.0000 on 4000 points).'"""
    active = [check for check in result.checks if check.active]
    if not active:
        return (f"No limit is active: every peak stays more than {100 * ACTIVE_SHARE:g} % below its limit "
                f"on {CHECK_GRID} points of one period.")
    names = [f"{LIMIT_SYMBOLS[c.name]} <= {c.limit:g} {LIMIT_RANGES[c.name][1]}" for c in active]
    noun = "limit" if len(active) == 1 else "limits"
    return f"Active {noun}: {join_words(names)}; every limit holds on {CHECK_GRID} points of one period."


def design_verdict(result: DesignResult) -> str:
    """How the design compares with rich motion, naming any parameter it determines worse (and, for cond, why)."""
    names = result.model.names
    design, rich = result.design, result.rich
    if design.noise_bound_std_error is None:
        return "The design does not determine every parameter."
    worse = result.worse_than_rich
    if worse:
        parts = []
        for name in worse:
            index = names.index(name)
            mine, theirs = design.noise_bound_std_error[index], rich.noise_bound_std_error[index]
            parts.append(f"{name} (SE {significant(mine)} against {significant(theirs)}, "
                         f"{100 * mine / theirs:.0f} % of rich motion's)")
        text = f"Worse than rich motion: {join_words(parts)}."
        if result.spec.criterion == "cond":
            text += (f" The condition number is {design.condition_number:.3f} against rich motion's "
                     f"{rich.condition_number:.3f}. {COND_CAVEAT}")
        return text
    ratios = design.noise_bound_std_error / rich.noise_bound_std_error
    best = int(ratios.argmin())
    return (f"Every parameter is determined at least as well as under rich motion; {names[best]}'s standard error "
            f"is {100 * ratios[best]:.0f} % of rich motion's.")


def design_text(result: DesignResult) -> str:
    """`jointid design`'s text: heading, the comparison table, the limits, the verdict."""
    return "\n\n".join([design_heading(result), design_table(result),
                        f"Limits on {CHECK_GRID} points of one period:\n{limits_table(result)}\n"
                        f"{active_sentence(result)}",
                        capitalise(design_verdict(result))])


def _finite(value) -> float | None:
    """A float for JSON, or None for NaN and infinities."""
    value = float(value)
    return value if math.isfinite(value) else None


def design_document(result: DesignResult) -> dict:
    """`jointid design --json`: the motion file's object, both motions' precision, the limits and the verdict."""
    def precision(of):
        if of.noise_bound_std_error is None:
            return {"std_error": None, "relative_pct": None, "condition_number": _finite(of.condition_number)}
        return {"std_error": dict(zip(result.model.names, map(_finite, of.noise_bound_std_error))),
                "relative_pct": dict(zip(result.model.names, map(_finite, of.relative_std_pct))),
                "condition_number": _finite(of.condition_number)}

    return {
        "motion": motion_document(result.motion),
        "design": precision(result.design),
        "rich": precision(result.rich),
        "limits": {check.name: {"limit": check.limit, "peak": check.peak, "margin": check.margin,
                                "active": check.active} for check in result.checks},
        "worse_than_rich": list(result.worse_than_rich),
        "starts_meeting_limits": result.converged,
        "verdict": design_verdict(result),
    }


CHART_POINTS = 241
"""Points per line of the q(t) chart over the 8 s window: smooth at any terminal width."""


@dataclass(frozen=True, eq=False)
class LinesData:
    """Lines y(x) to draw on one chart: x (M,), each line's label and values (M,), with axis titles."""

    titles: tuple[str, ...]
    """Heading, longest first; the widest that fits is shown."""
    x: np.ndarray
    lines: tuple[tuple[str, np.ndarray], ...]
    x_label: str
    y_label: str


def design_chart(result: DesignResult | None) -> LinesData:
    """q(t) of the designed motion against rich motion's over the 8 s training window (rich alone before a design)."""
    t = np.linspace(0.0, DURATION, CHART_POINTS)
    rich = ("rich", TRAINING_MOTIONS["rich"].states(t).q)
    if result is None:
        return LinesData(titles=("Angle q (rad) of rich motion, the one to beat", "q(t) of rich motion"), x=t,
                         lines=(rich,), x_label="t (s)", y_label="q (rad)")
    return LinesData(
        titles=("Angle q (rad) over the training window: designed motion against rich motion",
                "q(t): designed against rich", "q(t)"),
        x=t,
        lines=(("designed", result.motion.states(t).q), rich),
        x_label="t (s)",
        y_label="q (rad)",
    )
