"""A corpus of odd log files, made here: each is one clear line (status 2, LogError) or a correct fit, never a hang.

Every file goes through `jointid fit --csv FILE --json` (in-process) and
through the explorer's loader (`logfit.load_request`), each in a thread with a
deadline. A fit is checked against an independent numpy reference: lstsq on a
hand-built [qdd, 9.81 cos q, qd] regressor of the numbers written (with qd and
qdd from scipy's Savitzky-Golay filter when the log has only t, q, tau).
"""

from __future__ import annotations

import gzip
import json
import math
import os
import subprocess
import sys
import threading
import warnings
import zipfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from scipy.signal import savgol_filter

from jointid.cli import main
from jointid.estimation.exclusion import ExclusionRequest
from jointid.estimation.low_pass import FilterRequest
from jointid.logs.table import LogError
from jointid.studies.log_fit import LoadRequest, load_request

G = 9.81
COLUMNS = ("t", "q", "qd", "qdd", "tau")
DEADLINE = 60.0
"""Seconds any one file may take before the test calls it a hang."""
CHECKOUT = Path(__file__).resolve().parents[3]


def rich(count: int = 40, duration: float = 8.0, start: float = 0.0) -> dict[str, np.ndarray]:
    """The rich motion written out by hand, with a small torque disturbance so that no fit is exact."""
    t = start + np.linspace(0.0, duration, count)
    q = 0.7 * np.sin(1.3 * t) + 0.25 * np.sin(2.7 * t)
    qd = 0.7 * 1.3 * np.cos(1.3 * t) + 0.25 * 2.7 * np.cos(2.7 * t)
    qdd = -0.7 * 1.69 * np.sin(1.3 * t) - 0.25 * 7.29 * np.sin(2.7 * t)
    tau = 0.8 * qdd + 0.4 * G * np.cos(q) + 0.15 * qd + 0.01 * np.sin(17.0 * t)
    return {"t": t, "q": q, "qd": qd, "qdd": qdd, "tau": tau}


def scaled(data: dict, factor: float, names=("qd", "qdd", "tau")) -> dict:
    """The columns `names` multiplied by factor (the rest as they were)."""
    return {name: values * factor if name in names else values for name, values in data.items()}


def text_of(data: dict, names=COLUMNS, *, sep=",", end="\n", cell=lambda v: repr(float(v)), header=None,
            extra: Callable[[int], str] | None = None) -> str:
    """CSV text: a header, then one line per sample (cells exactly float-round-tripped by default)."""
    head = header if header is not None else sep.join(names)
    lines = [head]
    for i in range(len(data[names[0]])):
        cells = [cell(data[name][i]) for name in names]
        if extra is not None:
            cells.append(extra(i))
        lines.append(sep.join(cells))
    return end.join(lines) + end


@dataclass
class Case:
    """One corpus file: how to make it, and what must come of it."""

    make: Callable[[Path], dict | None]
    """Writes the file at the given path; returns the columns a fit must match, or None."""
    fits: bool
    """True: a correct fit; False: one clear line naming the file."""
    words: str = ""
    """For errors: words the message must contain."""
    derivatives: tuple[int, int] | None = None
    """(window, order) when qd/qdd are estimated, for the reference filter."""


def writes(text, encoding="utf-8", data=None):
    """A maker that writes text (or bytes) and returns `data`."""

    def make(path: Path):
        path.write_bytes(text if isinstance(text, bytes) else text.encode(encoding))
        return data

    return make


def fit_case(data: dict, encoding="utf-8", **layout) -> Case:
    """A file of `data` laid out by text_of(**layout) that must fit."""
    return Case(writes(text_of(data, **layout), encoding, data), True)


def error_case(text, words="", encoding="utf-8") -> Case:
    return Case(writes(text, encoding), False, words)


HEADER = ",".join(COLUMNS)
BASE = rich()
PLAIN = text_of(BASE)
ROWS = PLAIN.splitlines()[1:]


def with_row(row: str, at: int = 5) -> str:
    """PLAIN with data row `at` replaced by `row`."""
    rows = list(ROWS)
    rows[at] = row
    return "\n".join([HEADER, *rows]) + "\n"


def angle_only(count=1001, step=0.001, start=0.0) -> dict:
    """t, q, tau at 1 kHz (derivatives to be estimated), t = start + i*step."""
    data = rich(count, (count - 1) * step, start)
    data["t"] = start + np.arange(count) * step
    return data


