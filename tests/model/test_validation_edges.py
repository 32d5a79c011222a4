"""Accepted input that raised bare exceptions (issue 36): each now a short ``ParameterError`` naming
the argument, its value (cut) and the allowed range, or a right answer. The fit of Eq. (11), the
delivering faces, a wind record's fields, supply's arguments, a progress callback that fails, and
the command line's --workers and messages."""

from __future__ import annotations

import math
import re
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import windpump
from windpump import Design, ParameterError, cli
from windpump.model.wind import WindRecord

SEED = Design.seed_example()
SELF_STARTING = SEED.replace(T_0=0.3)
TWO_DAYS = (3600.0 * np.arange(48), [6.0] * 24 + [0.0] * 24)
SHORT = 300
"""The longest message an error may give [characters]."""

# What a caller may pass by mistake: numbers of every size and kind, text, None, nested lists.
HOSTILE = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(),
    st.integers(min_value=10**300, max_value=10**400),
    st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=30),
    st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=30),
    st.lists(st.integers(), max_size=30),
    st.recursive(
        st.floats() | st.integers() | st.text(max_size=5) | st.none(),
        lambda inner: st.lists(inner, max_size=4),
        max_leaves=10,
    ),
)
BARE = (OverflowError, AttributeError, ZeroDivisionError, TypeError, np.linalg.LinAlgError)


def refused(error: pytest.ExceptionInfo, name: str) -> None:
    """The error names ``name`` and is short."""
    message = str(error.value)
    assert isinstance(error.value, ParameterError), message
    assert error.value.name == name or name in message, message
    assert len(message) < SHORT, message
    assert "np.float64" not in message and "np.int64" not in message, message


def works_or_refuses(call) -> None:
    """``call()`` answers or raises the package's ParameterError; never a bare error."""
    try:
        call()
    except ParameterError as error:
        assert len(str(error)) < SHORT, str(error)
    except BARE as error:  # pragma: no cover - what the test is for
        raise AssertionError(f"a bare {type(error).__name__}: {error}") from error


# fit_torque_curve --------------------------------------------------------------------------------

OMEGA = [10.0, 25.0, 50.0, 75.0, 90.0]
TORQUE = [0.216, 0.45, 0.6, 0.45, 0.216]


@pytest.mark.parametrize(
    "omega, torque, name",
    [
        ([10**400, 25, 50], [0.2, 0.4, 0.2], "omega"),
        ([10, 25, 50], [10**400, 0.4, 0.2], "torque"),
        ([1e300, 2e300, 3e300, 4e300], [1.0, 2.0, 2.0, 1.0], "omega"),
        ([1.0, 2.0, 3.0, 4.0], [1e300, 2e300, 2e300, 1e300], "torque"),
        ("x" * 10_000_000, [0.2, 0.4], "omega"),
        ([10, 25, 50], "y" * 10_000_000, "torque"),
        ([[10, 25], [50]], [0.2, 0.4, 0.2], "omega"),
        (None, [0.2, 0.4, 0.2], "omega"),
        ([10, 25, float("nan")], [0.2, 0.4, 0.2], "omega"),
        ([10, 25, 50], [0.2, float("inf"), 0.2], "torque"),
        ([10, -25, 50], [0.2, 0.4, 0.2], "omega"),
    ],
    ids=[
        "omega-10**400", "torque-10**400", "omega-1e300", "torque-1e300", "omega-10MB",
        "torque-10MB", "ragged", "None", "omega-nan", "torque-inf", "negative-speed",
    ],
)  # fmt: skip
def test_the_fit_refuses_what_it_cannot_fit_naming_the_argument(omega, torque, name):
    with pytest.raises(ParameterError) as error:
        windpump.fit_torque_curve(omega, torque)
    refused(error, name)


