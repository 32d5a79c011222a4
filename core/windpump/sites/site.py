"""From a site's wind to water, by the averaged theory: thresholds, flow against wind, water a day.

A design's curve describes its rotor at V_ref; by similarity (``Design.in_wind``) torques scale as
V^2 and speeds as V. In the averaged equation (:mod:`windpump.averaging.theory`, which evaluates it) with
s = V/V_ref the rate k is unchanged, p scales as s and
``delta^2 = (omega_m/R+)^2 (R+ T_m s^2 - M) / (R+ (T_m - T_0))``, so the running speed
alpha+(V) = p + delta and the thresholds below have closed forms.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import typing

import numpy as np

from ..averaging.averaged import stall_margin
from ..averaging.revolution import mean_load
from ..averaging.theory import (
    LEAK_TABLE as LEAK_TABLE,  # re-exported: steady_flow moved below the run
)
from ..averaging.theory import cycle_mean, running_speeds
from ..averaging.theory import steady_flow as steady_flow
from ..errors import ParameterError, shown
from ..model.design import Design
from ..model.loads import peak_load_torque, starts_from_rest
from ..model.torque import furls_below, wind_at_rotor
from ..model.wind import MAX_WIND, WindRecord, as_record, shape, weibull_scale
from ..run.dynamics import SimulationResult, checked_kick, simulate
from ..units import SECONDS_PER_DAY
from ..validation import non_negative


def wind_thresholds(design: Design) -> tuple[float, float | None]:
    """Wind speeds (V_stop, V_start) [m/s] that bound where the pump runs.

    Below ``V_stop = V_ref / sqrt(stall margin)`` a running pump cannot keep running: the averaged
    theory's stall criterion (Eq. 22, generalised) in the wind V (with a rising main, where the
    averaged equation's roots meet; 0 with a leak hole, which never stalls, or with no head). Above
    ``V_start = V_ref sqrt(peak load torque / (eta_t R+ T_0))`` a resting pump starts from any
    crank angle (:func:`windpump.starts_from_rest` in that wind: the net torque at rest is > 0
    everywhere); None when T_0 = 0 (it never starts on its own), inf when eta_t R+ T_0 is too
    small for a double. Between them a pump that runs goes on running, one at rest stays there.

    Examples
    --------
    >>> from windpump import Design, wind_thresholds
    >>> v_stop, v_start = wind_thresholds(Design.seed_example().replace(T_0=0.3))
    >>> round(v_stop, 2), round(v_start, 2)
    (2.21, 5.65)
    >>> wind_thresholds(Design.seed_example())[1] is None
    True
    """
    V_stop = _stop_wind(design)
    if design.T_0 == 0.0:
        return V_stop, None
    at_rest = design.eta_t * design.rest_torque_on_crank  # 0 when a tiny T_0 underflows
    if not at_rest:
        return V_stop, math.inf
    V_start = design.V_ref * math.sqrt(peak_load_torque(design) / at_rest)
    if design.rotor is not None:  # a rotor's T_0 is its unfurled torque at V_ref when V_ref
        V_start *= math.sqrt(at_rest / _unfurled_rest(design))  # lies above the furl
        if V_start > furls_below(design) * design.V_ref:
            return V_stop, math.inf  # furled, the wheel's torque at rest stops growing
    return V_stop, V_start


def _unfurled_rest(design: Design) -> float:
    """eta_t R+ times the rotor's torque at rest in V_ref were it not furled [N m]."""
    rotor = design.rotor
    assert rotor is not None
    return design.eta_t * design.R_dagger * rotor.torque_scale * design.V_ref**2 * rotor.table_cq[0]


STOP_ROUNDS, STOP_WINDS = 6, 32
"""A rotor's pump with a rising main: V_stop found on STOP_WINDS winds at a time, narrowing the
bracket STOP_ROUNDS times (by 31^6 ~ 1e9)."""


