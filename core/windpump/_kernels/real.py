"""The real machine's terms in the kernels: reciprocating masses, transmission, rising main, leak.

Each function here takes the :class:`~.model.Machine` and resolves on the type of its ``real``
field when compiled (numba overloads, as :mod:`.wind` does for the wind): for the paper's ideal
machine (``real`` is None) it is the ideal model's expression and adds no code, so the ideal run
is compiled as it always was; for a :class:`~.model.Real` it adds the terms of docs/model.rst,
"The real machine"::

    J(theta) theta_ddot = eta_t R+ T - load(theta, theta_dot) + m_r g sum x_c' - J'(theta) theta_dot^2 / 2,
    J = I_eff + m_r sum x_c'^2.

In the angle domain the state is ``e - Lambda(theta)``, with ``e = J theta_dot^2 / (2 I_eff)``
and Lambda the closed-form work of the weights and of the static head ``rho_w g h A |x'|`` on
every face in its delivering half (as the ideal machine's): what is left to integrate is the
windmill's transmitted work less the *excess* of the load over the static head (the rising main's
friction; a leak hole's relief, negative, where a slow face delivers nothing), less the main's
friction frozen at the energy where each split of a segment begins, whose work is tabulated like
Lambda (docs/model.rst, "The real machine": the main's friction split at a frozen energy). The
quadratures ``W = (shaft work, volume leaked back, friction loss, excess load work)`` are
integrated with it, so a Runge-Kutta step keeps their linear relation exactly and the energy
balance closes to round-off as the ideal machine's does; the leak's loss is the static head's work on the swept volume plus
the excess, less the water lifted and the friction (:func:`windpump.power_budget`).

The pointwise equations (Eq. 1 and its derivatives, the hole's flow, the face's pressure) are
:mod:`.equations`' functions, shared with the numpy side. The sums over faces and cylinders are
twins of :func:`windpump.model.loads.faces_load` (and its friction at a frozen energy,
:func:`friction_density`), :func:`windpump.model.loads.weight_torque` and
:func:`windpump.model.reciprocating.crank_inertia`, kept for speed; tests/test_real_machine.py holds
each pair together to 1e-11 or closer.
"""

from __future__ import annotations

import functools
import math
import typing

import numpy as np
from numba import types
from numba.extending import overload

from ..model import equations
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
    E1,
    E3,
    E4,
    E5,
    E6,
    E7,
    NODES,
    dense_value,
)  # fmt: skip
from .jit import OPTIONS, inline_kernel, kernel
from .model import (
    NEITHER,
    Real,
    delivering_face,
    lever_arm,
    load_on_crank,
    load_work,
    phase,
    piston_over_R,
    segment_at,
    segment_start,
    windmill_torque_on_crank,
)
from .wind import wind_scale

JIT_OPTIONS: typing.Any = OPTIONS  # (numba's stubs type the options narrower than it takes)

lever_arm_slope = kernel(equations.lever_arm_slope)  # (d^2x/dphi^2)/R [-]
delivered_flow = kernel(equations.delivered_flow)  # max(u - q_L, 0) [m^3/s]
face_pressure = kernel(equations.face_pressure)  # [Pa]
arm_squared_integral = kernel(equations.lever_arm_squared_integral)  # [rad]

ROW = 21  # a stage's row: the inertia ratio j, |lever arm| of each cylinder's delivering face, C
# (C's first part; the other two in columns 16 and 17: :data:`C_PARTS`), (at the last node) the
# integrals of j - 1 and Lambda over the sub-step (:func:`time_frozen`), and what the ANGLE
# domain's rates take of j and the arms (:func:`_row_extras`, columns 10 to 15), and (at the
# last node) the integral of C over the sub-step less C at its start times its length (18-20)
C_PARTS = (7, 16, 17)  # the rows' columns of the frozen friction's C (:func:`_frozen_parts`)
M_PARTS = (18, 19, 20)  # the last row's columns of C's moment over the sub-step
WORKS = 4  # the real machine's quadratures: shaft work, leaked volume, friction, excess load


# -- Typed entry points: the ideal machine's expression, or the real machine's. -----------------


def inertia_ratio(theta, machine):
    """J(theta) / I_eff [-]: 1 for the ideal machine."""


def conservative_work(theta, segment, machine):
    """Lambda: the conservative torques' work since the segment began, per unit I_eff
    [J/(kg m^2)]: the static head's (:func:`~.model.load_work`) for a tight piston, plus the
    weights' ``m_r g sum (x_c - x_c(start))``."""


def conservative_torque(theta, segment, machine):
    """The conservative torques on the crank [N m]: the static head's (negative) for a tight
    piston, plus the weights' ``m_r g sum x_c'``."""


def torque_at_rest(theta, segment, machine):
    """The torques on a resting crank but the windmill's [N m]: the static head's (negative) for a
    tight piston, none through a leak hole (the water flows back through it), plus the weights'."""


def transmitted(torque, machine):
    """What the chain passes to the crank of a torque reflected to it, eta_t times it [N m]."""


def zero_work(machine):
    """The quadratures at the start: 0.0 (shaft work), or a tuple of WORKS zeros."""


def angle_rates(x0, t, aux, row, machine):
    """The ANGLE domain's rates (dx0, dt, dt, dW) per radian; x0 = e - Lambda, aux = Lambda."""


def time_rates(t, theta, theta_dot, row, segment, machine):
    """The TIME domain's rates (theta_dot, theta_ddot, 0, dW) per second; ``row`` is scratch."""


def fill_row(row, theta, segment, machine):
    """Write a stage's row (ROW numbers) for the real machine; nothing for the ideal one."""


def advance_work(q, h, a, c, d, e, f):
    """A step's 5th-order update of the work quadratures, q + h (b . stages)."""


def dense_work(h, a, c, d, e, f, g):
    """The continuous extension's term of the work quadratures, h (d . stages)."""


def work_at(sigma, start, end, rate_start, rate_end, dense, h):
    """The work quadratures at s + sigma h inside a step (:func:`~.dopri5.dense_value`)."""


def write_work(out, row, n, W):
    """Write the work quadratures into ``out[row:, n]``."""


def _ideal(real) -> bool:
    return isinstance(real, types.NoneType)


def _entry(function):
    """Register ``function``'s overload: ``ideal(...)`` for a None ``real``, else ``actual``."""

    def register(ideal, actual, on_machine=True, inline="never"):
        ideal, actual = (getattr(f, "py_func", f) for f in (ideal, actual))  # a kernel's source

        @functools.wraps(function)  # numba checks the typer's signature against the stub's
        def typer(*args):
            machine = args[-1]
            real = machine.types[machine.fields.index("real")] if on_machine else machine
            return ideal if _ideal(real) else actual

        overload(function, jit_options=JIT_OPTIONS, inline=inline)(typer)

    return register


# -- The real machine's expressions. ------------------------------------------------------------


@kernel
def _sums(row, theta, segment, machine, slopes):
    """Fill ``row`` at theta; return (sum a_c, sum a_c a_c') over every cylinder (the second
    only with ``slopes``: the time domain's J')."""
    real = machine.real
    squares = sum_a = sum_slope = 0.0
    for k in range(machine.cylinders):
        phi = theta - phase(k, machine)
        a = lever_arm(phi, machine.L_over_R)
        squares += a * a
        sum_a += a
        if slopes and real.mass_ratio != 0.0:
            sum_slope += a * lever_arm_slope(phi, machine.L_over_R)
        row[1 + k] = abs(a) if delivering_face(segment, k, machine) != NEITHER else 0.0
    row[0] = 1.0 + real.mass_ratio * squares
    return sum_a, sum_slope


@kernel
def _row_extras(j, arms, held, machine):
    """What the ANGLE domain's rates take of a node's j and delivering arms (sum |a|), kept in
    its row's columns 10-15 (:func:`step_rows`): 2 / j, A R sum |a| (the faces' swept volume per
    radian), the first part of the main's frozen friction torque (:func:`_frozen_parts`), j - 1,
    and the other two parts. Worked out when the row is filled (a tabled row once per run), not
    at every stage. ``held`` is what the segment's delivering faces' holes pass, faces q_L."""
    first, second, third = _frozen_parts(arms, j, held, machine)
    return 2.0 / j, machine.real.AR * arms, first, j - 1.0, second, third


