"""Chains of four-bar loops as one mechanism: the four-bar (one loop) and the Watt six-bar (two).

What a drawing of such a mechanism needs from the model: the closed position on the branches
asked for (:func:`assemble`, from the compass construction of each loop in turn), its joints by
name (:func:`mechanism_joints`) and the path of its output joint over the branch's reach
(:func:`coupler_path`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ..errors import ParameterError
from . import _checks as check
from .four_bar import branch_guess
from .newton import Closure, solve_loops
from .tracing import STEP, branch_reach
from .vectors import Loop, Vector, _as_loops, joints

FOUR_BAR_LOOPS = "loops of four_bar_loop or watt_six_bar_loops: one or two four-bars"


def assembly_guess(
    loops: Sequence[Sequence[Vector]], known: Mapping[str, float], branches: Sequence[int]
) -> dict[str, float]:
    """A starting position on the given branches, each loop drawn as with compasses in turn.

    Each loop's input angle comes from the loops before it (link 3's second arm of a Watt
    six-bar at theta3 + beta); :func:`branch_guess` puts its coupler joint on its branch.

    Parameters
    ----------
    loops : sequence of loops
        Four-bar loops (:func:`four_bar_loop`, :func:`watt_six_bar_loops`).
    known : mapping
        The first loop's input angle, e.g. ``{"theta1": 1.0}`` [rad].
    branches : sequence of int
        +1 or -1 for each loop.

    Returns
    -------
    dict
        Every unknown's starting value [rad].

    Examples
    --------
    >>> from windpump.linkage import watt_six_bar_loops
    >>> loops = watt_six_bar_loops(1.0, 3.0, 2.5, 3.0, 1.5, 2.5, 2.0, 2.5, beta=0.4)
    >>> guess = assembly_guess(loops, {"theta1": 1.0}, (1, -1))
    >>> {name: round(angle, 3) for name, angle in guess.items()}
    {'theta2': 0.586, 'theta3': 1.555, 'theta4': -1.059, 'theta5': -2.736}
    """
    loops = _four_bar_chain(loops)
    values = check.named_numbers("known", known)
    branches = _branches(branches, len(loops))
    guess = {}
    for loop, branch in zip(loops, branches, strict=True):
        link, coupler, output, ground = loop
        if link.angle not in values:
            raise ParameterError("known", known, f"a value for the input {link.angle!r}")
        theta_in = values[str(link.angle)] + link.offset
        r_in, r_coupler, r_out, r_ground = (float(v.length) for v in loop)
        angles = branch_guess(
            r_in, r_coupler, r_out, r_ground, theta_in, float(ground.angle), branch
        )
        for vector, angle in zip((coupler, output), angles, strict=True):
            guess[str(vector.angle)] = values[str(vector.angle)] = angle
    return guess


def assemble(
    loops: Sequence[Sequence[Vector]], known: Mapping[str, float], branches: Sequence[int]
) -> list[Closure]:
    """The mechanism closed on the given branches, from :func:`assembly_guess`.

    Parameters
    ----------
    loops : sequence of loops
        Four-bar loops (:func:`four_bar_loop`, :func:`watt_six_bar_loops`).
    known : mapping
        The first loop's input angle, e.g. ``{"theta1": 1.0}`` [rad].
    branches : sequence of int
        +1 or -1 for each loop.

    Returns
    -------
    list of Closure
        One per loop (:func:`solve_loops`); the last one's ``values`` hold every name.

    Raises
    ------
    NoClosure
        When a loop cannot close there.

    Examples
    --------
    >>> from windpump.linkage import four_bar_loop
    >>> closed = assemble([four_bar_loop(1.0, 3.0, 2.5, 3.0)], {"theta1": 1.0}, [-1])
    >>> round(closed[-1]["theta2"] % (2 * np.pi), 6), closed[-1].branch
    (5.038298, -1)
    """
    return solve_loops(loops, known, assembly_guess(loops, known, branches))


def mechanism_joints(
    loops: Sequence[Sequence[Vector]], values: Mapping[str, float]
) -> dict[str, np.ndarray]:
    """The mechanism's joints by name, as the seed's figure names them [m].

    Parameters
    ----------
    loops : sequence of loops
        Four-bar loops (:func:`four_bar_loop`, :func:`watt_six_bar_loops`).
    values : mapping
        A closed position: every name of the loops [rad or m].

    Returns
    -------
    dict of ndarray
        O (the input's pivot), A, B and D (the output's pivot) of loop 1; for a six-bar also C
        (the tip of link 3's second arm), F (links 4 and 5) and E (link 5's pivot). Each (x, y).

    Examples
    --------
    >>> from windpump.linkage import four_bar_loop
    >>> loops = [four_bar_loop(1.0, 3.0, 2.5, 3.0)]
    >>> position = assemble(loops, {"theta1": 1.0}, [1])[-1].values
    >>> {name: point.round(3).tolist() for name, point in mechanism_joints(loops, position).items()}
    {'O': [0.0, 0.0], 'A': [0.54, 0.841], 'B': [3.04, 2.5], 'D': [3.0, 0.0]}
    """
    loops = _four_bar_chain(loops)
    first = joints(loops[0], values)
    points = dict(zip("OABD", first[:4], strict=True))
    if len(loops) > 1:
        second = joints(loops[1], values, origin=points["D"])
        points.update(zip("CFE", second[1:4], strict=True))
    return points


def output_joint(loops: Sequence[Sequence[Vector]]) -> str:
    """The joint whose path :func:`coupler_path` traces: B of a four-bar, F of a Watt six-bar.

    Examples
    --------
    >>> from windpump.linkage import four_bar_loop
    >>> output_joint([four_bar_loop(1.0, 3.0, 2.5, 3.0)])
    'B'
    """
    return "B" if len(_four_bar_chain(loops)) == 1 else "F"


def coupler_path(
    loops: Sequence[Sequence[Vector]], position: Mapping[str, float], step: float = STEP
) -> np.ndarray:
    """The path of the output joint (:func:`output_joint`) over the reach of the position's branch.

    Parameters
    ----------
    loops : sequence of loops
        Four-bar loops (:func:`four_bar_loop`, :func:`watt_six_bar_loops`).
    position : mapping
        A closed position [rad]: it picks the branch.
    step : float
        The input's step [rad] (:func:`branch_reach`).

    Returns
    -------
    ndarray, shape (n, 2)
        The joint's positions [m] in the order of theta1: a closed curve for an input that
        turns fully, else an arc between the branch's ends.

    Examples
    --------
    >>> from windpump.linkage import four_bar_loop
    >>> loops = [four_bar_loop(1.0, 3.0, 2.5, 3.0)]
    >>> path = coupler_path(loops, assemble(loops, {"theta1": 1.0}, [1])[-1].values)
    >>> path.shape, bool(np.allclose(path[0], path[-1]))  # a turn back to a turn on: closed
    ((361, 2), True)
    """
    joint, input = output_joint(loops), str(loops[0][0].angle)
    reach = branch_reach(loops, position, input, step)
    positions = ({name: float(v[k]) for name, v in reach.items()} for k in range(len(reach[input])))
    return np.array([mechanism_joints(loops, values)[joint] for values in positions]).reshape(-1, 2)


def _four_bar_chain(loops: object) -> list[Loop]:
    """The loops, if one or two made by four_bar_vectors (the shape assembly_guess reads)."""
    checked = _as_loops(loops)
    if len(checked) > 2 or not all(_is_four_bar(loop) for loop in checked):
        raise ParameterError("loops", loops, FOUR_BAR_LOOPS)
    return checked


def _is_four_bar(loop: Loop) -> bool:
    if len(loop) != 4:
        return False
    link, coupler, output, ground = loop
    turning = all(isinstance(v.angle, str) for v in (link, coupler, output))
    fixed = all(not isinstance(v.length, str) for v in loop) and not isinstance(ground.angle, str)
    signs = (coupler.sign, output.sign, ground.sign) == (1, -1, -1)
    return turning and fixed and signs


def _branches(branches: object, count: int) -> list[int]:
    if isinstance(branches, (str, bytes)) or not isinstance(branches, Sequence):
        raise ParameterError("branches", branches, f"{count} of +1 or -1, one per loop")
    if len(branches) != count:
        raise ParameterError("branches", branches, f"{count} of +1 or -1, one per loop")
    return [check.branch(f"branches[{k}]", b) for k, b in enumerate(branches)]
