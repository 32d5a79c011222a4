"""The real machine's load on the crank and its averaged theory (issue 22, "The model" and
"Averaged theory"), against references written here from the issue's formulas.

The references: the lever arm dx/dtheta from Eq. (1) differentiated by hand; the load
``sum p_k A |x_c'|`` with ``q_k = max(u_k - q_L, 0)``, ``h_f = K Q^2`` and the hole's pressure
``rho_w/2 (u / (C_d a_L))^2``; revolution means by ``scipy.integrate.quad``; roots by
``brentq``; tau from a central difference; the stall margin by ``minimize_scalar``; the spin-up
by ``solve_ivp``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st
from scipy import integrate, optimize

import windpump
from windpump import ParameterError
from windpump.averaging.revolution import mean_load, reciprocating_inertia
from windpump.averaging.theory import cycle_mean, running_speeds
from windpump.model.loads import rest_torque, weight_torque

SEED = windpump.Design.seed_example()
HOLE = 0.004  # m: passes 0.106 L/s against 3 m


# ---------------------------------------------------------------- references from the issue


def dx_dtheta(phi, R, r):
    """Eq. (1) differentiated by hand: R sin phi (1 + cos phi / sqrt(r^2 - sin^2 phi))."""
    return R * math.sin(phi) * (1.0 + math.cos(phi) / math.sqrt(r * r - math.sin(phi) ** 2))


def faces(d, theta):
    """|x_c'| [m] of every delivering face at theta (top face on the exhaust half, bottom face
    of a double-acting piston on the other), and x_c' of every cylinder."""
    arms, slopes = [], []
    for c in range(d.cylinders):
        phi = (theta - 2 * math.pi * c / d.cylinders) % (2 * math.pi)
        slope = dx_dtheta(phi, d.R, d.L / d.R)
        slopes.append(slope)
        if phi > math.pi or (d.double_acting and phi <= math.pi):
            arms.append(abs(slope))
    return arms, slopes


def reference_load(d, theta, speed, h=None):
    """(load torque [N m], delivered flow [m^3/s]) from the issue's formulas."""
    h = d.h if h is None else h
    a_L = math.pi * d.d_leak**2 / 4
    q_L = d.Cd_leak * a_L * math.sqrt(2 * d.g * h)
    a_main = math.pi * d.D_main**2 / 4
    arms, _ = faces(d, theta)
    swept = [d.A * arm * speed for arm in arms]
    Q = sum(max(u - q_L, 0.0) for u in swept)
    h_f = d.f_main * (d.L_main / d.D_main) * (Q / a_main) ** 2 / (2 * d.g)
    load = 0.0
    for u, arm in zip(swept, arms, strict=True):
        if q_L > 0.0 and u <= q_L:
            p = 0.5 * d.rho_w * (u / (d.Cd_leak * a_L)) ** 2
        else:
            p = d.rho_w * d.g * (h + h_f)
        load += p * d.A * arm
    return load, Q


def revolution_mean(f, d):
    """(1/2 pi) int_0^2pi f, by quad between the switches (k pi / n)."""
    edges = np.linspace(0.0, 2 * math.pi, 2 * d.cylinders + 1)
    total = sum(
        integrate.quad(f, a, b, epsabs=1e-13, epsrel=1e-12, limit=400)[0]
        for a, b in zip(edges[:-1], edges[1:], strict=True)
    )
    return total / (2 * math.pi)


def reference_mean_load(d, speed):
    return revolution_mean(lambda th: reference_load(d, th, speed)[0], d)


def windmill_on_crank(d, alpha, s=1.0):
    """eta_t R+ T(R+ alpha) in the wind s (Eq. 11 with T_0 and the similarity)."""
    x = d.R_dagger * alpha / d.omega_m
    return d.eta_t * d.R_dagger * (s * s * d.T_0 + (d.T_m - d.T_0) * x * (2 * s - x))


def reference_I_bar(d):
    mean_square = revolution_mean(lambda th: sum(x * x for x in faces(d, th)[1]), d)
    return d.I_eff + d.m_r * mean_square


def reference_roots(F, upper, points=400):
    """Every root of F on (0, upper) by a fine scan and brentq: [(root, rising?)]."""
    grid = np.linspace(1e-9 * upper, upper, points)
    values = [F(a) for a in grid]
    roots = []
    for a, b, fa, fb in zip(grid[:-1], grid[1:], values[:-1], values[1:], strict=True):
        if (fa > 0) != (fb > 0):
            roots.append((optimize.brentq(F, a, b, xtol=1e-14, rtol=1e-14), fb > 0))
    return roots


