"""The rising main's friction, split at a frozen energy (docs/model.rst, "The real machine"):
its density, its work between angles by Gauss-Legendre, and the frozen work a step carries.
"""

from __future__ import annotations

import math

import numpy as np

from .dopri5 import (
    NODES,
)  # fmt: skip
from .jit import kernel
from .model import (
    NEITHER,
    delivering_face,
    lever_arm,
    phase,
)
from .real_entries import (
    C_PARTS,
    M_PARTS,
    _entry,
)


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
