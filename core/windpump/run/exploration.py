"""One call for everything known about a design and a kick: the full run and the averaged theory."""

from __future__ import annotations

import dataclasses
import enum
import functools
import math

import numpy as np

from ..averaging.averaged import (
    averaged_stall_time,
    spinup,
    stall_margin,
    steady_speeds,
    time_constant,
)
from ..averaging.operating import OperatingPoint, operating_point
from ..model.design import Design
from ..model.loads import starts_from_rest
from ..validation import whole
from .dynamics import Intermittency, SimulationResult, simulate
from .energy import EnergyTotals, power_budget


class Status(enum.Enum):
    """How a run went, in words anyone can read at a glance."""

    RUNNING = "running"
    """Still turning at t_end, and the windmill can carry the load (margin > 1, Eq. 22)."""
    SLOWING = "slowing to a stall"
    """Still turning at t_end, but the margin is 1 or less: the averaged theory says it will stall."""
    STALLED = "stalled"
    """It was turning and came to rest: the load won (the margin is 1 or less, or ripple)."""
    NEVER_STARTED = "never started"
    """It could not get going: stuck at rest from the start, or kicked below alpha- (Eq. 21)."""


class NotStarted(enum.Enum):
    """Why a run never started (:attr:`Exploration.not_started`)."""

    NO_KICK = "no kick, and no torque at rest"
    """Left at rest (theta_dot0 = 0) with a windmill that has no torque at rest (T_0 = 0)."""
    HELD_AT_REST = "held at rest by the load"
    """Left at rest, the windmill's torque at rest R+ T_0 could not beat the load at theta0."""
    KICK_TOO_SMALL = "kicked too gently"
    """Kicked below alpha- (Eq. 21), or with no running speed at all: it came to rest."""


@dataclasses.dataclass(frozen=True)
class Exploration:
    """A design run in full (Eq. 12) beside the averaged theory (Eqs. 19-25) and the operating point.

    Attributes
    ----------
    run : SimulationResult
        The full integration.
    theta_dot0 : float
        The kick [rad/s].
    margin : float
        Stall margin of Eq. (22) [-].
    alpha_plus, alpha_minus : float or None
        Steady cycle-mean crank speeds of Eq. (21) [rad/s]; None when the margin is 1 or less.
    tau : float or None
        Spin-up time constant of Eq. (25) [s]; None when the margin is 1 or less.
    averaged_t_stall : float or None
        When the averaged model stalls [s] (kicked below alpha-, or margin <= 1); else None.
    spinup_t, spinup_speed : ndarray
        The averaged spin-up of Eq. (24) [s], [rad/s], on ``points`` times over the run.
    cycle_t, cycle_speed : ndarray
        The integration's cycle-mean crank speed per revolution [s], [rad/s].
    intermittency : Intermittency or None
        Flow and speed figures over the last revolutions; None without a complete revolution.
    operating_point : OperatingPoint or None
        Eq. (5) against Eq. (11); None when the margin is 1 or less.
    status : Status
    starts_from_rest : bool
        Whether the windmill's torque at rest turns the crank from any angle
        (:func:`windpump.starts_from_rest`).
    """

    run: SimulationResult
    theta_dot0: float
    margin: float
    alpha_plus: float | None
    alpha_minus: float | None
    tau: float | None
    averaged_t_stall: float | None
    spinup_t: np.ndarray
    spinup_speed: np.ndarray
    cycle_t: np.ndarray
    cycle_speed: np.ndarray
    intermittency: Intermittency | None
    operating_point: OperatingPoint | None
    status: Status
    starts_from_rest: bool = False

    @property
    def design(self) -> Design:
        return self.run.design

    @property
    def not_started(self) -> NotStarted | None:
        """Why the run never started; None when it did (any status but ``NEVER_STARTED``).

        Examples
        --------
        >>> from windpump import Design, explore
        >>> explore(Design.seed_example(), 60.0, theta_dot0=0.0).not_started.value
        'no kick, and no torque at rest'
        >>> explore(Design.seed_example(), 60.0).not_started is None
        True
        """
        if self.status is not Status.NEVER_STARTED:
            return None
        if self.theta_dot0 == 0.0 and self.design.T_0 == 0.0:
            return NotStarted.NO_KICK
        if self.run.t_stall == 0.0:
            return NotStarted.HELD_AT_REST
        return NotStarted.KICK_TOO_SMALL

    @property
    def pumped_volume(self) -> float:
        """Water pumped over the run [m^3]."""
        return float(self.run.volume[-1])

    @functools.cached_property
    def energy_totals(self) -> EnergyTotals:
        """Where the windmill's work went over the run [J] (:meth:`windpump.PowerBudget.totals`), computed
        once: the page's waterfall and its energy readout both read it."""
        return power_budget(self.run).totals()

    @property
    def volumetric_efficiency(self) -> float:
        """Water delivered over the volume the pistons swept [-] (:attr:`SimulationResult.
        volumetric_efficiency`): below 1 with a leak hole."""
        return self.run.volumetric_efficiency

    @property
    def overall_efficiency(self) -> float:
        """Lifted water's energy over the windmill's work, rho_w g h V / W [-]
        (:attr:`SimulationResult.overall_efficiency`)."""
        return self.run.overall_efficiency

    @property
    def mean_flow(self) -> float:
        """Water pumped over the run / its duration [m^3/s] (0 for a run of no duration)."""
        duration = float(self.run.t[-1])
        return self.pumped_volume / duration if duration > 0 else 0.0


