"""The averaged theory: cycle-mean spin-up, stall criterion and time constant (paper Eqs. 18-25).

Averaging the load over a revolution (Eq. 18) turns Eq. (12) into the Riccati equation (19) for the
cycle-mean crank speed. Generalised to m = cylinders x (2 if double-acting else 1) deliveries per
revolution (mean load torque ``M = m rho_w g h A R / pi``) and a windmill torque at rest T_0, in
crank speed [rad/s] it reads

    d theta_dot / dt = -k [(theta_dot - p)^2 - delta^2],   k = R+^3 (T_m - T_0) / (I_eff omega_m^2),

with ``p = omega_m / R+`` (the crank speed at the windmill's peak torque) and
``delta^2 = p^2 (R+ T_m - M) / (R+ (T_m - T_0))``: the roots ``p +- delta`` are alpha+- omega_m of
Eq. (21), which these reduce to when m = 1 and T_0 = 0. Every function below takes its numbers from
that one form, written once (broadcasting over gear ratios, heads and winds) in
:mod:`windpump.averaging.theory`; this module adds the checks, the ``StallError`` and the solution in time
(Eqs. 23-24).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..errors import StallError
from ..model.design import Design
from ..model.kinematics import lever_arm
from ..validation import finite_array, non_negative, rod_ratio
from .revolution import Points, largest_ratio, largest_roots, leaky_spinup, stall_time
from .theory import RunningSpeeds, cycle_mean, running_speeds


def mean_lever_arm(L_over_R: float) -> float:
    """Cycle mean of the load's lever arm over the exhaust half, the integral of Eq. (18) [-].

    ``(1/2 pi) int_pi^2pi sin(theta + theta_c)/cos(theta_c) dtheta``, evaluated by adaptive
    quadrature; it equals -1/pi for every L/R > 1 (docs/model.rst, "Kinematics").

    Parameters
    ----------
    L_over_R : float
        Rod-to-crank ratio, > 1.

    Examples
    --------
    >>> import math
    >>> round(mean_lever_arm(3.75) * math.pi, 12)
    -1.0
    """
    ratio = rod_ratio(L_over_R)
    from scipy import integrate  # here, not at import: scipy.integrate takes ~0.5 s to load

    value, _ = integrate.quad(
        lambda theta: float(lever_arm(theta, ratio)),
        math.pi,
        2 * math.pi,
        epsabs=1e-14,
        epsrel=1e-13,
        limit=200,
    )
    return value / (2 * math.pi)


@functools.lru_cache(maxsize=64)
def own_speeds(design: Design) -> RunningSpeeds:
    """:func:`~windpump.averaging.theory.running_speeds` of the design as it is, remembered
    for the last designs (a frozen design is its own key): a run asks it up to three times (its
    sample count, its step count, whether it moves), and a rotor's takes ~0.7 ms."""
    return running_speeds(design)


def stall_margin(design: Design) -> float:
    """Stall margin [-]: above 1 the windmill can carry the load (Eq. 22 when m = 1).

    The largest ratio of the windmill's torque on the crank to the mean load over the crank
    speeds, ``max eta_t R+ T(R+ alpha) / L-bar(alpha)``. For the ideal machine it is the peak
    torque reflected to the crank over the mean load torque ``M = m rho_w g h A R / pi`` of m
    deliveries per revolution (``Design.mean_load_torque``), ``R+ T_m / M``; for the paper's one
    single-acting cylinder Eq. (22)'s ``T_m+ pi / (R+ L+)``. eta_t scales it; a rising main
    lowers it (``L-bar = M + c alpha^2``). Infinite when h = 0, and with a leak hole (the load
    through the hole vanishes at rest faster than the windmill's torque: such a pump never
    stalls, though in light wind it may only crawl, delivering nothing).

    Examples
    --------
    >>> from windpump import Design
    >>> round(stall_margin(Design.seed_example()), 2)
    5.1
    >>> round(stall_margin(Design.seed_example().replace(cylinders=2, double_acting=True)), 2)
    1.27
    >>> stall_margin(Design.seed_example().replace(d_leak=0.004))
    inf
    """
    if design.d_leak > 0.0:  # running_speeds' margin too, without its root finding
        return math.inf
    # One ratio of dimensional torques (equal to the groups' form), so that a tiny head cannot
    # underflow L+ to zero on the way.
    return float(own_speeds(design).margin)


