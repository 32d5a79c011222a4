"""Slider-crank kinematics of the pump (paper Eqs. 1, 2, 16; docs/model.rst, "Kinematics").

The crank angle ``theta`` is measured from top dead centre (TDC). The cylinder takes water in on
0 < theta mod 2 pi < pi and exhausts it on pi < theta mod 2 pi < 2 pi. All functions accept numpy
arrays and broadcast. Eq. (1) and its derivative are the functions the compiled kernels run
(:mod:`windpump.model.equations`, called here with arrays).

With several cylinders (``Design.cylinders = n``) cylinder k sees ``theta - 2 pi k / n``;
:func:`swept_flows` gives the flow every delivering face sweeps, :func:`face_flows` what it
delivers (less a leak hole's flow).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import ParameterError
from ..validation import finite_array, flag, positive, real_array, rod_ratio, whole
from .design import MAX_CYLINDERS
from .equations import delivered_flow as _delivered_flow
from .equations import lever_arm as _lever
from .equations import piston_over_R as _x_over_R


def _exhaust_strokes(theta, ratio):
    revolutions = np.floor(theta / (2 * np.pi))
    phi = theta - 2 * np.pi * revolutions
    return revolutions + np.where(phi <= np.pi, 0.0, 0.5 * (2.0 - _x_over_R(phi, ratio)))


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
    return R * _x_over_R(finite_array("theta", theta, "rad"), ratio)


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
    return _lever(finite_array("theta", theta, "rad"), rod_ratio(L_over_R))


def f2(theta, L_over_R: float):
    """Kinematic function f2 of Eq. (16): the pumped-volume rate per unit crank speed [-].

    ``dV/dt = 2 R A f2(theta) theta_dot``: ``f2 = -(dx/dtheta)/(2R) >= 0`` while exhausting and 0 while
    taking water in, so one revolution delivers one stroke volume 2RA. (The paper writes
    ``xdot = 2 R theta_dot f2``; docs/model.rst, "Sign conventions", explains the sign.)

    Examples
    --------
    >>> import math
    >>> float(f2(3 * math.pi / 2, 3.75)), float(f2(math.pi / 2, 3.75))
    (0.5, 0.0)
    """
    theta = finite_array("theta", theta, "rad")
    exhaust = np.mod(theta, 2 * np.pi) > np.pi
    return np.where(exhaust, -0.5 * _lever(theta, rod_ratio(L_over_R)), 0.0)


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
    return _exhaust_strokes(finite_array("theta", theta, "rad"), rod_ratio(L_over_R))


def delivering_faces(segment, cylinders: int, double_acting: bool):
    """Which face of each cylinder delivers in a segment of crank angle, by sign [-].

    Segment j is ``j pi/n <= theta <= (j + 1) pi/n`` (n = cylinders; the switches lie between
    segments). Returns an int array of shape ``segment.shape + (n,)``: +1 where cylinder k's top
    face delivers (``pi < theta - 2 pi k/n < 2 pi`` modulo 2 pi), -1 where its bottom face does
    (double-acting only, the other half), 0 where neither.

    Raises
    ------
    ParameterError
        Naming ``segment`` (not whole numbers from -2^53 to 2^53), ``cylinders`` (not a whole
        number from 1 to 6) or ``double_acting`` (not a bool).

    Examples
    --------
    >>> delivering_faces([0, 1], 1, False).tolist()  # intake, then exhaust
    [[0], [1]]
    >>> delivering_faces(0, 2, True).tolist()  # cylinder 1 is half a turn behind
    [-1, 1]
    """
    cylinders = whole("cylinders", cylinders, 1, MAX_CYLINDERS)
    double_acting = flag("double_acting", double_acting)
    allowed = f"whole numbers from {-(2**53)} to {2**53}"
    values = real_array("segment", segment)
    with np.errstate(invalid="ignore"):
        bad = ~(np.isfinite(values) & (np.abs(values) <= 2**53) & (values == np.round(values)))
    if bad.any():
        raise ParameterError("segment", float(values.flat[np.flatnonzero(bad)[0]]), allowed)
    segment = values.astype(np.int64)[..., None]
    behind = np.mod(segment - 2 * np.arange(cylinders), 2 * cylinders)
    return np.where(behind >= cylinders, 1, -1 if double_acting else 0)


def cylinder_angles(theta, cylinders: int) -> np.ndarray:
    """Each cylinder's own crank angle [rad], shape ``(cylinders,) + theta.shape``: cylinder k
    runs ``2 pi k/n`` behind the first (n = cylinders), as the kernels' faces have it.

    Examples
    --------
    >>> import math
    >>> (cylinder_angles(math.pi, 2) / math.pi).tolist()
    [1.0, 0.0]
    """
    lags = 2 * math.pi * np.arange(cylinders) / cylinders
    return np.asarray(theta)[None, ...] - lags.reshape((cylinders,) + (1,) * np.ndim(theta))


def swept_flows(theta, theta_dot, design):
    """Flow every delivering face sweeps, ``u = A |dx/dtheta| theta_dot`` [m^3/s], shape
    ``(faces, samples)``; 0 on a face that does not deliver.

    Row ``2k`` is cylinder k's top face (while ``pi < theta - 2 pi k/n < 2 pi`` modulo 2 pi),
    row ``2k + 1`` its bottom face (double-acting only: the other half, zero otherwise); Eq. (16)
    face by face. A tight piston delivers all of it (:func:`face_flows`).

    Parameters
    ----------
    theta : array_like
        Crank angles from TDC [rad].
    theta_dot : array_like
        Crank speeds [rad/s], broadcasting with theta.
    design : Design

    Examples
    --------
    >>> import math
    >>> from windpump import Design
    >>> d = Design.seed_example()
    >>> round(float(swept_flows([3 * math.pi / 2], [2.0], d)[0, 0] / (d.A * d.R)), 12)
    2.0
    """
    theta = finite_array("theta", theta, "rad")
    theta_dot = finite_array("theta_dot", theta_dot, "rad/s")
    return design.A * design.R * face_levers(theta, design) * theta_dot


def face_levers(theta, design) -> np.ndarray:
    """``|dx/dtheta| / R`` [-] of every face while it delivers, 0 while it does not, shape
    ``(2 cylinders,) + theta.shape`` (rows as :func:`swept_flows`).

    Examples
    --------
    >>> import math
    >>> from windpump import Design
    >>> face_levers(3 * math.pi / 2, Design.seed_example()).tolist()
    [1.0, 0.0]
    """
    theta = np.asarray(theta, dtype=float)
    n = design.cylinders
    levers = np.zeros((2 * n,) + theta.shape)
    for k, own in enumerate(cylinder_angles(theta, n)):
        phi = np.mod(own, 2 * math.pi)
        lever = np.abs(_lever(phi, design.L_over_R))
        levers[2 * k] = np.where(phi > math.pi, lever, 0.0)
        if design.double_acting:
            levers[2 * k + 1] = np.where(phi <= math.pi, lever, 0.0)
    return levers


def face_flows(theta, theta_dot, design):
    """Flow every face of every cylinder delivers into the rising main [m^3/s], shape
    ``(faces, samples)``.

    What the face sweeps (:func:`swept_flows`, Eq. 16 face by face) less what leaks back through
    its hole, ``q = max(u - q_L, 0)`` (``Design.leak_capacity``; a tight piston, d_leak = 0,
    delivers all it sweeps). Row ``2k`` is cylinder k's top face, row ``2k + 1`` its bottom face
    (double-acting only, zero otherwise). Their sum is the pump's flow Q.

    Parameters
    ----------
    theta : array_like
        Crank angles from TDC [rad].
    theta_dot : array_like
        Crank speeds [rad/s], >= 0 (the crank never turns backwards), broadcasting with theta.
    design : Design

    Examples
    --------
    >>> import math
    >>> from windpump import Design
    >>> d = Design.seed_example().replace(cylinders=2)
    >>> flows = face_flows([3 * math.pi / 2], [1.0], d)  # cylinder 0 exhausts at mid-stroke
    >>> [round(float(q / (d.A * d.R)), 6) for q in flows[:, 0]]
    [1.0, 0.0, 0.0, 0.0]
    >>> holed = d.replace(d_leak=0.004)  # its hole passes up to 0.106 L/s
    >>> float(face_flows([3 * math.pi / 2], [1.0], holed)[0, 0])  # slow: all leaks back
    0.0
    """
    return _delivered_flow(swept_flows(theta, theta_dot, design), design.leak_capacity)
