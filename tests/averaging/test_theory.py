"""The averaged theory written once (windpump.averaging.theory) against the averaged equation built here
from its parts: Eq. (12)'s load averaged over a revolution by quadrature, the windmill curve of
Eq. (11) with T_0 scaled by similarity, I_eff from the inertias; roots by brentq, tau by a
central difference. Every caller (averaged, maps, site) gives the same numbers on the same points.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

import windpump
from windpump import Design, theory

from conftest import SEED

DESIGNS = {
    "seed": SEED,
    "three double-acting cylinders, torque at rest": SEED.replace(
        cylinders=3, double_acting=True, T_0=0.2, T_m=2.0
    ),
    "two cylinders, short rod, light rotor": SEED.replace(
        cylinders=2, L=0.06, I0=0.01, I1=0.002, T_0=0.1
    ),
}
RATIOS = np.array([2.0, 4.0, 9.0])
HEADS = np.array([0.0, 1.5, 3.0, 6.0])
WINDS = np.array([2.5, 5.0, 8.0])


def lever(phi: float, ratio: float) -> float:
    """sin(phi + theta_c) / cos(theta_c), sin(theta_c) = sin(phi) / (L/R) (the paper's form)."""
    theta_c = math.asin(math.sin(phi) / ratio)
    return math.sin(phi + theta_c) / math.cos(theta_c)


def mean_load(design: Design, head: float) -> float:
    """Eq. (12)'s load summed over the delivering faces, averaged over a revolution [N m]."""
    n, ratio = design.cylinders, design.L / design.R
    scale = design.rho_w * design.g * head * design.A * design.R

    def load(theta):
        total = 0.0
        for k in range(n):
            phi = (theta - 2 * math.pi * k / n) % (2 * math.pi)
            if phi > math.pi or design.double_acting:  # top face exhausts on (pi, 2 pi)
                total += abs(lever(phi, ratio))
        return scale * total

    edges = [j * math.pi / n for j in range(2 * n + 1)]
    pieces = [quad(load, a, b, epsabs=0.0, epsrel=1e-13)[0] for a, b in itertools.pairwise(edges)]
    return sum(pieces) / (2 * math.pi)


def averaged_rhs(design: Design, ratio: float, head: float, V: float):
    """d theta_dot / dt of the cycle mean [rad/s^2] at gear ratio, head and wind."""
    s = V / design.V_ref
    I_eff = design.I1 + design.I0 * ratio**2
    M = mean_load(design, head)

    def curve(omega):  # Eq. (11) with T_0, at V_ref
        x = omega / design.omega_m
        return design.T_0 + (design.T_m - design.T_0) * x * (2 - x)

    def rhs(speed):  # similarity: in the wind s, T(omega) = s^2 T_ref(omega / s)
        return (ratio * s * s * curve(ratio * speed / s) - M) / I_eff

    return rhs, M


def reference(design: Design, ratio: float, head: float, V: float):
    """(margin, alpha+, alpha-, tau) of the averaged equation, NaN where it cannot run."""
    rhs, M = averaged_rhs(design, ratio, head, V)
    s = V / design.V_ref
    vertex = s * design.omega_m / ratio  # the windmill's peak: fastest acceleration
    margin = ratio * design.T_m * s * s / M if M > 0 else math.inf
    if margin <= 1.0:
        return margin, math.nan, math.nan, math.nan
    top = vertex * 4.0
    plus = brentq(rhs, vertex, top, xtol=1e-15, rtol=1e-15)
    minus = brentq(rhs, -top, vertex, xtol=1e-15, rtol=1e-15)
    step = 1e-6 * plus
    slope = (rhs(plus + step) - rhs(plus - step)) / (2 * step)
    return margin, plus, minus, -1.0 / slope


@pytest.fixture(scope="module", params=list(DESIGNS))
def case(request):
    """A design, its cycle mean broadcast over (gear ratio, head, wind), and the references."""
    design = DESIGNS[request.param]
    mean = theory.cycle_mean(
        design,
        gear_ratio=RATIOS[:, None, None],
        head=HEADS[None, :, None],
        V=WINDS[None, None, :],
    )
    expected = np.empty((4, RATIOS.size, HEADS.size, WINDS.size))
    for i, ratio in enumerate(RATIOS):
        for j, head in enumerate(HEADS):
            for k, V in enumerate(WINDS):
                expected[:, i, j, k] = reference(design, ratio, head, V)
    return design, mean, expected


def test_the_broadcast_cycle_mean_is_the_averaged_equation(case):
    """Margin (Eq. 22), both roots (Eq. 21) and tau (Eq. 25) at every point of a 3-D grid."""
    _, mean, (margin, plus, minus, tau) = case
    assert mean.alpha_plus.shape == (RATIOS.size, HEADS.size, WINDS.size)
    np.testing.assert_allclose(mean.margin, margin, rtol=1e-9)
    np.testing.assert_array_equal(mean.runs, margin > 1.0)
    assert np.isnan(plus).any() and not np.isnan(plus).all()  # both kinds of point are checked
    np.testing.assert_allclose(mean.alpha_plus, plus, rtol=1e-10)
    np.testing.assert_allclose(mean.alpha_minus, minus, rtol=1e-8, atol=1e-9 * np.nanmax(plus))
    np.testing.assert_allclose(mean.tau, tau, rtol=1e-6)


def test_averaged_maps_and_site_agree_with_the_reference_at_every_point(case):
    """The three callers of the one form give the reference's numbers on the grid's points."""
    design, _, (margin, plus, minus, tau) = case
    for i, ratio in enumerate(RATIOS):
        for j, head in enumerate(HEADS):
            point = design.replace(R1=design.R0 * ratio, h=float(head))
            for k, V in enumerate(WINDS):
                if not margin[i, j, k] > 1.0:
                    continue
                in_wind = point.in_wind(float(V))
                assert windpump.steady_speeds(in_wind) == pytest.approx(
                    (plus[i, j, k], minus[i, j, k]), rel=1e-8, abs=1e-9 * plus[i, j, k]
                )
                assert windpump.time_constant(in_wind) == pytest.approx(tau[i, j, k], rel=1e-6)
                flow = windpump.steady_flow(point, float(V))
                per_radian = point.volume_per_revolution / (2 * math.pi)
                assert flow == pytest.approx(per_radian * plus[i, j, k], rel=1e-10)
    at_V_ref = int(np.flatnonzero(WINDS == design.V_ref)[0])
    mapped = windpump.design_map(design, RATIOS, HEADS)
    np.testing.assert_allclose(mapped.margin, margin[:, :, at_V_ref].T, rtol=1e-9)
    np.testing.assert_allclose(mapped.alpha_plus, plus[:, :, at_V_ref].T, rtol=1e-10)
    np.testing.assert_allclose(mapped.tau, tau[:, :, at_V_ref].T, rtol=1e-6)


def test_the_groups_of_the_design_are_the_theorys():
    """I_eff, the load scale, the mean load and R+ T_0 of a Design come from the one form."""
    design = DESIGNS["three double-acting cylinders, torque at rest"]
    Rd = design.R1 / design.R0
    assert design.I_eff == pytest.approx(design.I1 + design.I0 * Rd**2, rel=1e-15)
    assert design.mean_load_torque == pytest.approx(mean_load(design, design.h), rel=1e-11)
    assert design.rest_torque_on_crank == pytest.approx(Rd * design.T_0, rel=1e-15)
    mean = theory.cycle_mean(design, V=2 * design.V_ref)
    assert mean.rest_torque == pytest.approx(4 * Rd * design.T_0, rel=1e-15)
