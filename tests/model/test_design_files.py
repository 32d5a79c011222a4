"""Designs as JSON files: round trips, and every bad file refused with a clear error."""

from __future__ import annotations

import json

import pytest
from hypothesis import given
from hypothesis import strategies as st

from windpump import Design, DesignFileError, ParameterError
from windpump.model.design import LEAKY_RATIO, REAL_MACHINE, UNITS

SEED = Design.seed_example()

# The fields of a version 1 file (before the real machine's), as that version wrote them.
VERSION_1_UNITS = {
    "R0": "m",
    "R1": "m",
    "R": "m",
    "L": "m",
    "A": "m^2",
    "I0": "kg m^2",
    "I1": "kg m^2",
    "T_m": "N m",
    "omega_m": "rad/s",
    "h": "m",
    "rho_w": "kg/m^3",
    "g": "m/s^2",
    "cylinders": "",
    "double_acting": "",
    "T_0": "N m",
    "V_ref": "m/s",
}


@st.composite
def designs(draw):
    """Valid designs across every field."""
    R = draw(st.floats(1e-3, 1.0))
    T_m = draw(st.floats(1e-2, 1e3))
    return SEED.replace(
        R0=draw(st.floats(1e-3, 1.0)),
        R1=draw(st.floats(1e-3, 10.0)),
        R=R,
        L=R * draw(st.floats(1.001, 20.0)),
        A=draw(st.floats(1e-6, 1.0)),
        I0=draw(st.floats(1e-6, 1e3)),
        I1=draw(st.floats(1e-6, 1e3)),
        T_m=T_m,
        omega_m=draw(st.floats(1e-2, 1e3)),
        h=draw(st.floats(0.0, 1e3)),
        cylinders=draw(st.integers(1, 6)),
        double_acting=draw(st.booleans()),
        T_0=T_m * draw(st.floats(0.0, 0.99)),
        V_ref=draw(st.floats(0.1, 50.0)),
    )


@st.composite
def real_machines(draw):
    """Valid designs with every real-machine field set anywhere in its range (the hole up to
    just below the bore)."""
    design = draw(designs())
    return design.replace(
        L=max(design.L, LEAKY_RATIO * design.R),  # (a leak hole's shortest rod)
        m_r=draw(st.floats(0.0, 1e3)),
        eta_t=draw(st.floats(0.1, 1.0)),
        L_main=draw(st.floats(0.0, 1e4)),
        D_main=draw(st.floats(1e-4, 1.0)),
        f_main=draw(st.floats(0.0, 0.2)),
        d_leak=design.bore * draw(st.floats(0.0, 0.999)),
        Cd_leak=draw(st.floats(0.05, 1.0)),
    )


@given(designs())
def test_every_design_round_trips_exactly(design):
    assert Design.from_json(design.to_json()) == design


@given(real_machines())
def test_every_real_machine_round_trips_exactly(design):
    again = Design.from_json(design.to_json())
    assert again == design
    assert all(getattr(again, name) == getattr(design, name) for name in REAL_MACHINE)


def test_the_real_machines_fields_are_written_with_their_units():
    design = SEED.replace(
        m_r=12.5, eta_t=0.85, L_main=30.0, D_main=0.025, f_main=0.03, d_leak=0.003, Cd_leak=0.7
    )
    document = json.loads(design.to_json())
    assert {name: document["fields"][name] for name in REAL_MACHINE} == {
        "m_r": 12.5,
        "eta_t": 0.85,
        "L_main": 30.0,
        "D_main": 0.025,
        "f_main": 0.03,
        "d_leak": 0.003,
        "Cd_leak": 0.7,
    }
    assert {name: document["units"][name] for name in REAL_MACHINE} == {
        "m_r": "kg",
        "eta_t": "",
        "L_main": "m",
        "D_main": "m",
        "f_main": "",
        "d_leak": "m",
        "Cd_leak": "",
    }
    assert Design.from_json(json.dumps(document)) == design


def test_the_file_states_its_schema_version_and_units():
    document = json.loads(SEED.to_json())
    assert document["schema"] == "windpump.model.design" and document["version"] == 3
    assert "rotor" not in document  # the paper's Eq. (11): no rotor to write
    assert document["units"] == UNITS and set(document["fields"]) == set(UNITS)
    assert set(UNITS) == set(VERSION_1_UNITS) | set(REAL_MACHINE)


def test_fields_with_defaults_may_be_left_out():
    document = json.loads(SEED.to_json())
    for name in ("rho_w", "g", "cylinders", "double_acting", "T_0", "V_ref", *REAL_MACHINE):
        del document["fields"][name]
    assert Design.from_json(json.dumps(document)) == SEED


def version_1_file(**changes) -> str:
    """A design file as version 1 wrote it (no real-machine fields), ``changes`` in its fields."""
    fields = {name: value for name, value in SEED.as_dict().items() if name in VERSION_1_UNITS}
    fields.update(R0=0.05, h=7.5, cylinders=2, **changes)
    document = {
        "schema": "windpump.model.design",
        "version": 1,
        "fields": fields,
        "units": VERSION_1_UNITS,
    }
    return json.dumps(document, indent=2)


def test_a_version_1_file_is_still_read_as_the_ideal_machine():
    design = Design.from_json(version_1_file())
    assert design == SEED.replace(R0=0.05, h=7.5, cylinders=2)
    assert design.is_ideal
    assert (design.m_r, design.eta_t, design.L_main, design.d_leak) == (0.0, 1.0, 0.0, 0.0)
    assert (design.D_main, design.f_main, design.Cd_leak) == (0.05, 0.02, 0.6)


