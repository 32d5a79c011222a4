"""The real machine's expressions: the sums over faces and cylinders (twins of
:func:`windpump.model.loads.faces_load`, :func:`windpump.model.loads.weight_torque` and
:func:`windpump.model.reciprocating.crank_inertia`), the loads, the rates in angle and in time, and
the stage rows of a sub-step.
"""

from __future__ import annotations

import math

from numba import types
from numba.extending import overload

from .dopri5 import (
    NODES,
)  # fmt: skip
from .jit import kernel
from .model import (
    NEITHER,
    delivering_face,
    lever_arm,
    load_on_crank,
    load_work,
    phase,
    piston_over_R,
    segment_start,
    windmill_torque_on_crank,
)
from .real_entries import (
    JIT_OPTIONS,
    ROW,
    _entry,
    angle_rates,
    conservative_torque,
    conservative_work,
    delivered_flow,
    face_pressure,
    fill_row,
    inertia_ratio,
    lever_arm_slope,
    time_rates,
    torque_at_rest,
    transmitted,
    zero_work,
)
from .real_friction import (
    _frozen_parts,
    _held,
)
from .real_ripple import (
    _inertia_since,
    _lambda_between,
)
from .wind import wind_scale


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
