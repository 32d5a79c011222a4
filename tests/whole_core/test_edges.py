"""The core's edges, probed: about 1,450 hostile calls, each refused by a ParameterError naming the
argument, its value (cut to a bounded length) and the allowed range, or answered with finite
numbers; and runs bit-identical across threads and processes.

Runs in about 40 s on 2 cores (most of it the process pool's start and one compile check).
"""

from __future__ import annotations

import concurrent.futures
import math
import multiprocessing
import numbers

import numpy as np
import pytest

import windpump
from windpump import Design, ParameterError
from windpump.model.design import MAX_CYLINDERS, UNITS
from windpump.validation import LARGEST, SMALLEST

SEED = Design.seed_example()
LONG_TEXT = "x" * 1_000_000

HOSTILE = {
    "nan": math.nan,
    "inf": math.inf,
    "-inf": -math.inf,
    "zero": 0.0,
    "int zero": 0,
    "minus one": -1.0,
    "int minus one": -1,
    "tiny negative": -1e-300,
    "tiny": 1e-300,
    "huge": 1e300,
    "huge negative": -1e300,
    "past the range": 1e13,
    "huge int": 10**400,
    "huge negative int": -(10**400),
    "numeric text": "3",
    "text": "abc",
    "empty text": "",
    "long text": LONG_TEXT,
    "None": None,
    "list": [1.0],
    "tuple": (1.0,),
    "dict": {},
    "complex": 1 + 0j,
    "bytes": b"1",
    "True": True,
    "False": False,
    "numpy nan": np.float64(math.nan),
    "array": np.array([1.0]),
}
"""Values no careful caller passes: each field and argument gets every one of them."""

MOST_MESSAGE = 600
"""An error message is never longer than this, whatever it was given."""


def is_number(value) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def in_field_range(name: str, value) -> bool:
    """Whether ``value`` lies in the documented range of the Design field ``name`` (seed's other
    fields), from the Design docstring, independently of the code that checks it."""
    if name == "double_acting":
        return isinstance(value, bool)
    if name == "cylinders":
        return is_number(value) and 1 <= value <= MAX_CYLINDERS and value == int(value)
    if not is_number(value) or isinstance(value, float) and not math.isfinite(value):
        return False
    narrower = {"rho_w": (1.0, 2e4), "eta_t": (0.1, 1.0), "Cd_leak": (0.05, 1.0)}
    if name in narrower:  # a liquid's density, a working drive's efficiency, an orifice's Cd
        return narrower[name][0] <= value <= narrower[name][1]
    if name == "d_leak":  # through the piston: narrower than its bore
        return 0.0 <= value < math.sqrt(4.0 * SEED.A / math.pi)
    lowest = 0.0 if name in ("h", "T_0", "m_r", "L_main", "f_main") else 1e-12
    highest = {"V_ref": 150.0, "f_main": 0.2}.get(name, 1e12)
    return lowest <= value <= highest


def assert_clear(error: ParameterError, names: tuple[str, ...]) -> None:
    message = str(error)
    assert error.name in names, message
    assert message.startswith(f"{error.name} = ") and " must be " in message
    assert len(message) <= MOST_MESSAGE, len(message)
    assert "\n" not in message


def assert_finite(answer) -> None:
    """Every number in an answer (scalars, arrays, tuples, dataclass fields) is finite."""
    if answer is None or isinstance(answer, bool | str):
        return
    if isinstance(answer, tuple | list):
        for item in answer:
            assert_finite(item)
    elif isinstance(answer, np.ndarray):
        if answer.dtype.kind == "f":
            assert np.all(np.isfinite(answer))
    elif isinstance(answer, numbers.Real):
        assert math.isfinite(answer), answer


def test_the_range_is_the_one_documented():
    assert (SMALLEST, LARGEST) == (1e-12, 1e12)


