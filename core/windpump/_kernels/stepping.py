"""Dormand-Prince steps of Eq. (12) in either independent variable, and the time-domain stretch.

ANGLE: s = theta, state x0 = u - Lambda(theta) with u = theta_dot^2/2 and Lambda the load's work
since the segment began (:func:`~.real.conservative_work`), quadratures (t, W). Only the
windmill (and, in the real machine, the dissipated work) changes x0, so a Runge-Kutta step keeps
``I_eff du = dW + I_eff dLambda`` exactly.
TIME: s = t, state (theta, theta_dot), quadratures (-, W).
"""

from __future__ import annotations

import math

import numpy as np

from .dopri5 import (
    A21,
    A31,
    A32,
    A41,
    A42,
    A43,
    A51,
    A52,
    A53,
    A54,
    A61,
    A62,
    A63,
    A64,
    A65,
    B1,
    B3,
    B4,
    B5,
    B6,
    C2,
    C3,
    C4,
    C5,
    D1,
    D3,
    D4,
    D5,
    D6,
    D7,
    E1,
    E3,
    E4,
    E5,
    E6,
    E7,
    step_factor,
)  # fmt: skip
from .jit import by_value_kernel, kernel
from .model import windmill_torque_on_crank
from .real import (
    ROW,
    advance_work,
    angle_rates,
    dense_work,
    leak_error,
    time_rates,
    torque_at_rest,
    transmitted,
)
from .rotor import furl_scale, unfurled_rest_torque
from .wind import rise_above, wind_scale

ANGLE = 0
TIME = 1

# Outcomes of a run, and of a stretch in time.
REACHED_T_END = 0
STALLED = 1
OVER_BUDGET = 2
LANDED = 3
RESTING = 4  # ran to t_end in a wind record, and rests there

# Kinds of events: the crank came to rest and waits for the wind, or began to turn from rest.
STOP, START = -1.0, 1.0

NO_TABLE = np.full(8, np.nan)  # the TIME domain has no stage loads


@by_value_kernel
def rates(domain, s, x0, x1, aux, row, machine, segment):
    """Derivatives (dx0, dx1, dq0, dq1) with respect to the independent variable s.

    In the ANGLE domain ``x1`` is the time (the wind's clock; it integrates 1/theta_dot as q0
    does), ``aux`` the conservative work Lambda at s, always given (tabulated or computed by the
    driver): computing it here would keep this function from being inlined into the step, which
    costs the seed example a third of its time. ``row`` holds the real machine's values at s
    (:mod:`.real`; in TIME, its scratch). In the TIME domain q0 is unused and q1 is the work.
    """
    if domain == ANGLE:
        return angle_rates(x0, x1, aux, row, machine)
    return time_rates(s, x0, x1, row, segment, machine)


@by_value_kernel
def dp5_step(domain, s, x0, x1, q0, q1, h, k1, aux, extra, segment, machine):
    """One Dormand-Prince 5(4) step of size h from (s; x0, x1; q0, q1), k1 = the rates there.

    ``aux`` holds the ANGLE domain's conservative work at the 7 stage nodes (unused in TIME) and
    ``extra`` the real machine's rows there (:mod:`.real`; in TIME, scratch). Returns
    whether the step is valid (u stays > 0 at every stage), the new state, its rates (k7: the
    next step's k1), the error estimates of x0, x1 and q0, and the dense-output terms of x0, q0
    and q1 (for :func:`~.dopri5.dense_value`).
    """
    a0, a1, a2, a3 = k1
    y0 = x0 + h * A21 * a0
    y1 = x1 + h * A21 * a1
    b0, b1, b2, b3 = rates(domain, s + C2 * h, y0, y1, aux[1], extra[1], machine, segment)
    y0 = x0 + h * (A31 * a0 + A32 * b0)
    y1 = x1 + h * (A31 * a1 + A32 * b1)
    c0, c1, c2, c3 = rates(domain, s + C3 * h, y0, y1, aux[2], extra[2], machine, segment)
    y0 = x0 + h * (A41 * a0 + A42 * b0 + A43 * c0)
    y1 = x1 + h * (A41 * a1 + A42 * b1 + A43 * c1)
    d0, d1, d2, d3 = rates(domain, s + C4 * h, y0, y1, aux[3], extra[3], machine, segment)
    y0 = x0 + h * (A51 * a0 + A52 * b0 + A53 * c0 + A54 * d0)
    y1 = x1 + h * (A51 * a1 + A52 * b1 + A53 * c1 + A54 * d1)
    e0, e1, e2, e3 = rates(domain, s + C5 * h, y0, y1, aux[4], extra[4], machine, segment)
    y0 = x0 + h * (A61 * a0 + A62 * b0 + A63 * c0 + A64 * d0 + A65 * e0)
    y1 = x1 + h * (A61 * a1 + A62 * b1 + A63 * c1 + A64 * d1 + A65 * e1)
    f0, f1, f2, f3 = rates(domain, s + h, y0, y1, aux[5], extra[5], machine, segment)
    n0 = x0 + h * (B1 * a0 + B3 * c0 + B4 * d0 + B5 * e0 + B6 * f0)
    n1 = x1 + h * (B1 * a1 + B3 * c1 + B4 * d1 + B5 * e1 + B6 * f1)
    m0 = q0 + h * (B1 * a2 + B3 * c2 + B4 * d2 + B5 * e2 + B6 * f2)
    m1 = advance_work(q1, h, a3, c3, d3, e3, f3)
    k7 = rates(domain, s + h, n0, n1, aux[6], extra[6], machine, segment)
    g0, g1, g2, g3 = k7
    err0 = h * (E1 * a0 + E3 * c0 + E4 * d0 + E5 * e0 + E6 * f0 + E7 * g0)
    err1 = h * (E1 * a1 + E3 * c1 + E4 * d1 + E5 * e1 + E6 * f1 + E7 * g1)
    err2 = h * (E1 * a2 + E3 * c2 + E4 * d2 + E5 * e2 + E6 * f2 + E7 * g2)
    dense = (
        h * (D1 * a0 + D3 * c0 + D4 * d0 + D5 * e0 + D6 * f0 + D7 * g0),
        h * (D1 * a2 + D3 * c2 + D4 * d2 + D5 * e2 + D6 * f2 + D7 * g2),
        dense_work(h, a3, c3, d3, e3, f3, g3),
    )
    valid = math.isfinite(err0) and math.isfinite(err2)  # a stage at u <= 0 makes them NaN or inf
    err3 = leak_error(h, a3, c3, d3, e3, f3, g3)
    return valid, (n0, n1, m0, m1), k7, (err0, err1, err2, err3), dense