def _rotor_stop_wind(design: Design) -> float:
    """V_stop [m/s] of a rotor's pump: where the stall margin reaches 1. Without a rising main
    the margin grows as V_s^2 (the rotor's similarity; V_s the wind capped at V_furl), so
    ``V_stop = V_s(V_ref) / sqrt(margin)``; with one, bracketed on winds up to the furl (or
    150 m/s). inf where the margin stays at or below 1 in every wind."""
    top = min(furls_below(design) * design.V_ref, MAX_WIND)
    if design.friction_coefficient == 0.0:
        V_s = float(wind_at_rotor(design)) / math.sqrt(stall_margin(design))
        return V_s if V_s < top else math.inf
    if float(running_speeds(design, V=top).margin) <= 1.0:
        return math.inf
    lo, hi = 0.0, top
    for _ in range(STOP_ROUNDS):
        winds = np.linspace(lo, hi, STOP_WINDS)
        runs = running_speeds(design, V=winds).margin > 1.0
        first = int(np.argmax(runs))  # runs[-1] is True: hi runs
        lo, hi = winds[max(first - 1, 0)], winds[first]
    return float(hi)


def _stop_wind(design: Design) -> float:
    """V_stop [m/s]: ``V_ref / sqrt(stall margin)`` (the margin grows as V^2), where delta^2 = 0
    with a rising main, 0 with a leak hole (it never stalls) or with no load to carry (h = 0: the
    windmill beats a main's friction near rest in any wind; there delta^2 and its wind slope can
    both underflow, and their ratio was NaN)."""
    if design.d_leak > 0.0 or design.mean_load_torque == 0.0:
        return 0.0
    if design.rotor is not None:
        return _rotor_stop_wind(design)
    if design.friction_coefficient == 0.0:
        return design.V_ref / math.sqrt(stall_margin(design))
    return design.V_ref * float(cycle_mean(design).s_stop)


def water_per_day(design: Design, mean_wind: float, k: float = 2.0) -> tuple[float, float]:
    """Water lifted a day [m^3/day] at a site with Weibull winds: (low, high) averaged bounds.

    The expectation of :func:`steady_flow` over the Weibull distribution of wind speeds with that
    mean and shape k (scale ``c = mean / Gamma(1 + 1/k)``), times a day: ``high`` counts every
    wind above V_stop (once started the pump runs whenever the wind can carry it), ``low`` only the
    winds above V_start (it runs only when it could start from rest); ``low = 0`` when T_0 = 0.
    Both by quadrature to 1e-8 relative (the linear part in closed form with the incomplete
    gamma function, the rest with the square root's end singularity removed); with a leak hole
    (no closed form for alpha+) by the trapezoidal rule over the running flow tabulated against
    the wind at 300 crank speeds, to about 1e-3 relative.

    What the bounds leave out (ripple, gusts faster than the spin-up time, stops at angles where
    the load is light) is what a full run in a wind record shows: ``simulate(..., wind=...)``.

    Parameters
    ----------
    design : Design
    mean_wind : float
        The site's mean wind speed [m/s], from 1e-3 (calm air; below it the Weibull scale
        underflowed and the answer was NaN) to 150.
    k : float, default 2.0
        Weibull shape [-] (2: Rayleigh), 0.5 to 20.

    Examples
    --------
    >>> from windpump import Design, water_per_day
    >>> low, high = water_per_day(Design.seed_example().replace(T_0=0.3), 5.0)
    >>> round(low, 2), round(high, 2)
    (23.24, 37.51)
    """
    c = weibull_scale(mean_wind, k)
    k = shape(k)
    V_stop, V_start = wind_thresholds(design)
    expected: typing.Callable[[float, float, float], float] = functools.partial(
        _expected_flow, design
    )
    if design.d_leak > 0.0 or design.rotor is not None:  # one table of the running flow
        V_far = c * 50.0 ** (1.0 / k)  # against the wind, for both bounds; beyond V_far the
        if design.d_leak > 0.0:  # density is below exp(-50)
            flows = _leaky_flows(design, V_far)
            expected = functools.partial(_expected_leaky_flow, flows, V_far=V_far)
        else:
            expected = functools.partial(_expected_rotor_flow, design)

    high = expected(V_stop, c, k) if _ever_blows(V_stop, c, k) else 0.0
    low = 0.0
    if V_start is not None and _ever_blows(V_start, c, k):
        low = expected(V_start, c, k)
    return float(SECONDS_PER_DAY * low), float(SECONDS_PER_DAY * high)


