"""What a run of the full equation of motion gives back: :class:`SimulationResult` (its samples,
and what is read off them), :class:`Intermittency` and :func:`revolution_marks`."""

from __future__ import annotations

import dataclasses
import io
import math
import os
import typing
from collections.abc import Callable

import numpy as np

from ..model.design import UNITS, Design
from ..model.kinematics import delivering_faces, face_flows
from ..model.reciprocating import crank_inertia
from ..model.wind import WindRecord
from ..units import LITRES_PER_M3
from ..validation import whole

SAMPLES_PER_STROKE = 16
"""Output samples per half revolution (per stroke) of the crank."""

MAX_SAMPLES = 1_000_000
"""Largest number of samples a run may produce; a longer request is refused before any work."""


class Deferred:
    """A result's array field that may be given as a function of no arguments, called when the
    field is first read (its array kept, read-only, and returned from then on): work a run
    would do that its caller may never read, as the flow of a pump with a leak hole (a sample's
    flow is a sum over its faces at its speed, 0.13 ms of the seed example's 600 s run, more
    than a tenth of the ideal machine's whole run). The numbers are those the function would
    have given at once; the result stays frozen (a field cannot be set from outside, and a
    pickled or copied result carries the arrays, not the functions).

    A descriptor of a frozen dataclass's field: ``__init__`` hands it the value given, the
    instance's ``__dict__`` keeps it under the field's name.

    Examples
    --------
    >>> import numpy as np
    >>> @dataclasses.dataclass(frozen=True)
    ... class Held:
    ...     x: Deferred = Deferred()
    >>> held = Held(lambda: np.arange(3.0))
    >>> held.x.tolist(), held.x.flags.writeable
    ([0.0, 1.0, 2.0], False)
    """

    def __init__(self, default: Callable[[], np.ndarray] | None = None) -> None:
        self.default = default  # a function: a field's default is hashable

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name

    def __get__(self, instance: object, owner: type | None = None) -> np.ndarray:
        if instance is None:  # the class's: the field's default, or none (AttributeError)
            if self.default is None:
                raise AttributeError(self.name)
            return self.default  # type: ignore[return-value]
        value = instance.__dict__[self.name]
        if not isinstance(value, np.ndarray):
            value = value()
            value.flags.writeable = False
            instance.__dict__[self.name] = value
        return value

    def __set__(self, instance: object, value: np.ndarray | Callable[[], np.ndarray]) -> None:
        instance.__dict__[self.name] = value


