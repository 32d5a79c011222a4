"""The full equation of motion, Eq. (12), integrated without averaging: :func:`simulate`.

Beyond the paper it integrates the summed load of several cylinders, single- or double-acting,
and a windmill with torque at rest (``Design.cylinders``, ``double_acting``, ``T_0``).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from .. import _kernels
from ..averaging.averaged import own_speeds, stall_margin
from ..averaging.revolution import friction_load, reciprocating_inertia
from ..averaging.theory import steady_flow
from ..errors import ParameterError
from ..model.design import Design
from ..model.torque import steepest_fall
from ..model.wind import WindRecord, as_record
from ..validation import LARGEST, non_negative, positive, real, whole

# A run's result and the design-to-kernel wrapper have modules of their own; their names stay
# importable from here, where scripts and the app found them.
from .machine import DEFAULTS as DEFAULTS
from .machine import first_capacity as first_capacity
from .machine import ideal_of as ideal_of
from .machine import kernel_machine as kernel_machine
from .machine import kernel_real as kernel_real
from .machine import kernel_real_base as kernel_real_base
from .machine import kernel_wind as kernel_wind
from .machine import solver_is_cached as solver_is_cached
from .result import MAX_SAMPLES as MAX_SAMPLES
from .result import SAMPLES_PER_STROKE as SAMPLES_PER_STROKE
from .result import Deferred as Deferred
from .result import Intermittency as Intermittency
from .result import SimulationResult as SimulationResult
from .result import revolution_marks as revolution_marks

MAX_STEPS = 20 * MAX_SAMPLES
"""Largest number of integration steps a run may take (a stiff design hits this)."""

SMALLEST_KICK = 1e-300
"""Smallest non-zero initial crank speed [rad/s]."""

LARGEST_KICK = LARGEST
"""Largest initial crank speed [rad/s] (1e12, the largest speed the core takes: a kick of 1e300
made its run's sample bound inf, and the refusal then blamed t_end)."""

RTOL = 1e-8
"""Local relative tolerance of the integrator (u = theta_dot^2/2, and the time per step)."""


def sample_bound(
    design: Design,
    t_end: float,
    theta_dot0: float,
    samples_per_stroke: int = SAMPLES_PER_STROKE,
    sample_dt: float | None = None,
    wind: WindRecord | None = None,
) -> float:
    """Most samples :func:`simulate` can produce for this run, besides two at each stop (the
    crank speed never exceeds theta_dot0 or the runaway speed over R+ in the strongest wind, where
    the windmill torque turns negative). A float: it may be too large for an integer."""
    if sample_dt is not None:
        return t_end / sample_dt + 3
    strongest = 1.0 if wind is None else float(np.max(wind.V)) / design.V_ref
    fastest = max(theta_dot0, strongest * design.runaway_speed / design.R_dagger)
    return fastest * t_end / (math.pi / samples_per_stroke) + 3


def estimated_steps(design: Design, t_end: float, record: WindRecord | None = None) -> float:
    """About how many integration steps a run takes: one at every switch (every pi/n of crank
    angle, at the averaged running speed in each wind: :func:`windpump.steady_flow`) and one at
    every sample of the record where the wind bends. A float: it may be too large for an int."""
    if not design.is_ideal:
        # The ideal machine runs at least as fast, and its averaged theory is in closed form (a
        # leak hole's takes a quadrature a wind speed: seconds for a day's record); a real run's
        # kinks and harmonics take up to ~3 steps a switch.
        return REAL_STEPS_PER_SWITCH * estimated_steps(ideal_of(design), t_end, record)
    per_speed = design.volume_per_revolution / (2 * math.pi)  # flow per crank speed [m^3/rad]
    switches_per_radian = design.cylinders / math.pi
    if record is None and design.rotor is not None:  # (remembered: no closed form)
        flow = float(np.nan_to_num(own_speeds(design).mean_flow))  # 0 where it cannot run
        return switches_per_radian * flow / per_speed * t_end
    if record is None:
        return switches_per_radian * steady_flow(design, design.V_ref) / per_speed * t_end
    t, V = record.t, record.V
    inside = t < t_end
    bends = int(np.count_nonzero(inside[:-1] & (np.diff(V) != 0.0)))
    times = np.concatenate(([0.0], t[inside], [t_end]))
    speed = steady_flow(design, np.interp(times, t, V)) / per_speed
    radians = float(np.sum(0.5 * (speed[1:] + speed[:-1]) * np.diff(times)))
    return bends + switches_per_radian * radians


REAL_STEPS_PER_SWITCH = 3.0
PACE_STEPS = 100_000
"""Every this many steps, a run without a wind record is refused when, at the pace of its last
``PACE_STEPS`` (steps per second of t), the rest of it would need more than 10 times what is
left of ``MAX_STEPS`` (``_kernels.stepping.PACE_MARGIN``: a start may be stiffer than the
rest): a design too stiff or too slow to integrate, whether its time scales show it or not, is
refused after ~0.1-0.3 s (twice that on a busy machine), not after ``MAX_STEPS`` (10-60 s). A
run on pace to need 1 to 10 times ``MAX_STEPS`` is still refused only when they run out: a
start that crawls is no guide to the rest (the leak-hole preset from rest takes 1.03 million
steps between t = 9 and 20 s, then ~5,000 in the 540 s after: a pace since t = 0 judged at 1e6
steps refused it, on pace for 40 million). A short
stiff run that ends early stays inside the margin (the seed example at m_r = 1e6 kg: 141,497
steps in 0.16 s, then it stalls; the first 100,000 at 4 times the pace of 60 s of MAX_STEPS).
In a wind record a calm stretch may follow a stormy one, so only ``MAX_STEPS`` holds there."""

STIFF_STEPS = 1.0
"""Integration steps per unit of ``t_end a1 / I_eff`` a light rotor takes at the least (measured
1.4 to 2.2 on the seed example's pump with I0 = I1 from 1e-7 to 1e-6 kg m^2)."""


def stiffness(design: Design) -> tuple[float, float, float, float]:
    """How fast the crank's speed relaxes [1/s], by cause: (the windmill's torque slope at rest
    ``a1 = 2 eta_t R+^2 (T_m - T_0) / omega_m``, the rising main's ``2 c p`` at the speed of peak
    torque p = omega_m / R+, the leak hole's ``2 rho_w g h (A R)^2 / q_L`` where a face starts to
    deliver, and the reciprocating masses' share of the inertia ``m_r sum <x_c'^2> / I_eff``
    [-]), each slope over I_eff. An explicit step must be shorter than about their inverse."""
    inertia = design.I_eff
    windmill = _windmill_slope(design)
    pipe = 2.0 * friction_load(design) * design.omega_m / design.R_dagger
    q_L = design.leak_capacity
    hole = 2.0 * design.load_torque * design.A * design.R / q_L if q_L > 0.0 else 0.0
    return (
        windmill / inertia,
        pipe / inertia,
        hole / inertia,
        reciprocating_inertia(design) / inertia,
    )


def _windmill_slope(design: Design, gear_ratio=None):
    """a1 = 2 eta_t R+^2 (T_m - T_0) / omega_m [N m s]: how fast the windmill's torque on the
    crank falls with the crank's speed, at rest (Eq. 11 through the chain; a rotor's steepest
    fall, :func:`windpump.model.torque.steepest_fall`); at the design's
    R+ = R1/R0, or at the gear ratios given (an array: a design map's)."""
    ratio = design.R_dagger if gear_ratio is None else gear_ratio
    if design.rotor is not None:  # its steepest fall, wherever on its curve
        return design.eta_t * ratio**2 * steepest_fall(design)
    return 2.0 * design.eta_t * ratio**2 * (design.T_m - design.T_0) / design.omega_m


def _stiff_advice(design: Design, t_end: float | None = None, crawled: bool = False) -> str:
    """What makes ``design`` too stiff to integrate, in words, and which fields to change in
    which direction: from the largest cause of :func:`stiffness` when one explains the steps a
    run of t_end [s] would need (``STIFF_STEPS`` a unit of rate times time), and otherwise from
    the numbers at the ends of double precision that the time scales miss. The one wording of
    this advice, for :func:`simulate` and the numeric design maps. ``crawled``: the run took
    far more steps than :func:`estimated_steps` before it was refused (then the fastest time
    scale, when a run spans many of them, is named as the likely cause)."""
    windmill, pipe, hole, masses = stiffness(design)
    if masses > 1e3:
        return (f"reciprocating masses of {masses:.3g} times the rotor's inertia on the crank "
                "(a lighter m_r, or a heavier rotor: increase I0 or I1)")  # fmt: skip
    largest = max(windmill, pipe, hole)
    explained = t_end is None or STIFF_STEPS * largest * t_end > PACE_STEPS
    if explained:
        return _fastest_cause(design, windmill, pipe, hole)
    extreme = _extreme_numbers(design)
    if extreme != _NO_EXTREME or not crawled or t_end is None or largest * t_end < 1.0:
        return "none of its time scales explains it: " + extreme
    # A run over many of its fastest settling times, refused late (on pace to need 1.5 to 10
    # times MAX_STEPS: a leak hole on a light rotor takes ~1,700 steps per settling time, not
    # STIFF_STEPS): that time scale is the likely cause, and a shorter t_end the other way
    return f"most likely {_fastest_cause(design, windmill, pipe, hole)}; or a shorter t_end"


def _fastest_cause(design: Design, windmill: float, pipe: float, hole: float) -> str:
    """The fastest of :func:`stiffness`'s rates [1/s] as a cause, in words (:func:`_stiff_advice`)."""
    largest = max(windmill, pipe, hole)
    if largest == windmill:
        geared = design.I1 > design.I0 * design.R_dagger**2  # a1/I_eff then grows with R+
        return (f"a rotor too light for its windmill: the crank's speed settles in "
                f"{1 / windmill:.3g} s (a heavier rotor: increase I0 or I1"
                + (", or a smaller R1/R0" if geared else "") + ")")  # fmt: skip
    if largest == pipe:
        return (f"a rising main whose friction settles the crank's speed in {1 / pipe:.3g} s "
                "(a shorter or wider main: a smaller L_main or a larger D_main; or a heavier "
                "rotor)")  # fmt: skip
    return (f"a leak hole whose load settles the crank's speed in {1 / hole:.3g} s, "
            "rho_w g h (A R)^2 / q_L over I_eff (a lower head h, a wider hole d_leak or "
            "none, or a heavier rotor)")  # fmt: skip


_NO_EXTREME = ("a run longer than the step budget allows at its pace (a shorter t_end, "
               "or omega_m, T_m, T_0, R1/R0, I0 and I1 nearer the paper's machine)")  # fmt: skip


def _extreme_numbers(design: Design) -> str:
    """The numbers of ``design`` at the ends of double precision that make a run crawl, with
    the direction that brings each back, in words (:func:`_stiff_advice`)."""
    peak = design.omega_m / design.R_dagger  # the crank's speed at the windmill's peak torque
    causes = []
    if peak < 1e-6:
        causes.append(f"a crank speed at the windmill's peak torque, omega_m / R+, of "
                      f"{peak:.3g} rad/s (a larger omega_m or a smaller R1/R0)")  # fmt: skip
    elif peak > 1e6:
        causes.append(f"a crank speed at the windmill's peak torque, omega_m / R+, of "
                      f"{peak:.3g} rad/s (a smaller omega_m or a larger R1/R0)")  # fmt: skip
    start = design.R_dagger * design.T_0 / design.I_eff  # the crank's acceleration from rest
    if design.T_0 > 0.0 and start < 1e-200:  # (0.0 when it underflows)
        causes.append(f"a torque at rest T_0 = {design.T_0:.3g} N m that accelerates the crank "
                      f"from rest at {start:.3g} rad/s^2, below 1e-200 (a larger T_0, or none: "
                      "T_0 = 0, or a lighter rotor)")  # fmt: skip
    if not causes:
        causes.append(_NO_EXTREME)
    return "; ".join(causes)


def check_work(design: Design, t_end: float, record: WindRecord | None = None) -> None:
    """Refuse, before any work, a run whose :func:`estimated_steps` exceed ``MAX_STEPS``: it
    would stop there, after minutes and gigabytes, as if the design were too stiff. And a rotor
    so light that a run could not be done in ``MAX_STEPS``: a running crank takes at least
    ``STIFF_STEPS t_end a1 / I_eff`` steps (:func:`stiffness`), found after a minute before."""
    windmill = _windmill_slope(design) / design.I_eff  # (stiffness's first: no quadrature)
    if record is None and STIFF_STEPS * windmill * t_end > MAX_STEPS and _moves(design):
        raise ParameterError(
            "design",
            f"I_eff = {design.I_eff:.3g} kg m^2",
            f"a rotor heavy enough to run {t_end:g} s in at most {MAX_STEPS:,} integration steps",
            why=f"the design is too stiff: {_stiff_advice(design, t_end)}; or a shorter t_end",
        )
    steps = estimated_steps(design, t_end, record)
    if steps <= MAX_STEPS:
        return
    cause = "" if record is None else f" ({len(record.t):,} wind samples)"
    raise ParameterError(
        "t_end" if record is None else "wind",
        f"{t_end:g} s of running{cause}",
        f"a run of at most {MAX_STEPS:,} integration steps",
        why=f"this one would take about {steps:.3g}: one at every switch (every pi/n of crank "
        "angle) and at every sample where the wind bends; a shorter t_end or a coarser record",
    )


def _moves(design: Design) -> bool:
    """Whether a run of ``design`` keeps its crank turning: it can carry its load (or leaks)."""
    return stall_margin(design) > 1.0


def simulate(
    design: Design,
    t_end: float,
    theta0: float = math.pi / 2,
    theta_dot0: float = 3.0,
    *,
    wind=None,
    samples_per_stroke: int = SAMPLES_PER_STROKE,
    sample_dt: float | None = None,
) -> SimulationResult:
    """Integrate the wind pump's equation of motion, Eq. (12), in full, from a start angle and kick.

    ``I_eff theta_ddot = R+ T(R+ theta_dot) + sum of rho_w g h A R lever arm`` over the delivering
    faces, each ``sin(phi + theta_c)/cos(theta_c)`` at its cylinder's own angle
    ``phi = theta - 2 pi k / n`` and braking the crank; ``V`` from Eq. (16) for every face. The
    windmill torque is ``T = T_0 + (T_m - T_0) x (2 - x)``, Eq. (11) when T_0 = 0. No averaging:
    finite L/R, and every step ends on a switch (every pi / n of crank angle).

    With T_0 > 0 a run may start from rest: it moves when R+ T_0 exceeds the load torque at theta0
    and is otherwise stalled at t = 0. A crank that slows to rest stops there when the load at
    that angle is at least R+ T_0 (it cannot turn backwards), and goes on otherwise.

    In a wind record V(t) the rotor's curve follows the wind by similarity (``Design.in_wind``:
    ``T = s^2 T_0 + (T_m - T_0) x (2 s - x)``, s = V/V_ref) inside the compiled integrator. A crank
    that comes to rest then waits (theta_dot = 0, no flow) until ``R+ T_0 s(t)^2`` exceeds the load
    at its angle, and moves again; the run goes on to t_end and lists its ``stops`` and
    ``starts``. The energy balance closes as without wind.

    Parameters
    ----------
    design : Design
        The wind pump.
    t_end : float
        Duration [s], > 0; bounded so the run makes at most ``MAX_SAMPLES`` samples.
    theta0 : float, default pi/2
        Initial crank angle from TDC [rad], any finite value: it is reduced modulo 2 pi to
        [0, 2 pi), where the run's ``theta`` starts.
    theta_dot0 : float, default 3.0
        Initial crank speed [rad/s]: 0 (a start from rest, which moves only with torque at rest,
        see :func:`windpump.starts_from_rest`) or from ``SMALLEST_KICK`` (1e-300) to
        ``LARGEST_KICK`` (1e12).
    wind : (t, V) pair, callable or None, keyword-only
        Wind speeds V [m/s] (0 to 150) at times t [s] (increasing), linear between samples
        and held past the ends, e.g. a :class:`windpump.model.wind.WindRecord`; or a function of t [s]
        (called with an array), sampled evenly over the run (:func:`windpump.model.wind.as_record`).
        None: the design's own curve (at V_ref) throughout.
    samples_per_stroke : int, default 16, keyword-only
        Output samples every ``pi / samples_per_stroke`` of crank angle (1 to 1024).
    sample_dt : float or None, keyword-only
        Instead, one sample every ``sample_dt`` seconds [s], > 0 (and each stop and start): a day
        at 1 s is 86,401 samples.

    Returns
    -------
    SimulationResult
        ``t, theta, theta_dot, volume, flow, shaft_work``, ``stalled, t_stall``, ``steps``,
        ``stops``, ``starts`` and ``wind``. Without a wind record, when the crank stops for good
        the run ends there: ``stalled=True`` and ``t_stall`` [s].

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

    Two cylinders half a turn apart and a windmill with torque at rest start on their own:

    >>> d = Design.seed_example().replace(cylinders=2, T_0=0.4)
    >>> run = simulate(d, 600.0, theta_dot0=0.0)
    >>> from windpump.units import LITRES_PER_M3
    >>> run.stalled, round(float(run.volume[-1]) * LITRES_PER_M3)  # litres
    (False, 230)

    The same pump through a lull: the wind drops to 1 m/s for half an hour, then comes back. The
    heavy rotor coasts for eight minutes, rests, and starts again when the wind returns:

    >>> lull = ([0.0, 600.0, 610.0, 2400.0, 2410.0], [5.0, 5.0, 1.0, 1.0, 5.0])
    >>> run = simulate(d, 3600.0, theta_dot0=0.0, wind=lull, sample_dt=1.0)
    >>> [round(float(t)) for t in run.stops], [round(float(t)) for t in run.starts], run.stalled
    ([1115], [0, 2409], False)
    """
    if not isinstance(design, Design):
        raise TypeError(f"design must be a windpump.Design, not {type(design).__name__}")
    t_end, theta0, theta_dot0 = _checked_start(t_end, theta0, theta_dot0)
    samples_per_stroke = whole("samples_per_stroke", samples_per_stroke, 1, 1024)
    if sample_dt is not None:
        sample_dt = positive("sample_dt", sample_dt, "s")
    record = None if wind is None else as_record(wind, t_end)
    bound = sample_bound(design, t_end, theta_dot0, samples_per_stroke, sample_dt, record)
    if bound > MAX_SAMPLES:  # a second's worth: t_end's bound without overflow (t_end 1e308)
        per_second = sample_bound(design, 1.0, theta_dot0, samples_per_stroke, sample_dt, record)
        _refuse_too_many_samples(t_end, bound, per_second - 3, sample_dt)
    check_work(design, t_end, record)
    run = _kernels.run(
        kernel_machine(design, record),
        theta0,
        theta_dot0,
        t_end,
        samples_per_stroke,
        sample_dt,
        RTOL,
        MAX_STEPS,
        capacity=first_capacity(design, t_end, theta_dot0, bound, samples_per_stroke, sample_dt),
        pace=PACE_STEPS if record is None else None,
    )
    if run.outcome == _kernels.OVER_BUDGET:
        reached = float(run.t[-1])  # the last sample before the refusal
        crawled = reached > 0.0 and run.steps > 10.0 * estimated_steps(design, reached)
        raise ParameterError(
            "design",
            f"I_eff = {design.I_eff:.3g} kg m^2",
            "a design whose crank speed settles over more than a crank revolution",
            why=f"the integration needed more than {MAX_STEPS:,} steps, or after {run.steps:,} "
            f"was on pace to need them by t_end: the design is too stiff: "
            + _stiff_advice(design, t_end, crawled),
        )
    return _simulation_result(design, run, record)


def _checked_start(t_end, theta0, theta_dot0) -> tuple[float, float, float]:
    """:func:`simulate`'s t_end [s], theta0 [rad] (reduced to [0, 2 pi)) and theta_dot0 [rad/s],
    checked; a ParameterError names the first out of range."""
    t_end = positive("t_end", t_end, "s")
    # Reduced first: a huge angle leaves no digits for the steps (1e15 rad has an ulp of 0.125).
    theta0 = real("theta0", theta0, "rad") % (2 * math.pi)
    return t_end, theta0, checked_kick("theta_dot0", theta_dot0)


def checked_kick(name: str, kick: object) -> float:
    """A kick [rad/s] as a float: 0, or from SMALLEST_KICK to LARGEST_KICK; a ParameterError
    naming ``name`` otherwise (simulate's theta_dot0, run_in_wind's kick)."""
    value = non_negative(name, kick, "rad/s")
    if 0.0 < value < SMALLEST_KICK or value > LARGEST_KICK:
        raise ParameterError(
            name,
            value,
            f"0 or from {SMALLEST_KICK:g} to {LARGEST_KICK:g} rad/s",
            "rad/s",
            why="a smaller kick is below double precision's normal range"
            if value < SMALLEST_KICK
            else "",
        )
    return value


def _refuse_too_many_samples(
    t_end: float, bound: float, per_second: float, sample_dt: float | None
) -> None:
    """Raise a ParameterError naming t_end [s] when a run could need ``bound`` samples, more than
    MAX_SAMPLES (:func:`sample_bound`), ``per_second`` samples a second of the run; naming
    sample_dt [s] when it is given (a run's samples are then t_end / sample_dt)."""
    if bound > MAX_SAMPLES and sample_dt is not None:
        raise ParameterError(
            "sample_dt",
            sample_dt,
            f">= {t_end / (MAX_SAMPLES - 3):.6g} s for t_end = {t_end:g} s",
            "s",
            why=f"the run would make {bound:.3g} samples; the bound is {MAX_SAMPLES}",
        )
    if bound > MAX_SAMPLES:
        longest = (MAX_SAMPLES - 3) / per_second
        raise ParameterError(
            "t_end",
            t_end,
            f"<= {longest:.6g} s for this design, theta_dot0 and output grid",
            "s",
            why=f"the run could need {bound:.3g} samples; the bound is {MAX_SAMPLES}"
            " (fewer samples_per_stroke, or a sample_dt, make room)",
        )


def _hole_passes_all(design: Design, theta_dot: np.ndarray) -> bool:
    """Whether a leak hole passes all its face ever sweeps over a run: its capacity q_L at least
    twice the most a face can sweep at the run's fastest sample, 2 A R max theta_dot (the lever
    arm |x'/R| of Eq. 1 is below 2 for any L/R > 1; the factor 2 over it covers a speed between
    samples). Such a run delivers nothing (Eq. 16 with :func:`~windpump.model.loads.delivered_flow`):
    its volume is 0 exactly, not the swept volume less the leaked one, a difference of two equal
    quadratures whose error is all that would be left (issue 36)."""
    fastest = float(np.max(theta_dot)) if len(theta_dot) else 0.0
    return design.leak_capacity >= 4.0 * design.A * design.R * fastest


def _settled(volume: np.ndarray) -> None:
    """Make a leaky run's delivered volume [m^3] (swept less leaked) never fall and never dip
    below 0, in place: each sample becomes the least of it and every later one, and 0 at most.

    Delivered water never flows back, but a hole's window leaks as a jump at the window's end
    (docs/model.rst, "The real machine": a leak hole's windows, jumped): a sample inside a
    window still counts its swept water and not yet its leak, up to the window's leak too high
    (3e-11 m^3 in the app's preset, -7.6e-12 m^3 below 0 with a hole near the bore; issue 36).
    The next settled sample is the right level there; the last sample is unchanged."""
    np.maximum(volume, 0.0, out=volume)
    volume[:] = np.minimum.accumulate(volume[::-1])[::-1]


def _simulation_result(design: Design, run, record: WindRecord | None) -> SimulationResult:
    """The kernels' run (a ``_kernels.KernelRun``) as a :class:`SimulationResult`: volume and flow
    (Eq. 16, every face) from the strokes and flow factor, every array read-only; a leak hole's
    flow and loss are worked out when first read (:class:`Deferred`)."""
    swept = design.stroke_volume * (run.strokes - run.strokes[0])
    volume = swept
    # Eq. (16); with a leak hole the kernel's flow factor is the delivered flow's, not the swept
    flow = _flow(design.stroke_volume, run.flow_factor, run.theta_dot)
    if run.leaked is None:  # the ideal machine
        friction = leak = np.zeros_like(run.t)
    else:  # the real machine
        if design.leak_capacity > 0.0 and _hole_passes_all(design, run.theta_dot):
            volume = np.zeros_like(swept)
        elif design.leak_capacity > 0.0:  # (a tight piston delivers what it sweeps)
            volume = np.subtract(swept, run.leaked, out=run.leaked)  # (the kernel's own copy)
            _settled(volume)
        friction = run.friction_loss
        leak = functools.partial(_leak_loss, design, swept, volume, run.leak_loss, friction)
    arrays = (
        run.t, run.theta, run.theta_dot, volume, flow, run.shaft_work, run.stops, run.starts,
        swept, friction, leak,
    )  # fmt: skip
    for array in arrays:
        if isinstance(array, np.ndarray):
            array.flags.writeable = False
    stalled = run.outcome in (_kernels.STALLED, _kernels.RESTING)
    t_stall = None
    if stalled:
        t_stall = float(run.stops[-1]) if len(run.stops) else 0.0
    return SimulationResult(
        design,
        t=run.t,
        theta=run.theta,
        theta_dot=run.theta_dot,
        volume=volume,
        flow=flow,
        shaft_work=run.shaft_work,
        stalled=stalled,
        t_stall=t_stall,
        steps=run.steps,
        stops=run.stops,
        starts=run.starts,
        wind=record,
        swept_volume=swept,
        friction_loss=friction,
        leak_loss=leak,
    )


def _flow(stroke_volume: float, factor, theta_dot: np.ndarray):
    """The flow [m^3/s] of Eq. (16), ``stroke_volume`` [m^3] times the flow factor times the
    crank speed; a function working it out when the factor is one (a leak hole's:
    :class:`Deferred`)."""
    if isinstance(factor, np.ndarray):
        return stroke_volume * factor * theta_dot
    return lambda: stroke_volume * factor() * theta_dot


def _leak_loss(design: Design, swept, volume, excess_work, friction) -> np.ndarray:
    """The work lost through the leak holes [J]: the kernel integrates the load's excess over the
    static head (``excess_work``); the static head's work on the swept volume is closed form.
    What neither lifted water nor rubbed is the leak's: lift (swept - volume) + the excess's
    work - friction, in place (no temporaries)."""
    leak = np.subtract(swept, volume)
    leak *= design.rho_w * design.g * design.h
    leak += excess_work
    leak -= friction
    return leak