# ---------------------------------------------------------------- the load on the crank


REAL = [
    SEED.replace(d_leak=HOLE),
    SEED.replace(L_main=30.0, D_main=0.02),
    SEED.replace(d_leak=0.006, L_main=50.0, D_main=0.015, h=8.0),
    SEED.replace(cylinders=3, double_acting=True, L=0.06, d_leak=0.005, L_main=20.0, D_main=0.02),
    SEED.replace(cylinders=2, d_leak=0.003, L_main=40.0, D_main=0.025),
]


@pytest.mark.parametrize("design", REAL, ids=range(len(REAL)))
def test_load_and_flows_follow_the_issues_formulas(design):
    theta = np.linspace(0.0, 4 * math.pi, 97) + 0.01
    for speed in (0.3, 3.0, 20.0):
        load = windpump.load_torque_on_crank(design, theta, speed)
        flows = windpump.face_flows(theta, np.full(theta.shape, speed), design)
        for i, th in enumerate(theta):
            expected, Q = reference_load(design, th, speed)
            assert load[i] == pytest.approx(expected, rel=1e-12, abs=1e-15)
            assert flows[:, i].sum() == pytest.approx(Q, rel=1e-12, abs=1e-18)


def test_the_ideal_machine_keeps_its_static_load_and_flows():
    theta = np.linspace(0.0, 2 * math.pi, 50)
    static = windpump.load_torque_on_crank(SEED, theta)
    assert np.array_equal(windpump.load_torque_on_crank(SEED, theta, 7.0), static)
    flows = windpump.face_flows(theta, np.full(theta.shape, 2.0), SEED)[0]
    expected = [SEED.A * 2.0 * abs(dx_dtheta(t, SEED.R, SEED.L / SEED.R)) if t > math.pi else 0.0
                for t in theta]  # fmt: skip
    assert flows == pytest.approx(expected, rel=1e-13, abs=1e-18)


def test_a_hole_takes_the_load_away_at_rest_and_delivers_nothing_when_slow():
    holed = SEED.replace(d_leak=HOLE)
    theta = np.linspace(0.0, 2 * math.pi, 50)
    assert np.all(windpump.load_torque_on_crank(holed, theta, 0.0) == 0.0)
    assert np.all(windpump.face_flows(theta, np.full(theta.shape, 0.5), holed) == 0.0)
    # the static load (theta_dot omitted) stays the tight pump's
    assert np.array_equal(
        windpump.load_torque_on_crank(holed, theta), windpump.load_torque_on_crank(SEED, theta)
    )


@pytest.mark.parametrize("changes", [{}, {"m_r": 3.0}, {"m_r": 3.0, "cylinders": 2},
                                     {"d_leak": HOLE, "m_r": 1.0}, {"eta_t": 0.8, "m_r": 1.0}])  # fmt: skip
def test_rest_torque_is_N_of_the_issue(changes):
    d = SEED.replace(T_0=0.3, **changes)
    V = 6.0
    for theta in np.linspace(0.0, 2 * math.pi, 37):
        arms, slopes = faces(d, theta)
        static = 0.0 if d.d_leak > 0 else sum(d.rho_w * d.g * d.h * d.A * arm for arm in arms)
        expected = (d.eta_t * d.R_dagger * d.T_0 * (V / d.V_ref) ** 2
                    + d.m_r * d.g * sum(slopes) - static)  # fmt: skip
        assert float(rest_torque(d, theta, V=V)) == pytest.approx(expected, rel=1e-12, abs=1e-12)
        weight = d.m_r * d.g * sum(slopes)
        assert float(weight_torque(d, theta)) == pytest.approx(weight, rel=1e-12, abs=1e-14)


@pytest.mark.parametrize("changes", [{"m_r": 3.0}, {"m_r": 3.0, "d_leak": HOLE},
                                     {"m_r": 2.0, "cylinders": 3, "double_acting": True}])  # fmt: skip
def test_peak_load_torque_is_the_largest_load_at_rest(changes):
    d = SEED.replace(**changes)
    theta = np.linspace(0.0, 2 * math.pi, 20001)
    largest = max(-float(rest_torque(d, th)) for th in theta)  # T_0 = 0: N = -(load at rest)
    assert windpump.peak_load_torque(d) == pytest.approx(largest, rel=1e-6)
    assert windpump.peak_load_torque(d) >= largest


