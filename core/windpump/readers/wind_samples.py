"""A wind CSV's samples: times (seconds or ISO timestamps) and wind speeds, read a piece at a
time under the rules every reader shares (:mod:`windpump.readers.labdata`). The record they make
is :class:`windpump.WindRecord` (:func:`windpump.model.wind.read_csv`)."""

from __future__ import annotations

import dataclasses
import datetime
import math
import numbers
import operator
import os
from collections.abc import Iterator

import numpy as np

from ..errors import LabDataError, cut
from .labdata import _cells, _is_number, check_columns, contents, decoded, split_header

MAX_CSV_BYTES = 50_000_000
"""Largest wind file read [bytes] (a day at one sample a second takes about 1.5 MB)."""

MAX_WIND = 150.0
"""Fastest wind speed a record may hold [m/s] (the strongest gusts measured are about 113 m/s)."""

MAX_TIME = 1e12
"""Largest time a record may hold, either side of zero [s] (about 31,700 years): the core's
largest number (``validation.LARGEST``); two such times are still apart by a finite number."""

COLUMNS = "two columns: time [s] or an ISO timestamp, then wind speed [m/s]"


CHUNK = 1 << 20
"""Characters of a wind CSV's text parsed at a time (a piece ends at a line's end)."""


@dataclasses.dataclass(frozen=True)
class Samples:
    """A wind CSV's samples (:func:`read_samples`): times from the first [s], speeds [m/s], each
    one's line in the file (None unless asked for) and, for timestamps, its calendar month (None
    for seconds)."""

    t: np.ndarray
    V: np.ndarray
    line: np.ndarray | None
    month: np.ndarray | None


def read_samples(
    source: bytes | str | os.PathLike, max_bytes: int = MAX_CSV_BYTES, lines: bool = False
) -> Samples:
    """What :func:`read_csv` reads, with each sample's month and (if ``lines``) line in the file:
    a site's year needs them (:func:`windpump.read_weather`). Its rules, its errors.

    The whole-file checks come first, as the lab reader makes them (UTF-8, no NUL byte, not
    empty, the separator any line uses, a header); then the lines, a piece of ``CHUNK``
    characters at a time. A piece of plain samples is converted in bulk; one that is not (a
    quoted cell, a trailing separator, a bad line...) is read line by line, which says which
    line is at fault, in the same words.

    Examples
    --------
    >>> data = b"t,V\\n# calm\\n2026-01-31T23:00,4\\n2026-02-01T00:00,5\\n"
    >>> samples = read_samples(data, lines=True)
    >>> samples.t.tolist(), samples.line.tolist(), samples.month.tolist()
    ([0.0, 3600.0], [3, 4], [1, 2])
    """
    return parse_samples(decoded(contents(source, max_bytes, what=None)), lines)


def parse_samples(text: str, lines: bool = False) -> Samples:
    """:func:`read_samples` of a file's text, once read and decoded (``labdata.decoded``)."""
    first = next((row for piece in _pieces(text) for row in zip(*_kept(*piece), strict=True)), None)
    if first is None:
        raise LabDataError(f"the file is empty; it needs {COLUMNS}")
    separator = _separator(text)
    header, _rows = split_header(
        [(int(first[0]), _cells(first[1], separator))],
        lambda cell: _is_number(cell) or _time(cell) is not None,
        COLUMNS,
    )
    reader = _Reader(separator, lines)
    for piece in _pieces(text):
        numbers, rows = _kept(*piece)
        if header is not None and len(numbers) and numbers[0] == first[0]:
            numbers, rows = numbers[1:], rows[1:]
        reader.read(numbers, rows)
    return reader.samples()


def _pieces(text: str) -> Iterator[tuple[int, str, list[str]]]:
    """``text`` in pieces of about ``CHUNK`` characters, each ending at a line's end: the number
    of its first line, the piece and its lines (``str.splitlines``'s)."""
    start, number = 0, 1
    while start < len(text):
        end = _piece_end(text, start, CHUNK)
        piece = text[start:end]
        lines = piece.splitlines()
        yield number, piece, lines
        number += len(lines)
        start = end