@pytest.mark.parametrize("label", HOSTILE)
@pytest.mark.parametrize("field", UNITS)
def test_every_field_refuses_every_hostile_value_by_name(field, label):
    value = HOSTILE[label]
    if field == "T_0" and is_number(value) and value == 1e-300:
        value = 1e-300  # below T_m: allowed
    try:
        design = SEED.replace(**{field: value})
    except ParameterError as error:
        assert not in_field_range(field, value) or field in ("L", "T_0")
        assert_clear(error, (field,))
        if label == "long text":
            assert "(1,000,002 characters)" in str(error) or "1,000,000 characters" in str(error)
        return
    assert in_field_range(field, value), f"{field} = {value!r} was taken"
    assert getattr(design, field) == value
    margin = windpump.stall_margin(design) if design.h > 0 else 0.0
    if design.d_leak > 0:  # the issue: a pump with a leak hole never stalls at low speed
        assert margin == math.inf
    else:
        assert_finite(margin)
    assert_finite(design.I_eff)


@pytest.fixture(scope="module")
def run():
    return windpump.simulate(SEED, 60.0)


X = [10.0, 30.0, 50.0, 70.0, 90.0]
Y = [0.216, 0.504, 0.6, 0.504, 0.216]

CALLS = {
    # name: (call with the value, names an error may give, whether every number is allowed)
    "t_end": (lambda v, r: windpump.simulate(SEED, v), ("t_end",)),
    "theta0": (lambda v, r: windpump.simulate(SEED, 0.5, theta0=v), ("theta0",)),
    "theta_dot0": (
        lambda v, r: windpump.simulate(SEED, 0.5, theta_dot0=v),
        ("theta_dot0", "t_end"),
    ),
    "samples_per_stroke": (
        lambda v, r: windpump.simulate(SEED, 0.5, samples_per_stroke=v),
        ("samples_per_stroke",),
    ),
    "sample_dt": (lambda v, r: windpump.simulate(SEED, 0.5, sample_dt=v), ("sample_dt", "t_end")),
    "wind": (lambda v, r: windpump.simulate(SEED, 0.5, wind=v), ("wind",)),
    "V": (lambda v, r: SEED.in_wind(v), ("V",)),
    "L_over_R": (lambda v, r: SEED.with_ratios(L_over_R=v), ("L_over_R", "L")),
    "R_dagger": (lambda v, r: SEED.with_ratios(R_dagger=v), ("R_dagger", "R1")),
    "steady_flow V": (lambda v, r: windpump.steady_flow(SEED, v), ("V",)),
    "mean_wind": (lambda v, r: windpump.water_per_day(SEED, v), ("mean_wind",)),
    "k": (lambda v, r: windpump.water_per_day(SEED, 5.0, k=v), ("k",)),
    "spinup t": (lambda v, r: windpump.spinup(SEED, v, 3.0), ("t",)),
    "spinup theta_dot0": (lambda v, r: windpump.spinup(SEED, [1.0], v), ("theta_dot0",)),
    "averaged_stall_time": (
        lambda v, r: windpump.averaged_stall_time(SEED, v),
        ("theta_dot0",),
    ),
    "samples_per_segment": (
        lambda v, r: windpump.peak_load_torque(SEED, v),
        ("samples_per_segment",),
    ),
    "points": (lambda v, r: windpump.piston_table(SEED, v), ("points",)),
    "max_frames": (lambda v, r: windpump.playback_frames(r, max_frames=v), ("max_frames",)),
    "max_turn": (lambda v, r: windpump.playback_frames(r, max_turn=v), ("max_turn",)),
    "gusty mean": (lambda v, r: windpump.model.wind.gusty(v, 10.0), ("mean_wind",)),
    "gusty duration": (lambda v, r: windpump.model.wind.gusty(5.0, v), ("duration", "dt")),
    "gusty time_scale": (
        lambda v, r: windpump.model.wind.gusty(5.0, 10.0, time_scale=v),
        ("time_scale",),
    ),
    "gusty dt": (lambda v, r: windpump.model.wind.gusty(5.0, 10.0, dt=v), ("dt",)),
    "seed": (lambda v, r: windpump.model.wind.gusty(5.0, 10.0, seed=v), ("seed",)),
    "revolutions": (lambda v, r: r.intermittency(v), ("revolutions",)),
    "last_revolutions": (lambda v, r: r.last_revolutions(v), ("revolutions",)),
    "at_rest": (lambda v, r: windpump.fit_torque_curve(X, Y, at_rest=v), ("at_rest",)),
    "explore points": (lambda v, r: windpump.explore(SEED, 5.0, points=v), ("points",)),
    "gear_ratios": (lambda v, r: windpump.design_map(SEED, v, [3.0]), ("gear_ratios",)),
    "heads": (lambda v, r: windpump.design_map(SEED, [4.0], v), ("heads",)),
    "sweep t_end": (lambda v, r: windpump.sweep([SEED], v, progress=False), ("t_end",)),
    "omega": (lambda v, r: windpump.windmill_torque(SEED, v), ("omega",)),
    "lever_arm": (lambda v, r: windpump.lever_arm(1.0, v), ("L_over_R",)),
    "startup mass": (lambda v, r: windpump.startup_power(v, 2.0, 10.0, 0.1), ("mass",)),
    "startup grade": (lambda v, r: windpump.startup_power(100.0, 2.0, 10.0, grade=v), ("grade",)),
    "record_water": (lambda v, r: windpump.record_water(SEED, v), ("wind", "record")),
}
"""The arguments of the public functions besides the Design's fields."""

