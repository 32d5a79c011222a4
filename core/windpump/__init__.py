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

from . import _old_paths

# Each public name -> where it lives ("module:name", or a module): imported on first use, so that
# `import windpump` loads neither numba nor a module a script does not use (the full run loads
# numba at its top; the averaged theory never does).
PUBLIC = {
    "averaged_stall_time": "averaging.averaged:averaged_stall_time",
    "mean_lever_arm": "averaging.averaged:mean_lever_arm",
    "spinup": "averaging.averaged:spinup",
    "stall_margin": "averaging.averaged:stall_margin",
    "stall_sides": "averaging.averaged:stall_sides",
    "steady_speeds": "averaging.averaged:steady_speeds",
    "time_constant": "averaging.averaged:time_constant",
    "OperatingPoint": "averaging.operating:OperatingPoint",
    "load_power": "averaging.operating:load_power",
    "operating_point": "averaging.operating:operating_point",
    "max_head": "averaging.ratings:max_head",
    "theory": "averaging.theory",
    "catalogue": "catalogue",
    "DesignFileError": "errors:DesignFileError",
    "LabDataError": "errors:LabDataError",
    "NoClosure": "errors:NoClosure",
    "ParameterError": "errors:ParameterError",
    "StallError": "errors:StallError",
    "linkage": "linkage",
    "Design": "model.design:Design",
    "delivering_faces": "model.kinematics:delivering_faces",
    "f2": "model.kinematics:f2",
    "face_flows": "model.kinematics:face_flows",
    "lever_arm": "model.kinematics:lever_arm",
    "piston_position": "model.kinematics:piston_position",
    "rod_angle": "model.kinematics:rod_angle",
    "swept_strokes": "model.kinematics:swept_strokes",
    "load_torque_on_crank": "model.loads:load_torque_on_crank",
    "peak_load_torque": "model.loads:peak_load_torque",
    "rest_torque": "model.loads:rest_torque",
    "starts_from_rest": "model.loads:starts_from_rest",
    "reciprocating": "model.reciprocating",
    "Rotor": "model.rotor:Rotor",
    "WindRecord": "model.wind:WindRecord",
    "wind": "model.wind",
    "TorqueFit": "model.windmill:TorqueFit",
    "fit_torque_curve": "model.windmill:fit_torque_curve",
    "windmill_power": "model.windmill:windmill_power",
    "windmill_torque": "model.windmill:windmill_torque",
    "files": "readers.files",
    "TorqueTable": "readers.labdata:TorqueTable",
    "labdata": "readers.labdata",
    "read_torque_csv": "readers.labdata:read_torque_csv",
    "Intermittency": "run.dynamics:Intermittency",
    "MAX_SAMPLES": "run.dynamics:MAX_SAMPLES",
    "SimulationResult": "run.dynamics:SimulationResult",
    "revolution_marks": "run.dynamics:revolution_marks",
    "simulate": "run.dynamics:simulate",
    "EnergyTotals": "run.energy:EnergyTotals",
    "PowerBudget": "run.energy:PowerBudget",
    "StartupPower": "run.energy:StartupPower",
    "energy": "run.energy",
    "power_budget": "run.energy:power_budget",
    "startup_power": "run.energy:startup_power",
    "Exploration": "run.exploration:Exploration",
    "NotStarted": "run.exploration:NotStarted",
    "Status": "run.exploration:Status",
    "explore": "run.exploration:explore",
    "CrankTable": "run.playback:CrankTable",
    "Playback": "run.playback:Playback",
    "crank_table": "run.playback:crank_table",
    "piston_table": "run.playback:piston_table",
    "playback": "run.playback",
    "playback_frames": "run.playback:playback_frames",
    "WindEvents": "sites.site:WindEvents",
    "WindRun": "sites.site:WindRun",
    "record_water": "sites.site:record_water",
    "run_in_wind": "sites.site:run_in_wind",
    "steady_flow": "averaging.theory:steady_flow",
    "water_per_day": "sites.site:water_per_day",
    "wind_thresholds": "sites.site:wind_thresholds",
    "read_weather": "sites.weather:read_weather",
    "sample_site": "sites.weather:sample_site",
    "weather": "sites.weather",
    "MonthTable": "sites.yearly:MonthTable",
    "Supply": "sites.yearly:Supply",
    "SupplyMap": "sites.yearly:SupplyMap",
    "Totals": "sites.yearly:Totals",
    "supply": "sites.yearly:supply",
    "supply_map": "sites.yearly:supply_map",
    "tank_for": "sites.yearly:tank_for",
    "DesignMap": "study.maps:DesignMap",
    "design_map": "study.maps:design_map",
    "Sweep": "study.studies:Sweep",
    "sweep": "study.studies:sweep",
    "units": "units",
}  # fmt: skip

_old_paths.install()  # windpump.dynamics etc., the paths before the sub-packages, keep working


def __getattr__(name: str):
    """A public name (:data:`PUBLIC`), imported on first use; or an old module path
    (``windpump.dynamics``: :mod:`windpump._old_paths`)."""
    if name in PUBLIC:
        module, _, attribute = PUBLIC[name].partition(":")
        value = importlib.import_module(f"{__name__}.{module}")
        if attribute:
            value = getattr(value, attribute)
        globals()[name] = value  # found once
        return value
    if name in _old_paths.MOVED:
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *PUBLIC})


# The public names by topic, as the API reference (docs/api/index.rst) groups them.
__all__ = [
    # designs and errors
    "Design", "Rotor", "ParameterError", "StallError", "DesignFileError", "NoClosure",
    "LabDataError",
    # the full equation of motion (Eq. 12) and what is read off a run
    "simulate", "SimulationResult", "Intermittency", "revolution_marks", "MAX_SAMPLES",
    "explore", "Exploration", "Status", "NotStarted",
    # the averaged theory (Eqs. 18-25)
    "stall_margin", "stall_sides", "steady_speeds", "time_constant", "spinup",
    "averaged_stall_time", "mean_lever_arm",
    # kinematics (Eq. 1) and loads
    "piston_position", "rod_angle", "f2", "lever_arm", "delivering_faces", "face_flows",
    "swept_strokes", "load_torque_on_crank", "peak_load_torque", "starts_from_rest", "rest_torque",
    # the windmill (Eq. 11, or a rotor), ratings and lab data
    "windmill_torque", "windmill_power", "load_power", "operating_point", "OperatingPoint",
    "max_head",
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
    "catalogue", "energy", "files", "labdata", "linkage", "playback", "reciprocating", "theory",
    "units", "weather", "wind",
]  # fmt: skip
