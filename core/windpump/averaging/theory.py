"""The averaged theory written once: the cycle-mean equation of the crank speed, its roots and its
time constant (paper Eqs. 18-25), broadcasting over arrays of gear ratios, heads and wind speeds.

Averaging the load over a revolution (Eq. 18) turns Eq. (12) into the Riccati equation (19) for the
cycle-mean crank speed. Generalised to m = cylinders x (2 if double-acting else 1) deliveries per
revolution (mean load torque ``M = m rho_w g h A R / pi``), a windmill torque at rest T_0 and a
wind V (by similarity the windmill's torques scale as s^2 and its speeds as s, ``s = V / V_ref``),
in crank speed [rad/s] it reads

    d theta_dot / dt = -k [(theta_dot - p)^2 - delta^2],
    k = R+^3 (T_m - T_0) / (I_eff omega_m^2),   p = s omega_m / R+,
    delta^2 = (omega_m / R+)^2 (R+ T_m s^2 - M) / (R+ (T_m - T_0)),

with T_m, T_0 and omega_m the curve's at V_ref and ``I_eff = I1 + I0 R+^2``; k does not depend on
the wind.

The real machine (docs/model.rst, "The real machine: averaged theory") averages to
``I-bar alpha' = F(alpha) = eta_t R+ T(R+ alpha) - L-bar(alpha)``, I-bar = I_eff + m_r sum_c
<x_c'^2> (the weight averages out). Without a leak hole ``L-bar = M + c alpha^2`` (c: the rising
main) and F is still a quadratic: with ``b = eta_t R+^3 (T_m - T_0) / omega_m^2`` and
``kappa = b / (b + c)``, ``k = (b + c) / I-bar``, p is kappa times the above and
``delta^2 = kappa (D - (1 - kappa) (s omega_m/R+)^2)``, D the above with R+ T_m and R+ T_0 times
eta_t; the paper's ideal machine (eta_t = 1, c = 0, m_r = 0) is the above to the last bit. With a
leak hole L-bar is a quadrature (:mod:`windpump.averaging.revolution`) and :func:`running_speeds` finds
the roots numerically. The roots ``p +- delta`` are alpha+- omega_m of Eq. (21), which these reduce to when
m = 1, T_0 = 0 and s = 1; delta^2 > 0 exactly when the stall margin ``R+ T_m s^2 / M`` exceeds 1
(Eq. 22), and the relaxation time at alpha+ is ``tau = 1 / (2 k delta)`` (Eq. 25).

:mod:`windpump.averaging.averaged` (one design, with its checks and ``StallError``), :mod:`windpump.study.maps`
(a grid of gear ratios and heads) and :mod:`windpump.sites.site` (wind speeds) all evaluate these
expressions here, through :func:`cycle_mean`. The groups they share with
:class:`~windpump.Design` (I_eff, the load torques, the torque at rest) and
:class:`~windpump.model.groups.RunningSpeeds` live below the design, in :mod:`windpump.model.groups`, and are
re-exported here. :func:`steady_flow` (re-exported by
:mod:`windpump.sites.site`) is the mean flow of the running speeds in steady winds: it sits here, below
the full run, whose step estimate (:func:`windpump.run.dynamics.estimated_steps`) uses it.
"""

from __future__ import annotations

import dataclasses
import math
import typing

import numpy as np

from ..errors import ParameterError
from ..model.design import Design
from ..model.groups import (
    RunningSpeeds,
    effective_inertia,
    load_torque,
    mean_load_torque,
    rest_torque_on_crank,
)
from ..model.wind import MAX_WIND
from ..validation import finite_array
from .revolution import friction_load, numeric_running_speeds, reciprocating_inertia

__all__ = [
    "CycleMean",
    "RunningSpeeds",
    "cycle_mean",
    "effective_inertia",
    "load_torque",
    "mean_load_torque",
    "rest_torque_on_crank",
    "running_speeds",
    "steady_flow",
]


Array = typing.Any  # a float or an ndarray: every expression broadcasts


