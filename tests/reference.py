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
from scipy.interpolate import PchipInterpolator

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


def equation_12(design: Design, exhaust: bool, windmill=None):
    """d(theta, theta_dot, V, W)/dt for one stroke, from Eqs. (11), (12) and (16); with
    ``windmill`` (a function of the windmill's speed [rad/s] giving its torque [N m]) in place
    of Eq. (11)."""
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
        if windmill is not None:
            torque = windmill(omega)
            drive = Rd * torque
        theta_ddot = (drive - piston_force * design.R * lever) / I_eff  # Eq. (12)
        flow = -design.A * design.R * lever * theta_dot if exhaust else 0.0  # -A dx/dt
        return [theta_dot, theta_ddot, flow, torque * omega]

    return rhs


def solve_to_switch(rhs, t, t_end, y, end, atol):
    """One DOP853 solve from (t, y) that ends at t_end, where theta reaches ``end`` (a switch of
    the load; event 0) or where theta_dot falls to 0 (event 1), whichever comes first."""

    def reaches_switch(_t, state):
        return state[0] - end

    def stops(_t, state):
        return state[1]

    reaches_switch.terminal, reaches_switch.direction = True, 1
    stops.terminal, stops.direction = True, -1
    return solve_ivp(
        rhs, (t, t_end), y, method="DOP853", rtol=RTOL, atol=atol, events=(reaches_switch, stops)
    )


def reference_run(
    design: Design, t_end: float, theta0: float, theta_dot0: float, windmill=None
) -> Reference:
    """The state at t_end, or at the stall if theta_dot reaches 0 first (``windmill``: as
    :func:`equation_12`)."""
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

        rhs = equation_12(design, stroke % 2 == 1, windmill)
        sol = solve_to_switch(rhs, t, t_end, y, dead_centre, atol)
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


def summed_load(design: Design, segment_mid: float):
    """The load term of Eq. (12) summed over the faces delivering in the segment around
    ``segment_mid``, as the issue states it: cylinder k at theta - 2 pi k / n, top face while
    sin(phi) < 0 (pi < phi < 2 pi), bottom face (double-acting) the other half, each braking the
    crank by rho_w g h A R |sin(phi + theta_c)/cos(theta_c)|."""
    n, ratio = design.cylinders, design.L / design.R
    scale = design.rho_w * design.g * design.h * design.A * design.R
    lags = [2 * math.pi * k / n for k in range(n)]
    delivering = [
        lag
        for lag in lags
        if math.sin(segment_mid - lag) < 0
        or (design.double_acting and math.sin(segment_mid - lag) > 0)
    ]

    def load(theta):
        total = 0.0
        for lag in delivering:
            phi = theta - lag
            theta_c = math.asin(math.sin(phi) / ratio)
            total += abs(math.sin(phi + theta_c) / math.cos(theta_c))
        return -scale * total

    return load


def segment_ahead(design: Design, theta: float):
    """(the switch that ends the segment theta is in [rad], that segment's summed load); a theta
    on a switch up to round-off belongs to the segment it starts."""
    width = math.pi / design.cylinders
    segment = math.floor(theta / width)
    if (segment + 1) * width - theta < 1e-13:
        segment += 1
    return (segment + 1) * width, summed_load(design, (segment + 0.5) * width)


def general_rhs(design: Design, load):
    """d(theta, theta_dot, V, W)/dt with the torque curve T_0 + (T_m - T_0) x (2 - x)."""
    Rd = design.R1 / design.R0
    I_eff = design.I1 + design.I0 * Rd**2
    pressure = design.rho_w * design.g * design.h

    def rhs(_t, y):
        theta, theta_dot = y[0], y[1]
        x = Rd * theta_dot / design.omega_m
        torque = design.T_0 + (design.T_m - design.T_0) * x * (2 - x)
        braking = load(theta)
        return [
            theta_dot,
            (Rd * torque + braking) / I_eff,
            -braking / pressure * theta_dot if pressure else 0.0,
            torque * Rd * theta_dot,
        ]

    return rhs


def general_reference_run(design: Design, t_end: float, theta0: float, theta_dot0: float):
    """Like :func:`reference_run` for several cylinders, double-acting faces and T_0: one
    solve_ivp call per segment between switches (every pi / n), a stop located as an event and
    resumed from rest when R+ T_0 exceeds the load there."""
    Rd = design.R1 / design.R0
    t, y = 0.0, np.array([theta0, theta_dot0, 0.0, 0.0])
    atol = [1e-12, 1e-13 * min(1.0, max(theta_dot0, 1e-3)), 1e-18, 1e-12]
    while True:
        end, load = segment_ahead(design, y[0])
        if y[1] == 0.0 and Rd * design.T_0 + load(y[0]) <= 0.0:
            return Reference(t, y[0], 0.0, y[2], y[3], True, t)

        sol = solve_to_switch(general_rhs(design, load), t, t_end, y, end, atol)
        t, y = sol.t[-1], sol.y[:, -1].copy()
        if sol.t_events[1].size:
            y[1] = 0.0  # at rest: the loop decides whether it moves on
            continue
        if not sol.t_events[0].size:
            return Reference(t, y[0], y[1], y[2], y[3], False, None)
        y[0] = end


