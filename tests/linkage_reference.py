"""The seed four-bar's assemblies in closed form: the reference the linkage's Newton-Raphson loop
closure (tests/linkage/test_linkage.py) and the Mechanisms tab (tests/app/test_app_mechanisms.py)
are held to."""

from __future__ import annotations

import math

import numpy as np

TWO_PI = 2.0 * math.pi


def half_angle(r1, r2, r3, r6, theta1, phi6=0.0):
    """Both assemblies of the seed's four-bar in closed form, as {branch: (theta2, theta3)}.

    With P = r6 e(phi6) - r1 e(theta1) the loop reads r2 e(theta2) = r3 e(theta3) + P; squaring it
    leaves Px cos theta3 + Py sin theta3 = C, C = (r2^2 - r3^2 - |P|^2) / (2 r3), and t = tan(theta3/2)
    turns that into (C + Px) t^2 - 2 Py t + (C - Px) = 0. Returns {} when the roots are complex.
    """
    px = r6 * math.cos(phi6) - r1 * math.cos(theta1)
    py = r6 * math.sin(phi6) - r1 * math.sin(theta1)
    c = (r2**2 - r3**2 - px**2 - py**2) / (2 * r3)
    a, b, k = c + px, -2 * py, c - px
    disc = b * b - 4 * a * k
    if disc < 0:
        return {}
    q = -0.5 * (b + math.copysign(math.sqrt(disc), b))  # the stable pair of roots q/a and k/q
    solutions = {}
    for theta3 in (2 * math.atan2(q, a), 2 * math.atan2(k, q)):
        theta2 = math.atan2(r3 * math.sin(theta3) + py, r3 * math.cos(theta3) + px)
        branch = int(np.sign(math.sin(theta3 - theta2)))
        solutions[branch] = (theta2 % TWO_PI, theta3 % TWO_PI)
    return solutions
