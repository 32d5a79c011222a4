"""The model the kernels integrate: Eq. (1), the loads of every delivering face, Eq. (11) with T_0.

Eq. (1), its derivative (the lever arm) and Eq. (11) are :mod:`.equations`' functions, compiled:
the numpy side (:mod:`windpump.model.kinematics`, :mod:`windpump.model.windmill`) calls the same definitions.
What is only here (which faces deliver in a segment, their sums, the closed-form work) has a numpy
twin in :mod:`windpump.model.kinematics` and :mod:`windpump.model.loads`; tests/kernels/test_kernel_twins.py holds
each pair together to 1e-12.

Crank angles are split into *segments* of width ``pi / cylinders`` between consecutive switches:
cylinder k sees ``phi = theta - 2 pi k / n`` (2k segments behind cylinder 0), its top face delivers
while ``pi < phi mod 2 pi < 2 pi`` and, double-acting, its bottom face delivers during the other
half. Inside a segment the set of delivering faces is fixed, so the load is smooth there.
"""

from __future__ import annotations

import math
import typing

from ..model import equations
from .jit import kernel
from .rotor import RotorTable, wheel_torque
from .wind import Wind


class Machine(typing.NamedTuple):
    """The design as the kernels see it, every parameter by name (SI units)."""

    R_dagger: float  # sprocket ratio R1/R0 [-]
    T_m: float  # peak windmill torque [N m]
    T_0: float  # windmill torque at rest [N m]
    omega_m: float  # windmill speed of the peak [rad/s]
    inv_I_eff: float  # 1 / inertia reflected to the crank [1/(kg m^2)]
    load_torque: float  # rho_w g h A R [N m]
    L_over_R: float  # rod / crank [-]
    cylinders: int  # n, 1 to 6
    double_acting: bool  # both faces of every piston deliver
    wind: Wind | None  # a wind record, or None: V = V_ref throughout
    real: Real | None  # the real machine's terms (:mod:`.real`), or None: the ideal machine
    rotor: RotorTable | None  # a rotor's C_Q table (:mod:`.rotor`), or None: Eq. (11)


class Real(typing.NamedTuple):
    """The real machine's terms as the kernels see them (SI units); None in :class:`Machine` for
    the paper's ideal machine, which then compiles without them."""

    eta_t: float  # transmission efficiency [-]
    weight_torque: float  # m_r g R: the weights' torque per unit lever arm [N m]
    mass_ratio: float  # m_r R^2 / I_eff: the masses' inertia per unit lever arm squared [-]
    AR: float  # A R: a face's swept flow per unit lever arm and crank speed [m^3/rad]
    q_L: float  # the leak hole's capacity [m^3/s]; 0: a tight piston
    friction: float  # the rising main's h_f / Q^2 [s^2/m^5]
    rho_g: float  # rho_w g [N/m^3]
    h: float  # head [m]


TOP, BOTTOM, NEITHER = 1, -1, 0  # which face of a cylinder delivers in a segment


piston_over_R = kernel(equations.piston_over_R)  # x/R, Eq. (1) [-]
lever_arm = kernel(equations.lever_arm)  # (dx/dphi)/R = sin(phi + theta_c)/cos(theta_c) [-]


@kernel
def delivering_face(segment, k, machine):
    """TOP, BOTTOM or NEITHER: the face of cylinder k that delivers in segment ``segment``.

    Cylinder k is 2k segments behind cylinder 0; it exhausts (top face) in the second half of
    its own revolution of 2n segments.
    """
    n = machine.cylinders
    if (segment - 2 * k) % (2 * n) >= n:
        return TOP
    return BOTTOM if machine.double_acting else NEITHER


@kernel
def phase(k, machine):
    """Cylinder k's lag behind cylinder 0, 2 pi k / n [rad]."""
    return 2.0 * math.pi * k / machine.cylinders