def _no_samples() -> np.ndarray:
    return np.empty(0)


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
        True when the crank came to rest for good (or could not start). Without a wind record
        the run ends there; in a record it runs to ``t_end`` and rests from its last stop.
    t_stall : float or None
        When it came to rest for good [s]; None when it was turning at the end.
    steps : int
        Dormand-Prince steps the integration took, rejected ones included.
    stops : ndarray
        Times the turning crank came to rest [s] (in a wind record, it waits there for the wind).
    starts : ndarray
        Times a resting crank began to turn [s] (a start from rest at t = 0 included).
    wind : WindRecord or None
        The wind record the run was given (times [s], speeds [m/s]), or None: V_ref throughout.
    swept_volume : ndarray
        Volume the delivering faces swept since t = 0 [m^3]: ``volume`` plus what leaked back
        through the holes (equal to it without a hole).
    friction_loss : ndarray
        Work lost to the rising main's friction since t = 0, ``int rho_w g h_f Q dt`` [J].
    leak_loss : ndarray
        Work lost through the leak holes since t = 0 [J]: the rest of the load's work
        ``int sum_k p_k u_k dt`` after the water lifted and the friction.
    """

    design: Design
    t: np.ndarray
    theta: np.ndarray
    theta_dot: np.ndarray
    volume: np.ndarray
    if typing.TYPE_CHECKING:  # (an array; a function before it is read, as it was given)
        flow: np.ndarray
    else:
        flow: Deferred = Deferred()
    shaft_work: np.ndarray
    stalled: bool
    t_stall: float | None
    steps: int = 0
    stops: np.ndarray = dataclasses.field(default_factory=lambda: np.empty(0))
    starts: np.ndarray = dataclasses.field(default_factory=lambda: np.empty(0))
    wind: WindRecord | None = None
    swept_volume: np.ndarray = dataclasses.field(default_factory=lambda: np.empty(0))
    friction_loss: np.ndarray = dataclasses.field(default_factory=lambda: np.empty(0))
    if typing.TYPE_CHECKING:
        leak_loss: np.ndarray = dataclasses.field(default_factory=_no_samples)
    else:
        leak_loss: Deferred = Deferred(_no_samples)

    def __getstate__(self) -> dict:
        """The fields as pickle and copy take them: every :class:`Deferred` one worked out."""
        return {field.name: getattr(self, field.name) for field in dataclasses.fields(self)}

    @property
    def wind_speed(self) -> np.ndarray:
        """Wind speed at the samples [m/s]: the record's, linear between its samples and held past
        its ends, or the design's V_ref throughout."""
        if self.wind is None:
            return np.full(self.t.shape, self.design.V_ref)
        return np.interp(self.t, self.wind.t, self.wind.V)

    @property
    def omega(self) -> np.ndarray:
        """Windmill speed R+ theta_dot [rad/s] (Eq. 4)."""
        return self.design.R_dagger * self.theta_dot

    @property
    def kinetic_energy(self) -> np.ndarray:
        """Kinetic energy of the moving parts, J(theta) theta_dot^2 / 2 [J]: I_eff theta_dot^2 / 2
        for the ideal machine, plus the reciprocating masses' (:func:`~windpump.model.reciprocating.
        crank_inertia`)."""
        if self.design.m_r == 0.0:
            return 0.5 * self.design.I_eff * self.theta_dot**2
        return 0.5 * crank_inertia(self.design, self.theta) * self.theta_dot**2

    @property
    def volumetric_efficiency(self) -> float:
        """Volume delivered over volume swept over the run [-]: 1 without a leak hole; NaN
        before the pistons have swept anything."""
        swept = float(self.swept_volume[-1])
        return float(self.volume[-1]) / swept if swept > 0.0 else math.nan

    @property
    def overall_efficiency(self) -> float:
        """The share of the work spent on the water that lifted it, over the run [-]:
        ``rho_w g h V / (rho_w g h V + (1 - eta_t) W + int rho_w g h_f Q dt + leak loss)``.

        By the energy balance (:func:`windpump.power_budget`) the denominator is the windmill's
        work W less the kinetic energy and the weights' potential energy gained: a pump that
        spins up stores work it has not yet spent, and one that stalls spends the kinetic
        energy of its kick, which the windmill never did (rho_w g h V / W was 456 % so). So it
        is at most 1, and 1 for the ideal machine with eta_t = 1 (it loses nothing); NaN before
        anything was lifted or lost. (Kicked above its runaway, the windmill brakes: its work
        is then negative, and the chain's loss counted as ``(1 - eta_t) |W|``.)

        Examples
        --------
        >>> from windpump import Design, simulate
        >>> seed = Design.seed_example()
        >>> simulate(seed, 600.0).overall_efficiency  # the ideal machine loses nothing
        1.0
        >>> stalled = simulate(seed.replace(h=21.0, eta_t=0.95), 600.0)
        >>> stalled.stalled, round(stalled.overall_efficiency, 2)  # its kick lifted water
        (True, 0.99)
        """
        lift = max(float(self.lift_work[-1]), 0.0)  # a leaky run's round-off below 0
        work = float(self.shaft_work[-1])
        friction = float(self.friction_loss[-1]) if len(self.friction_loss) else 0.0
        leak = float(self.leak_loss[-1]) if len(self.leak_loss) else 0.0
        # the chain's loss as a loss whichever way the power went: above the runaway the
        # windmill brakes the crank, and the model's eta_t T then counts (1 - eta_t) W < 0
        chain = (1.0 - self.design.eta_t) * abs(work)
        spent = lift + chain + max(friction, 0.0) + max(leak, 0.0)
        return lift / spent if spent > 0.0 else math.nan

    @property
    def lift_work(self) -> np.ndarray:
        """Work done lifting water, rho_w g h V [J]."""
        d = self.design
        return d.rho_w * d.g * d.h * self.volume

    def revolutions(self) -> tuple[np.ndarray, np.ndarray]:
        """Start and end times [s] of each complete crank revolution from theta0.

        Revolutions are counted from the initial angle: the k-th ends where
        ``theta = theta0 + 2 pi k`` (:func:`revolution_marks`).
        """
        _, times = revolution_marks(self.t, self.theta)
        return times[:-1], times[1:]

    def face_flows(self) -> np.ndarray:
        """Every face's flow [m^3/s], shape ``(2 cylinders, samples)``: row 2k is cylinder k's top
        face, row 2k + 1 its bottom face (zero unless double-acting). They sum to ``flow``."""
        return face_flows(self.theta, self.theta_dot, self.design)

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
        revolutions = whole("revolutions", revolutions, 1, MAX_SAMPLES)
        marks, times = revolution_marks(self.t, self.theta)
        if len(marks) < 2:
            raise ValueError("the run has no complete crank revolution to measure")
        marks, times = marks[-revolutions - 1 :], times[-revolutions - 1 :]
        start, end = times[:-1], times[1:]
        volume = np.interp([start[0], end[-1]], self.t, self.volume)
        mean_flow = (volume[1] - volume[0]) / (end[-1] - start[0])
        mean_speed = 2 * math.pi * len(start) / (end[-1] - start[0])
        window = (self.t >= start[0]) & (self.t <= end[-1])
        peak_flow = float(self.flow[window].max())
        idle = self._time_without_delivery(marks[0], marks[-1])
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
            no_delivery_fraction=idle / (end[-1] - start[0]),
        )

    def _time_without_delivery(self, theta_from: float, theta_to: float) -> float:
        """Time [s] the crank spends between two angles in segments (between switches) where no
        face delivers."""
        d = self.design
        width = math.pi / d.cylinders
        segments = np.arange(math.floor(theta_from / width), math.ceil(theta_to / width))
        edges = np.clip(np.append(segments, segments[-1] + 1) * width, theta_from, theta_to)
        durations = np.diff(np.interp(edges, self.theta, self.t))
        idle = ~delivering_faces(segments, d.cylinders, d.double_acting).any(axis=-1)
        return float(durations[idle].sum())

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
        revolutions = whole("revolutions", revolutions, 1, MAX_SAMPLES)
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
        scale, volume_unit = (LITRES_PER_M3, "L") if litres else (1.0, "m^3")
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
            shown = value if isinstance(value, (bool, int)) else f"{value:.12g}"
            buffer.write(f"# {name} = {shown} {UNITS[name]}".rstrip() + "\n")
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
    no_delivery_fraction : float
        Fraction of the time no face delivers [-]: the intake half for one single-acting
        cylinder (about 1/2), none for two or more, or for a double-acting pump.
    """

    mean_flow: float
    peak_flow: float
    peak_to_mean: float
    mean_speed: float
    speed_ripple: float
    no_delivery_fraction: float


def revolution_marks(t: np.ndarray, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Angles [rad] and times [s] where each complete crank revolution from ``theta[0]`` ends.

    The marks are ``theta[0] + 2 pi k`` for k = 0 ... (whole turns), their times found by
    interpolating the unwrapped angle in time. The one helper for counting revolutions.

    Examples
    --------
    >>> import numpy as np
    >>> marks, times = revolution_marks(np.array([0.0, 1.0, 2.0]), np.array([1.0, 5.0, 9.0]))
    >>> len(marks), [round(float(x), 3) for x in times]
    (2, [0.0, 1.571])
    """
    full = int(math.floor((theta[-1] - theta[0]) / (2 * math.pi)))
    marks = theta[0] + 2 * math.pi * np.arange(full + 1)
    return marks, np.interp(marks, theta, t)
