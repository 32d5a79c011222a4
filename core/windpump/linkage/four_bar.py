"""The seed's four-bar: its loop, its two assemblies (branches) and their compass construction.

Link 1 (the input, length r1) turns about the origin O; link 2 (the coupler) joins its tip A to B;
link 3 (the output) joins B to the fixed pivot D = r6 (cos phi6, sin phi6). The loop reads
R1 + R2 - R3 - R6 = 0 [1]_, two equations in theta2 and theta3 for a given theta1.

References
----------
.. [1] "Newton-Raphson Method: Application", blog post of 26 January 2013 (the project's second
   seed): loop 1 of its double-loop mechanism.
"""

from __future__ import annotations

import math

from . import _checks as check
from .newton import TOL, solve_loop
from .vectors import Loop, Vector


def four_bar_loop(r1: float, r2: float, r3: float, r6: float, phi6: float = 0.0) -> Loop:
    """The seed's four-bar loop R1 + R2 - R3 - R6 = 0: input theta1, unknowns theta2, theta3.

    Parameters
    ----------
    r1, r2, r3, r6 : float
        Input, coupler, output and ground link lengths [m], from 1e-100 to 1e100.
    phi6 : float, default 0
        Angle of the ground link from O to the output pivot D [rad].

    Returns
    -------
    tuple of Vector
        The loop, with the names ``"theta1"``, ``"theta2"``, ``"theta3"``.

    Examples
    --------
    >>> [vector.label for vector in four_bar_loop(1.0, 3.0, 2.5, 3.0)]
    ['r1', 'r2', 'r3', 'ground']
    """
    r1, r2, r3, r6 = check.link_lengths(r1=r1, r2=r2, r3=r3, r6=r6)
    return four_bar_vectors(
        r1, r2, r3, r6, check.angle("phi6", phi6), ("theta1", "theta2", "theta3")
    )


def four_bar_vectors(
    r_in: float,
    r_coupler: float,
    r_out: float,
    r_ground: float,
    phi_ground: float,
    names: tuple[str, str, str],
    offset: float = 0.0,
) -> Loop:
    """A four-bar loop with its angles named ``names``; arguments are not checked.

    Parameters
    ----------
    r_in, r_coupler, r_out, r_ground : float
        Input, coupler, output and ground link lengths [m].
    phi_ground : float
        Angle of the ground link [rad].
    names : (str, str, str)
        Names of the input, coupler and output angles; the labels follow them (theta3 -> r3).
    offset : float
        Added to the input's named angle [rad] (link 3's second arm of a Watt six-bar).

    Returns
    -------
    tuple of Vector
        ``r_in e(in + offset) + r_coupler e(coupler) - r_out e(out) - r_ground e(phi_ground)``.
    """
    theta_in, theta_coupler, theta_out = names
    labels = [f"r{name[5:]}" for name in names] + ["ground"]
    return (
        Vector(r_in, theta_in, offset=offset, label=labels[0]),
        Vector(r_coupler, theta_coupler, label=labels[1]),
        Vector(r_out, theta_out, sign=-1, label=labels[2]),
        Vector(r_ground, phi_ground, sign=-1, label=labels[3]),
    )


def four_bar(
    r1: float,
    r2: float,
    r3: float,
    r6: float,
    theta1: float,
    phi6: float = 0.0,
    guess: tuple[float, float] | None = None,
    tol: float = TOL,
) -> tuple[float, float]:
    """Coupler and output angles (theta2, theta3) of a four-bar for input angle theta1 [rad].

    Solves the seed's loop equations by Newton-Raphson::

        r1 cos theta1 + r2 cos theta2 - r3 cos theta3 - r6 cos phi6 = 0
        r1 sin theta1 + r2 sin theta2 - r3 sin theta3 - r6 sin phi6 = 0

    Parameters
    ----------
    r1, r2, r3, r6 : float
        Input, coupler, output and ground link lengths [m], from 1e-100 to 1e100.
    theta1 : float
        Input angle [rad].
    phi6 : float, default 0
        Angle of the ground link from O to the output pivot D [rad].
    guess : (float, float), optional
        Starting (theta2, theta3) [rad]; it selects the assembly: Newton-Raphson keeps the sign
        of sin(theta3 - theta2). By default ``branch_guess(..., branch=+1)``, the compass
        construction with the joint B to the left of the line from A to D.
    tol : float
        Newton-Raphson's step tolerance [rad], > 0 and <= 0.1.

    Returns
    -------
    theta2 : float
        The angle of link 2, in [0, 2 pi) [rad].
    theta3 : float
        The angle of link 3, in [0, 2 pi) [rad].

    Raises
    ------
    NoClosure
        The links cannot meet at this theta1, or it is a dead centre, or no convergence.

    Examples
    --------
    >>> theta2, theta3 = four_bar(1.0, 3.0, 2.5, 3.0, theta1=1.0)  # a crank-rocker
    >>> round(theta2, 6), round(theta3, 6)
    (0.585642, 1.554646)
    >>> theta2, theta3 = four_bar(1.0, 3.0, 2.5, 3.0, theta1=1.0, guess=(5.5, 4.0))  # mirror
    >>> round(theta2, 6), round(theta3, 6)
    (5.038298, 4.069294)
    """
    r1, r2, r3, r6 = check.link_lengths(r1=r1, r2=r2, r3=r3, r6=r6)
    theta1, phi6 = check.angle("theta1", theta1), check.angle("phi6", phi6)
    if guess is None:
        guess = branch_guess(r1, r2, r3, r6, theta1, phi6, branch=1)
    theta2, theta3 = check.pair("guess", guess)
    closed = solve_loop(
        four_bar_loop(r1, r2, r3, r6, phi6),
        {"theta1": theta1},
        {"theta2": theta2, "theta3": theta3},
        tol,
    )
    return check.wrap(closed["theta2"]), check.wrap(closed["theta3"])


