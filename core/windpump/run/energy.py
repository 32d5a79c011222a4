"""Where the power goes at start-up: to speed the machine up, and to lift its load (second seed).

The seed's ski lift must accelerate its chairs *and* raise them while it does; a wind pump spinning up
splits its windmill's power the same way, between the rotor's kinetic energy and the water it lifts:

    T omega = d(I_eff theta_dot^2 / 2)/dt + rho_w g h Q        (Eq. 12 times theta_dot).
"""

from __future__ import annotations

import dataclasses
import typing

import numpy as np

from ..errors import ParameterError
from ..model.loads import load_at_speed, weight_torque
from ..model.reciprocating import weight_potential
from ..model.windmill import shaft_power as _shaft_power
from ..validation import magnitude, real
from .dynamics import RTOL, SimulationResult, revolution_marks

__all__ = [
    "CycleMeanPower",
    "EnergyTotals",
    "PowerBudget",
    "StartupPower",
    "power_budget",
    "startup_power",
]


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

    The ranges are the design fields' (``SMALLEST`` to ``LARGEST``): inside them both powers are
    finite (at most 5e47 W); past them they overflowed (a bare ``OverflowError`` for
    ``speed = 1e300``), and now each is refused by name.

    Parameters
    ----------
    mass : float
        Moving mass [kg], 1e-12 to 1e12.
    speed : float
        Final speed along the slope [m/s], 0 to 1e12.
    duration : float
        Time to reach it [s], 1e-12 to 1e12.
    grade : float
        Rise over length along the slope [-], in [-1, 1] (the sine of the slope's angle).
    g : float, default 9.81
        Gravity [m/s^2], 1e-12 to 1e12.

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
    mass = magnitude("mass", mass, "kg")
    speed = magnitude("speed", speed, "m/s", zero=True)
    duration = magnitude("duration", duration, "s")
    grade = real("grade", grade)
    if abs(grade) > 1.0:
        raise ParameterError("grade", grade, "in [-1, 1]", why="rise over length along the slope")
    g = magnitude("g", g, "m/s^2")
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


class EnergyTotals(typing.NamedTuple):
    """Where the windmill's work went over a run [J] (:meth:`PowerBudget.totals`)."""

    shaft: float
    """The windmill's work W."""
    transmission: float
    """Lost in the chain and sprockets, (1 - eta_t) W."""
    friction: float
    """Lost to the rising main's friction."""
    leak: float
    """Lost through the leak holes."""
    kinetic: float
    """Gained as kinetic energy of the moving parts (spinning up)."""
    potential: float
    """Gained as the reciprocating weights' potential energy (0 over whole revolutions)."""
    water: float
    """Lifted water, rho_w g h V."""

    @property
    def imbalance(self) -> float:
        """What the terms leave of W, relative to W [-]: 0 for an exact run. Not promised small
        where W is far below the energy the run swings (:attr:`PowerBudget.closure` is the
        promised measure)."""
        rest = self.shaft - sum(self[1:])
        return abs(rest) / max(abs(self.shaft), np.finfo(float).tiny)


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
        Rate of change of the kinetic energy, d(J theta_dot^2 / 2)/dt [W]: Eq. (12) times
        theta_dot; negative while the rotor slows.
    hydraulic_power : ndarray
        Power lifting water, rho_w g h Q [W]: zero while no face delivers.
    shaft_work, kinetic_energy, lift_work : ndarray
        Their integrals since t = 0 [J]: the windmill's work, the change of J theta_dot^2 / 2,
        and rho_w g h V.
    theta : ndarray
        Crank angle [rad], unwrapped: it marks the revolutions of :meth:`cycle_means`.
    transmission_power, friction_power, leak_power, weight_power : ndarray
        The real machine's losses [W] (zero for the ideal machine): the chain's
        (1 - eta_t) T omega, the rising main's rho_w g h_f Q, the leak holes' (the faces' power
        sum p_k u_k less rho_w g (h + h_f) Q), and the rate the reciprocating weights gain
        potential energy, -m_r g sum x_c' theta_dot.
    transmission_loss, friction_loss, leak_loss, potential_energy : ndarray
        Their integrals since t = 0 [J].
    energy_scale : float
        The largest energy the run holds [J]: of the windmill's work, the kinetic energy
        J theta_dot^2 / 2 and the weights' potential energy m_r g sum x_c themselves (not their
        changes, whose last digits are theirs), at any sample; and the static lift's work over the
        run's angle, ``m rho_w g h A R abs(theta)``, whose last digits the angle's are (a light
        crank that stops within 5e-12 rad of a stroke lifts 4.5e-12 J to 1e-5). The budget
        closes to the integrator's tolerance of it (:attr:`closure`).
    steps : int
        The run's integration steps.
    """

    t: np.ndarray
    shaft_power: np.ndarray
    kinetic_power: np.ndarray
    hydraulic_power: np.ndarray
    shaft_work: np.ndarray
    kinetic_energy: np.ndarray
    lift_work: np.ndarray
    theta: np.ndarray
    transmission_power: np.ndarray
    friction_power: np.ndarray
    leak_power: np.ndarray
    weight_power: np.ndarray
    transmission_loss: np.ndarray
    friction_loss: np.ndarray
    leak_loss: np.ndarray
    potential_energy: np.ndarray
    energy_scale: float = 0.0
    steps: int = 0

    def totals(self, sample: int = -1) -> EnergyTotals:
        """Where the work went from t = 0 to a sample (the last by default) [J].

        Examples
        --------
        >>> from windpump import Design, simulate
        >>> d = Design.seed_example().replace(eta_t=0.9, L_main=20.0, d_leak=0.002)
        >>> totals = power_budget(simulate(d, 600.0)).totals()
        >>> round(totals.transmission / totals.shaft, 3), totals.imbalance < 1e-9
        (0.1, True)
        """
        return EnergyTotals(
            *(
                float(array[sample])
                for array in (
                    self.shaft_work,
                    self.transmission_loss,
                    self.friction_loss,
                    self.leak_loss,
                    self.kinetic_energy,
                    self.potential_energy,
                    self.lift_work,
                )
            )
        )

    @property
    def gap(self) -> np.ndarray:
        """The windmill's work less every term of :meth:`totals`, at each sample [J]: 0 for an
        exact run."""
        return (
            self.shaft_work
            - self.transmission_loss
            - self.friction_loss
            - self.leak_loss
            - self.kinetic_energy
            - self.potential_energy
            - self.lift_work
        )

    @property
    def imbalance(self) -> float:
        """Largest ``|W - every term of :meth:`totals`|`` over the run, relative to the largest
        shaft work [-]: 0 for an exact run. A diagnostic, not a promise: where the run swings far
        more energy than W (a heavy reciprocating mass, a heavy rotor held at speed) the kinetic
        energy's last digits and the integrator's tolerance on the swing are a large part of W
        (1e-4 at m_r = 1e6 kg on the seed example, 0.4 at 1e12). What the budget is promised to
        close to is :attr:`closure`, below :attr:`tolerance`."""
        return float(
            np.max(np.abs(self.gap)) / max(np.max(np.abs(self.shaft_work)), np.finfo(float).tiny)
        )

    @property
    def closure(self) -> float:
        """Largest ``|W - every term of :meth:`totals`|`` over the run, relative to
        :attr:`energy_scale` [-]: what the budget is promised to close to, ``tolerance``.

        :attr:`imbalance` divides by the work W, which may be far below the energy the run holds
        (a heavy rotor kept at speed, a reciprocating mass swinging energy to and from the
        rotor every revolution: W = -134 J against 7,300 J swung at m_r = 1e6 kg): there the
        kinetic energy's own last digits, or the integrator's error in the swing, are a large
        part of W (issue 36: imbalance 1e-4 at m_r = 1e6, 40 % at 1e12)."""
        return float(np.max(np.abs(self.gap)) / max(self.energy_scale, np.finfo(float).tiny))

    @property
    def tolerance(self) -> float:
        """What :attr:`closure` is promised to stay below [-]: the integrator's local tolerance
        (``windpump.run.dynamics.RTOL``) for every step, and 1e-12 for round-off."""
        return RTOL * max(self.steps, 1) + 1e-12

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
    """The wind pump's power split during a run: spinning up, lifting water, and the real
    machine's losses.

    ``T omega = (1 - eta_t) T omega + d(J theta_dot^2 / 2)/dt - m_r g sum x_c' theta_dot
    + rho_w g h Q + rho_w g h_f Q + P_leak`` at every sample (the equation of motion times
    theta_dot; Eq. 12 times theta_dot for the ideal machine), and integrated: the windmill's work
    since t = 0 equals the chain's loss, the kinetic energy gained, the weights' potential energy,
    the water's ``rho_w g h V``, the rising main's friction and the leak's loss. The integrals are
    the integrator's own quadratures, so they close to round-off.

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
    shaft_power = _shaft_power(design, result.omega)
    lift = design.rho_w * design.g
    hydraulic_power = lift * design.h * result.flow
    friction_power = lift * design.friction_coefficient * result.flow**3
    if design.is_ideal:  # every face delivers what it sweeps against the static head
        faces_power, leak_power = hydraulic_power, np.zeros_like(result.t)
    else:
        theta, theta_dot = result.theta, result.theta_dot
        faces_power = load_at_speed(design, theta, theta_dot) * theta_dot
        leak_power = faces_power - hydraulic_power - friction_power
    weight_power = -weight_torque(design, result.theta) * result.theta_dot
    transmission_power = (1.0 - design.eta_t) * shaft_power
    potential = weight_potential(design, result.theta)
    return PowerBudget(
        t=result.t,
        shaft_power=shaft_power,
        kinetic_power=shaft_power - transmission_power - faces_power - weight_power,
        hydraulic_power=hydraulic_power,
        shaft_work=result.shaft_work,
        kinetic_energy=result.kinetic_energy - result.kinetic_energy[0],
        lift_work=result.lift_work,
        theta=result.theta,
        transmission_power=transmission_power,
        friction_power=friction_power,
        leak_power=leak_power,
        weight_power=weight_power,
        transmission_loss=(1.0 - design.eta_t) * result.shaft_work,
        friction_loss=result.friction_loss,
        leak_loss=result.leak_loss,
        potential_energy=potential - potential[0],
        energy_scale=float(
            max(
                np.max(np.abs(result.shaft_work)),
                np.max(np.abs(result.kinetic_energy)),
                np.max(np.abs(potential)),
                # the lift's work over the run's angle: the angle's last digits carry it
                design.deliveries * design.load_torque * float(np.max(np.abs(result.theta))),
            )
        ),
        steps=int(result.steps),
    )