def stall_sides(design: Design) -> tuple[float, float]:
    """The two sides of the stall criterion, Eq. (22): (T_m+, m R+ L+ / pi) [-].

    The windmill's characteristic torque (Eq. 14) and the mean load it must carry (Eq. 15 times
    m R+ / pi, m deliveries per revolution); it can run when the first exceeds the second. Their
    ratio is :func:`stall_margin`. For the real machine the first is ``eta_t T_m+`` (through
    the chain) and the second that over the stall margin: with a rising main the load the
    windmill carries at its best speed, 0 with a leak hole.

    Examples
    --------
    >>> from windpump import Design
    >>> windmill, load = stall_sides(Design.seed_example())
    >>> round(windmill / load, 2)
    5.1
    >>> stall_sides(Design.seed_example().replace(d_leak=0.004))[1]
    0.0
    """
    load = design.deliveries * design.R_dagger * design.L_dagger / math.pi
    if design.d_leak == 0.0 and design.friction_coefficient == 0.0 and design.rotor is None:
        return design.eta_t * design.Tm_dagger, load
    windmill = design.eta_t * design.Tm_dagger
    return windmill, windmill / stall_margin(design)


def _riccati(design: Design) -> tuple[float, float, float]:
    """(k [1/rad], p [rad/s], delta^2 [rad^2/s^2]) of the averaged equation in crank speed."""
    mean = cycle_mean(design)
    return float(mean.k), float(mean.p), float(mean.delta2)


def steady_speeds(design: Design) -> tuple[float, float | None]:
    """Steady cycle-mean crank speeds (alpha+, alpha-) x omega_m [rad/s] (Eq. 21, generalised).

    The roots of ``F(alpha) = eta_t R+ T(R+ alpha) - L-bar(alpha)``: alpha+ the largest, where
    F falls (the stable running speed), alpha- the one below it where F rises (a pump below it
    decays, in the averaged model). Without a leak hole ``p +- delta`` of the averaged equation
    (module docstring); with m = 1, T_0 = 0 and the ideal machine this is Eq. (21),
    ``alpha+- = (pi T+ +- sqrt(pi^2 T+^2 - pi R+ T+ L+)) / (pi R+ T+)``. With torque at rest
    alpha- may be <= 0: when ``eta_t R+ T_0`` exceeds the mean load every kick (and a start
    from rest) spins up. With a leak hole alpha- is None where F > 0 from rest to alpha+
    (then every start spins up to alpha+), and alpha+ may be a crawl (the pump turns so slowly
    that all the water leaks back: ``steady_flow`` 0).

    Raises
    ------
    StallError
        When the stall margin is 1 or less: there is no steady speed.

    Examples
    --------
    >>> from windpump import Design
    >>> a_plus, a_minus = steady_speeds(Design.seed_example())
    >>> round(a_plus, 2), round(a_minus, 3)
    (23.71, 1.293)
    >>> a_plus, a_minus = steady_speeds(Design.seed_example().replace(d_leak=0.004))
    >>> round(a_plus, 2), a_minus
    (23.71, None)
    """
    speeds = own_speeds(design)
    if not speeds.runs:
        raise StallError(float(speeds.margin), "a steady speed")
    alpha_minus = float(speeds.alpha_minus)
    if (design.d_leak > 0.0 or design.rotor is not None) and math.isnan(alpha_minus):
        return float(speeds.alpha_plus), None
    return float(speeds.alpha_plus), alpha_minus


def time_constant(design: Design) -> float:
    """Spin-up time constant tau = I-bar / (-F'(alpha+)) [s] (Eq. 25, generalised).

    The rate at which the averaged equation relaxes to alpha+; without a leak hole
    ``1 / (2 k delta)``, and with m = 1, T_0 = 0 and the ideal machine Eq. (25)'s
    ``tau+ / omega_m``, ``tau+ = pi / (2 sqrt(pi^2 T+^2 - pi R+ T+ L+))``. It grows without
    bound as the stall margin falls to 1.

    Raises
    ------
    StallError
        When the stall margin is 1 or less.

    Examples
    --------
    >>> from windpump import Design
    >>> round(time_constant(Design.seed_example()), 1)
    78.6
    """
    speeds = own_speeds(design)
    if not speeds.runs:
        raise StallError(float(speeds.margin), "a spin-up time constant")
    return float(speeds.tau)


