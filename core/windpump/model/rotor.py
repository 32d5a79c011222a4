"""A windmill rotor by its aerodynamics: a torque coefficient C_Q against the tip-speed ratio.

The paper's Eq. (11) gives the windmill's torque as a parabola in its speed. A real rotor is
described by its torque coefficient ``C_Q(lambda)`` (or its power coefficient
``C_P = lambda C_Q``) against the tip-speed ratio ``lambda = omega r / V``, measured in a wind
tunnel or the field. In a steady wind V its torque is::

    T(omega, V) = 1/2 rho_air pi r^3 V_s^2 C_Q(omega r / V_s),   V_s = min(V, V_furl)

(a furling wheel turns out of the wind above V_furl: modelled as a wind capped at V_furl; the
governor's gradual turning is not modelled). Between the table's points C_Q is scipy's PCHIP
interpolant (monotone where the data are, no overshoot); past the last point it goes on as a
straight line with the interpolant's slope there.

The American multiblade wheel that farm pumps use has its largest torque at rest and loses it as
it speeds up: :meth:`Rotor.multiblade`.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import typing

import numpy as np

from ..errors import ParameterError, shown
from ..validation import LARGEST, finite_array, magnitude, real_array

RHO_AIR = 1.225
"""Air's density at sea level, 15 degC (the ISO standard atmosphere) [kg/m^3]."""

MAX_TABLE = 2000
"""Most points a C_Q table holds (a measured curve has tens; a digitised one hundreds)."""

MULTIBLADE_TSR = (0.0, 0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0)
MULTIBLADE_CQ = (0.50, 0.47, 0.43, 0.375, 0.30, 0.22, 0.14, 0.065, 0.0)
MULTIBLADE_SOURCE = (
    "American multiblade wheel as Lysen, Introduction to Wind Energy (CWD 82-1, 1983), Ch. 4, "
    "describes its C_P-lambda and C_Q-lambda curves: C_Q about 0.5 at rest, falling to 0 near "
    "lambda = 2, C_P peaking near 0.3 at lambda = 1 (points following that description; the "
    "figure itself was not at hand to be digitised)"
)