@kernel
def time_step(t, theta, theta_dot, W, h, k1, row, segment, machine):
    """A TIME-domain step (no tables; ``row`` is the real machine's scratch)."""
    return dp5_step(TIME, t, theta, theta_dot, 0.0, W, h, k1, NO_TABLE, row, segment, machine)


@kernel
def time_rates_at(t, theta, theta_dot, row, segment, machine):
    """The TIME domain's rates at a state (a step's first stage)."""
    return rates(TIME, t, theta, theta_dot, np.nan, row[0], machine, segment)


@kernel
def locate_in_time_step(t, x0, x1, q1, h_hi, k1, row, segment, machine, component, target):
    """Step length h in (0, h_hi] at which x[component] of a time step reaches target.

    The step's result is a smooth function of its length, crossing target between 0 and h_hi.
    Newton's method on the length, with the slope from the rates at the step's end, inside a
    bracket that shrinks with every iterate; an iterate that leaves the bracket is replaced by
    its midpoint, so the search always converges. Returns (h, state).
    """
    lo, hi = 0.0, h_hi
    rising = target > (x0 if component == 0 else x1)  # the sign of the crossing
    h = h_hi
    for _ in range(200):
        _, y, k7, _, _ = time_step(t, x0, x1, q1, h, k1, row, segment, machine)
        residual = (y[0] if component == 0 else y[1]) - target
        if residual == 0.0:
            break
        if (residual > 0.0) == rising:
            hi = h
        else:
            lo = h
        slope = k7[0] if component == 0 else k7[1]
        h_next = h - residual / slope if slope != 0.0 else -1.0
        if not lo < h_next < hi:
            h_next = 0.5 * (lo + hi)
        if hi - lo <= 4e-16 * hi or h_next == h:
            h = hi  # the end of the bracket past the crossing
            break
        h = h_next
    _, y, _, _, _ = time_step(t, x0, x1, q1, h, k1, row, segment, machine)
    return h, y


@kernel
def moves_from_rest(t, theta, segment, machine):
    """At theta_dot = 0 the crank turns on when R+ T_0 (V(t)/V_ref)^2 exceeds the load there (it
    cannot turn backwards, so otherwise it stays stopped)."""
    s = wind_scale(t, machine.wind)
    drive = transmitted(windmill_torque_on_crank(0.0, s, machine), machine)
    return drive + torque_at_rest(theta, segment, machine) > 0.0


@kernel
def next_start(t, theta, segment, machine):
    """The first time >= t [s] at which a crank resting at theta moves (:func:`moves_from_rest`),
    or inf: where the wind first rises past the threshold R+ T_0 s^2 = load, nudged past it by
    round-off."""
    if moves_from_rest(t, theta, segment, machine):
        return t
    rest_torque = unfurled_rest_torque(machine.rotor, machine.T_0)
    if rest_torque == 0.0:
        return math.inf
    load = -torque_at_rest(theta, segment, machine)
    rest = transmitted(machine.R_dagger * rest_torque, machine)
    threshold = math.sqrt(max(load, 1e-300) / rest)  # V/V_ref to exceed (above 0: calm air never)
    if threshold > furl_scale(machine.rotor):  # the furled wheel's torque stops growing there
        return math.inf
    while True:
        crossing = rise_above(t, threshold, machine.wind)
        if crossing == math.inf:
            return crossing
        nudge = 4e-16 * max(abs(crossing), 1.0)
        for _ in range(64):
            if moves_from_rest(crossing, theta, segment, machine):
                return crossing
            crossing += nudge
            nudge *= 2.0
        t = crossing