def test_a_leak_hole_lets_it_start():
    """The issue's preset: a torque at rest too small for the tight pump starts it with a hole."""
    tight = SEED.replace(T_0=0.2)
    assert not windpump.starts_from_rest(tight)
    assert windpump.starts_from_rest(tight.replace(d_leak=HOLE))
    # and a heavy rod without a hole: the weight resists the upstroke
    assert not windpump.starts_from_rest(tight.replace(d_leak=HOLE, m_r=20.0))


# ---------------------------------------------------------------- the averaged theory


@pytest.mark.parametrize("design", REAL + [SEED.replace(m_r=4.0, cylinders=2)], ids=range(6))
def test_revolution_means_by_quadrature(design):
    for speed in (0.2, 2.0, 9.0, 25.0):
        load, flow = mean_load(design, speed)
        assert float(load) == pytest.approx(reference_mean_load(design, speed), rel=1e-8)
        Q = revolution_mean(lambda th, s=speed: reference_load(design, th, s)[1], design)
        assert float(flow) == pytest.approx(Q, rel=1e-8, abs=1e-16)
    expected = reference_I_bar(design) - design.I_eff
    assert reciprocating_inertia(design) == pytest.approx(expected, rel=1e-10, abs=1e-16)


CLOSED = [
    SEED.replace(eta_t=0.85),
    SEED.replace(m_r=6.0, cylinders=2),
    SEED.replace(L_main=30.0, D_main=0.02),
    SEED.replace(L_main=60.0, D_main=0.02, eta_t=0.9, m_r=3.0, T_0=0.2),
    SEED.replace(L_main=20.0, D_main=0.04, cylinders=3, double_acting=True, h=1.0),
]


@pytest.mark.parametrize("design", CLOSED, ids=range(len(CLOSED)))
def test_closed_forms_with_chain_mass_and_pipe(design):
    """No hole: L-bar = M + c alpha^2; the roots, tau and margin against brentq, a central
    difference and minimize_scalar on F written here."""
    M = design.deliveries * design.rho_w * design.g * design.h * design.A * design.R / math.pi
    c = (reference_mean_load(design, 10.0) - M) / 100.0

    def F(a):
        return windmill_on_crank(design, a) - M - c * a * a

    upper = design.runaway_speed / design.R_dagger
    (high, falling) = reference_roots(F, upper)[-1]
    assert not falling
    # F is a quadratic: its other root (alpha-, maybe <= 0) from three of its values
    quadratic = np.polyfit([0.0, 0.5 * upper, upper], [F(0.0), F(0.5 * upper), F(upper)], 2)
    low = min(np.roots(quadratic).real)
    alpha_plus, alpha_minus = windpump.steady_speeds(design)
    assert alpha_plus == pytest.approx(high, rel=1e-10)
    assert alpha_minus == pytest.approx(low, rel=1e-8)
    slope = (F(high + 1e-4) - F(high - 1e-4)) / 2e-4
    assert windpump.time_constant(design) == pytest.approx(
        reference_I_bar(design) / -slope, rel=1e-7
    )
    best = optimize.minimize_scalar(lambda a: -windmill_on_crank(design, a) / (M + c * a * a),
                                    bounds=(0.0, upper), method="bounded", options={"xatol": 1e-10})  # fmt: skip
    assert windpump.stall_margin(design) == pytest.approx(-best.fun, rel=1e-9)
    flow = running_speeds(design).mean_flow
    assert float(flow) == pytest.approx(
        design.volume_per_revolution * high / (2 * math.pi), rel=1e-10
    )


HOLED = [
    SEED.replace(d_leak=HOLE),
    SEED.replace(d_leak=0.002, h=14.0),  # a dip: a crawl, a rising root and alpha+
    SEED.replace(d_leak=HOLE, T_0=0.2, L_main=30.0, D_main=0.02, m_r=5.0, eta_t=0.9),
    SEED.replace(d_leak=0.005, cylinders=2, double_acting=True, h=2.0),
]


