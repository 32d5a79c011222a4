"""An independent reference for Eq. (12): scipy's DOP853 at a tight tolerance, stroke by stroke.

Written from the paper, not from windpump's kernels: the load's lever arm is
sin(theta + theta_c)/cos(theta_c) with theta_c = arcsin(sin(theta)/(L/R)) as Eq. (12) writes it, and
the pumped volume and the shaft work are integrated as states (not taken from Eq. 1 in closed form).
Each stroke, dead centre to dead centre, is one solve_ivp call ending on a terminal event, so no step
straddles a switch of the load; a second terminal event finds theta_dot = 0 (a stall).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy.integrate import solve_ivp

from windpump import Design

RTOL = 1e-11


@dataclasses.dataclass(frozen=True)
class Reference:
    t: float
    theta: float
    theta_dot: float
    volume: float
    shaft_work: float
    stalled: bool
    t_stall: float | None


def equation_12(design: Design, exhaust: bool):
    """d(theta, theta_dot, V, W)/dt for one stroke, from Eqs. (11), (12) and (16)."""
    Rd, I_eff = design.R1 / design.R0, design.I1 + design.I0 * (design.R1 / design.R0) ** 2
    ratio = design.L / design.R
    piston_force = -design.rho_w * design.g * design.h * design.A if exhaust else 0.0  # F

    def rhs(_t, y):
        theta, theta_dot = y[0], y[1]
        omega = Rd * theta_dot
        torque = design.T_m * (omega / design.omega_m) * (2 - omega / design.omega_m)  # Eq. (11)
        theta_c = math.asin(math.sin(theta) / ratio)
        lever = math.sin(theta + theta_c) / math.cos(theta_c)
        drive = (
            Rd**2
            * design.T_m
            * (theta_dot / design.omega_m)
            * (2 - Rd * theta_dot / design.omega_m)
        )
        theta_ddot = (drive - piston_force * design.R * lever) / I_eff  # Eq. (12)
        flow = -design.A * design.R * lever * theta_dot if exhaust else 0.0  # -A dx/dt
        return [theta_dot, theta_ddot, flow, torque * omega]

    return rhs


def reference_run(design: Design, t_end: float, theta0: float, theta_dot0: float) -> Reference:
    """The state at t_end, or at the stall if theta_dot reaches 0 first."""
    t, y = 0.0, np.array([theta0, theta_dot0, 0.0, 0.0])
    if theta_dot0 == 0.0:
        return Reference(0.0, theta0, 0.0, 0.0, 0.0, True, 0.0)
    # Absolute tolerances far below the run's scales, the speed's below the kick (start-ups from a
    # small kick grow exponentially, and only a relative accuracy follows them).
    atol = [1e-12, 1e-13 * min(1.0, theta_dot0), 1e-18, 1e-12]
    while True:
        stroke = math.floor(y[0] / math.pi)
        if (stroke + 1) * math.pi - y[0] < 1e-13:  # on a dead centre, up to round-off
            stroke += 1
        dead_centre = (stroke + 1) * math.pi

        def reaches_dead_centre(_t, state, end=dead_centre):
            return state[0] - end

        def stalls(_t, state):
            return state[1]

        reaches_dead_centre.terminal, reaches_dead_centre.direction = True, 1
        stalls.terminal, stalls.direction = True, -1
        sol = solve_ivp(
            equation_12(design, stroke % 2 == 1),
            (t, t_end),
            y,
            method="DOP853",
            rtol=RTOL,
            atol=atol,
            events=(reaches_dead_centre, stalls),
        )
        t, y = sol.t[-1], sol.y[:, -1].copy()
        if sol.t_events[1].size:
            return Reference(t, y[0], 0.0, y[2], y[3], True, t)
        if not sol.t_events[0].size:
            return Reference(t, y[0], y[1], y[2], y[3], False, None)
        y[0] = dead_centre


def averaged_rhs(design: Design):
    """Eq. (19) in crank speed [rad/s^2], written from Eq. (12) with the load averaged by Eq. (18)."""
    Rd = design.R1 / design.R0
    I_eff = design.I1 + design.I0 * Rd**2
    mean_load = design.rho_w * design.g * design.h * design.A * design.R / math.pi

    def rhs(speed):
        drive = Rd**2 * design.T_m * (speed / design.omega_m) * (2 - Rd * speed / design.omega_m)
        return (drive - mean_load) / I_eff

    return rhs
