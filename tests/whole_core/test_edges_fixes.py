"""The failures the edge probe found (issue 21), each now a clear error naming the argument or a
right answer: reads without bounds, a study that one bad row stopped, overflows and recursion,
silent NaN and inf, misleading or unbounded messages, and the command line's tracebacks."""

from __future__ import annotations

import json
import math
import os
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import windpump
from windpump import (
    Design,
    DesignFileError,
    LabDataError,
    ParameterError,
    StallError,
    cli,
    dynamics,
    maps,
)

SEED = Design.seed_example()


def command(capsys, *args) -> tuple[int, str, str]:
    """``windpump ARGS`` in this process: its exit code, stdout and stderr."""
    code = cli.main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


def assert_one_line_error(code: int, err: str, *words: str) -> None:
    assert code == 1
    assert err.count("\n") == 1 and err.endswith("\n") and "Traceback" not in err, err
    assert all(word in err for word in words), err


# Reads without bounds --------------------------------------------------------------------------


@pytest.mark.parametrize("reader", [windpump.read_torque_csv, windpump.model.wind.read_csv])
def test_a_device_or_a_pipe_is_refused_before_it_is_read(reader, tmp_path):
    with pytest.raises(LabDataError, match="'/dev/zero' is not a regular file"):
        reader("/dev/zero")  # its size reads as 0: it was read until 8.8 GB
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    with pytest.raises(LabDataError, match="is not a regular file"):
        reader(fifo)  # without a writer: opening it must not wait


def test_a_missing_file_is_named_not_read_as_data():
    with pytest.raises(LabDataError, match="there is no file 'lab data.csv'") as caught:
        windpump.read_torque_csv("lab data.csv")
    assert "measurement" not in str(caught.value)


def test_a_file_is_read_to_the_limit_and_one_byte_no_further(tmp_path, monkeypatch):
    path = tmp_path / "lab.csv"
    path.write_bytes(b"10,0.2\n50,0.6\n90,0.2\n")
    asked = []
    real_read = windpump.readers.labdata.os.fstat

    def fstat_claiming_empty(descriptor):  # a file whose size says less than it holds
        status = real_read(descriptor)
        asked.append(status.st_size)
        return os.stat_result((status.st_mode, *status[1:6], 0, *status[7:]))

    monkeypatch.setattr(windpump.readers.labdata.os, "fstat", fstat_claiming_empty)
    with pytest.raises(LabDataError, match="more than 10 bytes"):
        windpump.read_torque_csv(path, max_bytes=10)
    assert asked == [21]


def test_the_command_line_refuses_a_device_as_a_design(capsys):
    code, _, err = command(capsys, "simulate", "--design", "/dev/zero")
    assert_one_line_error(code, err, "/dev/zero", "not a regular file")


# A study keeps its good rows --------------------------------------------------------------------


def test_a_sweep_keeps_every_good_row_and_lists_each_failed_one(monkeypatch):
    monkeypatch.setattr(dynamics, "MAX_STEPS", 200_000)  # the stiff rotor fails in 0.1 s, not 10
    stiff = SEED.replace(I0=1e-9, I1=1e-9)
    designs = [SEED.replace(h=h) for h in np.linspace(0.5, 6.0, 80)]
    designs.insert(40, stiff)
    with pytest.warns(RuntimeWarning, match=r"1 of 81 runs failed .*designs\[40\]: design = "):
        table = windpump.sweep(designs, 20.0, progress=False)
    assert list(table.failed) == [40] and "too stiff" in table.failed[40]
    assert table.ok.sum() == 80 and not table.ok[40]
    assert np.isnan(table.volume[40]) and not table.stalled[40] and table.steps[40] == 0
    good = table.without_failures()
    assert len(good) == 80 and good.designs == tuple(d for d in designs if d is not stiff)
    alone = windpump.simulate(designs[41], 20.0)
    assert good.volume[40] == alone.volume[-1] and good.steps[40] == alone.steps


