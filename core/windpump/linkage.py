"""Planar linkages by Newton-Raphson loop closure (second seed, "Newton-Raphson Method: Application").

A closed loop of a planar mechanism is a chain of vectors that sums to zero,

    sum_i s_i r_i (cos phi_i, sin phi_i) = 0,

two scalar equations that fix two unknowns: two angles (a four-bar), or an angle and a length (a
slider-crank). Newton-Raphson solves ``J dq = -F`` with the analytic 2x2 Jacobian from a guess; the
guess picks the assembly (the branch). Mechanisms of several loops (the seed's double loop, a Watt
six-bar) are solved loop by loop, each loop's known angles coming from the loops before it.

A loop is a tuple of :class:`Vector`; a length or an angle is a number, or a name whose value is
known (given, or found by an earlier loop) or is one of the loop's two unknowns.
"""

from __future__ import annotations

import dataclasses
import math
import typing
from collections.abc import Mapping, Sequence

import numpy as np

from .errors import NoClosure, ParameterError
from .validation import positive, real

TOL = 1e-13
"""Newton-Raphson stops once a step is smaller than this [rad; lengths relative to the loop's size]."""

MAX_ITERATIONS = 50
"""Iteration budget of one loop closure."""

MAX_STEP = 1.0
"""Largest Newton step [rad; lengths relative to the loop]: far from the root, a full step can leap."""

DEAD_CENTRE = 1e-12
"""Relative closeness to a dead centre (links in line, singular Jacobian) treated as one."""

ROUND_OFF = 8 * np.finfo(float).eps
"""A residual this small, relative to the loop's size, cannot be improved by another step."""

BLOCKED_HALVINGS = 30
"""A Newton step halved this often without staying on the guess's branch is blocked."""

MAX_HALVINGS = 12
"""A sweep halves a step up to this many times to stay on its branch."""


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
    """

    length: float | str
    angle: float | str
    sign: int = 1
    offset: float = 0.0
    label: str = ""

    def __post_init__(self):
        if self.sign not in (1, -1):
            raise ParameterError("sign", self.sign, "+1 or -1")
        if not isinstance(self.length, str):
            real("length", self.length, "m")
        if not isinstance(self.angle, str):
            real("angle", self.angle, "rad")
        real("offset", self.offset, "rad")

    def resolve(self, values: Mapping[str, float]) -> tuple[float, float]:
        """(signed length, angle) with the names looked up in ``values``."""
        length = values[self.length] if isinstance(self.length, str) else self.length
        angle = values[self.angle] + self.offset if isinstance(self.angle, str) else self.angle
        return self.sign * length, angle


Loop = tuple[Vector, ...]


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
        The unknowns at the guess and after every Newton step, shape (iterations + 1, 2).
    residuals : ndarray
        ``|F|`` relative to the loop's size at each iterate [-]: it falls quadratically near the root.
    branch : int
        The assembly found: minus the sign of the Jacobian's determinant at the solution, the
        convention under which a four-bar's branch is :func:`four_bar_branch` (+1 with B left of
        the line from A to D, as the Mechanisms tab labels it). A sweep that follows one branch
        keeps it; it changes only through a dead centre.
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


def names_in(loop: Sequence[Vector]) -> list[str]:
    """The names a loop uses, in order of appearance."""
    found = [part for v in loop for part in (v.length, v.angle) if isinstance(part, str)]
    return list(dict.fromkeys(found))


def residual(loop: Sequence[Vector], values: Mapping[str, float]) -> np.ndarray:
    """The loop's two closure equations F = sum_i s_i r_i (cos phi_i, sin phi_i) [m]."""
    total = np.zeros(2)
    for vector in loop:
        length, angle = vector.resolve(values)
        total += length * np.array([math.cos(angle), math.sin(angle)])
    return total


def jacobian(
    loop: Sequence[Vector], values: Mapping[str, float], unknowns: Sequence[str]
) -> np.ndarray:
    """Analytic dF/d(unknowns), 2x2: ``s r (-sin phi, cos phi)`` for an angle, ``s (cos phi, sin
    phi)`` for a length (the seed's step 2, with dF2/dtheta3 = -r3 cos theta3)."""
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