@kernel
def _face_loads(theta_dot, row, machine):
    """(load torque [N m], delivered flow Q [m^3/s], friction head h_f [m], sum |a|) of the
    delivering faces whose lever arms ``row`` holds, at crank speed theta_dot."""
    real = machine.real
    Q = arms = 0.0
    for k in range(machine.cylinders):
        Q += delivered_flow(real.AR * row[1 + k] * theta_dot, real.q_L)
        arms += row[1 + k]
    if real.q_L == 0.0 and real.friction == 0.0:  # a tight piston, no pipe: the static head
        return machine.load_torque * arms, Q, 0.0, arms
    h_f = real.friction * Q * Q
    load = 0.0
    for k in range(machine.cylinders):
        u = real.AR * row[1 + k] * theta_dot
        load += face_pressure(u, real.q_L, real.rho_g, 1.0, real.h, h_f) * real.AR * row[1 + k]
    return load, Q, h_f, arms


@kernel
def _continued_loads(theta_dot, row, faces, machine):
    """:func:`_face_loads` as if each of the ``faces`` delivering faces delivered, through its
    hole, what it sweeps less the hole's capacity, ``u - q_L``, at ``rho_w g (h + h_f)``: the
    delivering branch of :func:`~.equations.delivered_flow` and
    :func:`~.equations.face_pressure`, continued past the kinks. Equal to :func:`_face_loads`
    wherever every delivering face sweeps more than q_L; smooth inside a segment, where a
    delivering segment's steps take it, the windows next to its dead centres being corrected
    apart (:func:`window_jump`)."""
    arms = 0.0
    for k in range(machine.cylinders):
        arms += row[1 + k]
    Q, h_f, friction = _continued_friction(
        theta_dot, machine.real.AR * arms, faces * machine.real.q_L, machine
    )
    return machine.load_torque * arms + friction, Q, h_f, arms


@kernel
def _continued_friction(theta_dot, swept, held, machine):
    """(Q [m^3/s], h_f [m], the main's friction torque rho_w g h_f A R sum |a| [N m]) of
    :func:`_continued_loads`, from the delivering faces' swept volume per radian ``swept`` = A R
    sum |a| [m^3/rad] and what their holes pass, ``held`` = faces q_L [m^3/s]."""
    Q = swept * theta_dot - held
    h_f = machine.real.friction * Q * Q
    return Q, h_f, machine.real.rho_g * h_f * swept


def _real_angle_rates(x0, t, aux, row, machine):
    real = machine.real
    # ``row`` is a stage's :func:`step_rows` tuple: everything that does not depend on the state
    # is worked out there, before the step, so that only the speed's root and a few products
    # lie between one stage and the next (the stages are sequential: their latency is the cost).
    theta_dot = math.sqrt((x0 + (aux - row[7])) * row[0])  # x0 = e - Lambda + F, F = row[7]
    per_radian = 1.0 / theta_dot
    drive = windmill_torque_on_crank(theta_dot, wind_scale(t, machine.wind), machine)
    if row[9] >= 0.0:  # on the loads continued past the hole's windows (:func:`_continued_loads`)
        Q, h_f, friction = _continued_friction(theta_dot, row[12], row[13], machine)
        excess = friction - row[8]
    else:
        load, Q, h_f, arms = _face_loads(theta_dot, row, machine)
        excess = load - machine.load_torque * arms - row[8]
    # The static head's load is in Lambda: only the rest of the load (friction, and a hole's
    # relief) is integrated, and so is the water lifted and the friction; of the friction, less
    # its frozen part (at e_ref: :func:`friction_density`, row[8]), whose work F is tabulated.
    rate = (real.eta_t * drive - excess) * machine.inv_I_eff
    leaked = row[12] - Q * per_radian  # swept less delivered: small, so accurate
    friction = real.rho_g * h_f * Q * per_radian - row[8]
    time = per_radian - (row[10] - (aux - row[7]) * row[11])  # less its frozen ripple
    return rate, per_radian, time, (drive, leaked, friction, excess)


def _real_time_rates(t, theta, theta_dot, row, segment, machine):
    real = machine.real
    sum_a, sum_slope = _sums(row, theta, segment, machine, True)
    drive = windmill_torque_on_crank(theta_dot, wind_scale(t, machine.wind), machine)
    load, Q, h_f, arms = _face_loads(theta_dot, row, machine)
    torque = real.eta_t * drive - load + real.weight_torque * sum_a
    j_slope = 2.0 * real.mass_ratio * sum_slope  # dj/dtheta
    acceleration = (torque * machine.inv_I_eff - 0.5 * j_slope * theta_dot * theta_dot) / row[0]
    excess = (load - machine.load_torque * arms) * theta_dot
    leaked = real.AR * arms * theta_dot - Q
    works = (drive * theta_dot, leaked, real.rho_g * h_f * Q, excess)
    return theta_dot, acceleration, 0.0, works


@kernel
def _weight_work(theta, segment, machine):
    if machine.real.weight_torque == 0.0:
        return 0.0
    start = segment_start(segment, machine)
    total = 0.0
    for k in range(machine.cylinders):
        lag = phase(k, machine)
        total += piston_over_R(theta - lag, machine.L_over_R) - piston_over_R(
            start - lag, machine.L_over_R
        )
    return machine.real.weight_torque * machine.inv_I_eff * total


@kernel
def _weight_torque(theta, machine):
    if machine.real.weight_torque == 0.0:
        return 0.0
    total = 0.0
    for k in range(machine.cylinders):
        total += lever_arm(theta - phase(k, machine), machine.L_over_R)
    return machine.real.weight_torque * total


@kernel
def _inertia_ratio(theta, machine):
    if machine.real.mass_ratio == 0.0:
        return 1.0
    squares = 0.0
    for k in range(machine.cylinders):
        a = lever_arm(theta - phase(k, machine), machine.L_over_R)
        squares += a * a
    return 1.0 + machine.real.mass_ratio * squares


def _real_conservative_work(theta, segment, machine):
    return load_work(theta, segment, machine) + _weight_work(theta, segment, machine)


def _real_conservative_torque(theta, segment, machine):
    return load_on_crank(theta, segment, machine) + _weight_torque(theta, machine)


def _real_torque_at_rest(theta, segment, machine):
    head = load_on_crank(theta, segment, machine) if machine.real.q_L == 0.0 else 0.0
    return head + _weight_torque(theta, machine)


def _ideal_angle_rates(x0, t, aux, row, machine):
    theta_dot = math.sqrt(2.0 * (x0 + aux))
    per_radian = 1.0 / theta_dot
    drive = windmill_torque_on_crank(theta_dot, wind_scale(t, machine.wind), machine)
    return drive * machine.inv_I_eff, per_radian, per_radian, drive


def _ideal_time_rates(t, theta, theta_dot, row, segment, machine):
    drive = windmill_torque_on_crank(theta_dot, wind_scale(t, machine.wind), machine)
    load = load_on_crank(theta, segment, machine)
    return theta_dot, (drive + load) * machine.inv_I_eff, 0.0, drive * theta_dot


_entry(inertia_ratio)(lambda theta, machine: 1.0, _inertia_ratio)
_entry(conservative_work)(
    lambda theta, segment, machine: load_work(theta, segment, machine), _real_conservative_work
)
_entry(conservative_torque)(
    lambda theta, segment, machine: load_on_crank(theta, segment, machine),
    _real_conservative_torque,
)
_entry(torque_at_rest)(
    lambda theta, segment, machine: load_on_crank(theta, segment, machine),
    _real_torque_at_rest,
)
_entry(transmitted)(
    lambda torque, machine: torque, lambda torque, machine: machine.real.eta_t * torque
)
_entry(zero_work)(lambda machine: 0.0, lambda machine: (0.0, 0.0, 0.0, 0.0))
_entry(angle_rates)(_ideal_angle_rates, _real_angle_rates)
_entry(time_rates)(_ideal_time_rates, _real_time_rates)


@overload(time_rates, jit_options=JIT_OPTIONS)
def _time_rates_of_tuples(t, theta, theta_dot, row, segment, machine):
    """The ANGLE domain's steps take :func:`step_rows`' tuples, which ``rates`` types in its
    TIME branch too (never taken there): a stub for them."""
    if not isinstance(row, types.BaseTuple):
        return None

    def never(t, theta, theta_dot, row, segment, machine):
        return theta_dot, math.nan, 0.0, (math.nan, math.nan, math.nan, math.nan)

    return never


def _no_row(row, theta, segment, machine):
    return None


def _fill_row(row, theta, segment, machine):
    _sums(row, theta, segment, machine, False)
    arms = 0.0
    for k in range(machine.cylinders):
        arms += row[1 + k]
    extras = _row_extras(row[0], arms, _held(segment, machine), machine)
    row[10], row[11], row[12], row[13], row[14], row[15] = extras


