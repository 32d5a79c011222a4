"""A leak hole's windows, corrected apart (docs/model.rst, "The real machine"): the
narrow angles around a kink where the relief switches, jumped in closed form.
"""

from __future__ import annotations

import math

from .jit import inline_kernel, kernel
from .model import (
    NEITHER,
    delivering_face,
    segment_start,
)
from .real_entries import (
    _entry,
    conservative_torque,
)
from .real_friction import (
    _gauss,
    _weighted,
    friction_density,
)
from .real_loads import (
    _inertia_ratio,
)

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
