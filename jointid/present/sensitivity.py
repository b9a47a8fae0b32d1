"""The sensitivity check in words: which settings were varied, how far each parameter moved, and the warning."""

from __future__ import annotations

SETTINGS_DECIDE = "Your derivative settings decide this estimate"
"""The warning both faces print when the sensitivity check flags a parameter."""


def sensitivity_summary(check, effort: str = "torque") -> str:
    """One sentence: which settings were varied and each parameter's largest move (sensitivity.SensitivityCheck;
    `effort`: what the fit's effort is)."""
    tried = [name for name in ("window", "cutoff") if any(v.setting == name for v in check.variants)]
    if not tried:
        return "Sensitivity check: nothing to vary (no derivative was estimated and nothing was low-passed)."
    base = check.base
    settings = {"window": f"window {base.window} samples", "cutoff": f"cutoff {base.cutoff:.3g} Hz"
                if base.cutoff is not None else ""}
    varied = " and ".join(settings[name] for name in tried)
    if check.exact:
        moves = ", ".join(f"{name} {move:.1g}" for name, move in zip(check.names, check.relative_moves))
        return (f"Sensitivity check ({varied}, each halved and doubled): the {effort}s are fitted exactly "
                f"(noise-free data), so the standard errors are rounding and no move is judged by them; "
                f"largest relative moves {moves}.")
    moves = ", ".join(f"{name} {f'{check.worst(j)[1]:.2f}'}" for j, name in enumerate(check.names))
    return f"Sensitivity check ({varied}, each halved and doubled): largest moves {moves} noise standard errors."


def sensitivity_warning(check, compact: bool = False) -> str | None:
    """'Your derivative settings decide this estimate: ...' naming each flagged parameter, or None.

    Compact: each parameter with its largest move only, for a narrow status line.
    """
    if not check.flagged:
        return None
    moves: dict[str, list[str]] = {}  # by the setting that moves them most, so each setting is named once
    for j, name in enumerate(check.names):
        if check.flags[j]:
            variant, move = check.worst(j)
            moves.setdefault("" if compact else f"with the {variant.label}, ", []).append(
                f"{name} {move:.{1 if compact else 2}f}")
    parts = []
    for setting, named in moves.items():
        first, *rest = named
        name, move = first.split(" ")
        parts.append(f"{setting}{name} moves {move} noise standard errors" + "".join(f", {other}" for other in rest))
    return f"{SETTINGS_DECIDE}: " + "; ".join(parts) + "."


def sensitivity_text(check, effort: str = "torque") -> str:
    """The sensitivity check's summary line, then its warning when a parameter is flagged."""
    warning = sensitivity_warning(check)
    return sensitivity_summary(check, effort) + ("" if warning is None else "\n" + warning)
