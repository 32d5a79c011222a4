"""The Aermotor 702 back-geared windmill: its maker's pumping table, and the mill in the model's terms.

The table (capacity per hour and the elevation to which water can be raised, for the 6- to 16-ft
wheels and 1 7/8 to 3 3/4 in cylinders, "approximate, based on the mill set on the long stroke,
operating in a 15-20mph wind") is data in the package, ``aermotor_702.csv``, with its sources in
its header: :func:`aermotor_702_table`. :func:`aermotor_702` builds a :class:`~windpump.Design`
of one mill and cylinder for the model (:meth:`Design.from_machine` with
:meth:`Rotor.multiblade`), and :func:`aermotor_702_parts` gives its parts in SI units.

Where each number comes from (the sources as the search tool stores them; what could not be
found there is said, and estimated, not invented):

=====================  ==========================================================================
the table              Aermotor Windmill Company, "Aermotor Windmill Information" (web page,
                       aermotorwindmill.com, undated): cylinder, capacity [gal/h] for the 6-ft
                       and for the 8- to 16-ft mills, elevation [ft] per wheel; the short stroke
                       "increases elevation by one-third and reduces pumping capacities by
                       one-fourth". The 1 7/8 in cylinder's long and short stroke, and the wind
                       "18 to 20" mph: The Wind Engine 702, "How To" (web page, a dealer's).
gear ratio             3.29 wheel turns per pump stroke (:data:`GEAR_RATIO`): the figure commonly
                       cited for the 702's back gear; not found in the stored sources, which say
                       only that the back gearing makes the wheel turn "three revolutions for each
                       stroke" (Bright Hub, "The Aermotor Windmill - Design History and
                       Evolution"). Not a fitted number.
long stroke            No stroke lengths were found in the stored sources. Estimated from the
                       maker's own sizing rule on the same page: pumps for a mill "should be
                       capable of giving a clear stroke, equal in inches, to the diameter of the
                       windwheel in feet" (8 in for an 8-ft wheel): :data:`LONG_STROKE_IN`. The
                       rule bounds the mill's stroke from above; a mill whose long stroke is
                       shorter pumps proportionally less per turn.
short stroke           3/4 of the long (:data:`SHORT_OVER_LONG`): the table's own "one-fourth"
                       less water per stroke and "one-third" more elevation (1/0.75) at the same
                       strokes per minute and the same torque.
wheel inertia          An estimate, not from a source (:func:`wheel_inertia`): the sails, rims and
                       arms as 6.5 kg/m^2 over an annulus from 0.35 r to r. Only transients
                       (spin-up, gusts) depend on it: steady flow and the ratings do not.
rotor                  :meth:`Rotor.multiblade`: the American multiblade wheel's published curve,
                       not fitted to this table.
=====================  ==========================================================================
"""

from __future__ import annotations

import csv
import dataclasses
import functools
import math
import numbers
import typing
from importlib import resources

from ..errors import ParameterError
from ..model.design import Design
from ..model.rotor import Rotor
from ..units import M3_PER_US_GALLON, M_S_PER_MPH, METRES_PER_FOOT, METRES_PER_INCH
from ..validation import non_negative, positive

__all__ = [
    "CatalogueRow",
    "MillParts",
    "aermotor_702",
    "aermotor_702_parts",
    "aermotor_702_row",
    "aermotor_702_table",
    "wheel_inertia",
]

TABLE_FILE = "aermotor_702.csv"
"""The table's file in this package (US units, a comment header naming its sources)."""

WHEELS_FT = (6, 8, 10, 12, 14, 16)
"""The 702's wheel diameters [ft]."""

CYLINDERS = {
    "1 7/8": 1.875,
    "2 1/4": 2.25,
    "2 1/2": 2.5,
    "2 3/4": 2.75,
    "3 1/2": 3.5,
    "3 3/4": 3.75,
}
"""The table's cylinders: bore as printed -> bore [in]."""

LARGE_CYLINDER_WHEELS_FT = (10, 12, 14, 16)
"""The wheels the table lists the 3 3/4 in cylinder for [ft]."""

RATED_WINDS_MPH = (15.0, 20.0)
"""The winds the maker's table is stated for, "a 15-20mph wind" [mph]."""

GEAR_RATIO = 3.29
"""Wheel turns per crank turn (per pump stroke) of the 702's back gear [-]: the commonly cited
figure, not found in the stored sources (which say "three revolutions for each stroke")."""

LONG_STROKE_IN = {wheel: float(wheel) for wheel in WHEELS_FT}
"""The long stroke [in] per wheel [ft]: an estimate, the maker's sizing rule "a clear stroke, equal
in inches, to the diameter of the windwheel in feet" (no published stroke lengths were found)."""

