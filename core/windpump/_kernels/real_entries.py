"""The real machine's typed entry points in the kernels: each a stub that resolves, when compiled,
on the type of the machine's ``real`` field (the ideal machine's expression for None, the real
machine's for a :class:`~.model.Real`), the rows' layout, and the helper that registers them.
"""

from __future__ import annotations

import functools
import typing

from numba import types
from numba.extending import overload

from ..model import equations
from .jit import OPTIONS, kernel

JIT_OPTIONS: typing.Any = OPTIONS  # (numba's stubs type the options narrower than it takes)

lever_arm_slope = kernel(equations.lever_arm_slope)  # (d^2x/dphi^2)/R [-]
delivered_flow = kernel(equations.delivered_flow)  # max(u - q_L, 0) [m^3/s]
face_pressure = kernel(equations.face_pressure)  # [Pa]
arm_squared_integral = kernel(equations.lever_arm_squared_integral)  # [rad]

ROW = 21  # a stage's row: the inertia ratio j, |lever arm| of each cylinder's delivering face, C
# (C's first part; the other two in columns 16 and 17: :data:`C_PARTS`), (at the last node) the
# integrals of j - 1 and Lambda over the sub-step (:func:`time_frozen`), and what the ANGLE
# domain's rates take of j and the arms (:func:`_row_extras`, columns 10 to 15), and (at the
# last node) the integral of C over the sub-step less C at its start times its length (18-20)
C_PARTS = (7, 16, 17)  # the rows' columns of the frozen friction's C (:func:`_frozen_parts`)
M_PARTS = (18, 19, 20)  # the last row's columns of C's moment over the sub-step
WORKS = 4  # the real machine's quadratures: shaft work, leaked volume, friction, excess load


def inertia_ratio(theta, machine):
    """J(theta) / I_eff [-]: 1 for the ideal machine."""


def conservative_work(theta, segment, machine):
    """Lambda: the conservative torques' work since the segment began, per unit I_eff
    [J/(kg m^2)]: the static head's (:func:`~.model.load_work`) for a tight piston, plus the
    weights' ``m_r g sum (x_c - x_c(start))``."""


def conservative_torque(theta, segment, machine):
    """The conservative torques on the crank [N m]: the static head's (negative) for a tight
    piston, plus the weights' ``m_r g sum x_c'``."""


def torque_at_rest(theta, segment, machine):
    """The torques on a resting crank but the windmill's [N m]: the static head's (negative) for a
    tight piston, none through a leak hole (the water flows back through it), plus the weights'."""


def transmitted(torque, machine):
    """What the chain passes to the crank of a torque reflected to it, eta_t times it [N m]."""


def zero_work(machine):
    """The quadratures at the start: 0.0 (shaft work), or a tuple of WORKS zeros."""


def angle_rates(x0, t, aux, row, machine):
    """The ANGLE domain's rates (dx0, dt, dt, dW) per radian; x0 = e - Lambda, aux = Lambda."""


def time_rates(t, theta, theta_dot, row, segment, machine):
    """The TIME domain's rates (theta_dot, theta_ddot, 0, dW) per second; ``row`` is scratch."""


def fill_row(row, theta, segment, machine):
    """Write a stage's row (ROW numbers) for the real machine; nothing for the ideal one."""


def advance_work(q, h, a, c, d, e, f):
    """A step's 5th-order update of the work quadratures, q + h (b . stages)."""


def dense_work(h, a, c, d, e, f, g):
    """The continuous extension's term of the work quadratures, h (d . stages)."""


def work_at(sigma, start, end, rate_start, rate_end, dense, h):
    """The work quadratures at s + sigma h inside a step (:func:`~.dopri5.dense_value`)."""


def write_work(out, row, n, W):
    """Write the work quadratures into ``out[row:, n]``."""


def _ideal(real) -> bool:
    return isinstance(real, types.NoneType)


def _entry(function):
    """Register ``function``'s overload: ``ideal(...)`` for a None ``real``, else ``actual``."""

    def register(ideal, actual, on_machine=True, inline="never"):
        ideal, actual = (getattr(f, "py_func", f) for f in (ideal, actual))  # a kernel's source

        @functools.wraps(function)  # numba checks the typer's signature against the stub's
        def typer(*args):
            machine = args[-1]
            real = machine.types[machine.fields.index("real")] if on_machine else machine
            return ideal if _ideal(real) else actual

        overload(function, jit_options=JIT_OPTIONS, inline=inline)(typer)

    return register


# -- The real machine's expressions. ------------------------------------------------------------