@settings(max_examples=40)
@given(
    st.floats(1e-9, 1e9),
    st.floats(1e-9, 1e9),
    st.booleans(),
)
def test_the_fit_is_the_same_at_any_scale_of_speed_and_torque(speed, torque, at_rest):
    """Tiny or huge units fit as well as the lab's: Eq. (11) scales (no LinAlgError, no
    underflow of omega^2)."""
    omega = np.array([0.0, 20.0, 40.0, 60.0, 80.0])
    measured = np.array([0.21, 0.45, 0.59, 0.58, 0.46])  # with noise: residuals are not round-off
    base = windpump.fit_torque_curve(omega, measured, at_rest=at_rest)
    scaled = windpump.fit_torque_curve(omega * speed, measured * torque, at_rest=at_rest)
    assert scaled.omega_m == pytest.approx(base.omega_m * speed, rel=1e-9)
    assert scaled.T_m == pytest.approx(base.T_m * torque, rel=1e-9)
    assert scaled.T_0 == pytest.approx(base.T_0 * torque, rel=1e-9, abs=1e-300)
    assert scaled.rms_residual == pytest.approx(base.rms_residual * torque, rel=1e-6, abs=1e-300)
    for key, value in base.standard_errors.items():
        unit = speed if key == "omega_m" else torque
        assert scaled.standard_errors[key] == pytest.approx(value * unit, rel=1e-6, abs=1e-300)


@settings(max_examples=60)
@given(HOSTILE, HOSTILE, HOSTILE)
def test_the_fit_works_or_refuses_anything(omega, torque, at_rest):
    works_or_refuses(lambda: windpump.fit_torque_curve(omega, torque, at_rest=at_rest))
    works_or_refuses(lambda: windpump.fit_torque_curve(omega, TORQUE))
    works_or_refuses(lambda: windpump.fit_torque_curve(OMEGA, torque))


# delivering_faces --------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "segment, cylinders, double_acting, name",
    [
        ([0, "x"], 1, False, "segment"),
        ([0.5], 1, False, "segment"),
        ([10**400], 2, False, "segment"),
        ([float("nan")], 2, False, "segment"),
        (None, 2, False, "segment"),
        ([0, 1], 0, False, "cylinders"),
        ([0, 1], -1, False, "cylinders"),
        ([0, 1], 2.5, False, "cylinders"),
        ([0, 1], 10**400, False, "cylinders"),
        ([0, 1], "2", False, "cylinders"),
        ([0, 1], 2, None, "double_acting"),
        ([0, 1], 2, "yes", "double_acting"),
    ],
)
def test_delivering_faces_checks_its_arguments(segment, cylinders, double_acting, name):
    with pytest.raises(ParameterError) as error:
        windpump.delivering_faces(segment, cylinders, double_acting)
    refused(error, name)


def test_delivering_faces_takes_whole_numbers_of_any_integer_kind():
    expected = windpump.delivering_faces([0, 1, 2, 3], 2, True)
    assert windpump.delivering_faces(np.array([0.0, 1.0, 2.0, 3.0]), 2, True).tolist() == (
        expected.tolist()
    )
    assert windpump.delivering_faces(
        np.arange(4, dtype=np.int8), np.int64(2), np.True_
    ).tolist() == (expected.tolist())


@settings(max_examples=60)
@given(HOSTILE, HOSTILE, HOSTILE)
def test_delivering_faces_works_or_refuses_anything(segment, cylinders, double_acting):
    works_or_refuses(lambda: windpump.delivering_faces(segment, cylinders, double_acting))
    works_or_refuses(lambda: windpump.delivering_faces(segment, 2, True))
    works_or_refuses(lambda: windpump.delivering_faces([0, 1], cylinders, False))


# WindRecord --------------------------------------------------------------------------------------

T = np.array([0.0, 3600.0, 7200.0])
V = np.array([4.0, 5.0, 6.0])


@pytest.mark.parametrize(
    "fields, name",
    [
        ({"month": [0, 1, 1]}, "month"),
        ({"month": [1, 13, 12]}, "month"),
        ({"month": [1, float("nan"), 1]}, "month"),
        ({"month": [1, 1.5, 2]}, "month"),
        ({"month": [1, 2]}, "month"),
        ({"month": ["Jan", "Feb", "Mar"]}, "month"),
        ({"month": [1, 10**400, 1]}, "month"),
        ({"t": [0.0, 7200.0, 3600.0]}, "t"),
        ({"t": [0.0, 0.0, 3600.0]}, "t"),
        ({"t": [0.0, float("nan"), 7200.0]}, "t"),
        ({"t": [0.0, 3600.0, 10**400]}, "t"),
        ({"t": "x" * 10_000_000}, "t"),
        ({"t": [0.0, 3600.0]}, "V"),
        ({"V": [4.0, -1.0, 6.0]}, "V"),
        ({"V": [4.0, float("nan"), 6.0]}, "V"),
        ({"V": [4.0, float("inf"), 6.0]}, "V"),
        ({"V": [4.0, 1000.0, 6.0]}, "V"),
        ({"V": None}, "V"),
        ({"V": [[4.0], [5.0], [6.0]]}, "V"),
    ],
)
def test_a_wind_record_refuses_bad_times_speeds_and_months(fields, name):
    given_fields = {"t": T, "V": V} | fields
    with pytest.raises(ParameterError) as error:
        WindRecord(**given_fields)
    refused(error, name)


