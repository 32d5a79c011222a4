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
    "MM_PER_M",
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
