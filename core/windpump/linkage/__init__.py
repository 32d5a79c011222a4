"""Planar linkages by Newton-Raphson loop closure (the second seed [1]_).

A closed loop of a planar mechanism is a chain of vectors that sums to zero,

    sum_i s_i r_i (cos phi_i, sin phi_i) = 0,

two scalar equations that fix two unknowns: two angles (a four-bar), or an angle and a length (a
slider-crank). Newton-Raphson solves ``J dq = -F`` with the analytic 2x2 Jacobian from a guess;
the guess picks the assembly (the branch). Mechanisms of several loops (the seed's double loop, a
Watt six-bar) are solved loop by loop, each loop's known angles coming from the loops before it.

A loop is a tuple of :class:`Vector`; a length or an angle is a number, or a name whose value is
known (given, or found by an earlier loop) or is one of the loop's two unknowns. Bad arguments
raise :class:`~windpump.ParameterError` naming the argument, the value and the allowed range
(link lengths from 1e-100 to 1e100 m, angles within +-1e100 rad); a loop that does not close
raises :class:`~windpump.NoClosure` saying why.

Modules, one concept each:

- :mod:`~windpump.linkage.vectors`: :class:`Vector`, a loop's :func:`residual`, its analytic
  :func:`jacobian` and its :func:`joints`;
- :mod:`~windpump.linkage.newton`: Newton-Raphson loop closure, :func:`solve_loop` and
  :func:`solve_loops` (:class:`Closure`);
- :mod:`~windpump.linkage.closable`: whether a loop can close at all (Chace's cases);
- :mod:`~windpump.linkage.tracing`: branch continuation, :func:`trace_branch`,
  :func:`follow_branch` and :func:`branch_reach`;
- :mod:`~windpump.linkage.four_bar`, :mod:`~windpump.linkage.six_bar`,
  :mod:`~windpump.linkage.slider_crank`: the mechanisms;
- :mod:`~windpump.linkage.grashof`: Grashof's classes;
- :mod:`~windpump.linkage.chains`: a four-bar or six-bar assembled on chosen branches, its
  joints by name and its coupler path (what the explorer's Mechanisms tab draws).

``Sweep`` and ``sweep`` are the old names of :class:`BranchTrace` and :func:`trace_branch`, kept
so that code written for them runs; ``windpump.Sweep`` and ``windpump.sweep`` are the studies'.

References
----------
.. [1] "Newton-Raphson Method: Application", blog post of 26 January 2013 (the project's second
   seed): the joint angles of a double-loop mechanism by Newton-Raphson, loop by loop.

Examples
--------
>>> from windpump import linkage
>>> theta2, theta3 = linkage.four_bar(1.0, 3.0, 2.5, 3.0, theta1=1.0)
>>> round(theta2, 4), round(theta3, 4), linkage.grashof_class(1.0, 3.0, 2.5, 3.0)
(0.5856, 1.5546, 'crank-rocker')
"""

from ..errors import NoClosure
from .chains import assemble, assembly_guess, coupler_path, mechanism_joints, output_joint
from .closable import DEAD_CENTRE, check_closable
from .four_bar import branch_guess, four_bar, four_bar_branch, four_bar_loop, included_angle
from .grashof import grashof_class, input_turns_fully, is_grashof
from .newton import (
    BLOCKED_HALVINGS,
    LOOSEST_TOL,
    MAX_ITERATIONS,
    MAX_STEP,
    MOST_ITERATIONS,
    ROUND_OFF,
    TOL,
    Closure,
    solve_loop,
    solve_loops,
)
from .six_bar import watt_six_bar_loops
from .slider_crank import SliderCrankPose, slider_crank, slider_crank_loop, slider_crank_pose
from .tracing import (
    MAX_HALVINGS,
    MAX_POSITIONS,
    STEP,
    BranchMove,
    BranchTrace,
    branch_reach,
    follow_branch,
    trace_branch,
)
from .vectors import Loop, Vector, jacobian, joints, names_in, residual

Sweep = BranchTrace
"""The old name of :class:`BranchTrace`, kept (``windpump.Sweep`` is the studies')."""

sweep = trace_branch
"""The old name of :func:`trace_branch`, kept (``windpump.sweep`` is the studies')."""

__all__ = [
    "BLOCKED_HALVINGS",
    "DEAD_CENTRE",
    "LOOSEST_TOL",
    "MAX_HALVINGS",
    "MAX_ITERATIONS",
    "MAX_POSITIONS",
    "MOST_ITERATIONS",
    "MAX_STEP",
    "ROUND_OFF",
    "STEP",
    "TOL",
    "BranchMove",
    "BranchTrace",
    "Closure",
    "Loop",
    "NoClosure",
    "SliderCrankPose",
    "Sweep",
    "Vector",
    "assemble",
    "assembly_guess",
    "branch_guess",
    "branch_reach",
    "check_closable",
    "coupler_path",
    "follow_branch",
    "four_bar",
    "four_bar_branch",
    "four_bar_loop",
    "grashof_class",
    "included_angle",
    "input_turns_fully",
    "is_grashof",
    "jacobian",
    "joints",
    "mechanism_joints",
    "names_in",
    "output_joint",
    "residual",
    "slider_crank",
    "slider_crank_loop",
    "slider_crank_pose",
    "solve_loop",
    "solve_loops",
    "sweep",
    "trace_branch",
    "watt_six_bar_loops",
]