_entry(fill_row)(_no_row, _fill_row)


def fill_stages(aux, rows, theta, h, segment, machine):
    """At a step's 7 stage nodes theta + NODES h: the conservative work into ``aux[:7]``
    (:func:`conservative_work`) and, for the real machine, the rows (:func:`fill_row`)."""


def _ideal_stages(aux, rows, theta, h, segment, machine):
    for stage in range(7):
        node = theta + NODES[stage] * h
        aux[stage] = conservative_work(node, segment, machine)
        fill_row(rows[stage], node, segment, machine)


@kernel
def _real_stages(aux, rows, theta, h, segment, machine):
    # conservative_work and fill_row at once: one sin, cos and root per node and cylinder (Eq. 1
    # and its lever arm, in one function, share them: LLVM computes them once), the segment's
    # start once per cylinder, the last node (the 6th and 7th are both theta + h) once, and no
    # row views (an atomic reference pair each): 0.49 -> 0.17 us a sub-step (one cylinder).
    # Each sum is accumulated in the order of those functions (in aux, and the rows' columns 0
    # and 7, which fill_friction writes afterwards), so the numbers are theirs.
    real = machine.real
    L_over_R = machine.L_over_R
    start = segment_start(segment, machine)
    held = _held(segment, machine)
    for stage in range(6):
        aux[stage] = rows[stage, 0] = rows[stage, 7] = 0.0
    for k in range(machine.cylinders):
        lag = phase(k, machine)
        face = delivering_face(segment, k, machine)
        x_start = piston_over_R(start - lag, L_over_R)
        for stage in range(6):
            phi = theta + NODES[stage] * h - lag
            x = piston_over_R(phi, L_over_R) - x_start
            a = lever_arm(phi, L_over_R)
            if face != NEITHER:
                aux[stage] += face * x
            rows[stage, 7] += x
            rows[stage, 0] += a * a
            rows[stage, 1 + k] = abs(a) if face != NEITHER else 0.0
    for stage in range(6):
        work = machine.load_torque * machine.inv_I_eff * aux[stage]
        weights = rows[stage, 7] * (real.weight_torque * machine.inv_I_eff)
        aux[stage] = work + (weights if real.weight_torque != 0.0 else 0.0)
        rows[stage, 0] = 1.0 + real.mass_ratio * rows[stage, 0]
        arms = 0.0
        for k in range(machine.cylinders):
            arms += rows[stage, 1 + k]
        extras = _row_extras(rows[stage, 0], arms, held, machine)
        rows[stage, 10], rows[stage, 11], rows[stage, 12], rows[stage, 13] = extras[:4]
        rows[stage, 14], rows[stage, 15] = extras[4], extras[5]
    aux[6] = aux[5]
    for column in range(1 + machine.cylinders):
        rows[6, column] = rows[5, column]
    for column in range(10, ROW):
        rows[6, column] = rows[5, column]
    # the sub-step's integrals of j - 1 and Lambda (:func:`time_frozen`)
    rows[6, 8] = _inertia_since(theta + h, segment, machine) - _inertia_since(
        theta, segment, machine
    )
    rows[6, 9] = _lambda_between(theta, theta + h, segment, machine)


_entry(fill_stages)(_ideal_stages, _real_stages)


# -- The time's ripple, frozen (docs/model.rst, "The real machine"). -----------------------------
#
# dt/dtheta = sqrt(j / (2 e)) ripples with j(theta) = 1 + mu sum a_c^2 (mu = m_r R^2 / I_eff) and
# with e = x0 + Lambda(theta) - F(theta), F the main's frozen friction's work (C at the weights
# of e_ref): parts in 1e5 to 1e3 at the harmonics of theta, which the time's error estimate
# sees (the seed example with m_r = 1 kg took 6,479 steps against 4,087). Where a split begins
# at energy u, its first order there, tau ((j - 1) - (Lambda - F) / u) with tau = 1 / (2 sqrt(2
# u)), is taken out of the time's rate, and its integral added back at each sub-step's end and
# at the grid angles: int (j - 1) in closed form (:func:`~.equations.lever_arm_squared_integral`),
# int Lambda by Gauss-Legendre and int C by its moment (tabulated with the sub-steps). The step
# integrates only the rest. (With F's share left in the time's rate, the main alone took 4,543
# steps, not 3,393. Taking it out needs C exact at a tabled sub-step's inner nodes: with the
# polynomial through c there, the speed after 600 s was 3.3e-6 off, not 1.0e-6.)


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


def _gauss(points):
    """Gauss-Legendre nodes and weights on [0, 1], as tuples (numba's constants)."""
    x, w = np.polynomial.legendre.leggauss(points)
    return tuple(float(v) for v in 0.5 * (x + 1.0)), tuple(float(v) for v in 0.5 * w)


GAUSS4, GAUSS8 = _gauss(4), _gauss(8)
# Eq. (1) is analytic but for sqrt((L/R)^2 - sin^2 phi), which vanishes acosh(L/R) off the real
# axis: Gauss-Legendre on pieces of length p converges as (d/p)^(-2 points) for that distance d.
# Pieces at most EIGHT_POINTS d (and LONGEST_PIECE) long take 8 points, at most FOUR_POINTS d
# (and LONGEST_FOUR: the faces' cubed arms have the harmonics 3 theta) 4: C to ~1e-12 of itself.
EIGHT_POINTS, FOUR_POINTS = 0.7, 0.12
LONGEST_PIECE, LONGEST_FOUR = math.pi / 4, 0.15


@kernel
def _held(segment, machine):
    """What the holes of a segment's delivering faces pass [m^3/s]: faces q_L."""
    faces = 0.0
    for k in range(machine.cylinders):
        if delivering_face(segment, k, machine) != NEITHER:
            faces += 1.0
    return faces * machine.real.q_L


@kernel
def _frozen_parts(arms, j, held, machine):
    """The rising main's friction torque [N m] of delivering faces whose |lever arms| sum to
    ``arms`` and whose holes pass ``held`` (faces q_L), at the speed theta_dot^2 = 2 e_ref / j,
    as three parts of weights (e_ref, sqrt(e_ref), 1) (:func:`frozen_energy`): the continued
    loads' friction ``rho_w g K A R arms (A R arms theta_dot - held)^2``
    (:func:`_continued_friction`; without a hole :func:`windpump.model.loads.faces_load`'s)."""
    real = machine.real
    q = real.AR * arms
    k = real.rho_g * real.friction
    return (
        k * q * q * q * (2.0 / j),
        -2.0 * k * q * q * held * math.sqrt(2.0 / j),
        k * q * held * held,
    )


@kernel
def _weighted(weights, parts):
    """weights . parts: the frozen friction's (or its C's) value at the weights of an e_ref."""
    return weights[0] * parts[0] + weights[1] * parts[1] + weights[2] * parts[2]


@kernel
def friction_density(theta, segment, machine):
    """c(theta) [1/rad]: the frozen friction's torque over I_eff at theta, in its three parts
    (:func:`_frozen_parts`)."""
    real = machine.real
    squares = arms = 0.0
    for k in range(machine.cylinders):
        a = lever_arm(theta - phase(k, machine), machine.L_over_R)
        squares += a * a
        if delivering_face(segment, k, machine) != NEITHER:
            arms += abs(a)
    j = 1.0 + real.mass_ratio * squares
    first, second, third = _frozen_parts(arms, j, _held(segment, machine), machine)
    return first * machine.inv_I_eff, second * machine.inv_I_eff, third * machine.inv_I_eff


@kernel
def _longest_piece(machine):
    """The longest piece [rad] that 8 Gauss-Legendre points take (:data:`EIGHT_POINTS`)."""
    return min(LONGEST_PIECE, EIGHT_POINTS * math.acosh(machine.L_over_R))


@kernel
def _pieces(a, b, machine):
    """(How many equal pieces, their length [rad]) a quadrature from a to b takes."""
    pieces = max(1, int(math.ceil((b - a) / _longest_piece(machine))))
    return pieces, (b - a) / pieces


