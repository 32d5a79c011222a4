"""A year of water at a site (issue 23): the hour-by-hour rule, the tank's books, the sizing and the
map, each against a plain re-computation written here; steady_flow against quadrature; the year in
full against the quasi-steady one where the wind is steady within hours."""

from __future__ import annotations

import concurrent.futures
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate, optimize

import windpump
from windpump import Design, ParameterError, steady_flow, supply, supply_map, tank_for
from windpump import wind_thresholds as thresholds

HOUR = 3600.0
SELF_STARTING = Design.seed_example().replace(T_0=0.3)


def hourly_record(V):
    V = np.asarray(V, dtype=float)
    return (HOUR * np.arange(V.size), V)


# --- plain references -------------------------------------------------------------------------


def plain_running(V, V_stop, V_start, restart):
    """The rule of issue 23, written as its text reads."""
    running, was = [], False
    for speed in V:
        if restart == "attended":
            now = speed >= V_stop
        else:
            now = V_start is not None and (speed >= V_start or (was and speed >= V_stop))
        running.append(now)
        was = now
    return np.array(running, dtype=bool)


def plain_books(pumped, demand, tank):
    """The tank's bookkeeping, from full, pass after pass until the end level repeats."""
    start, passes = tank, 0
    while True:
        passes += 1
        level, rows = start, []
        for p, d in zip(pumped, demand, strict=True):
            available = level + p
            delivered = min(d, available)
            shortfall = d - delivered
            spilled = max(0.0, available - delivered - tank)
            level = available - delivered - spilled
            rows.append((delivered, shortfall, spilled, level))
        if abs(level - start) <= 1e-6 or passes == 20:
            return np.array(rows).T, passes
        start = level


speeds = st.lists(st.floats(0.0, 12.0, allow_nan=False), min_size=1, max_size=120)


@settings(max_examples=60, deadline=None)
@given(V=speeds, restart=st.sampled_from(["self", "attended"]))
def test_the_hour_by_hour_rule_as_written(V, restart):
    year = supply(SELF_STARTING, hourly_record(V), 1.0, 0.5, restart=restart)
    V_stop, V_start = thresholds(SELF_STARTING)
    expected = plain_running(V, V_stop, V_start, restart)
    np.testing.assert_array_equal(year.running, expected)
    flows = np.array([steady_flow(SELF_STARTING, v) for v in V])
    np.testing.assert_allclose(year.pumped, np.where(expected, flows * HOUR, 0.0), rtol=1e-12)
    assert year.starts == int(np.sum(expected & ~np.r_[False, expected[:-1]]))


