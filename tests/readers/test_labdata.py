"""Reading lab torque curves: separators, decimal commas, headers, and every bad file explained."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
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
        (b"10,0.2\n50,0.6,7\n90,0.2\n", 2, 3, "3 columns where the file needs two"),
        (b"10\n50\n90\n", 1, 2, "1 column where"),
        (b"10,0.2\n-50,0.6\n90,0.2\n", 2, 1, "negative"),
        (b"10,0.2\n50,inf\n90,0.2\n", 2, 2, "not a finite number"),
        (b"torque,speed\n0.2,10\n0.6,50\n0.2,90\n", 1, None, "names torque first"),
        (b"\xff\xfe1\x00,\x002\x00", None, None, "not UTF-8"),
        # a first row is a header by what it says, never because it fails to parse as data
        (b"10,0.216x\n50,0.6\n90,0.216\n", 1, 2, "'0.216x' is not a number"),
        (b"10;0,216x\n50;0,6\n90;0,216\n", 1, 2, "'0.216x' is not a number"),
        (b"-1O,0.216\n50,0.6\n90,0.216\n", 1, 1, "'-1O' is not a number"),
        (b"10,0.216,7\n50,0.6\n90,0.216\n", 1, 3, "3 columns"),
        (b"10,0.216,note\n50,0.6\n90,0.216\n", 1, 3, "3 columns"),
        (b"speed,torque,note\n10,0.2\n50,0.6\n90,0.2\n", 1, 3, "3 columns"),
        (b"speed\n10,0.2\n50,0.6\n90,0.2\n", 1, 2, "1 column where"),
        (b"speed,0.216\n50,0.6\n90,0.216\n", 1, 1, "'speed' is not a number"),
        (b"nan,0.216\n50,0.6\n90,0.216\n", 1, 1, "not a finite number"),
        (b"10,0.216\x00\n50,0.6\n90,0.216\n", 1, None, "NUL byte"),
        (b"10,0.2\n\n50\x00,0.6\n90,0.216\n", 3, None, "NUL byte"),
        (b"1\x00,\x002\x00\n\x00", 1, None, "not text"),
        (b"   \n\t\n", None, None, "the file is empty"),
        (b"speed,torque\n", None, None, "the file has 0 measurement"),
    ],
)
def test_bad_files_say_what_and_where(content, line, column, words):
    with pytest.raises(LabDataError, match=words) as caught:
        read_torque_csv(content)
    assert (caught.value.line, caught.value.column) == (line, column)


@settings(max_examples=60)
@given(
    rows=st.lists(st.tuples(finite, st.floats(-1e3, 1e3)), min_size=3, max_size=12),
    header=st.booleans(),
    at=st.data(),
    letter=st.characters(categories=["L"]),
)
def test_a_number_with_a_letter_after_it_is_refused_naming_its_line(rows, header, at, letter):
    """In any row, the first too: a typo never turns a row into a header or drops it."""
    lines = [[repr(omega), repr(torque)] for omega, torque in rows]
    row = at.draw(st.integers(0, len(rows) - 1), label="row")
    column = at.draw(st.integers(1, 2), label="column")
    lines[row][column - 1] += letter
    text = "\n".join(",".join(cells) for cells in ([["speed", "torque"]] if header else []) + lines)
    with pytest.raises(LabDataError, match="is not a number") as caught:
        read_torque_csv(text.encode())
    assert (caught.value.line, caught.value.column) == (row + 1 + header, column)


@settings(max_examples=60)
@given(
    rows=st.lists(st.tuples(finite, st.floats(-1e3, 1e3)), min_size=3, max_size=12),
    header=st.booleans(),
    at=st.data(),
)
def test_a_nul_byte_anywhere_refuses_the_file(rows, header, at):
    text = "\n".join((["speed,torque"] if header else []) + [f"{w!r},{t!r}" for w, t in rows])
    where = at.draw(st.integers(0, len(text)), label="where")
    with pytest.raises(LabDataError, match="NUL byte"):
        read_torque_csv((text[:where] + "\x00" + text[where:]).encode())


@pytest.mark.parametrize(
    "header",
    ["speed,torque", "ω [rad/s];T [N·m]", "Speed (rad/s)\tTorque (N m)", '"w","T"', "rpm,-"],
)
def test_a_header_of_names_is_read_as_one(header):
    separator = next((s for s in ("\t", ";") if s in header), ",")
    data = [f"10{separator}0.2", f"50{separator}0.6", f"90{separator}0.2"]
    table = read_torque_csv("\n".join([header, *data]))
    assert table.omega.tolist() == [10.0, 50.0, 90.0] and table.header is not None


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


def test_a_table_s_power_is_speed_times_torque():
    table = read_torque_csv(b"speed,torque\n10,0.25\n40,0.5\n80,0.125\n")
    assert table.power.tolist() == [2.5, 20.0, 10.0]  # W, by hand
    # Measurements on Eq. (11) itself give the windmill's power curve (Eq. 5's left side).
    design = windpump.Design.seed_example()
    omega = np.linspace(5.0, 150.0, 30)
    torque = windpump.windmill_torque(design, omega)
    rows = "\n".join(f"{w:.17g},{t:.17g}" for w, t in zip(omega, torque, strict=True))
    measured = read_torque_csv(rows.encode())
    np.testing.assert_allclose(measured.power, windpump.windmill_power(design, omega), rtol=1e-14)