def explore(
    design: Design,
    t_end: float,
    theta0: float = math.pi / 2,
    theta_dot0: float = 3.0,
    points: int = 400,
) -> Exploration:
    """Run a design in full and beside the averaged theory, as the paper's Fig. 3 does.

    Parameters
    ----------
    design : Design
    t_end, theta0, theta_dot0 : float
        As for :func:`windpump.simulate` [s], [rad], [rad/s].
    points : int, default 400
        Times at which the averaged spin-up (Eq. 24) is evaluated, evenly over the run: a whole
        number from 2 to 100,000.

    Raises
    ------
    ParameterError
        For an argument out of range (see :func:`windpump.simulate`).

    Examples
    --------
    >>> from windpump import Design, explore
    >>> seen = explore(Design.seed_example(), 600.0)
    >>> seen.status.value, round(seen.alpha_plus, 2), round(seen.tau, 1)
    ('running', 23.71, 78.6)
    """
    points = whole("points", points, 2, 100_000)
    run = simulate(design, t_end, theta0, theta_dot0)
    margin = stall_margin(design)
    alpha_plus = alpha_minus = tau = point = None
    if margin > 1.0:
        alpha_plus, alpha_minus = steady_speeds(design)
        tau = time_constant(design)
        point = operating_point(design)
    spinup_t = np.linspace(0.0, float(run.t[-1]), points)
    cycle_t, cycle_speed = run.cycle_mean_speed()
    whole_revolutions = len(cycle_t) > 0
    return Exploration(
        run=run,
        theta_dot0=float(theta_dot0),
        margin=margin,
        alpha_plus=alpha_plus,
        alpha_minus=alpha_minus,
        tau=tau,
        averaged_t_stall=averaged_stall_time(design, theta_dot0),
        spinup_t=spinup_t,
        spinup_speed=spinup(design, spinup_t, theta_dot0),
        cycle_t=cycle_t,
        cycle_speed=cycle_speed,
        intermittency=run.intermittency() if whole_revolutions else None,
        operating_point=point,
        status=_status(run, margin, alpha_minus, theta_dot0),
        starts_from_rest=starts_from_rest(design),
    )


def _status(run: SimulationResult, margin: float, alpha_minus, theta_dot0: float) -> Status:
    if not run.stalled:
        return Status.RUNNING if margin > 1.0 else Status.SLOWING
    if run.t_stall == 0.0 or (alpha_minus is not None and 0.0 < theta_dot0 < alpha_minus):
        return Status.NEVER_STARTED
    return Status.STALLED
