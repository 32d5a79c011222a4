"""The windmill's torque in a steady wind, whichever curve the design has: the paper's Eq. (11)
with T_0 (scaled by similarity) or a rotor's C_Q table (:mod:`windpump.model.rotor`).

Every numpy-side reader of the windmill's torque (the averaged theory, the loads at rest, a
site's winds, the maps) calls these; the compiled kernels have their twin in
:mod:`windpump._kernels.rotor`. Unchecked: for speeds and winds the model worked out itself.
"""

from __future__ import annotations

import math
import typing

import numpy as np

from .equations import windmill_torque
from .rotor import rotor_torque

if typing.TYPE_CHECKING:
    from .design import Design


def torque_in_wind(design: Design, omega, s=1.0):
    """The windmill's torque T [N m] at its speeds omega [rad/s] >= 0 in the winds
    ``V = s V_ref`` (s >= 0), broadcasting.

    Eq. (11) with T_0 scaled by similarity, ``s^2 T_0 + (T_m - T_0) x (2 s - x)``,
    ``x = omega / omega_m`` (at s = 1 the curve to the last bit); or the rotor's
    ``1/2 rho_air pi r^3 V_s^2 C_Q(omega r / V_s)``, ``V_s = min(s V_ref, V_furl)``.

    Examples
    --------
    >>> from windpump import Design, Rotor
    >>> seed = Design.seed_example()
    >>> float(torque_in_wind(seed, 50.0)), float(torque_in_wind(seed, 100.0, s=2.0))
    (0.6, 2.4)
    >>> wheel = Design.from_rotor(Rotor.multiblade(1.5), V_ref=5.0, **seed.geometry())
    >>> round(float(torque_in_wind(wheel, 0.0, s=2.0) / wheel.T_0), 12)
    4.0
    """
    rotor = design.rotor
    if rotor is None:
        return windmill_torque(np.divide(omega, design.omega_m), s, design.T_m, design.T_0)
    return rotor_torque(rotor, omega, wind_at_rotor(design, s))


def wind_at_rotor(design: Design, s=1.0):
    """The wind the wheel turns in [m/s]: ``s V_ref``, capped at a rotor's V_furl."""
    V = np.multiply(s, design.V_ref)
    rotor = design.rotor
    if rotor is None or rotor.V_furl is None:
        return V
    return np.minimum(V, rotor.V_furl)


def runaway_in_wind(design: Design, s=1.0):
    """The windmill's runaway speed [rad/s] (where its torque falls to 0) in the winds
    ``s V_ref``: ``s`` times :attr:`Design.runaway_speed` for Eq. (11); for a rotor
    ``lambda_runaway V_s / r``, which stops growing above V_furl.

    Examples
    --------
    >>> from windpump import Design
    >>> float(runaway_in_wind(Design.seed_example(), 2.0))
    200.0
    """
    rotor = design.rotor
    if rotor is None:
        return np.multiply(s, design.runaway_speed)
    return rotor.runaway_tsr * wind_at_rotor(design, s) / rotor.radius


def rest_torque_in_wind(design: Design, s=1.0):
    """The windmill's torque at rest [N m] in the winds ``s V_ref``: ``T_0 s^2`` (similarity),
    up to a rotor's furling wind, constant above it.

    Examples
    --------
    >>> from windpump import Design
    >>> float(rest_torque_in_wind(Design.seed_example().replace(T_0=0.2), 2.0))
    0.8
    """
    if design.rotor is None:
        return design.T_0 * np.square(s)
    return torque_in_wind(design, 0.0, s)


def furls_below(design: Design) -> float:
    """The wind scale s = V_furl / V_ref above which the rotor's torque stops growing [-]; inf
    for Eq. (11) and a wheel that never furls."""
    rotor = design.rotor
    if rotor is None or rotor.V_furl is None:
        return math.inf
    return rotor.V_furl / design.V_ref


def steepest_fall(design: Design) -> float:
    """How fast the windmill's torque can fall with its speed at V_ref, ``max |dT/domega|``
    [N m s]: ``2 (T_m - T_0) / omega_m`` for Eq. (11) (its slope at rest, the steepest), and
    ``1/2 rho_air pi r^3 V_s r max |dC_Q/dlambda|`` for a rotor (over its table up to the
    runaway). A step-size scale for the integrator's stiffness."""
    rotor = design.rotor
    if rotor is None:
        return 2.0 * (design.T_m - design.T_0) / design.omega_m
    V_s = float(wind_at_rotor(design))
    return rotor.torque_scale * V_s * rotor.radius * rotor.steepest_cq_slope


def peak_torque(design: Design, s=1.0):
    """The windmill's largest torque over its speeds up to the runaway [N m] in the winds
    ``s V_ref``: T_m s^2 for Eq. (11) (T_0 < T_m), ``1/2 rho_air pi r^3 V_s^2`` times the
    rotor's largest C_Q.

    Examples
    --------
    >>> from windpump import Design
    >>> float(peak_torque(Design.seed_example(), 2.0))
    2.4
    """
    rotor = design.rotor
    if rotor is None:
        return design.T_m * np.square(s)
    return rotor.torque_scale * np.square(wind_at_rotor(design, s)) * rotor.peak_cq
