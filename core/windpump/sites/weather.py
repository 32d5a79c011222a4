"""A site's year of wind from a weather file: TMY3 and EPW (read by pvlib, the optional extra
``site``) or the wind CSV the Wind tab reads, and the two typical years pvlib ships.

Typical meteorological years (TMY3, and EPW made from them) give one hour per line, 8760 lines,
each labelled at the end of its hour (``01:00`` is the hour from midnight), each month taken from a
different real year. A record keeps the times from its first hour [s], the wind speeds [m/s], the
anemometer's height (10 m in these files) and the calendar month each hour lies in (the month of
the hour's start: its label less one hour).
"""

from __future__ import annotations

import math
import os
import re
from pathlib import Path

import numpy as np

from ..errors import LabDataError, ParameterError, cut, shown
from ..model.wind import COLUMNS, MAX_CSV_BYTES, MAX_HEIGHT, MAX_WIND, WindRecord, parse_samples
from ..readers import files
from ..readers.labdata import decoded
from ..units import SECONDS_PER_HOUR
from ..validation import real

__all__ = [
    "SITES",
    "read_weather",
    "sample_site",
]

# What a weather file must hold, said when it holds nothing.
NEEDED = f"a TMY3 or EPW weather file, or {COLUMNS}"
SITES = {"greensboro": "723170TYA.CSV", "sand_point": "703165TY.csv"}
"""The typical years in pvlib's wheel (``pvlib/data``): Greensboro, North Carolina (mean wind
about 3.1 m/s) and Sand Point, Alaska (about 5.1 m/s)."""

TMY3_HEADER_LINES = 2
"""Lines before a TMY3 file's first hour: the station's line and the columns' names."""

EPW_HEADER_LINES = 8
"""Lines before an EPW file's first hour (LOCATION, DESIGN CONDITIONS, ..., DATA PERIODS)."""

EPW_MISSING_WIND = 999.0
"""EPW's code for a missing wind speed."""

ANEMOMETER = 10.0
"""Height of the wind speeds in TMY3 and EPW files [m] (the meteorological standard)."""


def pvlib_iotools():
    """``pvlib.iotools``, or a ModuleNotFoundError naming the extra that installs it."""
    try:
        from pvlib import iotools
    except ImportError:
        raise ModuleNotFoundError(
            "reading TMY3 and EPW weather files needs pvlib: pip install 'windpump[site]'"
        ) from None
    return iotools


def sample_site(site: str) -> WindRecord:
    """The typical year of wind at one of the sites whose TMY3 file pvlib ships.

    Parameters
    ----------
    site : {"greensboro", "sand_point"}
        Greensboro, North Carolina (TMY3 station 723170, mean wind about 3.1 m/s at 10 m) or
        Sand Point, Alaska (703165, about 5.1 m/s).

    Returns
    -------
    WindRecord
        8760 hourly speeds at 10 m, with their months, named after the station.

    Raises
    ------
    ParameterError
        For another name.
    ModuleNotFoundError
        Without pvlib (``pip install 'windpump[site]'``).

    Examples
    --------
    >>> record = sample_site("greensboro")
    >>> len(record.t), round(float(record.V.mean()), 2), record.height
    (8760, 3.05, 10.0)
    """
    if not isinstance(site, str) or site not in SITES:
        raise ParameterError("site", site, "one of " + ", ".join(map(repr, SITES)))
    iotools = pvlib_iotools()
    import pvlib

    path = Path(pvlib.__file__).parent / "data" / SITES[site]
    return _tmy3(iotools, path.read_text(encoding="utf-8", errors="replace"), site)


