"""A builder's units at the edges: the quantities a person types ("175 ft", "1 7/8 in",
"15 mph", "200 gal/h") read into the SI numbers the core works in, and SI numbers shown in the
units a reader asked for (``"si"`` or ``"us"``). The core never sees a unit: the command line
(and the page) call these two functions at their edges.

The units are pint's (https://pint.readthedocs.io), with a gallon the US liquid gallon
(3.785411784 L, pint's ``gal``) and ``gpm`` / ``gph`` added; pint is imported on the first text
with a unit in it, never by ``import windpump`` nor by a command line whose values are bare
numbers. A conversion factor is pint's, rounded to 15 significant digits: pint reaches the foot
through the yard and the inch, which leaves float noise in the 16th digit (1 ft =
0.30479999999999996 m); the units' definitions are exact decimals (1 ft = 0.3048 m, 1 in =
0.0254 m, 1 gal = 3.785411784 L, 1 mph = 0.44704 m/s: NIST SP 811, appendix B), which the
rounding gives back.

Examples
--------
>>> parse_quantity("h", "175 ft", "m")
53.34
>>> parse_quantity("bore", "1 7/8 in", "m")
0.047625
>>> format_quantity(53.34, "head", "us"), format_quantity(0.047625, "bore", "us")
('175 ft', '1 7/8 in')
>>> format_quantity(0.047625, "bore", "si")
'47.62 mm'
"""

from __future__ import annotations

import functools
import math
import re
from dataclasses import dataclass
from typing import Any

from ..errors import ParameterError

__all__ = [
    "KINDS",
    "SYSTEMS",
    "Kind",
    "display_unit",
    "format_quantity",
    "parse_quantity",
    "unit_of",
]

SYSTEMS = ("si", "us")
"""The systems :func:`format_quantity` shows in: SI (m, mm, L, L/s, L/min, m/s) and US customary
(ft, in, gal, gal/h, gpm, mph, lb)."""


@dataclass(frozen=True)
class Kind:
    """A kind of quantity: its SI unit in the core, and the unit each system shows it in.

    Attributes
    ----------
    core : str
        The unit of the core's number (``"m"``, ``"m^3/s"``).
    si, us : str
        The unit shown in each system (pint's spelling, which :func:`parse_quantity` reads back).
    """

    core: str
    si: str
    us: str


KINDS: dict[str, Kind] = {
    "length": Kind("m", si="m", us="ft"),
    "head": Kind("m", si="m", us="ft"),
    "height": Kind("m", si="m", us="ft"),
    "diameter": Kind("m", si="m", us="ft"),
    "bore": Kind("m", si="mm", us="in"),
    "stroke": Kind("m", si="mm", us="in"),
    "area": Kind("m^2", si="m^2", us="in^2"),
    "wind speed": Kind("m/s", si="m/s", us="mph"),
    "flow": Kind("m^3/s", si="L/s", us="gal/h"),
    "flow per minute": Kind("m^3/s", si="L/min", us="gpm"),
    "daily flow": Kind("m^3/day", si="m^3/day", us="gal/day"),
    "volume": Kind("m^3", si="L", us="gal"),
    "tank": Kind("m^3", si="m^3", us="gal"),
    "mass": Kind("kg", si="kg", us="lb"),
    "torque": Kind("N m", si="N m", us="lbf ft"),
    "inertia": Kind("kg m^2", si="kg m^2", us="lb ft^2"),
}
"""Every kind of quantity the command line (and the page) shows, in one place: the core's unit
and the unit of each system (a pump's flow in gal/h, as a windmill catalogue rates it, and in
gallons a minute, as a US pump's or well's flow is written: ``"flow per minute"``)."""

# What a field of a dimension takes, in words, with examples a builder would type; keyed by the
# core unit of the field (windpump.model.design.UNITS and the options' units).
TAKES = {
    "m": "a length, e.g. 175 ft, 53 m or 1 7/8 in",
    "m^2": "an area, e.g. 2.76 in^2 or 17.8 cm^2",
    "m^3": "a volume, e.g. 500 gal, 1.9 m^3 or 1900 L",
    "m/s": "a speed, e.g. 15 mph or 6.7 m/s",
    "m^3/s": "a flow, e.g. 200 gal/h, 3 gpm or 0.5 L/s",
    "m^3/day": "a flow, e.g. 500 gal/day, 3 gpm or 1.9 m^3/day",
    "kg": "a mass, e.g. 265 lb or 120 kg",
    "N m": "a torque, e.g. 50 lbf ft or 68 N m",
    "kg m^2": "a moment of inertia, e.g. 100 lb ft^2 or 4.2 kg m^2",
    "rad/s": "an angular speed, e.g. 30 rpm or 3.1 rad/s",
    "kg/m^3": "a density, e.g. 62.4 lb/ft^3 or 1000 kg/m^3",
    "m/s^2": "an acceleration, e.g. 32.2 ft/s^2 or 9.81 m/s^2",
}