SHORT_OVER_LONG = 0.75
"""The short stroke over the long [-]: the table's "reduces pumping capacities by one-fourth"."""

WHEEL_AREAL_DENSITY = 6.5
"""The wheel's mass per area of its annulus [kg/m^2], an estimate: 18 sails of 24-gauge (0.55 mm)
galvanised sheet covering ~85 % of the annulus (0.85 x 0.55e-3 m x 7850 kg/m^3 = 3.7 kg/m^2), and
rims and arms of about as much again less a quarter (~11 kg on an 8-ft wheel, 2.8 kg/m^2)."""

SAIL_ROOT = 0.35
"""Where the sails start, as a fraction of the wheel's radius [-] (an estimate from photographs'
proportions: the inner rim at about a third of the radius)."""


@dataclasses.dataclass(frozen=True)
class CatalogueRow:
    """One cell pair of the maker's table: a wheel and a cylinder's capacity and maximum lift.

    Parameters
    ----------
    source : str
        ``"aermotor"`` (the maker's table) or ``"windengine702"`` (a dealer's copy of the
        1 7/8 in row, with the short stroke's).
    stroke : str
        ``"long"`` or ``"short"``: the mill's stroke setting the row is for.
    cylinder : str
        The cylinder's bore as printed ("1 7/8") [in].
    wheel_ft : int
        The wheel's diameter [ft].
    capacity_gph : float
        Capacity [US gal/h] in the table's wind (15 to 20 mph).
    lift_ft : float
        The elevation to which water can be raised [ft].
    note : str
        What is doubtful about the row ("" when nothing is).
    """

    source: str
    stroke: str
    cylinder: str
    wheel_ft: int
    capacity_gph: float
    lift_ft: float
    note: str = ""

    @property
    def cylinder_in(self) -> float:
        """The bore [in]."""
        return CYLINDERS[self.cylinder]

    @property
    def bore(self) -> float:
        """The bore [m]."""
        return self.cylinder_in * METRES_PER_INCH

    @property
    def wheel_diameter(self) -> float:
        """The wheel's diameter [m]."""
        return self.wheel_ft * METRES_PER_FOOT

    @property
    def capacity(self) -> float:
        """The capacity [m^3/s]."""
        return self.capacity_gph * M3_PER_US_GALLON / 3600.0

    @property
    def lift(self) -> float:
        """The maximum lift [m]."""
        return self.lift_ft * METRES_PER_FOOT


def aermotor_702_table() -> tuple[CatalogueRow, ...]:
    """The Aermotor 702's pumping table as published, one row per wheel, cylinder and stroke.

    Read from the package's ``aermotor_702.csv`` (its header names the sources and what was read
    into them). The maker's rows (``source == "aermotor"``) are for the long stroke in "a
    15-20mph wind"; a dealer's copy of the 1 7/8 in row adds the short stroke's.

    Returns
    -------
    tuple of CatalogueRow
        In the file's order: the maker's 34 rows, then the dealer's 10.

    Examples
    --------
    >>> rows = aermotor_702_table()
    >>> eight = [r for r in rows if r.source == "aermotor" and r.wheel_ft == 8]
    >>> [(r.cylinder, r.capacity_gph, r.lift_ft) for r in eight][:2]
    [('1 7/8', 180.0, 175.0), ('2 1/4', 360.0, 112.0)]
    >>> round(eight[0].lift, 2), round(eight[0].capacity * 1e3, 4)  # [m], [L/s]
    (53.34, 0.1893)
    """
    return _read_table()


@functools.cache
def _read_table() -> tuple[CatalogueRow, ...]:
    """The package's ``aermotor_702.csv``, read once."""
    text = resources.files(__package__).joinpath(TABLE_FILE).read_text(encoding="utf-8")
    lines = [line for line in text.splitlines() if line and not line.startswith("#")]
    return tuple(
        CatalogueRow(
            source=row["source"],
            stroke=row["stroke"],
            cylinder=row["cylinder"],
            wheel_ft=int(row["wheel_ft"]),
            capacity_gph=float(row["capacity_gph"]),
            lift_ft=float(row["lift_ft"]),
            note=row["note"],
        )
        for row in csv.DictReader(lines)
    )


@dataclasses.dataclass(frozen=True)
class MillParts:
    """An Aermotor 702's parts in SI units, as :meth:`Design.from_machine` takes them.

    Parameters
    ----------
    wheel_diameter : float
        The wheel's diameter [m].
    gear_ratio : float
        Wheel turns per crank turn [-].
    stroke : float
        The pump's stroke [m].
    bore : float
        The cylinder's bore [m].
    wheel_inertia : float
        The wheel's moment of inertia about its shaft [kg m^2] (an estimate).
    """

    wheel_diameter: float
    gear_ratio: float
    stroke: float
    bore: float
    wheel_inertia: float


