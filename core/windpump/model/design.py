"""The wind pump's design: geometry, inertias, windmill curve and load, with the paper's groups."""

from __future__ import annotations

import dataclasses
import json
import math
import sys
import typing

from ..errors import DesignFileError, ParameterError, shown
from ..validation import LARGEST as LARGEST
from ..validation import SMALLEST as SMALLEST
from ..validation import flag, magnitude, positive, rod_ratio, whole
from . import equations, groups
from .rotor import Rotor
from .wind import MAX_WIND

# Field name -> unit, in the order of the paper's symbols (docs/model.rst, "Symbols").
UNITS = {
    "R0": "m",
    "R1": "m",
    "R": "m",
    "L": "m",
    "A": "m^2",
    "I0": "kg m^2",
    "I1": "kg m^2",
    "T_m": "N m",
    "omega_m": "rad/s",
    "h": "m",
    "rho_w": "kg/m^3",
    "g": "m/s^2",
    "cylinders": "",
    "double_acting": "",
    "T_0": "N m",
    "V_ref": "m/s",
    "m_r": "kg",
    "eta_t": "",
    "L_main": "m",
    "D_main": "m",
    "f_main": "",
    "d_leak": "m",
    "Cd_leak": "",
}

REAL_MACHINE = ("m_r", "eta_t", "L_main", "D_main", "f_main", "d_leak", "Cd_leak")
"""The fields of the real machine (beyond the paper): their defaults are its ideal machine."""

MAX_FRICTION_FACTOR = 0.2
"""Largest Darcy friction factor f_main [-]: past the roughest pipe of a Moody chart (~0.1)."""

MAX_CYLINDERS = 6

SCHEMA = "windpump.model.design"
SCHEMA_VERSION = 3
"""What a design file says it is, and the version of its layout (:meth:`Design.to_json`).
Version 2 added the real machine's fields (``REAL_MACHINE``), version 3 a rotor (``"rotor"``:
its diameter, C_Q table, air density, furling wind and source, beside ``"fields"``); files of
versions 1 and 2 are still read (the ideal machine; the paper's curve)."""

ROTOR_FIELDS = ("T_m", "omega_m", "T_0")
"""The fields a rotor sets (:meth:`Design.from_rotor`): its curve at V_ref, not the caller's."""

NARROWER = {
    "R": (1e-4, 1e3),
    "L": (1e-4, 1e3),
    "A": (1e-8, 1e2),
    "rho_w": (1.0, 2e4),
    "g": (0.1, 100.0),
    "eta_t": (0.1, 1.0),
    "Cd_leak": (0.05, 1.0),
}
"""Fields whose range is narrower than ``SMALLEST`` to ``LARGEST`` [their SI units]: a crank
radius and a connecting rod from 0.1 mm (a model pump's) to 1 km (past any machine's); a piston
area from 1e-8 m^2 (a 0.11 mm bore) to 100 m^2 (an 11 m bore); a liquid's density from 1 kg/m^3
(below any liquid's, ~70 for liquid hydrogen) to 2e4 (past mercury's 13,600); gravity from 0.1
m/s^2 (below the Moon's 1.62, Ceres' 0.28) to 100 (past Jupiter's 24.8, any planet's surface); a
chain drive's efficiency from 0.1 (below it the drive is broken, not lossy) to 1; a hole's
discharge coefficient from 0.05 (a long, rough bore) to 1. Past them no machine exists, and the
model's figures were wrong there (issue 36: a leaky pump's speeds NaN at rho_w = 1e12; the
windmill's torque on the crank underflowed to 0 at eta_t = 5e-324, a ZeroDivisionError; a run's
power budget closed far above its tolerance with a 1e-12 m or a 4e10 m crank, a 1e12 m rod, a
1e-12 m^2 piston or g = 1e12 m/s^2)."""

WIDEST_RATIO = 1e50
"""Largest L/R and R1/R0 (and smallest R1/R0 is its inverse), for the same reason."""

