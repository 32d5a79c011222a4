"""The windmill's torque as the kernels see it: the paper's Eq. (11) with T_0, or a rotor's C_Q
table (:class:`windpump.Rotor`).

A design with the paper's curve passes ``rotor=None``; these functions are numba overloads that
resolve on the argument's type when compiled, as :mod:`.wind` does: the Eq. (11) run carries no
table code at all (its numbers and speed stay as they were) and a rotor's run compiles its own
specialisation. The numpy twin is :mod:`windpump.model.rotor` (scipy's PCHIP);
tests/kernels/test_rotor_kernel.py holds the two together.
"""

from __future__ import annotations

import math
import typing

from numba import carray, types
from numba.extending import intrinsic, overload

from ..model import equations
from .jit import inline_kernel, kernel
from .wind import JIT_OPTIONS


class RotorTable(typing.NamedTuple):
    """A rotor's torque curve (SI units): T = torque_scale V_s^2 C_Q(omega r / V_s).

    The table itself is not here but at ``address``: n + 1 tip-speed ratios from 0, then the
    PCHIP's cubic on each interval as n numbers each of c3, c2, c1, c0 (``c3 x^3 + c2 x^2 + c1
    x + c0``, x = lambda - tsr[i]), float64 in a buffer the caller keeps alive for the run
    (:func:`windpump.run.machine.kernel_rotor`). Numbers only in the machine: an array in it is
    one more reference, counted atomically at every call that passes the machine (a rotor's
    run took 4 times Eq. 11's), and a tuple holding the table is copied at each (2 times, with
    32 intervals).
    """

    address: int  # where the table's 5 n + 1 numbers start
    intervals: int  # the table's intervals n
    end_value: float  # C_Q at the last point [-]
    end_slope: float  # dC_Q/dlambda past the last point [-]
    radius: float  # r [m]
    torque_scale: float  # 1/2 rho_air pi r^3 [N m s^2/m^2]
    V_ref: float  # the wind a wind scale s = 1 means [m/s]
    V_furl: float  # the wind above which the wheel furls [m/s]; inf: never


@intrinsic
def _doubles_at(typingctx, address):
    """A pointer to float64 at the integer ``address`` (for numba.carray: no reference counted)."""
    signature = types.CPointer(types.float64)(types.intp)

    def codegen(context, builder, _signature, arguments):
        return builder.inttoptr(arguments[0], context.get_value_type(types.CPointer(types.float64)))

    return signature, codegen


@inline_kernel
def _table(rotor):
    """The table's numbers as an array that owns nothing (no reference to count)."""
    return carray(_doubles_at(rotor.address), (5 * rotor.intervals + 1,))


SCANNED = 24
"""Tables of up to this many intervals are scanned for lambda's interval; longer ones bisected."""

equation_11 = kernel(equations.windmill_torque)  # Eq. (11) with T_0, in the wind s [N m]


def wheel_torque(omega, s, rotor, T_m, T_0, omega_m):
    """The windmill's torque T [N m] at its speed omega [rad/s] in the wind s = V/V_ref: Eq. (11)
    with T_0 scaled by similarity (``rotor`` None), or the rotor's table."""
    if rotor is None:
        return equations.windmill_torque(omega / omega_m, s, T_m, T_0)
    return _table_torque(omega, s, rotor, T_m, T_0, omega_m)


def unfurled_rest_torque(rotor, T_0):
    """The torque at rest [N m] at s = 1 were the wheel not furled: T_0 (Eq. 11), or the table's
    ``torque_scale V_ref^2 C_Q(0)``. At rest in the wind s it is this times s^2 up to the furl."""
    if rotor is None:
        return T_0
    return rotor.torque_scale * rotor.V_ref**2 * _table(rotor)[4 * rotor.intervals + 1]


def furl_scale(rotor):
    """V_furl / V_ref [-]: the wind scale above which the torque stops growing; inf without."""
    if rotor is None:
        return math.inf
    return rotor.V_furl / rotor.V_ref


@overload(wheel_torque, jit_options=JIT_OPTIONS)
def _wheel_torque_overload(omega, s, rotor, T_m, T_0, omega_m):
    if isinstance(rotor, types.NoneType):
        return lambda omega, s, rotor, T_m, T_0, omega_m: equation_11(omega / omega_m, s, T_m, T_0)
    return _table_torque


@overload(unfurled_rest_torque, jit_options=JIT_OPTIONS)
def _unfurled_rest_torque_overload(rotor, T_0):
    if isinstance(rotor, types.NoneType):
        return lambda rotor, T_0: T_0
    return lambda rotor, T_0: (
        rotor.torque_scale * rotor.V_ref**2 * _table(rotor)[4 * rotor.intervals + 1]
    )


@overload(furl_scale, jit_options=JIT_OPTIONS)
def _furl_scale_overload(rotor):
    if isinstance(rotor, types.NoneType):
        return lambda rotor: math.inf
    return lambda rotor: rotor.V_furl / rotor.V_ref


def _table_torque(omega, s, rotor, T_m, T_0, omega_m):
    V_s = min(s * rotor.V_ref, rotor.V_furl)
    if V_s <= 0.0:
        return 0.0  # calm: the limit of V_s^2 C_Q (linear in 1/V_s past the table)
    tip_speed = omega * rotor.radius
    last = _table(rotor)[rotor.intervals]
    if tip_speed >= last * V_s:  # past the table, C_Q linear in lambda: V_s^2 C_Q without
        # omega r / V_s (which overflows in a near-calm wind, where the torque tends to 0)
        rest = rotor.end_value - rotor.end_slope * last
        return rotor.torque_scale * V_s * (V_s * rest + rotor.end_slope * tip_speed)
    return rotor.torque_scale * V_s * V_s * table_cq(tip_speed / V_s, rotor)


@inline_kernel
def table_cq(lam, rotor):
    """C_Q at the tip-speed ratio lam >= 0: the PCHIP's cubic on its interval, a straight line
    past the last point (:meth:`windpump.Rotor.cq`)."""
    table = _table(rotor)
    last = rotor.intervals
    if lam >= table[last]:
        return rotor.end_value + rotor.end_slope * (lam - table[last])
    if last > SCANNED:  # table[lo] <= lam < table[hi]
        lo, hi = 0, last
        while hi - lo > 1:
            middle = (lo + hi) // 2
            if table[middle] <= lam:
                lo = middle
            else:
                hi = middle
        i = lo
    else:
        i = 0
        while table[i + 1] <= lam:  # a table of tens of points: a scan beats a bisection
            i += 1
    x = lam - table[i]
    c = last + 1 + i  # c3 of interval i; c2, c1, c0 follow every n numbers
    return ((table[c] * x + table[c + last]) * x + table[c + 2 * last]) * x + table[c + 3 * last]
