"""The model's pointwise equations, written once for numpy and for the compiled kernels.

Eq. (1) (the piston's position), its derivative (the lever arm of the rod force on the crank,
Eq. 12's load term) and Eq. (11) (the windmill's torque curve, with a torque at rest T_0 and the
wind similarity) as plain functions of numbers, in numpy's functions (``np.sin``, ...): called with
arrays they broadcast (:mod:`windpump.kinematics`, :mod:`windpump.windmill`), and numba compiles
the same functions for floats (:mod:`.model` wraps each in :func:`~.jit.kernel`). So there is one
copy of each equation, and the compiled model runs the numbers the numpy functions compute.

This module imports neither numba nor anything of the package: the numpy side imports it without
loading the compiler (``import windpump`` stays light).
"""

from __future__ import annotations

import numpy as np


def piston_over_R(phi, L_over_R):
    """Piston position from top dead centre over the crank radius, x/R [-] (Eq. 1).

    ``x/R = L/R + 1 - (sqrt((L/R)^2 - sin^2 phi) + cos phi)``: 0 at TDC, 2 at bottom dead centre.

    Parameters
    ----------
    phi : float or ndarray
        Crank angle from TDC [rad].
    L_over_R : float or ndarray
        Rod-to-crank ratio, > 1.

    Examples
    --------
    >>> import math
    >>> float(piston_over_R(0.0, 3.75)), float(piston_over_R(math.pi, 3.75))
    (0.0, 2.0)
    """
    s = np.sin(phi)
    return L_over_R + 1.0 - (np.sqrt(L_over_R * L_over_R - s * s) + np.cos(phi))


def lever_arm(phi, L_over_R):
    """Lever arm of the rod force on the crank, ``sin(phi + theta_c)/cos(theta_c)`` [-].

    Equal to ``(dx/dphi)/R``, the derivative of Eq. (1): ``sin phi (1 + cos phi /
    sqrt((L/R)^2 - sin^2 phi))``; negative on the exhaust half (Eq. 12, footnote 6).

    Parameters
    ----------
    phi : float or ndarray
        Crank angle from TDC [rad].
    L_over_R : float or ndarray
        Rod-to-crank ratio, > 1.

    Examples
    --------
    >>> import math
    >>> float(lever_arm(3 * math.pi / 2, 3.75))
    -1.0
    """
    s = np.sin(phi)
    return s * (1.0 + np.cos(phi) / np.sqrt(L_over_R * L_over_R - s * s))


def windmill_torque(x, s, T_m, T_0):
    """Windmill torque [N m] at ``x = omega / omega_m`` in the wind ``s = V / V_ref`` (Eq. 11).

    ``T = s^2 T_0 + (T_m - T_0) x (2 s - x)``: the curve ``T_0 + (T_m - T_0) x (2 - x)`` (Eq. 11
    when T_0 = 0) at V_ref, scaled by similarity (torques as s^2, speeds as s); at s = 1 it is that
    curve to the last bit. T_m, T_0 and omega_m are the curve's at V_ref.

    Parameters
    ----------
    x : float or ndarray
        Windmill speed over the speed of the peak at V_ref [-].
    s : float or ndarray
        Wind speed over V_ref [-].
    T_m, T_0 : float or ndarray
        Peak torque and torque at rest at V_ref [N m].

    Examples
    --------
    >>> float(windmill_torque(1.0, 1.0, 0.6, 0.0)), float(windmill_torque(2.0, 2.0, 0.6, 0.2))
    (0.6, 2.4)
    """
    return s * s * T_0 + (T_m - T_0) * x * (2.0 * s - x)
