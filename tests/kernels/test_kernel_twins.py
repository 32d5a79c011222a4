"""The compiled model and the numpy functions agree to 1e-12 over random designs and angles.

Eq. (1), its derivative and Eq. (11) are one definition (windpump.model.equations) that numba
compiles and numpy calls; the compiled copies are checked against the numpy calls here because
fastmath could still change them. The load's sum over the delivering faces, the flow factor,
the strokes and the closed-form work are written twice (the kernels pick the faces by segment,
the fast way; numpy by angle), so each pair is held together here, with the load's work checked
against a quadrature of the numpy load.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad

import windpump
from windpump import Design
from windpump._kernels import equations, model
from windpump.run.dynamics import kernel_machine

TOLERANCE = 1e-12


def between(low, high):
    return st.floats(low, high, allow_nan=False, allow_infinity=False)


@st.composite
def designs(draw):
    """Valid designs: any number of cylinders, single- or double-acting, rods from just longer
    than the crank (L/R = 1.01) to 1000 cranks, torque at rest from 0 to 0.99 T_m."""
    R = draw(between(0.005, 0.5))
    T_m = draw(between(0.01, 100.0))
    return Design.seed_example().replace(
        R=R,
        L=R * draw(st.one_of(between(1.01, 20.0), between(20.0, 1000.0))),
        A=draw(between(1e-5, 0.1)),
        h=draw(between(0.01, 100.0)),
        R1=0.03 * draw(between(0.2, 20.0)),
        T_m=T_m,
        T_0=T_m * draw(between(0.0, 0.99)),
        omega_m=draw(between(1.0, 200.0)),
        cylinders=draw(st.integers(1, windpump.model.design.MAX_CYLINDERS)),
        double_acting=draw(st.booleans()),
    )


@st.composite
def angles(draw, cylinders: int):
    """Crank angles over two revolutions either side of TDC, the switches k pi / n among them."""
    free = draw(st.lists(between(-4 * math.pi, 4 * math.pi), min_size=1, max_size=40))
    switches = [j * math.pi / cylinders for j in draw(st.lists(st.integers(-8, 8), max_size=8))]
    return np.array(free + switches)


def segments(theta: np.ndarray, design: Design) -> list[int]:
    machine = kernel_machine(design)
    return [model.segment_at(float(angle), machine) for angle in theta]


@settings(deadline=None)
@given(between(-4 * math.pi, 4 * math.pi), between(1.01, 1000.0))
def test_the_compiled_eq_1_and_its_derivative_are_numpys(phi, L_over_R):
    assert model.piston_over_R(phi, L_over_R) == pytest.approx(
        float(equations.piston_over_R(np.array([phi]), L_over_R)[0]), rel=0, abs=TOLERANCE
    )
    lever = float(equations.lever_arm(np.array([phi]), L_over_R)[0])
    assert model.lever_arm(phi, L_over_R) == pytest.approx(lever, rel=0, abs=TOLERANCE)
    x = float(windpump.piston_position(phi, 1.0, L_over_R))
    assert model.piston_over_R(phi, L_over_R) == pytest.approx(x, rel=0, abs=TOLERANCE)
    assert model.lever_arm(phi, L_over_R) == pytest.approx(
        float(windpump.lever_arm(phi, L_over_R)), rel=0, abs=TOLERANCE
    )


@settings(deadline=None)
@given(designs(), between(0.0, 3.0), st.one_of(st.just(0.0), between(1e-3, 4.0)))
def test_the_compiled_windmill_torque_is_the_numpy_curve_in_the_wind(design, speed, s):
    """windmill_torque_on_crank at crank speed theta_dot in the wind s V_ref is R+ times the
    numpy curve of the design in that wind (Design.in_wind: similarity)."""
    machine = kernel_machine(design)
    theta_dot = speed * design.omega_m / design.R_dagger  # up to 3 omega_m at the windmill
    compiled = model.windmill_torque_on_crank(theta_dot, s, machine)
    scale = design.R_dagger * design.T_m * max(s, speed, 1.0) ** 2
    if s > 0.0:
        in_wind = design.in_wind(s * design.V_ref)
        expected = design.R_dagger * float(
            windpump.windmill_torque(in_wind, design.R_dagger * theta_dot)
        )
    else:  # calm: no curve to scale, only the braking part is left
        x = design.R_dagger * theta_dot / design.omega_m
        expected = -design.R_dagger * (design.T_m - design.T_0) * x * x
    assert compiled == pytest.approx(expected, rel=0, abs=TOLERANCE * scale)


@settings(deadline=None)
@given(st.data())
def test_the_compiled_load_and_flow_factor_are_numpys(data):
    """Eq. (12)'s load summed over the delivering faces, and the flow factor (Eq. 16), in the
    kernels (faces by segment) and in numpy (faces by angle)."""
    design = data.draw(designs())
    theta = data.draw(angles(design.cylinders))
    machine = kernel_machine(design)
    load = windpump.load_torque_on_crank(design, theta) / design.load_torque
    flow = windpump.face_flows(theta, np.ones_like(theta), design).sum(axis=0)
    flow /= design.stroke_volume
    for angle, segment, numpy_load, numpy_flow in zip(
        theta, segments(theta, design), load, flow, strict=True
    ):
        compiled = -model.load_on_crank(angle, segment, machine) / machine.load_torque
        assert compiled == pytest.approx(numpy_load, rel=0, abs=TOLERANCE), angle
        factor = model.flow_factor(angle, segment, machine)
        assert factor == pytest.approx(numpy_flow, rel=0, abs=TOLERANCE), angle


@settings(deadline=None)
@given(st.integers(-50, 50), st.integers(1, 6), st.booleans())
def test_the_compiled_delivering_face_is_numpys(segment, cylinders, double_acting):
    machine = kernel_machine(Design.seed_example().replace(cylinders=cylinders))
    machine = machine._replace(double_acting=double_acting)
    faces = windpump.delivering_faces(segment, cylinders, double_acting)
    compiled = [model.delivering_face(segment, k, machine) for k in range(cylinders)]
    assert compiled == faces.tolist()


@settings(deadline=None)
@given(between(-4 * math.pi, 4 * math.pi), between(1.01, 1000.0))
def test_the_compiled_top_face_strokes_are_numpys_swept_strokes(phi, L_over_R):
    expected = float(windpump.swept_strokes(phi, L_over_R))
    compiled = model.face_strokes(phi, model.TOP, L_over_R)
    assert compiled == pytest.approx(expected, rel=0, abs=TOLERANCE)


@settings(deadline=None, max_examples=40)
@given(st.data())
def test_the_compiled_load_work_is_the_integral_of_the_numpy_load(data):
    """Lambda (load_work, closed form from Eq. 1) from a segment's start to theta, against the
    quadrature of the numpy load over the segment, per unit inertia."""
    design = data.draw(designs())
    machine = kernel_machine(design)
    segment = data.draw(st.integers(-8, 8))
    start = model.segment_start(segment, machine)
    theta = start + data.draw(between(0.0, 1.0)) * math.pi / design.cylinders

    def load(angle):
        return float(windpump.load_torque_on_crank(design, angle)) / design.load_torque

    integral, _ = quad(load, start, theta, epsabs=1e-14, epsrel=1e-13)
    work = model.load_work(theta, segment, machine) / (machine.load_torque * machine.inv_I_eff)
    assert -work == pytest.approx(integral, rel=0, abs=TOLERANCE * max(1.0, design.cylinders))
