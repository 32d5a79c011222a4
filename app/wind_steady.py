"""The Wind tab's steady-wind numbers, all of them the core's, apart from their drawing: the
water against a steady wind, the site's Weibull density, the wind thresholds and the water a day
by the averaged theory. A real machine's averaged theory is quadrature and root finding (~0.15 s
for the curve's 400 winds), so served they are worked out off the event loop
(``serving.off_the_loop``); this module changes no widget and no Bokeh model."""

from __future__ import annotations

import dataclasses

import numpy as np

import windpump
from windpump.model.wind import weibull_density, weibull_scale
from windpump.units import LITRES_PER_M3

POINTS = 400  # winds on the curve


@dataclasses.dataclass(frozen=True)
class SteadyWind:
    """The curve's winds ``V`` [m/s], the water at each ``flow`` [L/s] and the site's Weibull
    ``density`` [s/m]; the water at the steady wind ``here`` [L/s]; the wind thresholds
    ``V_stop`` and ``V_start`` [m/s] (None: it never starts on its own); the water a day at the
    site, ``low`` and ``high`` [L/day]."""

    V: np.ndarray
    flow: np.ndarray
    density: np.ndarray
    here: float
    V_stop: float
    V_start: float | None
    low: float
    high: float


def steady_wind(design: windpump.Design, mean_wind: float, k: float, V: float) -> SteadyWind:
    """``design``'s (at V_ref) numbers for a site of Weibull ``mean_wind`` [m/s] and shape ``k``,
    and the steady wind ``V`` [m/s]; the core's ValueError says why a design cannot run."""
    top = max(20.0, 2.5 * weibull_scale(mean_wind, k))
    winds = np.linspace(0.0, top, POINTS)
    V_stop, V_start = windpump.wind_thresholds(design)
    low, high = windpump.water_per_day(design, mean_wind, k)
    return SteadyWind(
        V=winds,
        flow=LITRES_PER_M3 * windpump.steady_flow(design, winds),
        density=weibull_density(winds, mean_wind, k),
        here=float(LITRES_PER_M3 * windpump.steady_flow(design, V)),
        V_stop=V_stop,
        V_start=V_start,
        low=LITRES_PER_M3 * low,
        high=LITRES_PER_M3 * high,
    )
