"""windpump: dynamics of a wind-driven single-acting piston pump.

The model is M. Louge, *A simple wind-pump analysis* (2010): a windmill drives, through a chain and
two sprockets, a slider-crank and a single-acting piston lifting water by a head h. Equation numbers
in the docstrings are that paper's.

>>> import windpump
>>> design = windpump.Design.seed_example()
>>> run = windpump.simulate(design, 600.0)
>>> round(windpump.time_constant(design), 1), run.stalled
(78.6, False)
"""

from . import energy, labdata, linkage, playback
from .averaged import (
    StallError,
    averaged_stall_time,
    mean_lever_arm,
    spinup,
    stall_margin,
    stall_sides,
    steady_speeds,
    time_constant,
)
from .design import Design
from .dynamics import MAX_SAMPLES, Intermittency, SimulationResult, simulate
from .energy import PowerBudget, StartupPower, power_budget, startup_power
from .exploration import Exploration, Status, explore
from .kinematics import f2, lever_arm, piston_position, rod_angle, swept_strokes
from .labdata import LabDataError, TorqueTable, read_torque_csv
from .playback import Playback, piston_table, playback_frames
from .validation import ParameterError
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
    "Design",
    "Exploration",
    "Intermittency",
    "LabDataError",
    "OperatingPoint",
    "ParameterError",
    "Playback",
    "PowerBudget",
    "SimulationResult",
    "StallError",
    "StartupPower",
    "Status",
    "TorqueFit",
    "TorqueTable",
    "averaged_stall_time",
    "energy",
    "explore",
    "f2",
    "fit_torque_curve",
    "labdata",
    "lever_arm",
    "linkage",
    "load_power",
    "mean_lever_arm",
    "operating_point",
    "piston_position",
    "piston_table",
    "playback",
    "playback_frames",
    "power_budget",
    "read_torque_csv",
    "rod_angle",
    "simulate",
    "spinup",
    "startup_power",
    "stall_margin",
    "stall_sides",
    "steady_speeds",
    "swept_strokes",
    "time_constant",
    "windmill_power",
    "windmill_torque",
]