def test_a_per_design_t_end_fails_its_own_row_only():
    with pytest.warns(RuntimeWarning, match="2 of 3 runs failed"):
        table = windpump.sweep([SEED] * 3, [20.0, -1.0, 1e9], progress=False)
    assert list(table.failed) == [1, 2]
    assert table.failed[1].startswith("t_end = -1.0 s is not allowed")
    assert "samples" in table.failed[2]
    assert table.volume[0] == windpump.simulate(SEED, 20.0).volume[-1]
    with pytest.raises(ParameterError, match="^t_end = -1.0 s"):
        windpump.sweep([SEED] * 3, -1.0)  # one value for every run: refused at once


def test_the_sweep_command_writes_the_good_rows_and_a_line_per_failed_one(tmp_path, capsys):
    table = tmp_path / "designs.csv"
    table.write_text("h,t_end\n1,20\n2,1e9\n3,20\n")
    out = tmp_path / "out.csv"
    code, _, err = command(capsys, "sweep", str(table), "--csv", str(out))
    assert code == 1 and err.count("\n") == 1 and "design 2 of" in err and "t_end" in err
    rows = out.read_text().splitlines()
    assert len(rows) == 3 and rows[1].startswith("0.03,") and ",1.0," in rows[1]


# Overflow, recursion, index and zero-division errors --------------------------------------------


def test_integers_beyond_double_precision_are_refused_by_name(tmp_path, capsys):
    with pytest.raises(ParameterError, match="^h = an integer of 401 digits m is not allowed"):
        Design(**(SEED.as_dict() | {"h": 10**400}))
    with pytest.raises(ParameterError, match="^t_end = an integer of 401 digits"):
        windpump.simulate(SEED, 10**400)
    text = SEED.to_json().replace('"h": 3.0', '"h": 1' + "0" * 400)
    with pytest.raises(ParameterError, match="^h = an integer of 401 digits"):
        Design.from_json(text)
    with pytest.raises(
        DesignFileError, match="not a design file: a number in it has more than 4,300 digits"
    ):
        Design.from_json(SEED.to_json().replace('"h": 3.0', '"h": 1' + "0" * 5000))
    code, _, err = command(capsys, "simulate", "--set", "cylinders=inf")
    assert_one_line_error(code, err, "cylinders = inf is not allowed")
    for column in ("cylinders", "h"):
        sheet = tmp_path / f"{column}.csv"
        sheet.write_text(f"{column}\n1e400\n")
        code, _, err = command(capsys, "sweep", str(sheet))
        assert_one_line_error(code, err, "line 2", f"{column} = inf")


def test_json_nested_too_deeply_is_not_a_design_file(short_tmp_path, capsys):
    deep = "[" * 100_000 + "]" * 100_000
    with pytest.raises(DesignFileError, match="nested too deeply"):
        Design.from_json(deep)
    path = short_tmp_path / "deep.json"
    path.write_text(deep)
    code, _, err = command(capsys, "sweep", str(path))
    assert_one_line_error(code, err, "deep.json: not a design file: its JSON is nested too deeply")


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda run: run.intermittency(0.5), "revolutions"),
        (lambda run: run.last_revolutions(0.5), "revolutions"),
        (lambda run: windpump.peak_load_torque(SEED, 0), "samples_per_segment"),
        (lambda run: windpump.playback_frames(run, max_frames=10**12), "max_frames"),
        (lambda run: windpump.piston_table(SEED, 1e10), "points"),
        (lambda run: windpump.model.wind.gusty(5.0, 10.0, seed=-1), "seed"),
        (lambda run: windpump.model.wind.gusty(5.0, 10.0, seed=1.5), "seed"),
        (lambda run: windpump.spinup(SEED, ["a"], 3.0), "t"),
        (lambda run: windpump.spinup(SEED, [1.0, math.nan], 3.0), "t"),
        (lambda run: windpump.spinup(SEED, -1.0, 3.0), "t"),
    ],
)
def test_what_raised_index_zero_division_or_memory_errors_is_refused_by_name(call, name):
    run = windpump.simulate(SEED, 60.0)
    with pytest.raises(ParameterError) as caught:
        call(run)
    assert caught.value.name == name and str(caught.value).startswith(f"{name} = ")


