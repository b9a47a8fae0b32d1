"""Opening a live source from a face's options: one source, each with only its own options."""

import pytest

from jointid.live.growing_csv import GrowingCsv
from jointid.live.opening import open_live_source


def test_a_csv_opens_as_a_growing_csv(tmp_path):
    path = tmp_path / "capture.csv"
    path.write_text("t,posn,tau\n0,0.5,1\n")
    source = open_live_source(csv=path, columns="q=posn", idle_timeout=1.0)
    assert isinstance(source, GrowingCsv) and source.poll(0.5).columns["q"].tolist() == [0.5]
    source.close()


@pytest.mark.parametrize("options, message", [
    ({}, "watch one source"),
    ({"nt": "127.0.0.1", "csv": "a.csv"}, "watch one source"),
    ({"nt": "127.0.0.1", "columns": "q=posn"}, "--columns: only for a CSV"),
    ({"csv": "a.csv", "entries": "q=/A/q,tau=/A/tau"}, "--entry: only for NetworkTables"),
    ({"csv": "a.csv", "units": "rotations"}, "--units: only for NetworkTables"),
])
def test_options_of_the_other_source_are_refused_in_one_line(options, message):
    with pytest.raises(ValueError, match=message):
        open_live_source(**options)
