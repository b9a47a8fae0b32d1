"""Reading CSV joint logs: columns, comments, units, chunking, progress, cancelling and every bad-file message."""

import math
import tracemalloc

import numpy as np
from scipy.signal import savgol_filter
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from support.import_check import packages_loaded

from jointid.logs import csv_reader
from jointid.logs.csv_reader import load_log, read_table
from jointid.logs.table import LoadCancelled, LogError


def write(tmp_path, text, name="log.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


FULL = "t,q,qd,qdd,tau\n0,0.1,0.2,0.3,1\n0.5,0.2,0.3,0.4,2\n1,0.3,0.4,0.5,3\n"


def test_a_full_log_reads_every_column(tmp_path):
    log = load_log(write(tmp_path, FULL))
    np.testing.assert_array_equal(log.data.t, [0, 0.5, 1])
    np.testing.assert_array_equal(log.data.q, [0.1, 0.2, 0.3])
    np.testing.assert_array_equal(log.data.qd, [0.2, 0.3, 0.4])
    np.testing.assert_array_equal(log.data.qdd, [0.3, 0.4, 0.5])
    np.testing.assert_array_equal(log.data.tau, [1, 2, 3])
    assert log.derivatives is None and log.ignored == () and log.notes == () and log.rows == 3


def test_columns_are_found_by_name_in_any_order_and_case(tmp_path):
    text = "TAU, Qdd ,qD,Q,T\n1,0.3,0.2,0.1,0\n2,0.4,0.3,0.2,0.5\n3,0.5,0.4,0.3,1\n"
    log = load_log(write(tmp_path, text))
    np.testing.assert_array_equal(log.data.q, [0.1, 0.2, 0.3])
    np.testing.assert_array_equal(log.data.tau, [1, 2, 3])
    np.testing.assert_array_equal(log.data.qdd, [0.3, 0.4, 0.5])


def test_extra_columns_are_ignored_even_when_not_numbers_and_named_in_a_note(tmp_path):
    text = "label,t,q,current,qd,qdd,tau\na,0,0.1,1.5,0.2,0.3,1\nb,0.5,0.2,,0.3,0.4,2\nc,1,0.3,x,0.4,0.5,3\n"
    log = load_log(write(tmp_path, text))
    assert log.ignored == ("label", "current")
    np.testing.assert_array_equal(log.data.tau, [1, 2, 3])
    assert len(log.notes) == 1 and "'label', 'current'" in log.notes[0]


def test_comments_blank_lines_crlf_and_a_byte_order_mark_are_skipped(tmp_path):
    text = (
        "\ufeff# logged by rig 3\r\n\r\n# units SI\r\nt,q,qd,qdd,tau\r\n# first\r\n0,0.1,0.2,0.3,1\r\n"
        "\r\n   # indented comment\r\n0.5,0.2,0.3,0.4,2\r\n1,0.3,0.4,0.5,3\r\n# end\r\n"
    )
    path = tmp_path / "log.csv"
    path.write_bytes(text.encode("utf-8"))
    log = load_log(path)
    np.testing.assert_array_equal(log.data.q, [0.1, 0.2, 0.3])
    np.testing.assert_array_equal(log.data.tau, [1, 2, 3])


def test_degrees_convert_angle_velocity_and_acceleration_but_not_time_or_torque(tmp_path):
    text = "t,q,qd,qdd,tau\n0,90,180,-45,1\n1,30,60,360,2\n2,0,1,2,3\n"
    log = load_log(write(tmp_path, text), degrees=True)
    np.testing.assert_allclose(log.data.q, [math.pi / 2, math.pi / 6, 0])
    np.testing.assert_allclose(log.data.qd, [math.pi, math.pi / 3, math.pi / 180])
    np.testing.assert_allclose(log.data.qdd, [-math.pi / 4, 2 * math.pi, math.pi / 90])
    np.testing.assert_array_equal(log.data.t, [0, 1, 2])
    np.testing.assert_array_equal(log.data.tau, [1, 2, 3])
    assert log.degrees


def test_a_log_without_t_but_with_both_derivatives_has_no_times(tmp_path):
    log = load_log(write(tmp_path, "q,qd,qdd,tau\n0.1,0.2,0.3,1\n0.2,0.3,0.4,2\n0.3,0.4,0.5,3\n"))
    assert log.data.t is None and log.derivatives is None
    np.testing.assert_array_equal(log.data.time_axis, [0, 1, 2])


def test_a_log_without_t_need_not_be_in_time_order(tmp_path):
    log = load_log(write(tmp_path, "q,qd,qdd,tau\n0.3,0.4,0.5,3\n0.1,0.2,0.3,1\n0.2,0.3,0.4,2\n"))
    np.testing.assert_array_equal(log.data.tau, [3, 1, 2])


def angle_only_text(rows, step=0.01, columns=("t", "q", "tau")):
    t = np.arange(rows) * step
    q = 0.5 * np.sin(1.3 * t)
    values = {"t": t, "q": q, "tau": np.cos(t), "qd": 0.65 * np.cos(1.3 * t)}
    lines = [",".join(columns)] + [",".join(repr(float(values[c][i])) for c in columns) for i in range(rows)]
    return "\n".join(lines) + "\n", t, q


def test_missing_derivatives_are_estimated_from_smoothed_angles_and_nothing_is_trimmed(tmp_path):
    text, t, q = angle_only_text(100)
    log = load_log(write(tmp_path, text), window=11, order=3)
    smoothed = savgol_filter(q, 11, 3, mode="interp")  # scipy's smoothing, polynomial ends
    qd = np.gradient(smoothed, 0.01)
    np.testing.assert_allclose(log.data.qd, qd, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(log.data.qdd, np.gradient(qd, 0.01), rtol=1e-9, atol=1e-9)
    np.testing.assert_array_equal(log.data.t, t)
    np.testing.assert_array_equal(log.data.q, q)
    assert log.data.count == 100 and log.rows == 100
    d = log.derivatives
    assert (d.method, d.window, d.order, d.trimmed, d.estimated) == (
        "savitzky-golay smoothing, central differences", 11, 3, 0, ("qd", "qdd"))
    assert d.step == pytest.approx(0.01)
    assert "qd and qdd estimated" in log.notes[0] and "no sample trimmed" in log.notes[0]


def test_a_logged_velocity_alone_is_not_mixed_with_an_estimated_acceleration(tmp_path):
    text, t, q = angle_only_text(60, columns=("t", "q", "qd", "tau"))
    log = load_log(write(tmp_path, text), window=7, order=2)
    assert log.derivatives.estimated == ("qd", "qdd")
    np.testing.assert_allclose(log.data.qd, np.gradient(savgol_filter(q, 7, 2, mode="interp"), 0.01), rtol=1e-9)
    assert any("the logged qd is not used" in note for note in log.notes)


def test_non_uniform_time_is_allowed_when_nothing_is_estimated(tmp_path):
    log = load_log(write(tmp_path, "t,q,qd,qdd,tau\n0,0,0,0,1\n0.1,0,0,0,1\n0.5,0,0,0,1\n"))
    np.testing.assert_array_equal(log.data.t, [0, 0.1, 0.5])


def random_table(seed, rows):
    rng = np.random.default_rng(seed)
    table = rng.normal(size=(rows, 5)) * 10.0 ** rng.integers(-3, 4, size=(rows, 5))
    table[:, 0] = np.arange(rows) * 0.001
    return table


@settings(max_examples=30, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    rows=st.integers(3, 400),
    chunk=st.integers(1, 3000),
    comment_every=st.integers(0, 50),
)
def test_any_chunk_size_reads_the_same_doubles(tmp_path_factory, seed, rows, chunk, comment_every):
    table = random_table(seed, rows)
    lines = ["# header comment", "t,q,qd,qdd,tau"]
    for i, row in enumerate(table):
        if comment_every and i % comment_every == 0:
            lines.append("# comment" if i % 2 else "")
        lines.append(",".join(repr(float(v)) for v in row))
    path = tmp_path_factory.mktemp("h") / "log.csv"
    path.write_text("\n".join(lines))  # no final newline
    read = read_table(path, chunk_bytes=chunk)
    for j, name in enumerate(("t", "q", "qd", "qdd", "tau")):
        np.testing.assert_array_equal(read.columns[name], table[:, j])


def test_row_numbers_count_comments_and_blank_lines_across_chunks(tmp_path):
    lines = ["t,q,qd,qdd,tau"]
    for i in range(300):
        if i % 7 == 0:
            lines.append("# note")
        if i % 11 == 0:
            lines.append("")
        lines.append(f"{i * 0.01!r},0,0,0,{'nan' if i == 250 else '1'}")
    path = write(tmp_path, "\n".join(lines) + "\n")
    expected = lines.index("2.5,0,0,0,nan") + 1
    for chunk in (1, 64, 1000, 1 << 22):
        with pytest.raises(LogError) as caught:
            read_table(path, chunk_bytes=chunk)
        assert (caught.value.row, caught.value.column) == (expected, "5 (tau)")


def test_progress_reaches_the_file_size_and_never_goes_back(tmp_path):
    text, _, _ = angle_only_text(2000)
    path = write(tmp_path, text)
    seen = []
    read_table(path, progress=lambda done, total: seen.append((done, total)), chunk_bytes=4096)
    assert len(seen) > 5
    assert [d for d, _ in seen] == sorted(d for d, _ in seen)
    assert seen[-1] == (path.stat().st_size, path.stat().st_size)


def test_cancel_stops_between_chunks(tmp_path):
    text, _, _ = angle_only_text(2000)
    path = write(tmp_path, text)
    calls = []

    def cancel():
        calls.append(1)
        return len(calls) > 3

    with pytest.raises(LoadCancelled):
        load_log(path, cancel=cancel, chunk_bytes=4096)
    assert len(calls) == 4


def test_peak_memory_stays_within_four_times_the_numbers(tmp_path):
    """With chunks a small share of the file, as 4 MiB is of a 1,000,000-row log (benchmarks/bench_csv.py)."""
    rows = 100_000
    table = random_table(3, rows)
    path = tmp_path / "big.csv"
    np.savetxt(path, table, delimiter=",", fmt="%.17g", header="t,q,qd,qdd,tau", comments="")
    tracemalloc.start()
    try:
        load_log(path, chunk_bytes=1 << 18)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak <= 4 * rows * 5 * 8


# Each bad file: its text, the problem's words, the row and the column the message must name.
BAD_FILES = {
    "header only": ("t,q,qd,qdd,tau\n", "no data rows", 1, None),
    "comments only": ("# nothing\n\n# here\n", "is empty", None, None),
    "missing q": ("t,qd,qdd,tau\n0,0,0,1\n", "missing required column 'q'", 1, None),
    "missing tau": ("# c\nt,q,qd,qdd\n0,0,0,0\n", "missing required column 'tau'", 2, None),
    "no t, no qdd": ("q,qd,tau\n0,0,1\n", "missing column 't'", 1, None),
    "duplicate column": ("t,q,qd,Q,qdd,tau\n0,0,0,0,0,1\n", "'q' appears twice (columns 2 and 4)", 1, None),
    "word in a cell": ("t,q,qd,qdd,tau\n0,0,0,0,1\n1,0,fast,0,1\n", "'fast' is not a number", 3, "3 (qd)"),
    "empty cell": ("t,q,qd,qdd,tau\n0,0,0,0,1\n1,0,0,,1\n", "is empty", 3, "4 (qdd)"),
    "NaN": ("t,q,qd,qdd,tau\n# c\n0,0,0,0,1\n1,NaN,0,0,1\n", "NaN", 4, "2 (q)"),
    "infinity": ("t,q,qd,qdd,tau\n0,0,0,0,inf\n1,0,0,0,1\n", "infinity", 2, "5 (tau)"),
    "minus infinity": ("t,q,qd,qdd,tau\n0,0,0,0,1\n1,0,-Infinity,0,1\n", "infinity", 3, "3 (qd)"),
    "too few cells": ("t,q,qd,qdd,tau\n0,0,0,0,1\n1,0,0,1\n", "has 4 cells but the header has 5", 3, None),
    "too many cells": ("t,q,qd,qdd,tau\n0,0,0,0,1\n1,0,0,0,1,9\n", "has 6 cells", 3, None),
    "ragged with extra columns": ("t,q,x,qd,qdd,tau\n0,0,a,0,0,1\n1,0,0,0,1\n2,0,b,0,0,1\n", "has 5 cells", 3, None),
    "time repeats": ("t,q,qd,qdd,tau\n0,0,0,0,1\n1,0,0,0,1\n1,0,0,0,2\n", "repeats with other values", 4, "1 (t)"),
    "time goes back": ("t,q,qd,qdd,tau\n0,0,0,0,1\n2,0,0,0,1\n# c\n1,0,0,0,1\n", "time runs backwards", 5, "1 (t)"),
    "two rows": ("q,qd,qdd,tau\n0,0,0,1\n1,1,1,1\n", "has 2 data rows", None, None),
    "shorter than the window": (angle_only_text(4)[0], "has 4 data rows; a window of 5", None, None),
    "trailing comment on a row": ("t,q,qd,qdd,tau\n0,0,0,0,1 # note\n", "'1 # note' is not a number", 2, "5 (tau)"),
    "quoted number": ('t,q,qd,qdd,tau\n0,"0",0,0,1\n', "'\"0\"' is not a number", 2, "2 (q)"),
    "semicolons": ("t;q;qd;qdd;tau\n0;0;0;0;1\n", "missing required column 'q'", 1, None),
    "underscore digits": ("t,q,qd,qdd,tau\n0,1_000,0,0,1\n", "'1_000' is not a number", 2, "2 (q)"),
}


def gap_text():
    """An angle-only log at 100 Hz missing the five samples before line 302 (a step of six median steps)."""
    text, _, _ = angle_only_text(400)
    lines = text.splitlines()
    del lines[296:301]
    return "\n".join(lines) + "\n"


BAD_FILES["gap in time"] = (gap_text(), "gap in time: 0.06 s between t = 2.94 s and 3 s", 297, "1 (t)")


@pytest.mark.parametrize("name", sorted(BAD_FILES))
def test_each_bad_file_names_the_file_row_and_column(tmp_path, name):
    text, problem, row, column = BAD_FILES[name]
    path = write(tmp_path, text, "bad.csv")
    with pytest.raises(LogError) as caught:
        load_log(path)
    message = str(caught.value)
    assert "\n" not in message and message.startswith(str(path))
    assert problem in message
    assert caught.value.row == row and caught.value.column == column
    if row is not None:
        assert f"row {row}" in message
    if column is not None:
        assert f"column {column}" in message


def test_missing_empty_and_directory_paths(tmp_path):
    for path, problem in (
        (tmp_path / "absent.csv", "cannot open: No such file"),
        (write(tmp_path, "", "empty.csv"), "is empty: no header row"),
        (tmp_path, "cannot"),
    ):
        with pytest.raises(LogError, match=problem):
            load_log(path)


# pandas' C reader parses clean chunks; numpy.loadtxt and the line-by-line diagnosis handle the rest.

TRICKY_NUMBERS = [
    "0.1", "0.2", "0.30000000000000004", "-0.0", "-0", "0", "+0.0", "1", "-1", "+1", ".5", "-.5", "5.", "1e5",
    "1E5", "1e+05", "1e-05", "-1.5E-300", "2.2250738585072014e-308", "2.2250738585072011e-308", "4.9e-324",
    "5e-324", "2.4703282292062327e-324", "2.4703282292062328e-324", "1e-400", "-1e-400", "1.7976931348623157e308",
    "1.7976931348623158e308", "9007199254740993", "9223372036854775807", "18446744073709551617",
    "123456789012345678901234567890", "0.00000000000001953", "00012.500", "3.14159265358979323846264338327950288",
    "0.1000000000000000055511151231257827021181583404541015625", "1.00000000000000011102230246251565404236316680908203125",
    "4.35679771e-01", "-6.0221408e+23", "1e22", "1e23", "8.98846567431158e307", "-1e-5000",
]


def tricky_corpus(seed=5, rows=3000):
    """Cells as float() reads them: the fixed list above plus random doubles written many ways."""
    rng = np.random.default_rng(seed)
    bits = rng.integers(0, 2**63, size=rows * 5, dtype=np.int64).view(np.float64)
    cells = list(TRICKY_NUMBERS)
    for i, x in enumerate(bits):
        if not np.isfinite(x):
            x = rng.normal()
        cells.append(("%.17g", "%.15g", "%r", "%.25e", "%.3f", "%d")[i % 6] % (float(x) if i % 6 != 5 else int(rng.integers(-(10**15), 10**15))))
    cells = cells[: len(cells) // 4 * 4]
    return np.array(cells, dtype=object).reshape(-1, 4)


def test_values_are_bit_identical_to_float_of_the_text_with_or_without_pandas(tmp_path, monkeypatch):
    cells = tricky_corpus()
    lines = ["q,qd,note,qdd,tau"] + [f"{a},{b},x{i},{c},{d}" for i, (a, b, c, d) in enumerate(cells)]
    path = write(tmp_path, "\n".join(lines) + "\n")
    expected = np.vectorize(float, otypes=[float])(cells)
    fast = read_table(path)
    monkeypatch.setattr(csv_reader, "_pandas_read_csv", lambda: None)
    slow = read_table(path)
    for j, name in enumerate(("q", "qd", "qdd", "tau")):
        assert fast.columns[name].view(np.uint64).tolist() == expected[:, j].view(np.uint64).tolist()
        assert slow.columns[name].view(np.uint64).tolist() == expected[:, j].view(np.uint64).tolist()


def test_clean_chunks_take_pandas_and_the_rest_take_loadtxt(tmp_path, monkeypatch):
    taken = []
    original = csv_reader._ChunkReader._fast
    monkeypatch.setattr(csv_reader._ChunkReader, "_fast", lambda self, data: taken.append(original(self, data)) or taken[-1])
    read_table(write(tmp_path, FULL), chunk_bytes=1 << 20)  # chunked, not the one-call reading
    assert taken and taken[-1] is not None
    taken.clear()
    read_table(write(tmp_path, "t,q,qd,qdd,tau,mode\n0,1,2,3,4,run\n1,1,2,3,4,run\n", "text.csv"))
    assert taken == [None]  # an 'u' could be part of 'true', which only pandas reads as a number


# Cells pandas' reader takes as numbers but numpy.loadtxt does not (found by fuzzing the two).
PANDAS_ONLY = ["true", "FALSE", "TrUe", "3e 2", "+8e\t1", "8E\x0b0", "1\x0c"]


@pytest.mark.parametrize("cell", PANDAS_ONLY)
def test_cells_only_pandas_would_read_are_still_not_numbers(tmp_path, cell):
    path = tmp_path / "bad.csv"
    path.write_bytes(f"t,q,qd,qdd,tau\n0,0,0,0,1\n1,0,{cell},0,1\n".encode())
    try:
        loadtxt_reads_it = np.loadtxt(path, delimiter=",", skiprows=1).shape == (2, 5)
    except ValueError:
        loadtxt_reads_it = False
    if loadtxt_reads_it:  # e.g. trailing whitespace: both agree, and so must we
        assert float(read_table(path).columns["qd"][1]) == float(cell)
        return
    with pytest.raises(LogError) as caught:
        read_table(path)
    assert (caught.value.row, caught.value.column) == (3, "3 (qd)")
    assert "is not a number" in caught.value.problem


@settings(max_examples=200, deadline=None)
@given(
    cells=st.lists(
        st.text(alphabet="0123456789.eE+-_ \t\r\x0bxinfatyrulsINFATYRULS\"'#", min_size=0, max_size=8),
        min_size=1,
        max_size=6,
    )
)
def test_with_or_without_pandas_the_same_values_or_the_same_error(tmp_path_factory, cells):
    folder = tmp_path_factory.mktemp("p")
    rows = ["t,q,qd,qdd,tau", "0,0,0,0,1"] + [f"{i + 1},0,{cell},0,1" for i, cell in enumerate(cells)]
    path = folder / "log.csv"
    path.write_bytes("\n".join(rows).encode() + b"\n")

    def outcome():
        try:
            table = read_table(path)
        except LogError as error:
            return str(error)
        return [table.columns[n].view(np.uint64).tolist() for n in ("t", "q", "qd", "qdd", "tau")]

    fast = outcome()
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(csv_reader, "_pandas_read_csv", lambda: None)
        assert outcome() == fast


def test_import_jointid_loads_no_pandas():
    imports = "jointid, jointid.logs.table, jointid.studies.experiment, jointid.present.documents, jointid.cli"
    assert packages_loaded(imports, {"pandas", "pyarrow"}) == []


@pytest.mark.parametrize("separator, name", [("\t", "tabs"), (";", "semicolons")])
def test_a_log_separated_otherwise_than_by_commas_is_named(tmp_path, separator, name):
    path = tmp_path / "other.csv"
    path.write_text(separator.join(["t", "q", "qd", "qdd", "tau"]) + "\n" + separator.join("00001") + "\n")
    with pytest.raises(LogError, match=f"separated by {name}, not commas"):
        load_log(str(path))


def test_an_empty_path_says_so():
    with pytest.raises(LogError, match="the path is empty"):
        load_log("")


def test_the_sweep_views_seed_count_reads_ascii_digits_only():
    from jointid.options import SettingsError
    from tui.screens.sweep import SEED_COUNT_RANGE

    assert SEED_COUNT_RANGE.parse("250") == 250
    for text in ("٣", "２"):
        with pytest.raises(SettingsError):
            SEED_COUNT_RANGE.parse(text)


# Without progress or cancel, pandas reads the whole file in one call from its path; anything doubtful
# goes the chunked way, which must then give the same doubles or the same message.

def chunked_calls(monkeypatch) -> list:
    """A list that grows by one for each chunk the chunked reading takes."""
    calls = []
    original = csv_reader._ChunkReader._next_chunk
    monkeypatch.setattr(csv_reader._ChunkReader, "_next_chunk", lambda self: calls.append(1) or original(self))
    return calls


def outcome_of(path, **options):
    """The columns' bits, or the error's text."""
    try:
        table = read_table(path, **options)
    except LogError as error:
        return str(error)
    return {name: values.view(np.uint64).tolist() for name, values in table.columns.items()}


def test_a_clean_log_is_read_in_one_call_and_gives_the_chunked_doubles(tmp_path, monkeypatch):
    cells = tricky_corpus(seed=9, rows=400)
    lines = ["# made by a test", "", "q,qd,qdd,tau"] + [",".join(row) for row in cells] + ["", ""]
    path = write(tmp_path, "\r\n".join(lines))
    calls = chunked_calls(monkeypatch)
    whole = outcome_of(path)
    assert calls == []
    chunked = outcome_of(path, chunk_bytes=1000)
    assert calls and whole == chunked
    expected = np.vectorize(float, otypes=[float])(cells)
    assert whole["tau"] == expected[:, 3].view(np.uint64).tolist()


DOUBTFUL_FILES = {
    "an extra cell in the first row": "t,q,qd,qdd,tau\n0,1,2,3,4,5\n1,1,2,3,4\n2,1,2,3,4\n",
    "an extra cell later": "t,q,qd,qdd,tau\n0,1,2,3,4\n1,1,2,3,4,5\n2,1,2,3,4\n",
    "a trailing comma": "t,q,qd,qdd,tau\n0,1,2,3,4\n1,1,2,3,4,\n2,1,2,3,4\n",
    "a short row": "t,q,qd,qdd,tau\n0,1,2,3,4\n1,1,2,3\n2,1,2,3,4\n",
    "a comment line": "t,q,qd,qdd,tau\n0,1,2,3,4\n# pause\n1,1,2,3,4\n2,1,2,3,4\n",
    "an indented comment": "t,q,qd,qdd,tau\n0,1,2,3,4\n  #,1,2,3,4\n1,1,2,3,4\n2,1,2,3,4\n",
    "a commented-out row": "t,q,qd,qdd,tau\n0,1,2,3,4\n#1,1,2,3,4\n2,1,2,3,4\n3,1,2,3,4\n",
    "a NUL byte": "t,q,qd,qdd,tau\n0,1,2,3,4\n1,1\x00,2,3,4\n2,1,2,3,4\n",
    "true": "t,q,qd,qdd,tau\n0,1,2,3,4\n1,true,2,3,4\n2,1,2,3,4\n",
    "a tab inside a number": "t,q,qd,qdd,tau\n0,1,2,3,4\n1,+8e\t1,2,3,4\n2,1,2,3,4\n",
    "a lone carriage return": "t,q,qd,qdd,tau\n0,1,2,3,4\r1,1,2,3,4\n2,1,2,3,4\n",
    "a blank line after the header": "t,q,qd,qdd,tau\n\n0,1,2,3,4\n1,1,2,3,4\n2,1,2,3,4\n",
    "nan": "t,q,qd,qdd,tau\n0,1,2,3,4\n1,1,nan,3,4\n2,1,2,3,4\n",
    "inf": "t,q,qd,qdd,tau\n0,1,2,3,4\n1,1,-inf,3,4\n2,1,2,3,4\n",
    "text in an ignored column": "t,q,qd,qdd,tau,mode\n0,1,2,3,4,go\n1,1,2,3,4,go\n2,1,2,3,4,go\n",
    "a lone carriage return at the end": "t,q,qd,qdd,tau\n0,1,2,3,4\n1,1,2,3,4\n2,1,2,3,4\r",
    "a line over a MiB": "t,q,qd,qdd,tau\n0,1,2,3,4\n1,1,2,3," + "0" * (1 << 20) + "4\n2,1,2,3,4\n",
}


@pytest.mark.parametrize("text", DOUBTFUL_FILES.values(), ids=DOUBTFUL_FILES.keys())
def test_a_doubtful_log_goes_the_chunked_way_with_the_same_result(tmp_path, monkeypatch, text):
    path = tmp_path / "log.csv"
    path.write_bytes(text.encode())
    calls = chunked_calls(monkeypatch)
    whole = outcome_of(path)
    assert calls, "the chunked reading was not asked"
    with monkeypatch.context() as patch:
        patch.setattr(csv_reader, "_pandas_read_csv", lambda: None)
        assert outcome_of(path) == whole


def test_without_proc_the_file_is_read_in_chunks(tmp_path, monkeypatch):
    # pandas gets /proc/self/fd/N, the file already checked to be regular, never the path again.
    path = write(tmp_path, FULL)
    calls = chunked_calls(monkeypatch)
    real_exists = csv_reader.os.path.exists
    monkeypatch.setattr(csv_reader.os.path, "exists", lambda name: not str(name).startswith("/proc/") and real_exists(name))
    assert outcome_of(path) == outcome_of(path, chunk_bytes=64)
    assert calls