def test_a_wind_record_keeps_good_fields_as_read_only_arrays():
    record = WindRecord([0, 3600, 7200], [4, 5, 6], 10.0, "here", month=[12.0, 12.0, 1.0])
    assert record.t.dtype == float and record.V.dtype == float and record.month.dtype.kind == "i"
    assert record.month.tolist() == [12, 12, 1]
    assert not (
        record.t.flags.writeable or record.V.flags.writeable or record.month.flags.writeable
    )
    t, V = record  # still the pair
    assert V.tolist() == [4.0, 5.0, 6.0]


def test_a_wind_record_does_not_share_a_callers_array():
    t = np.array([0.0, 3600.0])
    record = WindRecord(t, np.array([4.0, 5.0]))
    t[1] = -1.0  # the caller's array changes; the record's does not
    assert record.t.tolist() == [0.0, 3600.0]
    assert t.flags.writeable


@settings(max_examples=60)
@given(HOSTILE, HOSTILE, HOSTILE)
def test_a_wind_record_works_or_refuses_anything(t, V, month):
    works_or_refuses(lambda: WindRecord(t, V))
    works_or_refuses(lambda: WindRecord(T, V, month=month))
    works_or_refuses(lambda: WindRecord(T, V, height=t, name=V))


# supply's arguments ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "options, name",
    [
        ({"profile": [10**400]}, "profile"),
        ({"profile": [10**400] * 24}, "profile"),
        ({"profile": [1.0] * 23}, "profile"),
        ({"profile": [1.0] * 23 + [float("nan")]}, "profile"),
        ({"profile": [1.0] * 23 + [-1.0]}, "profile"),
        ({"profile": [0.0] * 24}, "profile"),
        ({"profile": "x" * 10_000_000}, "profile"),
        ({"profile": [[1.0] * 24]}, "profile"),
        ({"executor": "x"}, "executor"),
        ({"executor": "x", "method": "full"}, "executor"),
        ({"executor": 4, "method": "full"}, "executor"),
        ({"progress": "x", "method": "full"}, "progress"),
        ({"chunk_days": 0, "method": "full"}, "chunk_days"),
        ({"seed": -1, "method": "full"}, "seed"),
        ({"seed": 10**400, "method": "full"}, "seed"),
        ({"turbulence": 10**400, "method": "full"}, "turbulence"),
    ],
)
def test_supply_refuses_bad_arguments_naming_them(options, name):
    with pytest.raises(ParameterError) as error:
        windpump.supply(SELF_STARTING, TWO_DAYS, 2.0, 1.0, **options)
    refused(error, name)


def test_a_profile_of_huge_weights_spreads_the_demand_as_its_proportions():
    """1e308 x 24 sums past the largest double: the weights' proportions are still the demand's."""
    flat = windpump.supply(SELF_STARTING, TWO_DAYS, 2.0, 1.0)
    huge = windpump.supply(SELF_STARTING, TWO_DAYS, 2.0, 1.0, profile=[1e308] * 24)
    assert huge.demand.tolist() == pytest.approx(flat.demand.tolist(), rel=1e-12)
    assert huge.demand.sum() == pytest.approx(4.0)


@settings(max_examples=40)
@given(HOSTILE)
def test_supply_works_or_refuses_any_argument(value):
    for options in (
        {"profile": value},
        {"executor": value},
        {"turbulence": value},
        {"seed": value},
        {"chunk_days": value},
        {"progress": value},
        {"restart": value},
        {"method": value if value != "full" else None},
    ):
        works_or_refuses(lambda o=options: windpump.supply(SELF_STARTING, TWO_DAYS, 2.0, 1.0, **o))
    works_or_refuses(lambda: windpump.supply(SELF_STARTING, TWO_DAYS, value, 1.0))
    works_or_refuses(lambda: windpump.supply(SELF_STARTING, TWO_DAYS, 2.0, value))