NEVER_VALID = ("nan", "inf", "-inf", "huge int", "huge negative int", "numeric text", "text",
               "empty text", "long text", "None", "dict", "complex", "bytes", "numpy nan")  # fmt: skip
"""Values no argument takes (a list or an array may be a sequence of numbers)..."""

TAKEN = {name: ("None",) for name in ("sample_dt", "wind", "L_over_R", "R_dagger")}
TAKEN["seed"] = ("None", "huge int")  # numpy seeds with any whole number >= 0
"""...but for these: None is the default, and a seed may be any whole number."""


@pytest.mark.filterwarnings("ignore::RuntimeWarning")  # a sweep's failed run warns
@pytest.mark.parametrize("label", HOSTILE)
@pytest.mark.parametrize("argument", CALLS)
def test_every_argument_refuses_every_hostile_value_by_name(argument, label, run):
    call, names = CALLS[argument]
    value = HOSTILE[label]
    try:
        answer = call(value, run)
    except ParameterError as error:
        assert_clear(error, names)
        return
    assert label not in NEVER_VALID or label in TAKEN.get(argument, ()), "taken"
    if isinstance(answer, windpump.Sweep):
        assert not answer.failed or not answer.ok.any()
        return
    assert_finite(answer)


DESIGNS = [
    SEED,
    SEED.replace(cylinders=3, double_acting=True, T_0=0.3, h=6.0),
    SEED.replace(h=9.0),  # stalls from a kick of 3
    SEED.with_ratios(L_over_R=1.2, R_dagger=6.0),
]


def run_case(index: int):
    """A run that tests floating point on its way: a wind record, several cylinders, a stall."""
    design = DESIGNS[index % len(DESIGNS)]
    if index == len(DESIGNS):
        record = windpump.model.wind.gusty(5.0, 600.0, seed=7)
        return windpump.simulate(SEED.replace(T_0=0.3), 600.0, wind=record, sample_dt=1.0)
    return windpump.simulate(design, 300.0, theta_dot0=3.0)


def arrays(result) -> list[np.ndarray]:
    return [result.t, result.theta, result.theta_dot, result.volume, result.flow,
            result.shaft_work, result.stops, result.starts, np.array([result.steps])]  # fmt: skip


def assert_identical(first, second) -> None:
    for a, b in zip(arrays(first), arrays(second), strict=True):
        assert a.shape == b.shape and np.array_equal(a, b)  # exactly: bit for bit


CASES = list(range(len(DESIGNS) + 1))


def test_runs_are_bit_identical_across_threads():
    alone = [run_case(i) for i in CASES]
    with concurrent.futures.ThreadPoolExecutor(4) as pool:
        together = list(pool.map(run_case, CASES * 2))
    for i, result in enumerate(together):
        assert_identical(alone[i % len(CASES)], result)


def test_runs_are_bit_identical_across_spawned_processes():
    alone = [run_case(i) for i in CASES]
    context = multiprocessing.get_context("spawn")
    with concurrent.futures.ProcessPoolExecutor(2, mp_context=context) as pool:
        elsewhere = list(pool.map(run_case, CASES))
        table = windpump.sweep(DESIGNS, 300.0, executor=pool, chunksize=1, progress=False)
    for here, there in zip(alone, elsewhere, strict=True):
        assert_identical(here, there)
    serial = windpump.sweep(DESIGNS, 300.0, progress=False)
    for name, column in serial.columns().items():
        assert np.array_equal(column, table.columns()[name], equal_nan=column.dtype.kind == "f")
