"""The time's ripple, frozen (docs/model.rst, "The real machine"): the inertia ratio's and
Lambda's integrals taken out of the time's rate and added back at each sub-step's end.
"""

from __future__ import annotations

import math

import numpy as np

from .jit import kernel
from .model import (
    NEITHER,
    delivering_face,
    phase,
    piston_over_R,
    segment_start,
)
from .real_entries import (
    _entry,
    arm_squared_integral,
)
from .real_friction import (
    GAUSS8,
    _friction_moment,
    _pieces,
    _weighted,
)


@kernel
def _inertia_since(theta, segment, machine):
    """int (j - 1) dtheta from the segment's start to theta [rad] (0.0 without masses)."""
    real = machine.real
    if real.mass_ratio == 0.0:
        return 0.0
    start = segment_start(segment, machine)
    total = 0.0
    for k in range(machine.cylinders):
        lag = phase(k, machine)
        total += arm_squared_integral(theta - lag, machine.L_over_R) - arm_squared_integral(
            start - lag, machine.L_over_R
        )
    return real.mass_ratio * total


@kernel
def _lambda_between(a, b, segment, machine):
    """int_a^b Lambda dtheta inside a segment [J/(kg m^2) rad], by Gauss-Legendre
    (:func:`friction_between`'s pieces: Lambda is analytic inside a segment). Lambda at a node
    is :func:`conservative_work`'s sums, each piston's x/R there worked out once for the head
    and the weights, and at the segment's start once a call (a run's grid tables and sub-step
    tables take ~10,000 nodes: 4 sincos a node and cylinder, 1 now)."""
    pieces, length = _pieces(a, b, machine)
    start = segment_start(segment, machine)
    x_start = np.empty(machine.cylinders)
    for k in range(machine.cylinders):
        x_start[k] = piston_over_R(start - phase(k, machine), machine.L_over_R)
    total = 0.0
    x, w = GAUSS8
    for p in range(pieces):
        first = a + p * length
        for q in range(8):
            total += w[q] * _work_at_node(first + x[q] * length, x_start, segment, machine)
    return total * length


@kernel
def _work_at_node(theta, x_start, segment, machine):
    """:func:`conservative_work` at theta, the pistons' x/R at the segment's start given: the
    same sums in the same order (:func:`~.model.load_work`, :func:`_weight_work`)."""
    head = weights = 0.0
    for k in range(machine.cylinders):
        x = piston_over_R(theta - phase(k, machine), machine.L_over_R) - x_start[k]
        face = delivering_face(segment, k, machine)
        if face != NEITHER:
            head += face * x
        weights += x
    work = machine.load_torque * machine.inv_I_eff * head
    if machine.real.weight_torque == 0.0:
        return work + 0.0
    return work + machine.real.weight_torque * machine.inv_I_eff * weights


@kernel
def _lambda_since(theta, segment, machine):
    """int Lambda dtheta from the segment's start to theta."""
    return _lambda_between(segment_start(segment, machine), theta, segment, machine)


def inertia_since(theta, segment, machine):
    """(int (j - 1), int Lambda, int C) dtheta since the segment's start (C in its three
    parts); zeros for the ideal machine."""


def _real_inertia_since(theta, segment, machine):
    start = segment_start(segment, machine)
    K = (0.0, 0.0, 0.0)
    if machine.real.friction != 0.0:
        K = _friction_moment(start, theta, segment, machine)
    return _inertia_since(theta, segment, machine), _lambda_since(theta, segment, machine), K


_entry(inertia_since)(lambda theta, segment, machine: (0.0, 0.0), _real_inertia_since)


def no_integrals(machine):
    """:func:`inertia_since` where a segment begins: zeros."""


_entry(no_integrals)(lambda machine: (0.0, 0.0), lambda machine: (0.0, 0.0, (0.0, 0.0, 0.0)))


def time_frozen(u, allowed, machine):
    """(tau = 1 / (2 sqrt(2 u)) [s/rad], 1 / u) where a split begins at energy u, when the
    time's ripple is taken out of its rate (``allowed``: on an angle grid without a wind record),
    else zeros (and always for the ideal machine)."""


_entry(time_frozen)(
    lambda u, allowed, machine: (0.0, 0.0),
    lambda u, allowed, machine: (
        (0.5 / math.sqrt(2.0 * u), 1.0 / u) if allowed and u > 0.0 else (0.0, 0.0)
    ),
)


def inertia_at(J, X, j, M1, M2, M3, machine):
    """(int (j - 1), int Lambda) over a sub-step from its rows' ``rows[6, 8:10]``, J / I_eff
    where it ends, ``rows[6, 0]``, and C's moment over it, ``rows[6, M_PARTS]`` (zeros and 1.0
    for the ideal machine, whose rows hold nothing there). Taken from the rows, not computed
    again at the sub-step's end (a ``sincos`` a step with reciprocating masses)."""


_entry(inertia_at)(
    lambda J, X, j, M1, M2, M3, machine: (0.0, 0.0, 1.0, 0.0),
    lambda J, X, j, M1, M2, M3, machine: (J, X, j, (M1, M2, M3)),
)


def time_back(t, frozen_time, step, e_ref, c_at, h, machine):
    """A time off the step's quadrature, t, with the frozen ripple's integral over the sub-step
    (:func:`inertia_at`'s ``step``, h long, C = c_at at its start, the frozen friction's weights
    e_ref) added back, tau (dJ - (dX - e_ref . int C) / u) (the ideal machine's t as it is)."""


def _time_back(t, frozen_time, step, e_ref, c_at, h, machine):
    tau, inv_e = frozen_time
    M = step[3]
    C = (c_at[0] * h + M[0], c_at[1] * h + M[1], c_at[2] * h + M[2])
    return t + tau * (step[0] - (step[1] - _weighted(e_ref, C)) * inv_e)


_entry(time_back)(lambda t, frozen_time, step, e_ref, c_at, h, machine: t, _time_back)


def add_integrals(at, step, c_at, h, machine):
    """:func:`inertia_since`'s integrals where a sub-step began plus the sub-step's."""


def _add_integrals(at, step, c_at, h, machine):
    K, M = at[2], step[3]
    return (
        at[0] + step[0], at[1] + step[1],
        (K[0] + c_at[0] * h + M[0], K[1] + c_at[1] * h + M[1], K[2] + c_at[2] * h + M[2]),
    )  # fmt: skip


_entry(add_integrals)(lambda at, step, c_at, h, machine: at, _add_integrals)


# -- The rising main's friction, split at a frozen energy (docs/model.rst, "The real machine"). --
#
# On the loads continued past a hole's windows the friction torque is rho_w g K q (q theta_dot
# - faces q_L)^2 (q = A R arms), and theta_dot^2 = 2 e / j: at e = e_ref it is c(theta) .
# (e_ref, sqrt(e_ref), 1) I_eff, c's three parts functions of the angle alone
# (:func:`_frozen_parts`; the last two 0 without a hole). Frozen at e_ref (the energy where a
# split of a segment begins) its work is C(theta) . (e_ref, sqrt(e_ref), 1), C = int c from the
# segment's start, tabulated like Lambda; only the rest (e - e_ref, a hole's windows) is
# integrated. (Without the hole's two parts a leaky pump with a main took 4,405 steps: its
# energy's error estimate saw them.)