MAX_TEXT = 100
"""Most characters of a typed quantity read (a longer text is refused before pint sees it)."""

_NUMBER = r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?"
_QUANTITY = re.compile(
    r"\s*(?:(?P<whole>[+-]?\d+)(?:\s+|-)(?P<num>\d+)/(?P<den>\d+)"  # 1 7/8, 1-7/8
    r"|(?P<fnum>[+-]?\d+)/(?P<fden>\d+)"  # 7/8
    rf"|(?P<decimal>{_NUMBER}|[+-]?(?:nan|inf|infinity)\b))"  # 3.5, 1e3 (nan, inf: refused)
    r"\s*(?P<unit>.*?)\s*",
    re.IGNORECASE,
)
_FEET_INCHES = re.compile(
    rf"\s*(?P<feet>{_NUMBER})\s*(?:ft|feet|foot|')\s*"
    r"(?P<inches>\d+(?:\.\d*)?|\d+(?:\s+|-)\d+/\d+|\d+/\d+)\s*(?:in|inch|inches|\")?\s*"
)  # 5 ft 6 in, 5' 6"
_UNIT_CHARACTERS = re.compile(r"[A-Za-z0-9_ ^*/.()µ°²³]*")
_POWER = re.compile(r"\^\s*[+-]?\d{1,2}(?:\.\d+)?(?![\d.^*])")
_SYMBOLS = {'"': "in", "″": "in", "'": "ft", "′": "ft", "²": "^2", "³": "^3"}
_FRACTIONS = {"½": " 1/2", "¼": " 1/4", "¾": " 3/4", "⅛": " 1/8", "⅜": " 3/8", "⅝": " 5/8"}
_FRACTIONS.update({"⅞": " 7/8", "⅓": " 1/3", "⅔": " 2/3", "⁄": "/"})


@functools.cache
def _registry() -> Any:
    """pint's unit registry, with gpm and gph (made once, on the first unit typed)."""
    import pint

    units: Any = pint.UnitRegistry()
    units.define("gallon_per_minute = gallon / minute = gpm = GPM")
    units.define("gallon_per_hour = gallon / hour = gph = GPH")
    return units


@functools.cache
def _factor(unit: str, core: str) -> float | None:
    """The factor from ``unit`` to ``core`` (15 significant digits), or None when ``unit`` is
    of another dimension. Raises ValueError (or pint's errors) for text pint cannot read."""
    units = _registry()
    source, target = units.parse_units(unit), units.parse_units(core)
    if source.dimensionality != target.dimensionality:
        return None
    factor = units.Quantity(1.0, source).to(target).magnitude
    return float(f"{factor:.15g}")


def _dimension_of(unit: str) -> str:
    """What ``unit`` measures, in words (for saying a typed unit is of the wrong kind)."""
    try:
        dimensionality = _registry().parse_units(unit).dimensionality
    except Exception:
        return ""
    for core, takes in TAKES.items():
        if _registry().parse_units(core).dimensionality == dimensionality:
            return takes.split(",")[0]  # "a length"
    if not dimensionality:
        return "a pure number"
    return f"of dimension {dimensionality}"


def _number(match: re.Match) -> float:
    """The number a quantity's text starts with: a decimal, a fraction or a mixed number."""
    if match["decimal"] is not None:
        return float(match["decimal"])
    if match["fnum"] is not None:
        numerator, denominator, whole = int(match["fnum"]), int(match["fden"]), "0"
    else:
        numerator, denominator, whole = int(match["num"]), int(match["den"]), match["whole"]
    if denominator == 0:
        return math.nan
    fraction = numerator / denominator
    return int(whole) - fraction if whole.startswith("-") else int(whole) + fraction


def _normal(text: str) -> str:
    """``text`` with a typographer's fractions, primes and superscripts in plain characters."""
    for symbol, plain in {**_FRACTIONS, **_SYMBOLS}.items():
        text = text.replace(symbol, plain)
    return re.sub(r"(?<=[A-Za-z])([23])(?![0-9])", r"^\1", text)  # m3/day -> m^3/day


