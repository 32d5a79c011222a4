"""The Site tab's year as the core computes it, apart from its drawing: what a year is asked for
(``Asked``), and ``run_year``, which reads the site's record and runs the year, the smallest tank
for 5 % and the loss-of-load curve (``Year``). Served, it runs in a thread off the event loop
(``serving.off_the_loop``); it changes no widget and no Bokeh model."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

import windpump

from .compiling import COMPILE, SITE_TAB
from .site_figures import LOLP_TARGET
from .site_record import SiteRecords

TANKS = 41  # tank sizes on the loss-of-load curve, over the tank slider's range


@dataclasses.dataclass(frozen=True)
class Asked:
    """What a year is asked for: the design at V_ref, the tab's inputs, the uploaded record (by
    identity, ``WindRecord`` compares so: a second file is a new year) and the tank slider's
    end [m³]. Two are equal when they ask for the same year."""

    design: windpump.Design
    site: str
    hub: float  # [m]
    demand: float  # [m³/day]
    tank: float  # [m³]
    restart: str
    uploaded: windpump.WindRecord | None
    largest_tank: float  # [m³]


@dataclasses.dataclass(frozen=True)
class Year:
    """A year computed for an ``Asked``: the core's ``Supply``, the smallest tank for 5 % [m³]
    (inf: none is enough), what the loss-of-load curve is for (design, record, demand, restart,
    its largest tank) and the curve's points (None: the one drawn stands)."""

    supplied: windpump.Supply
    tank_5: float
    curve: tuple
    lolp: dict | None


def tank_range(tank: float, tank_5: float, largest: float) -> float:
    """The curve's largest tank [m³]: twice this tank's, or 1.5 times the smallest for 5 %,
    at least 20, rounded up to 10 and at most the slider's end (the curve's knee in view)."""
    wanted = max(20.0, 2.0 * tank)
    if math.isfinite(tank_5):
        wanted = max(wanted, 1.5 * tank_5)
    return min(largest, 10.0 * math.ceil(wanted / 10.0))


def run_year(records: SiteRecords, asked: Asked, curve: tuple, tank_5: float) -> Year:
    """The year ``asked`` for, with the smallest tank for 5 % and the loss-of-load curve, each
    recomputed only when what it depends on differs from ``curve`` (the one drawn, whose
    smallest tank is ``tank_5``). A design the year cannot run raises the core's ValueError."""
    COMPILE.wait(SITE_TAB)  # a first start compiles it in a worker: not a second time here
    design, demand = asked.design, asked.demand
    record = records.at(asked.site, asked.hub)
    rule = dict(restart=asked.restart)
    of = (design, record, demand, asked.restart)
    if of != curve[:4]:
        tank_5 = windpump.tank_for(design, record, demand, LOLP_TARGET, **rule)
    top = tank_range(asked.tank, tank_5, asked.largest_tank)
    lolp = None
    if (*of, top) != curve:
        tanks = np.linspace(0.0, top, TANKS)
        mapped = windpump.supply_map(design, record, demand, [design.R_dagger], tanks, **rule)
        lolp = {"tank": tanks, "lolp": 100 * mapped.lolp[:, 0]}
    supplied = windpump.supply(design, record, demand, asked.tank, **rule)
    return Year(supplied, tank_5, (*of, top), lolp)