@pytest.mark.parametrize("executor", ["x", 4])
def test_sweep_names_an_executor_it_cannot_use(executor):
    with pytest.raises(ParameterError) as error:
        windpump.sweep([SEED], 10.0, executor=executor)
    refused(error, "executor")
    assert "submit" in str(error.value)


# A progress callback that fails ------------------------------------------------------------------


def failing(after: int):
    """A progress callback that raises from its ``after``-th call on; it counts its calls."""
    calls = []

    def report(done: int, total: int) -> None:
        calls.append((done, total))
        if len(calls) >= after:
            raise RuntimeError("the progress bar's window was closed")

    report.calls = calls  # type: ignore[attr-defined]
    return report


def test_a_sweep_whose_callback_raises_returns_every_row_and_warns_once():
    designs = [SEED.replace(h=h) for h in (1.0, 2.0, 3.0, 4.0)]
    expected = windpump.sweep(designs, 30.0, chunksize=1, progress=False)
    report = failing(after=1)
    with pytest.warns(RuntimeWarning, match="progress") as caught:
        table = windpump.sweep(designs, 30.0, chunksize=1, progress=report)
    assert len([w for w in caught if "progress" in str(w.message)]) == 1
    assert "the progress bar's window was closed" in str(caught[0].message)
    assert report.calls == [(1, 4)]  # called no more once it failed
    assert len(table) == 4 and not table.failed
    assert table.volume.tolist() == expected.volume.tolist()


def test_a_design_map_whose_callback_raises_still_maps():
    ratios, heads = np.array([3.0, 4.0]), np.array([1.0, 3.0])
    expected = windpump.design_map(SEED, ratios, heads, numeric=True, progress=False)
    with pytest.warns(RuntimeWarning, match="progress"):
        found = windpump.design_map(SEED, ratios, heads, numeric=True, progress=failing(after=1))
    np.testing.assert_array_equal(found.alpha_plus, expected.alpha_plus)


def test_a_full_year_whose_callback_raises_still_runs():
    wind = (3600.0 * np.arange(4), [6.0] * 4)
    with pytest.warns(RuntimeWarning, match="progress"):
        year = windpump.supply(
            SELF_STARTING, wind, 2.0, 1.0, method="full", chunk_days=1, progress=failing(after=1)
        )
    assert year.hours == 4 and year.method == "full"


def test_a_callback_that_works_is_called_as_before():
    calls = []
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        windpump.sweep([SEED, SEED], 10.0, chunksize=1, progress=lambda *a: calls.append(a))
    assert calls == [(1, 2), (2, 2)]


@pytest.mark.parametrize("progress", ["x", 5, [1]])
def test_sweep_refuses_a_progress_that_is_neither_a_flag_nor_a_callable(progress):
    with pytest.raises(ParameterError) as error:
        windpump.sweep([SEED], 10.0, progress=progress)
    refused(error, "progress")


# The command line --------------------------------------------------------------------------------


@pytest.mark.parametrize("workers", ["0", "-1", "1.5", "many", "100000"])
@pytest.mark.parametrize(
    "command",
    [["sweep", "designs.csv"], ["supply", "--site", "greensboro", "--demand", "2", "--full"]],
    ids=["sweep", "supply"],
)
def test_workers_out_of_range_is_a_usage_error(capsys, command, workers):
    with pytest.raises(SystemExit) as exit_:
        cli.main([*command, "--workers", workers])
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert "--workers" in err and f"'{workers}'" in err and "from 1 to" in err, err


def test_messages_show_numpy_numbers_as_plain_numbers():
    error = ParameterError("t_end", np.float64("nan"), "a finite real number", "s")
    assert str(error) == "t_end = nan s is not allowed: t_end must be a finite real number"
    assert windpump.errors.shown(np.int64(3)) == "3"
    assert windpump.errors.shown([np.float64(1.5), np.float32(2.0)]) == "[1.5, 2.0]"
    assert cli.one_line(ValueError("V[3] = np.float64(nan) m/s")) == "V[3] = nan m/s"
    assert cli.one_line(ValueError("t = np.int64(7), ok = np.True_")) == "t = 7, ok = True"