@pytest.mark.parametrize("design", HOLED, ids=range(len(HOLED)))
def test_with_a_hole_by_quadrature_and_root_finding(design):
    def F(a):
        return windmill_on_crank(design, a) - reference_mean_load(design, a)

    upper = design.runaway_speed / design.R_dagger
    roots = reference_roots(F, upper, points=120)
    high, falling = roots[-1]
    assert not falling
    alpha_plus, alpha_minus = windpump.steady_speeds(design)
    assert alpha_plus == pytest.approx(high, rel=1e-9)
    rising = [a for a, up in roots if up]
    if rising:
        assert alpha_minus == pytest.approx(rising[-1], rel=1e-8)
    else:
        assert alpha_minus is None
    step = 1e-4 * high
    slope = (F(high + step) - F(high - step)) / (2 * step)
    assert windpump.time_constant(design) == pytest.approx(
        reference_I_bar(design) / -slope, rel=1e-6
    )
    assert windpump.stall_margin(design) == math.inf
    Q = revolution_mean(lambda th: reference_load(design, th, high)[1], design)
    assert windpump.steady_flow(design, design.V_ref) == pytest.approx(Q, rel=1e-8)


def test_a_dip_gives_a_crawl_below_the_rising_root():
    design = HOLED[1]
    _, alpha_minus = windpump.steady_speeds(design)
    crawl = float(windpump.spinup(design, [3000.0], 0.5 * alpha_minus)[0])
    F = lambda a: windmill_on_crank(design, a) - reference_mean_load(design, a)  # noqa: E731
    assert F(crawl) == pytest.approx(0.0, abs=1e-9)
    assert crawl < alpha_minus
    assert reference_load(design, 3 * math.pi / 2, crawl)[1] == 0.0  # all of it leaks back


@pytest.mark.parametrize(("design", "start"), [(HOLED[0], 3.0), (HOLED[0], 30.0), (HOLED[1], 5.0),
                                               (HOLED[1], 10.0), (HOLED[2], 0.0)])  # fmt: skip
def test_spinup_with_a_hole_against_solve_ivp(design, start):
    """The time integration (the spin-up's sigma quadrature and its inversion) against solve_ivp
    of I-bar alpha' = F(alpha), the mean load by the quadrature checked above."""
    I_bar = reference_I_bar(design)

    def rhs(_, y):
        return [
            (windmill_on_crank(design, y[0]) - float(mean_load(design, max(y[0], 0.0))[0])) / I_bar
        ]

    t = np.linspace(0.0, 900.0, 10)
    reference = integrate.solve_ivp(rhs, (0.0, 900.0), [start], t_eval=t, method="DOP853",
                                    rtol=1e-11, atol=1e-12).y[0]  # fmt: skip
    assert windpump.spinup(design, t, start) == pytest.approx(reference, rel=1e-6, abs=1e-9)


def test_stall_time_with_a_hole():
    holed = SEED.replace(d_leak=HOLE)
    assert windpump.averaged_stall_time(holed, 1.0) is None
    assert windpump.averaged_stall_time(holed, 0.0) == 0.0  # T_0 = 0: no torque at rest
    assert windpump.averaged_stall_time(holed.replace(T_0=0.1), 0.0) is None


# ---------------------------------------------------------------- limits and properties

designs = st.builds(
    lambda h, ratio, L_over_R, T_0, n, double: SEED.replace(h=h, R1=SEED.R0 * ratio,
                                                            L=SEED.R * L_over_R, T_0=T_0,
                                                            cylinders=n, double_acting=double),
    st.floats(0.5, 12.0), st.floats(2.0, 8.0), st.floats(1.3, 10.0), st.floats(0.0, 0.5),
    st.integers(1, 3), st.booleans(),
)  # fmt: skip


@given(designs)
def test_the_ideal_machine_keeps_the_papers_closed_forms(design):
    """Eqs. 21, 22, 25 generalised, written here: the real theory's ideal limit."""
    M = design.deliveries * design.load_torque / math.pi
    speeds = running_speeds(design)
    margin = design.R_dagger * design.T_m / M
    assert float(speeds.margin) == pytest.approx(margin, rel=1e-13)
    if margin <= 1.0:
        return
    p = design.omega_m / design.R_dagger
    spread = design.R_dagger * (design.T_m - design.T_0)
    delta = math.sqrt(p * p * (design.R_dagger * design.T_m - M) / spread)
    k = design.R_dagger**3 * (design.T_m - design.T_0) / (design.I_eff * design.omega_m**2)
    assert float(speeds.alpha_plus) == pytest.approx(p + delta, rel=1e-12)
    assert float(speeds.tau) == pytest.approx(1 / (2 * k * delta), rel=1e-12)
    # and the CycleMean attributes are unchanged by the new fields at their defaults
    mean = cycle_mean(design)
    assert float(mean.alpha_plus) == float(speeds.alpha_plus)
    assert mean.I_bar == design.I_eff