@dataclasses.dataclass(frozen=True)
class Rotor:
    """A windmill rotor: its diameter and its torque coefficient against the tip-speed ratio.

    Build one with :meth:`from_cq`, :meth:`from_cp` or :meth:`multiblade`; every field is checked
    on construction.

    Parameters
    ----------
    diameter : float
        The wheel's diameter D [m], 1e-3 to 1e3 (r = D/2).
    table_tsr : tuple of float
        Tip-speed ratios lambda [-] of the table: starting at 0, strictly increasing, finite,
        2 to 2000 points.
    table_cq : tuple of float
        Torque coefficients C_Q [-] at those ratios: finite, ``C_Q(0) >= 0``, positive somewhere,
        and falling to 0 (the runaway) inside the table or on its straight continuation.
    rho_air : float, default 1.225
        Air's density [kg/m^3], 0.01 to 10.
    V_furl : float or None, default None
        Wind speed [m/s] above which the wheel furls (turns out of the wind), 0.1 to 150, or
        None for a wheel that never furls.
    source : str, default ""
        Where the curve comes from.

    Examples
    --------
    >>> rotor = Rotor.from_cq(2.0, [0.0, 1.0, 2.0], [0.4, 0.3, 0.0])
    >>> round(float(rotor.cq(1.0)), 6), round(float(rotor.cp(1.0)), 6), rotor.runaway_tsr
    (0.3, 0.3, 2.0)
    >>> round(float(rotor.torque(0.0, 5.0)), 4)  # 1/2 rho pi r^3 V^2 C_Q(0) [N m]
    19.2423
    """

    diameter: float
    table_tsr: tuple[float, ...]
    table_cq: tuple[float, ...]
    rho_air: float = RHO_AIR
    V_furl: float | None = None
    source: str = ""

    def __post_init__(self) -> None:
        set_field = functools.partial(object.__setattr__, self)
        set_field("diameter", magnitude("diameter", self.diameter, "m", lowest=1e-3, highest=1e3))
        set_field(
            "rho_air", magnitude("rho_air", self.rho_air, "kg/m^3", lowest=0.01, highest=10.0)
        )
        if self.V_furl is not None:
            set_field("V_furl", magnitude("V_furl", self.V_furl, "m/s", lowest=0.1, highest=150.0))
        if not isinstance(self.source, str):
            raise ParameterError("source", self.source, "text")
        tsr, cq = _checked_table(self.table_tsr, self.table_cq)
        set_field("table_tsr", tuple(float(x) for x in tsr))
        set_field("table_cq", tuple(float(x) for x in cq))
        runaway_tsr(self.table_tsr, self.table_cq)  # the table must reach one

    @classmethod
    def from_cq(
        cls,
        diameter: float,
        tsr,
        cq,
        *,
        rho_air: float = RHO_AIR,
        V_furl: float | None = None,
        source: str = "",
    ) -> Rotor:
        """A rotor from a table of torque coefficients C_Q [-] at tip-speed ratios lambda [-].

        Examples
        --------
        >>> Rotor.from_cq(1.0, [0, 1, 2], [0.3, 0.2, 0.0], V_furl=9.0).V_furl
        9.0
        """
        return cls(diameter, _as_tuple("tsr", tsr), _as_tuple("cq", cq), rho_air, V_furl, source)

    @classmethod
    def from_cp(
        cls,
        diameter: float,
        tsr,
        cp,
        *,
        cq0: float,
        rho_air: float = RHO_AIR,
        V_furl: float | None = None,
        source: str = "",
    ) -> Rotor:
        """A rotor from a table of power coefficients C_P [-] at tip-speed ratios lambda [-]
        (starting at 0), with its torque coefficient at rest ``cq0`` [-]: C_P says nothing there
        (C_P(0) = 0 for any torque). ``C_Q = C_P / lambda`` at the other points.

        Examples
        --------
        >>> rotor = Rotor.from_cp(1.0, [0, 1, 2], [0.0, 0.2, 0.0], cq0=0.3)
        >>> rotor.table_cq
        (0.3, 0.2, 0.0)
        """
        tsr_values = _as_tuple("tsr", tsr)
        cp_values = _as_tuple("cp", cp)
        if len(cp_values) != len(tsr_values):
            raise ParameterError(
                "cp", f"{len(cp_values)} values", f"as many as tsr ({len(tsr_values)})"
            )
        if not tsr_values or tsr_values[0] != 0.0:
            raise ParameterError("tsr", shown(tsr_values[:1]), "a table starting at 0")
        cq = [magnitude("cq0", cq0, zero=True, highest=LARGEST)]
        cq += [
            p / x if x > 0 else math.nan for x, p in zip(tsr_values[1:], cp_values[1:], strict=True)
        ]
        return cls(diameter, tsr_values, tuple(cq), rho_air, V_furl, source)

    @classmethod
    def multiblade(
        cls, diameter: float, *, rho_air: float = RHO_AIR, V_furl: float | None = None
    ) -> Rotor:
        """The American multiblade wheel (the farm windmill's 15 to 18 sheet-metal sails) of the
        given diameter [m], by the curve the literature gives for it; not fitted to any maker's
        table.

        ``MULTIBLADE_TSR`` and ``MULTIBLADE_CQ`` follow Lysen, *Introduction to Wind Energy*
        (CWD 82-1, 1983), Ch. 4, "C_P-lambda and C_Q-lambda curves" of the rotor types, as its
        text and figure describe the multiblade: its torque is largest at rest (C_Q about 0.5)
        and falls to 0 near lambda = 2; its power coefficient peaks near 0.3 at lambda = 1. The
        figure was not at hand to be digitised point by point, so these nine points are drawn
        to that description (the peak C_P here is 0.300 at lambda 0.98). A wind-tunnel
        measurement of a multiblade rotor stored in the project's sources (quoted without its
        authors) gives C_P 0.296 at lambda 1.18. docs/validation.rst holds the wheel against
        the Aermotor 702's table.

        Examples
        --------
        >>> wheel = Rotor.multiblade(8 * 0.3048)  # an 8-ft wheel
        >>> round(float(wheel.cq(0.0)), 2), round(float(wheel.cp(1.0)), 2), wheel.runaway_tsr
        (0.5, 0.3, 2.0)
        """
        return cls(diameter, MULTIBLADE_TSR, MULTIBLADE_CQ, rho_air, V_furl, MULTIBLADE_SOURCE)

    @property
    def radius(self) -> float:
        """The wheel's radius r = D/2 [m]."""
        return 0.5 * self.diameter

    @property
    def swept_area(self) -> float:
        """The swept area pi r^2 [m^2]."""
        return math.pi * self.radius**2

    @property
    def torque_scale(self) -> float:
        """``1/2 rho_air pi r^3`` [kg/m = N m / (m/s)^2]: torque per V^2 and per unit C_Q."""
        return 0.5 * self.rho_air * math.pi * self.radius**3

    @property
    def runaway_tsr(self) -> float:
        """The tip-speed ratio where C_Q first falls to 0 [-]: the unloaded wheel's speed."""
        return _runaway(self.table_tsr, self.table_cq)

    @property
    def steepest_cq_slope(self) -> float:
        """The largest ``|dC_Q/dlambda|`` from rest to the runaway [-] (on 1,001 ratios)."""
        return _steepest_slope(self.table_tsr, self.table_cq)

    @property
    def peak_cq(self) -> float:
        """The largest C_Q from rest to the runaway [-]: the largest of the table's values there
        (PCHIP has no extremum between its points)."""
        inside = np.asarray(self.table_tsr) <= self.runaway_tsr
        return float(np.max(np.asarray(self.table_cq)[inside]))

    @property
    def end_slope(self) -> float:
        """The slope dC_Q/dlambda past the table's last point [-]: PCHIP's slope there."""
        return _cq_curve(self.table_tsr, self.table_cq).end_slope

    def cq(self, tsr):
        """Torque coefficient C_Q [-] at tip-speed ratios ``tsr`` [-] >= 0: PCHIP through the
        table, a straight line past its last point (negative past the runaway: a brake)."""
        lam = finite_array("tsr", tsr, minimum=0.0)
        return _cq_curve(self.table_tsr, self.table_cq)(lam)

    def cp(self, tsr):
        """Power coefficient C_P = lambda C_Q [-] at tip-speed ratios ``tsr`` [-] >= 0."""
        lam = finite_array("tsr", tsr, minimum=0.0)
        return lam * _cq_curve(self.table_tsr, self.table_cq)(lam)

    def wind_at_rotor(self, V):
        """The wind the wheel turns in, V_s = min(V, V_furl) [m/s] (V without furling)."""
        V = finite_array("V", V, "m/s", minimum=0.0, maximum=LARGEST)
        return V if self.V_furl is None else np.minimum(V, self.V_furl)

    def tip_speed_ratio(self, omega, V):
        """The tip-speed ratio lambda = omega r / V_s [-] at the wheel's speeds ``omega`` [rad/s]
        in steady winds ``V`` [m/s] > 0 (V_s = min(V, V_furl): the wind it turns in).

        Examples
        --------
        >>> Rotor.multiblade(2.0, V_furl=8.0).tip_speed_ratio(10.0, [5.0, 12.0]).tolist()
        [2.0, 1.25]
        """
        omega = finite_array("omega", omega, "rad/s", minimum=0.0, maximum=LARGEST)
        V_s = self.wind_at_rotor(V)
        if np.any(V_s <= 0.0):
            raise ParameterError("V", float(np.min(V_s)), "wind speeds > 0", "m/s")
        return omega * self.radius / V_s

    def torque(self, omega, V):
        """The wheel's torque T [N m] at speeds ``omega`` [rad/s] in steady winds ``V`` [m/s]:
        ``1/2 rho_air pi r^3 V_s^2 C_Q(omega r / V_s)``, 0 in calm air.

        Examples
        --------
        >>> rotor = Rotor.from_cq(2.0, [0.0, 1.0, 2.0], [0.4, 0.3, 0.0])
        >>> round(float(rotor.torque(10.0, 10.0) / rotor.torque(5.0, 5.0)), 12)  # T ~ V^2
        4.0
        """
        omega = finite_array("omega", omega, "rad/s", minimum=0.0, maximum=LARGEST)
        V_s = self.wind_at_rotor(V)
        return rotor_torque(self, omega, V_s)

    def power(self, omega, V):
        """The wheel's shaft power T omega [W] at speeds ``omega`` [rad/s] in winds ``V`` [m/s]."""
        return self.torque(omega, V) * finite_array("omega", omega, "rad/s", minimum=0.0)

    def kernel_table(self) -> tuple[np.ndarray, np.ndarray, float]:
        """The curve as the compiled integrator evaluates it: the table's points lambda_i (n),
        the PCHIP's cubic on each interval as ``(n-1, 4)`` coefficients of
        ``(lambda - lambda_i)^3, ^2, ^1, ^0``, and the slope at the last point."""
        curve = _cq_curve(self.table_tsr, self.table_cq)
        coefficients = np.ascontiguousarray(curve.pchip.c.T)
        return np.asarray(self.table_tsr, dtype=float), coefficients, curve.end_slope