@dataclasses.dataclass(frozen=True)
class CycleMean:
    """The averaged equation of designs that differ in gear ratio, head and wind (module
    docstring); every attribute broadcasts over the shapes of the arrays it was made from.

    Made by :func:`cycle_mean`. Where the pump cannot run (margin <= 1) the speeds and tau are
    NaN.

    Attributes
    ----------
    R_dagger : float or ndarray
        Gear ratio R1/R0 [-].
    T_m, T_0 : float
        The windmill's peak torque and torque at rest at V_ref [N m].
    omega_m : float
        The windmill speed of the peak at V_ref [rad/s].
    I_eff : float or ndarray
        Inertia reflected to the crank [kg m^2].
    mean_load : float or ndarray
        Cycle-mean load torque M [N m].
    s : float or ndarray
        Wind speed over V_ref [-].
    eta_t : float
        Transmission efficiency [-] (1: the ideal chain).
    friction : float
        The rising main's mean load per crank speed squared c [N m s^2]: the mean load is
        ``M + c alpha^2`` (0: no pipe).
    reciprocating_inertia : float
        What the reciprocating masses add to the mean inertia, ``m_r sum_c <x_c'^2>``
        [kg m^2].
    """

    R_dagger: Array
    T_m: float
    T_0: float
    omega_m: float
    I_eff: Array
    mean_load: Array
    s: Array = 1.0
    eta_t: Array = 1.0
    friction: Array = 0.0
    reciprocating_inertia: Array = 0.0

    @property
    def I_bar(self) -> Array:
        """The revolution-mean inertia on the crank, ``I_eff + m_r sum_c <x_c'^2>`` [kg m^2]."""
        return self.I_eff + self.reciprocating_inertia

    @property
    def b(self) -> Array:
        """The windmill curve's curvature on the crank, ``eta_t R+^3 (T_m - T_0) / omega_m^2``
        [N m s^2]: ``eta_t R+ T(R+ alpha)`` falls as ``-b alpha^2`` plus a linear part."""
        return self.eta_t * self.R_dagger**3 * (self.T_m - self.T_0) / self.omega_m**2

    @property
    def kappa(self) -> Array:
        """``b / (b + c)`` [-]: how much the pipe's friction (c) steepens the load; 1 without
        a pipe."""
        return self.b / (self.b + self.friction)

    @property
    def margin(self) -> Array:
        """Stall margin [-]: the largest ``eta_t R+ T(R+ alpha) / (M + c alpha^2)`` over the
        crank speeds, ``eta_t R+ T_m s^2 / M`` without a pipe (Eq. 22); inf where there is no
        load."""
        peak = self.eta_t * self.R_dagger * self.T_m * self.s**2  # the peak torque on the crank
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            margin = np.where(self.mean_load > 0.0, np.divide(peak, self.mean_load), math.inf)
            return np.where(self.friction > 0.0, self._margin_with_pipe(), margin)

    def _margin_with_pipe(self) -> Array:
        """The largest ratio ``(a0 + a1 alpha - b alpha^2) / (M + c alpha^2)`` over alpha >= 0:
        where its derivative vanishes, ``a1 c alpha^2 + 2 (b M + a0 c) alpha - a1 M = 0``."""
        a0 = self.eta_t * self.rest_torque  # the windmill's torque on the crank at rest
        a1 = 2.0 * self.b * self.omega_m * self.s / self.R_dagger
        M, c = self.mean_load, self.friction
        half = self.b * M + a0 * c
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            best = a1 * M / (half + np.sqrt(half * half + a1 * a1 * c * M))
            ratio = (a0 + (a1 - self.b * best) * best) / (M + c * best * best)
            return np.where(M > 0.0, ratio, math.inf)

    @property
    def runs(self) -> Array:
        """Whether the pump can run: the margin exceeds 1 [bool]."""
        return self.margin > 1.0

    @property
    def k(self) -> Array:
        """Rate of the averaged equation, ``(b + c) / I-bar`` [1/rad]: ``R+^3 (T_m - T_0) /
        (I_eff omega_m^2)`` for the ideal machine."""
        rate = self.eta_t * self.R_dagger**3 * (self.T_m - self.T_0)
        with_pipe = rate + self.friction * self.omega_m**2
        return with_pipe / (self.I_bar * self.omega_m**2)

    @property
    def p(self) -> Array:
        """Centre of the roots, ``kappa s omega_m / R+`` [rad/s]: the crank speed at the
        windmill's peak torque in this wind without a pipe."""
        return self.kappa * (self.omega_m / self.R_dagger * self.s)

    @property
    def delta2(self) -> Array:
        """``delta^2 = kappa (D - (1 - kappa) (s omega_m/R+)^2)`` [rad^2/s^2], with
        ``D = (omega_m/R+)^2 (eta_t R+ T_m s^2 - M) / (eta_t R+ (T_m - T_0))``, delta^2 itself
        without a pipe."""
        at_peak = self.omega_m / self.R_dagger  # p at V_ref
        spare = self.eta_t * self.R_dagger * self.T_m * self.s**2 - self.mean_load  # [N m]
        pipeless = at_peak * at_peak * spare / (self.eta_t * self.R_dagger * (self.T_m - self.T_0))
        steeper = (1.0 - self.kappa) * (at_peak * self.s) ** 2
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            # With a pipe, p^2 + (a0 - M) / (b + c): the same number without the difference
            # of pipeless and steeper, which cancel to their last digits when the pipe's c
            # dwarfs b (kappa ~ 1e-63: delta^2 was round-off, tau -78 s; issue 36).
            piped = self.p * self.p + (self.eta_t * self.rest_torque - self.mean_load) / (
                self.b + self.friction
            )
        return np.where(self.friction > 0.0, piped, self.kappa * (pipeless - steeper))

    @property
    def delta2_per_s2(self) -> Array:
        """How delta^2 grows with the wind, ``kappa (omega_m/R+)^2 (T_m / (T_m - T_0) - (1 -
        kappa))`` [rad^2/s^2]: by the wind similarity ``delta^2 = delta2_per_s2 (s^2 -
        s_stop^2)``, ``s_stop^2 = 1/margin(V_ref)`` without a pipe."""
        at_peak = self.omega_m / self.R_dagger
        pipeless = at_peak * at_peak * self.T_m / (self.T_m - self.T_0)
        # With a pipe kappa (omega_m/R+)^2 (T_0 / (T_m - T_0) + kappa): T_m / (T_m - T_0) - 1
        # and 1 - kappa cancel to round-off (0, and a division by it) when kappa is tiny.
        piped = self.kappa * at_peak * at_peak * (self.T_0 / (self.T_m - self.T_0) + self.kappa)
        return np.where(
            self.friction > 0.0,
            piped,
            self.kappa * (pipeless - (1.0 - self.kappa) * at_peak * at_peak),
        )

    @property
    def s_stop(self) -> Array:
        """The wind speed over V_ref below which the pump cannot run [-]: where delta^2 = 0,
        ``s / sqrt(margin)`` without a pipe. With one, where the averaged equation's roots
        meet, ``F = a0 (s'/s)^2 + a1 (s'/s) alpha - (b + c) alpha^2 - M`` with a double root:
        ``s' = s sqrt(4 M / (a1^2 / (b + c) + 4 a0))`` (delta^2 and its wind slope, both ~kappa^2,
        underflowed under a hair-thin main, and V_stop was inf or NaN; issue 36)."""
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            pipeless = np.sqrt(np.maximum(self.s**2 - self.delta2 / self.delta2_per_s2, 0.0))
            a0 = self.eta_t * self.rest_torque
            a1 = 2.0 * self.b * self.omega_m * self.s / self.R_dagger
            meet = 4.0 * self.mean_load / (a1 * (a1 / (self.b + self.friction)) + 4.0 * a0)
            piped = self.s * np.sqrt(np.maximum(meet, 0.0))
            return np.where(self.friction > 0.0, piped, pipeless)

    @property
    def delta(self) -> Array:
        """Half the distance between the roots, ``sqrt(delta^2)`` [rad/s]; NaN where it cannot
        run."""
        return np.sqrt(np.where(self.runs, np.maximum(self.delta2, 0.0), math.nan))

    @property
    def alpha_plus(self) -> Array:
        """Stable cycle-mean running speed ``p + delta`` [rad/s] (Eq. 21); NaN where it cannot
        run."""
        return self.p + self.delta

    @property
    def alpha_minus(self) -> Array:
        """Unstable steady speed ``p - delta`` [rad/s] (Eq. 21), from the product of the roots
        ``kappa (omega_m/R+)^2 (M - eta_t R+ T_0 s^2) / (eta_t R+ (T_m - T_0))`` over alpha+ (the difference cancels
        when the load is light); <= 0 when the torque at rest beats the mean load. NaN where it
        cannot run."""
        at_peak = self.omega_m / self.R_dagger
        product = at_peak * at_peak * (self.mean_load - self.eta_t * self.rest_torque)
        with np.errstate(divide="ignore", invalid="ignore"):
            windmill = self.eta_t * self.R_dagger * (self.T_m - self.T_0)
            return self.kappa * (product / windmill / self.alpha_plus)

    @property
    def tau(self) -> Array:
        """Spin-up time constant ``1 / (2 k delta) = I-bar / (-F'(alpha+))`` [s] (Eq. 25); NaN
        where it cannot run."""
        with np.errstate(divide="ignore"):
            return 1.0 / (2.0 * self.k * self.delta)

    @property
    def rest_torque(self) -> Array:
        """The windmill's torque at rest reflected to the crank, ``R+ T_0 s^2`` [N m]."""
        return rest_torque_on_crank(self.R_dagger, self.T_0, self.s)