@kernel
def load_on_crank(theta, segment, machine):
    """Load torque on the crank, the sum over delivering faces of the load term of Eq. (12) [N m].

    A top face pushes water up while x falls (lever arm < 0); a bottom face while x rises (> 0):
    either way it brakes the crank by rho_w g h A R |lever arm| (the absolute value also keeps the
    sign at a dead centre, where the lever arm is a round-off away from 0).
    """
    total = 0.0
    for k in range(machine.cylinders):
        if delivering_face(segment, k, machine) != NEITHER:
            total += abs(lever_arm(theta - phase(k, machine), machine.L_over_R))
    return -machine.load_torque * total


@kernel
def segment_start(segment, machine):
    """The crank angle where a segment begins, segment pi / n [rad] (one formula everywhere)."""
    return segment * (math.pi / machine.cylinders)


@kernel
def load_work(theta, segment, machine):
    """Work of the load since the segment began, per unit inertia, Lambda [J/(kg m^2)].

    The integral of :func:`load_on_crank` over theta, in closed form from Eq. (1): each delivering
    face adds ``+-rho_w g h A R (x/R - x_start/R) / I_eff``, i.e. ``-rho_w g h`` times the volume
    it delivered, over I_eff.
    """
    start = segment_start(segment, machine)
    total = 0.0
    for k in range(machine.cylinders):
        face = delivering_face(segment, k, machine)
        if face != NEITHER:
            lag = phase(k, machine)
            total += face * (
                piston_over_R(theta - lag, machine.L_over_R)
                - piston_over_R(start - lag, machine.L_over_R)
            )
    return machine.load_torque * machine.inv_I_eff * total


@kernel
def windmill_torque_on_crank(theta_dot, s, machine):
    """R+ T(R+ theta_dot) [N m] in a wind s = V/V_ref: T = s^2 T_0 + (T_m - T_0) x (2 s - x),
    x = omega/omega_m, or a rotor's ``1/2 rho_air pi r^3 V_s^2 C_Q(lambda)`` (:mod:`.rotor`).

    The curve T_0 + (T_m - T_0) x (2 - x) (Eq. 11 at T_0 = 0) scaled by similarity, torques by
    s^2 and speeds by s; at s = 1 it is that curve to the last bit. Reflected to the crank.
    """
    omega = machine.R_dagger * theta_dot
    return machine.R_dagger * wheel_torque(
        omega, s, machine.rotor, machine.T_m, machine.T_0, machine.omega_m
    )


@kernel
def face_strokes(phi, face, L_over_R):
    """Strokes one face has delivered at its own angle phi, counted from phi = 0 [-].

    Continuous and never decreasing: the top face adds ``(2R - x)/(2R)`` over pi < phi < 2 pi,
    the bottom face ``x/(2R)`` over 0 < phi < pi (Eq. 1); one stroke volume 2 R A per revolution.
    """
    revolutions = math.floor(phi / (2.0 * math.pi))
    within = phi - 2.0 * math.pi * revolutions
    x = piston_over_R(within, L_over_R)
    if face == TOP:
        return revolutions + (0.0 if within <= math.pi else 0.5 * (2.0 - x))
    return revolutions + (0.5 * x if within <= math.pi else 1.0)


@kernel
def delivered_strokes(theta, machine):
    """Stroke volumes 2 R A delivered by every face at crank angle theta, counted from 0 [-]."""
    total = 0.0
    for k in range(machine.cylinders):
        lag = phase(k, machine)
        total += face_strokes(theta - lag, TOP, machine.L_over_R) - face_strokes(
            -lag, TOP, machine.L_over_R
        )
        if machine.double_acting:
            total += face_strokes(theta - lag, BOTTOM, machine.L_over_R) - face_strokes(
                -lag, BOTTOM, machine.L_over_R
            )
    return total


@kernel
def flow_factor(theta, segment, machine):
    """The sum of f2 (Eq. 16) over the delivering faces: flow = 2 R A (this) theta_dot [-]."""
    total = 0.0
    for k in range(machine.cylinders):
        if delivering_face(segment, k, machine) != NEITHER:
            total += 0.5 * abs(lever_arm(theta - phase(k, machine), machine.L_over_R))
    return total


@kernel
def segment_at(theta, machine):
    """The segment holding theta (a switch belongs to the segment it starts)."""
    return int(math.floor(theta * machine.cylinders / math.pi))
