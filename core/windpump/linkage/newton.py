"""Newton-Raphson loop closure: the two unknowns of a vector loop from a guess (the second seed).

Each step solves ``J dq = -F`` with the analytic 2x2 Jacobian (the seed's steps 3-6 [1]_) until a
step is smaller than the tolerance or the residual is at round-off. The guess picks the assembly
(the branch): a step that would cross a dead centre onto the other branch is halved, so the
answer is on the guess's branch or a :class:`~windpump.NoClosure` says why not. Mechanisms of
several loops (the seed's double loop, a Watt six-bar) are closed loop by loop, each loop's known
angles coming from the loops before it (:func:`solve_loops`).

References
----------
.. [1] "Newton-Raphson Method: Application", blog post of 26 January 2013 (the project's second
   seed): the iteration for the joint angles of a double-loop mechanism, loop by loop.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence

import numpy as np

from ..errors import NoClosure, ParameterError
from ..validation import positive, whole
from . import _checks as check
from .closable import DEAD_CENTRE, check_closable
from .vectors import Loop, Vector, _as_loop, _as_loops, _jacobian, _residual, names_in

TOL = 1e-13
"""Newton-Raphson stops once a step is smaller than this [rad; lengths relative to the loop's size]."""

LOOSEST_TOL = 0.1
"""The largest tolerance a caller may ask for [rad]: a looser one would not fix a position."""

MAX_ITERATIONS = 50
"""Iteration budget of one loop closure."""

MOST_ITERATIONS = 10_000
"""The largest iteration budget a caller may ask for."""

MAX_STEP = 1.0
"""Largest Newton step [rad; lengths relative to the loop]: far from the root, a full step can leap."""

ROUND_OFF = 8 * np.finfo(float).eps
"""A residual this small, relative to the loop's size, cannot be improved by another step [-]."""

BLOCKED_HALVINGS = 30
"""A Newton step halved this often without staying on the guess's branch is blocked."""


@dataclasses.dataclass(frozen=True)
class Closure:
    """A closed loop: the solution and how Newton-Raphson got there.

    Attributes
    ----------
    values : dict
        Every named quantity of the loop, the known ones and the two solved [rad or m].
    unknowns : tuple of str
        The two names solved for, in the Jacobian's column order.
    iterates : ndarray
        The unknowns at the guess and after every Newton step, shape (iterations + 1, 2)
        [rad or m].
    residuals : ndarray
        ``|F|`` relative to the loop's size at each iterate [-]: it falls quadratically near the root.
    branch : int
        The assembly found: minus the sign of the Jacobian's determinant at the solution, the
        convention under which a four-bar's branch is :func:`four_bar_branch` (+1 with B left of
        the line from A to D). A branch-following trace keeps it; it changes only through a dead
        centre.
    """

    values: dict
    unknowns: tuple[str, str]
    iterates: np.ndarray
    residuals: np.ndarray
    branch: int

    @property
    def iterations(self) -> int:
        """Newton steps taken."""
        return len(self.iterates) - 1

    def __getitem__(self, name: str) -> float:
        return self.values[name]


@dataclasses.dataclass(frozen=True)
class _Problem:
    """One loop to close, checked: what Newton-Raphson iterates on."""

    loop: Loop
    known: dict[str, float]
    unknowns: tuple[str, str]
    where: dict[str, float]  # the loop's known names, for messages
    scale: float  # the loop's size [m]
    units: np.ndarray  # of a step: 1 for an angle [rad], the loop's size for a length [m]

    def values(self, q: np.ndarray) -> dict[str, float]:
        return {**self.known, **dict(zip(self.unknowns, map(float, q), strict=True))}


def solve_loop(
    loop: Sequence[Vector],
    known: Mapping[str, float],
    guess: Mapping[str, float],
    tol: float = TOL,
    max_iterations: int = MAX_ITERATIONS,
) -> Closure:
    """Close one vector loop by Newton-Raphson: its two unknowns, from a guess (second seed).

    Each step solves ``J dq = -F`` (the seed's steps 3-6) with the analytic Jacobian of
    :func:`jacobian`, until a step is smaller than ``tol`` or the residual is at round-off. Steps
    longer than ``MAX_STEP`` are shortened, so a poor guess cannot leap far from the loop, and a
    step that would cross a dead centre is halved: the solution is on the guess's branch (the
    sign of det J), or NoClosure says that Newton-Raphson was heading for the other one.

    Parameters
    ----------
    loop : sequence of Vector
        The loop; its names not in ``known`` must be exactly two.
    known : mapping
        Values of the loop's known names [rad or m].
    guess : mapping
        Starting values of the two unknowns [rad or m]; it selects the branch.
    tol : float
        Size of the last step [rad; lengths relative to the loop's size], > 0 and <= 0.1.
    max_iterations : int
        Iteration budget, 0 to ``MOST_ITERATIONS``.

    Returns
    -------
    Closure

    Raises
    ------
    NoClosure
        When the links cannot span the gap for these inputs, when the loop closes only at a dead
        centre or an iterate lands on one (singular Jacobian), or when the budget runs out or
        the iteration heads for the other branch (no convergence).
    ParameterError
        On a bad argument, or a loop whose unknowns are not exactly two.

    Examples
    --------
    >>> from windpump.linkage import four_bar_loop
    >>> loop = four_bar_loop(r1=1.0, r2=3.0, r3=2.5, r6=3.0)
    >>> closed = solve_loop(loop, {"theta1": 1.0}, {"theta2": 0.5, "theta3": 1.5})
    >>> round(closed["theta2"], 6), round(closed["theta3"], 6), closed.iterations
    (0.585642, 1.554646, 4)
    """
    tol = _tolerance(tol)
    max_iterations = whole("max_iterations", max_iterations, 0, MOST_ITERATIONS)
    problem = _problem(_as_loop("loop", loop), check.named_numbers("known", known))
    guess = check.named_numbers("guess", guess)
    for name in problem.unknowns:
        if name not in guess:
            raise ParameterError("guess", guess, f"a starting value for {name!r}")
    q = np.array([guess[name] for name in problem.unknowns])
    return _iterate(problem, q, tol, max_iterations)


def _tolerance(tol: object) -> float:
    """The step tolerance, in (0, LOOSEST_TOL] [rad]."""
    as_float = positive("tol", tol, "rad")
    if as_float > LOOSEST_TOL:
        raise ParameterError("tol", tol, f"a number > 0 and <= {LOOSEST_TOL:g}", "rad")
    return as_float


def _problem(loop: Loop, known: dict[str, float]) -> _Problem:
    """The loop with its two unknowns, after the geometry's verdict (:func:`check_closable`)."""
    unknowns = tuple(name for name in names_in(loop) if name not in known)
    if len(unknowns) != 2:
        raise ParameterError(
            "known",
            known,
            f"all but two of the loop's names {names_in(loop)}: "
            f"a planar loop fixes two unknowns; this one has {len(unknowns)}: {list(unknowns)}",
        )
    where = {name: known[name] for name in names_in(loop) if name in known}
    scale = check_closable(loop, known, unknowns, where)
    angles = {v.angle for v in loop}
    units = np.array([1.0 if name in angles else scale for name in unknowns])
    return _Problem(loop, known, (unknowns[0], unknowns[1]), where, scale, units)


def _iterate(problem: _Problem, q: np.ndarray, tol: float, max_iterations: int) -> Closure:
    """Newton-Raphson from q, on q's branch (the sign of det J at the guess)."""
    iterates, residuals, last_step, branch = [q.copy()], [], math.inf, 0
    for iteration in range(max_iterations + 1):
        values = problem.values(q)
        F, J = _residual(problem.loop, values), _jacobian(problem.loop, values, problem.unknowns)
        residuals.append(math.hypot(*F) / problem.scale)
        if residuals[-1] <= ROUND_OFF or last_step <= tol:
            return Closure(
                values, problem.unknowns, np.array(iterates), np.array(residuals), _branch(J)
            )
        if iteration == max_iterations:
            break
        if _in_line(J):
            raise _failure(problem, NoClosure.SINGULAR, iteration, q, "puts the links in line")
        branch = branch or _branch(J)  # set at the guess, kept after
        q, last_step = _step(problem, q, F, J, branch, iteration)
        iterates.append(q.copy())
    raise NoClosure(
        NoClosure.NO_CONVERGENCE,
        problem.where,
        f"{max_iterations} iterations left |F| = {residuals[-1]:.3g} of the loop's size at "
        f"{check.show(problem.unknowns, q)}; start from a closer guess",
        max_iterations,
    )


def _step(problem: _Problem, q, F, J, branch: int, iteration: int) -> tuple[np.ndarray, float]:
    """The next iterate and the step's size (inf when it was shortened or halved)."""
    dq = np.linalg.solve(J, -F)
    size = float(np.max(np.abs(dq) / problem.units))
    shrink = min(1.0, MAX_STEP / size) if size > 0 else 1.0
    q_next, halved = _step_on_branch(problem, q, dq * shrink, branch)
    if q_next is None:
        raise _failure(problem, NoClosure.NO_CONVERGENCE, iteration, q, "heads for the other")
    return q_next, math.inf if halved or size > MAX_STEP else size


def _failure(problem: _Problem, reason: str, iteration: int, q, what: str) -> NoClosure:
    """A NoClosure at an iterate, saying how to get past it."""
    at = f"iterate {iteration} ({check.show(problem.unknowns, q)})"
    if reason == NoClosure.SINGULAR:
        detail = f"{at} {what}; start from another guess"
    else:
        detail = (
            f"from {at} Newton-Raphson {what} assembly; start from a guess closer to the "
            "branch you want"
        )
    return NoClosure(reason, problem.where, detail, iteration)


def _in_line(J: np.ndarray) -> bool:
    """A singular Jacobian: its columns in line, to DEAD_CENTRE."""
    return abs(np.linalg.det(J)) <= DEAD_CENTRE * np.prod(np.linalg.norm(J, axis=0))


def _branch(J: np.ndarray) -> int:
    """The branch of a loop at a Jacobian J: -sign(det J). For the four-bar,
    det J = -r2 r3 sin(theta3 - theta2), so this is :func:`four_bar_branch`: one convention."""
    return -check.sign(np.linalg.det(J))


def _step_on_branch(problem: _Problem, q, step, branch: int) -> tuple[np.ndarray | None, bool]:
    """q + step, halved while it would cross a dead centre (flip the sign of det J) onto the other
    branch, so Newton-Raphson keeps its guess's branch; also says whether it was halved. None
    when the step stays blocked: Newton-Raphson is heading for the other branch."""
    for halvings in range(BLOCKED_HALVINGS):
        trial = q + step
        J = _jacobian(problem.loop, problem.values(trial), problem.unknowns)
        if _branch(J) == branch:
            return trial, halvings > 0
        step = 0.5 * step
    return None, True


def solve_loops(
    loops: Sequence[Sequence[Vector]],
    known: Mapping[str, float],
    guess: Mapping[str, float],
    tol: float = TOL,
) -> list[Closure]:
    """Close loops one after another, each using what the loops before it found (double loops).

    Parameters
    ----------
    loops : sequence of loops
        The mechanism's loops, in the order they are solved.
    known : mapping
        The first loop's known values (the input) [rad or m].
    guess : mapping
        Starting values of every loop's unknowns [rad or m]; they select the branches.
    tol : float
        As for :func:`solve_loop`.

    Returns
    -------
    list of Closure
        One per loop; the last one's ``values`` hold every name.

    Examples
    --------
    >>> from windpump.linkage import watt_six_bar_loops
    >>> loops = watt_six_bar_loops(1.0, 3.0, 2.5, 3.0, r3p=1.5, r4=2.5, r5=2.0, r6p=2.5)
    >>> guess = {"theta2": 0.5, "theta3": 1.5, "theta4": 0.5, "theta5": 1.5}
    >>> closed = solve_loops(loops, {"theta1": 1.0}, guess)
    >>> [round(closed[-1][name], 4) for name in ("theta2", "theta3", "theta4", "theta5")]
    [0.5856, 1.5546, 0.2014, 1.5839]
    """
    values = check.named_numbers("known", known)
    closures = []
    for loop in _as_loops(loops):
        closure = solve_loop(loop, values, guess, tol)
        closures.append(closure)
        values = closure.values
    return closures