def test_a_large_but_bounded_frame_count_still_works():
    run = windpump.simulate(SEED, 60.0)
    assert len(windpump.playback_frames(run, max_frames=1).t) == 2  # as before: at least two
    assert len(windpump.piston_table(SEED, 1_000_000)[0]) == 1_000_000


# Silent answers -------------------------------------------------------------------------------


def test_winds_beyond_any_record_are_refused_not_answered_with_nan_or_inf():
    with pytest.raises(ParameterError, match="^mean_wind = 1e\\+300 m/s .* from 0.001 to 150"):
        windpump.water_per_day(SEED, 1e300)
    with pytest.raises(ParameterError, match="^V = 1e\\+200 m/s .* from 0 to 150"):
        windpump.steady_flow(SEED, [5.0, 1e200])
    low, high = windpump.water_per_day(SEED, 150.0)  # the fastest mean still answers
    assert low == 0.0 and math.isfinite(high) and high > 0.0


def test_at_rest_takes_a_bool_only():
    x, y = [10, 30, 50, 70, 90], [0.216, 0.504, 0.6, 0.504, 0.216]
    with pytest.raises(ParameterError, match="^at_rest = 'no' is not allowed"):
        windpump.fit_torque_curve(x, y, at_rest="no")  # 'no' is truthy: it fitted T_0
    assert windpump.fit_torque_curve(x, y, at_rest=np.bool_(False)).T_0 == 0.0


def test_a_numeric_map_refuses_a_rotor_too_stiff_to_integrate(monkeypatch):
    monkeypatch.setattr(dynamics, "MAX_STEPS", 2_000)  # the seed's runs need more than that
    with pytest.raises(ParameterError, match="^design = 'I_eff = 27.1 kg m\\^2 at gear ratio 4"):
        windpump.design_map(SEED, [4.0], [3.0], numeric=True, progress=False)
    with pytest.raises(ParameterError, match="^t_end"):
        windpump.simulate(SEED, 600.0)  # as a full run of it is refused


def test_a_design_at_1e100_is_outside_the_range():
    fields = dict.fromkeys(
        ["R0", "R1", "R", "A", "I0", "I1", "T_m", "omega_m", "h", "rho_w"], 1e100
    )
    with pytest.raises(ParameterError, match="from 1e-12 to 1e\\+12"):
        Design(**fields, L=2e100, g=1e100, V_ref=1e100)


EDGES = [1e-12, 1e12]
FIELDS = ["R0", "R1", "R", "A", "I0", "I1", "T_m", "omega_m", "h", "rho_w", "g", "V_ref"]


def field_values():
    return st.one_of(st.sampled_from(EDGES), st.floats(-12.0, 12.0).map(lambda e: 10.0**e))


