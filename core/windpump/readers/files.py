"""The one guard every reader of a user's file goes through: :func:`read_bytes`.

A weather file (:func:`windpump.read_weather`), a wind record (:func:`windpump.model.wind.read_csv`), a
lab torque file (:func:`windpump.read_torque_csv`), a design file or a table of designs on the
command line: each takes the file's contents as bytes, or its path, and reads it here. The rules:

- **bytes are contents, a str or path object is a path.** A ``str`` that cannot be a path is
  refused, not looked for on the disk: one holding a line break (a file's contents: pass them as
  bytes), a NUL byte, or more than ``MAX_PATH`` characters.
- **A regular file only.** A pipe, a folder, a device or a socket is refused without being read
  and without waiting: it is looked at before it is opened, opened without blocking (a pipe
  without a writer would wait for one for ever) and looked at again once open.
- **At most ``max_bytes``.** A larger file is refused by its size before it is read, and at most
  ``max_bytes`` + 1 bytes are ever read (a file whose size says less than it holds, or one that
  grows meanwhile, is refused too).
- **Errors in words, of bounded length.** A path that cannot be one raises
  :class:`~windpump.errors.ParameterError` naming the parameter, showing at most ~80 characters
  of the value and saying the limit; a file that is missing, not a regular file, unreadable or too
  large raises :class:`~windpump.errors.LabDataError` naming the file (cut to ~80 characters).
  Both are ValueErrors; no bare OSError, UnicodeEncodeError or other ValueError comes out.
"""

from __future__ import annotations

import os
import stat

from ..errors import LabDataError, ParameterError, cut

__all__ = [
    "MAX_PATH",
    "check_size",
    "read_bytes",
]


MAX_PATH = 4096
"""Longest path read [characters] (Linux's PATH_MAX, in bytes, is as long)."""

KINDS = (
    (stat.S_ISDIR, "folder"),
    (stat.S_ISFIFO, "pipe"),
    (stat.S_ISCHR, "device"),
    (stat.S_ISBLK, "device"),
    (stat.S_ISSOCK, "socket"),
)


def read_bytes(
    source: bytes | bytearray | memoryview | str | os.PathLike,
    max_bytes: int,
    *,
    name: str = "source",
    what: str | None = None,
) -> bytes:
    """The contents of ``source``: itself if bytes, else the regular file at that path.

    Parameters
    ----------
    source : bytes, bytearray, memoryview, str or path object
        The file's contents (any bytes-like object), or its path (a ``str`` or an
        ``os.PathLike``). A ``str`` holding a line break or a NUL byte, or longer than
        ``MAX_PATH`` characters, cannot be a path and is refused.
    max_bytes : int
        The most bytes accepted [bytes]; a larger file (or larger contents) is refused.
    name : str, default "source"
        The parameter's name in an error about the path (a command line's option, say).
    what : str, optional
        What the file holds, said when it is too large ("a year of hourly weather"...).

    Returns
    -------
    bytes
        At most ``max_bytes`` of them.

    Raises
    ------
    ParameterError
        (a ValueError) for a ``source`` that is neither bytes nor a path, or a path that cannot be
        one: with a line break, a NUL byte, more than ``MAX_PATH`` characters, or characters the
        file system cannot name.
    LabDataError
        (a ValueError) for a path where there is no file, or not a regular file (a folder, a pipe,
        a device, a socket), or one that cannot be read or holds more than ``max_bytes`` bytes.

    Examples
    --------
    >>> read_bytes(b"0,4\\n3600,5\\n", 100)
    b'0,4\\n3600,5\\n'
    >>> read_bytes("0,4\\n3600,5\\n", 100)
    Traceback (most recent call last):
    ...
    windpump.errors.ParameterError: source = '0,4\\n3600,5\\n' is not allowed: source must be a file's path, without a line break (a file's contents are passed as bytes)
    >>> read_bytes("lab\\x00.csv", 100, name="--weather")
    Traceback (most recent call last):
    ...
    windpump.errors.ParameterError: --weather = 'lab\\x00.csv' is not allowed: --weather must be a file's path, without a NUL byte
    >>> read_bytes(".", 100)
    Traceback (most recent call last):
    ...
    windpump.errors.LabDataError: '.' is not a regular file but a folder; it cannot be read
    """
    if isinstance(source, bytes | bytearray | memoryview):
        data = bytes(source)
        check_size(len(data), max_bytes, what)
        return data
    path = _path(source, name)
    return _read_file(path, max_bytes, what)


