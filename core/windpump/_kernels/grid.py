"""Many runs of Eq. (12) at once: a grid of designs, in parallel over every core (numba prange)."""

from __future__ import annotations

import math

import numpy as np
from numba import prange

from .driver import integrate
from .jit import parallel_kernel
from .model import Machine
from .real import real_at
from .samples import STROKES, THETA
from .samples import T as TIME
from .stepping import REACHED_T_END


@parallel_kernel
def steady_runs(
    R_dagger, inv_I_eff, load_torque, theta_dot0, t_end, base, cylinders, double_acting, turns,
    rtol, max_steps, pace, real_base=None, rotor=None,
):  # fmt: skip
    """Run every point from theta = 0 at its theta_dot0 to its t_end; return the cycle-mean crank
    speed [rad/s] and the strokes delivered per second [1/s] over its last ``turns`` revolutions,
    and how each run ended (the integrator's outcome; -1 for a point not run).

    ``base`` holds (T_m, T_0, omega_m, L_over_R), the fields every point shares, and
    ``real_base`` the real machine's (:class:`~.real.RealBase`; None: the ideal machine), ``rotor``
    the windmill's C_Q table (:class:`~.rotor.RotorTable`; None: Eq. 11). A point with
    theta_dot0 = 0, or that stalls, or that does not complete ``turns`` revolutions, gets NaN.
    """
    points = R_dagger.size
    speed = np.full(points, np.nan)
    strokes_per_s = np.full(points, np.nan)
    outcomes = np.full(points, -1, dtype=np.int64)
    T_m, T_0, omega_m, L_over_R = base
    for i in prange(points):
        if not theta_dot0[i] > 0.0:
            continue
        machine = Machine(
            R_dagger[i], T_m, T_0, omega_m, inv_I_eff[i], load_torque[i], L_over_R, cylinders,
            double_acting, None, real_at(real_base, inv_I_eff[i], load_torque[i]), rotor,
        )  # fmt: skip
        capacity = int(1.1 * theta_dot0[i] * t_end[i] / math.pi) + 64
        ran = integrate(
            machine, 0.0, theta_dot0[i], t_end[i], 1, None, rtol, max_steps, pace, capacity
        )
        out, n, outcome = ran.out, ran.samples, ran.outcome
        outcomes[i] = outcome
        if outcome != REACHED_T_END:
            continue
        # Samples every pi from theta = 0, then the end (off the grid unless it fell on one).
        last = n - 1
        if abs(out[THETA, last] - math.pi * round(out[THETA, last] / math.pi)) > 1e-9:
            last -= 1
        first = last - 2 * turns
        if first < 0:
            continue
        duration = out[TIME, last] - out[TIME, first]
        speed[i] = (out[THETA, last] - out[THETA, first]) / duration
        strokes_per_s[i] = (out[STROKES, last] - out[STROKES, first]) / duration
    return speed, strokes_per_s, outcomes
