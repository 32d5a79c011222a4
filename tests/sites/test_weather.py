"""Wind records of a site (issue 23): the record's fields and its power law, weather files (TMY3
and EPW through pvlib, the Wind tab's CSV), pvlib's sample sites, and bad files at their line."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import windpump
from windpump import LabDataError, ParameterError, WindRecord, read_weather, sample_site, simulate

pvlib = pytest.importorskip("pvlib")
DATA = Path(pvlib.__file__).parent / "data"
GREENSBORO = DATA / "723170TYA.CSV"


def test_a_record_unpacks_as_the_pair_it_extends():
    record = WindRecord(np.array([0.0, 10.0]), np.array([5.0, 5.0]), 30.0, "mast")
    t, V = record
    assert t.tolist() == [0.0, 10.0] and V.tolist() == [5.0, 5.0] and len(record) == 2
    assert record[1] is record.V and (record.height, record.name, record.month) == (
        30.0,
        "mast",
        None,
    )
    plain = WindRecord(record.t, record.V)
    assert plain.height == 10.0 and plain.name == ""
    run = simulate(Design5, 10.0, wind=record, sample_dt=1.0)
    again = simulate(Design5, 10.0, wind=(record.t, record.V), sample_dt=1.0)
    np.testing.assert_array_equal(run.volume, again.volume)
    with pytest.raises(AttributeError):
        record.height = 5.0  # frozen


Design5 = windpump.Design.seed_example()


@pytest.mark.parametrize(("z", "shear"), [(40.0, 1 / 7), (5.0, 0.1), (80.0, 0.3), (10.0, 0.0)])
def test_at_height_is_the_power_law(z, shear):
    record = WindRecord(
        np.array([0.0, 1.0, 2.0]), np.array([0.0, 3.0, 7.5]), 10.0, "x", np.array([1, 1, 2])
    )
    high = record.at_height(z, shear)
    np.testing.assert_allclose(high.V, record.V * (z / 10.0) ** shear, rtol=1e-15)
    assert high.height == z and high.name == "x" and high.month.tolist() == [1, 1, 2]
    np.testing.assert_allclose(high.at_height(10.0, shear).V, record.V, rtol=1e-14)


@pytest.mark.parametrize(
    ("z", "shear", "name"),
    [
        (0.0, 0.2, "z"),
        (-5.0, 0.2, "z"),
        (600.0, 0.2, "z"),
        (10.0, -0.1, "shear"),
        (10.0, 1.5, "shear"),
        (10.0, math.nan, "shear"),
    ],
)
def test_at_height_refuses(z, shear, name):
    record = WindRecord(np.array([0.0, 1.0]), np.array([3.0, 4.0]))
    with pytest.raises(ParameterError) as error:
        record.at_height(z, shear)
    assert error.value.name == name


def test_the_sample_sites_are_pvlibs_tmy3_years():
    for name, file, mean in (
        ("greensboro", "723170TYA.CSV", 3.1),
        ("sand_point", "703165TY.csv", 5.1),
    ):
        record = sample_site(name)
        data, _meta = pvlib.iotools.read_tmy3(str(DATA / file), map_variables=True)
        np.testing.assert_array_equal(record.V, data["wind_speed"].to_numpy(dtype=float))
        assert record.V.mean() == pytest.approx(mean, abs=0.1)
        np.testing.assert_array_equal(record.t, 3600.0 * np.arange(8760))
        assert record.height == 10.0 and record.name
        # the hour labelled 01:00 on 1 January is January's, so is the one labelled 1 Feb 00:00
        hours = np.bincount(record.month, minlength=13)[1:]
        assert hours.tolist() == [24 * d for d in (31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31)]
        assert record.month[0] == 1 and record.month[743] == 1 and record.month[744] == 2
        assert record.month[-1] == 12


def test_an_unknown_site():
    with pytest.raises(ParameterError, match="site"):
        sample_site("paris")


def test_without_pvlib_the_message_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "pvlib", None)
    with pytest.raises(ModuleNotFoundError, match=r"windpump\[site\]"):
        sample_site("greensboro")
    with pytest.raises(ModuleNotFoundError, match=r"windpump\[site\]"):
        read_weather(GREENSBORO)


def test_read_weather_reads_a_tmy3_file():
    record = read_weather(GREENSBORO)
    assert record.name.startswith("GREENSBORO") and record.height == 10.0
    np.testing.assert_array_equal(record.V, sample_site("greensboro").V)
    assert read_weather(GREENSBORO, height=12.0, name="here").height == 12.0


def tmy3_lines():
    return GREENSBORO.read_text().splitlines()


def test_a_tmy3_file_with_a_bad_hour_is_refused_at_its_line(tmp_path):
    lines = tmy3_lines()
    broken = lines[:10] + lines[11:]  # the hour of line 11 is skipped
    path = tmp_path / "gap.csv"
    path.write_text("\n".join(broken) + "\n")
    with pytest.raises(LabDataError, match="line 11") as error:
        read_weather(path)
    assert "skips" in str(error.value)
    repeated = lines[:10] + [lines[9]] + lines[10:]
    path.write_text("\n".join(repeated) + "\n")
    with pytest.raises(LabDataError, match="line 11"):
        read_weather(path)


def epw_text(rows, city="Testville"):
    """A small EPW file: its 8 header lines, then (year, month, day, hour, wind) rows with the
    other 30 fields at plausible values."""
    header = [
        f"LOCATION,{city},ST,USA,TMY3,999999,36.10,-79.95,-5.0,273.0",
        "DESIGN CONDITIONS,0",
        "TYPICAL/EXTREME PERIODS,0",
        "GROUND TEMPERATURES,0",
        "HOLIDAYS/DAYLIGHT SAVINGS,No,0,0,0",
        "COMMENTS 1,written by tests/sites/test_weather.py",
        "COMMENTS 2,",
        "DATA PERIODS,1,1,Data,Sunday, 1/ 1,12/31",
    ]
    lines = []
    for year, month, day, hour, wind in rows:
        fields = [year, month, day, hour, 0, "?9?9?9?9E0?9?9?9?9?9?9?9?9?9?9?9?9?9?9?9*9*9?9?9?9"]
        fields += [10.0, 5.0, 70, 99000, 0, 1415, 300, 0, 0, 0, 0, 0, 0, 0, 180, wind]
        fields += [5, 5, 16.1, 77777, 9, 999999999, 10, 0.1, 0, 88, 0.2, 0.0, 1.0]
        lines.append(",".join(str(f) for f in fields))
    return "\n".join(header + lines) + "\n"


def test_read_weather_reads_an_epw_file(tmp_path):
    # the first two days of Greensboro's TMY3 year written as EPW, then 31 Jan into 1 Feb
    tmy3, _ = pvlib.iotools.read_tmy3(str(GREENSBORO), map_variables=True)
    winds = tmy3["wind_speed"].to_numpy(dtype=float)
    rows = [(1988, 1, 1 + h // 24, h % 24 + 1, winds[h]) for h in range(48)]
    path = tmp_path / "greensboro.epw"
    path.write_text(epw_text(rows))
    record = read_weather(path)
    np.testing.assert_array_equal(record.V, winds[:48])
    np.testing.assert_array_equal(record.t, 3600.0 * np.arange(48))
    assert record.month.tolist() == [1] * 48 and record.name == "Testville, ST, USA"
    rows = [(1990, 1, 31, h + 1, 4.0) for h in range(24)] + [
        (1990, 2, 1, h + 1, 6.0) for h in range(24)
    ]
    path.write_text(epw_text(rows))
    record = read_weather(path)
    assert record.month.tolist() == [1] * 24 + [2] * 24  # the hour labelled 24:00 is January's


def test_an_epw_with_a_missing_wind_is_refused_at_its_line(tmp_path):
    rows = [(1988, 1, 1, h + 1, 999.0 if h == 5 else 3.0) for h in range(24)]
    path = tmp_path / "missing.epw"
    path.write_text(epw_text(rows))
    with pytest.raises(LabDataError, match="line 14"):  # 8 header lines, the 6th hour
        read_weather(path)


def test_an_epw_hour_at_fault_is_quoted_in_the_files_own_dates(tmp_path):
    rows = [(1999, 1, 1, h + 1, 3.0) for h in range(24) if h != 12]
    path = tmp_path / "skip.epw"
    path.write_text(epw_text(rows))
    with pytest.raises(LabDataError, match="line 21") as error:  # 8 header lines, the 13th row
        read_weather(path)
    assert "“1999,1,1,14,0” skips" in str(error.value) and "2001" not in str(error.value)
    path = tmp_path / "gap.csv"  # a TMY3's own date and time
    lines = tmy3_lines()
    path.write_text("\n".join(lines[:10] + lines[11:]) + "\n")
    with pytest.raises(LabDataError, match="line 11") as error:
        read_weather(path)
    assert f"“{','.join(lines[11].split(',')[:2])}” skips"  # line 11 now in str(error.value)


def test_at_height_0_says_the_whole_range():
    record = WindRecord(np.array([0.0, 1.0]), np.array([3.0, 4.0]))
    for z in (0.0, 1e6):
        with pytest.raises(ParameterError, match="> 0 and <= 500"):
            record.at_height(z)


def test_read_weather_reads_the_wind_tabs_csv(tmp_path):
    path = tmp_path / "mast.csv"
    path.write_text("time,speed\n2026-01-31T23:00,4\n2026-01-31T23:30,5\n2026-02-01T00:00,6\n")
    record = read_weather(path)
    assert record.t.tolist() == [0.0, 1800.0, 3600.0] and record.V.tolist() == [4.0, 5.0, 6.0]
    assert record.height == 10.0 and record.name == "mast" and record.month.tolist() == [1, 1, 2]
    assert read_weather(path, height=25.0).height == 25.0
    seconds = tmp_path / "seconds.csv"
    seconds.write_text("0,4\n3600,5\n")
    assert read_weather(seconds).month is None
    with pytest.raises(ParameterError, match="height"):
        read_weather(seconds, height=0.0)
    bad = tmp_path / "bad.csv"
    bad.write_text("0,4\n3600,-5\n")
    with pytest.raises(LabDataError, match="line 2"):
        read_weather(bad)


def test_a_year_at_sand_point_with_a_tank():
    record = sample_site("sand_point").at_height(15.0)
    design = windpump.Design.seed_example().replace(T_0=0.3)
    year = windpump.supply(design, record, 5.0, 20.0)
    assert year.hours == 8760 and year.monthly.month.tolist() == list(range(1, 13))
    assert year.monthly.demand.sum() == pytest.approx(5.0 * 365)
    assert year.totals.pumped == pytest.approx(year.monthly.pumped.sum(), rel=1e-12)
    size = windpump.tank_for(design, record, 5.0, 0.05)
    assert windpump.supply(design, record, 5.0, size).lolp <= 0.05


def test_read_weather_takes_an_uploads_bytes():
    from_bytes = read_weather(GREENSBORO.read_bytes())
    np.testing.assert_array_equal(from_bytes.V, read_weather(GREENSBORO).V)
    np.testing.assert_array_equal(from_bytes.month, sample_site("greensboro").month)
    csv = read_weather(b"0,4\n1800,5\n3600,6\n", height=30.0)
    assert csv.V.tolist() == [4.0, 5.0, 6.0] and csv.height == 30.0 and csv.name == ""


def test_a_file_named_like_an_address_is_read_from_disk(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "http_site.epw").write_text(epw_text([(1988, 1, 1, h + 1, 4.0) for h in range(24)]))
    assert read_weather("http_site.epw").V.tolist() == [4.0] * 24


@pytest.mark.parametrize("height", [0.0, -1.0, math.nan, 1e4])
def test_a_record_refuses_a_bad_height(height):
    with pytest.raises(ParameterError, match="height"):
        WindRecord(np.array([0.0, 1.0]), np.array([3.0, 4.0]), height)


def test_a_csv_with_a_gap_is_refused_at_its_line(tmp_path):
    path = tmp_path / "gappy.csv"
    path.write_text("time,speed\n# a mast\n0,4\n1800,5\n9000,6\n")
    with pytest.raises(LabDataError, match="line 5") as error:
        read_weather(path)
    assert "gap of 2 h" in str(error.value)


@pytest.mark.parametrize(
    "contents, says",
    [
        (b"", "the file is empty; it needs a TMY3 or EPW weather file, or two columns"),
        (b" \n\n", "the file is empty; it needs a TMY3 or EPW weather file, or two columns"),
        (b"time,speed\n", "has 0 sample(s); a wind record needs at least 2 lines of two columns"),
    ],
)
def test_an_empty_weather_file_says_which_columns_it_needs(contents, says):
    with pytest.raises(LabDataError) as error:
        read_weather(contents)
    message = str(error.value)
    assert says in message
    assert "time [s] or an ISO timestamp" in message and "wind speed [m/s]" in message


@pytest.mark.parametrize("days", [31, 2, 1])
def test_a_short_tmy3_file_is_read_as_its_span(tmp_path, days):
    # Greensboro's year cut to its first days: its hours are the full year's first hours, as
    # pvlib reads the full file (the reference, without coercing the year: no row moved)
    full, _ = pvlib.iotools.read_tmy3(str(GREENSBORO), map_variables=True)
    hours = 24 * days
    path = tmp_path / "short.csv"
    path.write_text("\n".join(tmy3_lines()[: 2 + hours]) + "\n")
    record = read_weather(path)
    np.testing.assert_array_equal(record.V, full["wind_speed"].to_numpy(dtype=float)[:hours])
    np.testing.assert_array_equal(record.t, 3600.0 * np.arange(hours))
    assert record.month.tolist() == [1] * hours  # the last hour, 24:00, is still January's
    assert record.name.startswith("GREENSBORO")
    assert windpump.supply(windpump.Design.seed_example(), record, 1.0, 0.0).hours == hours


def test_a_short_tmy3_file_with_a_gap_names_the_gaps_line(tmp_path):
    lines = tmy3_lines()[: 2 + 48]
    path = tmp_path / "gap.csv"
    path.write_text("\n".join(lines[:20] + lines[23:]) + "\n")  # lines 21 to 23 left out
    with pytest.raises(LabDataError) as error:
        read_weather(path)
    said = str(error.value)
    assert said.startswith("line 21: ") and "skips" in said, said
    assert f"“{','.join(lines[23].split(',')[:2])}”" in said  # the file's own date and hour
    path.write_text("\n".join(lines[:-2] + lines[-1:]) + "\n")  # the last hour but one left out
    with pytest.raises(LabDataError, match=f"^line {len(lines) - 1}: .* skips"):
        read_weather(path)


def test_a_weather_file_without_a_header_field_says_which_in_words(tmp_path):
    path = tmp_path / "bare.epw"
    path.write_text("LOCATION,Here\n" + "\n".join(["x"] * 8) + "\n")
    with pytest.raises(LabDataError) as error:
        read_weather(path)
    assert str(error.value) == (
        "line 1: the EPW LOCATION line has 2 fields where it needs 10: it has no state or "
        "province, country, data source, WMO station number, latitude, longitude, time zone or "
        "altitude"
    )
    tmy3 = tmy3_lines()
    path = tmp_path / "columns.csv"
    path.write_text("\n".join([tmy3[0], "a,b,c", "1,2,3"]) + "\n")
    with pytest.raises(LabDataError) as error:
        read_weather(path)
    assert "'" not in str(error.value) and "no column “Date (MM/DD/YYYY)”" in str(error.value)


# A weather file whose header lacks a field, or holds a word where pvlib reads a number: pvlib
# says "KeyError: 'altitude'" or "could not convert string to float: ''"; the file is refused at its
# first line in words (and a TMY3 station line of 6 fields is still read as a TMY3's, not as a CSV
# of 6 columns).
STATION = tmy3_lines()[0].split(",")  # USAF, name, state, time zone, latitude, longitude, altitude
LOCATION = epw_text([]).splitlines()[0].split(",")
HEADERS = [
    ("tmy3", STATION[:6], "line 1: the TMY3 station line has 6 fields where it needs 7: it has no altitude"),
    ("tmy3", STATION[:6] + [""], "line 1, column 7: the altitude in the TMY3 station line is empty: it must be a number [m]"),
    ("tmy3", STATION[:5], "line 1: the TMY3 station line has 5 fields where it needs 7: it has no longitude or altitude"),
    ("tmy3", STATION[:3] + ["EST"] + STATION[4:], "line 1, column 4: the time zone in the TMY3 station line is “EST”: it must be a number [h]"),
    ("epw", LOCATION[:9], "line 1: the EPW LOCATION line has 9 fields where it needs 10: it has no altitude"),
    ("epw", LOCATION[:9] + ["  "], "line 1, column 10: the altitude in the EPW LOCATION line is empty: it must be a number [m]"),
    ("epw", LOCATION[:6] + ["north"] + LOCATION[7:], "line 1, column 7: the latitude in the EPW LOCATION line is “north”: it must be a number [°]"),
]  # fmt: skip


@pytest.mark.parametrize("kind, fields, says", HEADERS)
def test_a_weather_files_header_without_a_field_says_which_in_words(tmp_path, kind, fields, says):
    rows = (
        tmy3_lines()[1:30]
        if kind == "tmy3"
        else epw_text([(1990, 1, 1, h + 1, 4.0) for h in range(24)]).splitlines()[1:]
    )
    path = tmp_path / ("station.csv" if kind == "tmy3" else "station.epw")
    path.write_text("\n".join([",".join(fields), *rows]) + "\n")
    with pytest.raises(LabDataError) as error:
        read_weather(path)
    assert str(error.value) == says


def test_the_command_line_says_a_weather_files_missing_altitude_in_words(short_tmp_path):
    path = short_tmp_path / "greensboro.csv"
    path.write_text("\n".join([",".join(STATION[:6]), *tmy3_lines()[1:30]]) + "\n")
    done = subprocess.run(
        [sys.executable, "-m", "windpump", "supply", "--weather", str(path), "--demand", "1"],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert done.returncode == 1 and done.stdout == ""
    assert done.stderr.strip() == (
        f"windpump supply: error: --weather {path}: line 1: the TMY3 station line has 6 fields "
        "where it needs 7: it has no altitude"
    )


def test_a_missing_or_negative_tmy3_speed_is_said_as_a_number(tmp_path):
    lines = tmy3_lines()[:12]
    column = lines[1].split(",").index("Wspd (m/s)")
    for cell, says in (("", "the wind speed is missing"), ("-3", "the wind speed -3.0 m/s")):
        fields = lines[5].split(",")
        fields[column] = cell
        path = tmp_path / "speed.csv"
        path.write_text("\n".join(lines[:5] + [",".join(fields)] + lines[6:]) + "\n")
        with pytest.raises(LabDataError) as error:
            read_weather(path)
        assert str(error.value).startswith(f"line 6: {says}") and "np." not in str(error.value)


def test_a_records_refused_number_is_written_as_a_number():
    # numpy's repr (np.float64(nan)) is not what a user typed: the message writes the number
    t = np.arange(3, dtype=float)
    for V, says in (([1.0, np.nan, 2.0], "speeds[1] = nan"), ([1.0, -2.5, 2.0], "V[1] = -2.5 m/s")):
        with pytest.raises(ParameterError) as error:
            windpump.model.wind.as_record((t, np.asarray(V)), 2.0)
        assert says in str(error.value) and "np." not in str(error.value), str(error.value)
    with pytest.raises(ParameterError) as error:
        windpump.supply(windpump.Design.seed_example(), (np.array([0.0, 7200.0]), [3, 3]), 1, 0)
    assert "t[0] = 0.0 s" in str(error.value) and "np." not in str(error.value)
