"""The kernels' rotor torque (windpump._kernels.rotor) against the numpy side's (scipy's PCHIP,
windpump.Rotor), and the machine's table laid out as it says."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from windpump import Design, Rotor
from windpump._kernels.rotor import table_cq, wheel_torque
from windpump.model.torque import torque_in_wind
from windpump.run.machine import kernel_rotor

SEED = Design.seed_example()
DENSE = Rotor.from_cq(1.5, np.linspace(0.0, 3.0, 61), 0.5 * (1 - np.linspace(0.0, 3.0, 61) / 2.2))
TABLES = {
    "multiblade": Rotor.multiblade(1.5, V_furl=8.0),
    "hump": Rotor.from_cq(2.0, [0.0, 0.5, 1.0, 1.5, 2.0], [0.1, 0.3, 0.38, 0.2, 0.0]),
    "dense (bisected)": DENSE,
}


@pytest.mark.parametrize("name", TABLES)
@given(lam=st.floats(0.0, 6.0), omega=st.floats(0.0, 60.0), s=st.floats(0.0, 4.0))
def test_the_kernel_s_curve_is_scipy_s_pchip(name, lam, omega, s):
    rotor = TABLES[name]
    design = Design.from_rotor(rotor, V_ref=5.0, **SEED.geometry())
    table = kernel_rotor(design)
    assert table_cq(lam, table) == pytest.approx(float(rotor.cq(lam)), rel=1e-12, abs=1e-13)
    compiled = wheel_torque(omega, s, table, design.T_m, design.T_0, design.omega_m)
    expected = float(torque_in_wind(design, omega, s))
    assert compiled == pytest.approx(expected, rel=1e-12, abs=1e-12 * design.T_0)


def test_without_a_rotor_the_kernel_s_curve_is_eq_11():
    for omega, s in ((0.0, 1.0), (30.0, 1.0), (75.0, 1.3), (120.0, 0.5)):
        compiled = wheel_torque(omega, s, None, SEED.T_m, 0.2, SEED.omega_m)
        x = omega / SEED.omega_m
        assert compiled == s * s * 0.2 + (SEED.T_m - 0.2) * x * (2 * s - x)
    assert kernel_rotor(SEED) is None


def test_the_table_rides_by_address_and_says_its_layout():
    table = kernel_rotor(Design.from_rotor(DENSE, V_ref=5.0, **SEED.geometry()))
    n = table.intervals
    numbers = np.ctypeslib.as_array(
        (np.ctypeslib.ctypes.c_double * (5 * n + 1)).from_address(table.address)
    )
    np.testing.assert_array_equal(numbers[: n + 1], DENSE.table_tsr)
    c0 = numbers[1 + 4 * n :]
    np.testing.assert_allclose(c0, DENSE.table_cq[:-1], rtol=0, atol=1e-15)
    assert table.radius == 0.75 and table.V_furl == math.inf
