"""Branch continuation: a mechanism followed along one branch as its input moves.

Each position starts Newton-Raphson from the last one, pushed on along the secant of the last two
(a predictor-corrector continuation). A step that lands on another branch (the sign of a loop's
Jacobian flips) or fails to converge is halved; the trace ends where the loop cannot close or the
branch reaches a dead centre, and keeps the :class:`~windpump.NoClosure` that ended it.
"""

from __future__ import annotations

import dataclasses
import math
import typing
from collections.abc import Mapping, Sequence

import numpy as np

from ..errors import NoClosure, ParameterError
from ..validation import finite_array, positive
from . import _checks as check
from ._checks import LARGEST
from .newton import TOL, Closure, solve_loops
from .vectors import Loop, Vector, _as_loops, names_in

MAX_HALVINGS = 12
"""A trace halves a step up to this many times to stay on its branch."""

STEP = math.radians(2.0)
"""The largest step of a dragged input [rad]: small enough that the secant predictor lands on the
branch, large enough that a full turn takes 180 closures."""

MAX_POSITIONS = 100_000
"""The most positions :func:`follow_branch` and :func:`branch_reach` close in one call."""


@dataclasses.dataclass(frozen=True)
class BranchTrace:
    """A mechanism followed along one branch as its input moves, up to where the branch ends.

    ``windpump.linkage.Sweep`` is its old name, kept.

    Attributes
    ----------
    input : str
        The input's name.
    values : dict of ndarray
        Every name over the positions that closed [rad or m]. Angles are continuous (not wrapped).
    branches : tuple of int
        The branch of each loop (``Closure.branch``), kept along the trace.
    stop : NoClosure or None
        Why the trace ended before the last input value; None when every position closed.
    """

    input: str
    values: dict
    branches: tuple[int, ...]
    stop: NoClosure | None

    def __len__(self) -> int:
        return len(self.values[self.input])


def trace_branch(
    loops: Sequence[Sequence[Vector]],
    input: str,
    inputs,
    guess: Mapping[str, float],
    known: Mapping[str, float] | None = None,
    tol: float = TOL,
) -> BranchTrace:
    """Follow one branch of a mechanism as its input moves through ``inputs``.

    Each position starts Newton-Raphson from the last one, pushed on along the secant of the last
    two. A step that lands on another branch (the sign of a loop's Jacobian flips) or fails to
    converge is halved, up to ``MAX_HALVINGS`` times. The trace ends, keeping the ``NoClosure``
    in ``stop``, where the loop cannot close or the branch reaches a dead centre.
    ``windpump.linkage.sweep`` is its old name, kept.

    Parameters
    ----------
    loops : sequence of loops
        The mechanism, solved loop by loop (:func:`solve_loops`).
    input : str
        The name of the input, e.g. ``"theta1"``.
    inputs : array_like
        The input's values in order, at least one [rad or m].
    guess : mapping
        Starting values of every unknown at ``inputs[0]`` [rad or m]: they pick the branch.
    known : mapping, optional
        Other fixed values of the loops [rad or m].
    tol : float
        As for :func:`solve_loop`.

    Returns
    -------
    BranchTrace

    Raises
    ------
    NoClosure
        When the first position does not close (later ones end the trace instead).

    Examples
    --------
    >>> from windpump.linkage import four_bar_loop
    >>> loop = four_bar_loop(r1=2.0, r2=2.5, r3=2.0, r6=3.0)  # non-Grashof: the input rocks
    >>> traced = trace_branch([loop], "theta1", np.radians(np.arange(0, 360, 5)),
    ...                       {"theta2": 0.5, "theta3": 1.5})
    >>> len(traced), round(float(np.degrees(traced.values["theta1"][-1]))), traced.stop.reason
    (26, 125, 'cannot close')
    """
    loops = _as_loops(loops)
    input = _input_name(loops, input)
    inputs = _input_values(inputs)
    known = {} if known is None else check.named_numbers("known", known)
    closures = solve_loops(loops, {**known, input: float(inputs[0])}, guess, tol)
    branches = tuple(c.branch for c in closures)
    path, stop = [closures[-1].values], None
    for target in inputs[1:]:
        try:
            path.append(_advance(loops, input, path, float(target), branches, known, tol, 0))
        except NoClosure as error:
            stop = error
            break
    values = {name: np.array([p[name] for p in path]) for name in path[0]}
    return BranchTrace(input, values, branches, stop)


def _input_name(loops: list[Loop], input: object) -> str:
    names = [name for loop in loops for name in names_in(loop)]
    if not isinstance(input, str) or input not in names:
        raise ParameterError(
            "input", input, f"one of the loops' names {list(dict.fromkeys(names))}"
        )
    return input


def _input_values(inputs: object) -> np.ndarray:
    values = finite_array("inputs", inputs)
    if values.ndim != 1 or values.size == 0:
        shape = f"shape {values.shape}"
        raise ParameterError("inputs", shape, "a sequence of at least one number")
    if values.size and np.max(np.abs(values)) > LARGEST:
        raise ParameterError("inputs", float(np.max(np.abs(values))), check.BOUNDED)
    return values


def _advance(loops, input, path, target, branches, known, tol, depth) -> dict:
    """The next position of a branch-following trace, halving the step while it strays."""
    last = path[-1]
    try:
        closures = solve_loops(loops, {**known, input: target}, _predict(path, input, target), tol)
        if tuple(c.branch for c in closures) == branches:
            return closures[-1].values
        failure = NoClosure(
            NoClosure.SINGULAR,
            {input: target},
            f"the branch passes a dead centre between {input} = {last[input]:.6g} and here",
        )
    except NoClosure as error:
        if error.iteration is None:  # the geometry's verdict: the branch ends here
            raise
        failure = error
    if depth == MAX_HALVINGS:
        raise failure
    middle = 0.5 * (last[input] + target)
    half = _advance(loops, input, path, middle, branches, known, tol, depth + 1)
    return _advance(loops, input, [*path, half], target, branches, known, tol, depth + 1)