def _piece_end(text: str, start: int, size: int) -> int:
    """Where a piece from ``start`` ends: after the last ``\\n`` or ``\\r`` (of a ``\\r\\n``,
    after both) within ``size`` characters, or the first beyond them; or the text's end."""
    end = start + size
    if end >= len(text):
        return len(text)
    cut = max(text.rfind("\n", start, end), text.rfind("\r", start, end))
    if cut < 0:  # a line longer than a piece
        found = [i for i in (text.find("\n", end), text.find("\r", end)) if i >= 0]
        if not found:
            return len(text)
        cut = min(found)
    if text.startswith("\r\n", cut):
        cut += 1
    return cut + 1


def _kept(start: int, piece: str, lines: list[str]) -> tuple[np.ndarray, list[str]]:
    """The numbers of a piece's lines that are neither blank nor a ``#`` comment, and those
    lines, stripped."""
    stripped = [line.strip() for line in lines]
    if "#" not in piece and "" not in stripped:  # (most pieces: every line kept)
        return np.arange(start, start + len(stripped)), stripped
    kept = [i for i, line in enumerate(stripped) if line and line[0] != "#"]
    return start + np.array(kept, dtype=np.int64), [stripped[i] for i in kept]


def _separator(text: str) -> str:
    """Tab, then ``;``, then ``,``: the first one a line of data (or the header) uses."""
    if "\t" not in text and ";" not in text:
        return ","
    semicolon = False
    for start, piece, lines in _pieces(text):
        if "\t" in piece or ";" in piece:
            kept = "\n".join(_kept(start, piece, lines)[1])
            if "\t" in kept:
                return "\t"
            semicolon = semicolon or ";" in kept
    return ";" if semicolon else ","