LEAKY_RATIO = 1.05
"""Smallest L/R with a leak hole (``d_leak > 0``) [-]. Nearer L = R the lever arm of Eq. 1 falls
from about 2 to 0 within ~sqrt(2 (L/R - 1)) rad at mid-stroke (a jump at L/R = 1), and the
kernel's stretches in time there integrate the hole's leaked volume and the load's relief with
steps whose error control does not see it: a hole passing all the sweep closed its power budget
to 3.4e-3 against a tolerance of 7.4e-7 at L/R = 1 + 1e-10, 1.1e-5 against 5.6e-7 at 1.01,
2.0e-7 against 5.2e-7 at 1.05 (issue 36). The app's L/R starts at 1.05; a tight piston is right
at any L/R > 1 (4e-17 at 1 + 1e-10)."""


@dataclasses.dataclass(frozen=True)
class Design:
    """A wind pump: windmill, chain drive, slider-cranks and pistons (SI units).

    The defaults of the last three fields are the paper's machine: one single-acting cylinder and a
    windmill with no torque at rest.

    Every field is checked on construction: numbers from ``SMALLEST`` = 1e-12 to ``LARGEST`` =
    1e12 in SI units (h and T_0 from 0; V_ref is at most 150 m/s, the fastest wind a
    record holds), far past any machine and the range where every figure of the model stays
    finite; R, L, A, rho_w, g, eta_t and Cd_leak in the narrower ranges of ``NARROWER`` (a
    crank, a rod and a bore any pump could have, a liquid's density, a planet's gravity, a
    working chain drive, an orifice), past which the model's answers were wrong. A bad value raises :class:`~windpump.ParameterError` (a ``ValueError``) naming the
    field, its value (cut to a bounded length) and the allowed range.

    Parameters
    ----------
    R0 : float
        Small sprocket radius, on the windmill shaft [m].
    R1 : float
        Large sprocket radius, on the crankshaft [m].
    R : float
        Crank radius [m], 1e-4 to 1e3.
    L : float
        Connecting-rod length [m], 1e-4 to 1e3; must exceed ``R``, and be at least 1.05 ``R``
        with a leak hole (``LEAKY_RATIO``: Eq. 1's near-toggle).
    A : float
        Piston cross-section [m^2], 1e-8 to 100.
    I0 : float
        Inertia of windmill blades + shaft + small sprocket [kg m^2].
    I1 : float
        Inertia of large sprocket + crank [kg m^2].
    T_m : float
        Windmill torque scale of Eq. (11): the peak torque, at ``omega_m`` [N m].
    omega_m : float
        Windmill speed of peak torque, Eq. (11) [rad/s]; torque vanishes at 0 and ``2 omega_m``.
    h : float
        Head: height the water is lifted above the tank's waterline [m]; 0 means no load.
    rho_w : float, default 1000.0
        Water density [kg/m^3], 1 to 2e4 (any liquid's).
    g : float, default 9.81
        Gravity [m/s^2], 0.1 to 100 (any planet's surface).
    cylinders : int, default 1
        Number of cylinders n, 1 to 6, each with its own slider-crank of the same R, L and A on
        the one crank: cylinder k sees the crank angle ``theta - 2 pi k / n`` (beyond the paper,
        which names the phase lag but models one cylinder).
    double_acting : bool, default False
        Whether both faces of every piston deliver: the top face while
        ``pi < (theta - 2 pi k/n) mod 2 pi < 2 pi`` as the paper's one cylinder, the bottom face
        during the other half. The rod's area is neglected (both faces have area A).
    T_0 : float, default 0.0
        Windmill torque at rest [N m], 0 <= T_0 < T_m: the torque curve becomes
        ``T = T_0 + (T_m - T_0) x (2 - x)`` (Eq. 11 when T_0 = 0; the paper's footnote 7 notes a
        real windmill has torque at rest, which decides whether it starts on its own).
    V_ref : float, default 5.0
        Wind speed the curve (T_m, omega_m, T_0) is measured at [m/s], at most 150.
    m_r : float, default 0.0
        Reciprocating mass per cylinder: piston, rod and pump rod [kg], >= 0. The pump stands
        vertical: the mass adds ``m_r sum x_c'^2`` to the inertia on the crank and its weight
        ``m_r g sum x_c'`` to the torque (docs/model.rst, "The real machine").
    eta_t : float, default 1.0
        Transmission efficiency of the chain and sprockets [-], 0.1 <= eta_t <= 1: the crank
        gets ``eta_t R+ T``.
    L_main : float, default 0.0
        Length of the rising main [m], >= 0; 0: no pipe friction.
    D_main : float, default 0.05
        Inner diameter of the rising main [m], > 0.
    f_main : float, default 0.02
        Darcy friction factor of the rising main [-], 0 to 0.2: the friction head is
        ``h_f = f_main (L_main / D_main) (Q / a_main)^2 / (2 g)``.
    d_leak : float, default 0.0
        Diameter of a leak hole through each piston face [m], 0 (none) up to, not including, the
        bore: it passes up to ``q_L = Cd_leak (pi d_leak^2 / 4) sqrt(2 g h)``, so a slow piston
        delivers nothing and loads the crank little (the pump can start).
    Cd_leak : float, default 0.6
        The leak hole's discharge coefficient [-], 0.05 <= Cd_leak <= 1.
    rotor : Rotor or None, default None
        The windmill by its aerodynamics (:class:`~windpump.Rotor`), or None for the paper's
        Eq. (11). With a rotor, T_0, omega_m and T_m are its curve's at V_ref (set on
        construction, whatever was passed: build one with :meth:`from_rotor`): T_0 the torque at
        rest, omega_m half the runaway speed and T_m the torque there, as Eq. (11) has them when
        T_0 = 0; every function of the package then uses the rotor's torque.

    Examples
    --------
    >>> from windpump import Design
    >>> d = Design.seed_example()
    >>> round(d.R_dagger, 3), round(d.I_eff, 2)
    (4.0, 27.07)
    >>> d.replace(h=5.0).h
    5.0
    """

    R0: float
    R1: float
    R: float
    L: float
    A: float
    I0: float
    I1: float
    T_m: float
    omega_m: float
    h: float
    rho_w: float = 1000.0
    g: float = 9.81
    cylinders: int = 1
    double_acting: bool = False
    T_0: float = 0.0
    V_ref: float = 5.0
    m_r: float = 0.0
    eta_t: float = 1.0
    L_main: float = 0.0
    D_main: float = 0.05
    f_main: float = 0.02
    d_leak: float = 0.0
    Cd_leak: float = 0.6
    rotor: Rotor | None = None

    def __post_init__(self) -> None:
        for name in UNITS:
            value = getattr(self, name)
            if name == "cylinders":
                value = whole(name, value, 1, MAX_CYLINDERS)
            elif name == "double_acting":
                value = flag(name, value)
            elif name in ("h", "T_0", "m_r", "L_main", "d_leak"):  # 0 too (see below)
                value = magnitude(name, value, UNITS[name], zero=True)
            elif name in NARROWER:
                value = magnitude(name, value, UNITS[name], lowest=NARROWER[name][0],
                                  highest=NARROWER[name][1])  # fmt: skip
            elif name == "f_main":
                value = magnitude(name, value, zero=True, highest=MAX_FRICTION_FACTOR)
            elif name == "V_ref":  # a wind speed, as a record's
                value = magnitude(name, value, UNITS[name], highest=MAX_WIND)
            else:
                value = magnitude(name, value, UNITS[name])
            object.__setattr__(self, name, value)
        if self.rotor is not None:
            self._set_rotor_curve()
        if self.L <= self.R:
            raise ParameterError(
                "L", self.L, f"> R = {shown(self.R)} m", "m", why="the rod cannot reach the crank"
            )
        if self.d_leak > 0.0 and self.L < LEAKY_RATIO * self.R:
            raise ParameterError(
                "L", self.L, f">= {LEAKY_RATIO:g} R = {shown(LEAKY_RATIO * self.R)} m with a leak hole",
                "m", why="nearer L = R a hole's losses are integrated wrong at Eq. 1's near-toggle",
            )  # fmt: skip
        if self.L / self.R > WIDEST_RATIO:
            raise ParameterError("L", self.L, f"<= {WIDEST_RATIO:g} R", "m", why="L/R is too large")
        if not 1 / WIDEST_RATIO <= self.R1 / self.R0 <= WIDEST_RATIO:
            raise ParameterError(
                "R1", self.R1, f"from {1 / WIDEST_RATIO:g} to {WIDEST_RATIO:g} R0", "m"
            )
        if self.T_0 >= self.T_m and self.rotor is None:
            raise ParameterError(
                "T_0",
                self.T_0,
                f"< T_m = {shown(self.T_m)} N m",
                "N m",
                why="the torque at rest must lie below the peak torque",
            )
        if self.d_leak >= self.bore:
            raise ParameterError(
                "d_leak",
                self.d_leak,
                f"from 0 to below the bore = {shown(self.bore)} m",
                "m",
                why="the leak hole goes through the piston",
            )

    def _set_rotor_curve(self) -> None:
        """T_0, omega_m and T_m from the rotor at V_ref (see the ``rotor`` parameter)."""
        rotor = self.rotor
        if not isinstance(rotor, Rotor):
            raise ParameterError("rotor", rotor, "a windpump.Rotor or None")
        V_s = float(rotor.wind_at_rotor(self.V_ref))
        omega_m = 0.5 * rotor.runaway_tsr * V_s / rotor.radius
        curve = {
            "T_0": float(rotor.torque(0.0, self.V_ref)),
            "omega_m": omega_m,
            "T_m": float(rotor.torque(omega_m, self.V_ref)),
        }
        for name, value in curve.items():
            zero = name == "T_0"
            object.__setattr__(self, name, magnitude(name, value, UNITS[name], zero=zero))

    @classmethod
    def from_rotor(cls, rotor: Rotor, *, V_ref: float, **fields: typing.Any) -> Design:
        """A design whose windmill is ``rotor`` [:class:`~windpump.Rotor`] at the wind V_ref [m/s]:
        ``T = 1/2 rho_air pi r^3 V_s^2 C_Q(omega r / V_s)`` in place of Eq. (11).

        ``fields`` are :class:`Design`'s other fields by name (R0, R1, R, L, A, I0, I1, h and any
        with a default); T_m, omega_m and T_0 come from the rotor (naming one is refused).

        Examples
        --------
        >>> seed = Design.seed_example()
        >>> wheel = Rotor.multiblade(1.5)
        >>> d = Design.from_rotor(wheel, V_ref=5.0, **seed.geometry())
        >>> d.rotor is wheel, round(d.T_0, 4), round(d.omega_m, 4)
        (True, 10.1473, 6.6667)
        """
        given = sorted(set(fields) & set(ROTOR_FIELDS))
        if given:
            raise TypeError(f"from_rotor takes no {given}: the rotor's curve sets them")
        return cls(T_m=1.0, omega_m=1.0, V_ref=V_ref, rotor=rotor, **fields)

    @classmethod
    def from_machine(
        cls,
        rotor: Rotor,
        *,
        V_ref: float,
        gear_ratio: float,
        stroke: float,
        bore: float,
        head: float,
        wheel_inertia: float,
        crank_inertia: float = 1.0,
        L_over_R: float = 5.0,
        pinion_radius: float = 0.05,
        **fields: typing.Any,
    ) -> Design:
        """A design in a builder's terms: the wheel, its back gear, the pump's stroke and bore.

        Parameters
        ----------
        rotor : Rotor
            The wheel (:meth:`Rotor.multiblade` for a farm windmill).
        V_ref : float
            The wind the design is stated at [m/s].
        gear_ratio : float
            Wheel turns per crank turn [-] (the back gear's ratio; 1 for a direct-stroke mill):
            R1/R0 = R-dagger (Eq. 13).
        stroke : float
            The pump's stroke [m], twice the crank radius: R = stroke / 2.
        bore : float
            The cylinder's bore [m]: A = pi bore^2 / 4.
        head : float
            The lift from the water's surface in the well to the outlet [m]: h.
        wheel_inertia : float
            The wheel's moment of inertia about its shaft, with the pinion's [kg m^2]: I0.
        crank_inertia : float, default 1.0
            The large gear's and crank's [kg m^2]: I1 (a 0.5 m cast gear of ~30 kg has ~1).
        L_over_R : float, default 5.0
            The pitman's length over the crank radius, L/R [-].
        pinion_radius : float, default 0.05
            The pinion's (small gear's) pitch radius [m]: R0; only the ratio R1/R0 enters the
            model.
        **fields
            Any other field of :class:`Design` (the real machine's m_r, eta_t, L_main, ...).

        Examples
        --------
        >>> d = Design.from_machine(Rotor.multiblade(8 * 0.3048), V_ref=6.7, gear_ratio=3.3,
        ...                         stroke=0.1905, bore=0.0635, head=53.3, wheel_inertia=25.0)
        >>> round(d.R_dagger, 6), round(d.R, 5), round(d.bore, 6), d.h
        (3.3, 0.09525, 0.0635, 53.3)
        """
        R = 0.5 * positive("stroke", stroke, "m")
        A = math.pi / 4.0 * positive("bore", bore, "m") ** 2
        R0 = positive("pinion_radius", pinion_radius, "m")
        return cls.from_rotor(
            rotor,
            V_ref=V_ref,
            R0=R0,
            R1=R0 * positive("gear_ratio", gear_ratio),
            R=R,
            L=R * rod_ratio(L_over_R),
            A=A,
            I0=wheel_inertia,
            I1=crank_inertia,
            h=head,
            **fields,
        )

    def geometry(self) -> dict[str, float]:
        """The pump's fields without the windmill's curve: R0, R1, R, L, A, I0, I1 and h [SI],
        what :meth:`from_rotor` takes beside a rotor."""
        return {name: getattr(self, name) for name in ("R0", "R1", "R", "L", "A", "I0", "I1", "h")}

    @classmethod
    def seed_example(cls) -> Design:
        """The design of the paper's Fig. 3 example, read as in docs/model.rst (h = 3 m).

        Steel sprockets 1 cm thick (density 8000 kg/m^3) and three 0.75 m blades of
        2000 kg/m^3 x 0.1 m x 0.02 m (footnote 4: ``I = rho_b A_b R_b^3 / 3`` each).
        """
        steel_disc = 8000 * math.pi / 2 * 0.01  # rho * pi/2 * thickness: I = this * r^4
        blades = 3 * 2000 * 0.1 * 0.02 * 0.75**3 / 3
        return cls(
            R0=0.03,
            R1=0.12,
            R=0.04,
            L=0.15,
            A=math.pi / 4 * 0.04**2,
            I0=steel_disc * 0.04**4 + blades,
            I1=steel_disc * 0.15**4,
            T_m=0.6,
            omega_m=50.0,
            h=3.0,
            rho_w=1000.0,
            g=9.81,
        )

    def replace(self, **changes: typing.Any) -> Design:
        """Return a new, validated Design with ``changes`` applied.

        Raises ``TypeError`` for a name that is not a field, and
        :class:`~windpump.ParameterError` for a value out of range.
        """
        unknown = set(changes) - {f.name for f in dataclasses.fields(self)}
        if unknown:
            raise TypeError(
                f"Design has no parameter(s) {shown(sorted(unknown))}; fields: {list(UNITS)}"
            )
        rotor = changes.get("rotor", self.rotor)
        set_by_rotor = sorted(set(changes) & set(ROTOR_FIELDS)) if rotor is not None else []
        if set_by_rotor:
            name = set_by_rotor[0]
            raise ParameterError(
                name, changes[name], "the rotor's own (set by the rotor at V_ref)", UNITS[name],
                why="this design's windmill is a rotor: change the rotor or V_ref",
            )  # fmt: skip
        return dataclasses.replace(self, **changes)

    def with_ratios(
        self,
        L_over_R: float | None = None,
        R_dagger: float | None = None,
        **changes: typing.Any,
    ) -> Design:
        """A new, validated Design with the rod and sprocket set by their ratios to R and R0.

        ``L = R L/R`` and ``R1 = R0 R+`` (Eq. 13), the crank radius R and the small sprocket R0
        kept: the ratios the paper's groups (Eqs. 14, 15) and the explorer's sliders speak in.
        Other ``changes`` are applied as by :meth:`replace`.

        Raises
        ------
        ParameterError
            Naming ``L_over_R`` (must be > 1: the rod cannot reach the crank otherwise) or
            ``R_dagger`` (> 0), or another field out of range.

        Examples
        --------
        >>> d = Design.seed_example().with_ratios(L_over_R=2.0, R_dagger=5.0)
        >>> round(d.L, 6), round(d.R1, 6)
        (0.08, 0.15)
        """
        if L_over_R is not None:
            changes["L"] = self.R * rod_ratio(L_over_R)
        if R_dagger is not None:
            changes["R1"] = self.R0 * positive("R_dagger", R_dagger)
        return self.replace(**changes)

    def in_wind(self, V: float) -> Design:
        """The same rotor in a steady wind V [m/s], by similarity.

        A rotor's torque coefficient depends only on its tip-speed ratio, so its torque curve
        scales with the wind speed: torques as V^2, speeds as V. Returns the design with
        ``T_m (V/V_ref)^2``, ``omega_m V/V_ref``, ``T_0 (V/V_ref)^2`` and ``V_ref = V``; the pump
        is unchanged.

        Raises
        ------
        ParameterError
            Naming ``V`` unless it is a finite number > 0 (in calm air the rotor has no curve;
            :func:`windpump.simulate` takes V = 0 inside a wind record) in the range where the
            scaled fields stay in theirs (:meth:`wind_range`).

        Examples
        --------
        >>> d = Design.seed_example().in_wind(10.0)
        >>> round(d.T_m, 3), round(d.omega_m, 3), d.V_ref
        (2.4, 100.0, 10.0)
        """
        V = positive("V", V, "m/s")
        lowest, highest = self.wind_range()
        allowed = f"a wind speed from {lowest:.6g} to {highest:.6g} m/s for this design"
        why = "where T_m, omega_m and T_0 scaled by similarity stay in their ranges"
        if not lowest <= V <= highest:
            raise ParameterError("V", V, allowed, "m/s", why=why)
        s = V / self.V_ref
        try:
            if self.rotor is not None:  # the rotor's curve at V: similarity, and the furl
                return self.replace(V_ref=V)
            return self.replace(
                T_m=self.T_m * s**2, omega_m=self.omega_m * s, T_0=self.T_0 * s**2, V_ref=V
            )
        except ParameterError:  # a range's edge, by rounding
            raise ParameterError("V", V, allowed, "m/s", why=why) from None

    def wind_range(self) -> tuple[float, float]:
        """The wind speeds [m/s] :meth:`in_wind` takes: where ``T_m (V/V_ref)^2``,
        ``omega_m V/V_ref``, ``T_0 (V/V_ref)^2`` and V itself stay in the fields' ranges (up to
        150 m/s, the fastest wind a record holds).

        Examples
        --------
        >>> Design.seed_example().wind_range()
        (6.4549722436790284e-06, 150.0)
        """
        squared = [self.T_m] + ([self.T_0] if self.T_0 > 0.0 else [])
        # T_0 may shrink to 0 (its range starts there): only T_m bounds the wind from below
        lowest = max(SMALLEST / self.omega_m, SMALLEST / self.V_ref, math.sqrt(SMALLEST / self.T_m))
        highest = min([LARGEST / self.omega_m, MAX_WIND / self.V_ref]
                      + [math.sqrt(LARGEST / x) for x in squared])  # fmt: skip
        return self.V_ref * lowest, self.V_ref * highest

    def to_json(self) -> str:
        """The design as JSON text: every field with its unit, under a schema name and version.

        Examples
        --------
        >>> d = Design.seed_example()
        >>> Design.from_json(d.to_json()) == d
        True
        >>> import json
        >>> file = json.loads(d.to_json())
        >>> file["schema"], file["version"], file["fields"]["h"], file["units"]["h"]
        ('windpump.model.design', 3, 3.0, 'm')
        """
        document: dict[str, typing.Any] = {
            "schema": SCHEMA,
            "version": SCHEMA_VERSION,
            "fields": self.as_dict(),
            "units": dict(UNITS),
        }
        if self.rotor is not None:
            document["rotor"] = dataclasses.asdict(self.rotor)
        return json.dumps(document, indent=2) + "\n"

    @classmethod
    def from_json(cls, text: str | bytes) -> Design:
        """A design from the JSON text :meth:`to_json` writes.

        ``fields`` must name every field without a default (R0 ... h); those with one (rho_w,
        g, cylinders, double_acting, T_0, V_ref and the real machine's fields) may be left out. ``units``, when present, must
        be this version's (SI units throughout).

        Raises
        ------
        DesignFileError
            (a ValueError) for text that is not such a document: not JSON, another schema or a
            newer version, unknown or missing fields, or another unit; naming what is wrong.
        ParameterError
            For a field out of range, as the constructor.
        """
        document = read_json(text)
        fields = _design_fields(document)
        rotor = _rotor(typing.cast(dict, document))
        if rotor is None:
            return cls(**fields)
        return cls.from_rotor(rotor, **{n: v for n, v in fields.items() if n not in ROTOR_FIELDS})

    def as_dict(self) -> dict[str, float | int | bool]:
        """The numeric fields as a plain dict [SI units] (a rotor's table is :meth:`to_json`'s)."""
        return {name: getattr(self, name) for name in UNITS}

    @property
    def L_over_R(self) -> float:
        """Rod-to-crank ratio L/R [-] (Eq. 1 and sin(theta_c) = sin(theta)/(L/R))."""
        return self.L / self.R

    @property
    def R_dagger(self) -> float:
        """Sprocket ratio R-dagger = R1/R0 [-] (Eq. 13): windmill speed / crank speed, Eq. (4)."""
        return self.R1 / self.R0

    @property
    def I_eff(self) -> float:
        """Inertia reflected to the crank, I1 + I0 (R1/R0)^2 [kg m^2] (Eq. 12)."""
        return groups.effective_inertia(self.I1, self.I0, self.R_dagger)

    @property
    def Tm_dagger(self) -> float:
        """Characteristic windmill torque T_m-dagger [-] (Eq. 14)."""
        return self.R_dagger**2 * self.T_m / (self.omega_m**2 * self.I_eff)

    @property
    def L_dagger(self) -> float:
        """Characteristic pump load L-dagger [-] (Eq. 15)."""
        return self.load_torque / (self.omega_m**2 * self.I_eff)

    @property
    def load_torque(self) -> float:
        """Piston force times crank radius, rho_w g h A R [N m] (the load scale of Eq. 12)."""
        return groups.load_torque(self.rho_w, self.g, self.h, self.A, self.R)

    @property
    def stroke_volume(self) -> float:
        """Volume one face delivers per crank revolution, 2 R A [m^3] (Eq. 16)."""
        return 2.0 * self.R * self.A

    @property
    def deliveries(self) -> int:
        """Deliveries per crank revolution, m = cylinders x (2 if double-acting else 1) [-]."""
        return self.cylinders * (2 if self.double_acting else 1)

    @property
    def volume_per_revolution(self) -> float:
        """Volume delivered per crank revolution, m 2 R A [m^3] (Eq. 16 for every face)."""
        return self.deliveries * self.stroke_volume

    @property
    def mean_load_torque(self) -> float:
        """Cycle-mean load torque on the crank, m rho_w g h A R / pi [N m] (Eq. 18 for m faces)."""
        return groups.mean_load_torque(self.deliveries, self.load_torque)

    @property
    def rest_torque_on_crank(self) -> float:
        """The windmill's torque at rest reflected to the crank, R+ T_0 [N m]: a resting pump
        starts where it beats the load on the crank (:func:`windpump.starts_from_rest`)."""
        return groups.rest_torque_on_crank(self.R_dagger, self.T_0)

    @property
    def runaway_speed(self) -> float:
        """Windmill speed where its torque falls to zero, omega_m (1 + sqrt(T_m/(T_m - T_0)))
        [rad/s]: 2 omega_m when T_0 = 0 (Eq. 11), and with a rotor (omega_m is half of it)."""
        if self.rotor is not None:
            return 2.0 * self.omega_m
        return self.omega_m * (1.0 + math.sqrt(self.T_m / (self.T_m - self.T_0)))

    @property
    def is_ideal(self) -> bool:
        """Whether this is the paper's ideal machine: no reciprocating mass, a lossless chain, no
        pipe friction (L_main or f_main 0) and a tight piston (the real machine's defaults)."""
        return (
            self.m_r == 0.0
            and self.eta_t == 1.0
            and (self.L_main == 0.0 or self.f_main == 0.0)
            and self.d_leak == 0.0
        )

    @property
    def leak_capacity(self) -> float:
        """Most the leak hole passes against the static head, q_L = Cd_leak (pi d_leak^2 / 4)
        sqrt(2 g h) [m^3/s]; 0 without a hole."""
        return float(equations.leak_capacity(self.d_leak, self.Cd_leak, self.g, self.h))

    @property
    def friction_coefficient(self) -> float:
        """The rising main's friction head per flow squared, h_f / Q^2 = f_main (L_main / D_main)
        / (2 g a_main^2) [s^2/m^5], a_main = pi D_main^2 / 4; 0 without a pipe."""
        return float(equations.friction_coefficient(self.f_main, self.L_main, self.D_main, self.g))

    @property
    def bore(self) -> float:
        """Piston diameter sqrt(4 A / pi) [m], from its cross-section A."""
        return math.sqrt(4.0 * self.A / math.pi)


