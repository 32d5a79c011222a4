"""Whether a loop can close at all, decided from its geometry before Newton-Raphson iterates.

Where each of the two unknowns appears in one vector only, the planar vector equation is one of
Chace's four cases [1]_: the unknowns are the angle and length of one vector, two lengths, two
angles, or an angle and a length of two vectors. Each case has a closed-form verdict: the links
span the gap K left by the known vectors, or cannot, or only in line (a dead centre).

References
----------
.. [1] M. A. Chace, "Vector analysis of linkages", Journal of Engineering for Industry 85(3),
   289-297 (1963).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

from ..errors import NoClosure
from .vectors import Vector, _residual

DEAD_CENTRE = 1e-12
"""Relative closeness to a dead centre (links in line, singular Jacobian) treated as one [-]."""


def loop_size(loop: Sequence[Vector], known: Mapping[str, float]) -> float:
    """The sum of the loop's known lengths [m] (at least the smallest normal float)."""
    lengths = [abs(v.length) for v in loop if not isinstance(v.length, str)]
    lengths += [
        abs(known[v.length]) for v in loop if isinstance(v.length, str) and v.length in known
    ]
    return max(sum(lengths), np.finfo(float).tiny)


def check_closable(
    loop: Sequence[Vector],
    known: Mapping[str, float],
    unknowns: Sequence[str],
    where: Mapping[str, float],
) -> float:
    """Raise :class:`~windpump.NoClosure` if the geometry says the loop cannot close.

    Parameters
    ----------
    loop : sequence of Vector
        The loop.
    known : mapping
        Values of the loop's known names [rad or m].
    unknowns : sequence of str
        Its two unknowns.
    where : mapping
        The loop's inputs, for the error's message [rad or m].

    Returns
    -------
    float
        The loop's size [m] (:func:`loop_size`), the scale of its residual.

    Raises
    ------
    NoClosure
        When the links cannot span the gap, or span it only in line.
    """
    scale = loop_size(loop, known)
    carriers = [[v for v in loop if name in (v.length, v.angle)] for name in unknowns]
    if any(len(c) != 1 for c in carriers):
        return scale  # an unknown in two vectors: leave the verdict to Newton-Raphson
    (a,), (b,) = carriers
    K = _residual([v for v in loop if v is not a and v is not b], known)
    if a is b:
        _one_vector(math.hypot(*K), scale, where)
    elif a.length in unknowns and b.length in unknowns:
        _two_lengths(a, b, known, where)
    elif b.angle in unknowns and a.angle in unknowns:
        _two_angles(a, b, known, math.hypot(*K), where)
    else:
        turning, sliding = (b, a) if a.length in unknowns else (a, b)
        _angle_and_length(turning, sliding, known, K, where)
    return scale


def _one_vector(gap: float, scale: float, where: Mapping[str, float]) -> None:
    """Case 1: the angle and length of one vector: it points at -K, unless K is zero."""
    if gap <= DEAD_CENTRE * scale:
        raise NoClosure(NoClosure.SINGULAR, where, "the gap is zero, so the angle is free")


def _two_lengths(a: Vector, b: Vector, known, where) -> None:
    """Case 2: two lengths on fixed directions: any gap, unless the directions are parallel."""
    if abs(math.sin(_angle_of(b, known) - _angle_of(a, known))) <= DEAD_CENTRE:
        raise NoClosure(NoClosure.SINGULAR, where, "the two sliding links are parallel")


def _two_angles(a: Vector, b: Vector, known, gap: float, where) -> None:
    """Case 4: two angles: the links must span the gap, from |r_a - r_b| to r_a + r_b."""
    r_a, r_b = _length_of(a, known), _length_of(b, known)
    low, high = abs(r_a - r_b), r_a + r_b
    if gap > high * (1 + DEAD_CENTRE) or gap < low - DEAD_CENTRE * high:
        why = "too short to reach" if gap > high else "too unequal: one overreaches"
        raise NoClosure(
            NoClosure.CANNOT_CLOSE,
            where,
            f"{_link(a, r_a)} and {_link(b, r_b)} are {why} across the gap of {gap:.6g} "
            f"(together they span {low:.6g} to {high:.6g})",
        )
    if min(abs(gap - high), abs(gap - low)) <= DEAD_CENTRE * high:
        raise NoClosure(
            NoClosure.SINGULAR, where, f"{_link(a, r_a)} and {_link(b, r_b)} meet only in line"
        )


def _angle_and_length(turning: Vector, sliding: Vector, known, K: np.ndarray, where) -> None:
    """Case 3: one link turning, one sliding: it must reach the slider's line."""
    r_a = _length_of(turning, known)
    direction = _angle_of(sliding, known)  # -K's distance from the slider's line
    reach = abs(K[0] * math.sin(direction) - K[1] * math.cos(direction))
    if reach > r_a * (1 + DEAD_CENTRE):
        raise NoClosure(
            NoClosure.CANNOT_CLOSE,
            where,
            f"{_link(turning, r_a)} cannot reach the slider's line {reach:.6g} away",
        )
    if abs(reach - r_a) <= DEAD_CENTRE * r_a:
        raise NoClosure(NoClosure.SINGULAR, where, "the link closes only square to the slider")


def _length_of(vector: Vector, known: Mapping[str, float]) -> float:
    return abs(known[vector.length] if isinstance(vector.length, str) else vector.length)


def _angle_of(vector: Vector, known: Mapping[str, float]) -> float:
    if isinstance(vector.angle, str):
        return known[vector.angle] + vector.offset
    return vector.angle


def _link(vector: Vector, length: float) -> str:
    return f"{vector.label or 'the link'} = {length:.6g}"
