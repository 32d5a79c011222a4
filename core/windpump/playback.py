"""A run resampled for playing it back as an animation, and the piston's travel to draw it with.

A run's samples are every pi/16 of crank angle: tens of thousands for the paper's example, far
more than an animation needs. :func:`playback_frames` keeps a uniform time grid coarse enough to
send to a browser once per run, fine enough that interpolating between frames stays on the run.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .design import Design
from .dynamics import SimulationResult
from .kinematics import piston_position
from .validation import positive, whole

MAX_FRAMES = 4000
"""Most frames :func:`playback_frames` returns by default."""

MOST_FRAMES = 1_000_000
"""Largest ``max_frames`` of :func:`playback_frames` and ``points`` of :func:`piston_table` (a
run has at most ``windpump.MAX_SAMPLES`` samples to draw frames from)."""


@dataclasses.dataclass(frozen=True)
class Playback:
    """A run on a uniform time grid: time [s], crank angle [rad] (unwrapped), crank speed
    [rad/s] and volume pumped [m^3] at each frame."""

    t: np.ndarray
    theta: np.ndarray
    theta_dot: np.ndarray
    volume: np.ndarray


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
    return Playback(
        t=t,
        theta=np.interp(t, run.t, run.theta),
        theta_dot=np.interp(t, run.t, run.theta_dot),
        volume=np.interp(t, run.t, run.volume),
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