class _Reader:
    """The samples of a wind CSV's rows, read a piece at a time; the kind of time, the first
    sample's (the origin) and the last one's seconds carried from piece to piece. Each sample's
    line is kept when ``lines`` asks for it."""

    def __init__(self, separator: str, lines: bool):
        self.separator, self.lines = separator, lines
        self.kind: str | None = None
        self.origin: float | datetime.datetime | None = None
        self.last: float | None = None
        self.pieces: dict[str, list[np.ndarray]] = {"t": [], "V": [], "line": [], "month": []}

    def read(self, numbers: np.ndarray, rows: list[str]) -> None:
        """Read a piece's rows (stripped lines) and keep their samples."""
        if not rows:
            return
        t, V, month = self._in_bulk(rows) or self._line_by_line(numbers, rows)
        self.pieces["t"].append(t)
        self.pieces["V"].append(V)
        if month is not None and self.kind != "seconds":
            self.pieces["month"].append(month)
        if self.lines:  # (in 4 bytes a line while they fit)
            small = numbers[-1] < np.iinfo(np.int32).max
            self.pieces["line"].append(numbers.astype(np.int32) if small else numbers)

    def samples(self) -> Samples:
        """The samples of every piece read, each array joined once (its pieces then let go)."""
        count = sum(map(len, self.pieces["t"]))
        if count < 2:
            raise LabDataError(
                f"the file has {count} sample(s); a wind record needs at least 2 lines of {COLUMNS}"
            )
        joined = {}
        for name, pieces in self.pieces.items():
            joined[name] = np.concatenate(pieces) if pieces else None
            pieces.clear()
        t, V = joined["t"], joined["V"]
        assert t is not None and V is not None
        return Samples(t, V, joined["line"], joined["month"])

    def _in_bulk(self, rows: list[str]) -> tuple[np.ndarray, np.ndarray, np.ndarray | None] | None:
        """The piece's times, speeds and months if every row is two plain cells (no quotes, no
        space around the separator) of a time of the record's kind and a speed in range, in
        order; else None (then :meth:`_line_by_line` reads it)."""
        separators = list(map(operator.methodcaller("count", self.separator), rows))
        if separators.count(1) != len(separators):
            return None
        text = self.separator.join(rows)
        if self.separator != ",":
            text = text.replace(",", ".")  # decimal commas
        cells = text.split(self.separator)
        times, speeds = cells[0::2], cells[1::2]
        try:
            V = np.array(list(map(float, speeds)))
        except ValueError:
            return None
        if not np.all((V >= 0.0) & (V <= MAX_WIND)):  # (NaN fails too)
            return None
        month = None
        try:
            seconds = np.array(list(map(float, times)))
        except ValueError:
            moments = _timestamps(times)
            if moments is None:
                return None
            kinds = {_kind(moment) for moment in moments}
            kind = kinds.pop()
            if kinds or self.kind not in (None, kind):
                return None
            start = self.origin if isinstance(self.origin, datetime.datetime) else moments[0]
            seconds = np.array([(moment - start).total_seconds() for moment in moments])
            month = np.array([moment.month for moment in moments], dtype=np.int8)
            origin: float | datetime.datetime = start
        else:
            kind = "seconds"
            if not np.all(np.abs(seconds) <= MAX_TIME) or self.kind not in (None, kind):
                return None
            origin = self.origin if isinstance(self.origin, float) else float(seconds[0])
            seconds -= origin
        steps = np.diff(seconds, prepend=-np.inf if self.last is None else self.last)
        if not np.all(steps > 0.0):
            return None
        self.kind, self.origin, self.last = kind, origin, float(seconds[-1])
        return seconds, V, month

    def _line_by_line(
        self, numbers: np.ndarray, rows: list[str]
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The piece's times, speeds and months, a row at a time: the first row at fault raises
        its error."""
        t: list[float] = []
        V: list[float] = []
        months: list[int] = []
        for number, line in zip(numbers.tolist(), rows, strict=True):
            cells = _cells(line, self.separator)
            check_columns(number, cells, COLUMNS)
            moment = _time(cells[0])
            if moment is None:
                raise LabDataError(
                    f"'{_cut(cells[0])}' is neither seconds nor an ISO timestamp", number, 1
                )
            if isinstance(moment, float) and not abs(moment) <= MAX_TIME:
                raise LabDataError(
                    f"the time '{_cut(cells[0])}' is past {MAX_TIME:g} s either side of 0",
                    number,
                    1,
                )
            if self.kind is None:
                self.kind, self.origin = _kind(moment), moment
            elif _kind(moment) != self.kind:
                raise LabDataError(
                    f"'{_cut(cells[0])}' mixes {_kind(moment)} with {self.kind}", number, 1
                )
            speed = _speed(cells[1], number)
            seconds = _seconds(moment, self.origin)
            if self.last is not None and seconds <= self.last:
                raise LabDataError(
                    f"the time '{_cut(cells[0])}' does not come after the line before", number, 1
                )
            self.last = seconds
            t.append(seconds)
            V.append(speed)
            months.append(moment.month if isinstance(moment, datetime.datetime) else 0)
        return np.array(t), np.array(V), np.array(months, dtype=np.int8)


def _timestamps(cells: list[str]) -> list[datetime.datetime] | None:
    """The cells as timestamps, if every one is one and none is a number (``20260601`` is
    seconds, as :func:`_time` reads it); else None."""
    if any(map(str.isdigit, cells)):
        return None
    try:
        return [datetime.datetime.fromisoformat(cell.replace(" ", "T", 1)) for cell in cells]
    except ValueError:
        return None


def _time(cell: str) -> float | datetime.datetime | None:
    """Seconds (a finite number) or a timestamp, or None."""
    if _is_number(cell):
        value = float(cell)
        return value if math.isfinite(value) else None
    try:
        return datetime.datetime.fromisoformat(cell.replace(" ", "T", 1))
    except ValueError:
        return None


def _kind(moment: float | datetime.datetime) -> str:
    if isinstance(moment, numbers.Real):
        return "seconds"
    assert isinstance(moment, datetime.datetime)
    return "timestamps without a zone" if moment.tzinfo is None else "timestamps with a zone"


def _seconds(moment, origin) -> float:
    if isinstance(moment, datetime.datetime):
        return (moment - origin).total_seconds()
    return float(moment - origin)


def _speed(cell: str, line: int) -> float:
    try:
        value = float(cell)
    except ValueError:
        raise LabDataError(f"'{_cut(cell)}' is not a number", line, 2) from None
    if not 0.0 <= value <= MAX_WIND:  # (NaN fails too)
        raise LabDataError(
            f"the wind speed '{_cut(cell)}' is not a number from 0 to {MAX_WIND:g} m/s", line, 2
        )
    return value


def _cut(cell: str) -> str:
    return cut(cell, 20)