@kernel
def friction_between(a, b, segment, machine):
    """int_a^b c(theta) dtheta [-] inside a segment (where c is smooth: no face starts or stops
    inside), by Gauss-Legendre on equal pieces, as many as the rod's ratio asks: C's three
    parts (:func:`_frozen_parts`)."""
    reach = math.acosh(machine.L_over_R)  # how far off the real axis Eq. (1) is analytic
    pieces, length = _pieces(a, b, machine)
    first = second = third = 0.0
    for p in range(pieces):
        start = a + p * length
        if length <= min(FOUR_POINTS * reach, LONGEST_FOUR):
            x, w = GAUSS4
            for q in range(4):
                c = friction_density(start + x[q] * length, segment, machine)
                first, second, third = (
                    first + w[q] * c[0],
                    second + w[q] * c[1],
                    third + w[q] * c[2],
                )
        else:
            x, w = GAUSS8
            for q in range(8):
                c = friction_density(start + x[q] * length, segment, machine)
                first, second, third = (
                    first + w[q] * c[0],
                    second + w[q] * c[1],
                    third + w[q] * c[2],
                )
    return first * length, second * length, third * length


def fill_friction(rows, theta, h, c_at, known, exact, segment, machine):
    """Write C at a sub-step's 7 stage nodes into the rows' :data:`C_PARTS` columns, from
    ``c_at`` = C(theta), once ``rows`` holds the nodes' rows (:func:`fill_row`); nothing for the
    ideal machine (zeros without a rising main). ``known`` is (an angle at or past the sub-step's
    end, C there), from the tables, or (NaN, zeros): :func:`not_known`. ``exact``: the inner
    nodes' C by Gauss-Legendre (a table's, built once a run), else by the polynomial through c
    at the nodes; and C's moment over the sub-step (:func:`_friction_moment`) in the last row's
    :data:`M_PARTS` columns."""


def _interpolatory_weights():
    """w[s][k]: the integral from the step's start to its stage node s (1 to 4, C2 to C5) of the
    polynomial through a function's values at the 6 distinct nodes (0, C2 ... C5, 1), per unit
    step length: exact for degree 5."""
    nodes = NODES[:6]
    vandermonde = np.vander(nodes, increasing=True)
    powers = np.arange(1, 7)
    weights = []
    for target in nodes[1:5]:
        moments = target**powers / powers  # int_0^target x^p dx
        weights.append(tuple(float(v) for v in np.linalg.solve(vandermonde.T, moments)))
    return tuple(weights)


INTERPOLATORY = _interpolatory_weights()


def _moment_weights():
    """v[k]: int_0^1 (1 - x) p(x) dx for the polynomial p through a function's values at the
    6 distinct nodes, per value: exact for degree 5 (:func:`_friction_moment`'s off the
    tables)."""
    nodes = NODES[:6]
    powers = np.arange(6)
    moments = 1.0 / (powers + 1) - 1.0 / (powers + 2)  # int_0^1 (1 - x) x^p dx
    return tuple(float(v) for v in np.linalg.solve(np.vander(nodes, increasing=True).T, moments))


MOMENT = _moment_weights()


def _gauss8_inner_weights():
    """W[s][k]: the integral from 0 to stage node s (1 to 4) of the polynomial through a
    function's values at the 8 Gauss-Legendre points of [0, 1], per value: exact for degree 7
    (:func:`_fill_exactly`)."""
    points = np.array(GAUSS8[0])
    powers = np.arange(1, 9)
    vandermonde = np.vander(points, increasing=True)
    return tuple(
        tuple(float(v) for v in np.linalg.solve(vandermonde.T, target**powers / powers))
        for target in NODES[1:5]
    )


GAUSS8_INNER = _gauss8_inner_weights()


@kernel
def _density_at(rows, stage, machine):
    """c's three parts at a stage node, from its row's (columns 12, 14, 15: :func:`_row_extras`)."""
    scale = machine.inv_I_eff
    return rows[stage, 12] * scale, rows[stage, 14] * scale, rows[stage, 15] * scale


@kernel
def _fill_part(rows, part, h, c_at, densities, end):
    """Column ``C_PARTS[part]`` of a sub-step's rows: c_at at its start, the polynomial through
    the densities at its inner nodes, ``end`` at its end."""
    column = C_PARTS[part]
    c0, c1, c2, c3, c4, c5 = densities
    rows[0, column] = c_at
    for stage in range(1, 5):
        w = INTERPOLATORY[stage - 1]
        rows[stage, column] = c_at + h * (
            w[0] * c0 + w[1] * c1 + w[2] * c2 + w[3] * c3 + w[4] * c4 + w[5] * c5
        )
    rows[5, column] = rows[6, column] = end


def _fill_friction(rows, theta, h, c_at, known, exact, segment, machine):
    # The end's C enters the state: Gauss-Legendre. The inner nodes' C only moves the stages'
    # speeds, whose rates depend on it weakly (~1e-4 of it per radian at the seed's speed):
    # the polynomial through c at the nodes (rows filled) is ample.
    if machine.real.friction == 0.0:
        for stage in range(7):
            for column in C_PARTS:
                rows[stage, column] = 0.0
        for column in M_PARTS:
            rows[6, column] = 0.0
        return
    nodes = (
        _density_at(rows, 0, machine), _density_at(rows, 1, machine),
        _density_at(rows, 2, machine), _density_at(rows, 3, machine),
        _density_at(rows, 4, machine), _density_at(rows, 5, machine),
    )  # fmt: skip
    end = _friction_at_end(theta, h, c_at, known, segment, machine)
    if exact:  # a tabled sub-step's: once a run, and as the longest sub-steps need
        _fill_exactly(rows, theta, h, c_at, end, segment, machine)
        return
    for part in range(3):
        densities = (
            nodes[0][part], nodes[1][part], nodes[2][part],
            nodes[3][part], nodes[4][part], nodes[5][part],
        )  # fmt: skip
        _fill_part(rows, part, h, c_at[part], densities, end[part])
        v = MOMENT
        rows[6, M_PARTS[part]] = (h * h) * (
            v[0] * densities[0] + v[1] * densities[1] + v[2] * densities[2]
            + v[3] * densities[3] + v[4] * densities[4] + v[5] * densities[5]
        )  # fmt: skip


@kernel
def _friction_moment(a, b, segment, machine):
    """int_a^b C dtheta - C(a) (b - a) = int_a^b (b - s) c(s) ds [rad] inside a segment, in C's
    three parts, by Gauss-Legendre (:func:`friction_between`'s pieces): what the time's frozen
    ripple takes of the main's frozen friction (:func:`time_back`)."""
    pieces, length = _pieces(a, b, machine)
    first = second = third = 0.0
    x, w = GAUSS8
    for p in range(pieces):
        start = a + p * length
        for q in range(8):
            s = start + x[q] * length
            c = friction_density(s, segment, machine)
            weight = w[q] * (b - s)
            first, second, third = (
                first + weight * c[0],
                second + weight * c[1],
                third + weight * c[2],
            )
    return first * length, second * length, third * length


@kernel
def _fill_exactly(rows, theta, h, c_at, end, segment, machine):
    """C at a sub-step's inner nodes from c at the 8 Gauss-Legendre points of the sub-step (the
    polynomial through them, integrated: :data:`GAUSS8_INNER`) and C's moment over it (their
    quadrature), where one piece of :func:`friction_between` spans the sub-step; else by that
    quadrature from its start to each node."""
    one_piece = h <= _longest_piece(machine)
    x, w = GAUSS8
    densities = np.empty((8, 3))
    if one_piece:
        for k in range(8):
            densities[k, 0], densities[k, 1], densities[k, 2] = friction_density(
                theta + x[k] * h, segment, machine
            )
    for part in range(3):
        column = C_PARTS[part]
        rows[0, column] = c_at[part]
        rows[5, column] = rows[6, column] = end[part]
        if one_piece:
            moment = 0.0
            for k in range(8):
                moment += w[k] * (1.0 - x[k]) * densities[k, part]
            rows[6, M_PARTS[part]] = h * h * moment
            for stage in range(1, 5):
                inner = 0.0
                for k in range(8):
                    inner += GAUSS8_INNER[stage - 1][k] * densities[k, part]
                rows[stage, column] = c_at[part] + h * inner
    if not one_piece:
        for stage in range(1, 5):
            more = friction_between(theta, theta + NODES[stage] * h, segment, machine)
            for part in range(3):
                rows[stage, C_PARTS[part]] = c_at[part] + more[part]
        moment = _friction_moment(theta, theta + h, segment, machine)
        rows[6, M_PARTS[0]], rows[6, M_PARTS[1]], rows[6, M_PARTS[2]] = moment


