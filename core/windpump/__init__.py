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

from . import energy, linkage
from .averaged import (
    StallError,
    averaged_stall_time,
    mean_lever_arm,
    spinup,
    stall_margin,
    steady_speeds,
    time_constant,
)
from .design import Design
from .dynamics import MAX_SAMPLES, Intermittency, SimulationResult, simulate
from .energy import PowerBudget, StartupPower, power_budget, startup_power
from .exploration import Exploration, Status, explore
from .kinematics import f2, lever_arm, piston_position, rod_angle, swept_strokes
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
    "OperatingPoint",
    "ParameterError",
    "PowerBudget",
    "SimulationResult",
    "StallError",
    "StartupPower",
    "Status",
    "TorqueFit",
    "averaged_stall_time",
    "energy",
    "explore",
    "f2",
    "fit_torque_curve",
    "lever_arm",
    "linkage",
    "load_power",
    "mean_lever_arm",
    "operating_point",
    "piston_position",
    "power_budget",
    "rod_angle",
    "simulate",
    "spinup",
    "startup_power",
    "stall_margin",
    "steady_speeds",
    "swept_strokes",
    "time_constant",
    "windmill_power",
    "windmill_torque",
]
