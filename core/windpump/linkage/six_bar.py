"""The seed's double loop as a Watt six-bar: two four-bars in series on a ternary link 3.

Loop 1 is the four-bar O-A-B-D. Link 3 has a second arm r3p at ``theta3 + beta`` about D; it
drives loop 2, ``r3p e(theta3 + beta) + r4 e(theta4) - r5 e(theta5) - r6p e(phi6p) = 0``, whose
output link 5 turns about the fixed pivot E = D + r6p e(phi6p). The seed solves the two loops
one after the other [1]_ (:func:`solve_loops`).

References
----------
.. [1] "Newton-Raphson Method: Application", blog post of 26 January 2013 (the project's second
   seed): "the two loops shown in the figure are in fact two four-bar linkages, we can solve
   them independently".
"""

from __future__ import annotations

from . import _checks as check
from .four_bar import four_bar_loop, four_bar_vectors
from .vectors import Loop


def watt_six_bar_loops(
    r1: float,
    r2: float,
    r3: float,
    r6: float,
    r3p: float,
    r4: float,
    r5: float,
    r6p: float,
    phi6: float = 0.0,
    phi6p: float = 0.0,
    beta: float = 0.0,
) -> list[Loop]:
    """The two loops of a Watt six-bar: input theta1, unknowns theta2, theta3 then theta4, theta5.

    Parameters
    ----------
    r1, r2, r3, r6 : float
        Loop 1's input, coupler, output and ground lengths [m], from 1e-100 to 1e100.
    r3p, r4, r5, r6p : float
        Link 3's second arm, loop 2's coupler, its output link and the ground from D to E [m].
    phi6, phi6p : float, default 0
        Angles of the ground O->D and D->E [rad].
    beta : float, default 0
        The angle between link 3's arms [rad].

    Returns
    -------
    list of two loops
        Loop 2's known angle (theta3) comes from loop 1's solution; draw loop 2 from D
        (``joints(loops[1], values, origin=D)``).

    Examples
    --------
    >>> first, second = watt_six_bar_loops(1.0, 3.0, 2.5, 3.0, 1.5, 2.5, 2.0, 2.5, beta=0.4)
    >>> [vector.label for vector in second], second[0].offset
    (['r3', 'r4', 'r5', 'ground'], 0.4)
    """
    r3p, r4, r5, r6p = check.link_lengths(r3p=r3p, r4=r4, r5=r5, r6p=r6p)
    first = four_bar_loop(r1, r2, r3, r6, phi6)
    phi6p, beta = check.angle("phi6p", phi6p), check.angle("beta", beta)
    second = four_bar_vectors(r3p, r4, r5, r6p, phi6p, ("theta3", "theta4", "theta5"), beta)
    return [first, second]
