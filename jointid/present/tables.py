"""The seed sweep's statistics and the cross-excitation matrix, as sentences and aligned tables."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..options import VALIDATION_SAMPLES
from .text import UNAVAILABLE, format_number, settings_header, text_table

if TYPE_CHECKING:
    from ..studies.cross_excitation import CrossExcitationTable
    from ..studies.sweep import SweepResult

SWEEP_ROW_LABELS = ("true value", "mean", "std (empirical)", "std (expected)", "p5", "p50 (median)", "p95",
                    "sign check fails")
"""Rows of the sweep's statistics table, one column per parameter and RMSE."""
RMSE_COLUMNS = {"training_rmse": "train RMSE", "heldout_rmse": "held RMSE"}
"""The sweep table's RMSE columns and their headings."""

TRAINING_MARK = "*"
"""Marks a matrix entry evaluated on the motion its row was fitted on."""
MATRIX_COLUMN_TITLES = {"rich": "rich motion", "slow": "slow motion", "test": "validation"}
"""The matrix's column heading per prediction motion."""
MATRIX_EXPLANATION = (
    "Each row fits one motion at this noise, sample count and seed; each column is the torque "
    "RMSE (N m) of its predictions against a motion's noiseless truth. Only the unmarked entries "
    "test motions the fit never saw."
)
"""What the matrix shows, one paragraph."""


def sweep_heading(sweep: SweepResult) -> str:
    """e.g. 'Slow motion, noise 0.20 N m, 24 samples, 1000 seeds 7..1006'."""
    if sweep.seed_count == 1:
        return settings_header(sweep.settings, seeds=f"1 seed ({sweep.settings.seed})")
    return settings_header(sweep.settings, seeds=f"{sweep.seed_count} seeds {sweep.settings.seed}..{int(sweep.seeds[-1])}")


def sweep_message(sweep: SweepResult) -> str:
    """One plain paragraph on what the sweep shows."""
    head = sweep_heading(sweep)
    if not sweep.is_full_rank:
        return (
            f"{head}: rank {sweep.rank} of {sweep.model.size} for every seed (noise changes only "
            "the torques), so no seed gives a unique fit and the sweep has no estimates."
        )
    failing = [
        f"{sweep.model.parameter(name).label} fails its sign check in {100 * fraction:.1f} % of seeds"
        for name, fraction in sweep.sign_failure_fractions.items()
        if fraction > 0
    ]
    verdict = "; ".join(failing) if failing else "every seed passes the sign checks"
    if sweep.constraint_active_fraction is not None:
        verdict += (f" (fitted subject to the sign rules: a bound is active in "
                    f"{100 * sweep.constraint_active_fraction:.1f} % of seeds)")
    return f"{head}: {verdict}."


ROUNDING = 1e-12
"""Sweep statistics smaller than this (in the lesson's units, N m and its parameters' own) are rounding."""


def sweep_table(sweep: SweepResult) -> str:
    """The statistics table (rows: statistics; columns: parameters and both RMSEs), or '' without estimates."""
    if not sweep.is_full_rank:
        return ""
    model = sweep.model
    names = (*model.names, *RMSE_COLUMNS)
    stats = sweep.statistics
    blank_rmse = ["", ""]
    expected = sweep.noise_bound_std_error if sweep.noise_bound_std_error is not None else (None,) * model.size
    fractions = sweep.sign_failure_fractions

    def cell(value) -> str:
        # The sweep fits the lesson's synthetic joint (torques of about 1 N m): below ROUNDING a statistic is the
        # rounding of exact fits, read as the zero it is rather than as 1.973139e-31 among fixed decimals.
        return "-" if value is None else format_number(0.0 if abs(value) < ROUNDING else value)

    rows = [
        [cell(value) for value in sweep.settings.true_joint.values_for(model)] + blank_rmse,
        [cell(stats[name].mean) for name in names],
        [cell(stats[name].std) for name in names],
        [cell(value) for value in expected] + blank_rmse,
        [cell(stats[name].p5) for name in names],
        [cell(stats[name].p50) for name in names],
        [cell(stats[name].p95) for name in names],
        [f"{100 * fractions[name]:.1f} %" if model.parameter(name).sign else "-" for name in model.names] + blank_rmse,
    ]
    header = ["statistic", *model.names, *RMSE_COLUMNS.values()]
    return text_table(header, [[label, *row] for label, row in zip(SWEEP_ROW_LABELS, rows)])


def sign_failure_line(sweep: SweepResult) -> str:
    """How often any sign check fails, naming the requirements ('' without estimates)."""
    if sweep.sign_failure_fraction is None:
        return ""
    checks = ", ".join(parameter.requirement for parameter in sweep.model.parameters if parameter.requirement)
    return f"Seeds failing a sign check ({checks}): {100 * sweep.sign_failure_fraction:.1f} %."


def sweep_summary(sweep: SweepResult) -> str:
    """The sweep's message, then how often a sign check fails."""
    return " ".join(part for part in (sweep_message(sweep), sign_failure_line(sweep)) if part)


def sweep_text(sweep: SweepResult) -> str:
    """`jointid sweep`'s text: the summary, then the statistics table."""
    table = sweep_table(sweep)
    return sweep_summary(sweep) + (f"\n\n{table}" if table else "")


def matrix_title(table: CrossExcitationTable) -> str:
    """The matrix's heading with the settings every row shares."""
    return (f"Cross-excitation: prediction RMSE (N m); "
            f"{settings_header(table.settings, motion=False)}")


def matrix_cell(rmse: float | None, is_training_data: bool) -> str:
    """An entry: the RMSE, marked when it is training data, or 'unavailable'."""
    if rmse is None:
        return UNAVAILABLE
    return format_number(rmse) + (f" {TRAINING_MARK}" if is_training_data else "  ")


def matrix_table(table: CrossExcitationTable) -> str:
    """The RMSE table as aligned text, one row per training motion."""
    header = ["fitted on", *(MATRIX_COLUMN_TITLES[m] for m in table.prediction_motions)]
    rows = [
        [f"{row.label.lower()} (rank {row.fit.rank})",
         *(matrix_cell(cell.rmse, cell.is_training_data) for cell in row.cells)]
        for row in table.rows
    ]
    return text_table(header, rows)


def matrix_notes(table: CrossExcitationTable) -> str:
    """The legend: what the mark means, where each column's states come from, unavailable rows."""
    missing = [row.label.lower() for row in table.rows if not row.available]
    lines = [
        f"{TRAINING_MARK} training data: the fit saw these states (with noisy torques); not a held-out test.",
        f"Rich and slow columns: {table.settings.samples} samples at the training instants; "
        f"validation: its {VALIDATION_SAMPLES} states.",
    ]
    if missing:
        size = table.settings.joint_model.size
        lines.append(f"{', '.join(missing).capitalize()}: rank below {size}, no unique fit, so no predictions.")
    return "\n".join(lines)


def matrix_text(table: CrossExcitationTable) -> str:
    """`jointid matrix`'s text: title, table, legend and explanation."""
    return "\n".join((matrix_title(table), matrix_table(table), matrix_notes(table), MATRIX_EXPLANATION))