class _Curve(typing.NamedTuple):
    """C_Q through a table: PCHIP inside, a straight line past the last point."""

    pchip: typing.Any  # scipy.interpolate.PchipInterpolator
    last: float  # lambda of the last point
    end_value: float  # C_Q there
    end_slope: float  # the interpolant's slope there

    def __call__(self, lam):
        lam = np.asarray(lam, dtype=float)
        inside = self.pchip(np.minimum(lam, self.last))
        return np.where(
            lam > self.last, self.end_value + self.end_slope * (lam - self.last), inside
        )


@functools.lru_cache(maxsize=32)
def _cq_curve(tsr: tuple[float, ...], cq: tuple[float, ...]) -> _Curve:
    from scipy.interpolate import PchipInterpolator  # here, not at import (scipy loads slowly)

    pchip = PchipInterpolator(np.asarray(tsr), np.asarray(cq))
    return _Curve(pchip, tsr[-1], cq[-1], float(pchip.derivative()(tsr[-1])))


def rotor_torque(rotor: Rotor, omega, V_s):
    """``1/2 rho_air pi r^3 V_s^2 C_Q(omega r / V_s)`` [N m] at speeds omega [rad/s] >= 0 in the
    wind at the wheel V_s [m/s] >= 0 (already capped at V_furl), unchecked: 0 at V_s = 0 (the
    limit: past the runaway C_Q is linear in lambda, so V_s^2 C_Q falls as V_s)."""
    omega, V_s = np.broadcast_arrays(np.asarray(omega, dtype=float), np.asarray(V_s, dtype=float))
    curve = _cq_curve(rotor.table_tsr, rotor.table_cq)
    tip_speed = omega * rotor.radius
    past = tip_speed >= curve.last * V_s  # (calm air included)
    lam = np.where(past, 0.0, tip_speed / np.where(past, 1.0, V_s))
    inside = rotor.torque_scale * V_s**2 * curve(lam)
    # Past the table C_Q is linear in lambda: V_s^2 C_Q written without omega r / V_s, which
    # overflows in a near-calm wind (there the torque tends to 0, as slope omega r V_s)
    rest = curve.end_value - curve.end_slope * curve.last
    beyond = rotor.torque_scale * V_s * (V_s * rest + curve.end_slope * tip_speed)
    return np.where(past, beyond, inside)