def _g(t, k: float, delta2: float):
    """The time function of the Riccati solution: tanh(k d t)/d, k t, or tan(k q t)/q (d^2 = -q^2)."""
    if delta2 > 0.0:
        d = math.sqrt(delta2)
        return np.tanh(k * d * t) / d
    if delta2 < 0.0:
        q = math.sqrt(-delta2)
        return np.tan(k * q * t) / q
    return k * t


def averaged_stall_time(design: Design, theta_dot0: float) -> float | None:
    """When the averaged model (Eq. 19) started at theta_dot0 stalls [s], or None if it never does.

    It stalls when the margin of Eq. (22) is 1 or less, or when kicked below alpha- (Eq. 21); a
    start from rest (theta_dot0 = 0) stalls at once unless R+ T_0 exceeds the mean load.

    Examples
    --------
    >>> from windpump import Design
    >>> averaged_stall_time(Design.seed_example(), 3.0) is None
    True
    >>> round(averaged_stall_time(Design.seed_example(), 1.0), 1)
    113.3
    """
    theta_dot0 = non_negative("theta_dot0", theta_dot0, "rad/s")
    if design.d_leak > 0.0:  # F > 0 just above rest: only a crank at rest with T_0 = 0 stays
        return 0.0 if theta_dot0 == 0.0 and design.T_0 == 0.0 else None
    if design.rotor is not None:
        return _rotor_stall_time(design, theta_dot0)
    k, p, delta2 = _riccati(design)
    if delta2 > 0.0:  # from the roots (p^2 - delta^2 cancels when they lie decades apart)
        mean = cycle_mean(design)
        a_plus, a_minus = float(mean.alpha_plus), float(mean.alpha_minus)
        if theta_dot0 >= a_minus:
            return None
        # alpha reaches 0 where (alpha - a-)/(a+ - alpha) has fallen from its start to -a-/a+
        drop = math.log1p(-theta_dot0 / a_plus) - math.log1p(-theta_dot0 / a_minus)
        return drop / (k * (a_plus - a_minus))
    bend = delta2 + p * (theta_dot0 - p)
    if bend >= 0.0:
        return None
    g_star = -theta_dot0 / bend
    if delta2 < 0.0:
        q = math.sqrt(-delta2)
        return math.atan(q * g_star) / (k * q)
    return g_star / k


def _rotor_stall_time(design: Design, theta_dot0: float) -> float | None:
    """:func:`averaged_stall_time` of a rotor's pump: it settles where F falls through 0 above
    or below the kick (alpha+ from above alpha-, or a lower falling root), else it decays to
    rest after ``I-bar int_0^theta_dot0 dalpha / -F``."""
    points = Points(design, None, None, None)
    falling, rising, lower = (float(r[0]) for r in largest_roots(points, points.runaway, True))
    runs = float(largest_ratio(points)[0]) > 1.0
    if runs and (math.isnan(rising) or theta_dot0 >= rising):
        return None
    if runs and not math.isnan(lower):  # F > 0 near rest: a slower steady speed, no stall
        return None
    return stall_time(points, theta_dot0)


