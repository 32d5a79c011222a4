"""The real machine's terms in the kernels: reciprocating masses, transmission, rising main, leak.

Each function here takes the :class:`~.model.Machine` and resolves on the type of its ``real``
field when compiled (numba overloads, as :mod:`.wind` does for the wind): for the paper's ideal
machine (``real`` is None) it is the ideal model's expression and adds no code, so the ideal run
is compiled as it always was; for a :class:`~.model.Real` it adds the terms of docs/model.rst,
"The real machine"::

    J(theta) theta_ddot = eta_t R+ T - load(theta, theta_dot) + m_r g sum x_c' - J'(theta) theta_dot^2 / 2,
    J = I_eff + m_r sum x_c'^2.

In the angle domain the state is ``e - Lambda(theta)``, with ``e = J theta_dot^2 / (2 I_eff)``
and Lambda the closed-form work of the weights and of the static head ``rho_w g h A |x'|`` on
every face in its delivering half (as the ideal machine's): what is left to integrate is the
windmill's transmitted work less the *excess* of the load over the static head (the rising main's
friction; a leak hole's relief, negative, where a slow face delivers nothing), less the main's
friction frozen at the energy where each split of a segment begins, whose work is tabulated like
Lambda (docs/model.rst, "The real machine": the main's friction split at a frozen energy). The
quadratures ``W = (shaft work, volume leaked back, friction loss, excess load work)`` are
integrated with it, so a Runge-Kutta step keeps their linear relation exactly and the energy
balance closes to round-off as the ideal machine's does; the leak's loss is the static head's work on the swept volume plus
the excess, less the water lifted and the friction (:func:`windpump.power_budget`).

The pointwise equations (Eq. 1 and its derivatives, the hole's flow, the face's pressure) are
:mod:`.equations`' functions, shared with the numpy side. The sums over faces and cylinders are
twins of :func:`windpump.model.loads.faces_load` (and its friction at a frozen energy,
:func:`friction_density`), :func:`windpump.model.loads.weight_torque` and
:func:`windpump.model.reciprocating.crank_inertia`, kept for speed; tests/run/test_real_machine.py holds
each pair together to 1e-11 or closer.
"""

from __future__ import annotations

import math
import typing

from numba.extending import overload

from .model import (
    Real,
)
from .real_entries import (
    C_PARTS,
    JIT_OPTIONS,
    M_PARTS,
    ROW,
    WORKS,
    _entry,
    _ideal,
    advance_work,
    angle_rates,
    arm_squared_integral,
    conservative_torque,
    conservative_work,
    delivered_flow,
    dense_work,
    face_pressure,
    fill_row,
    inertia_ratio,
    lever_arm_slope,
    time_rates,
    torque_at_rest,
    transmitted,
    work_at,
    write_work,
    zero_work,
)
from .real_friction import (
    EIGHT_POINTS,
    FOUR_POINTS,
    GAUSS4,
    GAUSS8,
    GAUSS8_INNER,
    INTERPOLATORY,
    LONGEST_FOUR,
    LONGEST_PIECE,
    MOMENT,
    _density_at,
    _fill_exactly,
    _fill_friction,
    _fill_part,
    _friction_at_end,
    _friction_moment,
    _friction_since,
    _frozen_parts,
    _frozen_work,
    _gauss,
    _gauss8_inner_weights,
    _held,
    _interpolatory_weights,
    _longest_piece,
    _moment_weights,
    _pieces,
    _weighted,
    fill_friction,
    friction_at,
    friction_between,
    friction_density,
    friction_parts,
    friction_since,
    frozen_energy,
    frozen_record,
    frozen_start,
    frozen_work,
    less_frozen,
    no_friction,
    not_known,
)
from .real_grid import (
    _advance_work,
    _at_time,
    _dense_work,
    _end_works,
    _grid_aux,
    _grid_c,
    _grid_inertia,
    _grid_inertias,
    _grid_time,
    _grid_works,
    _is_none,
    _set_grid_inertia,
    _work_at,
    _write_work,
    at_time,
    end_works,
    grid_aux,
    grid_inertia,
    grid_inertias,
    grid_time,
    grid_works,
    inertia_table,
    set_grid_inertia,
)
from .real_leak import (
    LEAK_RTOL_FACTOR,
    _leak_error,
    _leak_kink_near,
    _next_leak_kink,
    leak_error,
    leak_scale,
    leaky_flow_factors,
    next_leak_kink,
)
from .real_loads import (
    _continued_friction,
    _continued_loads,
    _face_loads,
    _fill_row,
    _ideal_angle_rates,
    _ideal_stages,
    _ideal_time_rates,
    _inertia_ratio,
    _no_row,
    _real_angle_rates,
    _real_conservative_torque,
    _real_conservative_work,
    _real_stages,
    _real_time_rates,
    _real_torque_at_rest,
    _row_extras,
    _sums,
    _time_rates_of_tuples,
    _weight_torque,
    _weight_work,
    fill_stages,
)
from .real_ripple import (
    _add_integrals,
    _inertia_since,
    _lambda_between,
    _lambda_since,
    _real_inertia_since,
    _time_back,
    _work_at_node,
    add_integrals,
    inertia_at,
    inertia_since,
    no_integrals,
    time_back,
    time_frozen,
)
from .real_steps import (
    _row,
    _step_rows,
    split_sizes_by_parity,
    step_rows,
    work_rows,
)
from .real_windows import (
    _IDEAL_EDGE,
    GAUSS_WINDOW,
    SMALL_ANGLE,
    WINDOW_DRIFT,
    WINDOW_NEWTON,
    WINDOW_NODES,
    WINDOW_TARGET,
    _arm_of,
    _edge,
    _edge_phases,
    _energy_slope,
    _open_windows,
    _sin_cos,
    _window_arms,
    _window_edges,
    _window_jump,
    _window_kink,
    _window_loads,
    _window_widths,
    energy_slope,
    jump_work,
    open_windows,
    window_edges,
    window_jump,
)


