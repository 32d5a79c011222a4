"""Reading a measured torque curve (windmill speed, torque) from a CSV file, for Eq. (11)'s fit.

Lab files come from spreadsheets in several locales: comma, semicolon or tab separated, decimal
points or commas, with or without a header row. Every problem is reported with the line and
column at fault, in words a student can act on; nothing is guessed silently.
"""

from __future__ import annotations

import dataclasses
import math
import os
import re

import numpy as np

from ..errors import LabDataError, cut
from . import files

__all__ = [
    "MAX_BYTES",
    "TorqueTable",
    "check_file_size",
    "read_torque_csv",
]


MAX_BYTES = 1_000_000
"""Largest lab file read [bytes]; a larger one is refused before it is parsed."""

COLUMNS = "two columns: windmill speed [rad/s], then torque [N·m]"


@dataclasses.dataclass(frozen=True)
class TorqueTable:
    """Measured windmill speeds [rad/s] and torques [N m], and the header's names if there was one."""

    omega: np.ndarray
    torque: np.ndarray
    header: tuple[str, ...] | None

    @property
    def power(self) -> np.ndarray:
        """The measured shaft power T omega at each measurement [W] (Eq. 5's windmill side).

        Examples
        --------
        >>> read_torque_csv(b"10,0.2\\n50,0.6\\n90,0.2\\n").power.tolist()
        [2.0, 30.0, 18.0]
        """
        return self.omega * self.torque


def read_torque_csv(source: bytes | str | os.PathLike, max_bytes: int = MAX_BYTES) -> TorqueTable:
    """Read a CSV of windmill speed [rad/s] and torque [N m], one measurement per line.

    Separators ``,``, ``;`` or tab; with ``;`` or tab a decimal comma is read as a point. One
    header row of names may come first (a row is a header when its cells name columns: see
    :func:`split_header`); lines starting with ``#`` and blank lines are skipped.

    Parameters
    ----------
    source : bytes, str or path
        The file's content (bytes, or text with a line break) or its path (a ``str`` without a
        line break, or a path object), read by the guard every reader goes through
        (:func:`windpump.readers.files.read_bytes`): only a regular file, at most ``max_bytes`` + 1 bytes
        of it.
    max_bytes : int, default MAX_BYTES
        A longer file is refused before it is parsed [bytes].

    Raises
    ------
    LabDataError
        (a ValueError) saying what is wrong and where: no such file, not a regular file (a pipe,
        a folder, a device), an empty or over-long file, text that is not UTF-8 or holds a NUL
        byte, a line with other than two columns, a cell that is not a finite number (``0.216x``
        in the first row too), a negative speed, a header that names torque before speed, fewer
        than three measurements.
    ParameterError
        (a ValueError) for a path that cannot be one: a NUL byte, over ``files.MAX_PATH``
        characters.

    Examples
    --------
    >>> table = read_torque_csv(b"speed;torque\\n10;0,216\\n50;0,6\\n90;0,216\\n")
    >>> table.omega.tolist(), table.torque.tolist(), table.header
    ([10.0, 50.0, 90.0], [0.216, 0.6, 0.216], ('speed', 'torque'))
    """
    rows = read_rows(source, max_bytes, COLUMNS)
    first_line = rows[0][0]
    header, rows = split_header(rows, _is_number, COLUMNS)
    if header is not None:
        _check_header(first_line, header)
    values = np.array([_row(number, cells) for number, cells in rows]).reshape(-1, 2)
    if len(values) < 3:
        raise LabDataError(f"the file has {len(values)} measurement(s); the fit needs at least 3")
    return TorqueTable(omega=values[:, 0], torque=values[:, 1], header=header)


def read_rows(source, max_bytes: int, columns: str) -> list[tuple[int, list[str]]]:
    """A CSV's rows as (line number, cells): UTF-8 text, ``#`` comments and blank lines skipped,
    the separator found (tab, then ``;``, then ``,``; decimal commas read as points with the first
    two). The rules every file this package reads follows; ``columns`` says what an empty file
    needed.

    Raises
    ------
    LabDataError
        For a file over ``max_bytes``, not UTF-8 text, holding a NUL byte, or empty.
    """
    text = decoded(contents(source, max_bytes))
    lines = [
        (number, line.strip())
        for number, line in enumerate(text.splitlines(), start=1)
        if line.strip() and not line.lstrip().startswith("#")
    ]
    if not lines:
        raise LabDataError(f"the file is empty; it needs {columns}")
    separator = _separator(line for _, line in lines)
    return [(number, _cells(line, separator)) for number, line in lines]


def decoded(data: bytes) -> str:
    """A CSV's bytes as text: UTF-8 (a byte-order mark dropped) without a NUL byte.

    Raises
    ------
    LabDataError
        For bytes that are not UTF-8 (naming the first that is not) or hold a NUL byte (naming
        its line): a spreadsheet's own format or UTF-16, not CSV.
    """
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        raise LabDataError(
            f"the file is not text (byte {error.start + 1} is not UTF-8); save it as CSV"
        ) from None
    if "\x00" in text:  # UTF-16, or a spreadsheet's binary format
        line = text.count("\n", 0, text.index("\x00")) + 1
        raise LabDataError("the file is not text (it holds a NUL byte); save it as CSV", line)
    return text