@kernel
def first_time_step(t, theta, theta_dot, theta_target, t_target, k1):
    """A first step length: to t_target, no further than theta_target at the present speed (or
    acceleration, from rest), and no longer than halves the speed."""
    h = t_target - t
    if k1[1] < 0.0:
        h = min(h, 0.5 * theta_dot / -k1[1])
    if theta_dot > 0.0:
        h = min(h, (theta_target - theta) / theta_dot)
    elif k1[1] > 0.0:
        h = min(h, math.sqrt(2.0 * (theta_target - theta) / k1[1]))
    return h


PACE_MARGIN = 10.0
"""How far off pace a run must be to be stopped before max_steps (:func:`off_pace`): a start
can be stiffer than the rest, and a run can stall early (the seed example at m_r = 1e6 kg takes
141,497 steps in 0.16 s, then stalls)."""


@kernel
def off_pace(steps, t, t_end, max_steps, pace, mark):
    """Whether a run has taken max_steps, or has just taken another ``pace`` steps since the
    window of ``mark`` (steps, t) began at a pace that would pass max_steps PACE_MARGIN times
    over before t_end (the window then starts again here). A stiff or crawling run is caught
    after ``pace`` steps of it, not max_steps."""
    if steps >= max_steps:
        return True
    if steps < mark[0] + pace:
        return False
    ahead = (steps - mark[0]) * (t_end - t)  # the rest's steps at this pace, times the window's t
    late = ahead > PACE_MARGIN * (max_steps - steps) * (t - mark[1])
    mark[0], mark[1] = steps, t
    return late


@kernel
def advance_in_time(
    t, theta, theta_dot, W, theta_target, t_target, segment, machine, rtol, budget,
    steps_before, t_end, max_steps, pace, mark,
):  # fmt: skip
    """Integrate in time until theta reaches theta_target, the crank stops, or t reaches t_target.

    A crank that comes to rest goes on if :func:`moves_from_rest` (torque at rest, T_0 > 0) and
    stops there otherwise. Returns (outcome, t, theta, theta_dot, W, steps used); outcome is
    LANDED, STALLED, REACHED_T_END or OVER_BUDGET: after ``budget`` steps, or when the run's
    steps (``steps_before`` + used) are :func:`off_pace`.
    """
    scale_theta = rtol * math.pi
    row = np.empty((7, ROW))  # the real machine's scratch, a row per stage
    k1 = time_rates_at(t, theta, theta_dot, row, segment, machine)
    h = first_time_step(t, theta, theta_dot, theta_target, t_target, k1)
    used = 0
    while used < budget:
        if off_pace(steps_before + used, t, t_end, max_steps, pace, mark):
            break
        used += 1
        h = min(h, t_target - t)
        last = h == t_target - t
        _, y, k7, err, _ = time_step(t, theta, theta_dot, W, h, k1, row, segment, machine)
        # Relative in speed: near theta_dot = 0 the windmill torque is linear in theta_dot, so a
        # start-up grows exponentially from however small a kick.
        scale_speed = rtol * max(abs(theta_dot), abs(y[1]), 1e-300)
        scaled = max(abs(err[0]) / scale_theta, abs(err[1]) / scale_speed)
        if not scaled <= 1.0:
            h *= step_factor(scaled) if math.isfinite(scaled) else 0.2
            continue
        if y[1] <= 0.0 and theta_dot == 0.0:
            h *= 0.5  # from rest, it moves at first: the step was too long to tell
            continue
        outcome = REACHED_T_END if last else -1
        if y[1] <= 0.0:
            h, y = locate_in_time_step(t, theta, theta_dot, W, h, k1, row, segment, machine, 1, 0.0)
            outcome = STALLED
        if y[0] >= theta_target:
            h, y = locate_in_time_step(
                t, theta, theta_dot, W, h, k1, row, segment, machine, 0, theta_target
            )
            outcome = LANDED
        if outcome == REACHED_T_END:
            return outcome, t_target, y[0], y[1], y[3], used
        if outcome == LANDED:
            return outcome, t + h, theta_target, y[1], y[3], used
        if outcome == STALLED:
            if not moves_from_rest(t + h, y[0], segment, machine):
                return outcome, t + h, y[0], 0.0, y[3], used
            t, theta, theta_dot, W = t + h, y[0], 0.0, y[3]
            k1 = time_rates_at(t, theta, theta_dot, row, segment, machine)
            h = first_time_step(t, theta, theta_dot, theta_target, t_target, k1)
            continue
        t, theta, theta_dot, W = t + h, y[0], y[1], y[3]
        k1 = k7
        h *= step_factor(scaled)
    return OVER_BUDGET, t, theta, theta_dot, W, used
