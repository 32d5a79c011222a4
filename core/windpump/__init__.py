"""windpump: dynamics of a wind-driven piston pump.

The model is M. Louge, *A simple wind-pump analysis* (2010): a windmill drives, through a chain and
two sprockets, a slider-crank and a single-acting piston lifting water by a head h. Equation numbers
in the docstrings are that paper's. Beyond it: several cylinders with their phase lags,
double-acting pistons and a windmill with torque at rest (``Design.cylinders``, ``double_acting``,
``T_0``), the real machine's reciprocating mass, lossy chain, rising main and leak hole
(``Design.m_r``, ``eta_t``, ``L_main``, ``d_leak``, ...), the rotor in a site's wind (``Design.V_ref``, :mod:`windpump.model.wind`,
:func:`water_per_day`), and studies: the design map over gear ratio and head (:func:`design_map`)
and many runs on any executor, a dask cluster's included (:func:`sweep`).

>>> import windpump
>>> design = windpump.Design.seed_example()
>>> run = windpump.simulate(design, 600.0)
>>> round(windpump.time_constant(design), 1), run.stalled
(78.6, False)
"""

import importlib

from . import _old_paths, linkage, units
from .averaging import theory
from .averaging.averaged import (
    averaged_stall_time,
    mean_lever_arm,
    spinup,
    stall_margin,
    stall_sides,
    steady_speeds,
    time_constant,
)
from .averaging.operating import OperatingPoint, load_power, operating_point
from .errors import DesignFileError, LabDataError, NoClosure, ParameterError, StallError
from .model import reciprocating, wind
from .model.design import Design
from .model.kinematics import (
    delivering_faces,
    f2,
    face_flows,
    lever_arm,
    piston_position,
    rod_angle,
    swept_strokes,
)
from .model.loads import load_torque_on_crank, peak_load_torque, rest_torque, starts_from_rest
from .model.wind import WindRecord
from .model.windmill import TorqueFit, fit_torque_curve, windmill_power, windmill_torque
from .readers import files, labdata
from .readers.labdata import TorqueTable, read_torque_csv
from .run import energy, playback
from .run.dynamics import MAX_SAMPLES, Intermittency, SimulationResult, revolution_marks, simulate
from .run.energy import EnergyTotals, PowerBudget, StartupPower, power_budget, startup_power
from .run.exploration import Exploration, NotStarted, Status, explore
from .run.playback import CrankTable, Playback, crank_table, piston_table, playback_frames
from .sites import weather
from .sites.site import (
    WindEvents,
    WindRun,
    record_water,
    run_in_wind,
    steady_flow,
    water_per_day,
    wind_thresholds,
)
from .sites.weather import read_weather, sample_site
from .sites.yearly import MonthTable, Supply, SupplyMap, Totals, supply, supply_map, tank_for
from .study.maps import DesignMap, design_map
from .study.studies import Sweep, sweep

_old_paths.install()  # windpump.run.dynamics etc., the paths before the sub-packages, keep working


def __getattr__(name: str):
    """``windpump.run.dynamics`` and the other old paths (:mod:`windpump._old_paths`) as attributes."""
    if name in _old_paths.MOVED:
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


# The public names by topic, as the API reference (docs/api/index.rst) groups them.
__all__ = [
    # designs and errors
    "Design", "ParameterError", "StallError", "DesignFileError", "NoClosure", "LabDataError",
    # the full equation of motion (Eq. 12) and what is read off a run
    "simulate", "SimulationResult", "Intermittency", "revolution_marks", "MAX_SAMPLES",
    "explore", "Exploration", "Status", "NotStarted",
    # the averaged theory (Eqs. 18-25)
    "stall_margin", "stall_sides", "steady_speeds", "time_constant", "spinup",
    "averaged_stall_time", "mean_lever_arm",
    # kinematics (Eq. 1) and loads
    "piston_position", "rod_angle", "f2", "lever_arm", "delivering_faces", "face_flows",
    "swept_strokes", "load_torque_on_crank", "peak_load_torque", "starts_from_rest", "rest_torque",
    # the windmill (Eq. 11) and lab data
    "windmill_torque", "windmill_power", "load_power", "operating_point", "OperatingPoint",
    "fit_torque_curve", "TorqueFit", "read_torque_csv", "TorqueTable",
    # wind and site
    "wind_thresholds", "steady_flow", "water_per_day", "record_water", "run_in_wind",
    "WindRun", "WindEvents",
    # a site's year: weather records, the tank, the supply
    "WindRecord", "read_weather", "sample_site", "supply", "Supply", "MonthTable", "Totals",
    "tank_for", "supply_map", "SupplyMap",
    # studies
    "design_map", "DesignMap", "sweep", "Sweep",
    # energy and playback
    "startup_power", "StartupPower", "power_budget", "PowerBudget", "EnergyTotals",
    "playback_frames",
    "Playback", "piston_table", "crank_table", "CrankTable",
    # modules of their own
    "energy", "files", "labdata", "linkage", "playback", "reciprocating", "theory", "units",
    "weather", "wind",
]  # fmt: skip