def joints(loop: Sequence[Vector], values: Mapping[str, float], origin=(0.0, 0.0)) -> np.ndarray:
    """The loop's joints: the running sums of its vectors from ``origin`` [m], shape (n + 1, 2).

    A closed loop ends where it began. Use it to draw the mechanism.
    """
    points = [np.asarray(origin, dtype=float)]
    for vector in loop:
        length, angle = vector.resolve(values)
        points.append(points[-1] + length * np.array([math.cos(angle), math.sin(angle)]))
    return np.array(points)


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
        Size of the last step [rad; lengths relative to the loop's size].
    max_iterations : int
        Iteration budget.

    Returns
    -------
    Closure

    Raises
    ------
    NoClosure
        When the links cannot span the gap for these inputs, when the loop closes only at a dead
        centre or an iterate lands on one (singular Jacobian), or when the budget runs out or
        the iteration heads for the other branch (no convergence).

    Examples
    --------
    >>> loop = four_bar_loop(r1=1.0, r2=3.0, r3=2.5, r6=3.0)
    >>> closed = solve_loop(loop, {"theta1": 1.0}, {"theta2": 0.5, "theta3": 1.5})
    >>> round(closed["theta2"], 6), round(closed["theta3"], 6), closed.iterations
    (0.585642, 1.554646, 4)
    """
    loop = tuple(loop)
    tol = positive("tol", tol, "rad")
    known = {name: real(name, value) for name, value in known.items()}
    unknowns = tuple(name for name in names_in(loop) if name not in known)
    if len(unknowns) != 2:
        raise ValueError(
            f"a planar loop fixes two unknowns; this one has {len(unknowns)}: {list(unknowns)}"
        )
    where = {name: known[name] for name in names_in(loop) if name in known}
    q = np.array([real(f"guess[{name!r}]", _guess_of(guess, name)) for name in unknowns])
    scale = _check_closable(loop, known, unknowns, where)
    units = np.array([1.0 if _is_angle(loop, name) else scale for name in unknowns])
    iterates, residuals, last_step, branch = [q.copy()], [], math.inf, 0
    for iteration in range(max_iterations + 1):
        values = {**known, **dict(zip(unknowns, map(float, q), strict=True))}
        F, J = residual(loop, values), jacobian(loop, values, unknowns)
        residuals.append(math.hypot(*F) / scale)
        if residuals[-1] <= ROUND_OFF or last_step <= tol:
            branch = _branch(J)
            return Closure(values, unknowns, np.array(iterates), np.array(residuals), branch)
        if iteration == max_iterations:
            break
        if _in_line(J):
            raise NoClosure(
                NoClosure.SINGULAR,
                where,
                f"iterate {iteration} ({_show(unknowns, q)}) puts the links in line; "
                "start from another guess",
                iteration,
            )
        branch = branch or _branch(J)  # set at the guess, kept after
        dq = np.linalg.solve(J, -F)
        size = float(np.max(np.abs(dq) / units))
        shrink = min(1.0, MAX_STEP / size) if size > 0 else 1.0
        q_next, shortened = _step_on_branch(loop, known, unknowns, q, dq * shrink, branch)
        if q_next is None:
            raise NoClosure(
                NoClosure.NO_CONVERGENCE,
                where,
                f"from iterate {iteration} ({_show(unknowns, q)}) Newton-Raphson heads for the "
                "other assembly; start from a guess closer to the branch you want",
                iteration,
            )
        q = q_next
        last_step = math.inf if shortened or size > MAX_STEP else size
        iterates.append(q.copy())
    raise NoClosure(
        NoClosure.NO_CONVERGENCE,
        where,
        f"{max_iterations} iterations left |F| = {residuals[-1]:.3g} of the loop's size at "
        f"{_show(unknowns, q)}; start from a closer guess",
        max_iterations,
    )


def solve_loops(
    loops: Sequence[Sequence[Vector]],
    known: Mapping[str, float],
    guess: Mapping[str, float],
    tol: float = TOL,
) -> list[Closure]:
    """Close loops one after another, each using what the loops before it found (double loops).

    Returns one :class:`Closure` per loop; the last one's ``values`` hold every name.

    Examples
    --------
    >>> loops = watt_six_bar_loops(1.0, 3.0, 2.5, 3.0, r3p=1.5, r4=2.5, r5=2.0, r6p=2.5)
    >>> guess = {"theta2": 0.5, "theta3": 1.5, "theta4": 0.5, "theta5": 1.5}
    >>> closed = solve_loops(loops, {"theta1": 1.0}, guess)
    >>> [round(closed[-1][name], 4) for name in ("theta2", "theta3", "theta4", "theta5")]
    [0.5856, 1.5546, 0.2014, 1.5839]
    """
    values = dict(known)
    closures = []
    for loop in loops:
        closure = solve_loop(loop, values, guess, tol)
        closures.append(closure)
        values = closure.values
    return closures


@dataclasses.dataclass(frozen=True)
class Sweep:
    """A sweep of a mechanism's input along one branch, up to where the branch ends.

    Attributes
    ----------
    input : str
        The swept name.
    values : dict of ndarray
        Every name over the positions that closed [rad or m]. Angles are continuous (not wrapped).
    branches : tuple of int
        The branch of each loop (``Closure.branch``), kept along the sweep.
    stop : NoClosure or None
        Why the sweep ended before the last input value; None when every position closed.
    """

    input: str
    values: dict
    branches: tuple[int, ...]
    stop: NoClosure | None

    def __len__(self) -> int:
        return len(self.values[self.input])


def sweep(
    loops: Sequence[Sequence[Vector]],
    input: str,
    inputs,
    guess: Mapping[str, float],
    known: Mapping[str, float] | None = None,
    tol: float = TOL,
) -> Sweep:
    """Follow one branch of a mechanism as its input moves through ``inputs``.

    Each position starts Newton-Raphson from the last one, pushed on along the secant of the last
    two. A step that lands on another branch (the sign of a loop's Jacobian flips) or fails to
    converge is halved, up to ``MAX_HALVINGS`` times. The sweep ends, keeping the ``NoClosure``
    in ``stop``, where the loop cannot close or the branch reaches a dead centre.

    Examples
    --------
    >>> import numpy as np
    >>> loop = four_bar_loop(r1=2.0, r2=2.5, r3=2.0, r6=3.0)  # non-Grashof: the input rocks
    >>> swept = sweep([loop], "theta1", np.radians(np.arange(0, 360, 5)),
    ...               {"theta2": 0.5, "theta3": 1.5})
    >>> len(swept), round(float(np.degrees(swept.values["theta1"][-1]))), swept.stop.reason
    (26, 125, 'cannot close')
    """
    known = dict(known or {})
    inputs = np.asarray(inputs, dtype=float)
    closures = solve_loops(loops, {**known, input: float(inputs[0])}, guess, tol)
    branches = tuple(c.branch for c in closures)
    path, stop = [closures[-1].values], None
    for target in inputs[1:]:
        try:
            path.append(_advance(loops, input, path, float(target), branches, known, tol, 0))
        except NoClosure as error:
            stop = error
            break
    names = list(path[0])
    return Sweep(input, {name: np.array([p[name] for p in path]) for name in names}, branches, stop)


def _advance(loops, input, path, target, branches, known, tol, depth) -> dict:
    """The next position of a branch-following sweep, halving the step while it strays."""
    last = path[-1]
    previous = path[-2] if len(path) > 1 else last
    stride = last[input] - previous[input]
    ratio = (target - last[input]) / stride if stride else 0.0
    predicted = {name: last[name] + ratio * (last[name] - previous[name]) for name in last}
    try:
        closures = solve_loops(loops, {**known, input: target}, predicted, tol)
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


# -- the mechanisms of the seeds ------------------------------------------------------------


def four_bar_loop(r1: float, r2: float, r3: float, r6: float, phi6: float = 0.0) -> Loop:
    """The seed's four-bar loop R1 + R2 - R3 - R6 = 0: input theta1, unknowns theta2, theta3.

    Link 1 (the input, length r1) turns about the origin O; link 2 (the coupler) joins its tip A
    to B; link 3 (the output) joins B to the fixed pivot D = r6 (cos phi6, sin phi6).
    """
    return _four_bar_vectors(r1, r2, r3, r6, phi6, ("theta1", "theta2", "theta3"))


def four_bar(
    r1: float,
    r2: float,
    r3: float,
    r6: float,
    theta1: float,
    phi6: float = 0.0,
    guess: tuple[float, float] | None = None,
    tol: float = TOL,
) -> tuple[float, float]:
    """Coupler and output angles (theta2, theta3) of a four-bar for input angle theta1 [rad].

    Solves the seed's loop equations by Newton-Raphson::

        r1 cos theta1 + r2 cos theta2 - r3 cos theta3 - r6 cos phi6 = 0
        r1 sin theta1 + r2 sin theta2 - r3 sin theta3 - r6 sin phi6 = 0

    Parameters
    ----------
    r1, r2, r3, r6 : float
        Input, coupler, output and ground link lengths [m], > 0.
    theta1 : float
        Input angle [rad].
    phi6 : float, default 0
        Angle of the ground link from O to the output pivot D [rad].
    guess : (float, float), optional
        Starting (theta2, theta3) [rad]; it selects the assembly: Newton-Raphson keeps the sign
        of sin(theta3 - theta2). By default ``branch_guess(..., branch=+1)``, the compass
        construction with the joint B to the left of the line from A to D.
    tol : float
        Newton-Raphson's step tolerance [rad].

    Returns
    -------
    theta2 : float
        The angle of link 2, in [0, 2 pi) [rad].
    theta3 : float
        The angle of link 3, in [0, 2 pi) [rad].

    Raises
    ------
    NoClosure
        The links cannot meet at this theta1, or it is a dead centre, or no convergence.

    Examples
    --------
    >>> theta2, theta3 = four_bar(1.0, 3.0, 2.5, 3.0, theta1=1.0)  # a crank-rocker
    >>> round(theta2, 6), round(theta3, 6)
    (0.585642, 1.554646)
    >>> theta2, theta3 = four_bar(1.0, 3.0, 2.5, 3.0, theta1=1.0, guess=(5.5, 4.0))  # mirror
    >>> round(theta2, 6), round(theta3, 6)
    (5.038298, 4.069294)
    """
    r1, r2, r3, r6 = _lengths(r1=r1, r2=r2, r3=r3, r6=r6)
    theta1, phi6 = real("theta1", theta1, "rad"), real("phi6", phi6, "rad")
    if guess is None:
        guess = branch_guess(r1, r2, r3, r6, theta1, phi6, branch=1)
    closed = solve_loop(
        four_bar_loop(r1, r2, r3, r6, phi6),
        {"theta1": theta1},
        {"theta2": guess[0], "theta3": guess[1]},
        tol,
    )
    return _wrap(closed["theta2"]), _wrap(closed["theta3"])


def branch_guess(
    r1: float,
    r2: float,
    r3: float,
    r6: float,
    theta1: float,
    phi6: float = 0.0,
    branch: int = 1,
) -> tuple[float, float]:
    """A starting (theta2, theta3) on one branch of a four-bar, drawn as with compasses [rad].

    B is put where the circle of radius r2 about the input's tip A meets the circle of radius r3
    about the output pivot D (the cosine rule in triangle ABD), on the left of the line from A to
    D for ``branch=+1`` and on its right for ``-1`` (see :func:`four_bar_branch`). Where the circles
    do not meet, B is put on the line: Newton-Raphson then says why the loop cannot close.

    Examples
    --------
    >>> [round(angle, 3) for angle in branch_guess(1.0, 3.0, 2.5, 3.0, theta1=1.0)]
    [0.586, 1.555]
    """
    if branch not in (1, -1):
        raise ParameterError("branch", branch, "+1 or -1")
    A = r1 * np.array([math.cos(theta1), math.sin(theta1)])
    D = r6 * np.array([math.cos(phi6), math.sin(phi6)])
    d = math.dist(A, D)
    psi = math.atan2(D[1] - A[1], D[0] - A[0])  # direction from A to D
    cos_alpha = (r2**2 + d**2 - r3**2) / (2 * r2 * d) if d > r2 * 1e-300 else 0.0
    alpha = math.acos(min(1.0, max(-1.0, cos_alpha)))  # the angle DAB
    theta2 = psi + branch * alpha
    B = A + r2 * np.array([math.cos(theta2), math.sin(theta2)])
    return theta2, math.atan2(B[1] - D[1], B[0] - D[0])


def four_bar_branch(theta2: float, theta3: float) -> int:
    """Which assembly a four-bar is in: +1 when B is left of the line from A to D, -1 right.

    That is the sign of sin(theta3 - theta2), the sine of the angle from the coupler to the
    output link; 0 at a dead centre (coupler and output in line), where the branches meet.
    """
    return _sign(math.sin(theta3 - theta2))


def is_grashof(r1: float, r2: float, r3: float, r6: float) -> bool:
    """Grashof's condition s + l <= p + q: some link of the four-bar turns fully.

    With the shortest link as input (or ground) it turns all the way round; otherwise every
    moving link rocks between limits, where a branch-following sweep ends.
    """
    lengths = sorted(_lengths(r1=r1, r2=r2, r3=r3, r6=r6))
    return lengths[0] + lengths[3] <= lengths[1] + lengths[2]


def watt_six_bar_loops(
    r1: float,
    r2: float,
    r3: float,
    r6: float,
    r3p: float,
    r4: float,
    r5: float,
    r6p: float,
    phi6: float = 0.0,
    phi6p: float = 0.0,
    beta: float = 0.0,
) -> list[Loop]:
    """The seed's double loop as a Watt six-bar: two four-bars in series on a ternary link 3.

    Loop 1 is :func:`four_bar_loop`. Link 3 has a second arm r3p at ``theta3 + beta`` about D; it
    drives loop 2, ``r3p e(theta3 + beta) + r4 e(theta4) - r5 e(theta5) - r6p e(phi6p) = 0``, whose
    output link 5 turns about the fixed pivot E = D + r6p e(phi6p). Loop 2's known angle comes from
    loop 1's solution; draw it from D (``joints(loop2, values, origin=D)``).
    """
    r3p, r4, r5, r6p = _lengths(r3p=r3p, r4=r4, r5=r5, r6p=r6p)
    r1, r2, r3, r6 = _lengths(r1=r1, r2=r2, r3=r3, r6=r6)
    first = four_bar_loop(r1, r2, r3, r6, real("phi6", phi6, "rad"))
    second = _four_bar_vectors(
        r3p,
        r4,
        r5,
        r6p,
        real("phi6p", phi6p, "rad"),
        ("theta3", "theta4", "theta5"),
        real("beta", beta),
    )
    return [first, second]


def slider_crank_loop(R: float, L: float) -> Loop:
    """The pump's slider-crank as a loop: crank R at theta, rod L at phi, piston pin at s on the axis.

    ``R e(theta) + L e(phi) - s e(0) = 0``: unknowns the rod's angle phi and the pin's distance s from
    the crank centre, the cylinder axis along x and theta measured from it (from TDC).
    """
    R, L = _lengths(R=R, L=L)
    return (
        Vector(R, "theta", label="crank R"),
        Vector(L, "phi", label="rod L"),
        Vector("s", 0.0, sign=-1, label="piston"),
    )


def slider_crank(
    theta: float, R: float, L: float, guess: tuple[float, float] | None = None
) -> tuple[float, float]:
    """Piston position from TDC x [m] and rod angle theta_c [rad] by Newton-Raphson.

    The loop of :func:`slider_crank_loop` gives ``x = L + R - s`` and ``theta_c = -phi``, the
    rod's angle to the cylinder axis: on the usual branch (piston beyond the crank) this is Eq. (1)
    of the wind-pump paper and ``sin theta_c = sin theta / (L/R)``.

    Parameters
    ----------
    theta : float
        Crank angle from TDC [rad].
    R, L : float
        Crank radius and rod length [m] (L < R closes only where ``R |sin theta| <= L``).
    guess : (float, float), optional
        Starting (phi, s) [rad, m]; by default (0, L + R), the piston beyond the crank.

    Examples
    --------
    >>> import math
    >>> x, theta_c = slider_crank(math.pi / 2, R=0.04, L=0.15)
    >>> round(x, 6), round(math.degrees(theta_c), 4)
    (0.045432, 15.466)
    """
    pose = slider_crank_pose(theta, R, L, guess)
    return pose.x, pose.theta_c


class SliderCrankPose(typing.NamedTuple):
    """The slider-crank closed at one crank angle (see :func:`slider_crank_pose`)."""

    x: float
    """Piston position from TDC [m] (Eq. 1)."""
    theta_c: float
    """Rod angle to the cylinder axis [rad]."""
    joints: np.ndarray
    """Crank centre, crank pin and piston pin [m], the cylinder axis along +x, shape (3, 2)."""
    closure: Closure
    """The Newton-Raphson solution (iterates, residuals)."""


def slider_crank_pose(
    theta: float, R: float, L: float, guess: tuple[float, float] | None = None
) -> SliderCrankPose:
    """The slider-crank at crank angle theta, closed once: x, theta_c, the joints to draw it with
    and the Newton-Raphson history. Arguments as for :func:`slider_crank`.

    Examples
    --------
    >>> import math
    >>> pose = slider_crank_pose(math.pi / 2, R=0.04, L=0.15)
    >>> round(pose.x, 6), pose.joints.shape
    (0.045432, (3, 2))
    """
    theta = real("theta", theta, "rad")
    loop = slider_crank_loop(R, L)
    R, L = float(loop[0].length), float(loop[1].length)
    phi, s = guess if guess is not None else (0.0, L + R)
    closed = solve_loop(loop, {"theta": theta}, {"phi": phi, "s": s})
    return SliderCrankPose(
        x=L + R - closed["s"],
        theta_c=-math.remainder(closed["phi"], 2 * math.pi),
        joints=joints(loop, closed.values)[:3],
        closure=closed,
    )


# -- helpers -------------------------------------------------------------------------------


def _four_bar_vectors(r_in, r_coupler, r_out, r_ground, phi_ground, names, offset=0.0) -> Loop:
    theta_in, theta_coupler, theta_out = names
    labels = [f"r{name[5:]}" for name in names] + ["ground"]  # theta3 -> r3
    return (
        Vector(r_in, theta_in, offset=offset, label=labels[0]),
        Vector(r_coupler, theta_coupler, label=labels[1]),
        Vector(r_out, theta_out, sign=-1, label=labels[2]),
        Vector(r_ground, phi_ground, sign=-1, label=labels[3]),
    )


def _lengths(**lengths: float) -> typing.Any:
    """The lengths, checked, in order (a tuple of as many floats as given)."""
    return tuple(positive(name, value, "m") for name, value in lengths.items())


def _guess_of(guess: Mapping[str, float], name: str) -> float:
    if name not in guess:
        raise ParameterError("guess", dict(guess), f"a starting value for {name!r}")
    return guess[name]


def _is_angle(loop: Sequence[Vector], name: str) -> bool:
    return any(vector.angle == name for vector in loop)


def _link(vector: Vector, length: float) -> str:
    return f"{vector.label or 'the link'} = {length:.6g}"


def _angle_of(vector: Vector, known: Mapping[str, float]) -> float:
    if isinstance(vector.angle, str):
        return known[vector.angle] + vector.offset
    return vector.angle


def _in_line(J: np.ndarray) -> bool:
    """A singular Jacobian: its columns in line, to DEAD_CENTRE."""
    return abs(np.linalg.det(J)) <= DEAD_CENTRE * np.prod(np.linalg.norm(J, axis=0))


def _branch(J: np.ndarray) -> int:
    """The branch of a loop at a Jacobian J: -sign(det J). For the four-bar,
    det J = -r2 r3 sin(theta3 - theta2), so this is :func:`four_bar_branch`: one convention."""
    return -_sign(np.linalg.det(J))


def _step_on_branch(loop, known, unknowns, q, step, branch) -> tuple[np.ndarray | None, bool]:
    """q + step, halved while it would cross a dead centre (flip the sign of det J) onto the other
    branch, so Newton-Raphson keeps its guess's branch; also says whether it was halved. None
    when the step stays blocked: Newton-Raphson is heading for the other branch."""
    for halvings in range(BLOCKED_HALVINGS):
        trial = q + step
        values = {**known, **dict(zip(unknowns, map(float, trial), strict=True))}
        if _branch(jacobian(loop, values, unknowns)) == branch:
            return trial, halvings > 0
        step = 0.5 * step
    return None, True


def _wrap(angle: float) -> float:
    """The angle in [0, 2 pi) (a tiny negative angle would round to 2 pi)."""
    wrapped = angle % (2 * math.pi)
    return 0.0 if wrapped == 2 * math.pi else wrapped


def _sign(value: float) -> int:
    return int(value > 0) - int(value < 0)


def _show(unknowns, q) -> str:
    return ", ".join(f"{name} = {value:.6g}" for name, value in zip(unknowns, q, strict=True))


def _check_closable(loop, known, unknowns, where) -> float:
    """The loop's size [m], after the geometry's verdict where each unknown appears once (Chace's
    four cases of a planar vector equation): raise NoClosure if the links cannot span the gap K
    left by the known vectors, or span it only in line (a dead centre)."""
    lengths = [abs(v.length) for v in loop if not isinstance(v.length, str)]
    lengths += [abs(known[v.length]) for v in loop if v.length in known]
    scale = max(sum(lengths), np.finfo(float).tiny)
    carriers = [[v for v in loop if name in (v.length, v.angle)] for name in unknowns]
    if any(len(c) != 1 for c in carriers):
        return scale  # an unknown in two vectors: leave the verdict to Newton-Raphson
    (a,), (b,) = carriers
    K = residual([v for v in loop if v is not a and v is not b], known)
    gap = math.hypot(*K)
    if a is b:  # angle and length of one vector: it points at -K
        if gap <= DEAD_CENTRE * scale:
            raise NoClosure(NoClosure.SINGULAR, where, "the gap is zero, so the angle is free")
        return scale
    if a.length in unknowns and b.length in unknowns:  # two lengths on fixed directions
        if abs(math.sin(_angle_of(b, known) - _angle_of(a, known))) <= DEAD_CENTRE:
            raise NoClosure(NoClosure.SINGULAR, where, "the two sliding links are parallel")
        return scale
    if a.length in unknowns:
        a, b = b, a  # a: the vector turning through its angle; b: the one sliding
    r_a = abs(a.length if not isinstance(a.length, str) else known[a.length])
    if b.angle in unknowns:  # two unknown angles: the links must span |K|
        r_b = abs(b.length if not isinstance(b.length, str) else known[b.length])
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
        return scale
    direction = _angle_of(b, known)  # an angle and a slider's length: -K's distance from its line
    reach = abs(K[0] * math.sin(direction) - K[1] * math.cos(direction))
    if reach > r_a * (1 + DEAD_CENTRE):
        raise NoClosure(
            NoClosure.CANNOT_CLOSE,
            where,
            f"{_link(a, r_a)} cannot reach the slider's line {reach:.6g} away",
        )
    if abs(reach - r_a) <= DEAD_CENTRE * r_a:
        raise NoClosure(NoClosure.SINGULAR, where, "the link closes only square to the slider")
    return scale