@kernel
def _friction_at_end(theta, h, c_at, known, segment, machine):
    """C at theta + h [-]: C(theta) = c_at plus its integral, or a known C nearer (a tabled
    sub-step's end: a piece a hole's kink cut from it ends there, or near it), less the
    integral from there back."""
    anchor, c_anchor = known
    end = theta + h
    if abs(anchor - end) <= 1e-12 * max(1.0, abs(anchor)):
        return c_anchor
    if end < anchor < end + h:
        back = friction_between(end, anchor, segment, machine)
        return c_anchor[0] - back[0], c_anchor[1] - back[1], c_anchor[2] - back[2]
    more = friction_between(theta, end, segment, machine)
    return c_at[0] + more[0], c_at[1] + more[1], c_at[2] + more[2]


_entry(fill_friction)(
    lambda rows, theta, h, c_at, known, exact, segment, machine: None, _fill_friction
)


def friction_since(theta_i, theta, c_at, segment, machine):
    """C(theta) from C(theta_i) = c_at [-] (0.0 for the ideal machine; zeros without a main)."""


def _friction_since(theta_i, theta, c_at, segment, machine):
    if machine.real.friction == 0.0:
        return 0.0, 0.0, 0.0
    more = friction_between(theta_i, theta, segment, machine)
    return c_at[0] + more[0], c_at[1] + more[1], c_at[2] + more[2]


_entry(friction_since)(lambda theta_i, theta, c_at, segment, machine: 0.0, _friction_since)


def no_friction(machine):
    """C where a segment begins: 0.0 for the ideal machine, the real machine's three parts."""


_entry(no_friction)(lambda machine: 0.0, lambda machine: (0.0, 0.0, 0.0))


def not_known(machine):
    """No tabled C to start from (:func:`fill_friction`): (NaN, :func:`no_friction`)."""


_entry(not_known)(lambda machine: (math.nan, 0.0), lambda machine: (math.nan, (0.0, 0.0, 0.0)))


def friction_parts(C, machine):
    """C as the three numbers of a row's :data:`C_PARTS` columns (the ideal machine's C, 0.0,
    and two zeros)."""


_entry(friction_parts)(lambda C, machine: (C, 0.0, 0.0), lambda C, machine: C)


def frozen_energy(u, machine):
    """The weights of a split that begins at energy u [J/(kg m^2)] (:func:`_frozen_parts`): (u,
    sqrt(u), 1) with a rising main, else zeros (the ideal machine's: 0.0)."""


_entry(frozen_energy)(
    lambda u, machine: 0.0,
    lambda u, machine: (u, math.sqrt(u), 1.0) if machine.real.friction != 0.0 else (0.0, 0.0, 0.0),
)


def frozen_start(u, work, e_ref, c_at, machine):
    """x0 where a split begins at energy u, the conservative work there being ``work``:
    ``u - work``, and for the real machine plus the frozen friction's work (C = c_at at the
    weights e_ref: :func:`frozen_energy`)."""


_entry(frozen_start)(
    lambda u, work, e_ref, c_at, machine: u - work,
    lambda u, work, e_ref, c_at, machine: u - (work - _weighted(e_ref, c_at)),
)


def less_frozen(work, e_ref, C, machine):
    """The aux at a node: the conservative work there, less the frozen friction's work (C at
    the weights e_ref) for the real machine."""


_entry(less_frozen)(
    lambda work, e_ref, C, machine: work,
    lambda work, e_ref, C, machine: work - _weighted(e_ref, C),
)


def friction_at(first, second, third, machine):
    """C at a stage node, its row's :data:`C_PARTS` columns; 0.0 for the ideal machine (whose
    rows hold no C). Given the numbers, not the rows: an array handed to a helper, even inlined,
    costs a reference-count pair per call."""


_entry(friction_at)(
    lambda first, second, third, machine: 0.0,
    lambda first, second, third, machine: (first, second, third),
)


def frozen_work(W, e_ref, C, c_at, machine):
    """The work quadratures with the frozen friction's work from C = c_at to C added to the
    friction and the excess load, ``I_eff (weights . dC)`` [J]; the ideal machine's W as it
    is."""


def _frozen_work(W, e_ref, C, c_at, machine):
    dC = (C[0] - c_at[0], C[1] - c_at[1], C[2] - c_at[2])
    work = _weighted(e_ref, dC) / machine.inv_I_eff
    return W[0], W[1], W[2] + work, W[3] + work


_entry(frozen_work)(lambda W, e_ref, C, c_at, machine: W, _frozen_work)


def frozen_record(e_ref, c_at, W_new, frozen_time, j_at, machine):
    """What the recorders need of a sub-step's frozen friction and ripple: None for the ideal
    machine, else (the weights e_ref, I_eff, C where the sub-step began, the works where it
    ended, (tau, 1 / u), (int (j - 1), int Lambda) where it began)."""


_entry(frozen_record)(
    lambda e_ref, c_at, W_new, frozen_time, j_at, machine: None,
    lambda e_ref, c_at, W_new, frozen_time, j_at, machine: (
        e_ref, 1.0 / machine.inv_I_eff, c_at, W_new, frozen_time, j_at
    ),
)  # fmt: skip


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


def next_leak_kink(theta, theta_dot, segment, machine):
    """The first two angles past theta in its segment where a delivering face's swept flow
    reaches the leak hole's capacity at the present speed, ``A R |a_k| theta_dot = q_L`` [rad],
    inf where there is none.

    There the face starts (or stops) delivering and the load has a kink: the driver ends a
    sub-step on it, as on a wind record's kink, for the step's error estimate does not see one.
    """


@kernel
def _leak_kink_near(dead_centre, rising, target, sign, L_over_R, iterations):
    """The angle psi past a dead centre (0 or pi) where the face's |lever arm|
    ``sign * a(dead_centre + psi)`` reaches ``target``: on its rising side (psi < pi/2) or its
    falling side. Newton's method inside a shrinking bracket (|a| is 1 at pi/2 and 0 at the dead
    centres), at most ``iterations`` of them; NaN when the arm never reaches the target."""
    if target >= 1.0:
        return math.nan
    lo, hi = (0.0, 0.5 * math.pi) if rising else (0.5 * math.pi, math.pi)
    # From the arm's slope at the dead centre it is nearest, 1 + R/L at the top, 1 - R/L at the
    # bottom: |a| is odd about a dead centre, so the first iterate is off by O(target^3).
    at_top = (dead_centre == 0.0) == rising
    offset = target / (1.0 + 1.0 / L_over_R if at_top else 1.0 - 1.0 / L_over_R)
    psi = offset if rising else math.pi - offset
    if not lo < psi < hi:
        psi = target if rising else math.pi - target
    # Converged to the round-off of the arm's angle dead_centre + psi (below it, past pi, the
    # iterates wandered in the round-off until the bracket closed: 9 iterations, not 3)
    close = 4e-16 * dead_centre
    for _ in range(iterations):
        residual = sign * lever_arm(dead_centre + psi, L_over_R) - target
        if residual == 0.0:
            return psi
        if (residual < 0.0) == rising:
            lo = psi
        else:
            hi = psi
        slope = sign * lever_arm_slope(dead_centre + psi, L_over_R)
        guess = psi - residual / slope if slope != 0.0 else -1.0
        if abs(guess - psi) <= 4e-16 * psi + close:  # converged (it may sit on the bracket)
            return guess
        if not lo < guess < hi:
            guess = 0.5 * (lo + hi)
        if abs(guess - psi) <= 4e-16 * guess + close or hi - lo <= 4e-16 * hi + close:
            return guess
        psi = guess
    return psi


@kernel
def _next_leak_kink(theta, theta_dot, segment, machine):
    real = machine.real
    if real.q_L == 0.0 or not theta_dot > 0.0:
        return math.inf, math.inf
    target = real.q_L / (real.AR * theta_dot)  # the |lever arm| where a face starts delivering
    width = math.pi / machine.cylinders
    end = segment_start(segment + 1, machine)
    middle = segment_start(segment, machine) + 0.5 * width
    best = second = math.inf
    for k in range(machine.cylinders):
        if delivering_face(segment, k, machine) == NEITHER:
            continue
        lag = phase(k, machine)
        half = math.floor((middle - lag) / math.pi)  # the face's half turn: it began at half pi
        dead_centre = math.pi * (half % 2)  # reduced: Newton's iterates keep their digits
        sign = 1.0 if half % 2 == 0 else -1.0  # the arm's, as sin's: positive in an even half
        for rising in (True, False):  # near the dead centre it left, and near the next
            psi = _leak_kink_near(dead_centre, rising, target, sign, machine.L_over_R, 100)
            kink = lag + half * math.pi + psi
            if not theta + 1e-9 * width < kink < end - 1e-9 * width:
                continue
            if kink < best:
                best, second = kink, best
            elif kink < second:
                second = kink
    return best, second


