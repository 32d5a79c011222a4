"""The pump's slider-crank as a vector loop: Eq. (1) of the wind-pump paper by Newton-Raphson.

The crank R turns at theta from the cylinder axis (x), the rod L at phi, and the piston pin slides
at s along the axis: ``R e(theta) + L e(phi) - s e(0) = 0``, unknowns phi and s. The seed notes
that Newton-Raphson closes slider-cranks as it closes four-bars [1]_.

References
----------
.. [1] "Newton-Raphson Method: Application", blog post of 26 January 2013 (the project's second
   seed): "The Newton-Raphson method can be used on any closed-loop mechanisms, including
   non-inverted and inverted slider-crank mechanisms."
"""

from __future__ import annotations

import math
import typing

import numpy as np

from . import _checks as check
from .newton import Closure, solve_loop
from .vectors import Loop, Vector, joints


def slider_crank_loop(R: float, L: float) -> Loop:
    """The pump's slider-crank as a loop: crank R at theta, rod L at phi, piston pin at s.

    Parameters
    ----------
    R, L : float
        Crank radius and rod length [m], from 1e-100 to 1e100.

    Returns
    -------
    tuple of Vector
        ``R e(theta) + L e(phi) - s e(0) = 0``: unknowns the rod's angle phi and the pin's
        distance s from the crank centre, the cylinder axis along x and theta measured from it
        (from TDC).

    Examples
    --------
    >>> [vector.label for vector in slider_crank_loop(0.04, 0.15)]
    ['crank R', 'rod L', 'piston']
    """
    R, L = check.link_lengths(R=R, L=L)
    return (
        Vector(R, "theta", label="crank R"),
        Vector(L, "phi", label="rod L"),
        Vector("s", 0.0, sign=-1, label="piston"),
    )


class SliderCrankPose(typing.NamedTuple):
    """The slider-crank closed at one crank angle (see :func:`slider_crank_pose`)."""

    x: float
    """Piston position from TDC [m] (Eq. 1)."""
    theta_c: float
    """Rod angle to the cylinder axis [rad]."""
    joints: np.ndarray
    """Crank centre, crank pin and piston pin [m], the cylinder axis along +x, shape (3, 2)."""
    closure: Closure
    """The Newton-Raphson solution (iterates, residuals)."""


def slider_crank_pose(
    theta: float, R: float, L: float, guess: tuple[float, float] | None = None
) -> SliderCrankPose:
    """The slider-crank at crank angle theta, closed once.

    Parameters
    ----------
    theta : float
        Crank angle from TDC [rad].
    R, L : float
        Crank radius and rod length [m], from 1e-100 to 1e100 (L < R closes only where
        ``R |sin theta| <= L``).
    guess : (float, float), optional
        Starting (phi, s) [rad, m]; by default (0, L + R), the piston beyond the crank.

    Returns
    -------
    SliderCrankPose
        x, theta_c, the joints to draw it with and the Newton-Raphson history.

    Raises
    ------
    NoClosure
        Where a rod shorter than the crank cannot reach the axis.

    Examples
    --------
    >>> pose = slider_crank_pose(math.pi / 2, R=0.04, L=0.15)
    >>> round(pose.x, 6), pose.joints.shape
    (0.045432, (3, 2))
    """
    theta = check.angle("theta", theta)
    loop = slider_crank_loop(R, L)
    R, L = float(loop[0].length), float(loop[1].length)
    phi, s = (0.0, L + R) if guess is None else check.pair("guess", guess, "rad, m")
    closed = solve_loop(loop, {"theta": theta}, {"phi": phi, "s": s})
    return SliderCrankPose(
        x=L + R - closed["s"],
        theta_c=-math.remainder(closed["phi"], 2 * math.pi),
        joints=joints(loop, closed.values)[:3],
        closure=closed,
    )


def slider_crank(
    theta: float, R: float, L: float, guess: tuple[float, float] | None = None
) -> tuple[float, float]:
    """Piston position from TDC x [m] and rod angle theta_c [rad] by Newton-Raphson.

    The loop of :func:`slider_crank_loop` gives ``x = L + R - s`` and ``theta_c = -phi``, the
    rod's angle to the cylinder axis: on the usual branch (piston beyond the crank) this is Eq. (1)
    of the wind-pump paper and ``sin theta_c = sin theta / (L/R)``.

    Parameters
    ----------
    theta : float
        Crank angle from TDC [rad].
    R, L : float
        Crank radius and rod length [m], from 1e-100 to 1e100 (L < R closes only where
        ``R |sin theta| <= L``).
    guess : (float, float), optional
        Starting (phi, s) [rad, m]; by default (0, L + R), the piston beyond the crank.

    Returns
    -------
    x : float
        Piston position from TDC [m].
    theta_c : float
        Rod angle to the cylinder axis [rad].

    Examples
    --------
    >>> x, theta_c = slider_crank(math.pi / 2, R=0.04, L=0.15)
    >>> round(x, 6), round(math.degrees(theta_c), 4)
    (0.045432, 15.466)
    """
    pose = slider_crank_pose(theta, R, L, guess)
    return pose.x, pose.theta_c
