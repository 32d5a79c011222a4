"""The model's pointwise equations, written once for numpy and for the compiled kernels.

Eq. (1) (the piston's position), its derivative (the lever arm of the rod force on the crank,
Eq. 12's load term) and Eq. (11) (the windmill's torque curve, with a torque at rest T_0 and the
wind similarity) as plain functions of numbers, in numpy's functions (``np.sin``, ...): called with
arrays they broadcast (:mod:`windpump.model.kinematics`, :mod:`windpump.model.windmill`), and numba compiles
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


def lever_arm_slope(phi, L_over_R):
    """The lever arm's derivative, ``(d^2 x / dphi^2) / R`` [-] (Eq. 1 differentiated twice).

    With ``r = sqrt((L/R)^2 - sin^2 phi)``: ``cos phi + (cos^2 phi - sin^2 phi) / r +
    sin^2 phi cos^2 phi / r^3``. The reciprocating mass's inertia ``m_r x'^2`` changes with the
    crank angle at the rate ``2 m_r x' x''``.

    Parameters
    ----------
    phi : float or ndarray
        Crank angle from TDC [rad].
    L_over_R : float or ndarray
        Rod-to-crank ratio, > 1.

    Examples
    --------
    >>> float(lever_arm_slope(0.0, 3.75)) == 1.0 + 1.0 / 3.75
    True
    """
    s = np.sin(phi)
    c = np.cos(phi)
    r = np.sqrt(L_over_R * L_over_R - s * s)
    return c + (c * c - s * s) / r + s * s * c * c / (r * r * r)


def lever_arm_squared_integral(phi, L_over_R):
    """``int_0^phi (lever arm)^2 dphi'`` [rad], in closed form (the lever arm of
    :func:`lever_arm`).

    With ``r = L/R``, ``q = sqrt(r^2 - 1)`` and ``s = sin phi``, the arm squared is ``sin^2 phi``
    plus ``2 sin^2 phi cos phi / sqrt(r^2 - s^2)`` plus ``sin^2 phi cos^2 phi / (r^2 - s^2)``,
    whose integrals are ``phi/2 - sin(2 phi)/4``, ``r^2 asin(s/r) - s sqrt(r^2 - s^2)`` and
    ``(r^2 - 1/2) phi - sin(2 phi)/4 - r q psi``, psi the angle ``atan2(q sin phi, r cos phi)``
    made continuous (it stays within pi/2 of phi). It grows by about pi per half turn (the
    mean square arm is 1/2 for a long rod).

    Parameters
    ----------
    phi : float or ndarray
        Crank angle from TDC [rad].
    L_over_R : float or ndarray
        Rod-to-crank ratio, > 1.

    Examples
    --------
    >>> import math
    >>> round(float(lever_arm_squared_integral(2 * math.pi, 1e6)) / math.pi, 9)  # long rod
    1.0
    """
    r = L_over_R
    q = np.sqrt(r * r - 1.0)
    s, c = np.sin(phi), np.cos(phi)
    psi = np.arctan2(q * s, r * c)
    psi = psi + 2.0 * np.pi * np.round((phi - psi) / (2.0 * np.pi))
    double = 0.5 * np.sin(2.0 * phi)
    first = 0.5 * phi - 0.5 * double
    second = r * r * np.arcsin(s / r) - s * np.sqrt(r * r - s * s)
    third = (r * r - 0.5) * phi - 0.5 * double - r * q * psi
    return first + second + third


def leak_capacity(d_leak, Cd_leak, g, h):
    """The most a leak hole passes against the static head, ``q_L = Cd a_L sqrt(2 g h)``
    [m^3/s], ``a_L = pi d_leak^2 / 4``.

    Parameters
    ----------
    d_leak : float or ndarray
        Hole diameter [m]; 0: no hole.
    Cd_leak : float or ndarray
        Discharge coefficient [-].
    g : float or ndarray
        Gravity [m/s^2].
    h : float or ndarray
        Head [m].

    Examples
    --------
    >>> round(float(leak_capacity(0.004, 0.6, 9.81, 10.0)) * 1e3, 4)  # L/s
    0.1056
    """
    return Cd_leak * (0.25 * np.pi) * d_leak * d_leak * np.sqrt(2.0 * g * h)


def friction_coefficient(f_main, L_main, D_main, g):
    """The rising main's friction head per flow squared, ``h_f / Q^2 = f (L/D) / (2 g a^2)``
    [s^2/m^5] (Darcy-Weisbach), ``a = pi D^2 / 4``.

    Parameters
    ----------
    f_main : float or ndarray
        Darcy friction factor [-].
    L_main, D_main : float or ndarray
        Length and inner diameter of the rising main [m].
    g : float or ndarray
        Gravity [m/s^2].

    Examples
    --------
    >>> K = float(friction_coefficient(0.02, 30.0, 0.05, 9.81))
    >>> round(K * 1e-3 ** 2, 3)  # h_f [m] at 1 L/s
    0.159
    """
    area = 0.25 * np.pi * D_main * D_main
    return f_main * (L_main / D_main) / (2.0 * g * area * area)


def delivered_flow(u, q_L):
    """A delivering face's flow into the rising main, ``max(u - q_L, 0)`` [m^3/s]: what it
    sweeps less what leaks back through its hole.

    Parameters
    ----------
    u : float or ndarray
        Flow the face sweeps, ``A |x'| theta_dot`` [m^3/s], >= 0.
    q_L : float or ndarray
        The hole's capacity (:func:`leak_capacity`) [m^3/s]; 0: no hole.

    Examples
    --------
    >>> float(delivered_flow(3.0, 1.0)), float(delivered_flow(0.5, 1.0))
    (2.0, 0.0)
    """
    return np.maximum(u - q_L, 0.0)


def face_pressure(u, q_L, rho_w, g, h, h_f):
    """Pressure on a delivering face [Pa]: ``rho_w g (h + h_f)`` while it delivers (u > q_L, or
    always without a hole), else what drives u through the hole, ``rho_w g h (u / q_L)^2``
    (= ``rho_w/2 (u / (Cd a_L))^2``).

    Written in arithmetic (no branch) so that numpy broadcasts it and numba compiles it alike.

    Parameters
    ----------
    u : float or ndarray
        Flow the face sweeps [m^3/s], >= 0.
    q_L : float or ndarray
        The hole's capacity [m^3/s], >= 0.
    rho_w, g, h : float or ndarray
        Water density [kg/m^3], gravity [m/s^2], head [m].
    h_f : float or ndarray
        Friction head of the rising main at the delivered flow [m].

    Examples
    --------
    >>> float(face_pressure(1.0, 0.0, 1000.0, 10.0, 3.0, 1.0))  # no hole: head + friction
    40000.0
    >>> float(face_pressure(0.5, 1.0, 1000.0, 10.0, 3.0, 1.0))  # below the hole's capacity
    7500.0
    """
    delivering = np.maximum(np.sign(np.maximum(u - q_L, 0.0)), 1.0 - np.sign(q_L))
    through_hole = np.minimum(u, q_L) / np.maximum(q_L, 1e-300)
    return rho_w * g * (h * np.maximum(through_hole * through_hole, delivering) + h_f * delivering)
