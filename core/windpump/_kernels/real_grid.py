"""The real machine's values at the grid angles (time, energy and works with the frozen parts
added back) and the tables of the inertia over one revolution.
"""

from __future__ import annotations

import numpy as np
from numba import types
from numba.extending import overload

from .dopri5 import (
    B1,
    B3,
    B4,
    B5,
    B6,
    D1,
    D3,
    D4,
    D5,
    D6,
    D7,
    dense_value,
)  # fmt: skip
from .jit import kernel
from .model import (
    segment_start,
)
from .real_entries import (
    JIT_OPTIONS,
    WORKS,
    _entry,
    advance_work,
    dense_work,
    inertia_ratio,
    work_at,
    write_work,
)
from .real_friction import (
    _weighted,
    friction_since,
)
from .real_ripple import (
    _inertia_since,
    _lambda_since,
    inertia_since,
)


def grid_time(t, frozen, table, row):
    """A grid sample's time inside a sub-step: the step's ``t``, with the masses' frozen ripple
    since the sub-step began added back for the real machine (:func:`time_frozen`)."""


@overload(grid_time, jit_options=JIT_OPTIONS)
def _grid_time(t, frozen, table, row):
    if _is_none(frozen):
        return lambda t, frozen, table, row: t

    def at(t, frozen, table, row):
        (tau, inv_e), (J, X, K) = frozen[4], frozen[5]
        dK = (table[6, row] - K[0], table[7, row] - K[1], table[8, row] - K[2])
        dX = (table[3, row] - X) - _weighted(frozen[0], dK)
        return t + tau * ((table[2, row] - J) - dX * inv_e)

    return at


def _is_none(frozen) -> bool:
    return isinstance(frozen, types.NoneType)


def grid_aux(work, frozen, table, row):
    """A grid sample's aux inside a sub-step: its conservative work ``work``, less e_ref C for
    the real machine (C from :func:`inertia_table`'s second row)."""


@overload(grid_aux, jit_options=JIT_OPTIONS)
def _grid_aux(work, frozen, table, row):
    if _is_none(frozen):
        return lambda work, frozen, table, row: work
    return lambda work, frozen, table, row: work - _weighted(frozen[0], _grid_c(table, row))


@kernel
def _grid_c(table, row):
    """C's three parts at a grid angle (:func:`inertia_table`'s rows 1, 4 and 5)."""
    return table[1, row], table[4, row], table[5, row]


def grid_works(W, frozen, table, row):
    """A grid sample's works inside a sub-step: the integrated ``W``, with the real machine's
    frozen friction's work since the sub-step began."""


@overload(grid_works, jit_options=JIT_OPTIONS)
def _grid_works(W, frozen, table, row):
    if _is_none(frozen):
        return lambda W, frozen, table, row: W

    def works(W, frozen, table, row):
        C, c_at = _grid_c(table, row), frozen[2]
        extra = frozen[1] * _weighted(frozen[0], (C[0] - c_at[0], C[1] - c_at[1], C[2] - c_at[2]))
        return W[0], W[1], W[2] + extra, W[3] + extra

    return works


def at_time(work, W, frozen, theta_i, theta, segment, machine):
    """A sample's aux and works at an angle theta off the grid inside a sub-step from theta_i
    (:func:`grid_aux`, :func:`grid_works`; C from the sub-step's start)."""


@overload(at_time, jit_options=JIT_OPTIONS)
def _at_time(work, W, frozen, theta_i, theta, segment, machine):
    if _is_none(frozen):
        return lambda work, W, frozen, theta_i, theta, segment, machine: (work, W)

    def at(work, W, frozen, theta_i, theta, segment, machine):
        e_ref, I_eff, c_at, _, _, _ = frozen
        C = friction_since(theta_i, theta, c_at, segment, machine)
        extra = I_eff * _weighted(e_ref, (C[0] - c_at[0], C[1] - c_at[1], C[2] - c_at[2]))
        return work - _weighted(e_ref, C), (W[0], W[1], W[2] + extra, W[3] + extra)

    return at


def end_works(y, frozen):
    """The works where a sub-step ends: ``y[3]`` (the ideal machine's), or the frozen record's."""


@overload(end_works, jit_options=JIT_OPTIONS)
def _end_works(y, frozen):
    if _is_none(frozen):
        return lambda y, frozen: y[3]
    return lambda y, frozen: frozen[3]


def grid_inertias(theta, segment, machine):
    """At a grid angle: J / I_eff (the ideal machine: 1.0), and for the real machine C's first
    part, int (j - 1) and int Lambda since the segment began, and C's other two parts."""


