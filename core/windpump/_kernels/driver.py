"""The driver: Eq. (12) from a start to t_end or a stop, segment by segment, sampled on a grid.

Between switches (every pi / n of crank angle, see :mod:`.model`) the crank angle is the
independent variable (:mod:`.stepping`), and a segment is split into m equal sub-steps, m chosen
from the error estimates of the previous segment. Every segment of the same parity loads the crank
the same way (a shift of 2 pi / n turns cylinder k into k - 1), so what a split needs at its stage
nodes is tabulated once per run. Where theta is a poor variable (the crank near rest) or a step
would pass t_end, the run goes on in time as far as the next grid angle or switch.
"""

from __future__ import annotations

import math

import numpy as np

from .dopri5 import NODES, dense_value, step_factor
from .jit import kernel
from .model import delivered_strokes, flow_factor, segment_at, segment_start
from .real import (
    ROW,
    conservative_torque,
    conservative_work,
    fill_row,
    inertia_ratio,
    next_leak_kink,
    work_at,
    work_rows,
    write_work,
    zero_work,
)
from .stepping import (
    ANGLE,
    LANDED,
    OVER_BUDGET,
    REACHED_T_END,
    RESTING,
    STALLED,
    START,
    STOP,
    advance_in_time,
    dp5_step,
    moves_from_rest,
    next_start,
    rates,
)
from .wind import has_record, next_kink

# Rows of the output array, one per sampled quantity; the work quadratures last (the real
# machine's four from WORK on: shaft work, delivered volume, friction loss, leak loss).
T, THETA, THETA_DOT, STROKES, FLOW_FACTOR, WORK = range(6)
ROWS = 6  # the ideal machine's

# The time per step is a quadrature of 1/theta_dot: its error matters relative to the step's
# duration. At 10 rtol it leaves running designs to the u test and still guards slow starts.
TIME_RTOL_FACTOR = 10.0
MAX_TABLED_SUBSTEPS = 64  # segments split into more equal sub-steps compute their loads
MAX_SUBSTEPS = 2**20  # a segment that needs more is finished in time
FIRST_SUBSTEPS = 4


@kernel
def faces(machine):
    """Delivering faces: stroke volumes 2 R A delivered per revolution."""
    return machine.cylinders * (2 if machine.double_acting else 1)


@kernel
def grid_tables(n_per_stroke, machine):
    """At the grid angles g pi / n_per_stroke of one revolution: strokes delivered since theta = 0,
    the flow factor, the conservative work since the segment began, and J / I_eff."""
    rows = 2 * n_per_stroke
    delta = math.pi / n_per_stroke
    strokes, flows, works = np.empty(rows), np.empty(rows), np.empty(rows)
    inertias = np.empty(rows)
    for row in range(rows):
        theta = row * delta
        segment = (row * machine.cylinders) // n_per_stroke
        strokes[row] = delivered_strokes(theta, machine)
        flows[row] = flow_factor(theta, segment, machine)
        if (row * machine.cylinders) % n_per_stroke == 0:
            # On a switch the faces that start or stop sit at a dead centre and deliver nothing;
            # the side without them keeps round-off (sin pi = 1.2e-16) out of the flow.
            flows[row] = min(flows[row], flow_factor(theta, segment - 1, machine))
        works[row] = conservative_work(theta, segment, machine)
        inertias[row] = inertia_ratio(theta, machine)
    return strokes, flows, works, inertias


@kernel
def tabulate_segment(parity, m, machine, tables, rows, built):
    """For each of m equal sub-steps of a segment of this parity: the conservative work at its 7
    stage nodes and (column 7) the conservative torque at its start [N m]; and the real machine's
    rows at the nodes."""
    start = segment_start(parity, machine)
    h = (segment_start(parity + 1, machine) - start) / m
    for i in range(m):
        stage_values(start + i * h, h, parity, machine, tables[parity, m, i], rows[parity, m, i])
    built[parity, m] = True


@kernel
def stage_values(theta, h, segment, machine, aux, rows):
    """Fill a sub-step's stage values from theta, of length h: ``aux`` (the conservative work
    at its nodes, then the conservative torque at theta) and the real machine's ``rows``."""
    for stage in range(7):
        node = theta + NODES[stage] * h
        aux[stage] = conservative_work(node, segment, machine)
        fill_row(rows[stage], node, segment, machine)
    aux[7] = conservative_torque(theta, segment, machine)


@kernel
def copy_columns(target, source, n):
    """``target[:, :n] = source[:, :n]``, element by element: numba compiles a slice assignment
    with the string formatting of its shape-mismatch error, 4 of the 13 s a first start spent
    compiling the seed example's kernels."""
    for row in range(source.shape[0]):
        for i in range(n):
            target[row, i] = source[row, i]


