"""Compiled kernels for the equation of motion, Eq. (12). Private: call :func:`windpump.simulate`.

The package keeps apart what poliastro keeps apart in its ``core``: the model (:mod:`.model`:
Eq. 1, the loads of every delivering face, the windmill curve with T_0), the Dormand-Prince 5(4)
tableau (:mod:`.dopri5`), the steps in angle or time (:mod:`.stepping`) and the driver
(:mod:`.driver`). This module is their typed front: :func:`run` takes a :class:`Machine` and returns
a :class:`KernelRun`.

Method (docs/model.rst, "Dynamics")
-----------------------------------
The load switches on and off at the switches theta = k pi / n, where the right-hand side has a
kink. Between switches the crank angle is the independent variable, with ``u = theta_dot^2/2``
and the quadratures ``t`` and ``W`` (shaft work)::

    du/dtheta = (R+ T(R+ theta_dot) + load(theta)) / I_eff,  dt/dtheta = 1/theta_dot,  dW/dtheta = R+ T

so every segment between switches is integrated on its own and no step straddles a switch. The
load's work over a segment is known in closed form from Eq. (1), so the angle domain integrates
``u - Lambda(theta)``: only the windmill torque is left to integrate, and it is also the integrand
of W. A Runge-Kutta method keeps such a linear relation exactly, so the energy balance closes to
round-off, sub-step by sub-step. Samples on the uniform output grid come from the method's order-4
continuous extension. Near rest and for the stretch that ends at ``t_end`` the same tableau
integrates in time, with state ``(theta, theta_dot)``; a stop is located by Newton's method on the
step length.

Importing this package loads numba and the kernels (not compiling them: numba compiles each on
its first call, or loads it from its cache). ``import windpump`` does not import it: the package's
public names are imported on first use, and only the full run's (:mod:`windpump.run`), a site's
year's and a study's modules import the kernels.
"""

from __future__ import annotations

import functools
import typing

import numba
import numpy as np

from . import driver
from .model import Machine, Real
from .real import leaky_flow_factors
from .stepping import OVER_BUDGET, REACHED_T_END, RESTING, STALLED, START, STOP
from .wind import Wind

__all__ = [
    "OVER_BUDGET",
    "REACHED_T_END",
    "RESTING",
    "STALLED",
    "KernelRun",
    "Machine",
    "Real",
    "Wind",
    "is_cached",
    "run",
]


class KernelRun(typing.NamedTuple):
    """What the driver produced: samples (contiguous arrays) and how it ended."""

    t: np.ndarray  # [s]
    theta: np.ndarray  # [rad]
    theta_dot: np.ndarray  # [rad/s]
    shaft_work: np.ndarray  # [J]
    strokes: np.ndarray  # stroke volumes 2 R A delivered since theta = 0 [-]
    flow_factor: np.ndarray | typing.Callable[[], np.ndarray]  # sum of f2 (Eq. 16) over the
    # delivering faces [-]; with a leak hole the delivered flow over 2 R A theta_dot, as a
    # function that works it out (0.13 ms of the seed example's 600 s, a caller may never read)
    outcome: int  # REACHED_T_END, STALLED, RESTING or OVER_BUDGET
    steps: int  # Dormand-Prince steps taken, rejected ones included
    stops: np.ndarray  # times the crank came to rest and waited for the wind [s]
    starts: np.ndarray  # times a resting crank began to turn [s]
    # The real machine's quadratures (None for the ideal machine's run):
    leaked: np.ndarray | None = None  # volume swept but leaked back through the holes [m^3]
    friction_loss: np.ndarray | None = None  # work lost to the rising main's friction [J]
    leak_loss: np.ndarray | None = None  # the rest of the load's work: the leak hole's [J]


def run(
    machine: Machine,
    theta0: float,
    theta_dot0: float,
    t_end: float,
    samples_per_stroke: int,
    sample_dt: float | None,
    rtol: float,
    max_steps: int,
    capacity: int,
    pace: int | None = None,
) -> KernelRun:
    """Integrate from (theta0 [rad], theta_dot0 [rad/s]) at t = 0 up to t_end [s] or a stop.

    Samples every pi / samples_per_stroke of crank angle or, when sample_dt is not None, every
    sample_dt [s]. ``capacity`` is a first guess of the sample count; the output grows
    (doubling) past it. Past ``pace`` steps the run ends OVER_BUDGET as soon as it is on pace to
    pass max_steps by t_end (None: only at max_steps).
    """
    ran = driver.integrate(
        machine,
        theta0,
        theta_dot0,
        t_end,
        samples_per_stroke,
        sample_dt,
        rtol,
        max_steps,
        max_steps if pace is None else pace,
        capacity,
    )
    out, n = ran.out, ran.samples
    leaky = machine.real is not None and machine.real.q_L > 0.0
    t, theta, theta_dot, strokes, flow, work = (
        out[row, :0] if leaky and row == driver.FLOW_FACTOR else out[row, :n].copy()
        for row in range(driver.ROWS)
    )  # (a leak hole's flow factor is the delivered flow's, not the driver's: not copied)
    if leaky:  # worked out when the flow is first read (:class:`KernelRun`)
        flow = functools.partial(
            leaky_flow_factors, theta.view(), theta_dot.view(), samples_per_stroke, machine
        )  # (views: the arrays are made read-only, which numba would compile again for)
    real = [out[row, :n].copy() for row in range(driver.ROWS, out.shape[0])]
    times, kinds = ran.events[0, : ran.event_count], ran.events[1, : ran.event_count]
    return KernelRun(
        t,
        theta,
        theta_dot,
        work,
        strokes,
        flow,
        int(ran.outcome),
        int(ran.steps),
        stops=times[kinds == STOP].copy(),
        starts=times[kinds == START].copy(),
        leaked=real[0] if real else None,
        friction_loss=real[1] if real else None,
        leak_loss=real[2] if real else None,
    )


def is_cached(machine: Machine, sample_dt: float | None) -> bool:
    """Whether numba's on-disk cache holds :func:`run`'s driver compiled for these argument types
    (the machine's, and a sample_dt or None), from the cache's index alone; False when it does
    not, or when caching is off or numba's private cache API has changed."""
    dispatcher = driver.integrate
    arguments = (machine, 0.0, 0.0, 1.0, 1, sample_dt, 1e-8, 1, 1, 1)  # typed as run() passes them
    try:
        signature = tuple(numba.typeof(argument) for argument in arguments)
        cache = dispatcher._cache
        key = cache._index_key(signature, dispatcher.targetctx.codegen())
        return key in cache._cache_file._load_index()
    except Exception:  # a NullCache (no caching), or another numba
        return False
