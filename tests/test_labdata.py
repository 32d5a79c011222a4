"""Reading lab torque curves: separators, decimal commas, headers, and every bad file explained."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import windpump
from windpump import LabDataError, read_torque_csv

finite = st.floats(min_value=0.0, max_value=1e4, allow_nan=False, allow_infinity=False)


@given(
    rows=st.lists(st.tuples(finite, st.floats(-1e3, 1e3)), min_size=3, max_size=40),
    separator=st.sampled_from([",", ";", "\t"]),
    header=st.booleans(),
    decimal_comma=st.booleans(),
)
def test_a_written_table_reads_back(rows, separator, header, decimal_comma):
    comma = decimal_comma and separator != ","
    lines = ["speed [rad/s]" + separator + "torque [N m]"] if header else []
    for omega, torque in rows:
        cells = [repr(omega), repr(torque)]
        lines.append(separator.join(c.replace(".", ",") if comma else c for c in cells))
    table = read_torque_csv("\n".join(lines).encode())
    np.testing.assert_array_equal(table.omega, [r[0] for r in rows])
    np.testing.assert_array_equal(table.torque, [r[1] for r in rows])
    assert (table.header is not None) == header


def test_comments_blank_lines_quotes_and_a_bom_are_read():
    text = '\ufeff# measured 2026-05-01\n"speed","torque"\n\n10,0.2\n"50","0.6"\n90,0.2\n'
    table = read_torque_csv(text.encode("utf-8"))
    assert table.omega.tolist() == [10.0, 50.0, 90.0] and table.header == ("speed", "torque")


def test_a_path_is_read(tmp_path):
    path = tmp_path / "lab.csv"
    path.write_text("10,0.2\n50,0.6\n90,0.2\n", encoding="utf-8")
    assert read_torque_csv(path).torque.tolist() == [0.2, 0.6, 0.2]


@pytest.mark.parametrize(
    "content, line, column, words",
    [
        (b"", None, None, "the file is empty"),
        (b"# only a comment\n\n", None, None, "the file is empty"),
        (b"10,0.2\n50,0.6\n", None, None, "the fit needs at least 3"),
        (b"10,0.2\n50,abc\n90,0.2\n", 2, 2, "'abc' is not a number"),
        (b"10,0.2\n50,0.6,7\n90,0.2\n", 2, None, "3 columns where the file needs two"),
        (b"10\n50\n90\n", 1, None, "1 columns"),
        (b"10,0.2\n-50,0.6\n90,0.2\n", 2, 1, "negative"),
        (b"10,0.2\n50,inf\n90,0.2\n", 2, 2, "not a finite number"),
        (b"torque,speed\n0.2,10\n0.6,50\n0.2,90\n", 1, None, "names torque first"),
        (b"\xff\xfe1\x00,\x002\x00", None, None, "not UTF-8"),
    ],
)
def test_bad_files_say_what_and_where(content, line, column, words):
    with pytest.raises(LabDataError, match=words) as caught:
        read_torque_csv(content)
    assert (caught.value.line, caught.value.column) == (line, column)


def test_a_long_file_is_refused_before_it_is_parsed(tmp_path):
    with pytest.raises(LabDataError, match="at most 1,000,000"):
        read_torque_csv(b"1,2\n" * 300_000)
    path = tmp_path / "big.csv"
    path.write_bytes(b"1,2\n" * 300_000)
    with pytest.raises(LabDataError, match="1,200,000 bytes"):
        read_torque_csv(path)


def test_a_swapped_file_fits_poorly_and_a_good_one_well():
    omega = np.linspace(5, 95, 12)
    torque = 0.6 * (omega / 50) * (2 - omega / 50)
    good = windpump.fit_torque_curve(omega, torque)
    assert not good.poor and good.relative_residual < 1e-9
    noisy = torque + np.random.default_rng(1).normal(0, 0.01, omega.size)
    assert not windpump.fit_torque_curve(omega, noisy).poor
    try:
        swapped = windpump.fit_torque_curve(torque, omega)
    except windpump.ParameterError:
        return  # refused outright: just as good
    assert swapped.poor