@kernel
def with_room(out, n, more):
    """``out``, or a copy with twice the room, so that ``more`` samples fit after the first n."""
    if n + more <= out.shape[1]:
        return out
    bigger = np.empty((out.shape[0], max(2 * out.shape[1], n + more)))
    copy_columns(bigger, out, n)
    return bigger


@kernel
def record(out, n, t, theta, theta_dot, W, strokes, flow, final):
    """Write sample n (``out`` has room for it); return the sample count. A sample no later than
    the last one (the crank moved less than time can resolve) replaces it, but the initial state
    stays as given."""
    if n > 0 and t <= out[T, n - 1]:
        if n > 1:
            n -= 1
        elif not final:
            return n
    out[T, n] = t
    out[THETA, n] = theta
    out[THETA_DOT, n] = theta_dot
    write_work(out, WORK, n, W)
    out[STROKES, n] = strokes
    out[FLOW_FACTOR, n] = flow
    return n + 1


@kernel
def record_anywhere(out, n, t, theta, theta_dot, W, segment, machine, final):
    """Write a sample off the grid (the start or the end of the run); ``out`` has room."""
    strokes = delivered_strokes(theta, machine)
    flow = flow_factor(theta, segment, machine)
    return record(out, n, t, theta, theta_dot, W, strokes, flow, final)


@kernel
def kinetic(theta, theta_dot, machine):
    """Kinetic energy per unit I_eff, J theta_dot^2 / (2 I_eff) [rad^2/s^2]."""
    return 0.5 * inertia_ratio(theta, machine) * theta_dot * theta_dot


@kernel
def first_segment(theta, machine):
    """The segment holding theta, robust to round-off at a switch."""
    segment = segment_at(theta, machine)
    if segment_start(segment + 1, machine) <= theta:
        segment += 1
    return segment


@kernel
def time_of_sample(target, t, t_end_step, rate_start, rate_end, dense, h):
    """The fraction sigma of a step at which its continuous extension of t reaches ``target``.

    t(sigma) rises through the step (dt/dtheta = 1/theta_dot > 0): Newton's method on the
    extension's polynomial (:func:`~.dopri5.dense_value`), inside a shrinking bracket.
    """
    lo, hi = 0.0, 1.0
    rise = t_end_step - t
    back = h * rate_start - rise
    c = rise - h * rate_end - back
    sigma = (target - t) / rise
    for _ in range(60):
        p = back + sigma * (c + (1.0 - sigma) * dense)
        q = rise + (1.0 - sigma) * p
        residual = t + sigma * q - target
        if residual == 0.0:
            break
        if residual < 0.0:
            lo = sigma
        else:
            hi = sigma
        slope = q + sigma * ((1.0 - sigma) * (c + dense - 2.0 * dense * sigma) - p)
        step = sigma - residual / slope if slope > 0.0 else -1.0
        if not lo < step < hi:
            step = 0.5 * (lo + hi)
        if hi - lo <= 1e-15 or step == sigma:
            return step
        sigma = step
    return sigma


@kernel
def record_in_step(
    out, n, j, sample_dt, theta_i, h, t, W, u_free, y, k1, k7, dense, segment, machine
):
    """Samples at the times j sample_dt that an ANGLE sub-step from (theta_i, t, W) to y passed,
    from its continuous extension; returns (out, n, the next j)."""
    more = int(y[2] / sample_dt) - j + 2
    if more > 0 and n + more > out.shape[1]:
        out = with_room(out, n, more)
    while j * sample_dt <= y[2]:
        target = j * sample_dt
        sigma = time_of_sample(target, t, y[2], k1[2], k7[2], dense[1], h)
        theta = theta_i + sigma * h
        u = conservative_work(theta, segment, machine) + dense_value(
            sigma, u_free, y[0], k1[0], k7[0], dense[0], h
        )
        W_j = work_at(sigma, W, y[3], k1[3], k7[3], dense[2], h)
        theta_dot = math.sqrt(2.0 * max(u, 0.0) / inertia_ratio(theta, machine))
        n = record_anywhere(out, n, target, theta, theta_dot, W_j, segment, machine, False)
        j += 1
    return out, n, j