class RealBase(typing.NamedTuple):
    """The real machine's terms that do not change with the gear ratio and the head (a design
    map's points share them); :func:`real_at` completes them."""

    eta_t: float  # [-]
    weight_torque: float  # m_r g R [N m]
    mass_inertia: float  # m_r R^2 [kg m^2]
    AR: float  # A R [m^3/rad]
    leak_per_root_head: float  # Cd a_L sqrt(2 g): q_L / sqrt(h) [m^2.5/s]
    friction: float  # h_f / Q^2 [s^2/m^5]
    rho_g: float  # rho_w g [N/m^3]


def real_at(base, inv_I_eff, load_torque):
    """The :class:`~.model.Real` of a design with this base, 1 / I_eff [1/(kg m^2)] and load
    rho_w g h A R [N m]; None for the ideal machine's (None) base."""
    if base is None:
        return None
    h = load_torque / (base.rho_g * base.AR)
    return Real(
        base.eta_t, base.weight_torque, base.mass_inertia * inv_I_eff, base.AR,
        base.leak_per_root_head * math.sqrt(h), base.friction, base.rho_g, h,
    )  # fmt: skip


def _real_at_typer(base, inv_I_eff, load_torque):
    if _ideal(base):
        return lambda base, inv_I_eff, load_torque: None
    return real_at


overload(real_at, jit_options=JIT_OPTIONS)(_real_at_typer)


# Every name of the parts, as the driver, the stepping and the tests import them from here.
__all__ = [
    "C_PARTS",
    "EIGHT_POINTS",
    "FOUR_POINTS",
    "GAUSS4",
    "GAUSS8",
    "GAUSS8_INNER",
    "GAUSS_WINDOW",
    "INTERPOLATORY",
    "JIT_OPTIONS",
    "LEAK_RTOL_FACTOR",
    "LONGEST_FOUR",
    "LONGEST_PIECE",
    "MOMENT",
    "M_PARTS",
    "ROW",
    "RealBase",
    "SMALL_ANGLE",
    "WINDOW_DRIFT",
    "WINDOW_NEWTON",
    "WINDOW_NODES",
    "WINDOW_TARGET",
    "WORKS",
    "_IDEAL_EDGE",
    "_add_integrals",
    "_advance_work",
    "_arm_of",
    "_at_time",
    "_continued_friction",
    "_continued_loads",
    "_dense_work",
    "_density_at",
    "_edge",
    "_edge_phases",
    "_end_works",
    "_energy_slope",
    "_entry",
    "_face_loads",
    "_fill_exactly",
    "_fill_friction",
    "_fill_part",
    "_fill_row",
    "_friction_at_end",
    "_friction_moment",
    "_friction_since",
    "_frozen_parts",
    "_frozen_work",
    "_gauss",
    "_gauss8_inner_weights",
    "_grid_aux",
    "_grid_c",
    "_grid_inertia",
    "_grid_inertias",
    "_grid_time",
    "_grid_works",
    "_held",
    "_ideal",
    "_ideal_angle_rates",
    "_ideal_stages",
    "_ideal_time_rates",
    "_inertia_ratio",
    "_inertia_since",
    "_interpolatory_weights",
    "_is_none",
    "_lambda_between",
    "_lambda_since",
    "_leak_error",
    "_leak_kink_near",
    "_longest_piece",
    "_moment_weights",
    "_next_leak_kink",
    "_no_row",
    "_open_windows",
    "_pieces",
    "_real_angle_rates",
    "_real_at_typer",
    "_real_conservative_torque",
    "_real_conservative_work",
    "_real_inertia_since",
    "_real_stages",
    "_real_time_rates",
    "_real_torque_at_rest",
    "_row",
    "_row_extras",
    "_set_grid_inertia",
    "_sin_cos",
    "_step_rows",
    "_sums",
    "_time_back",
    "_time_rates_of_tuples",
    "_weight_torque",
    "_weight_work",
    "_weighted",
    "_window_arms",
    "_window_edges",
    "_window_jump",
    "_window_kink",
    "_window_loads",
    "_window_widths",
    "_work_at",
    "_work_at_node",
    "_write_work",
    "add_integrals",
    "advance_work",
    "angle_rates",
    "arm_squared_integral",
    "at_time",
    "conservative_torque",
    "conservative_work",
    "delivered_flow",
    "dense_work",
    "end_works",
    "energy_slope",
    "face_pressure",
    "fill_friction",
    "fill_row",
    "fill_stages",
    "friction_at",
    "friction_between",
    "friction_density",
    "friction_parts",
    "friction_since",
    "frozen_energy",
    "frozen_record",
    "frozen_start",
    "frozen_work",
    "grid_aux",
    "grid_inertia",
    "grid_inertias",
    "grid_time",
    "grid_works",
    "inertia_at",
    "inertia_ratio",
    "inertia_since",
    "inertia_table",
    "jump_work",
    "leak_error",
    "leak_scale",
    "leaky_flow_factors",
    "less_frozen",
    "lever_arm_slope",
    "next_leak_kink",
    "no_friction",
    "no_integrals",
    "not_known",
    "open_windows",
    "real_at",
    "set_grid_inertia",
    "split_sizes_by_parity",
    "step_rows",
    "time_back",
    "time_frozen",
    "time_rates",
    "torque_at_rest",
    "transmitted",
    "window_edges",
    "window_jump",
    "work_at",
    "work_rows",
    "write_work",
    "zero_work",
]
