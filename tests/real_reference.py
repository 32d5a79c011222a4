"""An independent reference for the real machine (issue: reciprocating mass, rising main, leak
hole, transmission): scipy's DOP853 at a tight tolerance, segment by segment.

Written from the issue's statement, not from windpump's kernels: Eq. (1) and its two derivatives
in the rod and crank lengths, each face's swept flow, the hole's capacity ``C_d a_L sqrt(2 g h)``
and pressure ``rho_w/2 (u / (C_d a_L))^2``, Darcy-Weisbach in the rising main, and

    J theta_ddot = eta_t R+ T - load + m_r g sum x_c' - J' theta_dot^2 / 2.

The water delivered, the shaft work, the friction loss and the faces' work sum p_k u_k are
integrated as states. A stop is an event; the crank then moves on when the torque at rest N > 0.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy.integrate import solve_ivp

from windpump import Design

RTOL = 1e-11


@dataclasses.dataclass(frozen=True)
class RealReference:
    t: float
    theta: float
    theta_dot: float
    volume: float
    shaft_work: float
    friction_loss: float
    faces_work: float  # int sum p_k u_k dt [J]
    stalled: bool


def piston(design: Design, phi: float) -> tuple[float, float, float]:
    """x, dx/dphi, d^2x/dphi^2 [m] of Eq. (1) at a cylinder's own angle phi."""
    R, L = design.R, design.L
    s, c = math.sin(phi), math.cos(phi)
    r = math.sqrt(L * L - R * R * s * s)
    x = R * (1 - c) + L - r
    dx = R * s + R * R * s * c / r
    ddx = R * c + R * R * (c * c - s * s) / r + R**4 * s * s * c * c / r**3
    return x, dx, ddx


def delivering(design: Design, phi_mid: float) -> int:
    """+1: the top face delivers (sin phi < 0, the upstroke), -1: the bottom face, 0: none."""
    if math.sin(phi_mid) < 0:
        return 1
    return -1 if design.double_acting else 0


def machine_rhs(design: Design, segment_mid: float, continued: bool = False):
    """d(theta, theta_dot, V, W, F, P)/dt inside the segment around ``segment_mid``.

    ``continued``: every delivering face delivers u - q_L (negative inside a hole's windows) at
    rho_w g (h + h_f), the loads continued through the windows (a windowed segment's steps)."""
    Rd = design.R1 / design.R0
    I_eff = design.I1 + design.I0 * Rd**2
    n = design.cylinders
    lags = [2 * math.pi * k / n for k in range(n)]
    faces = [delivering(design, segment_mid - lag) for lag in lags]
    a_leak = math.pi * design.d_leak**2 / 4
    q_leak = design.Cd_leak * a_leak * math.sqrt(2 * design.g * design.h)
    a_main = math.pi * design.D_main**2 / 4
    rho, g = design.rho_w, design.g

    def rhs(_t, y):
        theta, theta_dot = y[0], y[1]
        x = Rd * theta_dot / design.omega_m
        torque = design.T_0 + (design.T_m - design.T_0) * x * (2 - x)
        J, J_slope, weight = I_eff, 0.0, 0.0
        swept = []
        for lag, face in zip(lags, faces, strict=True):
            _, dx, ddx = piston(design, theta - lag)
            J += design.m_r * dx * dx
            J_slope += 2 * design.m_r * dx * ddx
            weight += design.m_r * g * dx
            if face:
                swept.append(abs(dx))
        flows = [design.A * arm * theta_dot - q_leak for arm in swept]
        if not continued:
            flows = [max(flow, 0.0) for flow in flows]
        Q = sum(flows)
        h_f = design.f_main * design.L_main / design.D_main * (Q / a_main) ** 2 / (2 * g)
        load = faces_power = 0.0
        for arm in swept:
            u = design.A * arm * theta_dot
            if continued or q_leak == 0.0 or u > q_leak:
                p = rho * g * (design.h + h_f)
            else:
                p = 0.5 * rho * (u / (design.Cd_leak * a_leak)) ** 2
            load += p * design.A * arm
            faces_power += p * u
        drive = design.eta_t * Rd * torque
        theta_ddot = (drive - load + weight - 0.5 * J_slope * theta_dot**2) / J
        return [theta_dot, theta_ddot, Q, torque * Rd * theta_dot, rho * g * h_f * Q, faces_power]

    return rhs


def torque_at_rest(design: Design, theta: float, segment_mid: float) -> float:
    """N(theta): eta_t R+ T_0 + m_r g sum x_c' - the static head on the delivering faces of a
    tight piston (none through a hole)."""
    Rd = design.R1 / design.R0
    n = design.cylinders
    total = design.eta_t * Rd * design.T_0
    for k in range(n):
        lag = 2 * math.pi * k / n
        _, dx, _ = piston(design, theta - lag)
        total += design.m_r * design.g * dx
        if design.d_leak == 0.0 and delivering(design, segment_mid - lag):
            total -= design.rho_w * design.g * design.h * design.A * abs(dx)
    return total


def real_reference_run(
    design: Design, t_end: float, theta0: float, theta_dot0: float
) -> RealReference:
    """The state at t_end, or where the crank comes to rest for good."""
    width = math.pi / design.cylinders
    t, y = 0.0, np.array([theta0, theta_dot0, 0.0, 0.0, 0.0, 0.0])
    atol = [1e-12, 1e-12, 1e-18, 1e-10, 1e-12, 1e-10]
    while True:
        segment = math.floor(y[0] / width)
        if (segment + 1) * width - y[0] < 1e-13:
            segment += 1
        end, mid = (segment + 1) * width, (segment + 0.5) * width
        if y[1] == 0.0 and torque_at_rest(design, y[0], mid) <= 0.0:
            return RealReference(t, y[0], 0.0, *y[2:], stalled=True)

        def reaches_switch(_t, state, end=end):
            return state[0] - end

        def stops(_t, state):
            return state[1] if state[1] != 0.0 else -1e-300

        reaches_switch.terminal, reaches_switch.direction = True, 1
        stops.terminal, stops.direction = True, -1
        sol = solve_ivp(
            machine_rhs(design, mid), (t, t_end), y, method="DOP853", rtol=RTOL, atol=atol,
            events=(reaches_switch, stops),
        )  # fmt: skip
        t, y = sol.t[-1], sol.y[:, -1].copy()
        if sol.t_events[1].size and t > sol.t[0]:
            y[1] = 0.0  # at rest: the loop decides whether it moves on
            continue
        if not sol.t_events[0].size:
            return RealReference(t, y[0], y[1], *y[2:], stalled=False)
        y[0] = end
