"""The driver's output: a run's samples (on the angle grid, at the times of a time grid, at rest,
at its ends) written into a growing array, and its stops and starts as events."""

from __future__ import annotations

import math

import numpy as np

from .dopri5 import dense_value
from .jit import inline_kernel, kernel
from .model import delivered_strokes, flow_factor
from .real import (
    at_time,
    conservative_work,
    end_works,
    grid_aux,
    grid_inertia,
    grid_time,
    grid_works,
    inertia_ratio,
    work_at,
    write_work,
)

# Rows of the output array, one per sampled quantity; the work quadratures last (the real
# machine's four from WORK on: shaft work, delivered volume, friction loss, leak loss).
T, THETA, THETA_DOT, STROKES, FLOW_FACTOR, WORK = range(6)


ROWS = 6  # the ideal machine's


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
    out, n, j, sample_dt, theta_i, h, t, W, u_free, y, k1, k7, dense, frozen, segment, machine
):
    """Samples at the times j sample_dt that an ANGLE sub-step from (theta_i, t, W) to y passed,
    from its continuous extension (the real machine's frozen friction's :func:`~.real.frozen_record`
    in ``frozen``). Returns (out, n, the next j)."""
    more = int(y[2] / sample_dt) - j + 2
    if more > 0 and n + more > out.shape[1]:
        out = with_room(out, n, more)
    while j * sample_dt <= y[2]:
        target = j * sample_dt
        sigma = time_of_sample(target, t, y[2], k1[2], k7[2], dense[1], h)
        theta = theta_i + sigma * h
        aux, W_j = at_time(
            conservative_work(theta, segment, machine),
            work_at(sigma, W, y[3], k1[3], k7[3], dense[2], h), frozen, theta_i, theta, segment,
            machine,
        )  # fmt: skip
        u = aux + dense_value(sigma, u_free, y[0], k1[0], k7[0], dense[0], h)
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
def record_grid_angles(out, n, g, last, end_grid, grid, strokes_table, flow_table, work_table,
                       inertia_table, theta_i, h_step, theta_new, u_new, u_free, t, W, y, k1, k7,
                       dense, frozen, t_new):  # fmt: skip
    """Samples at the grid angles g delta a sub-step from (theta_i, t, W) to (theta_new, y)
    passed, from its continuous extension (the real machine's frozen friction's
    :func:`~.real.frozen_record` in ``frozen``); the segment's end is a grid angle by index,
    whatever the round-off in g delta, of the :class:`Grid` (``at_grid`` holds
    :func:`grid_tables`); the segment's end sample at (theta_new, u_new, t_new) (t_new is y's
    time but after a leak hole's window: :func:`~.real.window_jump`). Returns (out, n, the next
    g)."""
    delta, period, per_revolution = grid
    while (last and g == end_grid) or (g != end_grid and g * delta <= theta_new):
        row = g % period
        if g == end_grid:
            u_g, t_g, W_g = u_new, t_new, end_works(y, frozen)
        else:
            sigma = (g * delta - theta_i) / h_step
            u_g = grid_aux(work_table[row], frozen, inertia_table, row) + dense_value(
                sigma, u_free, y[0], k1[0], k7[0], dense[0], h_step
            )
            t_g = grid_time(
                dense_value(sigma, t, y[2], k1[2], k7[2], dense[1], h_step), frozen, inertia_table,
                row,
            )  # fmt: skip
            W_g = grid_works(
                work_at(sigma, W, y[3], k1[3], k7[3], dense[2], h_step), frozen, inertia_table, row
            )
        strokes = (g // period) * per_revolution + strokes_table[row]
        theta_dot_g = math.sqrt(2.0 * u_g / grid_inertia(inertia_table, row))
        n = record(out, n, t_g, g * delta, theta_dot_g, W_g, strokes, flow_table[row], False)
        g += 1
    return n, g


@inline_kernel
def record_end(out, n, t, theta, theta_dot, W, segment, machine):
    """The last sample, at the end of a run that reached t_end on a switch (unless the grid put
    one there). Returns (out, n)."""
    out = with_room(out, n, 1)
    if out[T, n - 1] < t:
        n = record_anywhere(out, n, t, theta, theta_dot, W, segment, machine, True)
    return out, n