def read_weather(
    source: str | os.PathLike | bytes, height: float | None = None, name: str | None = None
) -> WindRecord:
    """A wind record from a weather file: TMY3, EPW, or the Wind tab's two-column CSV.

    TMY3 (a first line of 7 fields, the station's) is read by ``pvlib.iotools.read_tmy3``, EPW
    (a first line ``LOCATION,...``, or a name ending in ``.epw``) by ``pvlib.iotools.read_epw``;
    their speeds are at 10 m and every hour keeps its calendar month. Anything else is the
    Wind tab's CSV (:func:`windpump.model.wind.read_csv`: time in seconds or ISO timestamps, then
    speed), whose months are those of its timestamps (none for seconds). The file is read here,
    through the guard every reader goes through (:func:`windpump.readers.files.read_bytes`: a regular
    file only, never waiting on a pipe, at most ``MAX_CSV_BYTES``), and handed to pvlib as text,
    never as a name it could fetch.

    Parameters
    ----------
    source : str, PathLike or bytes
        The file's path, or its contents as bytes (an upload). A ``str`` is a path: one that
        cannot be (a line break: contents; a NUL byte; over ``files.MAX_PATH`` characters) is
        refused.
    height : float, optional
        The anemometer's height [m], > 0: the CSV's (10 m by default); a weather file's own is
        10 m, which this replaces.
    name : str, optional
        The site's name; by default the station's (TMY3, EPW) or the file's stem (CSV; "" for
        contents).

    Returns
    -------
    WindRecord

    Raises
    ------
    LabDataError
        (a ValueError) naming the line at fault: a missing or out-of-range speed (EPW's 999
        included), an hour that repeats or is skipped (a gap), a TMY3 station line or EPW
        LOCATION line short of a field (which) or with a word where a number goes (line 1, its
        column); or a file that is missing, not a
        regular file (a pipe, a folder, a device), cannot be read or is over ``MAX_CSV_BYTES``,
        or an empty one (saying what it needs: ``NEEDED``).
    ParameterError
        (a ValueError) naming ``source``: neither bytes nor a path, or a ``str`` that cannot be
        a path (a file's contents, a NUL byte, over ``files.MAX_PATH`` characters).
    ModuleNotFoundError
        For TMY3 or EPW without pvlib (``pip install 'windpump[site]'``).

    Examples
    --------
    >>> record = read_weather(b"2026-03-31T23:00,4.0\\n2026-04-01T00:00,5.5\\n", height=20.0)
    >>> record.t.tolist(), record.month.tolist(), record.height
    ([0.0, 3600.0], [3, 4], 20.0)
    """
    if height is not None:
        height = _height(height)
    data, stem, suffix = _contents(source)
    if _blank(data):
        raise LabDataError(f"the file is empty; it needs {NEEDED}")
    first, second = _first_lines(data)
    kind = _kind(first, suffix, second)
    if kind == "csv":
        text = decoded(data)
        del data  # (a record near the limit: its bytes are let go before it is parsed)
        samples = parse_samples(text, lines=True)
        steps = np.diff(samples.t)
        for i in np.flatnonzero(steps > SECONDS_PER_HOUR)[:1]:
            raise LabDataError(
                f"a gap of {steps[i] / SECONDS_PER_HOUR:.4g} h after the line before "
                "(a site's year needs a sample in every hour)",
                None if samples.line is None else int(samples.line[i + 1]),
            )
        for array in (samples.t, samples.V, samples.month):
            if array is not None:
                array.flags.writeable = False  # (frozen where they are: a year is 10^7 samples)
        record = WindRecord(samples.t, samples.V, ANEMOMETER, stem, samples.month)
    else:
        _check_header(first, kind)
        iotools = pvlib_iotools()
        reader = _tmy3 if kind == "tmy3" else _epw
        record = reader(iotools, data.decode("utf-8", errors="replace"), stem or kind.upper())
    return WindRecord(
        record.t,
        record.V,
        record.height if height is None else height,
        record.name if name is None else str(name),
        record.month,
    )


def _contents(source) -> tuple[bytes, str, str]:
    """The bytes of ``source`` (at most ``MAX_CSV_BYTES``, through the guard), its stem and
    suffix ("" for bytes)."""
    data = files.read_bytes(source, MAX_CSV_BYTES)
    if isinstance(source, bytes | bytearray | memoryview):
        return data, "", ""
    path = Path(os.fsdecode(os.fspath(source)))
    return data, path.stem, path.suffix.lower()


_NOT_SPACE = re.compile(rb"[^ \t\n\r\x0b\x0c\x1c-\x1f]")
"""A byte that is not ASCII white space (as ``str.isspace`` has it)."""


def _blank(data: bytes) -> bool:
    """Whether the file's text is white space only (as its decoded text's ``strip`` says),
    without decoding a large file to find out."""
    found = _NOT_SPACE.search(data)
    if found is None:
        return True
    if data[found.start()] < 0x80:
        return False
    return not data.decode("utf-8", errors="replace").strip()  # (U+00A0, U+3000 ...)


def _first_lines(data: bytes) -> tuple[str, str]:
    """The file's first two lines (each to its ``\\n``; "" if there is none), as text."""
    lines = data[: 1 << 16].split(b"\n", 2)[:2] + [b""]
    return lines[0].decode("utf-8", errors="replace"), lines[1].decode("utf-8", errors="replace")


