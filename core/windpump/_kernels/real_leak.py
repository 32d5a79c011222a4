"""A leak hole in the kernels: the next kink of its relief (where a face's sweep passes what the
hole passes), its error control, and the flow factors of a leaky run's samples.
"""

from __future__ import annotations

import math

import numpy as np
from numba import types
from numba.extending import overload

from .dopri5 import (
    E1,
    E3,
    E4,
    E5,
    E6,
    E7,
)  # fmt: skip
from .jit import kernel
from .model import (
    NEITHER,
    delivering_face,
    lever_arm,
    phase,
    segment_at,
    segment_start,
)
from .real_entries import (
    JIT_OPTIONS,
    ROW,
    _entry,
    delivered_flow,
    lever_arm_slope,
)
from .real_loads import (
    _sums,
)


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
