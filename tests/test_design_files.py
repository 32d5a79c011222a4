"""Designs as JSON files: round trips, and every bad file refused with a clear error."""

from __future__ import annotations

import json

import pytest
from hypothesis import given
from hypothesis import strategies as st

from windpump import Design, DesignFileError, ParameterError
from windpump.design import UNITS

SEED = Design.seed_example()


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


@given(designs())
def test_every_design_round_trips_exactly(design):
    assert Design.from_json(design.to_json()) == design


def test_the_file_states_its_schema_version_and_units():
    document = json.loads(SEED.to_json())
    assert document["schema"] == "windpump.design" and document["version"] == 1
    assert document["units"] == UNITS and set(document["fields"]) == set(UNITS)


def test_fields_with_defaults_may_be_left_out():
    document = json.loads(SEED.to_json())
    for name in ("rho_w", "g", "cylinders", "double_acting", "T_0", "V_ref"):
        del document["fields"][name]
    assert Design.from_json(json.dumps(document)) == SEED


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
        (edited(lambda d: d.update(version=2)), "newer windpump"),
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