def _ever_blows(V: float, c: float, k: float) -> bool:
    """Whether winds above V come with a probability exp(-(V/c)^k) above exp(-700), the smallest
    a double holds (beyond it the flow they bring is 0, and (V/c)^k may overflow)."""
    return k * math.log(V / c) < math.log(700.0) if V > 0.0 else True


def _expected_flow(design: Design, V_from: float, c: float, k: float) -> float:
    """E[flow(V); V > V_from] [m^3/s] for Weibull(c, k) winds, V_from >= V_stop."""
    from scipy import integrate, special

    V_stop = _stop_wind(design)
    mean = cycle_mean(design)  # at V_ref
    p = float(mean.p)
    per_radian = design.volume_per_revolution / (2 * math.pi)  # flow per crank speed [m^3/rad]
    # alpha+ = p s + g sqrt(V^2 - V_stop^2), s = V / V_ref (theory.CycleMean.delta2_per_s2);
    # p and delta2_per_s2 are scaled by kappa with a rising main.
    g = math.sqrt(mean.delta2_per_s2) / design.V_ref
    # E[V; V > a] = c Gamma(1 + 1/k, (a/c)^k), the upper incomplete gamma function.
    linear = c * math.gamma(1.0 + 1.0 / k) * special.gammaincc(1.0 + 1.0 / k, (V_from / c) ** k)

    def density(V):
        return k / c * (V / c) ** (k - 1.0) * math.exp(-((V / c) ** k))

    def root_term(q):  # V^2 = V_stop^2 + q^2: sqrt(V^2 - V_stop^2) dV = q^2 / V dq, smooth
        V = math.sqrt(V_stop * V_stop + q * q)
        return q * q / V * density(V) if V > 0.0 else 0.0  # (q = V = 0 when V_stop = 0)

    q_from = math.sqrt(max(V_from * V_from - V_stop * V_stop, 0.0))
    # Beyond V_far the density is below exp(-50) of its value at V_from (not of its peak: far out
    # a fixed cut left the near part a zero-length or 600-e-fold span, and quad warned, issue 36).
    u_far = (V_from / c) ** k + 50.0
    V_far = c * u_far ** (1.0 / k)
    q_far = math.sqrt(max((V_far - V_stop) * (V_far + V_stop), q_from * q_from))
    near, _ = integrate.quad(root_term, q_from, q_far, epsabs=0.0, epsrel=1e-12, limit=400)
    # Beyond q_far, in u = (V/c)^k = u_far + t (density dV = exp(-u) du): the tail is
    # exp(-u_far) times the integral of sqrt(V^2 - V_stop^2) exp(-t) dt over t >= 0, whose
    # integrand grows only as a power of t. (In q it decays as exp(-(q/c)^k), slowly for k < 1,
    # and quad to infinity warned "probably divergent" at k = 0.5, issue 36.)

    def tail_term(t):  # V^2 - V_stop^2 = q_far^2 + (V - V_far)(V + V_far), without cancellation
        rise = V_far * math.expm1(math.log1p(t / u_far) / k)  # V - V_far
        return math.sqrt(q_far * q_far + rise * (rise + 2.0 * V_far)) * math.exp(-t)

    tail, _ = integrate.quad(tail_term, 0.0, math.inf, epsabs=0.0, epsrel=1e-12, limit=400)
    tail *= math.exp(-u_far)
    return per_radian * (p / design.V_ref * linear + g * (near + tail))