def read_json(text: str | bytes) -> object:
    """JSON text as Python objects, or a :class:`DesignFileError` saying why not (nesting too deep
    for Python's recursion included)."""
    if not isinstance(text, str | bytes | bytearray):
        raise DesignFileError(
            f"a design file is JSON text (str or bytes), not a {type(text).__name__}"
        )
    try:
        return json.loads(text, object_pairs_hook=_once_each)
    except (json.JSONDecodeError, UnicodeDecodeError) as error:
        raise DesignFileError(f"not JSON: {error}") from None
    except DesignFileError:
        raise
    except ValueError:  # an integer of more digits than Python converts
        raise DesignFileError(
            f"not a design file: a number in it has more than {sys.get_int_max_str_digits():,} "
            "digits"
        ) from None
    except RecursionError:
        raise DesignFileError("not a design file: its JSON is nested too deeply to read") from None


def _once_each(pairs: list[tuple[str, object]]) -> dict[str, object]:
    """A JSON object's names and values, each name once: JSON leaves a repeated one's meaning
    open, and Python's reader would keep its last value silently."""
    document = dict(pairs)
    if len(document) < len(pairs):
        seen: set[str] = set()
        for name, _ in pairs:
            if name in seen:
                raise DesignFileError(f"not a design file: {shown(name)} is given twice")
            seen.add(name)
    return document