def wheel_inertia(wheel_ft: float) -> float:
    """An estimate of a multiblade wheel's moment of inertia about its shaft [kg m^2].

    The sails, rims and arms as a uniform annulus of :data:`WHEEL_AREAL_DENSITY` (6.5 kg/m^2)
    from ``SAIL_ROOT`` r (0.35 r) to r: ``m = sigma pi r^2 (1 - k^2)``, ``I = m r^2 (1 + k^2) / 2``
    with k = 0.35. Not from a source; good to perhaps a factor of 2. It sets how fast the wheel
    follows the wind, not the steady flow or the ratings.

    Parameters
    ----------
    wheel_ft : float
        The wheel's diameter [ft], > 0.

    Examples
    --------
    >>> round(wheel_inertia(8), 1), round(wheel_inertia(16) / wheel_inertia(8), 6)  # ~ D^4
    (22.2, 16.0)
    """
    r = 0.5 * positive("wheel_ft", wheel_ft, "ft") * METRES_PER_FOOT
    k2 = SAIL_ROOT**2
    mass = WHEEL_AREAL_DENSITY * math.pi * r**2 * (1.0 - k2)
    return 0.5 * mass * r**2 * (1.0 + k2)


def aermotor_702_parts(
    wheel_ft: float, cylinder_in: float | str, *, stroke: str = "long"
) -> MillParts:
    """An Aermotor 702 of the given wheel and cylinder, in SI units (every number's source in the
    module's table).

    Parameters
    ----------
    wheel_ft : float
        The wheel's diameter [ft]: 6, 8, 10, 12, 14 or 16.
    cylinder_in : float or str
        The cylinder's bore [in], one of the table's: 1 7/8, 2 1/4, 2 1/2, 2 3/4, 3 1/2, or
        3 3/4 (10- to 16-ft mills), as a number (1.875) or as printed ("1 7/8").
    stroke : {"long", "short"}
        The mill's stroke setting: the long stroke, or 3/4 of it.

    Returns
    -------
    MillParts

    Raises
    ------
    ParameterError
        A wheel, cylinder or stroke the table does not have, naming it and those it has.

    Examples
    --------
    >>> parts = aermotor_702_parts(8, "1 7/8")
    >>> parts.gear_ratio, round(parts.stroke, 4), round(parts.bore, 6)  # 3.29, 8 in, 1 7/8 in
    (3.29, 0.2032, 0.047625)
    >>> round(aermotor_702_parts(8, 1.875, stroke="short").stroke / 0.0254, 2)  # [in]
    6.0
    """
    wheel = _wheel(wheel_ft)
    label = _cylinder(cylinder_in, wheel)
    if stroke not in ("long", "short"):
        raise ParameterError("stroke", stroke, "'long' or 'short'")
    inches = LONG_STROKE_IN[wheel] * (SHORT_OVER_LONG if stroke == "short" else 1.0)
    return MillParts(
        wheel_diameter=wheel * METRES_PER_FOOT,
        gear_ratio=GEAR_RATIO,
        stroke=inches * METRES_PER_INCH,
        bore=CYLINDERS[label] * METRES_PER_INCH,
        wheel_inertia=wheel_inertia(wheel),
    )