def cycle_mean(
    design: Design,
    *,
    gear_ratio: Array | None = None,
    head: Array | None = None,
    V: Array | None = None,
) -> CycleMean:
    """The averaged equation (Eqs. 19-25, generalised) of ``design`` varied in gear ratio, head
    and wind, broadcasting: its closed forms, for a pump without a leak hole.

    The gear ratio R+ is varied through R1 with R0 fixed (so ``I_eff = I1 + I0 R+^2`` changes
    with it); every other field is the design's. The real machine's transmission efficiency,
    reciprocating mass and rising main keep the equation a Riccati equation (module docstring):
    eta_t scales the windmill's torque, the masses add to the inertia and the pipe adds
    ``c alpha^2`` to the mean load. :func:`running_speeds` covers a leak hole too.

    Parameters
    ----------
    design : Design
    gear_ratio : float or array_like, optional
        R+ = R1/R0 [-]; the design's by default.
    head : float or array_like, optional
        Head h [m]; the design's by default.
    V : float or array_like, optional
        Wind speeds [m/s] (by similarity from the curve at V_ref); V_ref by default.

    Returns
    -------
    CycleMean
        Whose attributes (margin, alpha_plus, alpha_minus, tau, ...) have the broadcast shape of
        the arguments.

    Raises
    ------
    ParameterError
        Naming ``d_leak`` for a pump with a leak hole (no closed form).

    Examples
    --------
    >>> from windpump import Design
    >>> mean = cycle_mean(Design.seed_example(), gear_ratio=[3.0, 4.0], head=[[2.0], [3.0]])
    >>> mean.alpha_plus.round(2).tolist()  # rows: heads, columns: gear ratios
    [[31.81, 24.15], [30.99, 23.71]]
    >>> float(cycle_mean(Design.seed_example()).tau.round(1))
    78.6
    """
    if design.d_leak > 0.0:
        raise ParameterError(
            "d_leak", design.d_leak, "0 (no leak hole) for the closed forms", "m",
            why="with a leak hole the averaged equation is solved by quadrature: running_speeds",
        )  # fmt: skip
    if design.rotor is not None:
        raise ParameterError(
            "rotor", "a Rotor", "None (the paper's Eq. 11) for the closed forms",
            why="a rotor's averaged equation is solved numerically: running_speeds",
        )  # fmt: skip
    R_dagger = design.R_dagger if gear_ratio is None else np.asarray(gear_ratio, dtype=float)
    h = design.h if head is None else np.asarray(head, dtype=float)
    load = load_torque(design.rho_w, design.g, h, design.A, design.R)
    return CycleMean(
        R_dagger=R_dagger,
        T_m=design.T_m,
        T_0=design.T_0,
        omega_m=design.omega_m,
        I_eff=effective_inertia(design.I1, design.I0, R_dagger),
        mean_load=mean_load_torque(design.deliveries, load),
        s=1.0 if V is None else np.asarray(V, dtype=float) / design.V_ref,
        eta_t=design.eta_t,
        friction=friction_load(design),
        reciprocating_inertia=reciprocating_inertia(design),
    )