def symlink_to(target: str | Callable[[Path], str]) -> Callable[[Path], None]:
    def make(path: Path):
        if target in ("/dev/zero", "/dev/null") and not os.path.exists(target):
            pytest.skip(f"no {target} here")
        os.symlink(target(path) if callable(target) else target, path)

    return make


def fifo(path: Path):
    if not hasattr(os, "mkfifo"):
        pytest.skip("no named pipes here")
    os.mkfifo(path)


def directory(path: Path):
    path.mkdir()


def good_target(path: Path) -> str:
    target = path.with_name("target.csv")
    target.write_text(PLAIN)
    return str(target)


def long_single_line(path: Path):
    with open(path, "wb") as handle:  # 50 MB without a newline, written in 1 MB pieces
        piece = b"1," * (1 << 19)
        for _ in range(50):
            handle.write(piece)


def long_line_in_data(path: Path):
    path.write_bytes(("\n".join(["t,q,qd,qdd,tau", *ROWS[:10]]) + "\n").encode() + b"5" * (3 << 20) + b"\n")


def many_rows() -> dict:
    return rich(60_000, 60.0)



CASES: dict[str, Case] = {
    # Encodings, byte order marks, line ends.
    "plain.csv": fit_case(BASE),
    "utf8_bom.csv": Case(writes(b"\xef\xbb\xbf" + PLAIN.encode(), data=BASE), True),
    "crlf.csv": fit_case(BASE, end="\r\n"),
    "bom_crlf.csv": Case(writes(b"\xef\xbb\xbf" + text_of(BASE, end="\r\n").encode(), data=BASE), True),
    "no_final_newline.csv": Case(writes(PLAIN.rstrip("\n"), data=BASE), True),
    "latin1_extra_column.csv": fit_case(BASE, "latin-1", header=HEADER + ",température", extra=lambda i: "é"),
    "utf8_unicode_extra_column.csv": fit_case(BASE, header=HEADER + ",τ_measured", extra=lambda i: "ü"),
    "cp1252_comment.csv": Case(writes(b"# \x93smart quotes\x94\n" + PLAIN.encode(), data=BASE), True),
    "cr_only.csv": error_case(text_of(BASE, end="\r"), "missing required column"),
    "utf16le_bom.csv": error_case(PLAIN, "NUL bytes", "utf-16"),
    "utf16be_bom.csv": error_case(b"\xfe\xff" + PLAIN.encode("utf-16-be"), "NUL bytes"),
    "utf16le_no_bom.csv": error_case(PLAIN, "NUL bytes", "utf-16-le"),
    "utf32.csv": error_case(PLAIN, "NUL bytes", "utf-32"),
    # Separators, quoting, spacing, header spellings.
    "tab_separated.csv": error_case(text_of(BASE, sep="\t"), "missing required column"),
    "semicolons.csv": error_case(text_of(BASE, sep=";"), "missing required column"),
    "semicolons_decimal_commas.csv": error_case(text_of(BASE, sep=";", cell=lambda v: repr(float(v)).replace(".", ","))),
    "quoted_header.csv": fit_case(BASE, header='"t","q","qd","qdd","tau"'),
    "quoted_cells.csv": error_case(text_of(BASE, cell=lambda v: f'"{float(v)!r}"'), "is not a number"),
    "spaces_around_cells.csv": fit_case(BASE, sep=" , ", header=" t , q , qd , qdd , tau "),
    "uppercase_header.csv": fit_case(BASE, header="T,Q,QD,QDD,TAU"),
    "shuffled_columns.csv": fit_case(BASE, names=("tau", "qdd", "q", "t", "qd")),
    "text_column.csv": fit_case(BASE, header=HEADER + ",note", extra=lambda i: f"sample {i} fine"),
    "many_columns.csv": fit_case(BASE, header=HEADER + "".join(f",x{j}" for j in range(2000)),
                                 extra=lambda i: ",".join(["1.5"] * 2000)),
    "duplicated_ignored_columns.csv": fit_case(BASE, header=HEADER + ",note,note", extra=lambda i: "a,b"),
    "trailing_commas_everywhere.csv": fit_case(BASE, header=HEADER + ",", extra=lambda i: ""),
    "trailing_commas_in_rows_only.csv": error_case(text_of(BASE, extra=lambda i: ""), "cells but the header has"),
    "duplicate_q.csv": error_case("t,q,q,qd,qdd,tau\n0,0,0,0,0,1\n", "appears twice"),
    "duplicate_tau_case.csv": error_case("t,q,qd,qdd,tau,TAU\n0,0,0,0,1,1\n", "appears twice"),
    "unicode_tau_header.csv": error_case(text_of(BASE, header="t,q,qd,qdd,τ"), "missing required column 'tau'"),
    "missing_tau.csv": error_case(text_of(BASE, names=("t", "q", "qd", "qdd")), "missing required column 'tau'"),
    "missing_q.csv": error_case(text_of(BASE, names=("t", "qd", "qdd", "tau")), "missing required column 'q'"),
    "no_t_no_qd.csv": error_case(text_of(BASE, names=("q", "qdd", "tau")), "missing column 't'"),
    "no_time_column.csv": fit_case(BASE, names=("q", "qd", "qdd", "tau")),
    # Comments, blank lines, empty files.
    "empty.csv": error_case("", "is empty"),
    "blank_only.csv": error_case("\n \n\t\n\r\n", "is empty"),
    "comment_only.csv": error_case("# nothing\n   # at all\n", "is empty"),
    "header_only.csv": error_case(HEADER + "\n", "no data rows"),
    "header_and_comments_only.csv": error_case(f"# a\n{HEADER}\n# b\n\n# c\n", "no data rows"),
    "comments_interleaved.csv": Case(writes("# start\n" + "\n".join(
        [HEADER, *(f"{row}\n# after row {i}" for i, row in enumerate(ROWS))]) + "\n", data=BASE), True),
    "blank_lines_interleaved.csv": Case(writes("\n\n" + HEADER + "\n\n" + "\n\n   \n".join(ROWS) + "\n\n", data=BASE), True),
    "indented_comments.csv": Case(writes("   # one\n\t# two\n" + PLAIN + "  # end\n", data=BASE), True),
    "mid_line_comment.csv": error_case(with_row(ROWS[5] + " # note"), "is not a number"),
    # Row counts and degenerate motion.
    "one_row.csv": error_case("\n".join([HEADER, *ROWS[:1]]) + "\n", "fitting 3 parameters needs at least 3"),
    "two_rows.csv": error_case("\n".join([HEADER, *ROWS[:2]]) + "\n", "fitting 3 parameters needs at least 3"),
    "three_rows.csv": fit_case({k: v[[0, 13, 27]] for k, v in BASE.items()}),
    "constant_rows.csv": fit_case({**{k: np.full(10, v[7]) for k, v in BASE.items()}, "t": np.arange(10.0)}),
    "all_zero.csv": fit_case({k: np.zeros(10) if k != "t" else np.arange(10.0) for k in COLUMNS}),
    "holds.csv": fit_case({"t": np.arange(12.0), "q": np.zeros(12), "qd": np.zeros(12), "qdd": np.zeros(12),
                           "tau": np.full(12, 0.4 * G) + 0.001 * np.sin(np.arange(12.0))}),
    "many_rows.csv": Case(lambda path: (path.write_text(text_of(many_rows())), many_rows())[1], True),
    # Number spellings.
    "plus_signs_and_negative_zero.csv": fit_case(BASE, cell=lambda v: "-0.0" if v == 0 else f"{float(v):+.17g}"),
    "exponent_forms.csv": fit_case(BASE, cell=lambda v: f"{float(v):.17e}"),
    "upper_exponents_leading_zeros.csv": fit_case(BASE, cell=lambda v: "000" + f"{abs(float(v)):.17E}"
                                                  if v >= 0 else f"-000{abs(float(v)):.17E}"),
    "fullwidth_digits.csv": error_case(with_row("０,１,２,３,４"), "is not a number"),
    "arabic_digits.csv": error_case(with_row("٠,١,٢,٣,٤"), "is not a number"),
    "underscore_digits.csv": error_case(with_row("0,1_000,0,0,1"), "is not a number"),
    "hex_float.csv": error_case(with_row("0,0x1p3,0,0,1"), "is not a number"),
    "true_false.csv": error_case(with_row("0,TRUE,false,0,1"), "is not a number"),
    "nan_cell.csv": error_case(with_row("0,0,nan,0,1"), "NaN is not a measurement"),
    "inf_cell.csv": error_case(with_row("0,0,0,0,-inf"), "infinity is not a measurement"),
    "overflowing_literal.csv": error_case(with_row("0,0,1e999,0,1"), "infinity is not a measurement"),
    "empty_cell.csv": error_case(with_row("0,,0,0,1"), "is empty"),
    "short_row.csv": error_case(with_row("0,0,0,1"), "cells but the header has"),
    "long_row.csv": error_case(with_row("0,0,0,0,1,2"), "cells but the header has"),
    "nul_in_data.csv": error_case(with_row("0,\x001,0,0,1"), "is not a number"),
    # Magnitudes: squares that overflow or underflow, denormals.
    "scaled_1e154.csv": fit_case(scaled(BASE, 1e154)),
    "scaled_1e200.csv": fit_case(scaled(BASE, 1e200)),
    "scaled_1e300.csv": fit_case(scaled(BASE, 1e300)),
    "scaled_1e-170.csv": fit_case(scaled(BASE, 1e-170)),
    "scaled_1e-300.csv": fit_case(scaled(BASE, 1e-300)),
    "denormal_columns.csv": fit_case(scaled(BASE, 1e-310)),
    "one_denormal_cell.csv": fit_case({**BASE, "qd": np.where(np.arange(40) == 5, 5e-324, BASE["qd"])}),
    "negative_values_only_torque.csv": fit_case({**BASE, "tau": BASE["tau"] - 100.0}),
    "overflowing_estimate.csv": error_case(text_of({**scaled(BASE, 1e300, ("tau",)), "qdd": BASE["qdd"] * 1e-300}),
                                           "overflows double precision"),
    # Time: negative, jittery, huge, decreasing, repeated, tiny steps.
    "negative_time.csv": fit_case(rich(start=-8.0)),
    "nonuniform_time_with_derivatives.csv": fit_case({**BASE, "t": BASE["t"] + 0.05 * np.sin(np.arange(40.0)) ** 2}),
    "huge_time_values.csv": fit_case({**BASE, "t": 1e15 + np.arange(40.0)}),
    "tiny_time_steps_with_derivatives.csv": fit_case({**BASE, "t": np.arange(40.0) * 1e-300}),
    "decreasing_time.csv": error_case(text_of({k: v[::-1] for k, v in BASE.items()}), "time runs backwards"),
    "repeated_time.csv": error_case(text_of({**BASE, "t": np.floor(BASE["t"])}),
                                   "repeats with other values"),
    "angle_only.csv": Case(writes(text_of(angle_only(), names=("t", "q", "tau")), data=angle_only()), True,
                           derivatives=(201, 4)),
    "angle_only_bom_crlf.csv": Case(writes(b"\xef\xbb\xbf" + text_of(angle_only(), names=("t", "q", "tau"),
                                                                       end="\r\n").encode(), data=angle_only()),
                                    True, derivatives=(201, 4)),
    "angle_and_velocity.csv": Case(writes(text_of(angle_only(), names=("t", "q", "qd", "tau")), data=angle_only()),
                                   True, derivatives=(201, 4)),
    "angle_only_negative_time.csv": Case(writes(text_of(angle_only(start=-3.0), names=("t", "q", "tau")),
                                                data=angle_only(start=-3.0)), True, derivatives=(201, 4)),
    "angle_only_gap.csv": error_case(text_of({k: np.delete(v, range(500, 506)) for k, v in angle_only().items()},
                                             names=("t", "q", "tau")), "gap in time"),
    "angle_only_too_short.csv": error_case(text_of(angle_only(4), names=("t", "q", "tau")), "a window of 5"),
    # Not text, not one sample per line, not a regular file.
    "gzip_bytes.csv": error_case(gzip.compress(PLAIN.encode(), mtime=0)),
    "random_bytes.csv": error_case(np.random.default_rng(5).integers(0, 256, 4096, dtype=np.uint8).tobytes()),
    "png_bytes.csv": error_case(b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR" + bytes(64)),
    "single_line_50MB.csv": Case(long_single_line, False, "longer than 1 MiB"),
    "long_line_in_data.csv": Case(long_line_in_data, False, "longer than 1 MiB"),
    "a_directory.csv": Case(directory, False, "a directory, not a regular file"),
    "dev_zero.csv": Case(symlink_to("/dev/zero"), False, "a character device, not a regular file"),
    "dev_null.csv": Case(symlink_to("/dev/null"), False, "a character device, not a regular file"),
    "fifo.csv": Case(fifo, False, "a named pipe (FIFO), not a regular file"),
    "broken_symlink.csv": Case(symlink_to("/nonexistent/jointid/log.csv"), False, "cannot open"),
    "symlink_to_good.csv": Case(lambda path: (symlink_to(good_target)(path), BASE)[1], True),
    "absent.csv": Case(lambda path: None, False, "cannot open: No such file"),
}


def zip_case(path: Path):
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("log.csv", PLAIN)


CASES["zip_bytes.csv"] = Case(zip_case, False)


def test_the_corpus_is_large():
    assert len(CASES) >= 80
    assert sum(case.fits for case in CASES.values()) >= 30 and sum(not case.fits for case in CASES.values()) >= 40


def strict_json(text: str):
    def refuse(constant):
        raise ValueError(f"not strict JSON: {constant}")

    return json.loads(text, parse_constant=refuse)


def with_deadline(work: Callable[[], object]):
    """work() in a daemon thread; fails the test if it runs past DEADLINE (a hang), re-raises what it raised."""
    outcome: dict = {}

    def target():
        try:
            outcome["value"] = work()
        except BaseException as error:  # noqa: BLE001 - handed to the test thread
            outcome["error"] = error

    thread = threading.Thread(target=target, daemon=True)
    thread.start()
    thread.join(DEADLINE)
    assert not thread.is_alive(), f"still running after {DEADLINE:.0f} s: a hang"
    if "error" in outcome:
        raise outcome["error"]
    return outcome["value"]


def run_cli(argv):
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # numpy's overflow warnings must not happen
        try:
            return main(argv)
        except SystemExit as stop:
            return stop.code


def equilibrated_lstsq(X: np.ndarray, y: np.ndarray):
    """numpy's lstsq after dividing each column and y by its largest magnitude (no overflow inside LAPACK)."""
    columns = np.max(np.abs(X), axis=0)
    columns[columns == 0] = 1.0
    top = np.max(np.abs(y)) or 1.0
    theta, _, rank, _ = np.linalg.lstsq(X / columns, y / top, rcond=None)
    return theta * top / columns, rank


def reference_fit(data: dict, derivatives: tuple[int, int] | None):
    """(theta, rank, qd, qdd) of the independent reference; with `derivatives`, q smoothed by scipy's
    Savitzky-Golay filter (polynomial ends) and differentiated by central differences, and the torque and the
    gravity column smoothed alike."""
    q, qd, qdd, tau = data["q"], data.get("qd"), data.get("qdd"), data["tau"]
    gravity = G * np.cos(q)
    if derivatives is not None:
        window, order = derivatives
        step = float(np.median(np.diff(data["t"])))
        smooth = lambda values: savgol_filter(values, window, order, mode="interp")  # noqa: E731
        qd = np.gradient(smooth(q), step)
        qdd = np.gradient(qd, step)
        gravity, tau = smooth(gravity), smooth(tau)
    X = np.column_stack([qdd, gravity, qd])
    theta, rank = equilibrated_lstsq(X, tau)
    return theta, rank, qd, qdd


def derivative_rounding(data: dict, derivatives: tuple[int, int], qdd: np.ndarray) -> float:
    """Relative size of the rounding in an acceleration estimated from angles, to first order: both sides fit a
    polynomial to each end's window (scipy's mode="interp", jointid's polyfit), whose column-scaled Vandermonde
    matrix has a condition number in the hundreds for a 201-sample window of order 4; the rounding of q (eps
    max|q|) it amplifies is then amplified by the second difference (4 / step^2), against qdd's largest value. Ten
    times that: on angle_only.csv, 1.2e-6, and 1.2e-5 once multiplied by the regressor's condition number (9.7) for
    the estimate, where two CPUs' kernels (OPENBLAS_CORETYPE=Prescott) moved it by 1.04e-6."""
    window, order = derivatives
    vandermonde = np.vander(np.arange(window, dtype=float), order + 1)
    vandermonde /= np.linalg.norm(vandermonde, axis=0)
    step = float(np.median(np.diff(data["t"])))
    rounding = np.finfo(float).eps * float(np.max(np.abs(data["q"]))) * 4.0 / step**2
    return 10.0 * float(np.linalg.cond(vandermonde)) * rounding / float(np.max(np.abs(qdd)))


def scaled_rms(values: np.ndarray) -> float:
    top = float(np.max(np.abs(values)))
    return 0.0 if top == 0 else top * math.sqrt(float(np.mean((values / top) ** 2)))


@pytest.mark.parametrize("name", sorted(CASES))
def test_every_corpus_file_is_one_clear_line_or_a_correct_fit(capsys, tmp_path, name):
    case = CASES[name]
    path = tmp_path / name
    data = case.make(path)
    status = with_deadline(lambda: run_cli(["fit", "--csv", str(path), "--json"]))
    out, err = capsys.readouterr()
    if case.fits:  # with the defaults (automatic window, low-pass, sensitivity check): a fit, no more
        assert (status, err) == (0, ""), err
        strict_json(out)
        # The numbers are checked against the reference without the low-pass and with the reference's window.
        window = [] if case.derivatives is None else ["--window", str(case.derivatives[0]),
                                                      "--order", str(case.derivatives[1])]
        status = with_deadline(lambda: run_cli(["fit", "--csv", str(path), "--json", "--cutoff", "0", *window,
                                                "--model", "plain", "--no-robust"]))
        out, err = capsys.readouterr()
    if not case.fits:
        assert (status, out) == (2, ""), err
        assert len(err.splitlines()) == 1 and err.startswith(f"jointid: {path}"), err
        assert "Traceback" not in err and case.words in err, err
        with pytest.raises(LogError) as raised:  # the explorer's loader: the same one-line LogError
            with_deadline(lambda: load_request(LoadRequest(str(path))))
        assert "\n" not in str(raised.value) and str(raised.value).startswith(str(path))
        return
    assert (status, err) == (0, ""), err
    document = strict_json(out)
    theta, rank, qd, qdd = reference_fit(data, case.derivatives)  # a logged qd alone is estimated too
    assert document["rank"] == rank
    window, order = (None, 3) if case.derivatives is None else case.derivatives
    loaded = with_deadline(lambda: load_request(LoadRequest(str(path), window=window, order=order,
                                                            filtering=FilterRequest(0)),
                                                exclusion=ExclusionRequest(robust=False)))
    # Logged derivatives: the fit's own rounding only. Estimated ones: the rounding the end polynomials amplify,
    # and in the estimate that again by the condition number of the column-scaled regressor.
    columns = 1e-9 if case.derivatives is None else max(1e-9, derivative_rounding(data, case.derivatives, qdd))
    if rank < 3:
        assert document["estimate"] is None and loaded.result.estimate is None
    else:
        X = np.column_stack([qdd, G * np.cos(data["q"]), qd])
        conditioning = float(np.linalg.cond(X / np.max(np.abs(X), axis=0)))
        estimate = np.array([document["estimate"][k] for k in ("I", "h", "B")])
        np.testing.assert_allclose(estimate, theta, rtol=1e-9 if case.derivatives is None else
                                   conditioning * columns)
        np.testing.assert_array_equal(loaded.result.estimate, estimate)  # the explorer's fit is the same
    # RMS readouts are those of the numbers fitted, finite however large or small.
    assert document["speed_rms"] == pytest.approx(scaled_rms(qd), rel=columns)
    assert document["accel_rms"] == pytest.approx(scaled_rms(qdd), rel=columns)


@pytest.mark.parametrize("name", ["fifo.csv", "dev_zero.csv", "single_line_50MB.csv", "utf16le_bom.csv"])
def test_a_real_process_refuses_special_files_promptly(tmp_path, name):
    path = tmp_path / name
    CASES[name].make(path)
    done = subprocess.run([sys.executable, "-m", "jointid", "fit", "--csv", str(path)], capture_output=True,
                          text=True, timeout=DEADLINE, env={**os.environ, "PYTHONPATH": str(CHECKOUT)})
    assert (done.returncode, done.stdout) == (2, "")
    assert len(done.stderr.splitlines()) == 1 and CASES[name].words in done.stderr, done.stderr


@pytest.mark.parametrize("step", [1e-200, 1e-302])
def test_angles_moving_below_double_precision_are_a_fit_that_says_so(capsys, tmp_path, step):
    """Time steps so small that q's change per step is lost in rounding: no crash and no overflow, a fit whose rank
    and low-pass say that q shows no motion."""
    path = tmp_path / "tiny.csv"
    path.write_text(text_of(angle_only(500, step), names=("t", "q", "tau")))
    status = with_deadline(lambda: run_cli(["fit", "--csv", str(path), "--json"]))
    out, err = capsys.readouterr()
    assert (status, err) == (0, "")
    document = strict_json(out)
    assert document["rank"] < 3 and document["estimate"] is None
    assert "no motion" in document["low_pass"]["reason"]