LEAKY_SPEEDS = 300
"""Crank speeds at which a pump with a leak hole's mean load and flow are tabulated for the
expected flow at a Weibull site."""


def _leaky_flows(design: Design, V_far: float) -> tuple[np.ndarray, np.ndarray]:
    """The running flow Q-bar [m^3/s] of a pump with a leak hole against the wind V [m/s] it
    runs in, V non-decreasing up to V_far, on LEAKY_SPEEDS crank speeds.

    By the wind similarity every crank speed alpha is a steady speed in one wind: the s where
    ``eta_t R+ T_s(R+ alpha) = L-bar(alpha)`` (a quadratic in s; L-bar does not depend on the
    wind). The running speed alpha+(V) is the largest alpha with ``V_ref s(alpha) = V``, so V
    runs through ``V_ref min over alpha' >= alpha of s(alpha')``, non-decreasing in alpha.
    """
    top = design.runaway_speed / design.omega_m  # x where T vanishes at V_ref
    fastest = V_far / design.V_ref * design.omega_m * top / design.R_dagger
    alpha = np.linspace(0.0, fastest, LEAKY_SPEEDS + 1)[1:]
    load, flow = mean_load(design, alpha)
    # eta_t R+ [T_0 s^2 + (T_m - T_0) x (2 s - x)] = load, x = R+ alpha / omega_m at V_ref.
    x = design.R_dagger * alpha / design.omega_m
    spread = design.T_m - design.T_0
    need = load / (design.eta_t * design.R_dagger) + spread * x * x
    s = need / (spread * x + np.sqrt((spread * x) ** 2 + design.T_0 * need))  # the root > 0
    return design.V_ref * np.minimum.accumulate(s[::-1])[::-1], flow


ROTOR_PANELS, ROTOR_NODES = 16, 8
"""A rotor's expected flow at a Weibull site: Gauss-Legendre panels (and nodes each) over the
winds it runs in (no closed form for its running speed)."""


def _expected_rotor_flow(design: Design, V_from: float, c: float, k: float) -> float:
    """E[flow(V); V > V_from] [m^3/s] for Weibull(c, k) winds, a rotor's pump (V_from >=
    V_stop): Gauss-Legendre panels in ``t = sqrt(V - V_from)`` (the running speed rises as the
    square root of V - V_stop from the stall's fold: smooth in t) up to where the density has
    fallen by exp(-50), cut at the furl (a kink of the flow), the running speeds of every node
    found at once (:func:`windpump.averaging.theory.running_speeds`)."""
    if not math.isfinite(V_from):
        return 0.0
    V_far = c * ((V_from / c) ** k + 50.0) ** (1.0 / k)
    edges = list(np.linspace(0.0, math.sqrt(V_far - V_from), ROTOR_PANELS + 1))
    V_furl = furls_below(design) * design.V_ref
    if V_from < V_furl < V_far:
        edges = sorted(edges + [math.sqrt(V_furl - V_from)])
    x, w = np.polynomial.legendre.leggauss(ROTOR_NODES)
    starts, widths = np.array(edges[:-1])[:, None], np.diff(edges)[:, None]
    t = (starts + 0.5 * widths * (x + 1.0)).ravel()
    V = V_from + t * t
    density = k / c * (V / c) ** (k - 1.0) * np.exp(-((V / c) ** k))
    weights = (0.5 * widths * w).ravel() * density * 2.0 * t  # dV = 2 t dt
    speeds = running_speeds(design, V=np.minimum(V, MAX_WIND) * (1.0 + 1e-12))
    return float(np.sum(np.nan_to_num(speeds.mean_flow) * weights))


