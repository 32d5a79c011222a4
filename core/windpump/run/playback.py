"""A run resampled for playing it back as an animation, with where every moving part is.

A run's samples are every pi/16 of crank angle: tens of thousands for the paper's example, far
more than an animation needs. :func:`playback_frames` keeps a uniform time grid coarse enough to
send to a browser once per run, fine enough that interpolating between frames stays on the run,
and :func:`crank_table` gives every crank pin and piston over one revolution, so that a player
interpolates and draws and computes no kinematics of its own.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..model.design import Design
from ..model.kinematics import cylinder_angles, piston_position
from ..validation import positive, whole
from .dynamics import SimulationResult

__all__ = [
    "MAX_FRAMES",
    "CrankTable",
    "Playback",
    "crank_table",
    "piston_table",
    "playback_frames",
]


MAX_FRAMES = 4000
"""Most frames :func:`playback_frames` returns by default."""

MOST_FRAMES = 1_000_000
"""Largest ``max_frames`` of :func:`playback_frames` and ``points`` of :func:`piston_table` (a
run has at most ``windpump.MAX_SAMPLES`` samples to draw frames from)."""


@dataclasses.dataclass(frozen=True)
class CrankTable:
    """Where each cylinder's moving parts are over one revolution of the crank, in its own crank's
    frame: the crank's centre at the origin, y along the cylinder's axis towards its head, x such
    that the crank turns anticlockwise seen this way (a pin at ``(-R sin phi, R cos phi)``).

    Cylinder k runs ``2 pi k / n`` behind the first (n = cylinders): its parts at crank angle theta
    are the first's at ``theta - 2 pi k / n``. Rows are cylinders, columns the angles.

    Attributes
    ----------
    theta : ndarray
        The first cylinder's crank angle from its TDC [rad], evenly from 0 to 2 pi.
    piston : ndarray
        Each piston's distance from its TDC [m] (Eq. 1), shape (cylinders, angles).
    pin_x, pin_y : ndarray
        Each crank pin [m], shape (cylinders, angles).
    piston_y : ndarray
        Each piston (gudgeon) pin's height above its crank's centre [m], ``L + R - piston``.
    """

    theta: np.ndarray
    piston: np.ndarray
    pin_x: np.ndarray
    pin_y: np.ndarray
    piston_y: np.ndarray


@dataclasses.dataclass(frozen=True)
class Playback:
    """A run on a uniform time grid, with what an animation of it draws at each frame.

    Between frames a player interpolates: both angles by cubic Hermite with their speeds, the
    volume and the tank's level linearly, and each part's position in :attr:`table` at the
    interpolated crank angle (linearly: its angles are half a degree apart by default).

    Attributes
    ----------
    t : ndarray
        Time [s].
    theta, theta_dot : ndarray
        Crank angle (unwrapped) [rad] and crank speed [rad/s].
    volume : ndarray
        Water pumped since t = 0 [m^3].
    rotor_angle, rotor_speed : ndarray
        The windmill's angle ``R+ theta`` [rad] and speed ``R+ theta_dot`` [rad/s] (Eq. 4).
    tank_level : ndarray
        The tank's level [-]: the volume pumped over the run's whole volume, 0 (empty) to 1 (full
        at the end); 0 throughout for a run that pumps nothing.
    pistons : ndarray
        Each piston's distance from its TDC [m] (Eq. 1, cylinder k ``2 pi k / n`` behind the
        first), shape (cylinders, frames).
    table : CrankTable or None
        The parts over one revolution (:func:`crank_table`), to draw between frames.
    """

    t: np.ndarray
    theta: np.ndarray
    theta_dot: np.ndarray
    volume: np.ndarray
    rotor_angle: np.ndarray | None = None
    rotor_speed: np.ndarray | None = None
    tank_level: np.ndarray | None = None
    pistons: np.ndarray | None = None
    table: CrankTable | None = None


def playback_frames(
    run: SimulationResult, max_frames: int = MAX_FRAMES, max_turn: float = math.pi / 2
) -> Playback:
    """The run at evenly spaced times, at most ``max_turn`` of crank angle apart where
    ``max_frames`` allows it.

    Each frame is the run linearly interpolated between its samples (pi/16 of crank angle
    apart), so a frame's angle is the run's to within ``theta_ddot dt^2 / 8``. Between frames, a
    player interpolates with the crank speed (cubic Hermite), which stays on the run as long as
    the speed varies little within ``max_turn``.

    Parameters
    ----------
    run : SimulationResult
    max_frames : int, default MAX_FRAMES
        A whole number from 1 to ``MOST_FRAMES`` (1 gives 2 frames: the start and the end).
    max_turn : float, default pi/2
        Largest crank angle between frames when the frame budget allows [rad], > 0.

    Examples
    --------
    >>> from windpump import Design, simulate
    >>> frames = playback_frames(simulate(Design.seed_example(), 600.0))
    >>> len(frames.t), float(frames.t[-1])
    (4000, 600.0)
    """
    max_frames = max(2, whole("max_frames", max_frames, 1, MOST_FRAMES))  # 1 gives 2, as ever
    max_turn = positive("max_turn", max_turn, "rad")
    # Frames dt apart turn at most max(theta_dot) dt: enough of them keep every gap <= max_turn.
    fastest_turn = float(np.max(run.theta_dot)) * float(run.t[-1])
    count = min(max_frames, max(2, math.ceil(fastest_turn / max_turn) + 1))
    t = np.linspace(0.0, float(run.t[-1]), count)
    design = run.design
    theta = np.interp(t, run.t, run.theta)
    theta_dot = np.interp(t, run.t, run.theta_dot)
    volume = np.interp(t, run.t, run.volume)
    full = float(run.volume[-1])
    tank_level = np.clip(volume / full, 0.0, 1.0) if full > 0.0 else np.zeros_like(volume)
    return Playback(
        t=t,
        theta=theta,
        theta_dot=theta_dot,
        volume=volume,
        rotor_angle=design.R_dagger * theta,
        rotor_speed=design.R_dagger * theta_dot,
        tank_level=tank_level,
        pistons=piston_position(cylinder_angles(theta, design.cylinders), design.R, design.L),
        table=crank_table(design),
    )


def crank_table(design: Design, points: int = 721) -> CrankTable:
    """Every cylinder's crank pin and piston over one revolution: what a drawing interpolates in
    at a crank angle instead of computing the slider-crank (Eq. 1) and the cylinders' lags itself.

    Parameters
    ----------
    design : Design
        Its crank radius R and rod length L [m], and its cylinders.
    points : int, default 721
        Angles from 0 to 2 pi inclusive (721: half a degree apart), 2 to 100,000.

    Returns
    -------
    CrankTable

    Examples
    --------
    >>> from windpump import Design
    >>> table = crank_table(Design.seed_example().replace(cylinders=2), 5)
    >>> [round(float(x), 4) for x in table.piston[1]]  # cylinder 1, half a turn behind
    [0.08, 0.0454, 0.0, 0.0454, 0.08]
    >>> round(float(table.pin_x[0, 1]), 3), round(float(table.piston_y[0, 0]), 3)  # [m]
    (-0.04, 0.19)
    """
    angles = np.linspace(0.0, 2 * math.pi, whole("points", points, 2, 100_000))
    own = cylinder_angles(angles, design.cylinders)
    piston = piston_position(own, design.R, design.L)
    return CrankTable(
        theta=angles,
        piston=piston,
        pin_x=-design.R * np.sin(own),
        pin_y=design.R * np.cos(own),
        piston_y=design.L + design.R - piston,
    )


def piston_table(design: Design, points: int = 721) -> tuple[np.ndarray, np.ndarray]:
    """Crank angles over one revolution [rad] and the piston's distance from TDC there [m]
    (Eq. 1): what a drawing interpolates in instead of evaluating Eq. (1) itself.

    Examples
    --------
    >>> from windpump import Design
    >>> theta, x = piston_table(Design.seed_example(), 5)
    >>> [round(float(v), 4) for v in x]  # TDC, quarter turn, BDC, three quarters, TDC
    [0.0, 0.0454, 0.08, 0.0454, 0.0]
    """
    theta = np.linspace(0.0, 2 * math.pi, whole("points", points, 1, MOST_FRAMES))
    return theta, piston_position(theta, design.R, design.L)
