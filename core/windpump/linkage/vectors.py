"""A planar loop as a chain of vectors, its two closure equations and their analytic Jacobian.

A closed loop of a planar mechanism is a chain of vectors that sums to zero,

    F = sum_i s_i r_i (cos phi_i, sin phi_i) = 0,

two scalar equations that fix two unknowns: two angles (a four-bar), or an angle and a length
(a slider-crank) [1]_. A length or an angle of a :class:`Vector` is a number, or a name whose
value is known or is one of the loop's two unknowns.

References
----------
.. [1] "Newton-Raphson Method: Application", blog post of 26 January 2013 (the project's second
   seed): the loop equation R1 + R2 - R3 - R6 = 0 of a double-loop mechanism, its two scalar
   equations and their partial derivatives.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence

import numpy as np

from ..errors import ParameterError
from . import _checks as check


@dataclasses.dataclass(frozen=True)
class Vector:
    """One vector of a loop: ``sign * length * (cos angle, sin angle)``.

    Attributes
    ----------
    length : float or str
        Length [m], or the name of an unknown or known length (a slider's position).
    angle : float or str
        Angle from the x axis, counter-clockwise [rad], or the name of one.
    sign : int
        +1 or -1: the vector's direction along the loop.
    offset : float
        Added to a named angle [rad]: the fixed angle between two arms of a ternary link.
    label : str
        The link's name in messages, e.g. ``"r2"``.

    Examples
    --------
    >>> Vector(2.0, "theta2", label="r2").resolve({"theta2": 0.5})
    (2.0, 0.5)
    >>> Vector(3.0, 0.0, sign=-1).resolve({})
    (-3.0, 0.0)
    """

    length: float | str
    angle: float | str
    sign: int = 1
    offset: float = 0.0
    label: str = ""

    def __post_init__(self):
        if isinstance(self.sign, bool) or self.sign not in (1, -1):
            raise ParameterError("sign", self.sign, "+1 or -1")
        for name, part, unit in (("length", self.length, "m"), ("angle", self.angle, "rad")):
            if isinstance(part, str) and not part:
                raise ParameterError(name, part, "a number or a name that is not empty", unit)
            if not isinstance(part, str):
                check.bounded(name, part, unit)
        check.angle("offset", self.offset)
        if not isinstance(self.label, str):
            raise ParameterError("label", self.label, "a str")

    def resolve(self, values: Mapping[str, float]) -> tuple[float, float]:
        """The signed length [m] and the angle [rad], with names looked up in ``values``."""
        length = values[self.length] if isinstance(self.length, str) else self.length
        angle = values[self.angle] + self.offset if isinstance(self.angle, str) else self.angle
        return self.sign * length, angle


Loop = tuple[Vector, ...]
"""A closed chain of vectors."""


def _as_loop(name: str, loop: object) -> Loop:
    """``loop`` as a tuple of :class:`Vector`, or a ParameterError naming ``name``."""
    if isinstance(loop, (str, bytes)) or not isinstance(loop, Sequence) or not loop:
        raise ParameterError(name, loop, "a non-empty sequence of linkage.Vector")
    if not all(isinstance(vector, Vector) for vector in loop):
        raise ParameterError(name, loop, "a sequence of linkage.Vector only")
    return tuple(loop)


def _as_loops(loops: object) -> list[Loop]:
    """``loops`` as a list of loops (a chain of them), or a ParameterError."""
    if isinstance(loops, (str, bytes)) or not isinstance(loops, Sequence) or not loops:
        raise ParameterError("loops", loops, "a non-empty sequence of loops")
    return [_as_loop(f"loops[{k}]", loop) for k, loop in enumerate(loops)]


def _values_for(loop: Loop, values: object) -> dict[str, float]:
    """``values`` checked: bounded numbers [rad or m], one at least for every name of the loop."""
    checked = check.named_numbers("values", values)
    missing = [name for name in names_in(loop) if name not in checked]
    if missing:
        raise ParameterError("values", values, f"a value for each of {missing}")
    return checked


def names_in(loop: Sequence[Vector]) -> list[str]:
    """The names a loop uses, in order of appearance.

    Examples
    --------
    >>> names_in([Vector(1.0, "theta1"), Vector("s", 0.0, sign=-1), Vector(2.0, "phi")])
    ['theta1', 's', 'phi']
    """
    found = [part for v in loop for part in (v.length, v.angle) if isinstance(part, str)]
    return list(dict.fromkeys(found))


def residual(loop: Sequence[Vector], values: Mapping[str, float]) -> np.ndarray:
    """The loop's two closure equations at ``values``.

    Parameters
    ----------
    loop : sequence of Vector
        The loop.
    values : mapping
        A value for every name of the loop [rad or m].

    Returns
    -------
    ndarray, shape (2,)
        ``F = sum_i s_i r_i (cos phi_i, sin phi_i)`` [m]: zero when the loop closes.

    Examples
    --------
    >>> residual([Vector(1.0, 0.0), Vector(1.0, "phi", sign=-1)], {"phi": 0.0}).tolist()
    [0.0, 0.0]
    """
    loop, values = _as_loop("loop", loop), _values_for(loop, values)
    return _residual(loop, values)


def _residual(loop: Sequence[Vector], values: Mapping[str, float]) -> np.ndarray:
    total = np.zeros(2)
    for vector in loop:
        length, angle = vector.resolve(values)
        total += length * np.array([math.cos(angle), math.sin(angle)])
    return total


def jacobian(
    loop: Sequence[Vector], values: Mapping[str, float], unknowns: Sequence[str]
) -> np.ndarray:
    """The analytic Jacobian dF/d(unknowns) of :func:`residual` (the seed's step 2).

    A vector's angle contributes ``s r (-sin phi, cos phi)``, its length ``s (cos phi, sin phi)``.
    For the four-bar this is the seed's matrix, with its slip corrected: dF2/dtheta3 = -r3 cos
    theta3.

    Parameters
    ----------
    loop : sequence of Vector
        The loop.
    values : mapping
        A value for every name of the loop [rad or m].
    unknowns : sequence of str
        The two names to differentiate by, in the columns' order.

    Returns
    -------
    ndarray, shape (2, 2)
        [m per rad] for an angle's column, [-] for a length's.

    Examples
    --------
    >>> loop = [Vector(2.0, "theta2"), Vector(1.0, "theta3", sign=-1)]
    >>> jacobian(loop, {"theta2": 0.0, "theta3": 0.0}, ("theta2", "theta3")).tolist()
    [[0.0, 0.0], [2.0, -1.0]]
    """
    loop, values = _as_loop("loop", loop), _values_for(loop, values)
    if (
        isinstance(unknowns, str)
        or not isinstance(unknowns, Sequence)
        or len(unknowns) != 2
        or not all(isinstance(name, str) and name in values for name in unknowns)
    ):
        raise ParameterError("unknowns", unknowns, f"two of the loop's names {names_in(loop)}")
    return _jacobian(loop, values, unknowns)


def _jacobian(
    loop: Sequence[Vector], values: Mapping[str, float], unknowns: Sequence[str]
) -> np.ndarray:
    columns = np.zeros((2, 2))
    for vector in loop:
        length, angle = vector.resolve(values)
        c, s = math.cos(angle), math.sin(angle)
        for k, name in enumerate(unknowns):
            if vector.angle == name:
                columns[:, k] += length * np.array([-s, c])
            if vector.length == name:
                columns[:, k] += vector.sign * np.array([c, s])
    return columns


def joints(
    loop: Sequence[Vector], values: Mapping[str, float], origin: Sequence[float] = (0.0, 0.0)
) -> np.ndarray:
    """The loop's joints: the running sums of its vectors from ``origin``, to draw it with.

    Parameters
    ----------
    loop : sequence of Vector
        The loop.
    values : mapping
        A value for every name of the loop [rad or m].
    origin : (float, float)
        Where the first vector starts [m].

    Returns
    -------
    ndarray, shape (n + 1, 2)
        The joints [m]; a closed loop ends where it began.

    Examples
    --------
    >>> joints([Vector(1.0, 0.0), Vector(1.0, "phi")], {"phi": math.pi / 2}).round(12).tolist()
    [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]
    """
    loop, values = _as_loop("loop", loop), _values_for(loop, values)
    points = [np.array(check.pair("origin", origin, "m"))]
    for vector in loop:
        length, angle = vector.resolve(values)
        points.append(points[-1] + length * np.array([math.cos(angle), math.sin(angle)]))
    return np.array(points)