@settings(deadline=None, max_examples=150, suppress_health_check=[HealthCheck.too_slow])
@given(
    st.fixed_dictionaries({name: field_values() for name in FIELDS}),
    st.sampled_from([1.5, 1e6, math.inf]),  # L/R (inf: L at its largest)
    st.sampled_from([0.0, 5e-324, 1e-20, 0.5, 0.999]),  # T_0 / T_m
    st.integers(1, 6),
    st.booleans(),
)
def test_every_figure_is_finite_anywhere_in_the_range(fields, rod, at_rest, cylinders, double):
    fields["V_ref"] = min(fields["V_ref"], 150.0)
    fields["rho_w"] = min(max(fields["rho_w"], 1.0), 2e4)  # a liquid's density
    fields["R"] = min(max(fields["R"], 1e-4), 1e3)  # a crank, a bore and a planet's gravity
    fields["A"] = min(max(fields["A"], 1e-8), 1e2)  # any pump could have (issue 36)
    fields["g"] = min(max(fields["g"], 0.1), 100.0)
    fields["L"] = min(fields["R"] * rod, 1e3)
    fields["T_0"] = fields["T_m"] * at_rest
    try:
        design = Design(**fields, cylinders=cylinders, double_acting=double)
    except ParameterError as error:  # L <= R when R is at the top of the range
        assert error.name == "L"
        return
    margin = windpump.stall_margin(design)
    V_stop, V_start = windpump.wind_thresholds(design)
    assert margin > 0.0 and V_stop >= 0.0 and (V_start is None or V_start >= 0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # scipy's quadrature may warn of its own accuracy
        answers = [*windpump.water_per_day(design, 5.0), *windpump.water_per_day(design, 150.0, 20)]
        answers += [*windpump.water_per_day(design, 0.01, 0.5)]
    answers += list(windpump.steady_flow(design, [0.0, 1e-3, 5.0, 150.0]))
    answers += [windpump.peak_load_torque(design), design.I_eff, design.Tm_dagger]
    answers += list(windpump.spinup(design, [0.0, 1.0, 1e6], 3.0))
    try:
        answers += [*windpump.steady_speeds(design), windpump.time_constant(design)]
    except StallError:
        assert margin <= 1.0
    assert all(math.isfinite(x) for x in answers), answers


# Messages -------------------------------------------------------------------------------------


def test_a_record_too_long_to_integrate_is_refused_up_front_with_the_reason(monkeypatch):
    record = windpump.model.wind.gusty(5.0, 20_000.0, dt=0.1, seed=1)  # 200,001 samples
    done = windpump.simulate(SEED, 20_000.0, wind=record, sample_dt=10.0)
    estimate = dynamics.estimated_steps(SEED, 20_000.0, windpump.model.wind.as_record(record, 2e4))
    assert 0.5 * done.steps <= estimate <= done.steps  # the work, about (a lower estimate)
    monkeypatch.setattr(dynamics, "MAX_STEPS", done.steps // 4)
    with pytest.raises(ParameterError) as caught:
        windpump.simulate(SEED, 20_000.0, wind=record, sample_dt=10.0)
    message = str(caught.value)
    assert caught.value.name == "wind" and "200,001 wind samples" in message
    assert "where the wind bends" in message and "stiff" not in message


def test_in_wind_names_the_wind_speed_and_its_range():
    with pytest.raises(ParameterError) as caught:
        SEED.in_wind(1e-200)
    assert caught.value.name == "V" and "from 6.45497e-06 to 150 m/s" in str(caught.value)
    lowest, highest = SEED.wind_range()
    assert SEED.in_wind(lowest).T_m >= 1e-12 and SEED.in_wind(highest).V_ref == 150.0
    assert math.isclose(lowest, 5.0 * math.sqrt(1e-12 / 0.6), rel_tol=1e-12)  # T_m's floor


def test_messages_echo_inputs_within_bounds():
    document = json.loads(SEED.to_json())
    document["fields"]["h"] = "x" * 20_000_000
    with pytest.raises(ParameterError) as caught:
        Design.from_json(json.dumps(document))
    assert len(str(caught.value)) < 300 and "(20,000,000 characters)" in str(caught.value)
    document["fields"] = {"y" * 1_000_000: 1.0}
    with pytest.raises(DesignFileError) as unknown:
        Design.from_json(json.dumps(document))
    assert len(str(unknown.value)) < 400
    header = "speed," + "torque" * 100_000
    with pytest.raises(LabDataError) as lab:
        windpump.read_torque_csv(f"torque,{header}\n1,2\n")
    assert len(str(lab.value)) < 400


# The command line -----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["simulate", "--set", "cylinders=inf"], ["cylinders"]),
        (["simulate", "--set", "h=" + "9" * 400], ["h = inf m", "finite"]),
        (["simulate", "--t-end", "inf"], ["t_end = inf"]),
        (["simulate", "--set", "x" * 100_000 + "=1"], ["--set", "characters"]),
        (["map", "--heads", "0:inf:5"], ["--heads", "finite"]),
        (["map", "--heads", "0:3:1000000000000"], ["--heads", "N from 1 to"]),
        (["map", "--gear-ratios", "nan:4:5"], ["--gear-ratios", "finite"]),
        (["simulate", "--design", "/no/such/design.json"], ["there is no file"]),
        (["simulate", "--design", "/"], ["cannot be read"]),
    ],
)
def test_every_failure_is_one_line_and_exit_1(capsys, args, words):
    code, _, err = command(capsys, *args)
    assert_one_line_error(code, err, *words)
    assert len(err) < 1000


