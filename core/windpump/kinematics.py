"""Slider-crank kinematics of the pump (paper Eqs. 1, 2, 16; model-notes.md "Kinematics").

The crank angle ``theta`` is measured from top dead centre (TDC). The cylinder takes water in on
0 < theta mod 2 pi < pi and exhausts it on pi < theta mod 2 pi < 2 pi. All functions accept numpy
arrays and broadcast.
"""

from __future__ import annotations

import numpy as np

from . import _kernels
from .validation import finite_array, positive, rod_ratio


def piston_position(theta, R: float, L: float):
    """Piston displacement from TDC, x [m] (Eq. 1).

    ``x = L + R - (sqrt(L^2 - R^2 sin^2 theta) + R cos theta)``; 0 at TDC, 2R at bottom dead centre.

    Parameters
    ----------
    theta : array_like
        Crank angle from TDC [rad].
    R, L : float
        Crank radius and rod length [m], L > R.

    Examples
    --------
    >>> import math
    >>> round(float(piston_position(math.pi, R=0.04, L=0.15)), 12)  # 2R at bottom dead centre
    0.08
    """
    R = positive("R", R, "m")
    ratio = rod_ratio(positive("L", L, "m") / R)
    return R * _kernels.piston_over_R_ufunc(finite_array("theta", theta, "rad"), ratio)


def rod_angle(theta, L_over_R: float):
    """Angle theta_c of the connecting rod with the cylinder axis [rad]: sin theta_c = sin theta/(L/R).

    Examples
    --------
    >>> import math
    >>> round(float(rod_angle(math.pi / 2, 2.0)), 6)  # asin(1/2)
    0.523599
    """
    return np.arcsin(np.sin(finite_array("theta", theta, "rad")) / rod_ratio(L_over_R))


def lever_arm(theta, L_over_R: float):
    """Lever arm of the rod force on the crank, sin(theta + theta_c)/cos(theta_c) [-] (Eqs. 12, 18).

    Equal to ``(dx/dtheta)/R``: positive on the intake half, negative on the exhaust half, zero at the
    dead centres theta = k pi.

    Examples
    --------
    >>> import math
    >>> float(lever_arm(3 * math.pi / 2, 3.75))
    -1.0
    """
    return _kernels.lever_arm_ufunc(finite_array("theta", theta, "rad"), rod_ratio(L_over_R))


def f2(theta, L_over_R: float):
    """Kinematic function f2 of Eq. (16): the pumped-volume rate per unit crank speed [-].

    ``dV/dt = 2 R A f2(theta) theta_dot``: ``f2 = -(dx/dtheta)/(2R) >= 0`` while exhausting and 0 while
    taking water in, so one revolution delivers one stroke volume 2RA. (The paper writes
    ``xdot = 2 R theta_dot f2``; model-notes.md explains the sign.)

    Examples
    --------
    >>> import math
    >>> float(f2(3 * math.pi / 2, 3.75)), float(f2(math.pi / 2, 3.75))
    (0.5, 0.0)
    """
    return _kernels.f2_ufunc(finite_array("theta", theta, "rad"), rod_ratio(L_over_R))


def swept_strokes(theta, L_over_R: float):
    """Exhaust strokes completed at crank angle theta, counted from theta = 0 [-].

    The integral of f2 over the angle, in closed form from Eq. (1): each exhaust half adds
    ``(2R - x)/(2R)`` as it goes, so the count is continuous and never decreases. Multiply a
    difference by 2 R A for the pumped volume [m^3].

    Examples
    --------
    >>> import math
    >>> float(swept_strokes(2 * math.pi, 3.75)), float(swept_strokes(3 * math.pi, 3.75))
    (1.0, 1.0)
    """
    return _kernels.swept_strokes_ufunc(finite_array("theta", theta, "rad"), rod_ratio(L_over_R))