def _height(height: object) -> float:
    value = real("height", height, "m")
    if not 0.0 < value <= MAX_HEIGHT:
        raise ParameterError("height", value, f"a height > 0 and <= {MAX_HEIGHT:g}", "m")
    return value


def _kind(first: str, suffix: str, second: str = "") -> str:
    """'tmy3', 'epw' or 'csv', from the file's first line (and an EPW's name, or a TMY3's second
    line, its columns' names: a TMY3 whose first line lacks a field is still one)."""
    if first.upper().startswith("LOCATION,") or suffix == ".epw":
        return "epw"
    fields = first.strip().split(",")
    if fields[0].strip().isdigit() and (len(fields) == 7 or second.startswith(TMY3_COLUMNS)):
        return "tmy3"
    return "csv"


def _tmy3(iotools, text: str, stem: str) -> WindRecord:
    data, meta = _read(iotools.read_tmy3, text, map_variables=True)
    data = _last_in_its_year(data)
    station = str(meta.get("Name", "")).strip().strip('"').strip()
    state = str(meta.get("State", "")).strip()
    name = f"{station}, {state}" if station and state else station or stem
    return _hourly(data, data["wind_speed"], name, text, TMY3_HEADER_LINES, labelled_at_end=True)


def _epw(iotools, text: str, stem: str) -> WindRecord:
    data, meta = _read(iotools.read_epw, text)
    parts = [str(meta.get(key, "")).strip() for key in ("city", "state-prov", "country")]
    name = ", ".join(part for part in parts if part and part != "-") or stem
    speed = data["wind_speed"].to_numpy(dtype=float)
    missing = np.flatnonzero(speed >= EPW_MISSING_WIND)
    if missing.size:
        line = EPW_HEADER_LINES + int(missing[0]) + 1
        raise LabDataError(f"the wind speed is missing (EPW's {EPW_MISSING_WIND:g})", line)
    return _hourly(data, data["wind_speed"], name, text, EPW_HEADER_LINES, labelled_at_end=False)


HEADER_FIELDS = {
    "USAF": "station number (USAF)",
    "Name": "station name",
    "State": "state",
    "TZ": "time zone",
    "latitude": "latitude",
    "longitude": "longitude",
    "altitude": "altitude",
    "loc": "LOCATION",
    "city": "city",
    "state-prov": "state or province",
    "country": "country",
    "data_type": "data source",
    "WMO_code": "WMO station number",
}
"""The fields of a TMY3's first line and an EPW's LOCATION line, as pvlib's readers name them,
and in words."""


TMY3_COLUMNS = "Date (MM/DD/YYYY),Time (HH:MM),"
"""How a TMY3 file's second line, its columns' names, begins."""

HEADER_ORDER = {
    "tmy3": ("USAF", "Name", "State", "TZ", "latitude", "longitude", "altitude"),
    "epw": (
        "loc", "city", "state-prov", "country", "data_type", "WMO_code", "latitude", "longitude",
        "TZ", "altitude",
    ),
}  # fmt: skip
"""The fields of a TMY3's first line and an EPW's LOCATION line in their order, as pvlib's
readers name them (they take them by position)."""

NUMBERS = {"USAF": "a whole number", "TZ": "a number [h]", "latitude": "a number [°]"}
NUMBERS |= {"longitude": "a number [°]", "altitude": "a number [m]"}
"""The header's fields pvlib reads as numbers, and what each must be."""


def _check_header(first: str, kind: str) -> None:
    """A TMY3's first line or an EPW's LOCATION line as pvlib reads it (split at every comma), or
    a LabDataError at line 1 that says in words which fields are missing, or which one is not a
    number: pvlib would say ``KeyError: 'altitude'`` or ``could not convert string to float``."""
    names = HEADER_ORDER[kind]
    fields = first.rstrip("\n").split(",")
    what = "the TMY3 station line" if kind == "tmy3" else "the EPW LOCATION line"
    if len(fields) < len(names):
        missing = [HEADER_FIELDS[name] for name in names[len(fields) :]]
        listed = missing[0] if len(missing) == 1 else f"{', '.join(missing[:-1])} or {missing[-1]}"
        raise LabDataError(
            f"{what} has {len(fields)} fields where it needs {len(names)}: it has no {listed}", 1
        )
    for column, (name, field) in enumerate(zip(names, fields, strict=False), start=1):
        if name in NUMBERS and not _a_number(field, whole=name == "USAF"):
            said = f"“{cut(field.strip(), 40)}”" if field.strip() else "empty"
            raise LabDataError(
                f"the {HEADER_FIELDS[name]} in {what} is {said}: it must be {NUMBERS[name]}",
                1,
                column,
            )


