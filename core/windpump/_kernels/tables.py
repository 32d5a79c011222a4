"""What a segment's split needs at its stage nodes, tabulated once per run (every segment of the
same parity loads the crank the same way), and the grid angles' values over one revolution."""

from __future__ import annotations

import math

import numpy as np

from .jit import inline_kernel, kernel
from .model import Machine, delivered_strokes, flow_factor, segment_start
from .real import (
    C_PARTS,
    conservative_torque,
    conservative_work,
    fill_friction,
    fill_stages,
    friction_at,
    grid_inertias,
    inertia_table,
    no_friction,
    not_known,
    set_grid_inertia,
)

C1, C2, C3 = C_PARTS  # the rows' columns of the real machine's C


@kernel
def grid_tables(n_per_stroke, machine):
    """At the grid angles g pi / n_per_stroke of one revolution: strokes delivered since theta = 0,
    the flow factor, the conservative work since the segment began, and J / I_eff (for the real
    machine with C since the segment began: :func:`~.real.grid_inertias`)."""
    rows = 2 * n_per_stroke
    delta = math.pi / n_per_stroke
    strokes, flows, works = np.empty(rows), np.empty(rows), np.empty(rows)
    inertias = inertia_table(rows, machine)
    for row in range(rows):
        theta = row * delta
        segment = (row * machine.cylinders) // n_per_stroke
        strokes[row] = delivered_strokes(theta, machine)
        flows[row] = flow_factor(theta, segment, machine)
        if (row * machine.cylinders) % n_per_stroke == 0:
            # On a switch the faces that start or stop sit at a dead centre and deliver nothing;
            # the side without them keeps round-off (sin pi = 1.2e-16) out of the flow.
            flows[row] = min(flows[row], flow_factor(theta, segment - 1, machine))
        works[row] = conservative_work(theta, segment, machine)
        set_grid_inertia(inertias, row, grid_inertias(theta, segment, machine))
    return strokes, flows, works, inertias


@kernel
def tabulate_segment(parity, m, machine, tables, rows, built):
    """For each of m equal sub-steps of a segment of this parity: the conservative work at its 7
    stage nodes and (column 7) the conservative torque at its start [N m]; and the real machine's
    rows at the nodes (C since the segment began in their C_PARTS columns, exact at the inner
    nodes: :func:`~.real.fill_friction`)."""
    start = segment_start(parity, machine)
    h = (segment_start(parity + 1, machine) - start) / m
    c_at = no_friction(machine)
    for i in range(m):
        sub_rows = rows[parity, m, i]
        stage_values(
            start + i * h, h, parity, machine, tables[parity, m, i], sub_rows, c_at,
            not_known(machine), True,
        )  # fmt: skip
        c_at = friction_at(sub_rows[6, C1], sub_rows[6, C2], sub_rows[6, C3], machine)
    built[parity, m] = True


@kernel
def stage_values(theta, h, segment, machine, aux, rows, c_at, known, exact):
    """Fill a sub-step's stage values from theta, of length h: ``aux`` (the conservative work
    at its nodes, then the conservative torque at theta) and the real machine's ``rows`` (with
    C from c_at = C(theta) in their C_PARTS columns, or from ``known``; ``exact`` for a table's:
    :func:`~.real.fill_friction`)."""
    fill_stages(aux, rows, theta, h, segment, machine)
    aux[7] = conservative_torque(theta, segment, machine)
    fill_friction(rows, theta, h, c_at, known, exact, segment, without_wind(machine))


@inline_kernel
def stage_work(aux):
    """The conservative work at a sub-step's 7 stage nodes, ``aux[:7]``, as the 7 numbers
    :func:`~.stepping.dp5_step` takes: the real machine's step is called, not inlined, and an
    array handed to it costs an atomic reference pair every step (4,393 pairs in the seed
    example's 600 s with every effect on); the ideal machine's, inlined, reads the same numbers."""
    return aux[0], aux[1], aux[2], aux[3], aux[4], aux[5], aux[6]


@inline_kernel
def without_wind(machine):
    """The machine without its wind record: what the loads, masses and tolerances need, with no
    arrays (an array passed to an inlined kernel is one more reference, counted on every call)."""
    return Machine(
        machine.R_dagger, machine.T_m, machine.T_0, machine.omega_m, machine.inv_I_eff,
        machine.load_torque, machine.L_over_R, machine.cylinders, machine.double_acting, None,
        machine.real, machine.rotor,
    )  # fmt: skip