def split_header(
    rows: list[tuple[int, list[str]]], is_value, columns: str
) -> tuple[tuple[str, ...] | None, list[tuple[int, list[str]]]]:
    """The first row as a header if it names the columns, and the rows of data.

    A header is recognised by what it says, not by failing to parse as data: none of its cells is
    a value (``is_value``) or starts like a number (``0.216x`` is a number with a typo), and one
    at least holds a letter. Any other first row is data, checked like the rest.

    Raises
    ------
    LabDataError
        For a header that does not name two columns (naming the line and the column at fault).

    Examples
    --------
    >>> split_header([(1, ["speed", "torque"]), (2, ["10", "0.2"])], _is_number, "")[0]
    ('speed', 'torque')
    >>> split_header([(1, ["10", "0.216x"]), (2, ["50", "0.6"])], _is_number, "")[0] is None
    True
    """
    number, cells = rows[0]
    values = [cell for cell in cells if is_value(cell) or _starts_like_a_number(cell)]
    if values or not any(letter.isalpha() for cell in cells for letter in cell):
        return None, rows
    check_columns(number, cells, columns)
    return tuple(cells), rows[1:]


def check_columns(line: int, cells: list[str], columns: str) -> None:
    """Refuse a row of other than two cells, naming its line and the column at fault (the third,
    or the missing second)."""
    if len(cells) != 2:
        raise LabDataError(
            f"{len(cells)} column{'s' if len(cells) > 1 else ''} where the file needs {columns}",
            line,
            3 if len(cells) > 2 else 2,
        )


def check_file_size(size: int, max_bytes: int = MAX_BYTES, what: str = "a torque curve") -> None:
    """Refuse a lab file of ``size`` bytes before reading it, if it is larger than ``max_bytes``.

    A page checks the size of a chosen file before sending it (a 50 MB file would otherwise
    close the page's connection) and reports a refusal in these same words.

    Parameters
    ----------
    size : int
        The file's size [bytes].
    max_bytes : int, default MAX_BYTES
        The largest file read [bytes].
    what : str, default "a torque curve"
        What the file holds, for the message.

    Raises
    ------
    LabDataError
        If ``size > max_bytes``, saying both.

    Examples
    --------
    >>> check_file_size(2_000)
    >>> check_file_size(52_428_800)
    Traceback (most recent call last):
    ...
    windpump.errors.LabDataError: the file has 52,428,800 bytes; at most 1,000,000 are read (a torque curve needs far fewer)
    """
    files.check_size(size, max_bytes, what)


def contents(
    source: bytes | str | os.PathLike, max_bytes: int, what: str | None = "a torque curve"
) -> bytes:
    """The bytes of a CSV reader's ``source``: text holding a line break is the file's contents
    (as the lab and wind readers have always taken it), anything else goes through the one guard,
    :func:`windpump.readers.files.read_bytes` (bytes, or the path of a regular file of at most
    ``max_bytes``)."""
    if isinstance(source, str) and ("\n" in source or "\r" in source):
        source = source.encode("utf-8")
    return files.read_bytes(source, max_bytes, what=what)


read_file = files.read_bytes
"""The guard, by the name it had here before it was :func:`windpump.readers.files.read_bytes`."""


def _separator(lines) -> str:
    """Tab, then semicolon, then comma: the first one any line uses."""
    text = "\n".join(lines)
    return next((s for s in ("\t", ";") if s in text), ",")


def _cells(line: str, separator: str) -> list[str]:
    cells = [cell.strip().strip('"').strip() for cell in line.split(separator)]
    if separator != ",":
        cells = [cell.replace(",", ".") for cell in cells]  # decimal commas
    while len(cells) > 2 and cells[-1] == "":
        cells.pop()  # a trailing separator
    return cells


def _is_number(cell: str) -> bool:
    try:
        float(cell)
    except ValueError:
        return False
    return True


def _starts_like_a_number(cell: str) -> bool:
    """``12``, ``-0.5x``, ``.5``, ``2026-06-01T…``: a digit after an optional sign and point."""
    return re.match(r"[+-]?\.?\d", cell) is not None


def _check_header(line: int, names: tuple[str, ...]) -> None:
    lowered = [name.lower() for name in names]
    if len(lowered) >= 2 and "torque" in lowered[0] and "torque" not in lowered[1]:
        raise LabDataError(
            f"the header names torque first ({cut(', '.join(names))}); the file needs {COLUMNS}",
            line,
        )


def _row(line: int, cells: list[str]) -> tuple[float, float]:
    check_columns(line, cells, COLUMNS)
    numbers = []
    for column, cell in enumerate(cells, start=1):
        try:
            value = float(cell)
        except ValueError:
            raise LabDataError(f"'{cut(cell, 20)}' is not a number", line, column) from None
        if not math.isfinite(value):
            raise LabDataError(f"'{cut(cell, 20)}' is not a finite number", line, column)
        numbers.append(value)
    if numbers[0] < 0:
        raise LabDataError(f"the speed {numbers[0]:g} rad/s is negative", line, 1)
    return numbers[0], numbers[1]