def _a_number(text: str, whole: bool) -> bool:
    """Whether pvlib reads ``text`` as a finite number (``int`` for a whole one, else ``float``)."""
    try:
        value = int(text) if whole else float(text)
    except ValueError:
        return False
    return math.isfinite(value)


def _read(reader, text: str, **options):
    """pvlib's reader on the file's text, its year coerced to one so the hours increase (a
    typical year mixes years across months); its failures as a LabDataError in words: a missing
    field of the header or column of the hours named as what it is."""
    import io

    try:
        return reader(io.StringIO(text), coerce_year=2001, **options)  # not a leap year, as TMY
    except KeyError as error:
        key = str(error.args[0]) if error.args else ""
        if key in HEADER_FIELDS:
            raise LabDataError(
                f"the file's header has no {HEADER_FIELDS[key]} field: is it a TMY3 or EPW file?"
            ) from None
        raise LabDataError(
            f"the file has no column “{cut(key, 60)}”: is it a TMY3 or EPW file?"
        ) from None
    except (ValueError, IndexError, TypeError) as error:
        message = cut(" ".join(str(error).split()), 200)
        raise LabDataError(f"not a TMY3 or EPW file pvlib can read ({message})") from None


def _last_in_its_year(data):
    """pvlib's TMY3 hours with the last one back in the year it belongs to. With its year
    coerced, pvlib moves the file's last line to the next year, right only for a year's last hour
    (``12/31,24:00``, the next year's midnight); a shorter file's last hour (``01/31,24:00``)
    would be a year after the one before it. It goes back a year unless that puts it at or
    before the hour before it."""
    import pandas

    if len(data.index) < 2:
        return data
    index = data.index
    last = index[-1] - pandas.DateOffset(years=1)
    if last <= index[-2]:
        return data
    data = data.copy()
    data.index = index[:-1].append(pandas.DatetimeIndex([last], tz=index.tz))
    return data


def _hourly(
    data, speed, name: str, text: str, header_lines: int, labelled_at_end: bool
) -> WindRecord:
    """The record of an hourly file (``text``), checked line by line. pvlib labels a TMY3 hour at
    its end (as the file does: its month is the label's less an hour), an EPW hour at its start
    (it takes an hour off the file's end label). A line at fault is quoted by its own date and
    hour, not pvlib's (whose year is coerced to one)."""
    V = speed.to_numpy(dtype=float)
    if V.size == 0:
        raise LabDataError(f"the file has no hours after its header ({header_lines} lines)")
    index = data.index
    seconds = (index - index[0]).total_seconds().to_numpy(dtype=float)
    for i in np.flatnonzero(~np.isfinite(V) | (V < 0.0) | (V > MAX_WIND))[:1]:
        said = (
            "is missing (not a number)"
            if np.isnan(V[i])
            else f"{shown(V[i])} m/s is outside 0 to {MAX_WIND:g} m/s"
        )
        raise LabDataError(
            f"the wind speed {said}",
            header_lines + int(i) + 1,
        )
    steps = np.diff(seconds)
    for i in np.flatnonzero(steps != SECONDS_PER_HOUR)[:1]:
        what = "skips an hour or more" if steps[i] > 0 else "does not come after the line before"
        line = header_lines + int(i) + 2
        raise LabDataError(f"the hour {_when(text, line, labelled_at_end)} {what}", line)
    month = ((index - _HOUR) if labelled_at_end else index).month.to_numpy(dtype=np.int8)
    return WindRecord(_frozen(seconds), _frozen(V), ANEMOMETER, name, _frozen(month, np.int8))


def _when(text: str, line: int, tmy3: bool) -> str:
    """A weather file's line's own date and hour, as the file writes them: a TMY3's
    ``MM/DD/YYYY,HH:MM``, an EPW's ``year,month,day,hour,minute``."""
    fields = text.splitlines()[line - 1].split(",")
    return "“" + ",".join(field.strip() for field in fields[: 2 if tmy3 else 5]) + "”"


def _frozen(values, dtype=float) -> np.ndarray:
    array = np.array(values, dtype=dtype)
    array.flags.writeable = False
    return array


class _Hour:
    """One hour as pandas' Timedelta, made on first use (pandas is imported only with pvlib)."""

    def __rsub__(self, index):
        import pandas

        return index - pandas.Timedelta(hours=1)


_HOUR = _Hour()