@settings(max_examples=60, deadline=None)
@given(
    V=speeds,
    demand=st.floats(0.0, 30.0),
    tank=st.floats(0.0, 20.0),
    profile=st.one_of(st.none(), st.lists(st.floats(0.0, 5.0), min_size=24, max_size=24)),
)
def test_the_tank_books_as_written(V, demand, tank, profile):
    if profile is not None and not sum(profile) > 0.0:
        profile = None
    year = supply(SELF_STARTING, hourly_record(V), demand, tank, profile=profile)
    weights = np.ones(24) if profile is None else np.asarray(profile)
    asked = np.array([demand * weights[h % 24] / weights.sum() for h in range(len(V))])
    np.testing.assert_allclose(year.demand, asked, rtol=1e-12, atol=1e-15)
    (delivered, shortfall, spilled, level), passes = plain_books(year.pumped, year.demand, tank)
    np.testing.assert_allclose(year.delivered, delivered, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(year.shortfall, shortfall, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(year.spilled, spilled, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(year.level, level, rtol=1e-12, atol=1e-12)
    assert year.passes == passes
    assert np.all(year.level >= 0.0) and np.all(year.level <= tank + 1e-12)
    # the water balls over the periodic year: in = out + what the level gained
    start = year.level[-1]  # the year starts where it ends, to 1e-6
    balance = year.pumped.sum() - year.delivered.sum() - year.spilled.sum()
    assert abs(balance) <= 1e-6 + 1e-9 * year.pumped.sum() or year.passes == 20
    assert 0.0 <= start <= tank + 1e-12
    total = year.demand.sum()
    assert year.lolp == pytest.approx(year.shortfall.sum() / total if total else 0.0, abs=1e-15)


def test_the_dry_days_and_spells_by_hand():
    # 4 days: windy, calm, calm, windy: a small tank runs dry on the calm days
    V = [8.0] * 24 + [0.0] * 48 + [8.0] * 24
    year = supply(SELF_STARTING, hourly_record(V), 2.4, 0.5)
    shortfall_by_day = year.shortfall.reshape(4, 24).sum(axis=1)
    assert shortfall_by_day[0] == 0.0 and shortfall_by_day[3] == 0.0
    assert year.dry_days == 2 and year.longest_dry_spell == 2
    assert year.totals.running_hours == 48 and year.starts == 2
    # the tank covers the first calm hours: 0.5 m^3 at 0.1 m^3 an hour
    assert year.shortfall[24:29].sum() == pytest.approx(0.0, abs=1e-12)
    assert year.shortfall[29] > 0.0
    assert year.lolp == pytest.approx((4.8 - 0.5) / 9.6, rel=1e-12)


def test_a_record_finer_than_an_hour_is_averaged_to_hours():
    t = np.arange(0.0, 3 * HOUR, 600.0)  # 10-minute samples, 3 hours
    V = np.tile([4.0, 5.0, 6.0, 7.0, 8.0, 6.0], 3) + np.repeat([0.0, 1.0, 2.0], 6)
    year = supply(SELF_STARTING, (t, V), 1.0, 0.0)
    np.testing.assert_allclose(year.V, [6.0, 7.0, 8.0])


def test_attended_runs_whenever_the_wind_can_carry_it():
    V = [1.0, 3.0, 4.0, 2.0, 6.0, 2.5, 2.0]
    V_stop, _ = thresholds(SELF_STARTING)
    year = supply(SELF_STARTING, hourly_record(V), 1.0, 1.0, restart="attended")
    np.testing.assert_array_equal(year.running, np.asarray(V) >= V_stop)


def test_without_torque_at_rest_it_never_starts_and_says_why():
    year = supply(Design.seed_example(), hourly_record([9.0] * 48), 1.0, 2.0, restart="self")
    assert not year.running.any() and year.pumped.sum() == 0.0
    assert "T_0 = 0" in year.why and year.lolp == 1.0
    assert "someone must start it" in year.why
    assert "restart" not in year.why and "'" not in year.why  # words, not Python
    attended = supply(
        Design.seed_example(), hourly_record([9.0] * 48), 1.0, 2.0, restart="attended"
    )
    assert attended.running.all() and attended.why == "" and attended.lolp == 0.0


def test_a_wind_that_never_reaches_the_threshold_is_said_in_words():
    V_stop, V_start = thresholds(SELF_STARTING)
    calm = hourly_record([0.5 * V_stop] * 24)
    alone = supply(SELF_STARTING, calm, 1.0, 0.0, restart="self")
    assert f"never reaches {V_start:.3g} m/s (V_start)" in alone.why
    attended = supply(SELF_STARTING, calm, 1.0, 0.0, restart="attended")
    assert f"never reaches {V_stop:.3g} m/s (V_stop)" in attended.why
    assert "=" not in alone.why + attended.why


def test_months_from_the_record_or_from_1_january():
    year = supply(SELF_STARTING, hourly_record([5.0] * (24 * 40)), 1.0, 0.0)
    table = year.monthly
    assert table.month.tolist() == [1, 2]
    assert table.demand.tolist() == pytest.approx([31.0, 9.0])
    assert table.running_hours.sum() == year.totals.running_hours
    frame = table.to_pandas()
    assert list(frame.index) == ["Jan", "Feb"] and frame["demand"].sum() == pytest.approx(40.0)
    months = np.repeat([12, 1], [24, 24])
    record = windpump.WindRecord(HOUR * np.arange(48), np.full(48, 6.0), month=months)
    by_record = supply(SELF_STARTING, record, 1.0, 0.0).monthly
    assert by_record.month.tolist() == [1, 12]  # calendar order
    assert by_record.starts.tolist() == [0, 1]


def test_steady_flow_against_quadrature():
    d = Design.seed_example()
    x = lambda th: d.R * math.cos(th) + math.sqrt(d.L**2 - (d.R * math.sin(th)) ** 2)  # noqa: E731
    dx = lambda th: (x(th + 1e-6) - x(th - 1e-6)) / 2e-6  # noqa: E731
    swept, _ = integrate.quad(
        lambda th: d.A * max(0.0, -dx(th)), 0.0, 2 * math.pi, points=[math.pi], epsabs=1e-14
    )
    mean_load = d.rho_w * d.g * d.h * swept / (2 * math.pi)  # the load torque's revolution mean
    for V in (3.0, 5.0, 8.0, 12.0):
        s = V / d.V_ref

        def F(alpha, s=s):
            w = d.R_dagger * alpha / (s * d.omega_m)
            return d.R_dagger * s * s * (d.T_0 + (d.T_m - d.T_0) * w * (2 - w)) - mean_load

        top = 2 * s * d.omega_m / d.R_dagger  # the runaway speed on the crank
        alpha = optimize.brentq(F, s * d.omega_m / d.R_dagger, top, xtol=1e-14)
        assert steady_flow(d, V) == pytest.approx(swept * alpha / (2 * math.pi), rel=1e-6)
    V_stop, _ = thresholds(d)
    assert steady_flow(d, 0.999 * V_stop) == 0.0


def test_tank_for_is_the_smallest_litre():
    rng = np.random.default_rng(3)
    V = np.clip(rng.weibull(2.0, 24 * 30) * 5.0, 0.0, 20.0)
    record = hourly_record(V)
    for target in (0.0, 0.02, 0.1):
        size = tank_for(SELF_STARTING, record, 10.0, target)
        assert size == round(size * 1000) / 1000
        assert supply(SELF_STARTING, record, 10.0, size).lolp <= target + 1e-12
        if size > 0.0:
            assert supply(SELF_STARTING, record, 10.0, size - 0.001).lolp > target


def test_tank_for_none_or_endless():
    record = hourly_record([8.0] * 48)
    assert tank_for(SELF_STARTING, record, 1.0, 0.0) == 0.0
    calm = hourly_record([8.0] * 2 + [0.0] * 46)
    pumped = supply(SELF_STARTING, calm, 0.0, 0.0).pumped.sum()
    asked = pumped  # [m^3/day] over 2 days: twice the water pumped, half of it is missing
    assert tank_for(SELF_STARTING, calm, asked, 0.4) == math.inf
    size = tank_for(SELF_STARTING, calm, asked, 0.55)
    assert math.isfinite(size) and supply(SELF_STARTING, calm, asked, size).lolp <= 0.55


@pytest.mark.parametrize("restart", ["self", "attended"])
def test_supply_map_against_supply_design_by_design(restart):
    rng = np.random.default_rng(5)
    record = hourly_record(np.clip(rng.weibull(2.0, 24 * 20) * 5.5, 0.0, 20.0))
    ratios, tanks = np.array([3.0, 4.0, 5.5]), np.array([0.0, 1.5, 4.0, 12.0])
    found = supply_map(SELF_STARTING, record, 6.0, ratios, tanks, restart=restart)
    assert found.lolp.shape == (tanks.size, ratios.size)
    for j, ratio in enumerate(ratios):
        design = SELF_STARTING.with_ratios(R_dagger=float(ratio))
        for i, tank in enumerate(tanks):
            year = supply(design, record, 6.0, float(tank), restart=restart)
            assert found.lolp[i, j] == pytest.approx(year.lolp, abs=1e-12)
        assert found.pumped[j] == pytest.approx(year.pumped.sum(), rel=1e-12)


def test_a_leaky_real_machine_carries_on_in_any_wind():
    leaky = SELF_STARTING.replace(d_leak=0.004)
    V_stop, V_start = thresholds(leaky)
    assert V_stop == 0.0 and V_start == 0.0  # no load at rest: the water leaks back
    year = supply(leaky, hourly_record([0.0, 7.0, 0.0, 1.0]), 1.0, 0.0)
    assert year.running.all() and year.starts == 1
    assert year.pumped[0] == year.pumped[2] == 0.0 and year.pumped[1] > 0.0


@pytest.mark.parametrize(
    ("change", "name"),
    [
        ({"demand": -1.0}, "demand"),
        ({"demand": math.inf}, "demand"),
        ({"tank": -0.1}, "tank"),
        ({"tank": math.nan}, "tank"),
        ({"profile": [1.0] * 23}, "profile"),
        ({"profile": [0.0] * 24}, "profile"),
        ({"profile": [1.0] * 23 + [-1.0]}, "profile"),
        ({"restart": "sometimes"}, "restart"),
        ({"method": "exact"}, "method"),
    ],
)
def test_bad_input_names_the_argument(change, name):
    arguments = {"demand": 1.0, "tank": 1.0, **change}
    demand, tank = arguments.pop("demand"), arguments.pop("tank")
    with pytest.raises(ParameterError) as error:
        supply(SELF_STARTING, hourly_record([5.0] * 30), demand, tank, **arguments)
    assert error.value.name == name and "allowed" in str(error.value)


@pytest.mark.parametrize("lolp", [-0.1, 1.0, math.nan])
def test_tank_for_refuses_a_bad_lolp(lolp):
    with pytest.raises(ParameterError, match="lolp"):
        tank_for(SELF_STARTING, hourly_record([5.0] * 30), 1.0, lolp)


@pytest.mark.parametrize(
    ("t", "V", "fault"),
    [
        ([0.0, 3600.0, 10800.0], [5.0, 5.0, 5.0], "t[1]"),  # a gap: no sample in hour 2
        ([0.0, 3600.0, 7200.0], [5.0, -1.0, 5.0], "V[1]"),
        ([0.0, 3600.0, 7200.0], [5.0, 5.0, math.nan], "speeds[2]"),
        ([0.0, 3600.0, 3600.0], [5.0, 5.0, 5.0], "t[2]"),
    ],
)
def test_a_bad_record_is_refused_at_its_sample(t, V, fault):
    with pytest.raises(ParameterError, match=re_escape(fault)) as error:
        supply(SELF_STARTING, (t, V), 1.0, 1.0)
    assert error.value.name == "record"


def re_escape(text):
    import re

    return re.escape(text)


# --- the year in full ---------------------------------------------------------------------------


def test_the_full_year_against_the_quasi_steady_one_in_steady_winds():
    # Steady within hours and for long: 6 m/s for 30 hours, calm for 6, 7 m/s for 12.
    V = [6.0] * 30 + [0.0] * 6 + [7.0] * 12
    record = hourly_record(V)
    full = supply(SELF_STARTING, record, 3.0, 2.0, method="full", chunk_days=1)
    steady = full.quasi_steady
    assert full.method == "full" and steady is not None and steady.method == "quasi-steady"
    # hours well inside the steady stretches agree to the averaged theory's ripple
    inside = list(range(3, 29)) + list(range(39, 47))
    np.testing.assert_allclose(full.pumped[inside], steady.pumped[inside], rtol=0.01)
    assert abs(full.quasi_steady_gap) < 0.03
    assert full.running[inside].all() and not full.running[31:36].any()
    (delivered, shortfall, spilled, level), _ = plain_books(full.pumped, full.demand, 2.0)
    np.testing.assert_allclose(full.delivered, delivered, atol=1e-12)


def test_the_full_year_is_the_same_on_an_executor_and_its_gusts_are_seeded():
    record = hourly_record([6.0] * 6 + [3.0] * 6)
    options = {"method": "full", "turbulence": 0.15, "seed": 4, "chunk_days": 1}
    serial = supply(SELF_STARTING, record, 1.0, 0.0, **options)
    with concurrent.futures.ThreadPoolExecutor(2) as pool:
        pooled = supply(SELF_STARTING, record, 1.0, 0.0, executor=pool, **options)
    np.testing.assert_array_equal(serial.pumped, pooled.pumped)
    other = supply(SELF_STARTING, record, 1.0, 0.0, **{**options, "seed": 5})
    assert not np.array_equal(serial.pumped, other.pumped)
    calls = []
    supply(
        SELF_STARTING, record, 1.0, 0.0, method="full", progress=lambda d, t: calls.append((d, t))
    )
    assert calls == [(1, 1)]


@pytest.mark.parametrize("turbulence", [-0.1, 0.01, 5.0])
def test_the_full_year_refuses_a_turbulence_the_gust_model_cannot_give(turbulence):
    with pytest.raises(ParameterError, match="turbulence"):
        supply(
            SELF_STARTING, hourly_record([5.0] * 3), 1.0, 0.0, method="full", turbulence=turbulence
        )


def test_attended_in_full_someone_starts_a_pump_without_torque_at_rest():
    seed = Design.seed_example()  # T_0 = 0: it never starts on its own
    record = hourly_record([1.0] * 3 + [6.0] * 9)
    alone = supply(seed, record, 1.0, 0.0, method="full", restart="self", chunk_days=1)
    assert alone.pumped.sum() == 0.0 and "T_0 = 0" in alone.why
    helped = supply(seed, record, 1.0, 0.0, method="full", restart="attended", chunk_days=1)
    steady = helped.quasi_steady
    np.testing.assert_array_equal(steady.running, np.arange(12) >= 3)
    assert not helped.running[:3].any() and helped.running[4:].all()
    np.testing.assert_allclose(helped.pumped[5:11], steady.pumped[5:11], rtol=0.01)


@settings(max_examples=40, deadline=None)
@given(
    V=st.lists(st.floats(0.0, 12.0, allow_nan=False), min_size=24, max_size=96),
    demand=st.floats(0.1, 30.0),
)
def test_a_larger_tank_never_loses_more(V, demand):
    tanks = np.array([0.0, 0.3, 1.0, 2.5, 7.0, 40.0])
    found = supply_map(SELF_STARTING, hourly_record(V), demand, [3.5, 4.0, 5.0], tanks)
    assert np.all(np.diff(found.lolp, axis=0) <= 1e-12)
    assert np.all((found.lolp >= 0.0) & (found.lolp <= 1.0 + 1e-12))


@settings(max_examples=40, deadline=None)
@given(
    demand=st.one_of(st.floats(max_value=-1e-300), st.just(math.nan), st.just(math.inf)),
)
def test_any_bad_demand_is_named(demand):
    with pytest.raises(ParameterError) as error:
        supply(SELF_STARTING, hourly_record([5.0] * 3), demand, 1.0)
    assert error.value.name == "demand"


def test_the_full_years_chunks_are_cut_to_what_a_run_may_do():
    from windpump.run.dynamics import MAX_STEPS, estimated_steps
    from windpump.sites.fullyear import _spans

    V = np.full(24 * 120, 14.0)  # 120 days of strong wind in one chunk
    spans = _spans(SELF_STARTING, V, V.size, False)
    assert len(spans) > 1 and spans[0][0] == 0
    assert all(a + n == b for (a, n), (b, _) in zip(spans, spans[1:], strict=False))
    assert sum(n for _, n in spans) == V.size
    for first, hours in spans:
        t = (np.arange(hours) + 0.5) * HOUR
        assert (
            estimated_steps(
                SELF_STARTING, hours * HOUR, windpump.WindRecord(t, V[first : first + hours])
            )
            <= MAX_STEPS / 2
        )


def test_a_tank_of_exactly_n_hours_of_demand_has_no_round_off_dry_day():
    # 10 m^3 holds exactly 5 days of 2 m^3/day: emptied hour by hour, it ends a round-off short
    V = [9.0] * 24 + [0.0] * (24 * 5) + [9.0] * 24
    year = supply(SELF_STARTING, hourly_record(V), 2.0, 10.0)
    assert year.shortfall.sum() < 1e-12
    assert year.dry_days == 0 and year.longest_dry_spell == 0


def test_the_maps_kernel_is_the_single_tanks_number_for_number():
    from windpump._kernels import supply as kernels

    rng = np.random.default_rng(11)
    pumped = rng.exponential(0.2, (4, 500)) * (rng.random((4, 500)) < 0.4)
    demand = np.full(500, 0.08)
    tanks = np.array([0.0, 0.05, 0.4, 1.0, 3.0, 30.0])
    found = kernels.shortfall_map(pumped, demand, tanks, 1e-6, 20)
    for i in range(4):
        for j, tank in enumerate(tanks):
            assert found[i, j] == kernels.short_total(pumped[i], demand, tank, 1e-6, 20)