def _predict(path: list[dict], input: str, target: float) -> dict[str, float]:
    """The secant predictor: the last position pushed on along the last step, to ``target``."""
    last = path[-1]
    previous = path[-2] if len(path) > 1 else last
    stride = last[input] - previous[input]
    ratio = (target - last[input]) / stride if stride else 0.0
    predicted = {name: last[name] + ratio * (last[name] - previous[name]) for name in last}
    if all(abs(value) <= LARGEST for value in predicted.values()):  # False for inf and NaN
        return predicted
    return dict(last)  # a leap too long to extrapolate: start from the last position


class BranchMove(typing.NamedTuple):
    """Where :func:`follow_branch` left a mechanism."""

    closures: list[Closure]
    """The loops closed at the last position reached, from the one before (their Newton history)."""
    stop: NoClosure | None
    """Why the branch ended before the target; None when the target was reached."""


def follow_branch(
    loops: Sequence[Sequence[Vector]],
    position: Mapping[str, float],
    target: float,
    input: str = "theta1",
    step: float = STEP,
) -> BranchMove:
    """Move a mechanism's input from a closed position to ``target`` along the position's branch.

    The input goes in equal steps of at most ``step`` (:func:`trace_branch`), as a dragged input
    does, so the mechanism stays on its branch; past the branch's end it stays at the end.

    Parameters
    ----------
    loops : sequence of loops
        The mechanism.
    position : mapping
        A closed position: every name of the loops [rad or m].
    target : float
        The input's new value [rad or m].
    input : str, default "theta1"
        The input's name.
    step : float
        The largest step [rad or m], > 0 and at least 1/``MAX_POSITIONS`` of the move.

    Returns
    -------
    BranchMove
        ``closures[-1].values`` is the new position.

    Examples
    --------
    >>> from windpump.linkage import four_bar_loop
    >>> loops = [four_bar_loop(1.0, 3.0, 2.5, 3.0)]
    >>> start = {"theta1": 0.0, "theta2": 0.9, "theta3": 2.0}
    >>> moved = follow_branch(loops, solve_loops(loops, {"theta1": 0.0}, start)[-1].values, 1.0)
    >>> round(moved.closures[-1]["theta2"], 6), moved.stop
    (0.585642, None)
    """
    position = check.named_numbers("position", position)
    input = _input_name(_as_loops(loops), input)
    start, target = _start(position, input), check.bounded("target", target)
    count = _positions("step", step, abs(target - start))
    traced = trace_branch(loops, input, np.linspace(start, target, max(2, count + 1)), position)
    last = {name: float(values[-1]) for name, values in traced.values.items()}
    previous = {
        name: float(values[max(0, len(values) - 2)]) for name, values in traced.values.items()
    }
    closures = solve_loops(loops, {input: last[input]}, previous)
    return BranchMove(closures, traced.stop)


def branch_reach(
    loops: Sequence[Sequence[Vector]],
    position: Mapping[str, float],
    input: str = "theta1",
    step: float = STEP,
) -> dict[str, np.ndarray]:
    """Every position of the branch through ``position``: a full turn either way, or to its ends.

    Parameters
    ----------
    loops : sequence of loops
        The mechanism.
    position : mapping
        A closed position: every name of the loops [rad or m].
    input : str, default "theta1"
        The input's name (an angle).
    step : float
        The input's step [rad], > 0 and at least 2 pi / ``MAX_POSITIONS``.

    Returns
    -------
    dict of ndarray
        Every name over the positions, in the order of the input [rad or m]: from one end of the
        branch (or a turn back) to the other end (or a turn on).

    Examples
    --------
    >>> from windpump.linkage import branch_guess, four_bar_loop
    >>> theta2, theta3 = branch_guess(2.0, 2.5, 2.0, 3.0, theta1=0.0)  # a triple-rocker
    >>> reach = branch_reach([four_bar_loop(2.0, 2.5, 2.0, 3.0)],
    ...                      {"theta1": 0.0, "theta2": theta2, "theta3": theta3})
    >>> # it rocks to where |AD| = r2 + r3, theta1 = +-127.2 degrees: the last 2-degree step
    >>> [round(float(np.degrees(end))) for end in reach["theta1"][[0, -1]]]
    [-126, 126]
    """
    position = check.named_numbers("position", position)
    input = _input_name(_as_loops(loops), input)
    here = _start(position, input)
    count = _positions("step", step, 2 * math.pi)
    pieces = []
    for direction in (-1, 1):
        inputs = here + direction * step * np.arange(count + 1)
        pieces.append(trace_branch(loops, input, inputs, position).values)
    backward, forward = pieces
    return {name: np.concatenate([backward[name][::-1], forward[name][1:]]) for name in forward}


def _start(position: dict[str, float], input: str) -> float:
    if input not in position:
        raise ParameterError("position", position, f"a value for the input {input!r}")
    return position[input]


def _positions(name: str, step: object, span: float) -> int:
    """How many steps of ``step`` cross ``span``, refused past MAX_POSITIONS."""
    step = positive(name, step)
    count = span / step
    if not count <= MAX_POSITIONS:
        raise ParameterError(
            name, step, f">= {span / MAX_POSITIONS:.6g} ({MAX_POSITIONS} steps at most)"
        )
    return math.ceil(count)
