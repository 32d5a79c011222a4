"""A builder's units read and shown (windpump.readers.quantities), against conversions by hand
from the units' definitions: 1 ft = 0.3048 m, 1 in = 0.0254 m, 1 US gal = 3.785411784 L and
1 mph = 0.44704 m/s exactly (NIST SP 811, appendix B)."""

from __future__ import annotations

import math
import subprocess
import sys

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from windpump.errors import ParameterError
from windpump.readers.quantities import KINDS, SYSTEMS, format_quantity, parse_quantity

FT, INCH, GAL, MPH = 0.3048, 0.0254, 3.785411784e-3, 0.44704  # [m], [m], [m^3], [m/s]
HOUR, MINUTE, DAY = 3600.0, 60.0, 86400.0  # [s]

TYPED = [
    ("175 ft", "m", 175 * FT),
    ("175ft", "m", 175 * FT),
    ("175 feet", "m", 175 * FT),
    ("175 FT", "m", 175 * FT),
    ("175'", "m", 175 * FT),
    ("8 ft", "m", 8 * FT),
    ("3.5 m", "m", 3.5),
    ("350 mm", "m", 0.35),
    ("1 7/8 in", "m", (1 + 7 / 8) * INCH),
    ("1-7/8 in", "m", (1 + 7 / 8) * INCH),
    ('1 7/8"', "m", (1 + 7 / 8) * INCH),
    ("1 7/8in", "m", (1 + 7 / 8) * INCH),
    ("1⅞ in", "m", (1 + 7 / 8) * INCH),
    ("7/8 in", "m", 7 / 8 * INCH),
    ("3 1/2 inches", "m", 3.5 * INCH),
    ("5 ft 6 in", "m", 5 * FT + 6 * INCH),
    ("5' 6\"", "m", 5 * FT + 6 * INCH),
    ("8", "m", 8.0),  # a bare number: in the field's unit
    ("1e1", "m", 10.0),
    ("15 mph", "m/s", 15 * MPH),
    ("15 MPH", "m/s", 15 * MPH),
    ("6.7 m/s", "m/s", 6.7),
    ("200 gal/h", "m^3/s", 200 * GAL / HOUR),
    ("200 gph", "m^3/s", 200 * GAL / HOUR),
    ("3 gpm", "m^3/s", 3 * GAL / MINUTE),
    ("3 gal/min", "m^3/s", 3 * GAL / MINUTE),
    ("0.5 L/s", "m^3/s", 0.5e-3),
    ("500 gal/day", "m^3/day", 500 * GAL),
    ("2 m3/day", "m^3/day", 2.0),
    ("3 gpm", "m^3/day", 3 * GAL / MINUTE * DAY),
    ("500 gal", "m^3", 500 * GAL),
    ("1900 L", "m^3", 1.9),
    ("2.76 in^2", "m^2", 2.76 * INCH**2),
    ("2.76 in²", "m^2", 2.76 * INCH**2),
    ("265 lb", "kg", 265 * 0.45359237),
    ("30 rpm", "rad/s", 30 * 2 * math.pi / 60),
    ("-3 m/s", "m/s", -3.0),  # (a negative speed is the core's to refuse, by its own rule)
]


@pytest.mark.parametrize(("text", "unit", "expected"), TYPED, ids=[t[0] for t in TYPED])
def test_what_a_builder_types_is_read_in_si(text, unit, expected):
    assert parse_quantity("x", text, unit) == pytest.approx(expected, rel=1e-14, abs=0.0)


def test_the_defined_factors_are_exact():
    """pint's own chain (yard, foot, inch) leaves float noise in the 16th digit; the factors
    are rounded back to the definitions."""
    assert parse_quantity("h", "1 ft", "m") == 0.3048
    assert parse_quantity("h", "1 in", "m") == 0.0254
    assert parse_quantity("V", "1 mph", "m/s") == 0.44704
    assert parse_quantity("tank", "1 gal", "m^3") == 0.003785411784
    assert parse_quantity("h", "175 ft", "m") == 175 * 0.3048


def test_pint_agrees_with_the_packages_own_us_units():
    """windpump.units holds the same definitions as constants (the catalogue's): one truth."""
    from windpump import units

    assert parse_quantity("h", "1 ft", "m") == units.METRES_PER_FOOT
    assert parse_quantity("h", "1 in", "m") == units.METRES_PER_INCH
    assert parse_quantity("V", "1 mph", "m/s") == pytest.approx(units.M_S_PER_MPH, rel=1e-15)
    assert parse_quantity("v", "1 gal", "m^3") == pytest.approx(units.M3_PER_US_GALLON, rel=1e-15)


