"""The notes a fit of logs carries: how each log was read, timed, differentiated and low-passed, in words."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ..estimation.low_pass import ATTENUATION_DB, FILTER_NAME, FLATNESS
from ..text_safety import shown_name
from .text import ordinal

if TYPE_CHECKING:
    from ..estimation.low_pass import ParallelFilter
    from ..studies.log_fit import LoadedLogs


def log_notes(logs: LoadedLogs) -> tuple[str, ...]:
    """The loaders' notes (ignored columns, timing, estimated derivatives) and the filter's, training log first."""
    notes = list(logs.training.notes)
    if logs.filter is not None:
        notes.append(f"{shown_name(logs.training.path)}: {low_pass_note(logs.filter, logs.result.model.effort.name)}")
    if logs.heldout is not None:
        notes.extend(logs.heldout.notes)
        notes.append(f"{shown_name(logs.heldout.path)}: {heldout_note(logs)}")
    if getattr(logs, "mechanism", None) is not None:
        notes.append(logs.mechanism.note())
    return tuple(notes)


def heldout_note(logs: LoadedLogs) -> str:
    """How the held-out log was predicted: through the training log's pipeline (what it left out, said), or as
    it is when that pipeline cannot take it."""
    effort = logs.result.model.effort.name
    if logs.heldout_pipeline is None:
        return (f"predicted as it is (the training log's low-pass cannot take it), less the ends where its derivatives "
                f"come from the smoothing's end polynomials; the held-out RMSE is of its measured {effort}.")
    left, low_pass = logs.heldout_pipeline
    filtered = low_pass_short_note(low_pass, effort)
    parts = []
    if left is not None and left.pushes.any():
        inside = left.within
        plural = "es" if len(inside) != 1 else ""
        pushed = f"{len(inside)} stretch{plural} where an outside torque acts" if inside else ""
        ends = "the ends" if len(inside) < len(left.excluded) else ""
        parts.append(f"{' and '.join(part for part in (pushed, ends) if part)} ({left.excluded_share:.1%})")
    if left is not None and left.standstill.any():
        parts.append(f"standstill ({left.standstill_share:.1%})")
    left_out = f"; left out, found as the training log's were: {', '.join(parts)}" if parts else ""
    return (f"predicted as the training log was fitted (derivatives over the same span of time, {filtered}"
            f"{left_out}); the held-out RMSE is of the filtered {effort} at its {logs.result.heldout.count} "
            "samples kept, comparable with the training RMSE.")



def low_pass_short_note(low_pass: ParallelFilter, effort: str = "torque") -> str:
    """The low-pass in a few words, for a narrow status line (`effort`: what the fit's effort is)."""
    if not low_pass.active:
        return "not low-passed"
    kept = "" if low_pass.decimation == 1 else f", every {ordinal(low_pass.decimation)} sample kept"
    return f"{effort} and regressor low-passed at {low_pass.cutoff:.3g} Hz{kept}"


def low_pass_note(low_pass: ParallelFilter, effort: str = "torque") -> str:
    """The low-pass and decimation in one sentence for a person (`effort`: what the fit's effort is)."""
    if not low_pass.active:
        return f"{effort} and regressor columns not low-passed: {low_pass.reason}."
    design = low_pass.design
    kept = "" if low_pass.decimation == 1 else f", then every {ordinal(low_pass.decimation)} sample kept"
    return (f"{effort} and every regressor column low-passed alike at {low_pass.cutoff:.3g} Hz (zero-phase FIR, "
            f"{FILTER_NAME}, {design.length} taps, Kaiser beta {design.beta:.3g}: flat within "
            f"{FLATNESS:.1%} below {design.passband_edge:.3g} Hz, {ATTENUATION_DB:g} dB down above "
            f"{design.stopband_edge:.3g} Hz; each end extended by {low_pass.extension} samples, reflected about "
            f"a line fitted to its last half cutoff period, so no sample is lost){kept} ({low_pass.reason}); "
            f"the training RMSE is of the filtered {effort}.")


def exclusion_text(logs: LoadedLogs) -> str | None:
    """What the fit left out of the training log and why, in one paragraph; None when it kept every sample."""
    left = logs.exclusions
    if left is None or left.kept.all() and logs.exclusion.robust:
        return None if left is None or logs.exclusion.robust else "Every sample kept (--no-robust)."
    parts = []
    ends, inside = left.at_ends, left.within
    found = "found by the robust fit" + (" or given with --exclude" if logs.exclusion.by_hand else "") \
        if logs.exclusion.robust else "given with --exclude"
    if inside:
        spans = ", ".join(f"{start:.2f}-{end:.2f} s" for start, end in inside)
        parts.append(f"{len(inside)} stretch{'es' if len(inside) > 1 else ''} where an outside torque acts "
                     f"({found}): {spans}")
    if ends:
        spans = ", ".join(f"{start:.2f}-{end:.2f} s" for start, end in ends)
        parts.append(f"the log's end{'s' if len(ends) > 1 else ''} where the model stops matching ({found}; "
                     f"the smoothing and the low-pass reach past the log there): {spans}")
    if left.pushes.any():
        parts.append(f"together {left.excluded_share:.1%} of the samples")
    if left.standstill.any():
        parts.append(f"standstill, |qd| below {left.speed_threshold:.3g} rad/s, where friction is static "
                     f"({left.standstill_share:.1%})")
    if not logs.exclusion.robust:
        parts.append("no search for outside torques (--no-robust)")
    return "Left out of the fit: " + "; ".join(parts) + "."


def exclusion_object(logs: LoadedLogs) -> dict:
    """The JSON of what the fit left out: `excluded` [[start, end], ...] seconds from the log's start, and why."""
    left = logs.exclusions
    if left is None:
        return {"excluded": [], "exclusions": None}
    return {"excluded": [[start, end] for start, end in left.excluded],
            "exclusions": {"robust": logs.exclusion.robust,
                           "by_hand": [[start, end] for start, end in logs.exclusion.by_hand],
                           "outside_torque_share": left.excluded_share,
                           "standstill_share": left.standstill_share,
                           "standstill_speed_threshold": left.speed_threshold,
                           "flag_level_robust_scales": None if left.level is None or not math.isfinite(left.level)
                           else left.level}}


def left_out_brief(logs: LoadedLogs) -> str | None:
    """What the fit left out in a few words, or None when it kept every sample."""
    left = logs.exclusions
    if left is None or left.kept.all():
        return None
    inside = left.within
    parts = []
    if inside:
        parts.append(f"{len(inside)} stretch{'es' if len(inside) > 1 else ''} of outside torque")
    if len(inside) < len(left.excluded):
        parts.append("the ends")
    pushed = f"{' and '.join(parts)} ({left.excluded_share:.1%})" if parts else None
    still = f"standstill ({left.standstill_share:.0%})" if left.standstill.any() else None
    return "Left out: " + ", ".join(part for part in (pushed, still) if part) + "."


OMITTED_WORDS = {"Fc": "Coulomb friction (sign qd)", "tau0": "a torque bias", "h_s": "an angle offset (g sin q)",
                 "Bq": "quadratic drag (qd |qd|)", "kS": "a static voltage (sign qd)", "V0": "a voltage bias",
                 "kG_s": "an angle offset (sin q)", "kVq": "quadratic drag (qd |qd|)"}
"""How the text names each candidate term of the omitted-terms test (torque terms, and their volt twins)."""
OMITTED_MODELS = {"Fc": "coulomb", "tau0": "bias", "h_s": "angle-offset", "kS": "coulomb", "V0": "bias",
                  "kG_s": "angle-offset"}
"""The model term that adds each candidate, where a model has one (no model has quadratic drag)."""


def omitted_sentence(logs: LoadedLogs, compact: bool = False) -> str | None:
    """What the residuals follow that the model lacks and which estimates it decides, or None when they follow
    none of the candidates (or nothing was tested)."""
    test = logs.omitted
    if test is None or not test.found:
        return None
    named = " and ".join(OMITTED_WORDS[name] for name in test.followed)
    decided = logs.decided_by_omitted
    if compact:
        moved = f": {', '.join(decided)} weak" if decided else ""
        return f"The residuals follow {named}, which the model lacks{moved}."
    model = logs.result.model
    strength = ", ".join(f"|t| {abs(candidate.t):.1f}" for candidate in test.candidates
                         if candidate.name in test.followed)
    terms = [OMITTED_MODELS[name] for name in test.followed if name in OMITTED_MODELS]
    extras = [part for part in model.name.split("+") if part != "plain"]
    suggestion = (f" (--model {'+'.join(dict.fromkeys([*extras, *terms]))}, or compare the ladder with jointid "
                  "compare)") if terms else ""
    if decided:
        moves = {}
        for candidate in test.candidates:
            if candidate.name in test.followed:
                for name, column, move in zip(model.names, model.column_names, candidate.moves):
                    if column in test.decided:
                        moves[name] = max(moves.get(name, 0.0), move)
        effect = (f"; adding it moves {', '.join(f'{name} {move:.1f}' for name, move in moves.items())} standard "
                  f"errors, so {'they are' if len(moves) > 1 else 'it is'} not well determined")
    else:
        effect = "; adding it moves no estimate beyond its errors"
    # An angle offset of a quarter or half turn is most often a log whose angle 0 is not horizontal.
    zero = (" If the log's angle 0 does not point horizontally right, --zero down, up or left reads it as jointid's "
            "q." if any(name in ("h_s", "kG_s") for name in test.followed) else "")
    return (f"The residuals follow {named}, which the model lacks ({strength} against {test.threshold:.1f} for "
            f"{test.effective_count:.0f} independent samples){effect}{suggestion}.{zero}")


def omitted_object(logs: LoadedLogs) -> dict | None:
    """The JSON of the omitted-terms test: each candidate's t and moves, the threshold, what the residuals follow."""
    test = logs.omitted
    if test is None:
        return None
    return {"candidates": {candidate.name: {"t": candidate.t,
                                            "moves_std_errors": dict(zip(test.columns, candidate.moves))}
                           for candidate in test.candidates},
            "threshold": test.threshold, "effective_count": test.effective_count,
            "found": test.found, "followed": list(test.followed), "decides": list(test.decided)}