def spinup(design: Design, t, theta_dot0: float):
    """Cycle-mean crank speed [rad/s] at times t [s] by the averaged theory, Eq. (24).

    The closed-form solution of Eq. (19) from the initial crank speed theta_dot0: it rises or falls
    to alpha+ (Eq. 21) on the time scale tau (Eq. 25) when kicked above alpha-, and decays to a stall
    when kicked below alpha- or when the margin of Eq. (22) is 1 or less; after the stall
    (:func:`averaged_stall_time`) the speed is 0.

    Parameters
    ----------
    design : Design
    t : array_like
        Times [s], >= 0.
    theta_dot0 : float
        Initial crank speed [rad/s], >= 0.

    Returns
    -------
    ndarray
        Cycle-mean crank speed [rad/s], the shape of t.

    Examples
    --------
    >>> from windpump import Design, spinup
    >>> [round(float(w), 2) for w in spinup(Design.seed_example(), [0.0, 79.0, 600.0], 3.0)]
    [3.0, 5.41, 23.58]
    """
    theta_dot0 = non_negative("theta_dot0", theta_dot0, "rad/s")
    t = finite_array("t", t, "s", minimum=0.0)
    if design.d_leak > 0.0 or design.rotor is not None:
        return leaky_spinup(design, t, theta_dot0)
    k, p, delta2 = _riccati(design)
    t_stall = averaged_stall_time(design, theta_dot0)
    running = t < t_stall if t_stall is not None else np.ones(t.shape, dtype=bool)
    t_run = np.where(running, t, 0.0)
    if delta2 > 0.0:
        mean = cycle_mean(design)
        roots = float(mean.alpha_plus), float(mean.alpha_minus)
        speed = _between_roots(t_run, k, theta_dot0, *roots)
    else:
        g = _g(t_run, k, delta2)
        z0 = theta_dot0 - p
        speed = p + (z0 + delta2 * g) / (1.0 + z0 * g)
    return np.where(running, speed, 0.0)


def _between_roots(t, k: float, theta_dot0: float, a_plus: float, a_minus: float):
    """Eq. (24) with two real roots, written from them: ``(alpha - a-) / (a+ - alpha)`` grows as
    ``exp(k (a+ - a-) t)``.

    The same curve as ``p + (z0 + delta^2 g) / (1 + z0 g)``, but with no difference of nearly
    equal numbers: that form lost every digit (and gave negative speeds) when the roots lie many
    orders of magnitude apart (alpha- ~ 1e-45, alpha+ ~ 1e20 rad/s, inside the fields' range).
    """
    span = a_plus - a_minus
    if theta_dot0 == a_plus:
        return np.full(t.shape, a_plus)
    ratio = (theta_dot0 - a_minus) / (a_plus - theta_dot0)  # (alpha - a-) / (a+ - alpha) at 0
    if ratio == 0.0:
        return np.full(t.shape, a_minus)
    # Exponents kept finite: past exp(690) alpha is its limit to the last digit anyway.
    rate = np.minimum(k * span * t, 690.0)
    if ratio > 0.0 and a_minus < 0.0:  # between the roots, a- below rest: from the kick, as
        # theta_dot0 + (theta_dot0 - a-) expm1(rate) / (1 + x): the weighted roots' form has
        # terms of opposite signs there, cancelling to round-off of |a-| (a crank at 3 rad/s
        # between roots 1e36 apart started at -6.7e7 rad/s; issue 36)
        x = np.exp(np.minimum(math.log(ratio) + k * span * t, 690.0))
        return theta_dot0 + (theta_dot0 - a_minus) * (np.expm1(rate) / (1.0 + x))
    if ratio > 0.0:  # between the roots: rises (or falls) to a+
        x = np.exp(np.minimum(math.log(ratio) + k * span * t, 690.0))
        return a_minus / (1.0 + x) + a_plus * (x / (1.0 + x))
    # |ratio| e^rate - 1 and 1 - |ratio| e^rate from the gaps, not from |ratio| ~ 1
    if theta_dot0 > a_plus:  # above a+: falls to it
        return a_plus + span / (span / (theta_dot0 - a_plus) * np.exp(rate) + np.expm1(rate))
    # Below a-: decays to the stall (1 + ratio e^rate reaches 0 there), from the kick as
    # theta_dot0 + (theta_dot0 - a-) expm1(rate) / (1 + ratio e^rate): written from a- it
    # cancelled to round-off of a- (a kick of 3 rad/s under a- = 5.5e16 started at -8 rad/s)
    with np.errstate(divide="ignore"):
        rest = span / (a_plus - theta_dot0) + ratio * np.expm1(rate)  # 1 + ratio e^rate
        return theta_dot0 + (theta_dot0 - a_minus) * (np.expm1(rate) / rest)
