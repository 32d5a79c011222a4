"""windpump: dynamics of a wind-driven piston pump.

The model is M. Louge, *A simple wind-pump analysis* (2010): a windmill drives, through a chain and
two sprockets, a slider-crank and a single-acting piston lifting water by a head h. Equation numbers
in the docstrings are that paper's. Beyond it: several cylinders with their phase lags,
double-acting pistons and a windmill with torque at rest (``Design.cylinders``, ``double_acting``,
``T_0``), the real machine's reciprocating mass, lossy chain, rising main and leak hole
(``Design.m_r``, ``eta_t``, ``L_main``, ``d_leak``, ...), the rotor in a site's wind (``Design.V_ref``, :mod:`windpump.wind`,
:func:`water_per_day`), and studies: the design map over gear ratio and head (:func:`design_map`)
and many runs on any executor, a dask cluster's included (:func:`sweep`).

>>> import windpump
>>> design = windpump.Design.seed_example()
>>> run = windpump.simulate(design, 600.0)
>>> round(windpump.time_constant(design), 1), run.stalled
(78.6, False)
"""

from . import (
    energy,
    files,
    labdata,
    linkage,
    playback,
    reciprocating,
    theory,
    units,
    weather,
    wind,
)
from .averaged import (
    averaged_stall_time,
    mean_lever_arm,
    spinup,
    stall_margin,
    stall_sides,
    steady_speeds,
    time_constant,
)
from .design import Design
from .dynamics import MAX_SAMPLES, Intermittency, SimulationResult, revolution_marks, simulate
from .energy import EnergyTotals, PowerBudget, StartupPower, power_budget, startup_power
from .errors import DesignFileError, LabDataError, NoClosure, ParameterError, StallError
from .exploration import Exploration, NotStarted, Status, explore
from .kinematics import (
    delivering_faces,
    f2,
    face_flows,
    lever_arm,
    piston_position,
    rod_angle,
    swept_strokes,
)
from .labdata import TorqueTable, read_torque_csv
from .loads import load_torque_on_crank, peak_load_torque, rest_torque, starts_from_rest
from .maps import DesignMap, design_map
from .playback import CrankTable, Playback, crank_table, piston_table, playback_frames
from .site import (
    WindEvents,
    WindRun,
    record_water,
    run_in_wind,
    steady_flow,
    water_per_day,
    wind_thresholds,
)
from .studies import Sweep, sweep
from .weather import read_weather, sample_site
from .wind import WindRecord
from .windmill import (
    OperatingPoint,
    TorqueFit,
    fit_torque_curve,
    load_power,
    operating_point,
    windmill_power,
    windmill_torque,
)
from .yearly import MonthTable, Supply, SupplyMap, Totals, supply, supply_map, tank_for

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
