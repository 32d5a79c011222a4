"""Compiled kernels for the equation of motion, Eq. (12). Private: call :func:`windpump.simulate`.

Method (model-notes.md, "Dynamics")
-----------------------------------
The load switches on and off at the dead centres theta = k pi, where the right-hand side has a kink.
Between dead centres the crank angle is the independent variable, with ``u = theta_dot^2/2`` and the
quadratures ``t`` and ``W`` (shaft work)::

    du/dtheta = (R+ T(R+ theta_dot) + load(theta)) / I_eff,  dt/dtheta = 1/theta_dot,  dW/dtheta = R+ T

so every stroke (dead centre to dead centre) is integrated on its own and no step straddles a
switch. A stroke is split into m equal Dormand-Prince 5(4) sub-steps, m chosen from the error
estimates; every exhaust stroke is the same in theta, so what a split needs at its stage nodes is
tabulated once per run.

The load's work over a stroke is known in closed form from Eq. (1), so the angle domain integrates
``u - Lambda(theta)`` (see :func:`load_work`): only the windmill torque is left to integrate, and it
is also the integrand of the shaft work W. A Runge-Kutta method keeps such a linear relation exactly,
so the energy balance ``I_eff du = dW + I_eff dLambda`` closes to round-off, sub-step by sub-step.
Samples on the uniform output grid come from the method's order-4 continuous extension.

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
def piston_over_R(theta, L_over_R):
    """Piston position from top dead centre over the crank radius, x/R, Eq. (1) [-]."""
    s = math.sin(theta)
    return L_over_R + 1.0 - (math.sqrt(L_over_R * L_over_R - s * s) + math.cos(theta))


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
    return revolutions + 0.5 * (2.0 - piston_over_R(phi, L_over_R))


@vectorize(["float64(float64, float64)"], cache=True)
def piston_over_R_ufunc(theta, L_over_R):
    return piston_over_R(theta, L_over_R)


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
def load_work(theta, exhaust, p):
    """Work of the load since the stroke began, per unit inertia, Lambda [J/(kg m^2)].

    The integral of the load of Eq. (12) over theta, in closed form from Eq. (1):
    ``rho_w g h A R (x/R - 2) / I_eff`` while exhausting (from bottom dead centre, x = 2R), else 0.
    It is ``-rho_w g h`` times the volume delivered in the stroke, over I_eff.
    """
    if not exhaust:
        return 0.0
    return p[LOAD_TORQUE] * p[INV_I_EFF] * (piston_over_R(theta, p[L_OVER_R]) - 2.0)


@kernel
def windmill_torque_on_crank(theta_dot, p):
    """R+ T(R+ theta_dot) [N m]: the windmill torque of Eq. (11) reflected to the crank."""
    x = p[R_DAGGER] * theta_dot / p[OMEGA_M]
    return p[R_DAGGER] * p[T_M] * x * (2.0 - x)


@kernel
def rates(domain, s, x0, x1, aux, p, exhaust):
    """Derivatives (dx0, dx1, dq0, dq1) with respect to the independent variable s.

    ANGLE: s = theta, x0 = u - Lambda(theta) with u = theta_dot^2/2, q = (t, W); ``aux`` is the
    load work Lambda at s (NaN: compute), so that only the windmill drives x0 and W.
    TIME: s = t, x = (theta, theta_dot), q = (W, -).
    """
    if domain == ANGLE:
        if aux != aux:
            aux = load_work(s, exhaust, p)
        theta_dot = math.sqrt(2.0 * (x0 + aux))
        drive = windmill_torque_on_crank(theta_dot, p)
        return drive * p[INV_I_EFF], 0.0, 1.0 / theta_dot, drive
    drive = windmill_torque_on_crank(x1, p)
    return x1, (drive + load_on_crank(x0, exhaust, p)) * p[INV_I_EFF], drive * x1, 0.0


@kernel
def dp5_step(domain, s, x0, x1, q0, q1, h, k1, aux, exhaust, p):
    """One Dormand-Prince 5(4) step of size h from (s; x0, x1; q0, q1) with k1 = rates there.

    ``aux`` holds the ANGLE domain's load work at the 7 stage nodes (NaN: compute; see
    :func:`rates`). Returns whether the step is valid (in the ANGLE domain u must stay > 0 at every
    stage), the new state, its rates
    (k7, for the next step: first same as last), the error estimates of x0, x1 and q0, and the
    dense-output terms of x0, q0 and q1 (for :func:`dense_value`).
    """
    a0, a1, a2, a3 = k1
    y0 = x0 + h * A21 * a0
    y1 = x1 + h * A21 * a1
    b0, b1, b2, b3 = rates(domain, s + C2 * h, y0, y1, aux[1], p, exhaust)
    y0 = x0 + h * (A31 * a0 + A32 * b0)
    y1 = x1 + h * (A31 * a1 + A32 * b1)
    c0, c1, c2, c3 = rates(domain, s + C3 * h, y0, y1, aux[2], p, exhaust)
    y0 = x0 + h * (A41 * a0 + A42 * b0 + A43 * c0)
    y1 = x1 + h * (A41 * a1 + A42 * b1 + A43 * c1)
    d0, d1, d2, d3 = rates(domain, s + C4 * h, y0, y1, aux[3], p, exhaust)
    y0 = x0 + h * (A51 * a0 + A52 * b0 + A53 * c0 + A54 * d0)
    y1 = x1 + h * (A51 * a1 + A52 * b1 + A53 * c1 + A54 * d1)
    e0, e1, e2, e3 = rates(domain, s + C5 * h, y0, y1, aux[4], p, exhaust)
    y0 = x0 + h * (A61 * a0 + A62 * b0 + A63 * c0 + A64 * d0 + A65 * e0)
    y1 = x1 + h * (A61 * a1 + A62 * b1 + A63 * c1 + A64 * d1 + A65 * e1)
    f0, f1, f2_, f3 = rates(domain, s + h, y0, y1, aux[5], p, exhaust)
    n0 = x0 + h * (B1 * a0 + B3 * c0 + B4 * d0 + B5 * e0 + B6 * f0)
    n1 = x1 + h * (B1 * a1 + B3 * c1 + B4 * d1 + B5 * e1 + B6 * f1)
    m0 = q0 + h * (B1 * a2 + B3 * c2 + B4 * d2 + B5 * e2 + B6 * f2_)
    m1 = q1 + h * (B1 * a3 + B3 * c3 + B4 * d3 + B5 * e3 + B6 * f3)
    k7 = rates(domain, s + h, n0, n1, aux[6], p, exhaust)
    g0, g1, g2 = k7[0], k7[1], k7[2]
    err0 = h * (E1 * a0 + E3 * c0 + E4 * d0 + E5 * e0 + E6 * f0 + E7 * g0)
    err1 = h * (E1 * a1 + E3 * c1 + E4 * d1 + E5 * e1 + E6 * f1 + E7 * g1)
    err2 = h * (E1 * a2 + E3 * c2 + E4 * d2 + E5 * e2 + E6 * f2_ + E7 * g2)
    dense = (
        h * (D1 * a0 + D3 * c0 + D4 * d0 + D5 * e0 + D6 * f0 + D7 * g0),
        h * (D1 * a2 + D3 * c2 + D4 * d2 + D5 * e2 + D6 * f2_ + D7 * g2),
        h * (D1 * a3 + D3 * c3 + D4 * d3 + D5 * e3 + D6 * f3 + D7 * k7[3]),
    )
    valid = math.isfinite(err0) and math.isfinite(err2)  # a stage at u <= 0 makes them NaN or inf
    return valid, (n0, n1, m0, m1), k7, (err0, err1, err2), dense


NO_TABLE = np.full(8, np.nan)  # stage values to be computed, not looked up


@kernel
def step_factor(err):
    """Standard step-size update for a 5th-order pair, clipped to [0.2, 5]."""
    if err == 0.0:
        return 5.0
    return min(5.0, max(0.2, 0.9 * err**-0.2))


@kernel
def locate_in_time_step(t, x0, x1, q0, h_hi, k1, exhaust, p, component, target):
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
        _, y, k7, _, _ = dp5_step(TIME, t, x0, x1, q0, 0.0, h, k1, NO_TABLE, exhaust, p)
        residual = y[component] - target
        if residual == 0.0:
            break
        if (residual > 0.0) == rising:
            hi = h
        else:
            lo = h
        slope = k7[component]
        h_next = h - residual / slope if slope != 0.0 else -1.0
        if not lo < h_next < hi:
            h_next = 0.5 * (lo + hi)
        if hi - lo <= 4e-16 * hi or h_next == h:
            h = hi  # the end of the bracket past the crossing
            break
        h = h_next
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
        # Relative in speed: near theta_dot = 0 the windmill torque is linear in theta_dot, so a
        # start-up grows exponentially from however small a kick.
        scale_speed = rtol * max(abs(theta_dot), abs(y[1]), 1e-300)
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
def grid_tables(n_per_stroke, p):
    """Swept strokes, f2 and load work at the grid angles k pi / n_per_stroke of a revolution."""
    delta = math.pi / n_per_stroke
    strokes = np.empty(2 * n_per_stroke)
    f2s = np.empty(2 * n_per_stroke)
    works = np.empty(2 * n_per_stroke)
    for row in range(2 * n_per_stroke):
        strokes[row] = swept_strokes(row * delta, p[L_OVER_R])
        f2s[row] = f2(row * delta, p[L_OVER_R])
        works[row] = load_work(row * delta, row >= n_per_stroke, p)
    return strokes, f2s, works


@kernel
def record(out, n, t, theta, theta_dot, W, strokes, f2_value, final=False):
    """Write sample n; return the sample count. A sample no later than the last one (the crank
    moved less than time can resolve) replaces it, but the initial state stays as given."""
    if n > 0 and t <= out[n - 1, OUT_T]:
        if n > 1:
            n -= 1
        elif not final:
            return n
    out[n, OUT_T] = t
    out[n, OUT_THETA] = theta
    out[n, OUT_THETA_DOT] = theta_dot
    out[n, OUT_WORK] = W
    out[n, OUT_STROKES] = strokes
    out[n, OUT_F2] = f2_value
    return n + 1


@kernel
def record_anywhere(out, n, t, theta, theta_dot, W, p, final):
    """Write a sample off the grid (the start or the end of the run)."""
    lr = p[L_OVER_R]
    return record(out, n, t, theta, theta_dot, W, swept_strokes(theta, lr), f2(theta, lr), final)


# The time per step is a quadrature of 1/theta_dot: its error matters relative to the step's
# duration. At 10 rtol it leaves running designs to the u test and still guards slow starts.
TIME_RTOL_FACTOR = 10.0
MAX_TABLED_SUBSTEPS = 64  # strokes split into more equal sub-steps compute their loads
MAX_SUBSTEPS = 2**20  # a stroke that needs more is finished in time


@kernel
def tabulate_stroke(m, p, tables, built):
    """For each of m equal sub-steps of an exhaust stroke: the load work Lambda at its 7 stage nodes,
    and (column 7) the load at its start [N m].

    Every exhaust stroke is the same in theta, so a run computes each used m once.
    """
    h = math.pi / m
    for i in range(m):
        for stage in range(7):
            tables[m, i, stage] = load_work(math.pi + (i + NODES[stage]) * h, True, p)
        tables[m, i, 7] = load_on_crank(math.pi + i * h, True, p)
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
    strokes_table, f2_table, work_table = grid_tables(n_per_stroke, p)
    tables = np.empty((MAX_TABLED_SUBSTEPS + 1, MAX_TABLED_SUBSTEPS, 8))
    built = np.zeros(MAX_TABLED_SUBSTEPS + 1, dtype=np.bool_)
    stroke_work = -2.0 * p[LOAD_TORQUE] * p[INV_I_EFF]  # Lambda at the end of an exhaust stroke

    t, theta, W = 0.0, theta0, 0.0
    theta_dot = theta_dot0  # kept beside u: u underflows for theta_dot below about 1e-154
    u = 0.5 * theta_dot * theta_dot
    n = record_anywhere(out, 0, t, theta, theta_dot0, W, p, False)
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
        work = tables[m_seg, 0, 0] if use_table else load_work(theta, exhaust, p)
        u_free = u - work  # u less the load's work: only the windmill changes it
        k1 = rates(ANGLE, theta, u_free, 0.0, work, p, exhaust)
        worst = 0.0
        failed = False
        i = 0
        while i < m_seg:
            if steps >= max_steps:
                return n, OVER_BUDGET, steps
            theta_i = segment_start + i * h
            aux = tables[m_seg, i] if use_table else NO_TABLE
            load = aux[7] if use_table else load_on_crank(theta_i, exhaust, p)
            if abs(k1[0] + load * p[INV_I_EFF]) * max(h, g * delta - theta_i) >= u:
                # u may change by more than itself before the next grid angle: theta_dot is near 0,
                # where theta is singular (dt/dtheta = 1/theta_dot) but time is not. Go on in time.
                break
            ok, y, k7, err, dense = dp5_step(
                ANGLE, theta_i, u_free, 0.0, t, W, h, k1, aux, exhaust, p
            )
            steps += 1
            scaled = max(
                abs(err[0]) / (rtol * u),
                abs(err[2]) / (TIME_RTOL_FACTOR * rtol * max(y[2] - t, 1e-300)),
            )
            if not (ok and scaled <= 1.0):
                needed = math.pi / (h * (step_factor(scaled) if ok else 0.25))
                if needed > MAX_SUBSTEPS:
                    break  # sub-steps this fine no longer suit theta: go on in time
                m = max(m + 1, int(math.ceil(needed)))
                failed = True
                break
            if y[2] > t_end:
                break  # the sub-step would pass t_end: go on in time
            last = i == m_seg - 1
            if last:
                theta_new, work = stroke_end, stroke_work if exhaust else 0.0
            else:
                theta_new = theta_i + h
                work = aux[6] if use_table else load_work(theta_new, exhaust, p)
            u_new = y[0] + work
            # Samples at the grid angles this sub-step passed, from the continuous extension; the
            # stroke's end is a grid angle by index, whatever the round-off in g * delta.
            while g * delta <= theta_new or (last and g <= last_grid):
                row = g % period
                if g * delta >= theta_new or (last and g == last_grid):
                    u_g, t_g, W_g = u_new, y[2], y[3]
                else:
                    sigma = (g * delta - theta_i) / h
                    u_g = work_table[row] + dense_value(
                        sigma, u_free, y[0], k1[0], k7[0], dense[0], h
                    )
                    t_g = dense_value(sigma, t, y[2], k1[2], k7[2], dense[1], h)
                    W_g = dense_value(sigma, W, y[3], k1[3], k7[3], dense[2], h)
                n = record(
                    out,
                    n,
                    t_g,
                    g * delta,
                    math.sqrt(2.0 * u_g),
                    W_g,
                    g // period + strokes_table[row],
                    f2_table[row],
                )
                g += 1
                if n >= out.shape[0] - 1:
                    return n, OVER_BUDGET, steps
            u_free, t, W, theta = y[0], y[2], y[3], theta_new
            u = u_new
            theta_dot = math.sqrt(2.0 * u)
            k1 = k7
            worst = max(worst, scaled)
            i += 1
        if i == m_seg:  # the stroke is done: size the next one's sub-steps
            if t >= t_end:
                if out[n - 1, OUT_T] < t:
                    n = record_anywhere(out, n, t, theta, theta_dot, W, p, True)
                return n, REACHED_T_END, steps
            if full or m_seg > 1:  # a single sub-step of a stroke's tail is short by position
                m = min(MAX_SUBSTEPS, max(1, int(math.ceil(math.pi / (h * step_factor(worst))))))
            continue
        if failed:
            continue
        # theta_dot is near 0 (singular in theta, regular in time), or the sub-step would pass t_end,
        # or sub-steps no longer suit theta: go on in time as far as the next grid angle.
        outcome, t, theta, theta_dot, W, used = advance_in_time(
            t, theta, theta_dot, W, g * delta, t_end, exhaust, p, rtol, max_steps - steps
        )
        steps += used
        if outcome != LANDED:
            if outcome != OVER_BUDGET:
                n = record_anywhere(out, n, t, theta, theta_dot, W, p, True)
            return n, outcome, steps
        u = 0.5 * theta_dot * theta_dot
        row = g % period
        n = record(out, n, t, theta, theta_dot, W, g // period + strokes_table[row], f2_table[row])
        g += 1
        if n >= out.shape[0] - 1:
            return n, OVER_BUDGET, steps