def branch_guess(
    r1: float,
    r2: float,
    r3: float,
    r6: float,
    theta1: float,
    phi6: float = 0.0,
    branch: int = 1,
) -> tuple[float, float]:
    """A starting (theta2, theta3) on one branch of a four-bar, drawn as with compasses [rad].

    B is put where the circle of radius r2 about the input's tip A meets the circle of radius r3
    about the output pivot D (the cosine rule in triangle ABD), on the left of the line from A to
    D for ``branch=+1`` and on its right for ``-1`` (see :func:`four_bar_branch`). Where the circles
    do not meet, B is put on the line: Newton-Raphson then says why the loop cannot close.

    Parameters
    ----------
    r1, r2, r3, r6 : float
        Input, coupler, output and ground link lengths [m], from 1e-100 to 1e100.
    theta1 : float
        Input angle [rad].
    phi6 : float, default 0
        Angle of the ground link [rad].
    branch : {+1, -1}
        The assembly.

    Returns
    -------
    theta2 : float
        The angle of link 2 [rad], exact where the circles meet.
    theta3 : float
        The angle of link 3 [rad], exact where the circles meet.

    Examples
    --------
    >>> [round(angle, 3) for angle in branch_guess(1.0, 3.0, 2.5, 3.0, theta1=1.0)]
    [0.586, 1.555]
    >>> [round(angle, 3) for angle in branch_guess(1.0, 3.0, 2.5, 3.0, 1.0, branch=-1)]
    [-1.245, -2.214]
    """
    r1, r2, r3, r6 = check.link_lengths(r1=r1, r2=r2, r3=r3, r6=r6)
    theta1, phi6 = check.angle("theta1", theta1), check.angle("phi6", phi6)
    branch = check.branch("branch", branch)
    ax, ay = r1 * math.cos(theta1), r1 * math.sin(theta1)
    dx, dy = r6 * math.cos(phi6), r6 * math.sin(phi6)
    psi = math.atan2(dy - ay, dx - ax)  # direction from A to D
    alpha = included_angle(r2, math.hypot(dx - ax, dy - ay), r3)  # the angle DAB
    theta2 = psi + branch * alpha
    bx, by = ax + r2 * math.cos(theta2), ay + r2 * math.sin(theta2)
    return theta2, math.atan2(by - dy, bx - dx)


def included_angle(a: float, b: float, opposite: float) -> float:
    """The angle between sides a and b of a triangle, by the cosine rule [rad].

    Clamped to [0, pi] where the sides cannot make a triangle; pi/2 where a or b is too small
    to divide by. Products, not powers: a large side overflows to inf, never to an error.

    Parameters
    ----------
    a, b : float
        The sides that meet at the angle [m].
    opposite : float
        The side opposite it [m].

    Returns
    -------
    float
        The angle, in [0, pi] [rad].

    Examples
    --------
    >>> round(math.degrees(included_angle(3.0, 4.0, 5.0)), 9)
    90.0
    """
    denominator = 2 * a * b
    if not denominator > 0:
        return math.pi / 2
    cosine = (a * a + b * b - opposite * opposite) / denominator
    return math.acos(min(1.0, max(-1.0, cosine)))


def four_bar_branch(theta2: float, theta3: float) -> int:
    """Which assembly a four-bar is in: +1 when B is left of the line from A to D, -1 right.

    Parameters
    ----------
    theta2, theta3 : float
        Coupler and output angles [rad].

    Returns
    -------
    int
        The sign of sin(theta3 - theta2), the sine of the angle from the coupler to the output
        link; 0 at a dead centre (coupler and output in line), where the branches meet.

    Examples
    --------
    >>> four_bar_branch(0.585642, 1.554646), four_bar_branch(5.038298, 4.069294)
    (1, -1)
    """
    theta2, theta3 = check.angle("theta2", theta2), check.angle("theta3", theta3)
    return check.sign(math.sin(theta3 - theta2))