@functools.lru_cache(maxsize=32)
def _runaway(tsr: tuple[float, ...], cq: tuple[float, ...]) -> float:
    """:func:`runaway_tsr`, remembered for the last tables (a run asks it several times)."""
    return runaway_tsr(tsr, cq)


@functools.lru_cache(maxsize=32)
def _steepest_slope(tsr: tuple[float, ...], cq: tuple[float, ...]) -> float:
    lam = np.linspace(0.0, _runaway(tsr, cq), 1001)
    return float(np.abs(_cq_curve(tsr, cq).pchip.derivative()(lam)).max())


def runaway_tsr(tsr: tuple[float, ...], cq: tuple[float, ...]) -> float:
    """The tip-speed ratio [-] where a table's C_Q first falls from above 0 to 0, or a
    ParameterError naming ``cq`` when it never does (or is never positive)."""
    values = np.asarray(cq)
    positive = np.flatnonzero(values > 0.0)
    rule = "a C_Q positive at some tip-speed ratio, then falling to 0 (the runaway)"
    if positive.size == 0:
        raise ParameterError("cq", shown(cq), rule, why="C_Q is never positive")
    curve = _cq_curve(tsr, cq)
    after = np.flatnonzero((values <= 0.0) & (np.arange(values.size) > positive[0]))
    if after.size:  # the PCHIP is monotone between points of opposite sign: one root there
        i = int(after[0])
        if values[i] == 0.0:
            return tsr[i]
        root = _bracketed_root(curve.pchip, tsr[i - 1], tsr[i])
        return root
    if curve.end_slope < 0.0:
        return tsr[-1] - cq[-1] / curve.end_slope
    raise ParameterError(
        "cq",
        shown(cq),
        rule,
        why=f"C_Q is {cq[-1]:.4g} at the last point and does not fall past it",
    )


