"""Compiled kernels for the equation of motion, Eq. (12). Private: call :func:`windpump.simulate`.

Method (model-notes.md, "Dynamics")
-----------------------------------
The load switches on and off at the dead centres theta = k pi, where the right-hand side has a kink.
Between dead centres the crank angle is the independent variable, with state ``u = theta_dot^2/2``
and the quadratures ``t`` and ``W`` (shaft work)::

    du/dtheta = (R+ T(R+ theta_dot) + load(theta)) / I_eff,  dt/dtheta = 1/theta_dot,  dW/dtheta = R+ T

so every stroke (dead centre to dead centre) is integrated on its own and no step straddles a
switch. A stroke is split into m equal Dormand-Prince 5(4) sub-steps, m chosen from the error
estimates; every exhaust stroke is the same in theta, so the loads at the stage nodes of a split
are tabulated once per run. Samples on the uniform output grid come from the method's order-4
continuous extension.

Where theta is a poor variable the same tableau integrates in time, with state
``(theta, theta_dot)`` and quadrature ``W``: approaching theta_dot = 0 (a stall, located by Newton's
method on the step length) and for the stretch that ends at ``t_end``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, vectorize

# Compiled once per machine (cache=True). NumPy's error model drops the zero-division checks;
# fastmath allows contraction and reassociation only: no-NaN/no-inf assumptions would break step
# rejection, and approximate library functions would cost accuracy.
kernel = njit(cache=True, error_model="numpy", fastmath={"contract", "reassoc", "nsz", "arcp"})

# Dormand-Prince 5(4): nodes c, stage matrix a, 5th-order weights b (= a7), b - b_hat in e.
C2, C3, C4, C5 = 1 / 5, 3 / 10, 4 / 5, 8 / 9
A21 = 1 / 5
A31, A32 = 3 / 40, 9 / 40
A41, A42, A43 = 44 / 45, -56 / 15, 32 / 9
A51, A52, A53, A54 = 19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729
A61, A62, A63, A64, A65 = 9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656
B1, B3, B4, B5, B6 = 35 / 384, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84
E1, E3, E4, E5, E6, E7 = 71 / 57600, -71 / 16695, 71 / 1920, -17253 / 339200, 22 / 525, -1 / 40
NODES = np.array([0.0, C2, C3, C4, C5, 1.0, 1.0])

# Hairer's continuous extension of order 4 (DOPRI5's contd5): weights of the dense-output term.
D1, D3, D4 = -12715105075 / 11282082432, 87487479700 / 32700410799, -10690763975 / 1880347072
D5, D6, D7 = 701980252875 / 199316789632, -1453857185 / 822651844, 69997945 / 29380423

# Outcomes of a run, and of a time-domain excursion.
REACHED_T_END = 0
STALLED = 1
OVER_BUDGET = 2
LANDED = 3

# Independent variable of a step.
ANGLE = 0  # state (u, -), quadratures (t, W)
TIME = 1  # state (theta, theta_dot), quadrature (W, -)

# Indices into the parameter vector.
R_DAGGER, T_M, OMEGA_M, INV_I_EFF, LOAD_TORQUE, L_OVER_R = range(6)

# Columns of the output array.
OUT_T, OUT_THETA, OUT_THETA_DOT, OUT_WORK, OUT_STROKES, OUT_F2 = range(6)


def pack_params(R_dagger, T_m, omega_m, I_eff, load_torque, L_over_R):
    """The design as the float vector the kernels take."""
    return np.array([R_dagger, T_m, omega_m, 1.0 / I_eff, load_torque, L_over_R], dtype=np.float64)


@kernel
def lever_arm(theta, L_over_R):
    """sin(theta + theta_c)/cos(theta_c) = (dx/dtheta)/R, from Eq. (1) [-]."""
    s = math.sin(theta)
    return s * (1.0 + math.cos(theta) / math.sqrt(L_over_R * L_over_R - s * s))


@kernel
def f2(theta, L_over_R):
    """f2 of Eq. (16): -(dx/dtheta)/(2R) while exhausting (pi < theta mod 2 pi < 2 pi), else 0."""
    if theta - 2.0 * math.pi * math.floor(theta / (2.0 * math.pi)) <= math.pi:
        return 0.0
    return -0.5 * lever_arm(theta, L_over_R)


@kernel
def swept_strokes(theta, L_over_R):
    """Exhaust strokes completed at theta, from theta = 0: the integral of f2, by Eq. (1) [-]."""
    revolutions = math.floor(theta / (2.0 * math.pi))
    phi = theta - 2.0 * math.pi * revolutions
    if phi <= math.pi:
        return revolutions
    s = math.sin(phi)
    x_over_R = L_over_R + 1.0 - (math.sqrt(L_over_R * L_over_R - s * s) + math.cos(phi))
    return revolutions + 0.5 * (2.0 - x_over_R)


@vectorize(["float64(float64, float64)"], cache=True)
def lever_arm_ufunc(theta, L_over_R):
    return lever_arm(theta, L_over_R)


@vectorize(["float64(float64, float64)"], cache=True)
def f2_ufunc(theta, L_over_R):
    return f2(theta, L_over_R)


@vectorize(["float64(float64, float64)"], cache=True)
def swept_strokes_ufunc(theta, L_over_R):
    return swept_strokes(theta, L_over_R)


@kernel
def load_on_crank(theta, exhaust, p):
    """Load term of Eq. (12) [N m]: rho_w g h A R times the lever arm while exhausting, else 0."""
    if not exhaust:
        return 0.0
    return p[LOAD_TORQUE] * lever_arm(theta, p[L_OVER_R])


@kernel
def windmill_torque_on_crank(theta_dot, p):
    """R+ T(R+ theta_dot) [N m]: the windmill torque of Eq. (11) reflected to the crank."""
    x = p[R_DAGGER] * theta_dot / p[OMEGA_M]
    return p[R_DAGGER] * p[T_M] * x * (2.0 - x)


@kernel
def rates(domain, s, x0, x1, load, p, exhaust):
    """Derivatives (dx0, dx1, dq0, dq1) with respect to the independent variable s.

    ANGLE: s = theta, x0 = u = theta_dot^2/2, q = (t, W). ``load`` is the load at s (NaN: compute).
    TIME: s = t, x = (theta, theta_dot), q = (W, -).
    """
    if domain == ANGLE:
        theta_dot = math.sqrt(2.0 * x0)
        drive = windmill_torque_on_crank(theta_dot, p)
        if load != load:
            load = load_on_crank(s, exhaust, p)
        return (drive + load) * p[INV_I_EFF], 0.0, 1.0 / theta_dot, drive
    drive = windmill_torque_on_crank(x1, p)
    return x1, (drive + load_on_crank(x0, exhaust, p)) * p[INV_I_EFF], drive * x1, 0.0


@kernel
def dp5_step(domain, s, x0, x1, q0, q1, h, k1, loads, exhaust, p):
    """One Dormand-Prince 5(4) step of size h from (s; x0, x1; q0, q1) with k1 = rates there.

    ``loads`` holds the load at the 7 stage nodes (NaN: compute). Returns whether the step is valid
    (in the ANGLE domain u must stay > 0; a stage below 0 makes the error NaN), the new state, its rates
    (k7, for the next step: first same as last), the error estimates of x0, x1 and q0, and the
    dense-output terms of x0, q0 and q1 (for :func:`dense_value`).
    """
    a0, a1, a2, a3 = k1
    y0 = x0 + h * A21 * a0
    y1 = x1 + h * A21 * a1
    b0, b1, b2, b3 = rates(domain, s + C2 * h, y0, y1, loads[1], p, exhaust)
    y0 = x0 + h * (A31 * a0 + A32 * b0)
    y1 = x1 + h * (A31 * a1 + A32 * b1)
    c0, c1, c2, c3 = rates(domain, s + C3 * h, y0, y1, loads[2], p, exhaust)
    y0 = x0 + h * (A41 * a0 + A42 * b0 + A43 * c0)
    y1 = x1 + h * (A41 * a1 + A42 * b1 + A43 * c1)
    d0, d1, d2, d3 = rates(domain, s + C4 * h, y0, y1, loads[3], p, exhaust)
    y0 = x0 + h * (A51 * a0 + A52 * b0 + A53 * c0 + A54 * d0)
    y1 = x1 + h * (A51 * a1 + A52 * b1 + A53 * c1 + A54 * d1)
    e0, e1, e2, e3 = rates(domain, s + C5 * h, y0, y1, loads[4], p, exhaust)
    y0 = x0 + h * (A61 * a0 + A62 * b0 + A63 * c0 + A64 * d0 + A65 * e0)
    y1 = x1 + h * (A61 * a1 + A62 * b1 + A63 * c1 + A64 * d1 + A65 * e1)
    f0, f1, f2_, f3 = rates(domain, s + h, y0, y1, loads[5], p, exhaust)
    n0 = x0 + h * (B1 * a0 + B3 * c0 + B4 * d0 + B5 * e0 + B6 * f0)
    n1 = x1 + h * (B1 * a1 + B3 * c1 + B4 * d1 + B5 * e1 + B6 * f1)
    m0 = q0 + h * (B1 * a2 + B3 * c2 + B4 * d2 + B5 * e2 + B6 * f2_)
    m1 = q1 + h * (B1 * a3 + B3 * c3 + B4 * d3 + B5 * e3 + B6 * f3)
    k7 = rates(domain, s + h, n0, n1, loads[6], p, exhaust)
    g0, g1, g2 = k7[0], k7[1], k7[2]
    err0 = h * (E1 * a0 + E3 * c0 + E4 * d0 + E5 * e0 + E6 * f0 + E7 * g0)
    err1 = h * (E1 * a1 + E3 * c1 + E4 * d1 + E5 * e1 + E6 * f1 + E7 * g1)
    err2 = h * (E1 * a2 + E3 * c2 + E4 * d2 + E5 * e2 + E6 * f2_ + E7 * g2)
    dense = (
        h * (D1 * a0 + D3 * c0 + D4 * d0 + D5 * e0 + D6 * f0 + D7 * g0),
        h * (D1 * a2 + D3 * c2 + D4 * d2 + D5 * e2 + D6 * f2_ + D7 * g2),
        h * (D1 * a3 + D3 * c3 + D4 * d3 + D5 * e3 + D6 * f3 + D7 * k7[3]),
    )
    valid = domain != ANGLE or n0 > 0.0  # a stage at u < 0 has made the error NaN as well
    return valid, (n0, n1, m0, m1), k7, (err0, err1, err2), dense


NO_TABLE = np.full(7, np.nan)  # stage loads to be computed, not looked up


@kernel
def step_factor(err):
    """Standard step-size update for a 5th-order pair, clipped to [0.2, 5]."""
    if err == 0.0:
        return 5.0
    return min(5.0, max(0.2, 0.9 * err**-0.2))


@kernel
def locate_in_time_step(t, x0, x1, q0, h_hi, k1, exhaust, p, component, target):
    """Step length h in (0, h_hi] at which x[component] of a time step reaches target.

    Newton's method on the step length, with the slope taken from the rates at the step's end:
    the step is a smooth function of h, so a few iterations reach round-off. Returns (h, state).
    """
    h = h_hi
    for _ in range(60):
        _, y, k7, _, _ = dp5_step(TIME, t, x0, x1, q0, 0.0, h, k1, NO_TABLE, exhaust, p)
        slope = k7[component]
        if slope == 0.0:
            break
        h_new = min(h_hi, max(h - (y[component] - target) / slope, 0.0))
        converged = abs(h_new - h) <= 1e-15 * h or h_new == 0.0
        h = h_new
        if converged:
            break
    _, y, _, _, _ = dp5_step(TIME, t, x0, x1, q0, 0.0, h, k1, NO_TABLE, exhaust, p)
    return h, y


@kernel
def advance_in_time(t, theta, theta_dot, W, theta_target, t_target, exhaust, p, rtol, steps_left):
    """Integrate in time from t until theta reaches theta_target, theta_dot reaches 0, or t
    reaches t_target, whichever comes first.

    Returns (outcome, t, theta, theta_dot, W, steps used); outcome is LANDED, STALLED,
    REACHED_T_END or OVER_BUDGET.
    """
    scale_theta = rtol * math.pi
    scale_speed = rtol * p[OMEGA_M] / p[R_DAGGER]
    k1 = rates(TIME, t, theta, theta_dot, np.nan, p, exhaust)
    h = t_target - t
    if k1[1] < 0.0:
        h = min(h, 0.5 * theta_dot / -k1[1])
    if theta_dot > 0.0:
        h = min(h, (theta_target - theta) / theta_dot)
    used = 0
    while used < steps_left:
        used += 1
        h = min(h, t_target - t)
        last = h == t_target - t
        _, y, k7, err, _ = dp5_step(TIME, t, theta, theta_dot, W, 0.0, h, k1, NO_TABLE, exhaust, p)
        scaled = max(abs(err[0]) / scale_theta, abs(err[1]) / scale_speed)
        if not scaled <= 1.0:
            h *= step_factor(scaled) if math.isfinite(scaled) else 0.2
            continue
        outcome = REACHED_T_END if last else -1
        if y[1] <= 0.0:
            h, y = locate_in_time_step(t, theta, theta_dot, W, h, k1, exhaust, p, 1, 0.0)
            outcome = STALLED
        if y[0] >= theta_target:
            h, y = locate_in_time_step(t, theta, theta_dot, W, h, k1, exhaust, p, 0, theta_target)
            outcome = LANDED
        if outcome == REACHED_T_END:
            return outcome, t_target, y[0], y[1], y[2], used
        if outcome == STALLED:
            return outcome, t + h, y[0], 0.0, y[2], used
        if outcome == LANDED:
            return outcome, t + h, theta_target, y[1], y[2], used
        t, theta, theta_dot, W = t + h, y[0], y[1], y[2]
        k1 = k7
        h *= step_factor(scaled)
    return OVER_BUDGET, t, theta, theta_dot, W, used


@kernel
def dense_value(sigma, start, end, rate_start, rate_end, dense, h):
    """A component at s + sigma h inside a step, by the order-4 continuous extension."""
    rise = end - start
    back = h * rate_start - rise
    return start + sigma * (
        rise + (1.0 - sigma) * (back + sigma * (rise - h * rate_end - back + (1.0 - sigma) * dense))
    )


@kernel
def grid_tables(n_per_stroke, L_over_R):
    """Swept strokes and f2 at the grid angles k pi / n_per_stroke of one revolution."""
    delta = math.pi / n_per_stroke
    strokes = np.empty(2 * n_per_stroke)
    f2s = np.empty(2 * n_per_stroke)
    for row in range(2 * n_per_stroke):
        strokes[row] = swept_strokes(row * delta, L_over_R)
        f2s[row] = f2(row * delta, L_over_R)
    return strokes, f2s


@kernel
def record(out, n, t, theta, theta_dot, W, strokes, f2_value):
    out[n, OUT_T] = t
    out[n, OUT_THETA] = theta
    out[n, OUT_THETA_DOT] = theta_dot
    out[n, OUT_WORK] = W
    out[n, OUT_STROKES] = strokes
    out[n, OUT_F2] = f2_value
    return n + 1


@kernel
def record_anywhere(out, n, t, theta, theta_dot, W, p):
    lr = p[L_OVER_R]
    return record(out, n, t, theta, theta_dot, W, swept_strokes(theta, lr), f2(theta, lr))


# The time per step is a quadrature of 1/theta_dot: its error matters relative to the step's
# duration. At 10 rtol it leaves running designs to the u test and still guards slow starts.
TIME_RTOL_FACTOR = 10.0
MAX_TABLED_SUBSTEPS = 64  # strokes split into more equal sub-steps compute their loads


@kernel
def tabulate_stroke(m, p, tables, built):
    """Load at the 7 stage nodes of each of m equal sub-steps of an exhaust stroke [N m].

    Every exhaust stroke is the same in theta, so a run computes each used m once.
    """
    h = math.pi / m
    for i in range(m):
        for stage in range(7):
            tables[m, i, stage] = load_on_crank(math.pi + (i + NODES[stage]) * h, True, p)
    built[m] = True


@kernel
def integrate(p, theta0, theta_dot0, t_end, n_per_stroke, rtol, max_steps, out):
    """Integrate Eq. (12) from (theta0, theta_dot0) at t = 0 up to t_end or a stall.

    Each stroke (dead centre to dead centre) is split into m equal sub-steps, m chosen from the
    error estimates of the previous stroke. A failed sub-step is retried as the rest of the stroke
    split more finely, from where it began; a stroke entered part way (at the start, or after a
    stretch in time) is split in proportion.

    ``out`` is a (capacity, 6) array; row i receives sample i (columns OUT_*): the start, every grid
    angle g pi / n_per_stroke passed, and the end. Returns (samples written, outcome, steps).
    """
    period = 2 * n_per_stroke
    delta = math.pi / n_per_stroke
    strokes_table, f2_table = grid_tables(n_per_stroke, p[L_OVER_R])
    tables = np.empty((MAX_TABLED_SUBSTEPS + 1, MAX_TABLED_SUBSTEPS, 7))
    built = np.zeros(MAX_TABLED_SUBSTEPS + 1, dtype=np.bool_)
    scale_u = 0.5 * (p[OMEGA_M] / p[R_DAGGER]) ** 2

    t, theta, W = 0.0, theta0, 0.0
    u = 0.5 * theta_dot0 * theta_dot0
    n = record_anywhere(out, 0, t, theta, theta_dot0, W, p)
    if theta_dot0 <= 0.0:
        return n, STALLED, 0

    g = int(math.floor(theta0 / delta)) + 1  # the next grid angle to sample is g * delta
    if g * delta <= theta0:  # theta0 sits on a grid angle, up to round-off
        g += 1
    steps = 0
    m = 4  # sub-steps per stroke
    while True:
        stroke = (g - 1) // n_per_stroke  # the stroke [stroke pi, (stroke + 1) pi] holding theta
        exhaust = stroke % 2 == 1
        stroke_end = (stroke + 1) * math.pi
        last_grid = (stroke + 1) * n_per_stroke  # grid index of stroke_end
        full = theta == stroke * math.pi
        m_seg = m if full else max(1, int(math.ceil(m * (stroke_end - theta) / math.pi)))
        use_table = full and exhaust and m_seg <= MAX_TABLED_SUBSTEPS
        if use_table and not built[m_seg]:
            tabulate_stroke(m_seg, p, tables, built)
        segment_start = theta
        h = (stroke_end - theta) / m_seg
        k1 = rates(ANGLE, theta, u, 0.0, np.nan, p, exhaust)
        worst = 0.0
        failed = False
        i = 0
        while i < m_seg:
            if steps >= max_steps:
                return n, OVER_BUDGET, steps
            theta_i = segment_start + i * h
            if k1[0] < 0.0 and u < -k1[0] * max(h, g * delta - theta_i):
                break  # theta_dot may reach 0 before the next grid angle: go on in time
            if theta_i + h <= theta_i:
                break  # sub-steps no longer resolve theta: go on in time
            loads = tables[m_seg, i] if use_table else NO_TABLE
            ok, y, k7, err, dense = dp5_step(ANGLE, theta_i, u, 0.0, t, W, h, k1, loads, exhaust, p)
            steps += 1
            scaled = max(
                abs(err[0]) / (rtol * max(scale_u, u)),
                abs(err[2]) / (TIME_RTOL_FACTOR * rtol * max(y[2] - t, 1e-300)),
            )
            if not (ok and scaled <= 1.0):
                # Finish the stroke from here in smaller equal sub-steps.
                shrink = step_factor(scaled) if ok else 0.25
                m = max(m + 1, int(math.ceil(math.pi / (h * shrink))))
                failed = True
                break
            if y[2] > t_end:
                break  # the sub-step would pass t_end: go on in time
            last = i == m_seg - 1
            theta_new = stroke_end if last else theta_i + h
            # Samples at the grid angles this sub-step passed, from the continuous extension; the
            # stroke's end is a grid angle by index, whatever the round-off in g * delta.
            while g * delta <= theta_new or (last and g <= last_grid):
                row = g % period
                if g * delta >= theta_new or (last and g == last_grid):
                    u_g, t_g, W_g = y[0], y[2], y[3]
                else:
                    sigma = (g * delta - theta_i) / h
                    u_g = dense_value(sigma, u, y[0], k1[0], k7[0], dense[0], h)
                    t_g = dense_value(sigma, t, y[2], k1[2], k7[2], dense[1], h)
                    W_g = dense_value(sigma, W, y[3], k1[3], k7[3], dense[2], h)
                n = record(
                    out, n, t_g, g * delta, math.sqrt(2.0 * u_g), W_g,
                    g // period + strokes_table[row], f2_table[row],
                )
                g += 1
                if n >= out.shape[0] - 1:
                    return n, OVER_BUDGET, steps
            u, t, W, theta = y[0], y[2], y[3], theta_new
            k1 = k7
            worst = max(worst, scaled)
            i += 1
        if i == m_seg:  # the stroke is done: size the next one's sub-steps
            if t >= t_end:
                if out[n - 1, OUT_T] < t:
                    n = record_anywhere(out, n, t, theta, math.sqrt(2.0 * u), W, p)
                return n, REACHED_T_END, steps
            m = max(1, int(math.ceil(math.pi / (h * step_factor(worst)))))
            continue
        if failed:
            continue
        # theta_dot may reach 0 (singular in theta, regular in time), or the sub-step would pass
        # t_end, or sub-steps no longer resolve theta: go on in time as far as the next grid angle.
        outcome, t, theta, theta_dot, W, used = advance_in_time(
            t, theta, math.sqrt(2.0 * u), W, g * delta, t_end, exhaust, p, rtol, max_steps - steps
        )
        steps += used
        if outcome != LANDED:
            if outcome != OVER_BUDGET:
                n = record_anywhere(out, n, t, theta, theta_dot, W, p)
            return n, outcome, steps
        u = 0.5 * theta_dot * theta_dot
        row = g % period
        n = record(out, n, t, theta, theta_dot, W, g // period + strokes_table[row], f2_table[row])
        g += 1
        if n >= out.shape[0] - 1:
            return n, OVER_BUDGET, steps