@kernel
def record_rest(out, n, j, sample_dt, t_from, t_to, theta, W, segment, machine):
    """Samples of a crank resting at theta from t_from to t_to: at both ends, and at the times
    j sample_dt between them on a time grid; returns (out, n, the next j)."""
    more = 2 + (int(t_to / sample_dt) - j + 1 if sample_dt is not None else 0)
    out = with_room(out, n, max(more, 2))
    n = record_anywhere(out, n, t_from, theta, 0.0, W, segment, machine, False)
    if sample_dt is not None:
        while j * sample_dt <= t_to:
            if j * sample_dt > t_from:
                n = record_anywhere(out, n, j * sample_dt, theta, 0.0, W, segment, machine, False)
            j += 1
    n = record_anywhere(out, n, t_to, theta, 0.0, W, segment, machine, False)
    return out, n, j


@kernel
def note_event(events, count, t, kind):
    """Append (t, kind) to the events (STOP or START), growing them; returns (events, count)."""
    if count == events.shape[1]:
        bigger = np.empty((2, 2 * count))
        copy_columns(bigger, events, count)
        events = bigger
    events[0, count] = t
    events[1, count] = kind
    return events, count + 1


@kernel
def integrate(
    machine, theta0, theta_dot0, t_end, n_per_stroke, sample_dt, rtol, max_steps, capacity
):
    """Integrate Eq. (12) from (theta0, theta_dot0) at t = 0 up to t_end or a stop.

    Samples go on the grid of angles g pi / n_per_stroke or, when sample_dt is a number (not
    None: each grid compiles its own specialisation), of times j sample_dt. In a wind record a crank that comes to rest waits (:func:`~.stepping.next_start`)
    and the run goes on to t_end. Returns (out, samples, outcome, steps, events, event count):
    ``out[:, :samples]`` holds, by rows T ... FLOW_FACTOR, the start, the grid samples and the
    end; ``events[:, :count]`` the times (row 0) of every STOP and START (row 1).
    """
    width = math.pi / machine.cylinders
    period = 2 * n_per_stroke
    delta = math.pi / n_per_stroke
    waits = has_record(machine.wind)  # a resting crank waits for the wind, to t_end
    per_revolution = faces(machine)
    strokes_table, flow_table, work_table, inertia_table = grid_tables(n_per_stroke, machine)
    tables = np.empty((2, MAX_TABLED_SUBSTEPS + 1, MAX_TABLED_SUBSTEPS, 8))
    row_tables = np.empty((2, MAX_TABLED_SUBSTEPS + 1, MAX_TABLED_SUBSTEPS, 7, ROW))
    built = np.zeros((2, MAX_TABLED_SUBSTEPS + 1), dtype=np.bool_)
    end_work = (  # Lambda at the end of a segment of each parity
        conservative_work(segment_start(1, machine), 0, machine),
        conservative_work(segment_start(2, machine), 1, machine),
    )

    scratch = np.empty(8)  # the stage values of a sub-step off the tables
    scratch_rows = np.empty((7, ROW))
    out = np.empty((ROWS - 1 + work_rows(machine), max(capacity, 2)))
    events = np.empty((2, 8))
    count = 0
    t, theta, W = 0.0, theta0, zero_work(machine)
    theta_dot = theta_dot0  # kept beside u: u underflows for theta_dot below about 1e-154
    u = kinetic(theta, theta_dot, machine)
    segment = first_segment(theta0, machine)
    n = record_anywhere(out, 0, t, theta, theta_dot0, W, segment, machine, False)
    j = 1  # the next time sample is j * sample_dt
    steps = 0
    if theta_dot0 <= 0.0:
        start = next_start(0.0, theta0, segment, machine) if waits else 0.0
        if not moves_from_rest(start, theta0, segment, machine) or start >= t_end:
            if not waits:
                return out, n, STALLED, 0, events, count
            out, n, j = record_rest(out, n, j, sample_dt, 0.0, t_end, theta, W, segment, machine)
            return out, n, RESTING, 0, events, count
        if start > 0.0:
            out, n, j = record_rest(out, n, j, sample_dt, 0.0, start, theta, W, segment, machine)
        t = start
        events, count = note_event(events, count, t, START)

    g = int(math.floor(theta0 / delta)) + 1  # the next grid angle to sample is g * delta
    if g * delta <= theta0:  # theta0 sits on a grid angle, up to round-off
        g += 1
    kink = next_kink(t, machine.wind)  # steps land on the wind record's samples
    m = FIRST_SUBSTEPS  # sub-steps per segment
    # Whether theta is where the segment starts: tracked, not compared (fastmath may round
    # (j + 1) pi/n and j pi/n differently).
    full = theta == segment_start(segment, machine)
    leak_kink = later_kink = math.inf
    kink_segment = -1
    while True:
        end = segment_start(segment + 1, machine)
        parity = segment % 2
        # The grid index of the segment's end, when the end is a grid angle (else -1).
        ends = (segment + 1) * n_per_stroke
        end_grid = ends // machine.cylinders if ends % machine.cylinders == 0 else -1
        if sample_dt is not None:
            end_grid = -1  # no grid angles on a time grid
        m_seg = m if full else max(1, int(math.ceil(m * (end - theta) / width)))
        use_table = full and m_seg <= MAX_TABLED_SUBSTEPS
        if use_table and not built[parity, m_seg]:
            tabulate_segment(parity, m_seg, machine, tables, row_tables, built)
        first = theta
        h = (end - theta) / m_seg
        work = 0.0 if full else conservative_work(theta, segment, machine)
        u_free = u - work  # u less the conservative work: only the windmill (and losses) change it
        if use_table:
            rows = row_tables[parity, m_seg, 0]
        else:
            rows = scratch_rows
            fill_row(rows[0], theta, segment, machine)
        k1 = rates(ANGLE, theta, u_free, t, work, rows[0], machine, segment)
        # The next angles where a face starts or stops delivering through its hole: found for a
        # segment at its first speed, used as the run passes them (a landing is up to round-off).
        if kink_segment != segment:
            leak_kink, later_kink = next_leak_kink(theta, theta_dot, segment, machine)
            kink_segment = segment
        elif theta >= leak_kink - 1e-9 * width:
            leak_kink, later_kink = later_kink, math.inf
        worst = 0.0
        failed = landed = False
        i = 0
        while i < m_seg:
            if steps >= max_steps:
                return out, n, OVER_BUDGET, steps, events, count
            theta_i = first + i * h
            if use_table:
                aux, rows = tables[parity, m_seg, i], row_tables[parity, m_seg, i]
            else:
                aux, rows = scratch, scratch_rows
                stage_values(theta_i, h, segment, machine, aux, rows)
            torque = aux[7]
            # (on a time grid, as far as a grid angle would be: pi / n_per_stroke)
            reach = max(h, delta if sample_dt is not None else g * delta - theta_i)
            if abs(k1[0] + torque * machine.inv_I_eff) * reach >= u:
                # u may change by more than itself before the next grid angle: theta_dot is near 0,
                # where theta is singular (dt/dtheta = 1/theta_dot) but time is not. Go on in time.
                break
            h_step, at_kink, at_wind_kink = h, False, False
            if theta_i < leak_kink < theta_i + h:  # a face starts or stops delivering inside
                h_step, at_kink = leak_kink - theta_i, True
                aux, rows = scratch, scratch_rows
                stage_values(theta_i, h_step, segment, machine, aux, rows)
            ok, y, k7, err, dense = dp5_step(
                ANGLE, theta_i, u_free, t, t, W, h_step, k1, aux, rows, segment, machine
            )
            steps += 1
            if ok and kink < y[2] <= t_end:
                # V(t) has a kink inside: take the sub-step only as far as it, from where the
                # step's continuous extension puts the kink's time (the rest of the segment
                # follows in smaller sub-steps).
                h_step *= time_of_sample(kink, t, y[2], k1[2], k7[2], dense[1], h_step)
                stage_values(theta_i, h_step, segment, machine, scratch, scratch_rows)
                ok, y, k7, err, dense = dp5_step(
                    ANGLE, theta_i, u_free, t, t, W, h_step, k1, scratch, scratch_rows, segment,
                    machine,
                )  # fmt: skip
                steps += 1
                at_kink = at_wind_kink = True
            scaled = max(
                abs(err[0]) / (rtol * u),
                abs(err[2]) / (TIME_RTOL_FACTOR * rtol * max(y[2] - t, 1e-300)),
            )
            if y[2] > t_end:
                break  # the sub-step would pass t_end: go on in time
            if not (ok and scaled <= 1.0):
                needed = width / (h_step * (step_factor(scaled) if ok else 0.25))
                if needed > MAX_SUBSTEPS:
                    break  # sub-steps this fine no longer suit theta: go on in time
                m = max(m + 1, int(math.ceil(needed)))
                failed = True
                break
            last = i == m_seg - 1 and not at_kink
            if last:
                theta_new, work = end, end_work[parity]
            else:
                theta_new = theta_i + h_step
                at_table = use_table and not at_kink
                work = aux[6] if at_table else conservative_work(theta_new, segment, machine)
            u_new = y[0] + work
            if sample_dt is not None:
                out, n, j = record_in_step(
                    out, n, j, sample_dt, theta_i, h_step, t, W, u_free, y, k1, k7, dense,
                    segment, machine,
                )  # fmt: skip
            else:
                if n + int(h / delta) + 2 > out.shape[1]:  # (a call per sample would cost 20 %)
                    out = with_room(out, n, int(h / delta) + 2)
                # Samples at the grid angles this sub-step passed, from the continuous extension;
                # the segment's end is a grid angle by index, whatever the round-off in g * delta.
                while (last and g == end_grid) or (g != end_grid and g * delta <= theta_new):
                    row = g % period
                    if g == end_grid:
                        u_g, t_g, W_g = u_new, y[2], y[3]
                    else:
                        sigma = (g * delta - theta_i) / h_step
                        u_g = work_table[row] + dense_value(
                            sigma, u_free, y[0], k1[0], k7[0], dense[0], h_step
                        )
                        t_g = dense_value(sigma, t, y[2], k1[2], k7[2], dense[1], h_step)
                        W_g = work_at(sigma, W, y[3], k1[3], k7[3], dense[2], h_step)
                    strokes = (g // period) * per_revolution + strokes_table[row]
                    theta_dot_g = math.sqrt(2.0 * u_g / inertia_table[row])
                    n = record(
                        out, n, t_g, g * delta, theta_dot_g, W_g, strokes, flow_table[row], False
                    )
                    g += 1
            u_free, t, W, theta = y[0], y[2], y[3], theta_new
            u = u_new
            theta_dot = math.sqrt(2.0 * u / inertia_ratio(theta, machine))
            k1 = k7
            worst = max(worst, scaled)
            i += 1
            if at_kink:  # past it, up to round-off in its time: on from here in a new split
                if at_wind_kink:
                    kink = next_kink(max(t, kink), machine.wind)
                    m = min(MAX_SUBSTEPS, max(1, int(math.ceil(width / (h * step_factor(worst))))))
                # (a leak's kink keeps m: the split before it may be a segment's short tail)
                landed = True
                break
        if i == m_seg and not landed:  # the segment is done: size the next one's sub-steps
            segment += 1
            was_full, full = full, True
            if t >= t_end:
                out = with_room(out, n, 1)
                if out[T, n - 1] < t:
                    n = record_anywhere(out, n, t, theta, theta_dot, W, segment, machine, True)
                return out, n, REACHED_T_END, steps, events, count
            if was_full or m_seg > 1:  # a single sub-step of a segment's tail is short by position
                m = min(MAX_SUBSTEPS, max(1, int(math.ceil(width / (h * step_factor(worst))))))
            continue
        if i > 0:
            full = False  # part of the segment is done
        if failed or landed:
            continue
        # On in time, as far as the next grid angle or switch (or sample time).
        target = end if g == end_grid or sample_dt is not None else min(g * delta, end)
        until = min(t_end, kink)
        if sample_dt is not None:
            until = min(until, j * sample_dt)
        outcome, t, theta, theta_dot, W, used = advance_in_time(
            t, theta, theta_dot, W, target, until, segment, machine, rtol, max_steps - steps
        )
        steps += used
        out = with_room(out, n, 1)
        if outcome == REACHED_T_END and t < t_end:  # a sample time or a kink
            if sample_dt is not None and t == j * sample_dt:
                n = record_anywhere(out, n, t, theta, theta_dot, W, segment, machine, False)
                j += 1
            if t == kink:
                kink = next_kink(t, machine.wind)
            u = kinetic(theta, theta_dot, machine)
            full = False
            continue
        if outcome == STALLED and waits:  # rest until the wind can turn the crank again
            events, count = note_event(events, count, t, STOP)
            start = next_start(t, theta, segment, machine)
            rest_end = min(start, t_end)
            out, n, j = record_rest(out, n, j, sample_dt, t, rest_end, theta, W, segment, machine)
            if start >= t_end:
                return out, n, RESTING, steps, events, count
            events, count = note_event(events, count, start, START)
            t, theta_dot, u = start, 0.0, 0.0
            kink = next_kink(t, machine.wind)
            full = theta == segment_start(segment, machine)
            continue
        if outcome != LANDED:
            if outcome == STALLED:
                events, count = note_event(events, count, t, STOP)
            if outcome != OVER_BUDGET:
                n = record_anywhere(out, n, t, theta, theta_dot, W, segment, machine, True)
            return out, n, outcome, steps, events, count
        u = kinetic(theta, theta_dot, machine)
        full = target == end
        if full:
            segment += 1
        if g == end_grid or (target != end and sample_dt is None):
            row = g % period
            strokes = (g // period) * per_revolution + strokes_table[row]
            n = record(out, n, t, theta, theta_dot, W, strokes, flow_table[row], False)
            g += 1
