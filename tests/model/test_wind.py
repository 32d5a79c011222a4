"""Wind: the rotor by similarity, runs in a wind record with stops and restarts, the averaged site
figures, gusty and measured records. References are written here or in reference.py."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate, special, stats

import windpump
from windpump import Design, ParameterError, simulate
from windpump.model.wind import gusty, read_csv, weibull_density, weibull_scale
from windpump.readers.labdata import LabDataError
from windpump.units import SECONDS_PER_DAY

from reference import wind_reference_run

SEED = Design.seed_example()
# A light rotor that stops within seconds of a calm, with torque at rest to start again.
LIGHT = SEED.replace(I0=0.05, T_0=0.3)
STEPS = ([0.0, 20.0, 20.5, 60.0, 60.5], [5.0, 5.0, 0.4, 0.4, 6.0])


def test_in_wind_is_the_scaled_design():
    d = SEED.replace(T_0=0.2)
    for V in (0.5, 5.0, 7.3, 40.0):
        moved = d.in_wind(V)
        s = V / d.V_ref
        assert moved.T_m == d.T_m * s**2
        assert moved.omega_m == d.omega_m * s
        assert moved.T_0 == d.T_0 * s**2
        assert moved.V_ref == V
        assert moved.replace(T_m=d.T_m, omega_m=d.omega_m, T_0=d.T_0, V_ref=d.V_ref) == d


@pytest.mark.parametrize("V", [0.0, -1.0, math.nan, math.inf, "5"])
def test_in_wind_refuses_a_wind_without_a_curve(V):
    with pytest.raises(ParameterError, match=r"\bV\b"):
        SEED.in_wind(V)


def test_a_wind_at_v_ref_reproduces_the_run_without_one():
    d = SEED.replace(cylinders=3, T_0=0.2)
    plain = simulate(d, 120.0)
    steady = simulate(d, 120.0, wind=([0.0, 50.0], [d.V_ref, d.V_ref]))
    assert plain.t.shape == steady.t.shape
    for name in ("t", "theta", "theta_dot", "volume", "shaft_work"):
        np.testing.assert_allclose(
            getattr(steady, name), getattr(plain, name), rtol=1e-13, atol=1e-13
        )


def test_a_constant_wind_equals_the_design_moved_to_it():
    """V(t) = 7 m/s throughout against design.in_wind(7) without a record: round-off apart."""
    d = SEED.replace(T_0=0.1)
    moved = simulate(d.in_wind(7.0), 60.0, sample_dt=0.5)
    record = simulate(d, 60.0, wind=([0.0], [7.0]), sample_dt=0.5)
    np.testing.assert_allclose(record.theta, moved.theta, rtol=1e-9)
    np.testing.assert_allclose(record.theta_dot, moved.theta_dot, rtol=1e-8)
    np.testing.assert_allclose(record.volume, moved.volume, rtol=1e-8, atol=1e-12)


def test_stops_and_restarts_in_a_stepped_wind_match_the_reference():
    run = simulate(LIGHT, 90.0, theta_dot0=0.0, wind=STEPS, sample_dt=0.1)
    ref, stops, starts = wind_reference_run(LIGHT, 90.0, math.pi / 2, 0.0, *STEPS)
    assert len(run.stops) == len(stops) == 1
    assert len(run.starts) == len(starts) == 2
    np.testing.assert_allclose(run.stops, stops, atol=1e-5)
    np.testing.assert_allclose(run.starts, starts, atol=1e-6)
    assert run.theta[-1] == pytest.approx(ref.theta, rel=1e-7)
    assert run.theta_dot[-1] == pytest.approx(ref.theta_dot, rel=1e-6)
    assert run.volume[-1] == pytest.approx(ref.volume, rel=1e-7)
    # At rest between the stop and the restart: no speed, no flow, no volume.
    resting = (run.t > run.stops[0]) & (run.t < run.starts[1])
    assert abs(resting.sum() - (run.starts[1] - run.stops[0]) / 0.1) <= 1
    assert np.all(run.theta_dot[resting] == 0.0) and np.all(run.flow[resting] == 0.0)
    assert np.ptp(run.volume[resting]) == 0.0


def test_stops_and_restarts_in_a_gusty_wind_match_the_reference():
    record = gusty(2.5, 300.0, time_scale=10.0, dt=1.0, seed=7)
    run = simulate(LIGHT, 300.0, theta_dot0=0.0, wind=record, sample_dt=1.0)
    ref, stops, starts = wind_reference_run(LIGHT, 300.0, math.pi / 2, 0.0, *record)
    assert len(stops) >= 2, "the record should stop the pump"
    np.testing.assert_allclose(run.stops, stops, atol=1e-4)
    np.testing.assert_allclose(run.starts, starts, atol=1e-4)
    assert run.volume[-1] == pytest.approx(ref.volume, rel=1e-6)
    assert run.stalled == ref.stalled


def test_without_torque_at_rest_a_calm_stops_the_pump_for_good():
    d = LIGHT.replace(T_0=0.0)
    run = simulate(d, 90.0, wind=STEPS, sample_dt=0.5)
    ref, stops, _ = wind_reference_run(d, 90.0, math.pi / 2, 3.0, *STEPS)
    assert run.stalled and ref.stalled
    assert run.t[-1] == 90.0, "in a wind record the run goes on to t_end"
    # (4e-5 s apart at the kernel's rtol 1e-8; it converges on the reference as rtol falls)
    assert run.t_stall == pytest.approx(stops[-1], abs=2e-4)
    assert len(run.starts) == 0 and np.all(run.theta_dot[run.t > run.t_stall] == 0.0)


def test_energy_closes_in_a_gusty_wind():
    d = LIGHT.replace(cylinders=2, double_acting=True, h=1.0)
    record = gusty(4.0, 600.0, time_scale=15.0, seed=3)
    run = simulate(d, 600.0, theta_dot0=0.0, wind=record, sample_dt=0.25)
    assert len(run.stops) >= 1
    kinetic = run.kinetic_energy - run.kinetic_energy[0]
    balance = run.shaft_work - kinetic - run.lift_work
    assert np.max(np.abs(balance)) <= 1e-9 * np.max(np.abs(run.shaft_work))
    assert np.all(np.diff(run.volume) >= 0.0)


def test_a_callable_wind_is_the_record_of_its_samples():
    def breeze(t):
        return 5.0 + 2.0 * np.sin(t / 7.0)

    run = simulate(SEED, 50.0, wind=breeze, sample_dt=1.0)
    grid = np.linspace(0.0, 50.0, 5001)
    again = simulate(SEED, 50.0, wind=(grid, breeze(grid)), sample_dt=1.0)
    np.testing.assert_array_equal(run.theta, again.theta)
    scalar_only = simulate(SEED, 50.0, wind=lambda t: 5.0 + 2.0 * math.sin(t / 7.0), sample_dt=1.0)
    np.testing.assert_allclose(scalar_only.theta, run.theta, rtol=1e-12)
    np.testing.assert_allclose(run.wind_speed, breeze(run.t), atol=1e-3)


def test_a_day_at_one_sample_a_second_holds_a_day_of_samples():
    record = gusty(5.0, SECONDS_PER_DAY, seed=11)
    run = simulate(
        SEED.replace(T_0=0.3), SECONDS_PER_DAY, theta_dot0=0.0, wind=record, sample_dt=1.0
    )
    on_grid = np.isclose(run.t, np.round(run.t), rtol=0.0, atol=1e-9)
    assert on_grid.sum() == 86_401
    assert len(run.t) - 86_401 <= 2 * (len(run.stops) + len(run.starts))
    assert run.t[-1] == SECONDS_PER_DAY and np.all(np.diff(run.t) > 0.0)


def test_the_stroke_grid_still_serves_a_wind_run():
    run = simulate(LIGHT, 90.0, theta_dot0=0.0, wind=STEPS, samples_per_stroke=4)
    timed = simulate(LIGHT, 90.0, theta_dot0=0.0, wind=STEPS, sample_dt=0.1)
    np.testing.assert_allclose(run.stops, timed.stops, atol=1e-9)
    assert run.volume[-1] == pytest.approx(timed.volume[-1], rel=1e-9)
    moving = run.theta_dot > 0
    angles = run.theta[moving] / (math.pi / 4)
    assert np.mean(np.isclose(angles, np.round(angles), atol=1e-9)) > 0.9


@pytest.mark.parametrize(
    ("wind", "fragment"),
    [
        (([0.0, 1.0], [5.0, math.nan]), "speeds"),
        (([0.0, 1.0], [5.0, -1.0]), "from 0 to 150"),
        (([0.0, 1.0], [5.0, 151.0]), "from 0 to 150"),
        (([0.0, 0.0], [5.0, 5.0]), "increasing"),
        (([0.0, 1.0, 2.0], [5.0, 5.0]), "shape"),
        (([], []), "length >= 1"),
        ("gale", "pair"),
        (lambda t: 1 / 0, "calling it failed"),
    ],
)
def test_a_bad_wind_is_refused_by_name(wind, fragment):
    with pytest.raises(ParameterError, match="wind") as caught:
        simulate(SEED, 10.0, wind=wind)
    assert fragment in str(caught.value)


@pytest.mark.parametrize(
    ("options", "name"),
    [({"sample_dt": 0.0}, "sample_dt"), ({"samples_per_stroke": 0}, "samples_per_stroke")],
)
def test_a_bad_output_grid_is_refused_by_name(options, name):
    with pytest.raises(ParameterError, match=name):
        simulate(SEED, 10.0, **options)


def test_a_day_on_the_stroke_grid_is_refused_with_the_way_out():
    with pytest.raises(ParameterError, match="sample_dt"):
        simulate(SEED, SECONDS_PER_DAY, wind=([0.0], [5.0]))


# The averaged site figures.


def test_steady_flow_is_the_running_speed_of_the_design_moved_to_each_wind():
    d = SEED.replace(cylinders=2, T_0=0.25)
    V_stop, _ = windpump.wind_thresholds(d)
    winds = np.linspace(0.2, 15.0, 60)
    flows = windpump.steady_flow(d, winds)
    for V, flow in zip(winds, flows, strict=True):
        if V <= V_stop:
            assert flow == 0.0
        else:
            alpha = windpump.steady_speeds(d.in_wind(V))[0]
            assert flow == pytest.approx(d.volume_per_revolution * alpha / (2 * math.pi), rel=1e-12)


def test_the_thresholds_are_where_the_moved_design_stalls_and_starts():
    d = SEED.replace(cylinders=3, T_0=0.2)
    V_stop, V_start = windpump.wind_thresholds(d)
    assert windpump.stall_margin(d.in_wind(V_stop)) == pytest.approx(1.0, rel=1e-12)
    assert windpump.starts_from_rest(d.in_wind(V_start * (1 + 1e-9)))
    assert not windpump.starts_from_rest(d.in_wind(V_start * (1 - 1e-9)))
    assert V_stop < V_start
    assert windpump.wind_thresholds(SEED)[1] is None


def weibull_pdf(V, c, k):
    return k / c * (V / c) ** (k - 1) * np.exp(-((V / c) ** k))


@pytest.mark.parametrize(("mean", "k"), [(5.0, 2.0), (3.5, 1.5), (7.0, 3.0)])
def test_water_per_day_against_an_independent_quadrature(mean, k):
    d = SEED.replace(cylinders=2, T_0=0.3)
    low, high = windpump.water_per_day(d, mean, k)
    c = mean / special.gamma(1 + 1 / k)
    V_stop, V_start = windpump.wind_thresholds(d)

    def expected(V_from):
        # Straight in V, the flow written out from the Riccati roots, split where it bends.
        def integrand(V):
            s = V / d.V_ref
            p = d.omega_m / d.R_dagger
            spare = d.R_dagger * d.T_m * s * s - d.mean_load_torque
            alpha = p * s + math.sqrt(max(spare, 0.0) * p * p / (d.R_dagger * (d.T_m - d.T_0)))
            return d.volume_per_revolution * alpha / (2 * math.pi) * weibull_pdf(V, c, k)

        edges = [V_from, V_from * 1.001, V_from * 1.1, c, 3 * c, 10 * c]
        edges = sorted(e for e in edges if e >= V_from)
        total = sum(
            integrate.quad(integrand, a, b, epsabs=0, epsrel=1e-13, limit=500)[0]
            for a, b in zip(edges[:-1], edges[1:], strict=True)
        )
        return SECONDS_PER_DAY * (
            total + integrate.quad(integrand, edges[-1], np.inf, epsrel=1e-13)[0]
        )

    assert high == pytest.approx(expected(V_stop), rel=1e-8)
    assert low == pytest.approx(expected(V_start), rel=1e-8)
    assert 0 < low < high


def test_water_per_day_against_a_monte_carlo_of_the_weibull():
    d = SEED.replace(T_0=0.3)
    low, high = windpump.water_per_day(d, 5.0)
    rng = np.random.default_rng(5)
    V = weibull_scale(5.0, 2.0) * rng.weibull(2.0, 1_000_000)
    flow = windpump.steady_flow(d, V)
    V_stop, V_start = windpump.wind_thresholds(d)
    for bound, kept in ((high, V > V_stop), (low, V >= V_start)):
        daily = SECONDS_PER_DAY * np.where(kept, flow, 0.0)
        error = daily.std() / math.sqrt(len(V))
        assert abs(daily.mean() - bound) < 4 * error


def test_without_torque_at_rest_the_low_bound_is_zero():
    low, high = windpump.water_per_day(SEED, 5.0)
    assert low == 0.0 and high > 0.0


def test_the_full_day_lies_between_the_bounds_of_its_own_slow_wind():
    """A wind that varies slowly against the spin-up time (tau ~ 80 s): the full run lifts what
    the averaged bounds over the same record say, between the low and the high."""
    d = SEED.replace(T_0=0.3)
    record = gusty(4.0, SECONDS_PER_DAY, time_scale=7200.0, dt=10.0, seed=2)
    run = simulate(d, SECONDS_PER_DAY, theta_dot0=0.0, wind=record, sample_dt=10.0)
    V_stop, V_start = windpump.wind_thresholds(d)
    flow = windpump.steady_flow(d, record.V)
    dt = np.diff(record.t)
    mid = 0.5 * (flow[1:] + flow[:-1])
    high = np.sum(np.where(record.V[1:] > V_stop, mid, 0.0) * dt)
    low = np.sum(np.where(record.V[1:] >= V_start, mid, 0.0) * dt)
    assert len(run.stops) >= 1 and len(run.starts) >= 2
    assert low < run.volume[-1] < high


# Records.


def test_gusty_is_reproducible_and_weibull_distributed():
    a = gusty(6.0, 200_000.0, k=2.4, time_scale=30.0, dt=2.0, seed=4)
    assert np.array_equal(a.V, gusty(6.0, 200_000.0, k=2.4, time_scale=30.0, dt=2.0, seed=4).V)
    assert not np.array_equal(a.V, gusty(6.0, 200_000.0, k=2.4, time_scale=30.0, dt=2.0, seed=5).V)
    assert a.t[1] - a.t[0] == 2.0 and a.t[-1] == 200_000.0
    c = weibull_scale(6.0, 2.4)
    # The samples are correlated: effective sample count about n dt / (2 time_scale).
    effective = len(a.V) * 2.0 / (2 * 30.0)
    assert abs(a.V.mean() - 6.0) < 4 * a.V.std() / math.sqrt(effective)
    ks = stats.kstest(a.V, stats.weibull_min(2.4, scale=c).cdf).statistic
    assert ks < 4 * 1.36 / math.sqrt(effective)
    fitted_k, _, _ = stats.weibull_min.fit(a.V, floc=0)
    assert fitted_k == pytest.approx(2.4, rel=0.05)


def test_gusty_correlation_time_is_the_time_scale():
    record = gusty(5.0, 500_000.0, time_scale=40.0, dt=1.0, seed=8)
    c = weibull_scale(5.0, 2.0)
    z = -special.ndtri(np.exp(-((record.V / c) ** 2)))  # back to the Gaussian process
    z = z - z.mean()
    lags = np.arange(0, 400)
    acf = np.array([np.dot(z[: len(z) - lag], z[lag:]) for lag in lags]) / np.dot(z, z)
    integral_scale = np.trapezoid(acf, lags)
    effective = len(z) / (2 * 40.0)
    assert integral_scale == pytest.approx(40.0, rel=4 * math.sqrt(2 / effective) + 0.02)
    assert acf[1] == pytest.approx(math.exp(-1 / 40.0), abs=4 / math.sqrt(effective))


@pytest.mark.parametrize(
    ("options", "name"),
    [({"mean": 0.0}, "mean_wind"), ({"k": 0.1}, "k"), ({"time_scale": -1.0}, "time_scale"),
     ({"dt": 1e-6}, "dt"), ({"duration": math.nan}, "duration")],
)  # fmt: skip
def test_gusty_refuses_bad_input_by_name(options, name):
    arguments = {"mean": 5.0, "duration": SECONDS_PER_DAY} | options
    with pytest.raises(ParameterError, match=name):
        gusty(**arguments)


def test_read_csv_takes_seconds_or_timestamps():
    seconds = read_csv(b"# a mast\nt [s],V [m/s]\n100,4.5\n101.5,6\n103,0\n")
    assert seconds.t.tolist() == [0.0, 1.5, 3.0] and seconds.V.tolist() == [4.5, 6.0, 0.0]
    stamps = read_csv("time;speed\n2026-06-01 23:59:50;4,5\n2026-06-02T00:00:10;5\n")
    assert stamps.t.tolist() == [0.0, 20.0]
    zoned = read_csv(b"2026-06-01T12:00:00+02:00\t3\n2026-06-01T10:00:30+00:00\t4\n")
    assert zoned.t.tolist() == [0.0, 30.0]
    run = simulate(SEED, 3.0, wind=seconds, sample_dt=1.0)
    assert run.wind_speed.tolist() == [4.5, 5.5, 4.0, 0.0]


@pytest.mark.parametrize(
    ("content", "fragment"),
    [
        (b"", "empty"),
        (b"0,5\n", "at least 2"),
        (b"0,5\n1,5,6\n", "3 columns"),
        (b"0,5\nnoon,5\n", "neither seconds nor an ISO timestamp"),
        (b"0,5\n0,6\n", "does not come after"),
        (b"0,5\n1,-2\n", "from 0 to 150"),
        (b"0,5\n1,nan\n", "from 0 to 150"),
        (b"0,5\n1,fast\n", "not a number"),
        (b"0,5\n2026-06-01T00:00:00,5\n", "mixes"),
        (b"\xff\xfe0,5\n", "not text"),
    ],
)
def test_read_csv_refuses_bad_files_saying_where(content, fragment):
    with pytest.raises(LabDataError, match=fragment):
        read_csv(content)


@pytest.mark.parametrize(
    ("content", "line", "column", "fragment"),
    [
        # a first row is a header by what it says, never because it fails to parse as data
        (b"0,5x\n10,6\n20,4\n", 1, 2, "'5x' is not a number"),
        (b"0;5,5x\n10;6\n20;4\n", 1, 2, "'5.5x' is not a number"),
        (b"0x,5\n10,6\n", 1, 1, "neither seconds nor an ISO timestamp"),
        (b"2026-06-01T00:00:0x,5\n2026-06-01T00:00:10,6\n", 1, 1, "neither seconds"),
        (b"nan,nan\n0,5\n10,6\n", 1, 1, "neither seconds"),
        (b"0,5,7\n10,6\n20,4\n", 1, 3, "3 columns"),
        (b"time,speed,gust\n0,5\n10,6\n", 1, 3, "3 columns"),
        (b"0,5\n10,6,7\n", 2, 3, "3 columns"),
        (b"0,5\n10\n", 2, 2, "1 column where"),
        (b"0,5\n10,6\x00\n", 2, None, "NUL byte"),
        (b"\x00", 1, None, "NUL byte"),
        (b" \n# nothing yet\n", None, None, "the file is empty"),
    ],
)
def test_read_csv_names_the_line_and_column_at_fault(content, line, column, fragment):
    with pytest.raises(LabDataError, match=fragment) as caught:
        read_csv(content)
    assert (caught.value.line, caught.value.column) == (line, column)


@pytest.mark.parametrize("header", ["t [s],V [m/s]", "time;speed", "Zeit\tWind", '"t","V"'])
def test_read_csv_reads_a_header_of_names(header):
    separator = next((s for s in ("\t", ";") if s in header), ",")
    record = read_csv("\n".join([header, f"0{separator}5", f"10{separator}6"]))
    assert record.t.tolist() == [0.0, 10.0] and record.V.tolist() == [5.0, 6.0]


@settings(max_examples=60)
@given(
    speeds=st.lists(st.floats(0.0, 150.0), min_size=2, max_size=12),
    header=st.booleans(),
    stamps=st.booleans(),
    at=st.data(),
    letter=st.characters(categories=["L"]),
)
def test_a_sample_with_a_letter_after_it_is_refused_naming_its_line(
    speeds, header, stamps, at, letter
):
    """In any row, the first too: a typo never turns a row into a header or drops it (which
    would shift the record's times)."""
    times = [f"2026-06-01T00:{i // 6:02d}:{10 * (i % 6):02d}" if stamps else str(10 * i)
             for i in range(len(speeds))]  # fmt: skip
    lines = [[time, repr(speed)] for time, speed in zip(times, speeds, strict=True)]
    row = at.draw(st.integers(0, len(lines) - 1), label="row")
    column = at.draw(st.integers(1, 2), label="column")
    lines[row][column - 1] += letter
    text = "\n".join(",".join(cells) for cells in ([["time", "speed"]] if header else []) + lines)
    with pytest.raises(LabDataError) as caught:
        read_csv(text.encode())
    assert (caught.value.line, caught.value.column) == (row + 1 + header, column)


@settings(max_examples=60, deadline=None)
@given(
    t=st.lists(st.floats(allow_nan=True, allow_infinity=True, width=64), min_size=1, max_size=6),
    V=st.lists(st.floats(allow_nan=True, allow_infinity=True, width=64), min_size=1, max_size=6),
)
def test_any_wind_record_runs_or_is_refused_by_name(t, V):
    try:
        run = simulate(LIGHT, 5.0, theta_dot0=1.0, wind=(t, V), sample_dt=0.5)
    except ParameterError as error:
        assert error.name in ("wind", "t_end")
        return
    assert np.all(np.isfinite(run.theta_dot)) and np.all(np.diff(run.volume) >= 0)
    assert run.t[-1] == 5.0


def test_weibull_density_is_scipys():
    V = np.linspace(0.0, 30.0, 301)
    for mean, k in ((5.0, 2.0), (3.0, 1.4), (8.0, 3.5)):
        expected = stats.weibull_min(k, scale=weibull_scale(mean, k)).pdf(V)
        np.testing.assert_allclose(weibull_density(V, mean, k), expected, rtol=1e-12, atol=1e-300)


# A light rotor whose torque at rest beats the load at any angle: it starts on its own.
SELF_STARTING = LIGHT.replace(T_0=0.4)


def test_a_run_in_wind_lets_a_self_starting_pump_go_from_rest_and_kicks_any_other():
    assert windpump.starts_from_rest(SELF_STARTING) and not windpump.starts_from_rest(LIGHT)
    day = windpump.run_in_wind(SELF_STARTING, STEPS, kick=3.0)
    assert day.kick == 0.0 and day.run.theta_dot[0] == 0.0 and day.starts.t[0] == 0.0
    kicked = windpump.run_in_wind(LIGHT, STEPS, kick=2.5)
    assert kicked.kick == 2.5 and kicked.run.theta_dot[0] == 2.5


def test_a_run_in_wind_has_its_stops_and_starts_with_the_wind_and_water_at_each():
    day = windpump.run_in_wind(SELF_STARTING, STEPS)
    _, stops, starts = wind_reference_run(SELF_STARTING, 60.5, math.pi / 2, 0.0, *STEPS)
    assert len(day.stops) == len(stops) == 1 and len(day.starts) == len(starts) == 2
    np.testing.assert_allclose(day.stops.t, stops, atol=1e-5)
    np.testing.assert_allclose(day.starts.t, starts, atol=1e-6)
    # The stop falls in the lull (0.4 m/s from 20.5 s to 60 s); the restart on the ramp to 6 m/s.
    assert 20.5 < day.stops.t[0] < 60.0 and day.stops.V[0] == pytest.approx(0.4, rel=1e-12)
    restart = day.starts.t[1]
    assert 60.0 < restart < 60.5
    assert day.starts.V[1] == pytest.approx(0.4 + 5.6 * (restart - 60.0) / 0.5, rel=1e-9)
    assert day.starts.V[0] == 5.0 and day.starts.volume[0] == 0.0
    # Stops are samples of the run; at rest it pumps nothing: the restart finds the stop's water.
    at_stop = day.run.volume[day.run.t == day.stops.t[0]]
    assert len(at_stop) == 1 and day.stops.volume[0] == at_stop[0] > 0.0
    assert day.starts.volume[1] == pytest.approx(day.stops.volume[0], rel=1e-12)


def test_a_run_in_wind_is_a_day_of_water_at_the_record_s_rate_sampled_once_a_second():
    day = windpump.run_in_wind(SELF_STARTING, STEPS)
    direct = simulate(SELF_STARTING, 60.5, math.pi / 2, 0.0, wind=STEPS, sample_dt=1.0)
    assert day.volume == direct.volume[-1] and day.duration == 60.5
    assert day.per_day == pytest.approx(direct.volume[-1] * 86_400.0 / 60.5, rel=1e-15)
    assert np.max(np.diff(day.run.t)) <= 1.0 + 1e-9
    assert day.mean_wind == pytest.approx(np.mean(np.interp(day.run.t, *STEPS)), rel=1e-12)


def test_a_record_longer_than_a_day_gives_a_day_s_samples():
    calm = ([0.0, 2 * 86_400.0], [0.0, 0.0])  # kicked, it stops at once and rests two days
    day = windpump.run_in_wind(LIGHT, calm)
    assert day.duration == 2 * 86_400.0 and len(day.stops) == 1
    assert np.max(np.diff(day.run.t)) == pytest.approx(2.0, rel=1e-9)
    assert len(day.run.t) <= 86_400 + 3 + len(day.stops) + len(day.starts)
    assert day.per_day == pytest.approx(day.volume / 2, rel=1e-15)


@pytest.mark.parametrize(
    ("record", "kick", "name"),
    [(STEPS, -1.0, "kick"), (STEPS, math.nan, "kick"), (([0.0], [5.0]), 3.0, "record"),
     (([0.0, 1.0], [5.0, -1.0]), 3.0, "record"), ("gusty", 3.0, "record")],
)  # fmt: skip
def test_a_run_in_wind_refuses_bad_input_by_name(record, kick, name):
    with pytest.raises(ParameterError) as error:
        windpump.run_in_wind(LIGHT, record, kick=kick)
    assert error.value.name == name


@pytest.mark.parametrize("times", ["-1e308\n1e308", "0\n1e13", "-2e12\n0"])
def test_a_file_with_times_past_1e12_s_is_refused_at_its_line(tmp_path, times):
    """Times so far apart that their difference overflowed (-1e308 and 1e308 made the second
    sample's time inf, with numpy's RuntimeWarning) are refused at their line, in words."""
    first, second = times.split("\n")
    path = tmp_path / "far.csv"
    path.write_text(f"t,V\n{first},5\n{second},6\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow on the way
        with pytest.raises(LabDataError, match=r"past 1e\+12 s either side of 0") as caught:
            read_csv(path)
    bad_line = 2 if abs(float(first)) > 1e12 else 3
    assert caught.value.line == bad_line


@given(st.floats(1e12, 1e308, exclude_min=True), st.sampled_from([-1.0, 1.0]))
def test_a_record_holds_times_from_minus_to_plus_1e12_s(far, sign):
    """A record's times lie within +-MAX_TIME: a time past it is refused by name, so no span
    between two of them overflows; at the bound itself the record is kept."""
    times = np.array(sorted([0.0, sign * far]))
    with pytest.raises(ParameterError, match="from -1e\\+12 to 1e\\+12") as caught:
        windpump.WindRecord(times, np.array([4.0, 5.0]))
    assert caught.value.name == "t"
    kept = windpump.WindRecord(np.array([-1e12, 1e12]), np.array([4.0, 5.0]))
    assert np.isfinite(np.diff(kept.t)).all()
