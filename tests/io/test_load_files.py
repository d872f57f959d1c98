"""Load-history files (pdamper.io.loads): units, separators, comments, the error field."""

import pytest

from pdamper.errors import InputError
from pdamper.io.loads import read_load


def test_units_and_separators(tmp_path):
    p = tmp_path / "f.csv"
    p.write_text("# shock\n\ntime [ms];force [kN]\n0;0\n5;0.04\n10;0\n")
    h = read_load(p)
    assert list(h.time) == pytest.approx([0.0, 0.005, 0.01])
    assert list(h.values) == pytest.approx([0.0, 40.0, 0.0])
    q = tmp_path / "a.csv"
    q.write_text("acceleration [g0]\ttime [s]\n1\t0\n-1\t0.5\n")  # columns in any order
    a = read_load(q, "base_acceleration")
    assert list(a.values) == pytest.approx([9.80665, -9.80665]) and a.duration == 0.5
    assert a.at(0.25) == pytest.approx(0.0) and a.at(0.6) == 0.0  # linear, then zero


@pytest.mark.parametrize("text, kind, field, words", [
    ("time [s], force [N]\n0, 0\n1, 1\n", "base_acceleration", "base_acceleration",
     "not a time or acceleration"),
    ("time [s], acceleration [m/s^2]\n0, 0\n1, 1\n", "force", "load", "not a time or force"),
    ("time [s], force [N]\n0, 0\n0, 1\n", "force", "load", "row 3, column 'time [s]'"),
    ("time [s], force [N]\n0, 0\n1, inf\n", "force", "load", "row 3, column 'force [N]'"),
])
def test_errors_name_the_field_row_and_column(tmp_path, text, kind, field, words):
    p = tmp_path / "x.csv"
    p.write_text(text)
    with pytest.raises(InputError) as e:
        read_load(p, kind)
    assert e.value.field == field and words in e.value.message
    assert "\n" not in str(e.value)
