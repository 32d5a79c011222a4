"""windpump: dynamics of a wind-driven piston pump.

The model is M. Louge, *A simple wind-pump analysis* (2010): a windmill drives, through a chain and
two sprockets, a slider-crank and a single-acting piston lifting water by a head h. Equation numbers
in the docstrings are that paper's. Beyond it: several cylinders with their phase lags,
double-acting pistons and a windmill with torque at rest (``Design.cylinders``, ``double_acting``,
``T_0``), the rotor in a site's wind (``Design.V_ref``, :mod:`windpump.wind`,
:func:`water_per_day`), and studies: the design map over gear ratio and head (:func:`design_map`)
and many runs on any executor, a dask cluster's included (:func:`sweep`).

>>> import windpump
>>> design = windpump.Design.seed_example()
>>> run = windpump.simulate(design, 600.0)
>>> round(windpump.time_constant(design), 1), run.stalled
(78.6, False)
"""

from . import energy, labdata, linkage, playback, wind
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
from .energy import PowerBudget, StartupPower, power_budget, startup_power
from .errors import DesignFileError, NoClosure, ParameterError, StallError
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
from .labdata import LabDataError, TorqueTable, read_torque_csv
from .loads import load_torque_on_crank, peak_load_torque, starts_from_rest
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
from .windmill import (
    OperatingPoint,
    TorqueFit,
    fit_torque_curve,
    load_power,
    operating_point,
    windmill_power,
    windmill_torque,
)

__all__ = [
    "MAX_SAMPLES",
    "CrankTable",
    "Design",
    "DesignFileError",
    "DesignMap",
    "Exploration",
    "Intermittency",
    "LabDataError",
    "NoClosure",
    "NotStarted",
    "OperatingPoint",
    "ParameterError",
    "Playback",
    "PowerBudget",
    "SimulationResult",
    "StallError",
    "StartupPower",
    "Sweep",
    "Status",
    "TorqueFit",
    "TorqueTable",
    "WindEvents",
    "WindRun",
    "averaged_stall_time",
    "delivering_faces",
    "crank_table",
    "design_map",
    "energy",
    "explore",
    "f2",
    "face_flows",
    "fit_torque_curve",
    "labdata",
    "lever_arm",
    "linkage",
    "load_power",
    "load_torque_on_crank",
    "mean_lever_arm",
    "operating_point",
    "peak_load_torque",
    "piston_position",
    "piston_table",
    "playback",
    "playback_frames",
    "power_budget",
    "read_torque_csv",
    "record_water",
    "revolution_marks",
    "rod_angle",
    "run_in_wind",
    "simulate",
    "spinup",
    "startup_power",
    "starts_from_rest",
    "stall_margin",
    "stall_sides",
    "steady_flow",
    "steady_speeds",
    "sweep",
    "swept_strokes",
    "time_constant",
    "water_per_day",
    "wind",
    "wind_thresholds",
    "windmill_power",
    "windmill_torque",
]
