"""A rotor by its aerodynamics (windpump.Rotor): the table's rules, its curve against scipy's PCHIP
built here, the torque law written here, similarity, furling, and design files."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.interpolate import PchipInterpolator

from windpump import Design, ParameterError, Rotor
from windpump.model.design import ROTOR_FIELDS

SEED = Design.seed_example()
TSR = [0.0, 0.5, 1.0, 1.5, 2.0, 2.5]
CQ = [0.45, 0.40, 0.31, 0.19, 0.06, -0.05]


def law(rotor_diameter, tsr, cq, omega, V, rho_air=1.225, V_furl=None):
    """T = 1/2 rho pi r^3 V_s^2 C_Q(omega r / V_s), C_Q a PCHIP continued by its end slope."""
    r = rotor_diameter / 2
    V_s = V if V_furl is None else min(V, V_furl)
    curve = PchipInterpolator(tsr, cq)
    lam = omega * r / V_s
    if lam <= tsr[-1]:
        coefficient = float(curve(lam))
    else:
        coefficient = cq[-1] + float(curve.derivative()(tsr[-1])) * (lam - tsr[-1])
    return 0.5 * rho_air * math.pi * r**3 * V_s**2 * coefficient


@given(
    omega=st.floats(0.0, 40.0),
    V=st.floats(0.5, 30.0),
    diameter=st.floats(0.5, 20.0),
)
def test_the_torque_is_the_law_through_scipy_s_pchip(omega, V, diameter):
    rotor = Rotor.from_cq(diameter, TSR, CQ)
    expected = law(diameter, TSR, CQ, omega, V)
    assert float(rotor.torque(omega, V)) == pytest.approx(expected, rel=1e-12, abs=1e-12)
    assert float(rotor.power(omega, V)) == pytest.approx(expected * omega, rel=1e-12, abs=1e-12)


@given(lam=st.floats(0.0, 10.0))
def test_cp_is_lambda_times_cq_and_cq_passes_through_the_table(lam):
    rotor = Rotor.from_cq(2.0, TSR, CQ)
    assert float(rotor.cp(lam)) == pytest.approx(lam * float(rotor.cq(lam)), rel=1e-14, abs=1e-15)
    np.testing.assert_allclose(rotor.cq(TSR), CQ, rtol=0, atol=1e-15)


@given(s=st.floats(0.1, 10.0), omega=st.floats(0.0, 20.0))
def test_similarity_torque_as_v_squared_speed_as_v(s, omega):
    rotor = Rotor.from_cq(3.0, TSR, CQ)
    base = float(rotor.torque(omega, 5.0))
    assert float(rotor.torque(s * omega, s * 5.0)) == pytest.approx(
        s * s * base, rel=1e-10, abs=1e-12
    )


def test_a_furled_wheel_turns_in_the_wind_capped_at_v_furl():
    rotor = Rotor.from_cq(3.0, TSR, CQ, V_furl=8.0)
    for omega in (0.0, 2.0, 5.0):
        assert float(rotor.torque(omega, 14.0)) == float(rotor.torque(omega, 8.0))
        assert float(rotor.torque(omega, 14.0)) == pytest.approx(law(3.0, TSR, CQ, omega, 8.0))
    assert float(rotor.torque(2.0, 6.0)) == pytest.approx(law(3.0, TSR, CQ, 2.0, 6.0))


def test_the_runaway_is_where_cq_falls_to_zero():
    rotor = Rotor.from_cq(2.0, TSR, CQ)
    assert 2.0 < rotor.runaway_tsr < 2.5
    assert abs(float(rotor.cq(rotor.runaway_tsr))) < 1e-14
    # on the straight continuation past the table
    beyond = Rotor.from_cq(2.0, [0.0, 1.0, 2.0], [0.5, 0.3, 0.1])
    slope = float(PchipInterpolator([0.0, 1.0, 2.0], [0.5, 0.3, 0.1]).derivative()(2.0))
    assert beyond.runaway_tsr == pytest.approx(2.0 - 0.1 / slope, rel=1e-14)
    assert float(beyond.torque(0.0, 0.0)) == 0.0  # calm air


def test_from_cp_divides_by_lambda_and_takes_the_torque_at_rest():
    rotor = Rotor.from_cp(2.0, [0.0, 1.0, 2.0, 3.0], [0.0, 0.3, 0.2, 0.0], cq0=0.5)
    assert rotor.table_cq == (0.5, 0.3, 0.1, 0.0)
    assert float(rotor.cp(1.0)) == pytest.approx(0.3)


def test_the_multiblade_wheel_has_its_largest_torque_at_rest():
    wheel = Rotor.multiblade(8 * 0.3048)
    lam = np.linspace(0.0, wheel.runaway_tsr, 200)
    cq = wheel.cq(lam)
    assert np.all(np.diff(cq) <= 1e-15) and cq[0] == max(cq)  # falls all the way
    assert 0.4 <= cq[0] <= 0.7 and 1.5 <= wheel.runaway_tsr <= 3.0
    assert 0.25 <= float(wheel.cp(lam).max()) <= 0.35  # C_P ~ 0.3 near lambda ~ 1
    assert wheel.source  # the docstring and the field name where it comes from


BAD_TABLES = [
    ({"tsr": [0.1, 1.0, 2.0]}, "tsr"),  # not from rest
    ({"tsr": [0.0, 1.0, 1.0]}, "tsr"),  # not increasing
    ({"tsr": [0.0, 2.0, 1.0]}, "tsr"),
    ({"tsr": [0.0, math.nan, 2.0]}, "tsr"),
    ({"cq": [0.4, math.nan, 0.0]}, "cq"),
    ({"cq": [-0.1, 0.3, 0.0]}, "cq"),  # below 0 at rest
    ({"cq": [0.4, 0.5, 0.6]}, "cq"),  # never falls to 0
    ({"cq": [0.0, 0.0, 0.0]}, "cq"),  # never positive
    ({"cq": [0.4, 0.3]}, "cq"),  # fewer than tsr
    ({"diameter": 0.0}, "diameter"),
    ({"diameter": -2.0}, "diameter"),
    ({"rho_air": 0.0}, "rho_air"),
    ({"rho_air": math.inf}, "rho_air"),
    ({"V_furl": 0.0}, "V_furl"),
    ({"V_furl": -5.0}, "V_furl"),
]


@pytest.mark.parametrize("changes, name", BAD_TABLES)
def test_bad_tables_and_sizes_are_refused_by_name(changes, name):
    arguments = {"diameter": 2.0, "tsr": [0.0, 1.0, 2.0], "cq": [0.4, 0.3, 0.0], **changes}
    diameter, tsr, cq = (arguments.pop(key) for key in ("diameter", "tsr", "cq"))
    with pytest.raises(ParameterError) as caught:
        Rotor.from_cq(diameter, tsr, cq, **arguments)
    assert caught.value.name == name
    assert name in str(caught.value)


@given(st.lists(st.floats(allow_nan=True, allow_infinity=True), min_size=0, max_size=6))
def test_any_table_is_a_rotor_or_a_parameter_error(cq):
    tsr = list(range(len(cq)))
    try:
        rotor = Rotor.from_cq(2.0, tsr, cq)
    except ParameterError as error:
        assert error.name in ("tsr", "cq")
    else:
        assert rotor.runaway_tsr > 0.0 and float(rotor.cq(rotor.runaway_tsr)) == pytest.approx(
            0.0, abs=1e-9 * max(1.0, max(abs(x) for x in cq))
        )


def wheel_design(**changes):
    return Design.from_rotor(
        Rotor.multiblade(1.5, V_furl=9.0), V_ref=5.0, **SEED.geometry()
    ).replace(**changes)


def test_a_rotor_design_s_curve_is_the_rotor_s_at_v_ref():
    d = wheel_design()
    rotor = d.rotor
    assert d.T_0 == pytest.approx(law(1.5, rotor.table_tsr, rotor.table_cq, 0.0, 5.0))
    runaway = rotor.runaway_tsr * 5.0 / 0.75
    assert d.runaway_speed == pytest.approx(runaway) and d.omega_m == pytest.approx(runaway / 2)
    assert d.T_m == pytest.approx(law(1.5, rotor.table_tsr, rotor.table_cq, d.omega_m, 5.0))
    # in_wind keeps the rotor, its curve moved by similarity (below the furl)
    windy = d.in_wind(7.0)
    assert windy.rotor == rotor and windy.T_0 == pytest.approx(d.T_0 * (7 / 5) ** 2)
    assert windy.omega_m == pytest.approx(d.omega_m * 7 / 5)


@pytest.mark.parametrize("name", ROTOR_FIELDS)
def test_a_rotor_design_refuses_its_curve_s_fields_by_name(name):
    with pytest.raises(ParameterError) as caught:
        wheel_design().replace(**{name: 1.0})
    assert caught.value.name == name
    with pytest.raises(TypeError):
        Design.from_rotor(Rotor.multiblade(1.5), V_ref=5.0, **{**SEED.geometry(), name: 1.0})


def test_a_rotor_design_file_reads_back_and_older_files_still_read():
    d = wheel_design(h=12.0, eta_t=0.9)
    text = d.to_json()
    document = json.loads(text)
    assert document["version"] == 3 and document["rotor"]["table_cq"] == list(d.rotor.table_cq)
    assert Design.from_json(text) == d
    document["version"] = 2
    with pytest.raises(ValueError, match="rotor"):
        Design.from_json(json.dumps(document))
    older = json.loads(SEED.to_json())
    older["version"] = 2
    assert Design.from_json(json.dumps(older)) == SEED and SEED.rotor is None


def test_from_machine_in_a_builder_s_terms_by_hand():
    wheel = Rotor.multiblade(8 * 0.3048)
    d = Design.from_machine(wheel, V_ref=6.7, gear_ratio=3.29, stroke=7.5 * 0.0254,
                            bore=2.5 * 0.0254, head=175 * 0.3048, wheel_inertia=30.0)  # fmt: skip
    assert d.R_dagger == pytest.approx(3.29) and d.R == pytest.approx(7.5 * 0.0254 / 2)
    assert d.A == pytest.approx(math.pi / 4 * (2.5 * 0.0254) ** 2) and d.h == pytest.approx(53.34)
    assert d.I0 == 30.0 and d.L == pytest.approx(5.0 * d.R) and d.rotor is wheel
    for name, value in (("gear_ratio", 0.0), ("stroke", -1.0), ("bore", math.nan)):
        arguments = dict(V_ref=6.7, gear_ratio=3.29, stroke=0.19, bore=0.06, head=50.0,
                         wheel_inertia=30.0)  # fmt: skip
        arguments[name] = value
        with pytest.raises(ParameterError) as caught:
            Design.from_machine(wheel, **arguments)
        assert caught.value.name == name
