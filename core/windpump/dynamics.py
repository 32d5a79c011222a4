"""The full equation of motion, Eq. (12), integrated without averaging: :func:`simulate`."""

from __future__ import annotations

import dataclasses
import io
import math
import os

import numpy as np

from . import _kernels
from .design import UNITS, Design
from .validation import ParameterError, non_negative, positive, real

SAMPLES_PER_STROKE = 16
"""Output samples per half revolution (per stroke) of the crank."""

MAX_SAMPLES = 1_000_000
"""Largest number of samples a run may produce; a longer request is refused before any work."""

MAX_STEPS = 20 * MAX_SAMPLES
"""Largest number of integration steps a run may take (a stiff design hits this)."""

SMALLEST_KICK = 1e-300
"""Smallest non-zero initial crank speed [rad/s]."""

RTOL = 1e-8
"""Local relative tolerance of the integrator (u = theta_dot^2/2, and the time per step)."""


@dataclasses.dataclass(frozen=True)
class SimulationResult:
    """A run of :func:`simulate`: samples on one time grid, and how the run ended.

    Samples are taken at the start, at every crank angle ``k pi / samples_per_stroke`` (so every dead
    centre, where the load switches, is a sample), and at the end. Arrays are read-only.

    Attributes
    ----------
    design : Design
        The design that was run.
    t : ndarray
        Time [s], from 0.
    theta : ndarray
        Crank angle from TDC [rad], unwrapped.
    theta_dot : ndarray
        Crank speed [rad/s].
    volume : ndarray
        Water pumped since t = 0 [m^3].
    flow : ndarray
        Instantaneous volume flow rate [m^3/s]: zero while the cylinder takes water in.
    shaft_work : ndarray
        Work done by the windmill on its shaft since t = 0 [J] (the integral of T omega).
    stalled : bool
        True when the crank speed reached zero (or started at zero): the run ends there.
    t_stall : float or None
        When it stalled [s]; None when it ran to ``t_end``.
    """

    design: Design
    t: np.ndarray
    theta: np.ndarray
    theta_dot: np.ndarray
    volume: np.ndarray
    flow: np.ndarray
    shaft_work: np.ndarray
    stalled: bool
    t_stall: float | None

    @property
    def omega(self) -> np.ndarray:
        """Windmill speed R+ theta_dot [rad/s] (Eq. 4)."""
        return self.design.R_dagger * self.theta_dot

    @property
    def kinetic_energy(self) -> np.ndarray:
        """Kinetic energy of the rotating parts, I_eff theta_dot^2 / 2 [J]."""
        return 0.5 * self.design.I_eff * self.theta_dot**2

    @property
    def lift_work(self) -> np.ndarray:
        """Work done lifting water, rho_w g h V [J]."""
        d = self.design
        return d.rho_w * d.g * d.h * self.volume

    def revolutions(self) -> tuple[np.ndarray, np.ndarray]:
        """Start and end times [s] of each complete crank revolution from theta0.

        Revolutions are counted from the initial angle: the k-th ends where
        ``theta = theta0 + 2 pi k``, found by interpolating the unwrapped angle in time.
        """
        theta0 = self.theta[0]
        full = int(math.floor((self.theta[-1] - theta0) / (2 * math.pi)))
        marks = theta0 + 2 * math.pi * np.arange(full + 1)
        times = np.interp(marks, self.theta, self.t)
        return times[:-1], times[1:]

    def cycle_mean_speed(self) -> tuple[np.ndarray, np.ndarray]:
        """Cycle-mean crank speed of each complete revolution: (mid-times [s], speeds [rad/s]).

        The time average of theta_dot over a revolution is exactly 2 pi / (its duration): the
        quantity the averaged theory (Eqs. 19-24) describes.
        """
        start, end = self.revolutions()
        return 0.5 * (start + end), 2 * math.pi / (end - start)

    def intermittency(self, revolutions: int = 10) -> Intermittency:
        """Flow and speed figures over the last ``revolutions`` complete revolutions.

        Raises ``ValueError`` when the run has no complete revolution.
        """
        revolutions = int(positive("revolutions", revolutions))
        start, end = self.revolutions()
        if len(start) == 0:
            raise ValueError("the run has no complete crank revolution to measure")
        start, end = start[-revolutions:], end[-revolutions:]
        volume = np.interp([start[0], end[-1]], self.t, self.volume)
        mean_flow = (volume[1] - volume[0]) / (end[-1] - start[0])
        mean_speed = 2 * math.pi * len(start) / (end[-1] - start[0])
        window = (self.t >= start[0]) & (self.t <= end[-1])
        peak_flow = float(self.flow[window].max())
        ripple = 0.0
        for t0, t1 in zip(start, end, strict=True):
            speed = self.theta_dot[(self.t >= t0) & (self.t <= t1)]
            ripple = max(ripple, float(np.ptp(speed)) * (t1 - t0) / (2 * math.pi))
        return Intermittency(
            mean_flow=float(mean_flow),
            peak_flow=peak_flow,
            peak_to_mean=float(peak_flow / mean_flow) if mean_flow > 0 else math.inf,
            mean_speed=float(mean_speed),
            speed_ripple=ripple,
        )

    def last_revolutions(self, revolutions: int = 3) -> slice:
        """The samples from the start of the last ``revolutions`` complete revolutions to the run's
        end: a close-up of the steady pulses, or of the last turns before a stall.

        A run with fewer complete revolutions gives all of its samples.

        Examples
        --------
        >>> from windpump import Design, simulate
        >>> run = simulate(Design.seed_example(), 60.0)
        >>> window = run.last_revolutions(3)  # 3 whole turns, and the part of one after them
        >>> 3 <= float(run.theta[window][-1] - run.theta[window][0]) / (2 * math.pi) < 4
        True
        """
        revolutions = int(positive("revolutions", revolutions))
        start, _ = self.revolutions()
        if len(start) == 0:
            return slice(0, len(self.t))
        first = start[-min(revolutions, len(start))]
        return slice(int(np.searchsorted(self.t, first, side="left")), len(self.t))

    def to_csv(
        self, path: str | os.PathLike | io.TextIOBase | None = None, litres: bool = False
    ) -> str | None:
        """Write the samples as CSV; return the text if no path is given.

        The first lines, each starting with ``#``, record the design (every parameter with its
        unit) and the run's start and end; then a row of column names with units. With
        ``litres=True`` volume and flow are in L and L/s instead of m^3 and m^3/s.

        Examples
        --------
        >>> from windpump import Design, simulate
        >>> text = simulate(Design.seed_example(), 1.0).to_csv(litres=True)
        >>> [line for line in text.splitlines() if line.startswith("# h ")]
        ['# h = 3 m']
        >>> text.splitlines()[len(UNITS) + 2]
        't [s],theta [rad],theta_dot [rad/s],volume [L],flow [L/s],shaft_work [J]'
        """
        scale, volume_unit = (1e3, "L") if litres else (1.0, "m^3")
        columns = {
            "t [s]": self.t,
            "theta [rad]": self.theta,
            "theta_dot [rad/s]": self.theta_dot,
            f"volume [{volume_unit}]": scale * self.volume,
            f"flow [{volume_unit}/s]": scale * self.flow,
            "shaft_work [J]": self.shaft_work,
        }
        buffer = io.StringIO()
        buffer.write("# windpump run of the design (Louge 2010, Eq. 12)\n")
        for name, value in self.design.as_dict().items():
            buffer.write(f"# {name} = {value:.12g} {UNITS[name]}\n")
        ending = f"stalled at t = {self.t_stall:.12g} s" if self.stalled else "ran to its end"
        buffer.write(
            f"# theta0 = {self.theta[0]:.12g} rad, theta_dot0 = {self.theta_dot[0]:.12g} rad/s, "
            f"t_end = {self.t[-1]:.12g} s, {ending}\n"
        )
        buffer.write(",".join(columns) + "\n")
        np.savetxt(buffer, np.column_stack(list(columns.values())), delimiter=",", fmt="%.12g")
        if path is None:
            return buffer.getvalue()
        if isinstance(path, io.TextIOBase):
            path.write(buffer.getvalue())
        else:
            with open(path, "w", encoding="utf-8") as f:
                f.write(buffer.getvalue())
        return None