def wind_rhs(design: Design, load, wind_t, wind_V):
    """:func:`general_rhs` in a wind record: the curve at V(t) by similarity, written out as the
    issue states it (T_m, T_0 scaled by (V/V_ref)^2, omega_m by V/V_ref)."""
    Rd = design.R1 / design.R0
    I_eff = design.I1 + design.I0 * Rd**2
    pressure = design.rho_w * design.g * design.h

    def rhs(t, y):
        theta, theta_dot = y[0], y[1]
        ratio = float(np.interp(t, wind_t, wind_V)) / design.V_ref
        T_m, T_0 = design.T_m * ratio**2, design.T_0 * ratio**2
        omega_m = design.omega_m * ratio
        omega = Rd * theta_dot
        torque = (
            T_0 + (T_m - T_0) * (omega / omega_m) * (2 - omega / omega_m)
            if ratio
            else (-(design.T_m - design.T_0) * (omega / design.omega_m) ** 2)
        )
        braking = load(theta)
        return [
            theta_dot,
            (Rd * torque + braking) / I_eff,
            -braking / pressure * theta_dot if pressure else 0.0,
            torque * omega,
        ]

    return rhs


def restart_time(design: Design, load_at_rest: float, t: float, wind_t, wind_V) -> float:
    """The first time >= t when R+ T_0 (V/V_ref)^2 exceeds the load torque, by brentq on each
    interval of the record (V linear there), or inf."""
    from scipy.optimize import brentq

    Rd = design.R1 / design.R0

    def excess(time):
        ratio = float(np.interp(time, wind_t, wind_V)) / design.V_ref
        return Rd * design.T_0 * ratio**2 - load_at_rest

    if excess(t) > 0:
        return t
    for a, b in zip(wind_t[:-1], wind_t[1:], strict=True):
        if b <= t or excess(b) <= 0:
            continue
        return brentq(excess, max(a, t), b, xtol=1e-14, rtol=1e-15)
    return math.inf


def wind_reference_run(design: Design, t_end, theta0, theta_dot0, wind_t, wind_V):
    """:func:`general_reference_run` in a wind record: each solve also ends at the record's next
    sample (where V(t) has a kink); a crank at rest waits for :func:`restart_time`. Returns the
    final Reference and the lists of stop and start times."""
    wind_t, wind_V = np.asarray(wind_t, float), np.asarray(wind_V, float)
    t, y = 0.0, np.array([theta0, theta_dot0, 0.0, 0.0])
    atol = [1e-12, 1e-13 * min(1.0, max(theta_dot0, 1e-3)), 1e-18, 1e-12]
    stops, starts = [], []
    moving = theta_dot0 > 0
    while True:
        end, load = segment_ahead(design, y[0])
        if y[1] == 0.0:
            restart = restart_time(design, -load(y[0]), t, wind_t, wind_V)
            if moving and restart > t:
                stops.append(t)
            if restart >= t_end:
                return (
                    Reference(t_end, y[0], 0.0, y[2], y[3], True, stops[-1] if stops else 0.0),
                    stops,
                    starts,
                )
            if restart > t or not moving:
                starts.append(restart)
            t, moving = restart, True
        later = wind_t[wind_t > t + 1e-12]
        until = min(t_end, later[0]) if later.size else t_end
        sol = solve_to_switch(wind_rhs(design, load, wind_t, wind_V), t, until, y, end, atol)
        t, y = sol.t[-1], sol.y[:, -1].copy()
        if sol.t_events[1].size:
            y[1] = 0.0
            continue
        if sol.t_events[0].size:
            y[0] = end
        elif t >= t_end:
            return Reference(t, y[0], y[1], y[2], y[3], False, None), stops, starts


def rotor_law(rotor, V: float):
    """A rotor's torque [N m] against its speed [rad/s] in the steady wind V [m/s], written from
    its table as issue 39 states the law: ``1/2 rho_air pi r^3 V_s^2 C_Q(omega r / V_s)``,
    V_s = min(V, V_furl), C_Q scipy's PCHIP through the table, continued past it by its end
    slope."""
    curve = PchipInterpolator(rotor.table_tsr, rotor.table_cq)
    last, slope = rotor.table_tsr[-1], float(curve.derivative()(rotor.table_tsr[-1]))
    r = rotor.diameter / 2
    V_s = V if rotor.V_furl is None else min(V, rotor.V_furl)

    def torque(omega):
        lam = omega * r / V_s
        cq = float(curve(lam)) if lam <= last else rotor.table_cq[-1] + slope * (lam - last)
        return 0.5 * rotor.rho_air * math.pi * r**3 * V_s**2 * cq

    return torque