@pytest.mark.parametrize(
    "wind, words",
    [
        (([0.0, 1.0], [math.nan, 1.0]), "speeds[0] = nan"),
        (([0.0, 0.0], [1.0, 1.0]), "t[1] = 0.0 s after t[0] = 0.0 s"),
        (([0.0, 1.0], [1.0, 200.0]), "V[1] = 200.0 m/s"),
        (([0.0, 3600.0, 10800.0], [1.0, 1.0, 1.0]), "after t[1] = 3600.0 s"),
    ],
)
def test_wind_messages_show_plain_numbers(wind, words):
    with pytest.raises(ParameterError) as error:
        windpump.supply(SELF_STARTING, wind, 2.0, 1.0)
    assert words in str(error.value)
    refused(error, "record")


# Refusals that take a number, each given a refused value (< 0, or NaN) as a numpy scalar of every
# kind: the message writes the number as Python would (-3, -2.5, nan), never as numpy 2's repr
# (np.float64(-2.5), np.int64(-3)), wherever it sits (alone, in a list, in a dict: issue 37).
NUMPY_KINDS = [np.float64, np.float32, np.float16, np.int64, np.int32, np.int16, np.int8]
HOURS = 3600.0 * np.arange(48)
RECORD = WindRecord(HOURS, np.full(48, 5.0))
LOOPS = windpump.linkage.watt_six_bar_loops(1.0, 3.0, 2.5, 3.0, 1.5, 2.5, 2.0, 2.5, beta=0.4)
TAKE_A_NUMBER = {
    **{
        f"Design.{field}": lambda x, field=field: SEED.replace(**{field: x})
        for field in ("h", "R", "L", "T_m", "omega_m", "I0", "I1", "T_0", "rho_w", "V_ref")
    },
    "WindRecord height": lambda x: WindRecord(HOURS, np.full(48, 5.0), x),
    "WindRecord t": lambda x: WindRecord([*HOURS[:-1], x], [5.0] * 48),
    "WindRecord V": lambda x: WindRecord(HOURS, [*[5.0] * 47, x]),
    "WindRecord month": lambda x: WindRecord(HOURS, np.full(48, 5.0), 10.0, "", [1] * 47 + [x]),
    "at_height": lambda x: RECORD.at_height(x),
    "simulate's wind": lambda x: windpump.model.wind.as_record((HOURS, [*[5.0] * 47, x]), 2.0),
    "supply demand": lambda x: windpump.supply(SELF_STARTING, RECORD, x, 1.0),
    "supply tank": lambda x: windpump.supply(SELF_STARTING, RECORD, 1.0, x),
    "supply profile": lambda x: windpump.supply(SELF_STARTING, RECORD, 1.0, 1.0, profile=[x] * 24),
    "supply's record": lambda x: windpump.supply(SELF_STARTING, (HOURS, [*[5.0] * 47, x]), 1, 1),
    "supply turbulence": lambda x: windpump.supply(
        SELF_STARTING, RECORD, 1.0, 1.0, method="full", turbulence=x
    ),
    "tank_for lolp": lambda x: windpump.tank_for(SELF_STARTING, RECORD, 1.0, x),
    "supply_map tanks": lambda x: windpump.supply_map(SELF_STARTING, RECORD, 1.0, [1.0], [x]),
    "supply_map ratios": lambda x: windpump.supply_map(SELF_STARTING, RECORD, 1.0, [x], [1.0]),
    "water_per_day": lambda x: windpump.water_per_day(SELF_STARTING, x),
    "steady_flow": lambda x: windpump.steady_flow(SELF_STARTING, [1.0, x]),
    "record_water": lambda x: windpump.record_water(SELF_STARTING, (HOURS, [*[5.0] * 47, x])),
    "run_in_wind kick": lambda x: windpump.run_in_wind(SELF_STARTING, RECORD, kick=x),
    "gusty": lambda x: windpump.model.wind.gusty(x, 3600.0),
    "linkage known": lambda x: windpump.linkage.assembly_guess(LOOPS, {"theta9": x}, (1, -1)),
    "linkage guess": lambda x: windpump.linkage.solve_loop(LOOPS[0], {"theta1": 1.0}, {"a": x}),
}