def parse_quantity(name: str, text: str, unit: str) -> float:
    """What a person typed as a quantity, in the core's unit ``unit``.

    A number, a fraction (``7/8``) or a mixed number (``1 7/8``, ``1-7/8``), then a unit pint
    knows (``ft``, ``in``, ``"``, ``'``, ``mph``, ``gal/h``, ``gpm``, ``L/s``, ``m^3/day``, ...,
    case as pint spells it, else lower case) or none: a bare number is in ``unit``. Feet and
    inches together (``5 ft 6 in``, ``5' 6"``) for a length. A gallon is the US gallon.

    Parameters
    ----------
    name : str
        The field or option, named in an error (``"h"``, ``"--demand"``).
    text : str
        What was typed.
    unit : str
        The core's unit of the field [e.g. ``"m"``, ``"m/s"``, ``"m^3/s"``], in pint's spelling:
        the unit of the result and of a bare number.

    Returns
    -------
    float
        The quantity in ``unit``.

    Raises
    ------
    ParameterError
        Naming ``name``, the text as typed (cut short when long) and what the field takes: for
        a text with no number, a unit pint does not know or of another dimension, a value that
        is not finite (NaN, inf, a fraction over 0) or a negative length.

    Examples
    --------
    >>> parse_quantity("V_ref", "15 mph", "m/s")
    6.7056
    >>> parse_quantity("flow", "3 gpm", "m^3/s")  # 3 x 3.785411784 L / 60 s
    0.0001892705892
    >>> parse_quantity("h", "8", "m")
    8.0
    >>> parse_quantity("h", "3 kg", "m")
    Traceback (most recent call last):
    ...
    windpump.errors.ParameterError: h = '3 kg' is not allowed: h must be a length, e.g. 175 ft, 53 m or 1 7/8 in (kg is a mass)
    """
    takes = TAKES.get(unit, f"a quantity in {unit} or another unit of its kind")

    def refuse(why: str, allowed: str = takes) -> ParameterError:
        return ParameterError(name, text, allowed, why=why)

    if not isinstance(text, str):
        raise refuse("not text")
    if len(text) > MAX_TEXT:
        raise refuse(f"longer than {MAX_TEXT} characters")
    plain = _normal(text)
    if not plain.strip():
        raise refuse("empty", f"a number, or {takes}")
    feet_inches = _FEET_INCHES.fullmatch(plain) if unit == "m" else None
    if feet_inches is not None:
        try:
            inches = parse_quantity(name, feet_inches["inches"] + " in", "m")
            feet = parse_quantity(name, feet_inches["feet"] + " ft", "m")
        except ParameterError as error:
            raise refuse(error.why) from None
        return feet + inches
    match = _QUANTITY.fullmatch(plain)
    if match is None:
        raise refuse("it starts with no number", f"a number, or {takes}")
    value = _number(match)
    typed_unit = match["unit"]
    if not math.isfinite(value):
        raise refuse("not a finite number")
    factor = _unit_factor(typed_unit, unit) if typed_unit else 1.0
    if factor is None:
        if not _known(typed_unit):
            raise refuse(f"{shown_unit(typed_unit)} is not a unit")
        kind = _dimension_of(typed_unit)
        raise refuse(f"{typed_unit} is {kind}" if kind else "a unit of another kind")
    result = value * factor
    if not math.isfinite(result):
        raise refuse("not a finite number")
    if unit == "m" and result < 0:
        raise refuse("a negative length")
    return result


def unit_of(text: str) -> str:
    """The unit a typed quantity ends with, as typed (``""`` for a bare number or a text that is
    no quantity): what a list of quantities lends the bare numbers before its last.

    Examples
    --------
    >>> unit_of("17.5 mph"), unit_of("1 7/8 in"), unit_of("15"), unit_of("mph")
    ('mph', 'in', '', '')
    """
    match = _QUANTITY.fullmatch(_normal(text)) if len(text) <= MAX_TEXT else None
    return match["unit"] if match is not None else ""


def shown_unit(text: str) -> str:
    """A unit as typed, quoted and cut short, for a message."""
    return repr(text if len(text) <= 20 else text[:19] + "…")