REFUSED = [
    ("3 kg", "m", "kg is a mass"),
    ("3 gal", "m", "gal is a volume"),
    ("15 mph", "m", "mph is a speed"),
    ("3 ft", "m^3/s", "ft is a length"),
    ("3 furlongz", "m", "'furlongz' is not a unit"),
    ("3 m^9^9^9", "m", "is not a unit"),  # never computed (9^387420489)
    ("3 __import__('os')", "m", "is not a unit"),
    ("", "m", "empty"),
    ("   ", "m", "empty"),
    ("heavy", "kg", "starts with no number"),
    ("ft", "m", "starts with no number"),
    ("nan ft", "m", "not a finite number"),
    ("inf", "m", "not a finite number"),
    ("-inf mph", "m/s", "not a finite number"),
    ("1e400 ft", "m", "not a finite number"),
    ("1/0 in", "m", "not a finite number"),
    ("-3 ft", "m", "a negative length"),
    ("-1 7/8 in", "m", "a negative length"),
    ("-5 ft 6 in", "m", "a negative length"),
    ("1" * 200 + " ft", "m", "longer than 100 characters"),
]


@pytest.mark.parametrize(("text", "unit", "why"), REFUSED, ids=[t[0][:20] for t in REFUSED])
def test_a_quantity_that_is_not_one_is_refused_naming_the_field(text, unit, why):
    with pytest.raises(ParameterError) as caught:
        parse_quantity("h", text, unit)
    message = str(caught.value)
    assert message.startswith("h = ") and why in message, message
    assert caught.value.name == "h" and caught.value.value == text
    if unit == "m":
        assert "a length, e.g. 175 ft, 53 m or 1 7/8 in" in message
    assert len(message) < 300  # what was typed, cut short


def test_the_message_shows_what_was_typed_safely():
    with pytest.raises(ParameterError) as caught:
        parse_quantity("h", "3 \u202eft", "m")  # a bidirectional control: repr escapes it
    assert "\\u202e" in str(caught.value)


@pytest.mark.parametrize(
    ("value", "kind", "system", "expected"),
    [
        (175 * FT, "head", "us", "175 ft"),
        (53.34, "head", "si", "53.34 m"),
        ((1 + 7 / 8) * INCH, "bore", "us", "1 7/8 in"),
        (3 * INCH, "bore", "us", "3 in"),
        (0.5 * INCH, "stroke", "us", "1/2 in"),
        (0.05, "bore", "us", "1.969 in"),  # not a sixteenth: decimals
        ((1 + 7 / 8) * INCH, "bore", "si", "47.62 mm"),
        (15 * MPH, "wind speed", "us", "15 mph"),
        (300 * GAL / HOUR, "flow", "us", "300 gal/h"),
        (0.5e-3, "flow", "si", "0.5 L/s"),
        (500 * GAL, "daily flow", "us", "500 gal/day"),
        (100 * GAL, "volume", "us", "100 gal"),
        (0.1, "volume", "si", "100 L"),
        (2.0, "tank", "si", "2 m^3"),
        (265 * 0.45359237, "mass", "us", "265 lb"),
    ],
)
def test_shown_in_the_readers_units(value, kind, system, expected):
    assert format_quantity(value, kind, system) == expected


def test_an_unknown_kind_or_system_is_refused_by_name():
    with pytest.raises(ParameterError, match="kind = 'speed'"):
        format_quantity(1.0, "speed", "us")
    with pytest.raises(ParameterError, match="system = 'imperial'"):
        format_quantity(1.0, "length", "imperial")


@settings(max_examples=300, deadline=None)
@given(
    value=st.floats(1e-6, 1e6),
    kind=st.sampled_from(sorted(KINDS)),
    system=st.sampled_from(SYSTEMS),
    digits=st.integers(4, 15),
)
def test_what_is_shown_reads_back(value, kind, system, digits):
    text = format_quantity(value, kind, system, digits)
    back = parse_quantity(kind, text, KINDS[kind].core)
    assert back == pytest.approx(value, rel=10.0 ** (1 - digits))


@settings(max_examples=200, deadline=None)
@given(whole=st.integers(0, 99), sixteenths=st.integers(1, 15), spaced=st.booleans())
def test_a_mixed_number_of_inches_reads_as_its_sum(whole, sixteenths, spaced):
    text = f"{whole}{' ' if spaced else '-'}{sixteenths}/16 in"
    expected = (whole + sixteenths / 16) * INCH
    assert parse_quantity("bore", text, "m") == pytest.approx(expected, rel=1e-15)


def test_import_windpump_does_not_import_pint():
    """pint is for the edges: neither the package nor its command line loads it until a unit
    is typed or shown."""
    code = (
        "import sys, windpump, windpump.command.cli; "
        "windpump.command.cli.build_parser(); "
        "windpump.command.cliargs.typed('h', '5'); "
        "assert 'pint' not in sys.modules, 'pint imported'; "
        "windpump.command.cliargs.typed('h', '5 ft'); "
        "assert 'pint' in sys.modules"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
