"""CSV logs for the tests: the lesson's motions in closed form as CSV rows, and a corpus of broken files."""

from __future__ import annotations

import numpy as np

from jointid.model.terms import TRUE_PARAMETERS, G
from jointid.synthetic.motions import ALL_MOTIONS


def truth_states(motion, samples, duration=8.0):
    """Times and exact states, computed here from the motion's sine terms (not via Motion.states)."""
    t = np.linspace(0.0, duration, samples)
    q, qd, qdd = np.zeros(samples), np.zeros(samples), np.zeros(samples)
    for term in ALL_MOTIONS[motion].terms:
        angle = term.frequency * t + term.phase
        q += term.amplitude * np.sin(angle)
        qd += term.amplitude * term.frequency * np.cos(angle)
        qdd -= term.amplitude * term.frequency**2 * np.sin(angle)
    inertia, mass_moment, damping = TRUE_PARAMETERS
    tau = inertia * qdd + mass_moment * G * np.cos(q) + damping * qd
    return t, q, qd, qdd, tau


def rows_of(*columns):
    """CSV lines of float columns at 17 significant digits (what simulate writes)."""
    return [",".join(f"{v:.17g}" for v in row) for row in zip(*columns)]


def good_rows(count=30, step=0.01):
    _, q, qd, qdd, tau = truth_states("rich", count)
    return rows_of(np.arange(count) * step, q, qd, qdd, tau)


HEADER = "t,q,qd,qdd,tau"

CORPUS = {
    "empty.csv": "",
    "blank.csv": "\n\n   \n",
    "comments_only.csv": "# nothing here\n",
    "header_only.csv": HEADER + "\n",
    "header_and_comments.csv": f"# a\n{HEADER}\n# b\n\n",
    "no_q.csv": "t,qd,qdd,tau\n0,0,0,1\n",
    "no_tau.csv": "t,q,qd,qdd\n0,0,0,0\n",
    "no_t_no_qd.csv": "q,qdd,tau\n0,0,1\n",
    "duplicate.csv": "t,q,qd,qdd,tau,TAU\n0,0,0,0,1,1\n",
    "word.csv": "\n".join([HEADER, *good_rows(5), "0.05,abc,0,0,1"]) + "\n",
    "empty_cell.csv": "\n".join([HEADER, *good_rows(5), "0.05,,0,0,1"]) + "\n",
    "nan.csv": "\n".join([HEADER, *good_rows(5), "0.05,0,nan,0,1"]) + "\n",
    "inf.csv": "\n".join([HEADER, *good_rows(5), "0.05,0,0,0,inf"]) + "\n",
    "minus_inf.csv": "\n".join([HEADER, *good_rows(5), "0.05,0,0,-inf,1"]) + "\n",
    "short_row.csv": "\n".join([HEADER, *good_rows(5), "0.05,0,0,1"]) + "\n",
    "long_row.csv": "\n".join([HEADER, *good_rows(5), "0.05,0,0,0,1,7"]) + "\n",
    "time_repeats.csv": "\n".join([HEADER, *good_rows(5), *rows_of([4 * 0.01], [1], [0], [0], [1])]) + "\n",
    "time_backwards.csv": "\n".join([HEADER, *good_rows(5), "0.01,0,0,0,1"]) + "\n",
    "uneven_time.csv": "t,q,tau\n" + "".join(f"{i * 0.01 + (0.05 if i >= 250 else 0)!r},0,1\n" for i in range(400)),
    "two_rows.csv": "\n".join([HEADER, *good_rows(2)]) + "\n",
    "binary.csv": "\x00\x01\x02,\xff\n\x00,\x00\n",
    "mid_line_comment.csv": "\n".join([HEADER, *good_rows(5), "0.05,0,0,0,1 # note"]) + "\n",
    "semicolons.csv": HEADER.replace(",", ";") + "\n0;0;0;0;1\n",
}