@dataclasses.dataclass(frozen=True)
class Intermittency:
    """Figures of the pulsing flow over whole revolutions (see SimulationResult.intermittency).

    Attributes
    ----------
    mean_flow : float
        Volume pumped / time [m^3/s].
    peak_flow : float
        Largest instantaneous flow [m^3/s].
    peak_to_mean : float
        peak_flow / mean_flow [-] (about pi for a slow single-acting pump with a long rod).
    mean_speed : float
        Cycle-mean crank speed [rad/s].
    speed_ripple : float
        Largest (max - min) / mean of the crank speed within one revolution [-].
    """

    mean_flow: float
    peak_flow: float
    peak_to_mean: float
    mean_speed: float
    speed_ripple: float


def sample_bound(design: Design, t_end: float, theta_dot0: float) -> float:
    """Most samples :func:`simulate` can produce for this run (the crank speed never exceeds
    max(theta_dot0, 2 omega_m / R+), where the windmill torque turns negative). A float: it may be
    too large for an integer."""
    fastest = max(theta_dot0, 2 * design.omega_m / design.R_dagger)
    return fastest * t_end / (math.pi / SAMPLES_PER_STROKE) + 3


def simulate(
    design: Design, t_end: float, theta0: float = math.pi / 2, theta_dot0: float = 3.0
) -> SimulationResult:
    """Integrate the wind pump's equation of motion, Eq. (12), in full, from rest angle and kick.

    ``I_eff theta_ddot = R+^2 T_m (theta_dot/omega_m)(2 - R+ theta_dot/omega_m)
    + rho_w g h A R sin(theta + theta_c)/cos(theta_c)`` while exhausting (the last term is negative
    there), with no load while taking water in; ``V`` from Eq. (16). No averaging: finite L/R, the
    windmill torque of Eq. (11) and the load switched at every dead centre.

    Parameters
    ----------
    design : Design
        The wind pump.
    t_end : float
        Duration [s], > 0; bounded so the run makes at most ``MAX_SAMPLES`` samples.
    theta0 : float, default pi/2
        Initial crank angle from TDC [rad].
    theta_dot0 : float, default 3.0
        Initial crank speed [rad/s]: 0 (the windmill has no torque at rest, so the pump never
        starts) or at least ``SMALLEST_KICK``.

    Returns
    -------
    SimulationResult
        ``t, theta, theta_dot, volume, flow, shaft_work`` and ``stalled, t_stall``. When the crank
        speed reaches 0 the run ends there: ``stalled=True`` and ``t_stall`` [s].

    Raises
    ------
    ParameterError
        (a ValueError) for an argument out of range, naming it, its value and the allowed range.

    Examples
    --------
    >>> import math
    >>> from windpump import Design, simulate
    >>> run = simulate(Design.seed_example(), 600.0, theta0=math.pi / 2, theta_dot0=3.0)
    >>> run.stalled, round(float(run.theta_dot[-1]), 1)
    (False, 23.6)
    """
    if not isinstance(design, Design):
        raise TypeError(f"design must be a windpump.Design, not {type(design).__name__}")
    t_end = positive("t_end", t_end, "s")
    theta0 = real("theta0", theta0, "rad")
    theta_dot0 = non_negative("theta_dot0", theta_dot0, "rad/s")
    if 0.0 < theta_dot0 < SMALLEST_KICK:
        raise ParameterError(
            "theta_dot0",
            theta_dot0,
            f"0 or >= {SMALLEST_KICK:g} rad/s",
            "rad/s",
            why="a smaller kick is below double precision's normal range",
        )
    bound = sample_bound(design, t_end, theta_dot0)
    if bound > MAX_SAMPLES:
        longest = t_end * (MAX_SAMPLES - 3) / (bound - 3)
        raise ParameterError(
            "t_end",
            t_end,
            f"<= {longest:.6g} s for this design and theta_dot0",
            "s",
            why=f"the run could need {bound:.3g} samples; the bound is {MAX_SAMPLES}",
        )
    capacity = math.ceil(bound)
    params = _kernels.pack_params(
        design.R_dagger,
        design.T_m,
        design.omega_m,
        design.I_eff,
        design.load_torque,
        design.L_over_R,
    )
    out = np.empty((capacity, 6))
    n, outcome, _ = _kernels.integrate(
        params, theta0, theta_dot0, t_end, SAMPLES_PER_STROKE, RTOL, MAX_STEPS, out
    )
    if outcome == _kernels.OVER_BUDGET:
        raise ValueError(
            f"the integration needed more than {MAX_STEPS} steps: the design is too stiff "
            f"(its spin-up takes less than a crank revolution); increase I0 or I1"
        )
    samples = out[:n]
    strokes = samples[:, _kernels.OUT_STROKES]
    theta_dot = samples[:, _kernels.OUT_THETA_DOT].copy()
    arrays = [
        samples[:, _kernels.OUT_T].copy(),
        samples[:, _kernels.OUT_THETA].copy(),
        theta_dot,
        design.stroke_volume * (strokes - strokes[0]),
        design.stroke_volume * samples[:, _kernels.OUT_F2] * theta_dot,  # Eq. (16)
        samples[:, _kernels.OUT_WORK].copy(),
    ]
    for array in arrays:
        array.flags.writeable = False
    stalled = outcome == _kernels.STALLED
    return SimulationResult(
        design, *arrays, stalled=stalled, t_stall=float(arrays[0][-1]) if stalled else None
    )