def _expected_leaky_flow(flows, V_from: float, c: float, k: float, *, V_far: float) -> float:
    """E[flow(V); V > V_from] [m^3/s] for Weibull(c, k) winds from :func:`_leaky_flows`: the
    integral of ``Q-bar f(V) dV`` by the trapezoidal rule (where the running speed jumps, V
    stands still and adds nothing)."""
    V, flow = flows
    V = np.clip(V, V_from, max(V_from, V_far))
    density = k / c * (V / c) ** (k - 1.0) * np.exp(-((V / c) ** k))
    weighted = flow * density
    return float(np.sum(0.5 * (weighted[1:] + weighted[:-1]) * np.diff(V)))


def record_water(design: Design, record) -> tuple[float, float]:
    """Water a day [m^3/day] by the averaged theory over a wind record's own speeds: (low, high).

    The time average of :func:`steady_flow` over the record (V linear between samples, by the
    trapezoidal rule on its samples), counting the winds above V_start (low; 0 when T_0 = 0) or
    above V_stop (high), per day: the bounds :func:`water_per_day` gives for a Weibull site, for
    this record. A full run in the record (``simulate(..., wind=record)``) lies between them when
    the wind varies slowly against the spin-up time.

    Parameters
    ----------
    design : Design
    record : (t, V) pair
        Times [s] and wind speeds [m/s], as ``simulate`` takes them; at least two samples.

    Examples
    --------
    >>> from windpump import Design
    >>> low, high = record_water(Design.seed_example(), ([0.0, 3600.0], [5.0, 5.0]))
    >>> low, round(high, 2)
    (0.0, 32.77)
    """
    t, V = as_record(record, 1.0)
    if len(t) < 2:
        raise ParameterError("record", f"{len(t)} sample", "a record of at least 2 samples")
    V_stop, V_start = wind_thresholds(design)
    flow = steady_flow(design, V)
    duration = t[-1] - t[0]

    def daily(kept) -> float:
        q = np.where(kept, flow, 0.0)
        return float(SECONDS_PER_DAY * np.sum(0.5 * (q[1:] + q[:-1]) * np.diff(t)) / duration)

    return (0.0 if V_start is None else daily(V >= V_start)), daily(V > V_stop)


@dataclasses.dataclass(frozen=True)
class WindEvents:
    """Moments of a run in a wind record (its stops, or its starts): when, the wind then, and the
    water pumped so far.

    Attributes
    ----------
    t : ndarray
        Times [s].
    V : ndarray
        The record's wind speed at those times [m/s] (linear between its samples).
    volume : ndarray
        Water pumped since the run's start at those times [m^3].
    """

    t: np.ndarray
    V: np.ndarray
    volume: np.ndarray

    def __len__(self) -> int:
        return len(self.t)


@dataclasses.dataclass(frozen=True)
class WindRun:
    """A design run in full through a wind record (:func:`run_in_wind`).

    Attributes
    ----------
    run : SimulationResult
        The full integration (Eq. 12 with the rotor following the wind), over the whole record.
    record : WindRecord
        The wind it ran in: times [s] from the run's start, speeds [m/s].
    kick : float
        The crank speed it was given at t = 0 [rad/s]: 0 when the windmill starts on its own.
    stops, starts : WindEvents
        When the turning crank came to rest and when a resting one began to turn, with the wind
        speed and the water pumped at each.
    """

    run: SimulationResult
    record: WindRecord
    kick: float
    stops: WindEvents
    starts: WindEvents

    @property
    def duration(self) -> float:
        """The record's length, and the run's [s]."""
        return float(self.run.t[-1])

    @property
    def volume(self) -> float:
        """Water pumped over the whole record [m^3]."""
        return float(self.run.volume[-1])

    @property
    def per_day(self) -> float:
        """Water pumped at the record's mean rate, a day's worth [m^3/day]: the record's water for a
        record of a day, scaled by a day over its length for a shorter or longer one."""
        return self.volume * SECONDS_PER_DAY / self.duration

    @property
    def mean_wind(self) -> float:
        """The mean of the wind speed at the run's samples [m/s]."""
        return float(np.mean(self.run.wind_speed))