@given(designs, st.floats(0.0005, 0.006), st.floats(0.0, 60.0), st.floats(0.6, 1.0))
def test_the_real_machine_delivers_no_more_than_it_sweeps_or_is_given(
    design, d_leak, L_main, eta_t
):
    """At its running speed the real pump delivers at most its swept volume, and lifts water
    with at most the power the windmill gives the crank (the ideal machine: both equalities)."""
    real = design.replace(d_leak=min(d_leak, 0.9 * design.bore), L_main=L_main, D_main=0.02,
                          eta_t=eta_t, m_r=2.0)  # fmt: skip
    for V in (3.0, 5.0, 8.0):
        speeds = running_speeds(real, V=V)
        alpha, flow = float(speeds.alpha_plus), float(speeds.mean_flow)
        assert flow <= real.volume_per_revolution * alpha / (2 * math.pi) * (1 + 1e-12)
        water = real.rho_w * real.g * real.h * flow
        assert water <= windmill_on_crank(real, alpha, V / real.V_ref) * alpha * (1 + 1e-9)
    assert windpump.stall_margin(real) == math.inf  # a leak hole never stalls


def test_a_hole_delivers_less_than_the_tight_pump_at_the_seeds_wind():
    holed = SEED.replace(d_leak=HOLE)
    for V in (5.0, 8.0):
        assert windpump.steady_flow(holed, V) < windpump.steady_flow(SEED, V)


def test_water_per_day_with_a_hole_is_the_weibull_mean_of_the_flow():
    design = SEED.replace(d_leak=HOLE, T_0=0.2, L_main=30.0, D_main=0.02)
    c = 5.0 / math.gamma(1.5)
    V_stop, V_start = windpump.wind_thresholds(design)
    assert V_stop == 0.0

    def expected(V_from):
        def f(V):
            density = 2 / c * (V / c) * math.exp(-((V / c) ** 2))
            return float(windpump.steady_flow(design, V)) * density

        return 86400 * integrate.quad(f, V_from, 60.0, limit=200, epsrel=1e-8)[0]

    low, high = windpump.water_per_day(design, 5.0)
    assert high == pytest.approx(expected(V_stop), rel=2e-3)
    assert low == pytest.approx(expected(V_start), rel=2e-3)


def test_wind_thresholds_with_a_pipe():
    """V_stop: the wind where the margin with a pipe is 1 (the margin by minimize_scalar)."""
    design = SEED.replace(L_main=60.0, D_main=0.015, h=8.0, T_0=0.1)
    V_stop, V_start = windpump.wind_thresholds(design)
    M = design.deliveries * design.load_torque / math.pi
    c = (reference_mean_load(design, 10.0) - M) / 100.0
    s = V_stop / design.V_ref
    upper = s * design.runaway_speed / design.R_dagger
    best = optimize.minimize_scalar(lambda a: -windmill_on_crank(design, a, s) / (M + c * a * a),
                                    bounds=(0.0, upper), method="bounded", options={"xatol": 1e-12})  # fmt: skip
    assert -best.fun == pytest.approx(1.0, rel=1e-8)
    peak = max(
        -float(rest_torque(design.replace(T_0=0.0), th))
        for th in np.linspace(0, 2 * math.pi, 20001)
    )
    assert V_start == pytest.approx(
        design.V_ref * math.sqrt(peak / (design.R_dagger * design.T_0)), rel=1e-5
    )


def test_design_map_follows_the_real_theory():
    design = SEED.replace(L_main=30.0, D_main=0.02, eta_t=0.9)
    ratios, heads = np.linspace(1.0, 12.0, 40), np.array([2.0, 6.0])
    m = windpump.design_map(design, ratios, heads)
    for i, h in enumerate(heads):
        for j, ratio in enumerate(ratios[::7]):
            point = design.replace(R1=design.R0 * ratio, h=h)
            assert m.margin[i, 7 * j] == pytest.approx(windpump.stall_margin(point), rel=1e-12)
    boundary = m.stall_gear_ratio
    for h, ratio in zip(heads, boundary, strict=True):
        at = design.replace(R1=design.R0 * ratio, h=h)
        assert windpump.stall_margin(at) == pytest.approx(1.0, rel=1e-9)
    holed = windpump.design_map(SEED.replace(d_leak=HOLE), ratios[::8], heads)
    assert np.all(np.isinf(holed.margin))
    point = SEED.replace(d_leak=HOLE, R1=SEED.R0 * ratios[8], h=6.0)
    assert holed.mean_flow[1, 1] == pytest.approx(
        windpump.steady_flow(point, point.V_ref), rel=1e-12
    )