def running_speeds(
    design: Design,
    *,
    gear_ratio: Array | None = None,
    head: Array | None = None,
    V: Array | None = None,
) -> RunningSpeeds:
    """Stall margin, steady speeds, time constant and mean flow of the averaged equation
    ``I-bar alpha' = F(alpha) = eta_t R+ T(R+ alpha) - L-bar(alpha)``, broadcasting.

    Without a leak hole and with the paper's Eq. (11), in closed form (:func:`cycle_mean`, the
    paper's Riccati equation with the real machine's eta_t, I-bar and pipe). A rotor's torque
    curve (:class:`~windpump.Rotor`) has no closed form: its roots are found as a hole's are
    below, and its stall margin is the largest ratio ``eta_t R+ T(R+ alpha) / L-bar(alpha)``
    over the crank speeds. With a hole L-bar is a quadrature
    (:func:`windpump.averaging.revolution.mean_load`): F is scanned on a grid of crank speeds up to the
    windmill's runaway speed and its roots refined by the Illinois method to round-off; tau
    from a central difference of F. Such a pump never stalls (margin inf): F > 0 just above
    rest, where the load through the hole vanishes as alpha^2.

    Parameters
    ----------
    design : Design
    gear_ratio, head, V : float or array_like, optional
        As :func:`cycle_mean`: R+ [-], h [m], wind speed [m/s].

    Returns
    -------
    RunningSpeeds

    Examples
    --------
    >>> from windpump import Design
    >>> d = Design.seed_example()
    >>> round(float(running_speeds(d).alpha_plus), 2)
    23.71
    >>> holed = running_speeds(d.replace(d_leak=0.004))
    >>> float(holed.margin), round(float(holed.alpha_plus), 2), bool(np.isnan(holed.alpha_minus))
    (inf, 23.71, True)
    """
    if design.d_leak == 0.0 and design.rotor is None:
        mean = cycle_mean(design, gear_ratio=gear_ratio, head=head, V=V)
        runs = mean.runs
        alpha_plus = np.where(runs, mean.alpha_plus, math.nan)
        return RunningSpeeds(
            margin=mean.margin,
            alpha_plus=alpha_plus,
            alpha_minus=np.where(runs, mean.alpha_minus, math.nan),
            tau=np.where(runs, mean.tau, math.nan),
            mean_flow=design.volume_per_revolution * alpha_plus / (2 * math.pi),
            I_bar=mean.I_bar,
        )
    return numeric_running_speeds(design, gear_ratio=gear_ratio, head=head, V=V)


