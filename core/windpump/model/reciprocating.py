"""The reciprocating masses of the real machine: their inertia on the crank and their weight.

Each cylinder's piston, rod and pump rod (mass m_r, ``Design.m_r``) move with the piston,
``x_c(theta)`` of Eq. (1) at the cylinder's own angle. The pump stands vertical with top dead
centre at the top, so x grows downward and (docs/model.rst, "The real machine")

    J(theta) = I_eff + m_r sum_c x_c'^2,      weight torque = + m_r g sum_c x_c',
    potential energy change = - m_r g sum_c (x_c - x_c(theta_0)).

The weights' torque is :func:`windpump.model.loads.weight_torque` (the torque at rest needs it); their
revolution-mean inertia is :func:`windpump.averaging.revolution.reciprocating_inertia`.

The compiled integrator keeps its own copy of these sums for speed (``_kernels.real``);
tests/run/test_real_machine.py holds the two together.
"""

from __future__ import annotations

import numpy as np

from . import equations
from .design import Design
from .kinematics import cylinder_angles

__all__ = [
    "crank_inertia",
    "weight_potential",
]


def crank_inertia(design: Design, theta):
    """The inertia on the crank, ``J = I_eff + m_r sum_c x_c'^2`` [kg m^2].

    Parameters
    ----------
    design : Design
    theta : float or array_like
        Crank angle [rad].

    Examples
    --------
    >>> import math
    >>> from windpump import Design
    >>> d = Design.seed_example().replace(m_r=2.0)
    >>> round(float(crank_inertia(d, 3 * math.pi / 2) - d.I_eff), 6)  # x' = -R: m_r R^2
    0.0032
    """
    arms = equations.lever_arm(cylinder_angles(theta, design.cylinders), design.L_over_R)
    return design.I_eff + design.m_r * design.R**2 * np.sum(arms * arms, axis=0)


def weight_potential(design: Design, theta):
    """The reciprocating weights' potential energy from top dead centre, ``-m_r g sum_c x_c``
    [J]: its change over a run is what the weights took from the crank.

    Examples
    --------
    >>> import math
    >>> from windpump import Design
    >>> d = Design.seed_example().replace(m_r=2.0)
    >>> round(float(weight_potential(d, math.pi)), 4)  # bottom dead centre: x = 2R
    -1.5696
    """
    x_over_R = equations.piston_over_R(cylinder_angles(theta, design.cylinders), design.L_over_R)
    return -design.m_r * design.g * design.R * np.sum(x_over_R, axis=0)