_entry(next_leak_kink)(
    lambda theta, theta_dot, segment, machine: (math.inf, math.inf), _next_leak_kink
)


class RealBase(typing.NamedTuple):
    """The real machine's terms that do not change with the gear ratio and the head (a design
    map's points share them); :func:`real_at` completes them."""

    eta_t: float  # [-]
    weight_torque: float  # m_r g R [N m]
    mass_inertia: float  # m_r R^2 [kg m^2]
    AR: float  # A R [m^3/rad]
    leak_per_root_head: float  # Cd a_L sqrt(2 g): q_L / sqrt(h) [m^2.5/s]
    friction: float  # h_f / Q^2 [s^2/m^5]
    rho_g: float  # rho_w g [N/m^3]


def real_at(base, inv_I_eff, load_torque):
    """The :class:`~.model.Real` of a design with this base, 1 / I_eff [1/(kg m^2)] and load
    rho_w g h A R [N m]; None for the ideal machine's (None) base."""
    if base is None:
        return None
    h = load_torque / (base.rho_g * base.AR)
    return Real(
        base.eta_t, base.weight_torque, base.mass_inertia * inv_I_eff, base.AR,
        base.leak_per_root_head * math.sqrt(h), base.friction, base.rho_g, h,
    )  # fmt: skip


def _real_at_typer(base, inv_I_eff, load_torque):
    if _ideal(base):
        return lambda base, inv_I_eff, load_torque: None
    return real_at


overload(real_at, jit_options=JIT_OPTIONS)(_real_at_typer)


def leak_error(h, a, c, d, e, f, g):
    """The step's error estimate of the volume leaked back [m^3]: 0.0 for the ideal machine."""


@overload(leak_error, jit_options=JIT_OPTIONS)
def _leak_error(h, a, c, d, e, f, g):
    if isinstance(a, types.Float):
        return lambda h, a, c, d, e, f, g: 0.0

    def error(h, a, c, d, e, f, g):
        return h * (E1 * a[1] + E3 * c[1] + E4 * d[1] + E5 * e[1] + E6 * f[1] + E7 * g[1])

    return error


def leak_scale(width, machine):
    """What a step's leaked volume is measured against, LEAK_RTOL_FACTOR A R width [m^3]: about
    what a face sweeps over a segment (inf for the ideal machine, which leaks nothing). It keeps
    the delivered volume (swept less leaked) from wandering (a half-bore hole took it 2e-6 of
    the swept volume below zero without it); tighter, the kinks' sub-steps multiply."""


LEAK_RTOL_FACTOR = 100.0  # a run's leaked volume to ~1e-6 of its swept volume, at rtol 1e-8
_entry(leak_scale)(
    lambda width, machine: math.inf,
    lambda width, machine: LEAK_RTOL_FACTOR * machine.real.AR * width,
)