def _design_fields(document: object) -> dict[str, typing.Any]:
    """The ``fields`` of a design document, checked against this version's layout."""
    if not isinstance(document, dict) or document.get("schema") != SCHEMA:
        raise DesignFileError(f'not a design file: it needs "schema": "{SCHEMA}"')
    version = document.get("version")
    if isinstance(version, bool) or not isinstance(version, int) or version < 1:
        raise DesignFileError(
            f'"version" = {shown(version)} is not allowed: it must be 1 to {SCHEMA_VERSION}'
        )
    if version > SCHEMA_VERSION:
        raise DesignFileError(
            f"version {shown(version)} was written by a newer windpump; this one reads version "
            f"{SCHEMA_VERSION}"
        )
    fields = document.get("fields")
    if not isinstance(fields, dict):
        raise DesignFileError('"fields" must be an object of field names and values')
    known = [name for name in UNITS if version > 1 or name not in REAL_MACHINE]
    unknown = sorted(set(fields) - set(known))
    if unknown:
        raise DesignFileError(
            f"unknown field(s) {shown(unknown)}; the fields of version {version} are {known}"
        )
    required = [f.name for f in dataclasses.fields(Design) if f.default is dataclasses.MISSING]
    missing = [name for name in required if name not in fields]
    if missing:
        raise DesignFileError(f"missing field(s) {missing}")
    units = document.get("units", {})
    if not isinstance(units, dict):
        raise DesignFileError('"units" must be an object of field names and units')
    for name, unit in units.items():
        if name in UNITS and unit != UNITS[name]:
            raise DesignFileError(
                f'the unit of {name} is {_quoted(unit)}; design files use SI units: "{UNITS[name]}"'
            )
    return fields


def _rotor(document: dict) -> Rotor | None:
    """The rotor of a version 3 design document, or None (the paper's curve)."""
    rotor = document.get("rotor")
    if rotor is None:
        return None
    if document.get("version", 1) < 3 or not isinstance(rotor, dict):
        raise DesignFileError(
            '"rotor" must be an object (diameter, table_tsr, table_cq, ...) in version 3'
        )
    known = [f.name for f in dataclasses.fields(Rotor)]
    unknown = sorted(set(rotor) - set(known))
    missing = [name for name in ("diameter", "table_tsr", "table_cq") if name not in rotor]
    if unknown or missing:
        raise DesignFileError(
            f"the rotor's field(s) {shown(unknown or missing)} are "
            + ("unknown" if unknown else "missing")
            + f"; a rotor has {known}"
        )
    return Rotor.from_cq(
        rotor["diameter"], rotor["table_tsr"], rotor["table_cq"],
        **{name: rotor[name] for name in ("rho_air", "V_furl", "source") if name in rotor},
    )  # fmt: skip


def _quoted(text: object) -> str:
    """A short text in double quotes, as a file writes it; anything else as :func:`shown`."""
    return f'"{text}"' if isinstance(text, str) and len(text) <= 40 else shown(text)