def check_size(size: int, max_bytes: int, what: str | None = None) -> None:
    """Refuse a file of ``size`` bytes if it is larger than ``max_bytes``, saying both (and what
    the file holds, if ``what`` says it).

    Raises
    ------
    LabDataError
        If ``size > max_bytes``.

    Examples
    --------
    >>> check_size(2_000, 1_000_000)
    >>> check_size(52_428_800, 1_000_000, "a torque curve")
    Traceback (most recent call last):
    ...
    windpump.errors.LabDataError: the file has 52,428,800 bytes; at most 1,000,000 are read (a torque curve needs far fewer)
    """
    if size > max_bytes:
        message = f"the file has {size:,} bytes; at most {max_bytes:,} are read"
        raise LabDataError(f"{message} ({what} needs far fewer)" if what else message)


def _path(source: object, name: str) -> str | bytes:
    """``source`` as a path for ``os.open``, if it can be one."""
    if not isinstance(source, str | os.PathLike):
        raise ParameterError(name, source, "bytes (a file's contents) or a path (str or PathLike)")
    try:
        path = os.fspath(source)
    except TypeError:  # an os.PathLike whose __fspath__ returns neither
        raise ParameterError(name, source, "a path (str or PathLike)") from None
    text = os.fsdecode(path) if isinstance(path, bytes) else path
    if isinstance(source, str) and ("\n" in text or "\r" in text):
        raise ParameterError(
            name, source, "a file's path, without a line break",
            why="a file's contents are passed as bytes",
        )  # fmt: skip
    if "\x00" in text:
        raise ParameterError(name, source, "a file's path, without a NUL byte")
    if len(text) > MAX_PATH:
        raise ParameterError(name, source, f"a path of at most {MAX_PATH:,} characters")
    try:
        os.fsencode(text)
    except UnicodeError:  # a lone surrogate, say
        raise ParameterError(
            name, source, "a path the file system can name (it cannot encode these characters)"
        ) from None
    return path


def _read_file(path: str | bytes, max_bytes: int, what: str | None) -> bytes:
    """The bytes of the regular file at ``path``: at most ``max_bytes`` + 1 of them are read."""
    named = f"'{cut(os.fsdecode(path))}'"
    try:
        _check_regular(os.stat(path), named)  # before opening: a device may act on an open
        flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0)
        descriptor = os.open(path, flags)  # not blocking: a pipe would wait for a writer
        with open(descriptor, "rb", buffering=0) as file:
            status = os.fstat(descriptor)
            _check_regular(status, named)  # what was opened: it may have been swapped meanwhile
            check_size(status.st_size, max_bytes, what)
            wanted = min(status.st_size, max_bytes) + 1
            data = _read_up_to(file, wanted)
            if len(data) == wanted <= max_bytes:  # it holds more than its size says
                data += _read_up_to(file, max_bytes + 1 - wanted)  # to the limit + 1, no further
    except FileNotFoundError:
        raise LabDataError(f"there is no file {named}") from None
    except OSError as error:  # no permission, a name too long for a folder, a loop of links...
        raise LabDataError(f"{named} cannot be read: {error.strerror or error}") from None
    if len(data) > max_bytes:
        raise LabDataError(f"{named} has more than {max_bytes:,} bytes; at most that many are read")
    return data


def _read_up_to(file, count: int) -> bytes:
    """``count`` bytes of ``file``, or all it has left if fewer."""
    pieces, left = [], count
    while left > 0:
        piece = file.read(left)
        if not piece:
            break
        pieces.append(piece)
        left -= len(piece)
    return pieces[0] if len(pieces) == 1 else b"".join(pieces)


def _check_regular(status: os.stat_result, named: str) -> None:
    if not stat.S_ISREG(status.st_mode):
        kind = next((kind for test, kind in KINDS if test(status.st_mode)), "special file")
        raise LabDataError(f"{named} is not a regular file but a {kind}; it cannot be read")