def _bracketed_root(function, lo: float, hi: float) -> float:
    from scipy.optimize import brentq  # (as above)

    return float(brentq(function, lo, hi, xtol=1e-300, rtol=1e-15))


def _as_tuple(name: str, values) -> tuple[float, ...]:
    array = real_array(name, values).ravel()
    return tuple(float(x) for x in array)


def _checked_table(tsr, cq) -> tuple[np.ndarray, np.ndarray]:
    """The table as arrays, or a ParameterError naming ``tsr`` or ``cq`` and the rule broken."""
    lam = finite_array("tsr", real_array("tsr", tsr).ravel())
    coefficient = finite_array(
        "cq", real_array("cq", cq).ravel(), minimum=-LARGEST, maximum=LARGEST
    )
    if not 2 <= lam.size <= MAX_TABLE:
        raise ParameterError("tsr", f"{lam.size} points", f"2 to {MAX_TABLE} points")
    if coefficient.size != lam.size:
        raise ParameterError("cq", f"{coefficient.size} values", f"as many as tsr ({lam.size})")
    if lam[0] != 0.0:
        raise ParameterError("tsr", float(lam[0]), "a table starting at 0 (the wheel at rest)")
    steps = np.diff(lam)
    if (steps <= 0.0).any():
        i = int(np.flatnonzero(steps <= 0.0)[0]) + 1
        raise ParameterError("tsr", f"tsr[{i}] = {lam[i]:.6g}", "strictly increasing ratios")
    if lam[-1] > 1e3:
        raise ParameterError("tsr", float(lam[-1]), "ratios up to 1000")
    if coefficient[0] < 0.0:
        raise ParameterError("cq", float(coefficient[0]), "C_Q at rest >= 0", why="cq[0] < 0")
    if np.abs(coefficient).max() > 1e3:
        i = int(np.argmax(np.abs(coefficient)))
        raise ParameterError(
            "cq", f"cq[{i}] = {coefficient[i]:.6g}", "coefficients from -1000 to 1000"
        )
    return lam, coefficient