def _plain_unit(unit: str) -> bool:
    """Whether ``unit`` is for pint's parser: letters, digits, ``* / ( ) . _`` and spaces, each
    power (``^``, ``**``) a number of at most two digits (pint computes ``m^9^9^9`` as
    9^387420489 first: a Python integer of 370 million digits)."""
    if not _UNIT_CHARACTERS.fullmatch(unit):
        return False
    powers = unit.replace("**", "^")
    return powers.count("^") == len(_POWER.findall(powers))


def _known(unit: str) -> bool:
    if not _plain_unit(unit):
        return False
    try:
        _registry().parse_units(unit)
    except Exception:
        return False
    return True


def _unit_factor(typed_unit: str, core: str) -> float | None:
    """The factor from the unit typed to ``core``; pint's spelling first, then in lower case
    (``FT``, ``MPH``). None when it is of another dimension or no unit."""
    if not _plain_unit(typed_unit):
        return None
    for spelling in dict.fromkeys((typed_unit, typed_unit.lower())):
        try:
            return _factor(spelling, core)
        except Exception:  # pint's UndefinedUnitError, its tokenizer's and parser's errors
            continue
    return None


def format_quantity(value_si: float, kind: str, system: str, digits: int = 4) -> str:
    """An SI number as a reader reads it: the number in ``kind``'s unit of ``system``, then the
    unit (``"175 ft"``, ``"0.316 L/s"``); a US bore or stroke that is a whole number of
    sixteenths of an inch to the digits shown as a mixed number (``"1 7/8 in"``, as a catalogue
    writes it).

    Parameters
    ----------
    value_si : float
        The number in the kind's core unit (:data:`KINDS`) [e.g. m, m^3/s].
    kind : str
        A key of :data:`KINDS` (``"length"``, ``"bore"``, ``"head"``, ``"flow"``, ``"volume"``,
        ``"wind speed"``, ...).
    system : str
        ``"si"`` or ``"us"``.
    digits : int
        Significant digits shown (the ``g`` format's).

    Returns
    -------
    str
        What :func:`parse_quantity` reads back (to ``digits`` digits).

    Examples
    --------
    >>> format_quantity(6.7056, "wind speed", "us"), format_quantity(6.7056, "wind speed", "si")
    ('15 mph', '6.706 m/s')
    >>> format_quantity(3.155e-4, "flow", "us", digits=3), format_quantity(3.155e-4, "flow", "si")
    ('300 gal/h', '0.3155 L/s')
    >>> format_quantity(1.892705892e-4, "flow per minute", "us")  # 3 gal a minute
    '3 gpm'
    """
    factor, shown_in = display_unit(kind, system)
    number = value_si * factor
    if system == "us" and kind in ("bore", "stroke") and math.isfinite(number):
        sixteenths = round(number * 16)  # the fraction when the digits would say the same
        if 0 < sixteenths and f"{number:.{digits}g}" == f"{sixteenths / 16:.{digits}g}":
            return f"{_mixed(sixteenths, 16)} {shown_in}"
    return f"{number:.{digits}g} {shown_in}"


def display_unit(kind: str, system: str) -> tuple[float, str]:
    """The factor from ``kind``'s core unit to the unit ``system`` shows it in, and that unit.

    Parameters
    ----------
    kind : str
        A key of :data:`KINDS`.
    system : str
        ``"si"`` or ``"us"``.

    Returns
    -------
    factor : float
        The core's number times this is the number shown [shown unit / core unit].
    unit : str
        The unit shown.

    Examples
    --------
    >>> display_unit("flow", "si"), display_unit("tank", "us")
    ((1000.0, 'L/s'), (264.1720523581484, 'gal'))
    """
    if kind not in KINDS:
        raise ParameterError("kind", kind, f"one of {', '.join(KINDS)}")
    if system not in SYSTEMS:
        raise ParameterError("system", system, "'si' or 'us'")
    entry = KINDS[kind]
    unit = entry.us if system == "us" else entry.si
    if unit == entry.core:
        return 1.0, unit
    inverse = _factor(unit, entry.core)  # the definition's exact decimal (0.3048 m/ft)
    assert inverse is not None, (kind, system)  # (the table's units are of one dimension)
    return 1.0 / inverse, unit


def _mixed(numerator: int, denominator: int) -> str:
    """A positive fraction as a mixed number in lowest terms: ``30/16`` -> ``"1 7/8"``."""
    whole, part = divmod(numerator, denominator)
    if part == 0:
        return str(whole)
    divisor = math.gcd(part, denominator)
    fraction = f"{part // divisor}/{denominator // divisor}"
    return f"{whole} {fraction}" if whole else fraction