@kernel
def leaky_flow_factors(theta, theta_dot, n_per_stroke, machine):
    """With a leak hole, each sample's delivered flow over ``2 A R theta_dot`` [-] (0 at rest):
    what the driver's flow factor is for a tight piston, ``2 R A (this) theta_dot`` the flow:
    ``Q = sum max(A R |a_k| theta_dot - q_L, 0)`` over the delivering faces. The faces' ``A R
    |a_k|`` at the grid angles g pi / n_per_stroke are tabulated; a sample off them computes its
    own. One loop, no helper taking the table: an array handed to a compiled helper per sample
    costs an atomic reference pair (0.3 ms of the seed example's 600 s with a hole, 45,000
    samples: a tenth of its run)."""
    real = machine.real
    period = 2 * n_per_stroke
    delta = math.pi / n_per_stroke
    levers, own = np.empty((period, ROW)), np.empty(ROW)
    for row in range(period):
        _sums(levers[row], row * delta, (row * machine.cylinders) // n_per_stroke, machine, False)
        for k in range(machine.cylinders):
            levers[row, 1 + k] *= real.AR
    factors = np.empty(theta.shape[0])
    # The last sample's grid index and its row: the next sample is most often the next grid
    # angle (no division, rounding or remainder: 3.1 -> 2.1 ns a sample)
    g, row = -2, 0
    for i in range(theta.shape[0]):
        speed = theta_dot[i]
        if not speed > 0.0:
            factors[i] = 0.0
            continue
        if (g + 1) * delta == theta[i]:
            g, row = g + 1, row + 1 if row + 1 < period else 0
        else:
            g = int(round(theta[i] / delta))
            row = g % period
        on_grid = g * delta == theta[i]
        if not on_grid:
            _sums(own, theta[i], segment_at(theta[i], machine), machine, False)
        Q = 0.0
        for k in range(machine.cylinders):
            swept = levers[row, 1 + k] if on_grid else real.AR * own[1 + k]
            Q += delivered_flow(swept * speed, real.q_L)
        factors[i] = 0.5 * Q / (real.AR * speed)
    return factors


def step_rows(rows, e_ref, faces, frozen_time, machine):
    """The real machine's rows at a step's 7 stage nodes as a tuple of tuples, each what the
    ANGLE domain's rates (:func:`angle_rates`) take at its node, worked out before the step so
    that little but the speed's root lies between one stage and the next (the stages are
    sequential: their latency is the step's cost): 2 / j, the delivering faces' |lever arms|
    (6), C and the main's frozen friction torque at e_ref (:func:`_frozen_parts` at the
    weights ``e_ref``, :func:`frozen_energy`),
    ``faces`` (the delivering faces of a segment stepped on :func:`_continued_loads`, its hole's
    windows corrected apart, or -1.0), tau (j - 1) and tau / u (:func:`time_frozen`), A R sum
    |a| and faces q_L. The ideal machine's: ``rows`` as they are. A stage's row taken from the
    array is a view, whose reference is counted atomically as it is made and dropped: 14 atomic
    operations a step, a third of the time of the real machine's steps (eta_t alone)."""


@kernel
def _row(rows, stage, e_ref, faces, frozen_time, machine):
    tau, per_u = frozen_time
    return (
        rows[stage, 10], rows[stage, 1], rows[stage, 2], rows[stage, 3], rows[stage, 4],
        rows[stage, 5], rows[stage, 6],
        _weighted(e_ref, (rows[stage, 7], rows[stage, 16], rows[stage, 17])),
        _weighted(e_ref, (rows[stage, 12], rows[stage, 14], rows[stage, 15])), faces,
        tau * rows[stage, 13], tau * per_u, rows[stage, 11],
        max(faces, 0.0) * machine.real.q_L,  # (faces is -1.0 where the windows are not jumped)
    )  # fmt: skip


def _step_rows(rows, e_ref, faces, frozen_time, machine):
    f, m = frozen_time, machine
    return (
        _row(rows, 0, e_ref, faces, f, m), _row(rows, 1, e_ref, faces, f, m),
        _row(rows, 2, e_ref, faces, f, m), _row(rows, 3, e_ref, faces, f, m),
        _row(rows, 4, e_ref, faces, f, m), _row(rows, 5, e_ref, faces, f, m),
        _row(rows, 6, e_ref, faces, f, m),
    )  # fmt: skip


_entry(step_rows)(
    lambda rows, e_ref, faces, frozen_time, machine: rows, _step_rows, inline="always"
)  # (spliced in: compiled apart, its 98 numbers came back through memory, 0.1 ms a run)


def split_sizes_by_parity(m, m_other, machine):
    """After a segment, (the next segment's sub-steps, the other parity's): the ideal machine
    keeps one m for every segment, (m, m_other) as they are; the real machine one per parity,
    swapped, for its two parities load the crank differently (a single cylinder's delivering
    half has the main's friction and the hole's kinks, its intake half none: one m for both
    made every delivering segment fail its first sub-step and go on off the tables)."""


_entry(split_sizes_by_parity)(
    lambda m, m_other, machine: (m, m_other), lambda m, m_other, machine: (m_other, m)
)


def work_rows(machine):
    """How many rows the work quadratures take in the output: 1, or WORKS."""


_entry(work_rows)(lambda machine: 1, lambda machine: WORKS)


# -- A leak hole's windows, corrected apart (docs/model.rst, "The real machine"). -----------------
#
# Inside a delivering segment a face's hole changes its load only in a window next to each of its
# dead centres, where it sweeps less than the hole passes (u_k <= q_L: 0.005-0.009 rad wide at the
# seed example's running speed). A segment whose windows are narrow is stepped on the loads
# continued past them (:func:`_continued_loads`: smooth, so its steps neither stop at the windows'
# kinks nor leave the tables), and each window's difference, true less continued, is added as a
# jump: the window after the segment's start at its start, the one before its end at its end.

WINDOW_TARGET = 0.05  # windows only while q_L / (A R theta_dot) (the arm at a kink) is below this
WINDOW_DRIFT = 0.01  # ... and the energy changes by less than this share over twice their width
WINDOW_NEWTON = 4  # at most Newton's iterations for a window's kink (:func:`_window_kink`: one
# but for a short rod's bottom dead centre; its error moves a jump only to second order)
WINDOW_NODES = 3  # Gauss-Legendre nodes between a window's kinks (4 moved the runs by < 1e-12;
# 2 missed a 3 mm hole's jump at a slow crank, 0.09 rad windows, by 4e-4 of itself)
GAUSS_WINDOW = _gauss(WINDOW_NODES)


def open_windows(theta, u, slope, h, segment, delta, j, machine):
    """At a delivering segment's start theta, at energy u with slope du/dtheta: how many faces
    deliver in it, as a float, when its hole's windows are narrow enough to be corrected apart
    (:func:`window_jump`), else -1.0 (and always for the ideal machine, or a tight piston); h
    is the split's sub-step.

    Narrow: the arm at a kink at most WINDOW_TARGET, the energy's change over twice the widest
    window at most WINDOW_DRIFT of it, and no grid angle ``g delta`` inside either window but the
    dead centres (the samples there are taken before the jump at the start, after it at the end),
    nor a whole sub-step h (past the first the run may go on without windows: the start's is
    behind it). ``j`` is J / I_eff at theta (:func:`window_edges`).
    """


@kernel
def _open_windows(theta, u, slope, h, segment, delta, j, machine):
    real = machine.real
    if real.q_L == 0.0 or not u > 0.0:
        return -1.0
    target = real.q_L / real.AR * math.sqrt(0.5 * j / u)  # q_L / (A R theta_dot)
    if not target <= WINDOW_TARGET:
        return -1.0
    ratio = machine.L_over_R
    reach = 2.0 * target * ratio / (ratio - 1.0)  # twice the widest window
    if reach * abs(slope) > WINDOW_DRIFT * u or reach > h:
        return -1.0
    start, end = segment_start(segment, machine), segment_start(segment + 1, machine)
    per_delta = 1.0 / delta
    if math.floor((start + reach) * per_delta) * delta > start + 1e-9 * delta:
        return -1.0
    if math.ceil((end - reach) * per_delta) * delta < end - 1e-9 * delta:
        return -1.0
    faces = 0.0
    for k in range(machine.cylinders):
        if delivering_face(segment, k, machine) != NEITHER:
            faces += 1.0
    return faces


_entry(open_windows)(lambda theta, u, slope, h, segment, delta, j, machine: -1.0, _open_windows)


def window_edges(machine):
    """What a leak hole's windows take at a segment's edges, which depends on the angle alone:
    ``edges[parity][0]`` at the start of a segment of that parity, ``[1]`` at its end, each (the
    conservative torque over I_eff [1/s^2], the frozen friction's density c [1/rad], J / I_eff
    [-]). Every segment of a parity loads the crank the same way (:mod:`.driver`): computed
    once, not at every delivering segment's two edges (0.1 us a segment). Constants for the
    ideal machine, which has no windows."""


@kernel
def _edge(theta, segment, machine):
    """(conservative torque / I_eff, c, J / I_eff) at theta (:func:`window_edges`)."""
    no_main = (0.0, 0.0, 0.0)
    c = friction_density(theta, segment, machine) if machine.real.friction != 0.0 else no_main
    torque = conservative_torque(theta, segment, machine) * machine.inv_I_eff
    return torque, c, _inertia_ratio(theta, machine)


def _window_edges(machine):
    starts = (segment_start(0, machine), segment_start(1, machine), segment_start(2, machine))
    return (
        (_edge(starts[0], 0, machine), _edge(starts[1], 0, machine)),
        (_edge(starts[1], 1, machine), _edge(starts[2], 1, machine)),
    )


_IDEAL_EDGE = (0.0, 0.0, 1.0)
_entry(window_edges)(
    lambda machine: ((_IDEAL_EDGE, _IDEAL_EDGE), (_IDEAL_EDGE, _IDEAL_EDGE)), _window_edges
)


def energy_slope(rate, e_ref, edge, machine):
    """de/dtheta [J/(kg m^2) per rad] at a segment's edge (:func:`window_edges`' ``edge``)
    where x0's rate is ``rate``: e = x0 + Lambda - (C at the weights e_ref), for a leak hole's windows
    (:func:`open_windows`, :func:`window_jump`); 0.0 without a hole (the ideal machine, a tight
    piston), which has no windows."""


def _energy_slope(rate, e_ref, edge, machine):
    if machine.real.q_L == 0.0:
        return 0.0
    slope = rate + edge[0]
    if machine.real.friction != 0.0:
        slope -= _weighted(e_ref, edge[1])
    return slope


_entry(energy_slope)(lambda rate, e_ref, edge, machine: 0.0, _energy_slope)


# A window's angles are counted from its dead centre, s (a few hundredths of a radian): each
# node's sin s and cos s from their Taylor series, and each cylinder's arm there by the angle
# addition from its phase at the segment's edge (a multiple of pi / n, worked out once a
# window), with no sincos (a window's kink and 3 nodes took 4 of the real machine's 7 % in
# it) and no round-off of the crank's angle (1e-12 rad after 600 s of a seed example's run).
SMALL_ANGLE = 0.25  # |s| up to which a window's sin s and cos s are Taylor's (:func:`_sin_cos`)


@inline_kernel
def _sin_cos(s):
    """(sin s, cos s) [-] of an angle s [rad] off a dead centre: for |s| <= SMALL_ANGLE (every
    window but a very short rod's) their Taylor series to s^11 and s^12, whose next terms are
    below 1e-17 of them there; math's beyond."""
    if not abs(s) <= SMALL_ANGLE:
        return math.sin(s), math.cos(s)
    z = s * s
    sin = s + s * z * (
        -1.0 / 6.0 + z * (1.0 / 120.0 + z * (-1.0 / 5040.0 + z * (1.0 / 362880.0 - z / 39916800.0)))
    )
    cos = 1.0 + z * (
        -0.5
        + z * (
            1.0 / 24.0
            + z * (-1.0 / 720.0 + z * (1.0 / 40320.0 + z * (-1.0 / 3628800.0 + z / 479001600.0)))
        )
    )  # fmt: skip
    return sin, cos


@inline_kernel
def _arm_of(sin, cos, L_over_R):
    """Eq. (1)'s lever arm (:func:`~.equations.lever_arm`) [-] of the angle whose sine and
    cosine are given, and its derivative (:func:`~.equations.lever_arm_slope`) [-]."""
    inv_r = 1.0 / math.sqrt(L_over_R * L_over_R - sin * sin)
    q = cos * inv_r
    arm = sin * (1.0 + q)
    slope = cos + (cos * cos - sin * sin) * inv_r + sin * sin * q * q * inv_r
    return arm, slope


@inline_kernel
def _edge_phases(edge, segment, rows, machine):
    """At the segment's edge ``edge`` pi / n, for each cylinder k: in ``rows[4, k]`` and
    ``rows[5, k]`` the sine and cosine of its angle there, a multiple of pi / n (exact at a dead
    centre); in ``rows[3, k]`` 1.0 if its face delivers in the segment, else 0.0; in
    ``rows[2, k]`` 1.0 (-1.0) if that face has its top (bottom) dead centre there, else 0.0.
    Returns how many delivering faces have their dead centre there."""
    n = machine.cylinders
    at_dead_centre = 0
    for k in range(n):
        p = (edge - 2 * k) % (2 * n)  # the angle p pi / n, in [0, 2 pi)
        delivers = delivering_face(segment, k, machine) != NEITHER
        rows[3, k] = 1.0 if delivers else 0.0
        rows[2, k] = 0.0
        if p == 0 or p == n:
            rows[4, k], rows[5, k] = 0.0, 1.0 if p == 0 else -1.0
            if delivers:
                rows[2, k] = rows[5, k]
                at_dead_centre += 1
        else:
            rows[4, k], rows[5, k] = math.sin(p * math.pi / n), math.cos(p * math.pi / n)
    return at_dead_centre


@inline_kernel
def _window_kink(target, top, L_over_R, iterations):
    """The distance s [rad] from a dead centre (the top one, phi = 0, or the bottom one) where
    the lever arm's size |a| reaches ``target`` (< 1): from its Taylor series to s^5, |a| = c1 s
    + c3 s^3 + c5 s^5 + ..., inverted, then at most ``iterations`` of Newton's method, each squaring the error,
    until a step is below 1e-8 of s (from O(target^7), one is enough but next to a short rod's
    bottom dead centre, whose arm grows as (1 - R/L) s)."""
    k = 1.0 if top else -1.0  # |a| = sin s (1 + k cos s / r), r = sqrt((L/R)^2 - sin^2 s)
    inv_L = 1.0 / L_over_R
    c1 = 1.0 + k * inv_L
    inv_c1 = 1.0 / c1
    inv_L2 = inv_L * inv_L
    c3 = -c1 / 6.0 + k * inv_L * (0.5 * inv_L2 - 0.5)
    c5 = 1.0 / 120.0 + k * inv_L * (2.0 / 15.0 + inv_L2 * (-0.5 + 0.375 * inv_L2))
    first = target * inv_c1
    cube = first * first * first
    s = first + cube * inv_c1 * (-c3 + (3.0 * c3 * c3 - c1 * c5) * first * first * inv_c1)
    if not 0.0 < s < 0.5 * math.pi:
        s = first if first < 0.5 * math.pi else target
    for _ in range(iterations):
        sin, cos = _sin_cos(s)
        arm, slope = _arm_of(k * sin, k * cos, L_over_R)
        arm, slope = k * arm, k * slope  # |a| and its slope in s
        step = (arm - target) / slope if slope > 0.0 else 0.0
        if not 0.0 < s - step < 0.5 * math.pi:
            break
        s -= step
        if abs(step) <= 1e-8 * s:  # the next step would be below round-off
            break
    return s


@inline_kernel
def _window_widths(e, slope, side, j, rows, machine):
    """The widths [rad] of the windows of the faces whose dead centre is the segment's start
    (side 1) or end (side -1), as :func:`_edge_phases` wrote them in ``rows``: (the narrowest,
    the next wider or inf), inf where there is none (at most two faces share a dead centre: a
    cylinder's and the opposite one's). The kink is where the face's swept flow reaches q_L at
    the speed there, e growing linearly from the edge (the speed taken at the kink's first
    guess, from the arm's slope at the dead centre; J / I_eff = j there). Newton stops after
    WINDOW_NEWTON iterations (:func:`_window_kink`): the kink is where the face's flow reaches
    q_L at the speed of e taken linear across the window, itself an approximation."""
    real = machine.real
    q = real.q_L / real.AR  # the arm at a kink times the crank's speed [rad/s]
    half_j = 0.5 * j
    guess = q * math.sqrt(half_j / e)  # the arm at a kink, at the edge's speed
    first = second = math.inf
    for k in range(machine.cylinders):
        if rows[2, k] == 0.0:
            continue  # its dead centre is not the edge, or it does not deliver
        top = rows[2, k] > 0.0
        c1 = 1.0 + (1.0 if top else -1.0) * (1.0 / machine.L_over_R)  # the arm's slope there
        target = q * math.sqrt(half_j / (e + side * slope * guess * (1.0 / c1)))
        psi = _window_kink(target, top, machine.L_over_R, WINDOW_NEWTON)
        if psi < first:
            first, second = psi, first
        elif first < psi < second:
            second = psi
    return first, second


@inline_kernel
def _window_arms(row, sin_s, cos_s, rows, machine):
    """:func:`_sums`' row at the angle s past the edge whose phases :func:`_edge_phases` wrote
    into ``rows`` (sin s and cos s given): J / I_eff, and |lever arm| of each delivering face."""
    squares = 0.0
    for k in range(machine.cylinders):
        sin = rows[4, k] * cos_s + rows[5, k] * sin_s
        cos = rows[5, k] * cos_s - rows[4, k] * sin_s
        a = _arm_of(sin, cos, machine.L_over_R)[0]
        squares += a * a
        row[1 + k] = abs(a) * rows[3, k]
    row[0] = 1.0 + machine.real.mass_ratio * squares


@inline_kernel
def _window_loads(theta_dot, row, faces, machine):
    """:func:`_face_loads` less :func:`_continued_loads` at crank speed theta_dot [rad/s] on the
    faces whose arms ``row`` holds: (the load torque's [N m], the delivered flow's, continued
    less true [m^3/s], and the friction's, h_f Q less h_f Q continued [m^4/s]). Their twin for
    a window's nodes, with a hole (q_L > 0): :func:`~.equations.face_pressure`'s two branches
    as a branch (its form without one, for numpy, cost a window 25 ns)."""
    real = machine.real
    Q = arms = 0.0
    for k in range(machine.cylinders):
        Q += max(real.AR * row[1 + k] * theta_dot - real.q_L, 0.0)  # :func:`delivered_flow`
        arms += row[1 + k]
    h_f = real.friction * Q * Q
    Q_c = real.AR * arms * theta_dot - faces * real.q_L
    h_f_c = real.friction * Q_c * Q_c
    heads = 0.0  # sum over the faces of their head times their arm [m]
    for k in range(machine.cylinders):
        u = real.AR * row[1 + k] * theta_dot
        if u > real.q_L:  # delivering: the head and the main's friction
            heads += (real.h + h_f) * row[1 + k]
        else:  # what drives u through the hole
            heads += real.h * (u / real.q_L) * (u / real.q_L) * row[1 + k]
    load = real.rho_g * real.AR * heads
    load_c = (machine.load_torque + real.rho_g * h_f_c * real.AR) * arms
    return load - load_c, Q_c - Q, h_f * Q - h_f_c * Q_c


def window_jump(theta, e, slope, side, segment, faces, j, rows, machine):
    """The windows next to the dead centre theta, the segment's start (side 1) or end (side -1),
    of a segment stepped on :func:`_continued_loads` at energy e (de/dtheta = slope there):
    (the jump of e, of the time, and of the work quadratures), true less continued.

    With f the rates' difference over the window (the load's excess, the leaked volume, the
    friction; the windmill's is second order), the jumps are its integrals, e's being -excess /
    I_eff; the time's is int (1/theta_dot_true - 1/theta_dot) over the window, to first order in
    e's difference -side int s f_e / (2 e theta_dot) ds (s from the dead centre). Gauss-Legendre
    (WINDOW_NODES) between the kinks (the integrand is smooth between them). ``j`` is J / I_eff
    at theta (:func:`window_edges`). ``rows`` is scratch (7 rows of ROW numbers, rows 3 to 6
    written): one allocated per call cost the seed with a hole 0.1 us a window, and its last
    row handed as a view an atomic reference pair."""


@kernel
def _window_jump(theta, e, slope, side, segment, faces, j, rows, machine):
    row = rows[6]
    if _edge_phases(segment if side > 0 else segment + 1, segment, rows, machine) == 0:
        return 0.0, 0.0, (0.0, 0.0, 0.0, 0.0)  # no delivering face's dead centre: no window
    x, w = GAUSS_WINDOW
    dt = leaked = friction = excess = 0.0
    low = 0.0
    for high in _window_widths(e, slope, side, j, rows, machine):
        if high == math.inf:
            break
        for q in range(WINDOW_NODES):
            s = low + x[q] * (high - low)
            e_at = e + slope * s * side
            inv_2e = 0.5 / e_at
            sin_s, cos_s = _sin_cos(side * s)
            _window_arms(row, sin_s, cos_s, rows, machine)
            theta_dot = math.sqrt(2.0 * e_at / row[0])
            load, Q, h_f_Q = _window_loads(theta_dot, row, faces, machine)
            weight = w[q] * (high - low)
            per_radian = weight * theta_dot * row[0] * inv_2e  # weight / theta_dot
            excess += weight * load
            leaked += per_radian * Q
            friction += per_radian * h_f_Q
            dt -= side * per_radian * s * load * inv_2e
        low = high
    inv_I_eff = machine.inv_I_eff
    return -excess * inv_I_eff, dt * inv_I_eff, (0.0, leaked, friction * machine.real.rho_g, excess)


_entry(window_jump)(
    lambda theta, e, slope, side, segment, faces, j, rows, machine: (0.0, 0.0, 0.0), _window_jump
)


def jump_work(W, jump, machine):
    """The work quadratures W plus a window's jump (the ideal machine's W as it is)."""


_entry(jump_work)(
    lambda W, jump, machine: W,
    lambda W, jump, machine: (W[0] + jump[0], W[1] + jump[1], W[2] + jump[2], W[3] + jump[3]),
)