@pytest.mark.parametrize("name", REAL_MACHINE)
def test_a_version_1_file_with_a_real_machine_field_is_refused(name):
    with pytest.raises(DesignFileError) as caught:
        Design.from_json(version_1_file(**{name: SEED.as_dict()[name]}))
    message = str(caught.value)
    assert f"unknown field(s) ['{name}']" in message and "version 1" in message


BAD_REAL_MACHINE = [
    ("m_r", -0.5, "from 0 to"),
    ("m_r", -1e-9, "from 0 to"),
    ("eta_t", 0.0, "from 0.1 to 1"),
    ("eta_t", 0.09, "from 0.1 to 1"),
    ("eta_t", -0.2, "from 0.1 to 1"),
    ("eta_t", 1.01, "from 0.1 to 1"),
    ("L_main", -1.0, "from 0 to"),
    ("D_main", 0.0, "from 1e-12 to"),
    ("D_main", -0.05, "from 1e-12 to"),
    ("f_main", -0.01, "from 0 to 0.2"),
    ("f_main", 0.21, "from 0 to 0.2"),
    ("d_leak", SEED.bore, f"below the bore = {SEED.bore!r} m"),
    ("d_leak", 0.05, f"below the bore = {SEED.bore!r} m"),
    ("d_leak", -0.001, "from 0"),
    ("Cd_leak", 0.0, "from 0.05 to 1"),
    ("Cd_leak", 0.04, "from 0.05 to 1"),
    ("Cd_leak", 1.5, "from 0.05 to 1"),
]


@pytest.mark.parametrize("name, value, allowed", BAD_REAL_MACHINE)
def test_a_bad_real_machine_value_names_the_field_value_and_range(name, value, allowed):
    for make in (
        lambda: SEED.replace(**{name: value}),
        lambda: Design(**{**SEED.as_dict(), name: value}),
        lambda: Design.from_json(edited(lambda d: d["fields"].update({name: value}))),
    ):
        with pytest.raises(ParameterError) as caught:
            make()
        message = str(caught.value)
        assert caught.value.name == name and caught.value.value == value
        assert message.startswith(f"{name} = {value!r}") and allowed in message, message


def edited(change) -> str:
    document = json.loads(SEED.to_json())
    change(document)
    return json.dumps(document)


@pytest.mark.parametrize(
    "text, words",
    [
        ("{not json", "not JSON"),
        ("[]", "not a design file"),
        (edited(lambda d: d.update(schema="other")), "not a design file"),
        (edited(lambda d: d.update(version=4)), "newer windpump"),
        (edited(lambda d: d.update(version="1")), '"version"'),
        (edited(lambda d: d["fields"].update(bore=0.04)), "unknown field(s) ['bore']"),
        (edited(lambda d: d["fields"].pop("h")), "missing field(s) ['h']"),
        (edited(lambda d: d["units"].update(h="ft")), 'the unit of h is "ft"'),
        (edited(lambda d: d.update(fields=[1, 2])), '"fields"'),
    ],
)
def test_bad_files_say_what_is_wrong(text, words):
    with pytest.raises(DesignFileError) as caught:
        Design.from_json(text)
    assert words in str(caught.value)


def test_a_value_out_of_range_names_the_field():
    with pytest.raises(ParameterError) as caught:
        Design.from_json(edited(lambda d: d["fields"].update(h=-2)))
    assert caught.value.name == "h"
    with pytest.raises(ParameterError) as caught:
        Design.from_json(edited(lambda d: d["fields"].update(R1="big")))
    assert caught.value.name == "R1"


VALUES = st.one_of(st.none(), st.booleans(), st.integers(-5, 5), st.floats(), st.text(max_size=5))


@given(st.dictionaries(st.sampled_from([*UNITS, "bore"]), VALUES, max_size=4))
def test_any_edit_of_the_fields_loads_as_written_or_raises_a_value_error(changes):
    text = edited(lambda d: d["fields"].update(changes))
    try:
        design = Design.from_json(text)
    except ValueError as error:  # DesignFileError or ParameterError, naming what is wrong
        named = getattr(error, "name", None) or str(error)
        partners = {"R": "L", "T_m": "T_0", "R0": "R1"}  # checked against each other
        assert any(name in named or partners.get(name) == named for name in changes)
        return
    for name, value in changes.items():
        assert getattr(design, name) == value


def test_a_field_given_twice_is_refused_naming_it():
    """JSON leaves a repeated name's meaning open; Python's reader kept the last one silently (a
    file edited by hand with "h": 3.0 and a later "h": 40 ran at 40 m)."""
    text = SEED.to_json().replace('"h": 3.0', '"h": 3.0, "h": 40', 1)
    with pytest.raises(DesignFileError) as caught:
        Design.from_json(text)
    assert "'h' is given twice" in str(caught.value)


def test_a_number_of_thousands_of_digits_is_refused_in_a_designers_words():
    """Python's own words were for a programmer ("use sys.set_int_max_str_digits()")."""
    text = SEED.to_json().replace('"h": 3.0', '"h": ' + "9" * 5_000, 1)
    with pytest.raises(DesignFileError) as caught:
        Design.from_json(text)
    assert "more than 4,300 digits" in str(caught.value)
    assert "sys." not in str(caught.value)
