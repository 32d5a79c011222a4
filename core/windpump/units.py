"""Units in one place: the conversions the package and its callers print and report with.

Every quantity inside the package is in SI units (m, s, m^3, N m, rad/s); these constants turn
them into the units a reader expects (litres, days, hours, millimetres).

Examples
--------
>>> from windpump.units import LITRES_PER_M3, SECONDS_PER_DAY
>>> flow = 3.79e-4  # [m^3/s]
>>> round(flow * LITRES_PER_M3, 3), round(flow * SECONDS_PER_DAY, 2)  # [L/s], [m^3/day]
(0.379, 32.75)
"""

from __future__ import annotations

__all__ = [
    "LITRES_PER_M3",
    "METRES_PER_FOOT",
    "METRES_PER_INCH",
    "MM_PER_M",
    "M3_PER_US_GALLON",
    "M_S_PER_MPH",
    "SECONDS_PER_DAY",
    "SECONDS_PER_HOUR",
    "WATTS_PER_KW",
]


SECONDS_PER_HOUR = 3_600.0
"""[s/h]"""

SECONDS_PER_DAY = 86_400.0
"""[s/day]: m^3/s times this is m^3/day."""

LITRES_PER_M3 = 1_000.0
"""[L/m^3]: m^3 times this is litres, m^3/s times this L/s."""

MM_PER_M = 1_000.0
"""[mm/m]"""

WATTS_PER_KW = 1_000.0
"""[W/kW]"""

# US customary units, exact by definition (the international yard and pound agreement, 1959; the
# US gallon is 231 cubic inches): what a US maker's catalogue is printed in.

METRES_PER_FOOT = 0.3048
"""[m/ft]: feet times this is metres."""

METRES_PER_INCH = 0.0254
"""[m/in]: inches times this is metres."""

M3_PER_US_GALLON = 231 * METRES_PER_INCH**3
"""[m^3/gal]: US gallons times this is m^3 (231 in^3, 3.785411784 L)."""

M_S_PER_MPH = 1609.344 / 3600.0
"""[(m/s)/mph]: miles per hour times this is m/s (0.44704)."""