def aermotor_702(
    wheel_ft: float,
    cylinder_in: float | str,
    *,
    stroke: str = "long",
    lift_ft: float,
    V_ref: float = RATED_WINDS_MPH[0] * M_S_PER_MPH,
    V_furl: float | None = None,
    **fields: typing.Any,
) -> Design:
    """An Aermotor 702 back-geared windmill on a cylinder, lifting water by ``lift_ft``: a
    :class:`~windpump.Design` for the model.

    The wheel is :meth:`Rotor.multiblade` of the wheel's diameter; the gear ratio, the stroke and
    the wheel's inertia are :func:`aermotor_702_parts`' (their sources in the module's table);
    :meth:`Design.from_machine` turns them into R1/R0, R = stroke/2, A = pi bore^2/4 and I0.

    Parameters
    ----------
    wheel_ft : float
        The wheel's diameter [ft]: 6, 8, 10, 12, 14 or 16.
    cylinder_in : float or str
        The cylinder's bore [in], one of the table's (1.875 or "1 7/8", ...).
    stroke : {"long", "short"}
        The mill's stroke setting.
    lift_ft : float
        The lift from the water in the well to the outlet [ft], >= 0: the design's h.
    V_ref : float, default 15 mph (6.7056 m/s)
        The wind the design is stated at [m/s]: the low end of the table's 15 to 20 mph.
    V_furl : float or None, default None
        The wind above which the wheel turns out of the wind [m/s] (None: never).
    **fields
        Any other field of :class:`~windpump.Design` or argument of :meth:`Design.from_machine`
        (eta_t, m_r, crank_inertia, ...).

    Returns
    -------
    Design

    Raises
    ------
    ParameterError
        A wheel or cylinder the table does not have (naming ``wheel_ft`` or ``cylinder_in`` and
        the sizes there are), a stroke other than long or short, a negative lift.

    Examples
    --------
    >>> d = aermotor_702(8, "1 7/8", lift_ft=175)  # the table's 8-ft mill at its maximum lift
    >>> round(d.R_dagger, 2), round(d.R, 4), round(d.A * 1e4, 3), round(d.h, 2)  # R [m], A [cm^2]
    (3.29, 0.1016, 17.814, 53.34)
    >>> round(d.V_ref, 4), d.rotor.diameter == 8 * 0.3048
    (6.7056, True)
    """
    parts = aermotor_702_parts(wheel_ft, cylinder_in, stroke=stroke)
    head = non_negative("lift_ft", lift_ft, "ft") * METRES_PER_FOOT
    return Design.from_machine(
        Rotor.multiblade(parts.wheel_diameter, V_furl=V_furl),
        V_ref=V_ref,
        gear_ratio=parts.gear_ratio,
        stroke=parts.stroke,
        bore=parts.bore,
        head=head,
        wheel_inertia=parts.wheel_inertia,
        **fields,
    )


def aermotor_702_row(
    wheel_ft: float, cylinder_in: float | str, *, stroke: str = "long"
) -> CatalogueRow | None:
    """The table's row for an Aermotor 702 of this wheel, cylinder and stroke: its published
    capacity and maximum lift (the maker's row first, else a dealer's), or None when the table
    has none for it.

    Parameters
    ----------
    wheel_ft : float
        The wheel's diameter [ft]: 6, 8, 10, 12, 14 or 16.
    cylinder_in : float or str
        The cylinder's bore [in], one of the table's (1.875 or "1 7/8", ...).
    stroke : {"long", "short"}
        The mill's stroke setting.

    Returns
    -------
    CatalogueRow or None

    Raises
    ------
    ParameterError
        As :func:`aermotor_702_parts`: a wheel, cylinder or stroke the table does not have.

    Examples
    --------
    >>> row = aermotor_702_row(8, "1 7/8")
    >>> row.capacity_gph, row.lift_ft  # [US gal/h] in a 15-20 mph wind, [ft]
    (180.0, 175.0)
    """
    aermotor_702_parts(wheel_ft, cylinder_in, stroke=stroke)  # the same refusals
    wheel = _wheel(wheel_ft)
    label = _cylinder(cylinder_in, wheel)
    rows = [
        row
        for row in aermotor_702_table()
        if (row.wheel_ft, row.cylinder, row.stroke) == (wheel, label, stroke)
    ]
    return next((row for row in rows if row.source == "aermotor"), rows[0] if rows else None)


def _wheel(value: object) -> int:
    """``value`` as one of :data:`WHEELS_FT`, or a ParameterError naming ``wheel_ft``."""
    allowed = f"one of the 702's wheels, {', '.join(map(str, WHEELS_FT))} ft"
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ParameterError("wheel_ft", value, allowed, "ft")
    for wheel in WHEELS_FT:
        if float(value) == wheel:
            return wheel
    raise ParameterError("wheel_ft", value, allowed, "ft")


def _cylinder(value: object, wheel: int) -> str:
    """``value`` as one of :data:`CYLINDERS`' labels offered on ``wheel``, or a ParameterError
    naming ``cylinder_in``."""
    allowed = f"one of the table's cylinders, {', '.join(CYLINDERS)} in"
    label = None
    if isinstance(value, str):
        label = " ".join(value.replace('"', " ").replace("in", " ").split())
        label = label if label in CYLINDERS else None
    elif isinstance(value, numbers.Real) and not isinstance(value, bool):
        label = next((k for k, inches in CYLINDERS.items() if float(value) == inches), None)
    if label is None:
        raise ParameterError("cylinder_in", value, allowed, "in")
    if label == "3 3/4" and wheel not in LARGE_CYLINDER_WHEELS_FT:
        raise ParameterError(
            "cylinder_in",
            value,
            f"one of {', '.join(k for k in CYLINDERS if k != '3 3/4')} in on a {wheel}-ft mill",
            "in",
            why="the table lists the 3 3/4 in cylinder for the 10- to 16-ft mills only",
        )
    return label