LEAK_TABLE = 257
"""With a leak hole, more distinct wind speeds than this are interpolated on this many (evenly
spaced over them): a quadrature and root finding per wind took 79 s for a day's record."""


def steady_flow(design: Design, V):
    """Averaged mean flow [m^3/s] in steady winds V [m/s]: the revolution mean of the delivered
    flow at alpha+(V), ``m A R alpha+(V) / pi`` for a tight piston, above V_stop.

    ``alpha+(V)`` is the running crank speed of :func:`windpump.steady_speeds` for
    ``design.in_wind(V)``; below (and at) V_stop the pump cannot run and the flow is 0. Above V_stop
    the flow jumps from 0 to ``m A R p s_stop / pi`` and then grows about linearly with V (the
    crank runs near the windmill's peak, which moves with V). With a leak hole the flow is the
    delivered one (swept less leaked), 0 while the pump only crawls; more than ``LEAK_TABLE``
    distinct winds are interpolated linearly on that many.

    Parameters
    ----------
    design : Design
    V : array_like
        Wind speeds [m/s], from 0 to 150 (``windpump.model.wind.MAX_WIND``, as a record's).

    Returns
    -------
    ndarray or float
        The flow [m^3/s], the shape of V.

    Examples
    --------
    >>> from windpump import Design, steady_flow
    >>> from windpump.units import LITRES_PER_M3
    >>> flows = steady_flow(Design.seed_example(), [2.0, 5.0, 8.0])
    >>> [round(float(q) * LITRES_PER_M3, 3) for q in flows]  # [L/s]
    [0.0, 0.379, 0.627]
    """
    speeds = finite_array("V", V, "m/s", minimum=0.0)
    if speeds.size and speeds.max() > MAX_WIND:  # as a record's (a flow of inf, otherwise)
        raise ParameterError("V", float(speeds.max()), f"wind speeds from 0 to {MAX_WIND:g}", "m/s")
    if design.d_leak > 0.0 or design.rotor is not None:  # roots per wind: each distinct once
        values, where = np.unique(speeds, return_inverse=True)
        if values.size > LEAK_TABLE:  # a record's winds: interpolated on a table of them
            table = np.linspace(values[0], values[-1], LEAK_TABLE)
            table_flow = np.nan_to_num(running_speeds(design, V=table).mean_flow)
            flow = np.interp(speeds, table, table_flow)
        else:
            flow = np.nan_to_num(running_speeds(design, V=values).mean_flow)[
                where.reshape(speeds.shape)
            ]
    else:
        flow = np.nan_to_num(running_speeds(design, V=speeds).mean_flow)
    return flow if flow.ndim else float(flow)