@pytest.mark.parametrize("kind", NUMPY_KINDS, ids=lambda kind: kind.__name__)
@pytest.mark.parametrize("refusal", TAKE_A_NUMBER)
def test_a_refused_numpy_number_is_written_as_a_number(refusal, kind):
    for value in (-3, -2.5, math.nan) if np.issubdtype(kind, np.floating) else (-3,):
        x = kind(value)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            with pytest.raises(ParameterError) as error:
                TAKE_A_NUMBER[refusal](x)
        message = str(error.value)
        assert not re.search(r"np\.\w+\(|numpy", message), message
        assert len(message) < SHORT, message


@pytest.mark.parametrize("kick", [1e12 * (1 + 1e-15), 1e13, 1e300, 1e308])
def test_a_kick_past_1e12_rad_s_is_refused_by_its_name_at_once(kick):
    """simulate's theta_dot0 and run_in_wind's kick are at most LARGEST_KICK (1e12 rad/s): a kick
    of 1e300 made the sample bound inf and the refusal blamed t_end ("t_end must be <= 0 s"), and
    run_in_wind ran 2e7 steps (40 s) to blame the design."""
    seed = windpump.Design.seed_example()
    with pytest.raises(windpump.ParameterError) as refused:
        windpump.simulate(seed, 10.0, theta_dot0=kick)
    assert refused.value.name == "theta_dot0" and "1e+12" in str(refused.value)
    with pytest.raises(windpump.ParameterError) as refused:
        windpump.run_in_wind(seed, ([0.0, 60.0], [5.0, 5.0]), kick=kick)
    assert refused.value.name == "kick" and "1e+12 rad/s" in str(refused.value)


@pytest.mark.parametrize(
    ("t_end", "options", "name"),
    [
        (1e308, {}, "t_end"),
        (10.0, {"sample_dt": 5e-324}, "sample_dt"),
        (1e308, {"sample_dt": 1.0}, "sample_dt"),
    ],
)
def test_too_many_samples_names_the_argument_and_a_finite_bound(t_end, options, name):
    """A run that would make more than MAX_SAMPLES samples names t_end, or sample_dt when one is
    given, with a finite bound (t_end 1e308 said "t_end must be <= nan s")."""
    from windpump.run.dynamics import MAX_SAMPLES

    seed = windpump.Design.seed_example()
    with pytest.raises(windpump.ParameterError) as refused:
        windpump.simulate(seed, t_end, **options)
    assert refused.value.name == name
    number = float(re.search(r"must be [<>]= ([0-9.e+-]+) s", str(refused.value)).group(1))
    assert math.isfinite(number) and number > 0.0
    if name == "t_end":  # the longest run: MAX_SAMPLES samples at the fastest crank speed
        fastest = max(3.0, seed.runaway_speed / seed.R_dagger)
        assert number == pytest.approx((MAX_SAMPLES - 3) * (math.pi / 16) / fastest, rel=1e-5)
    else:
        assert number == pytest.approx(t_end / (MAX_SAMPLES - 3), rel=1e-5)


SCALAR_FIELDS = {
    "Design.h": lambda x: SEED.replace(h=x),
    "Design.T_m": lambda x: SEED.replace(T_m=x),
    "simulate t_end": lambda x: windpump.simulate(SEED, x),
    "simulate theta0": lambda x: windpump.simulate(SEED, 1.0, theta0=x),
    "water_per_day": lambda x: windpump.water_per_day(SELF_STARTING, x),
    "supply demand": lambda x: windpump.supply(SELF_STARTING, RECORD, x, 1.0),
    "at_height": lambda x: RECORD.at_height(x),
}


@pytest.mark.parametrize("dtype", [np.float32, np.float64, np.int64])
@pytest.mark.parametrize("refusal", SCALAR_FIELDS)
def test_an_array_where_a_number_belongs_is_written_as_numbers(refusal, dtype):
    """A message showed numpy's repr of an array ("array([1.5], dtype=float32)") given for a
    number: now its numbers, plainly."""
    with pytest.raises(ParameterError) as error:
        SCALAR_FIELDS[refusal](np.array([1.5, 2.0]).astype(dtype))
    message = str(error.value)
    assert not re.search(r"array\(|dtype|np\.\w+\(", message), message
    assert "an array [1" in message, message
