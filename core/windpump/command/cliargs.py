"""The command line's shared arguments: ``--workers``, ``--design`` and ``--set``, the quantities
typed with their units (``--set h='175 ft'``, ``--demand '500 gal/day'``) and ``--units``, and the one
reader of the files a command line names; :mod:`windpump.command.cli` and :mod:`windpump.command.sitecli` both use
them (here, so that neither imports the other back; issue 38).
"""

from __future__ import annotations

import argparse
from typing import Any

from ..errors import LabDataError, cut, shown
from ..model.design import UNITS, Design
from ..readers import files
from ..readers.quantities import SYSTEMS, parse_quantity

RATIOS = ("L_over_R", "R_dagger")  # what --set takes besides the fields, through with_ratios
# The explorer's link gives these fields in millimetres (?d_leak_mm=3); --set takes metres.
LINK_MILLIMETRES = {"d_leak_mm": "d_leak", "D_main_mm": "D_main"}
MAX_FILE_BYTES = 50_000_000

MAX_WORKERS = 1024
"""Most processes ``--workers`` may ask for."""


def workers(text: str) -> int:
    """``--workers N``: a whole number from 1 to ``MAX_WORKERS``, else a usage error (exit 2).
    0 and -1 are refused, not taken as 1 or as every core.

    Examples
    --------
    >>> workers("4")
    4
    >>> workers("0")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: '0' is not allowed: it must be a whole number from 1 to 1024
    """
    allowed = f"it must be a whole number from 1 to {MAX_WORKERS}"
    try:
        count = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{cut(text)!r} is not allowed: {allowed}") from None
    if not 1 <= count <= MAX_WORKERS:
        raise argparse.ArgumentTypeError(f"{cut(text)!r} is not allowed: {allowed}")
    return count


def quantity(unit: str, option: str):
    """An argparse ``type`` for ``option``, whose number is in ``unit`` [e.g. ``"m"``,
    ``"m^3/day"``]: a number as ``float`` reads it (as before: ``-inf`` and ``nan`` too, refused
    by the command in words), else a quantity with its unit (:func:`parse_quantity`); a text that
    is neither is a usage error (exit 2) naming the option and what it takes.

    Examples
    --------
    >>> quantity("m", "--hub-height")("12")
    12.0
    >>> quantity("m", "--hub-height")("40 ft")
    12.192
    """

    def read(text: str) -> float:
        try:
            return float(text)
        except ValueError:
            pass
        try:
            return parse_quantity(option, text, unit)
        except ValueError as error:
            raise argparse.ArgumentTypeError(str(error)) from None

    read.__name__ = f"quantity in {unit}"
    return read


def units_option(parser: argparse.ArgumentParser) -> None:
    """``--units si|us``: the units a command shows its answers in."""
    parser.add_argument(
        "--units",
        choices=SYSTEMS,
        default="si",
        help="show the answers in SI units (m, L, L/s, m/s: the default) or US units "
        "(ft, in, gal, gal/h, mph)",
    )


def chosen_design(args: argparse.Namespace, base: Design | None = None) -> Design:
    """The design of --design (or ``base``, else the paper's example) and --set."""
    design = Design.seed_example() if base is None else base
    if args.design:
        text = read_text(args.design, "--design")
        try:
            design = Design.from_json(text)
        except ValueError as error:  # which file, as sweep says it
            raise ValueError(f"{cut(args.design)}: {error}") from None
    changes: dict[str, Any] = dict(parse_setting(text) for text in args.set)
    ratios = {name: changes.pop(name) for name in RATIOS if name in changes}
    return design.with_ratios(**ratios, **changes)


def parse_setting(text: str) -> tuple[str, object]:
    """``NAME=VALUE`` as (name, value), the value typed as the field is."""
    name, equals, value = text.partition("=")
    name, value = name.strip(), value.strip()
    known = ", ".join((*UNITS, *RATIOS))
    if not equals:
        raise ValueError(f"--set {shown(text)}: expected NAME=VALUE with NAME one of {known}")
    if name in LINK_MILLIMETRES:  # a name copied from the explorer's link
        field = LINK_MILLIMETRES[name]
        try:
            millimetres = float(value)
        except ValueError:
            hint = f"--set {field}=VALUE (in metres, or with its unit: '{field}=25 mm')"
        else:
            hint = (
                f"--set {field}={millimetres / 1000:g} (in metres) "
                f"or --set '{field}={millimetres:g} mm'"
            )
        raise ValueError(
            f"--set {shown(text)}: {name} is the explorer's link name: use {field}, {hint}"
        )
    if name not in (*UNITS, *RATIOS):
        raise ValueError(
            f"--set {shown(text)}: {cut(name)} is not a field of the design; one of {known}"
        )
    return name, typed(name, value)


def typed(name: str, value: str) -> float | int | bool:
    """A field's value from text: double_acting true/false, cylinders whole, else a float; a
    field with a unit also a quantity with its unit (``h=175 ft``, ``V_ref=15 mph``,
    ``A=2.76 in^2``: :func:`windpump.readers.quantities.parse_quantity`), in the field's SI unit.

    Examples
    --------
    >>> typed("h", "5"), typed("h", "175 ft"), typed("V_ref", "15 mph")
    (5.0, 53.34, 6.7056)
    """
    if name == "double_acting":
        if value.lower() in ("true", "1", "yes"):
            return True
        if value.lower() in ("false", "0", "no"):
            return False
        raise ValueError(f"double_acting = {shown(value)} is not allowed: it must be true or false")
    try:
        number = float(value)
    except ValueError:
        if UNITS.get(name):  # a quantity with its unit, or what the field takes in words
            return parse_quantity(name, value, UNITS[name])
        raise ValueError(
            f"{name} = {shown(value)} is not allowed: {name} must be a number"
        ) from None
    if name == "cylinders" and number.is_integer():  # (inf and NaN are refused by name later)
        return int(number)
    return number


def read_text(path: str, option: str = "--design") -> str:
    """The text of the file a command line names (``--design FILE``, ``sweep FILE``), read
    through the one guard (:func:`windpump.readers.files.read_bytes`): a regular file only, never waiting
    on a pipe, at most ``MAX_FILE_BYTES``; a path that cannot be one (a NUL byte, over
    ``files.MAX_PATH`` characters) refused naming ``option``.

    Examples
    --------
    >>> read_text("lab\\x00.json", "--design")
    Traceback (most recent call last):
    ...
    windpump.errors.ParameterError: --design = 'lab\\x00.json' is not allowed: --design must be a file's path, without a NUL byte
    """
    try:
        data = files.read_bytes(path, MAX_FILE_BYTES, name=option)
    except LabDataError as error:  # which option named the file
        raise LabDataError(f"{option}: {error}") from None
    try:
        return data.decode("utf-8-sig")  # a spreadsheet's byte-order mark is not a column name
    except UnicodeDecodeError as error:
        raise ValueError(f"{cut(path)}: not UTF-8 text (byte {error.start + 1})") from None
