"""Where the power goes at start-up: to speed the machine up, and to lift its load (second seed).

The seed's ski lift must accelerate its chairs *and* raise them while it does; a wind pump spinning up
splits its windmill's power the same way, between the rotor's kinetic energy and the water it lifts:

    T omega = d(I_eff theta_dot^2 / 2)/dt + rho_w g h Q        (Eq. 12 times theta_dot).
"""

from __future__ import annotations

import dataclasses
import typing

import numpy as np

from .dynamics import SimulationResult, revolution_marks
from .errors import ParameterError
from .validation import non_negative, positive, real
from .windmill import windmill_power


class StartupPower(typing.NamedTuple):
    """Mean powers over a start-up at constant acceleration [W]."""

    accelerate: float
    """Kinetic energy gained / duration: m V^2 / (2 duration)."""
    lift: float
    """Potential energy gained / duration: m g (rise during the start-up) / duration."""
    total: float
    """Their sum: what the drive must supply on average while it starts."""


def startup_power(
    mass: float, speed: float, duration: float, grade: float, g: float = 9.81
) -> StartupPower:
    """Mean power to bring a load from rest to ``speed`` in ``duration`` up a slope (second seed).

    At constant acceleration ``a = speed / duration`` the load travels ``speed * duration / 2``
    along the slope and rises ``grade`` times that, so

    ``P_accelerate = m speed^2 / (2 duration)`` and ``P_lift = m g grade speed / 2``.

    Both grow linearly during the start-up: the power at its end is twice these means.

    Parameters
    ----------
    mass : float
        Moving mass [kg], > 0.
    speed : float
        Final speed along the slope [m/s], >= 0.
    duration : float
        Time to reach it [s], > 0.
    grade : float
        Rise over length along the slope [-], in [-1, 1] (the sine of the slope's angle).
    g : float, default 9.81
        Gravity [m/s^2], > 0.

    Returns
    -------
    StartupPower
        ``(accelerate, lift, total)`` [W].

    Examples
    --------
    The seed's ski lift: 50 chairs of 250 kg, 10 km/h in 5 s, 200 m of rise over 1 km.

    >>> power = startup_power(50 * 250.0, 10 / 3.6, 5.0, 200 / 1000)
    >>> from windpump.units import WATTS_PER_KW
    >>> [round(p / WATTS_PER_KW, 1) for p in power]  # kW: accelerate, lift, total
    [9.6, 34.1, 43.7]
    """
    mass = positive("mass", mass, "kg")
    speed = non_negative("speed", speed, "m/s")
    duration = positive("duration", duration, "s")
    grade = real("grade", grade)
    if abs(grade) > 1.0:
        raise ParameterError("grade", grade, "in [-1, 1]", why="rise over length along the slope")
    g = positive("g", g, "m/s^2")
    accelerate = 0.5 * mass * speed**2 / duration
    lift = mass * g * grade * (0.5 * speed * duration) / duration
    return StartupPower(accelerate, lift, accelerate + lift)


@dataclasses.dataclass(frozen=True)
class CycleMeanPower:
    """Powers averaged over each complete crank revolution [W], at the revolutions' mid-times [s]."""

    t: np.ndarray
    shaft: np.ndarray
    kinetic: np.ndarray
    hydraulic: np.ndarray


@dataclasses.dataclass(frozen=True)
class PowerBudget:
    """The windmill's power and where it goes, at every sample of a run.

    Attributes
    ----------
    t : ndarray
        Time [s].
    shaft_power : ndarray
        Windmill shaft power T(omega) omega, Eq. (11) [W].
    kinetic_power : ndarray
        Rate of change of the kinetic energy, d(I_eff theta_dot^2 / 2)/dt [W]: Eq. (12) times
        theta_dot; negative while the rotor slows.
    hydraulic_power : ndarray
        Power lifting water, rho_w g h Q [W]: zero while the cylinder takes water in.
    shaft_work, kinetic_energy, lift_work : ndarray
        Their integrals since t = 0 [J]: the windmill's work, the change of I_eff theta_dot^2 / 2,
        and rho_w g h V.
    theta : ndarray
        Crank angle [rad], unwrapped: it marks the revolutions of :meth:`cycle_means`.
    """

    t: np.ndarray
    shaft_power: np.ndarray
    kinetic_power: np.ndarray
    hydraulic_power: np.ndarray
    shaft_work: np.ndarray
    kinetic_energy: np.ndarray
    lift_work: np.ndarray
    theta: np.ndarray

    @property
    def imbalance(self) -> float:
        """Largest ``|shaft work - kinetic energy gained - lift work|`` over the run [-].

        Relative to the largest shaft work: 0 for an exact run."""
        gap = self.shaft_work - self.kinetic_energy - self.lift_work
        return float(
            np.max(np.abs(gap)) / max(np.max(np.abs(self.shaft_work)), np.finfo(float).tiny)
        )

    def cycle_means(self) -> CycleMeanPower:
        """Each power averaged over each complete revolution from the run's first angle.

        The energies at the revolutions' ends (every ``2 pi`` of crank angle) divided by their
        durations: the pulses of one revolution are smoothed out, the spin-up trend stays.
        """
        marks, times = revolution_marks(self.t, self.theta)
        duration = np.diff(times)

        def mean(energy):
            return np.diff(np.interp(marks, self.theta, energy)) / duration

        return CycleMeanPower(
            0.5 * (times[1:] + times[:-1]),
            mean(self.shaft_work),
            mean(self.kinetic_energy),
            mean(self.lift_work),
        )


def power_budget(result: SimulationResult) -> PowerBudget:
    """The wind pump's power split during a run: spinning up, and lifting water.

    ``T(omega) omega = d(I_eff theta_dot^2 / 2)/dt + rho_w g h Q`` at every sample (Eq. 12 times
    theta_dot, Eqs. 11 and 16, Q summed over every delivering face), and integrated: the windmill's
    work since t = 0 equals the kinetic energy gained plus the water's potential energy
    ``rho_w g h V``.

    Parameters
    ----------
    result : SimulationResult
        A run of :func:`windpump.simulate`; it carries its design.

    Returns
    -------
    PowerBudget

    Examples
    --------
    >>> from windpump import Design, simulate
    >>> budget = power_budget(simulate(Design.seed_example(), 600.0))
    >>> W, K, E = budget.shaft_work[-1], budget.kinetic_energy[-1], budget.lift_work[-1]
    >>> round(W), round(K), round(E), budget.imbalance < 1e-6  # J: to spin up, to lift water
    (11967, 7402, 4565, True)
    """
    if not isinstance(result, SimulationResult):
        raise TypeError(f"result must be a windpump.SimulationResult, not {type(result).__name__}")
    design = result.design
    shaft_power = windmill_power(design, result.omega)
    hydraulic_power = design.rho_w * design.g * design.h * result.flow
    return PowerBudget(
        t=result.t,
        shaft_power=shaft_power,
        kinetic_power=shaft_power - hydraulic_power,  # I_eff theta_dot theta_ddot, from Eq. (12)
        hydraulic_power=hydraulic_power,
        shaft_work=result.shaft_work,
        kinetic_energy=result.kinetic_energy - result.kinetic_energy[0],
        lift_work=result.lift_work,
        theta=result.theta,
    )