def kick_in_wind(design: Design, kick: float) -> float:
    """The crank speed [rad/s] a day in the wind starts with (:func:`run_in_wind`'s policy): 0
    for a windmill that starts from rest on its own (:func:`windpump.starts_from_rest`), else
    ``kick``.

    Parameters
    ----------
    design : Design
        The pump, its rotor at V_ref.
    kick : float
        Crank speed offered at t = 0 [rad/s], >= 0.

    Examples
    --------
    >>> from windpump import Design
    >>> kick_in_wind(Design.seed_example(), 3.0), kick_in_wind(Design.seed_example().replace(T_0=0.4), 3.0)
    (3.0, 0.0)
    """
    kick = checked_kick("kick", kick)  # named here, not as theta_dot0
    return 0.0 if starts_from_rest(design) else kick


def run_in_wind(design: Design, record, theta0: float = math.pi / 2, kick: float = 3.0) -> WindRun:
    """Run a design in full through a whole wind record: what the pump does on a real day.

    The rotor is given at V_ref by ``design`` and follows the record's wind by similarity
    (:func:`windpump.simulate` with ``wind=record``). A windmill that starts from rest on its
    own (:func:`windpump.starts_from_rest`) is let go from rest; any other is given ``kick``.
    The run is sampled once a second (each stop and start too), and for a record longer than a
    day once every ``length / 1 day`` seconds, so that no record gives more than a day's samples.

    Parameters
    ----------
    design : Design
        The pump, its rotor at V_ref.
    record : WindRecord or (t, V) pair
        Times [s] from the run's start, increasing, the last > 0, and wind speeds [m/s].
    theta0 : float, default pi/2
        Crank angle at t = 0 [rad].
    kick : float, default 3.0
        Crank speed given at t = 0 to a windmill that cannot start on its own [rad/s], 0 or from
        1e-300 to 1e12 (as :func:`windpump.simulate`'s ``theta_dot0``).

    Returns
    -------
    WindRun
        The run, its water a day, and its stops and starts with the wind and water at each.

    Raises
    ------
    ParameterError
        For a bad record or argument, or a run :func:`windpump.simulate` refuses.

    Examples
    --------
    An hour of 5 m/s wind, an hour of calm, an hour of 5 m/s again, for a windmill that starts on
    its own:

    >>> from windpump import Design, run_in_wind
    >>> wind = ([0, 3600, 3660, 7200, 7260, 10800], [5, 5, 0, 0, 5, 5])
    >>> day = run_in_wind(Design.seed_example().replace(T_0=0.4), wind)
    >>> day.kick, len(day.stops), len(day.starts)
    (0.0, 1, 2)
    >>> round(float(day.stops.t[0])), float(day.stops.V[0])  # it coasts into the calm [s], [m/s]
    (4323, 0.0)
    >>> round(float(day.starts.V[1]), 2), round(day.per_day, 1)  # back with the wind [m/s], [m^3/day]
    (4.65, 27.8)
    """
    kick = non_negative("kick", kick, "rad/s")
    try:
        checked = as_record(record, 1.0)
    except ParameterError as error:  # named as this function's argument, not simulate's
        raise ParameterError("record", error.value, error.allowed, error.unit, error.why) from None
    duration = float(checked.t[-1])
    if not duration > 0.0:
        raise ParameterError(
            "record", f"last time {shown(duration)} s", "a record ending after t = 0"
        )
    kick = kick_in_wind(design, kick)
    run = simulate(
        design,
        duration,
        theta0,
        kick,
        wind=checked,
        sample_dt=max(1.0, duration / SECONDS_PER_DAY),
    )

    def events(times) -> WindEvents:
        at = np.asarray(times, dtype=float)
        return WindEvents(at, np.interp(at, checked.t, checked.V), np.interp(at, run.t, run.volume))

    return WindRun(run, checked, kick, events(run.stops), events(run.starts))