# ---------------------------------------------------------------- bad input


def test_bad_input_names_the_parameter():
    with pytest.raises(ParameterError, match="theta_dot"):
        windpump.load_torque_on_crank(SEED, 1.0, -1.0)
    with pytest.raises(ParameterError, match="V"):
        rest_torque(SEED, 1.0, V=-2.0)
    with pytest.raises(ParameterError, match="d_leak"):
        cycle_mean(SEED.replace(d_leak=HOLE))
    with pytest.raises(ParameterError, match="theta"):
        windpump.face_flows([math.nan], [1.0], SEED)
    with pytest.raises(ParameterError, match="t"):
        windpump.spinup(SEED.replace(d_leak=HOLE), [-1.0], 3.0)


@pytest.mark.parametrize("design", [SEED.replace(eta_t=0.7), CLOSED[2], HOLED[0]], ids=range(3))
def test_stall_sides_keep_the_margin_as_their_ratio(design):
    windmill, load = windpump.stall_sides(design)
    assert windmill == pytest.approx(design.eta_t * design.Tm_dagger, rel=1e-15)
    if load:
        assert windmill / load == pytest.approx(windpump.stall_margin(design), rel=1e-12)
    else:
        assert windpump.stall_margin(design) == math.inf


def test_a_leaky_pumps_flow_over_a_records_many_winds_is_its_flow_at_each():
    """More distinct winds than site.LEAK_TABLE are interpolated on a table (a quadrature per
    wind took 79 s for a day): within 1e-3 of the largest flow of the one-by-one values."""
    from windpump.sites.site import LEAK_TABLE

    design = windpump.Design.seed_example().replace(T_0=0.25, d_leak=0.003)
    winds = np.linspace(0.05, 12.0, 3 * LEAK_TABLE)
    table = windpump.steady_flow(design, winds)
    one_by_one = np.array([windpump.steady_flow(design, float(v)) for v in winds[::37]])
    assert np.max(np.abs(table[::37] - one_by_one)) <= 1e-3 * one_by_one.max()


@given(
    ratio=st.floats(0.5, 10.0),
    d_leak=st.floats(0.0005, 0.01),
    T_0=st.sampled_from([0.0, 0.25]),
)
@example(ratio=5.5, d_leak=0.003, T_0=0.0)  # F(runaway) was 4e-17 > 0: no root found
def test_a_leaky_pump_with_no_head_runs_at_the_windmills_runaway_speed(ratio, d_leak, T_0):
    """No head and no pipe: no load at any speed (the hole passes nothing against no head), so
    alpha+ is where the windmill's torque vanishes, T(R+ alpha) = 0 (Eq. 11): its runaway speed
    over R+. F is zero there give or take round-off, which left alpha+ NaN at some ratios."""
    design = SEED.replace(d_leak=d_leak, h=0.0, T_0=T_0, R1=SEED.R0 * ratio)
    alpha_plus, _alpha_minus = windpump.steady_speeds(design)
    assert alpha_plus == pytest.approx(design.runaway_speed / ratio, rel=1e-12)
    assert math.isfinite(windpump.time_constant(design))


@pytest.mark.parametrize("design", REAL + HOLED + CLOSED[:1], ids=range(len(REAL + HOLED) + 1))
def test_the_load_line_is_the_real_load_reflected_and_meets_the_curve_at_the_operating_point(
    design,
):
    """Eq. (5) of the real machine: the mean load torque on the crank (by quadrature here) at
    omega / R+, reflected through the chain, times omega; the operating point (alpha+ and
    alpha-, from steady_speeds) lies on it: the Operating point view's dot on its line."""
    for omega in (1.0, 20.0, 70.0):
        expected = reference_mean_load(design, omega / design.R_dagger) * omega
        expected /= design.eta_t * design.R_dagger
        # (the reference's adaptive quadrature across a hole's kinks: ~3e-8)
        assert float(windpump.load_power(design, omega)) == pytest.approx(expected, rel=1e-7)
    op = windpump.operating_point(design)
    assert float(windpump.load_power(design, op.omega)) == pytest.approx(op.power, rel=1e-9)
    if math.isfinite(op.omega_unstable) and op.omega_unstable > 0.0:
        unstable = float(windpump.load_power(design, op.omega_unstable))
        assert unstable == pytest.approx(op.power_unstable, rel=1e-8)