def test_an_unexpected_failure_is_one_line_too(capsys, monkeypatch):
    def broken(*args, **kwargs):
        raise RecursionError("deep\ninside")

    monkeypatch.setattr(cli, "summary", broken)
    code, _, err = command(capsys, "simulate", "--t-end", "1")
    assert_one_line_error(code, err, "RecursionError: deep inside")


@pytest.mark.parametrize(
    "text",
    [
        "\ufeffh,t_end\n1,60\n2,60\n",  # a spreadsheet's byte-order mark
        "h;t_end\n1;60\n2;60\n",  # semicolons
        "h;t_end\n1,0;60\n2,0;60\n",  # semicolons and decimal commas
        "\ufeffh\tt_end\n1\t60\n2\t60\n",  # tabs
    ],
)
def test_a_sweep_table_from_a_spreadsheet_is_read(tmp_path, capsys, text):
    table = tmp_path / "designs.csv"
    table.write_bytes(text.encode("utf-8"))
    code, out, err = command(capsys, "sweep", str(table))
    assert code == 0, err
    expected = windpump.sweep([SEED.replace(h=1.0), SEED.replace(h=2.0)], 60.0, progress=False)
    assert out == expected.to_csv()


def test_a_numeric_map_says_how_long_it_will_take(capsys, monkeypatch, tmp_path):
    monkeypatch.setattr(maps, "POINTS_PER_REPORT", 2)  # a first report before the end
    monkeypatch.setattr(cli.TimeLeft, "SAY_FROM", 0.0)  # say it however short
    args = ["map", "--numeric", "--gear-ratios", "3:5:2", "--heads", "1:3:2"]
    code, out, err = command(capsys, *args, "--csv", str(tmp_path / "map.csv"))
    assert code == 0
    lines = err.splitlines()
    assert lines[0] == "windpump map: 4 full simulations"
    assert (
        len(lines) == 2
        and lines[1].startswith("windpump map: about ")
        and lines[1].endswith(" left")
    )


@pytest.mark.parametrize("scale", [1e12, 1e-12])
@pytest.mark.parametrize("theta_dot0", [0.0, 3.0, 1e30])
def test_spinup_between_roots_many_decades_apart(scale, theta_dot0):
    # alpha- ~ 1e-45 and alpha+ ~ 1e20 rad/s (or 1e-109 and 2e-36): p + (z0 + d^2 g) / (1 + z0 g)
    # gave -16384 and NaN (hypothesis found it; in today's ranges 1.6e-10 and 2e20, or 1.6e-74
    # and 2e-36); the curve must go monotonically from the kick
    # to alpha+ and stay finite and positive.
    fields = dict.fromkeys(["I0", "I1", "h", "V_ref"], 1e-12)
    # the lightest liquid, the shortest crank, the smallest bore, the weakest gravity and a
    # 1e-12 m head keep the load as light as the ranges allow
    fields.update(rho_w=1.0, R=1e-4, A=1e-8, g=0.1)
    design = Design(
        **fields, R0=scale, R1=1e4 if scale > 1 else 1e12, T_m=scale, omega_m=scale, L=1.5e-4
    )
    alpha_plus, alpha_minus = windpump.steady_speeds(design)
    tau = windpump.time_constant(design)
    t = np.array([0.0, 1e-3, 1.0, 10.0, 100.0]) * tau
    speeds = windpump.spinup(design, t, theta_dot0)
    assert np.all(np.isfinite(speeds)) and np.all(speeds >= 0.0), speeds
    if theta_dot0 > alpha_minus:
        assert speeds[0] == pytest.approx(theta_dot0, rel=1e-12)
        assert speeds[-1] == pytest.approx(alpha_plus, rel=1e-12)
        steps = np.diff(speeds) * np.sign(alpha_plus - theta_dot0)
        assert np.all(steps >= 0.0), speeds