def _grid_inertias(theta, segment, machine):
    C = friction_since(segment_start(segment, machine), theta, (0.0, 0.0, 0.0), segment, machine)
    K = inertia_since(theta, segment, machine)[2]
    return (
        inertia_ratio(theta, machine), C[0], _inertia_since(theta, segment, machine),
        _lambda_since(theta, segment, machine), C[1], C[2], K[0], K[1], K[2],
    )  # fmt: skip


_entry(grid_inertias)(lambda theta, segment, machine: 1.0, _grid_inertias)


def inertia_table(rows, machine):
    """Room for :func:`grid_inertias` at ``rows`` grid angles: (rows,), or (9, rows)."""


_entry(inertia_table)(
    lambda rows, machine: np.empty(rows), lambda rows, machine: np.empty((9, rows))
)


def set_grid_inertia(table, row, values):
    """table[row] = values (1-D), or table[:, row] = values (2-D)."""


@overload(set_grid_inertia, jit_options=JIT_OPTIONS)
def _set_grid_inertia(table, row, values):
    if table.ndim == 1:

        def set_one(table, row, values):
            table[row] = values

        return set_one

    def set_two(table, row, values):
        table[0, row], table[1, row], table[2, row], table[3, row] = values[:4]
        table[4, row], table[5, row] = values[4], values[5]
        table[6, row], table[7, row], table[8, row] = values[6], values[7], values[8]

    return set_two


def grid_inertia(table, row):
    """J / I_eff at a grid angle (:func:`inertia_table`)."""


@overload(grid_inertia, jit_options=JIT_OPTIONS)
def _grid_inertia(table, row):
    if table.ndim == 1:
        return lambda table, row: table[row]
    return lambda table, row: table[0, row]


# -- The work quadratures: a float (the shaft work) or a tuple of WORKS. -------------------------
@overload(advance_work, jit_options=JIT_OPTIONS)
def _advance_work(q, h, a, c, d, e, f):
    if isinstance(q, types.Float):
        return lambda q, h, a, c, d, e, f: q + h * (B1 * a + B3 * c + B4 * d + B5 * e + B6 * f)

    def advance(q, h, a, c, d, e, f):
        return (
            q[0] + h * (B1 * a[0] + B3 * c[0] + B4 * d[0] + B5 * e[0] + B6 * f[0]),
            q[1] + h * (B1 * a[1] + B3 * c[1] + B4 * d[1] + B5 * e[1] + B6 * f[1]),
            q[2] + h * (B1 * a[2] + B3 * c[2] + B4 * d[2] + B5 * e[2] + B6 * f[2]),
            q[3] + h * (B1 * a[3] + B3 * c[3] + B4 * d[3] + B5 * e[3] + B6 * f[3]),
        )

    return advance


@overload(dense_work, jit_options=JIT_OPTIONS)
def _dense_work(h, a, c, d, e, f, g):
    if isinstance(a, types.Float):
        return lambda h, a, c, d, e, f, g: h * (D1 * a + D3 * c + D4 * d + D5 * e + D6 * f + D7 * g)

    def dense(h, a, c, d, e, f, g):
        return (
            h * (D1 * a[0] + D3 * c[0] + D4 * d[0] + D5 * e[0] + D6 * f[0] + D7 * g[0]),
            h * (D1 * a[1] + D3 * c[1] + D4 * d[1] + D5 * e[1] + D6 * f[1] + D7 * g[1]),
            h * (D1 * a[2] + D3 * c[2] + D4 * d[2] + D5 * e[2] + D6 * f[2] + D7 * g[2]),
            h * (D1 * a[3] + D3 * c[3] + D4 * d[3] + D5 * e[3] + D6 * f[3] + D7 * g[3]),
        )

    return dense


@overload(work_at, jit_options=JIT_OPTIONS)
def _work_at(sigma, start, end, rate_start, rate_end, dense, h):
    if isinstance(start, types.Float):
        return lambda sigma, start, end, rate_start, rate_end, dense, h: dense_value(
            sigma, start, end, rate_start, rate_end, dense, h
        )

    def at(sigma, start, end, rate_start, rate_end, dense, h):
        return (
            dense_value(sigma, start[0], end[0], rate_start[0], rate_end[0], dense[0], h),
            dense_value(sigma, start[1], end[1], rate_start[1], rate_end[1], dense[1], h),
            dense_value(sigma, start[2], end[2], rate_start[2], rate_end[2], dense[2], h),
            dense_value(sigma, start[3], end[3], rate_start[3], rate_end[3], dense[3], h),
        )

    return at


@overload(write_work, jit_options=JIT_OPTIONS)
def _write_work(out, row, n, W):
    if isinstance(W, types.Float):

        def write_one(out, row, n, W):
            out[row, n] = W

        return write_one

    def write(out, row, n, W):
        for i in range(WORKS):
            out[row + i, n] = W[i]

    return write
