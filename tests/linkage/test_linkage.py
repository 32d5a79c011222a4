"""Loop closure by Newton-Raphson against closed forms: four-bars, the double loop, the slider-crank."""

from __future__ import annotations

import inspect
import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from linkage_reference import half_angle

import windpump
from windpump import linkage, studies
from windpump.linkage import NoClosure

TWO_PI = 2 * math.pi
CRANK_ROCKER = (1.0, 3.0, 2.5, 3.0)  # Grashof, shortest link the input: it turns fully
DOUBLE_CRANK = (3.0, 3.5, 3.0, 1.0)  # Grashof, shortest link the ground: it turns fully too
TRIPLE_ROCKER = (2.0, 2.5, 2.0, 3.0)  # non-Grashof: the input rocks between limits


def angle_gap(a, b):
    return abs(math.remainder(a - b, TWO_PI))


def assert_same_angles(found, expected, tol=1e-10):
    for a, b in zip(found, expected, strict=True):
        assert angle_gap(a, b) < tol, (found, expected)


# -- the four-bar ---------------------------------------------------------------------------------


@pytest.mark.parametrize("branch", [1, -1])
@pytest.mark.parametrize(
    "links", [CRANK_ROCKER, DOUBLE_CRANK], ids=["crank-rocker", "double-crank"]
)
def test_a_grashof_sweep_follows_one_branch_all_the_way_round(links, branch):
    assert linkage.is_grashof(*links)
    theta1 = np.radians(np.arange(0.0, 720.5, 1.0))  # twice round: the branch closes on itself
    start = linkage.branch_guess(*links, theta1[0], branch=branch)
    swept = linkage.sweep(
        [linkage.four_bar_loop(*links)],
        "theta1",
        theta1,
        {"theta2": start[0], "theta3": start[1]},
    )
    assert swept.stop is None and len(swept) == len(theta1)
    for t1, t2, t3 in zip(theta1, swept.values["theta2"], swept.values["theta3"], strict=True):
        assert_same_angles((t2, t3), half_angle(*links, t1)[branch])
    assert np.all(np.abs(np.diff(swept.values["theta3"])) < 0.1)  # continuous, not wrapped


@pytest.mark.parametrize("branch", [1, -1])
@pytest.mark.parametrize("direction", [1, -1])
def test_a_non_grashof_sweep_ends_where_its_branch_ends(branch, direction):
    links = TRIPLE_ROCKER
    assert not linkage.is_grashof(*links)
    step = math.radians(0.5)
    theta1 = direction * step * np.arange(0, 721)
    start = linkage.branch_guess(*links, 0.0, branch=branch)
    swept = linkage.sweep(
        [linkage.four_bar_loop(*links)], "theta1", theta1, {"theta2": start[0], "theta3": start[1]}
    )
    for t1, t2, t3 in zip(*(swept.values[n] for n in ("theta1", "theta2", "theta3")), strict=True):
        assert_same_angles((t2, t3), half_angle(*links, t1)[branch])
    # The input's limit: |A - D| = r2 + r3, i.e. r1^2 + r6^2 - 2 r1 r6 cos(theta1) = (r2 + r3)^2
    r1, r2, r3, r6 = links
    limit = math.acos((r1**2 + r6**2 - (r2 + r3) ** 2) / (2 * r1 * r6))
    last = abs(swept.values["theta1"][-1])
    assert limit - step <= last < limit
    assert isinstance(swept.stop, NoClosure) and swept.stop.reason == NoClosure.CANNOT_CLOSE
    assert half_angle(*links, direction * (last + step)) == {}
    assert f"theta1 = {direction * (last + step):.6g}" in str(swept.stop)


@given(
    links=st.tuples(*[st.floats(0.2, 5.0)] * 4),
    theta1=st.floats(-10.0, 10.0),
    phi6=st.floats(-math.pi, math.pi),
    branch=st.sampled_from([1, -1]),
)
def test_four_bar_matches_the_closed_form_on_the_branch_of_its_guess(links, theta1, phi6, branch):
    expected = half_angle(*links, theta1, phi6)
    guess = linkage.branch_guess(*links, theta1, phi6, branch)
    if not expected:
        with pytest.raises(NoClosure):
            linkage.four_bar(*links, theta1, phi6, guess=guess)
        return
    # Away from a dead centre, where the closed form itself loses digits.
    assume(set(expected) == {1, -1})
    theta2, theta3 = expected[branch]
    assume(abs(math.sin(theta3 - theta2)) > 1e-3)
    found = linkage.four_bar(*links, theta1, phi6, guess=guess)
    assert all(0 <= angle < TWO_PI for angle in found)
    assert_same_angles(found, expected[branch], tol=1e-9)


@given(
    links=st.tuples(*[st.floats(0.2, 5.0)] * 4),
    theta1=st.floats(-10.0, 10.0),
    branch=st.sampled_from([1, -1]),
    nudge=st.tuples(st.floats(-0.5, 0.5), st.floats(-0.5, 0.5)),
)
def test_a_rough_guess_stays_on_its_branch(links, theta1, branch, nudge):
    expected = half_angle(*links, theta1)
    assume(set(expected) == {1, -1})
    exact = expected[branch]
    assume(
        abs(math.sin(exact[1] - exact[0])) > 0.3
    )  # a sketch half a radian off, not near a toggle
    guess = (exact[0] + nudge[0], exact[1] + nudge[1])
    assume(linkage.four_bar_branch(*guess) == branch)
    try:
        found = linkage.four_bar(*links, theta1, guess=guess)
    except NoClosure as error:  # never the other assembly in silence
        assert error.reason == NoClosure.NO_CONVERGENCE and "other assembly" in str(error)
        assume(False)
    else:
        assert_same_angles(found, exact)


def test_the_default_guess_is_branch_plus_one():
    theta2, theta3 = linkage.four_bar(*CRANK_ROCKER, theta1=1.0)
    assert linkage.four_bar_branch(theta2, theta3) == 1
    assert_same_angles((theta2, theta3), half_angle(*CRANK_ROCKER, 1.0)[1])


def test_newton_raphson_converges_quadratically():
    links, theta1 = CRANK_ROCKER, 1.0
    exact = np.array(half_angle(*links, theta1)[1])
    closed = linkage.solve_loop(
        linkage.four_bar_loop(*links),
        {"theta1": theta1},
        {"theta2": exact[0] + 0.4, "theta3": exact[1] - 0.3},
    )
    errors = [
        np.max(np.abs(np.remainder(q - exact + math.pi, TWO_PI) - math.pi)) for q in closed.iterates
    ]
    assert errors[-1] < 1e-14
    # Each error about the square of the last, once near: order log(e_k+1)/log(e_k) -> 2
    near = [
        (a, b) for a, b in zip(errors[:-1], errors[1:], strict=True) if 1e-9 < a < 0.1 and b > 1e-14
    ]
    assert len(near) >= 2
    for before, after in near:
        assert after < 5 * before**2
        assert math.log(after) / math.log(before) > 1.8
    # The residual history shows it too, and it ends at round-off
    residuals = closed.residuals
    assert residuals[-1] < 1e-15
    assert any(
        1e-9 < a < 1e-3 and b < 10 * a**2
        for a, b in zip(residuals[:-1], residuals[1:], strict=True)
    )


def test_the_jacobian_is_analytic():
    loop = linkage.four_bar_loop(*CRANK_ROCKER, phi6=0.3)
    values = {"theta1": 0.7, "theta2": 0.4, "theta3": 1.9}
    J = linkage.jacobian(loop, values, ("theta2", "theta3"))
    r2, r3 = CRANK_ROCKER[1], CRANK_ROCKER[2]
    # The seed's step 2, with its slip corrected: dF2/dtheta3 = -r3 cos theta3
    expected = [
        [-r2 * math.sin(0.4), r3 * math.sin(1.9)],
        [r2 * math.cos(0.4), -r3 * math.cos(1.9)],
    ]
    np.testing.assert_allclose(J, expected, rtol=1e-15)
    h = 1e-6
    for k, name in enumerate(("theta2", "theta3")):
        up, down = {**values, name: values[name] + h}, {**values, name: values[name] - h}
        slope = (linkage.residual(loop, up) - linkage.residual(loop, down)) / (2 * h)
        np.testing.assert_allclose(J[:, k], slope, atol=1e-9)


# -- when it does not close -----------------------------------------------------------------------


def test_links_too_short_cannot_close():
    with pytest.raises(NoClosure) as caught:
        linkage.four_bar(1.0, 1.0, 1.0, 5.0, theta1=0.25)
    error = caught.value
    assert isinstance(error, ValueError) and error.reason == NoClosure.CANNOT_CLOSE
    assert error.where == {"theta1": 0.25} and error.iteration is None
    assert "theta1 = 0.25" in str(error) and "r2 = 1" in str(error) and "r3 = 1" in str(error)


def test_one_link_too_long_cannot_close():
    with pytest.raises(NoClosure, match="too unequal") as caught:
        linkage.four_bar(1.0, 5.0, 1.0, 2.0, theta1=0.0)
    assert caught.value.reason == NoClosure.CANNOT_CLOSE


def test_a_dead_centre_is_a_singular_jacobian():
    # theta1 = 0: A = (1, 0), D = (2, 0), |AD| = 1 = r2 - r3, so coupler and output lie in line
    with pytest.raises(NoClosure, match="in line") as caught:
        linkage.four_bar(1.0, 2.0, 1.0, 2.0, theta1=0.0)
    assert caught.value.reason == NoClosure.SINGULAR


def test_a_guess_on_a_dead_centre_is_a_singular_jacobian():
    with pytest.raises(NoClosure, match="iterate 0") as caught:
        linkage.four_bar(*CRANK_ROCKER, theta1=1.0, guess=(0.5, 0.5))  # coupler along the output
    assert caught.value.reason == NoClosure.SINGULAR and caught.value.iteration == 0


def test_a_spent_budget_is_no_convergence():
    loop = linkage.four_bar_loop(*CRANK_ROCKER)
    with pytest.raises(NoClosure, match="2 iterations") as caught:
        linkage.solve_loop(loop, {"theta1": 1.0}, {"theta2": 2.5, "theta3": 4.0}, max_iterations=2)
    assert caught.value.reason == NoClosure.NO_CONVERGENCE


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda: linkage.four_bar(1.0, -2.0, 1.0, 1.0, 0.0), "r2"),
        (lambda: linkage.four_bar(1.0, 2.0, 1.0, 1.0, math.nan), "theta1"),
        (lambda: linkage.four_bar(1.0, 2.0, 1.0, 0.0, 0.0), "r6"),
        (lambda: linkage.slider_crank(0.0, R=0.0, L=1.0), "R"),
        (lambda: linkage.branch_guess(1.0, 1.0, 1.0, 1.0, 0.0, branch=0), "branch"),
        (lambda: linkage.Vector(1.0, 0.0, sign=2), "sign"),
    ],
)
def test_bad_input_names_the_parameter(call, name):
    with pytest.raises(windpump.ParameterError) as caught:
        call()
    assert caught.value.name == name and str(caught.value).startswith(f"{name} = ")


def test_a_loop_needs_exactly_two_unknowns():
    loop = linkage.four_bar_loop(*CRANK_ROCKER)
    with pytest.raises(ValueError, match="has 3"):
        linkage.solve_loop(loop, {}, {"theta1": 0, "theta2": 0, "theta3": 0})
    with pytest.raises(windpump.ParameterError, match="theta3"):
        linkage.solve_loop(loop, {"theta1": 1.0}, {"theta2": 0.5})


# -- chained loops --------------------------------------------------------------------------------


SIX_BAR = dict(r1=1.0, r2=3.0, r3=2.5, r6=3.0, r3p=1.5, r4=2.5, r5=2.0, r6p=2.5, beta=0.4)


def test_the_double_loop_is_solved_loop_by_loop():
    loops = linkage.watt_six_bar_loops(**SIX_BAR)
    theta1 = np.radians(np.arange(0.0, 360.5, 2.0))
    first = half_angle(1.0, 3.0, 2.5, 3.0, 0.0)[1]
    d = SIX_BAR
    # Loop 2 is a four-bar driven from D by link 3's second arm at theta3 + beta
    second = half_angle(d["r3p"], d["r4"], d["r5"], d["r6p"], first[1] + d["beta"])[1]
    guess = dict(zip(("theta2", "theta3", "theta4", "theta5"), (*first, *second), strict=True))
    swept = linkage.sweep(loops, "theta1", theta1, guess)
    assert swept.stop is None
    v = swept.values
    for k, t1 in enumerate(theta1):
        one = half_angle(1.0, 3.0, 2.5, 3.0, t1)[1]
        assert_same_angles((v["theta2"][k], v["theta3"][k]), one)
        two = half_angle(d["r3p"], d["r4"], d["r5"], d["r6p"], v["theta3"][k] + d["beta"])[1]
        assert_same_angles((v["theta4"][k], v["theta5"][k]), two)
    # Drawn from D, loop 2 closes at D again; loop 1 closes at O
    values = {name: v[name][10] for name in v}
    D = linkage.joints(loops[0], values)[3]
    np.testing.assert_allclose(linkage.joints(loops[0], values)[-1], [0, 0], atol=1e-12)
    np.testing.assert_allclose(linkage.joints(loops[1], values, origin=D)[-1], D, atol=1e-12)


# -- the pump's slider-crank ----------------------------------------------------------------------


@pytest.mark.parametrize("L_over_R", [1.05, 1.5, 3.75, 10.0])
def test_the_slider_crank_loop_is_eq_1(L_over_R):
    R = 0.04
    for theta in np.linspace(-2 * math.pi, 4 * math.pi, 301):
        x, theta_c = linkage.slider_crank(theta, R, L_over_R * R)
        assert x == pytest.approx(
            float(windpump.piston_position(theta, R, L_over_R * R)), abs=1e-14
        )
        assert theta_c == pytest.approx(float(windpump.rod_angle(theta, L_over_R)), abs=1e-12)


def test_the_slider_crank_other_branch_puts_the_piston_behind_the_crank():
    R, L, theta = 0.04, 0.15, 0.7
    x, theta_c = linkage.slider_crank(theta, R, L, guess=(math.pi, L - R))
    s = L + R - x  # distance of the pin from the crank centre: R cos theta - sqrt(L^2 - R^2 sin^2)
    assert s == pytest.approx(R * math.cos(theta) - math.sqrt(L**2 - (R * math.sin(theta)) ** 2))
    assert math.sin(theta_c) == pytest.approx(math.sin(theta) * R / L)  # as on the usual branch


def test_a_rod_shorter_than_the_crank_closes_only_near_the_axis():
    R, L = 1.0, 0.5
    x, _ = linkage.slider_crank(0.2, R, L)
    assert x == pytest.approx(L + R - (R * math.cos(0.2) + math.sqrt(L**2 - math.sin(0.2) ** 2)))
    with pytest.raises(NoClosure, match="cannot reach") as caught:
        linkage.slider_crank(math.pi / 2, R, L)
    assert caught.value.where == {"theta": math.pi / 2}


@pytest.mark.parametrize("tol", [0.0, -1e-9, math.nan, math.inf, "small"])
def test_a_bad_tolerance_is_named(tol):
    from windpump.errors import ParameterError

    with pytest.raises(ParameterError, match="^tol = "):
        linkage.four_bar(1.0, 3.0, 2.5, 3.0, theta1=1.0, tol=tol)


@pytest.mark.parametrize("guess", [(0.5, 1.5), (5.5, 4.0)])
def test_a_closure_labels_its_assembly_as_four_bar_branch_does(guess):
    closed = linkage.solve_loop(
        linkage.four_bar_loop(1.0, 3.0, 2.5, 3.0),
        {"theta1": 1.0},
        dict(zip(("theta2", "theta3"), guess, strict=True)),
    )
    assert closed.branch == linkage.four_bar_branch(closed["theta2"], closed["theta3"]) != 0


# -- names: the old ones kept, the studies' at the top ------------------------------------------

OLD_NAMES = """Vector Loop Closure names_in residual jacobian joints solve_loop solve_loops Sweep sweep
four_bar_loop four_bar branch_guess four_bar_branch is_grashof watt_six_bar_loops slider_crank_loop
slider_crank SliderCrankPose slider_crank_pose NoClosure TOL MAX_ITERATIONS MAX_STEP DEAD_CENTRE
ROUND_OFF BLOCKED_HALVINGS MAX_HALVINGS""".split()


def test_the_old_linkage_names_stay_importable():
    for name in OLD_NAMES:
        assert hasattr(linkage, name), name
    from windpump.linkage import Sweep, sweep  # as code written before the subpackage did

    assert Sweep is linkage.BranchTrace and sweep is linkage.trace_branch
    parameters = inspect.signature(sweep).parameters
    assert list(parameters) == ["loops", "input", "inputs", "guess", "known", "tol"]
    assert parameters["known"].default is None and parameters["tol"].default == linkage.TOL


def test_the_top_level_sweep_is_the_studies():
    assert windpump.Sweep is studies.Sweep and windpump.sweep is studies.sweep
    assert windpump.Sweep is not linkage.Sweep and windpump.sweep is not linkage.sweep


def test_the_old_sweep_still_follows_a_branch():
    start = linkage.branch_guess(*CRANK_ROCKER, 0.0)
    theta1 = np.radians(np.arange(0.0, 91.0, 5.0))
    swept = linkage.sweep(
        [linkage.four_bar_loop(*CRANK_ROCKER)],
        "theta1",
        theta1,
        dict(theta2=start[0], theta3=start[1]),
    )
    assert isinstance(swept, linkage.Sweep) and swept.stop is None and len(swept) == len(theta1)
    assert_same_angles(
        (swept.values["theta2"][-1], swept.values["theta3"][-1]),
        half_angle(*CRANK_ROCKER, theta1[-1])[1],
    )


# -- Grashof's classes ----------------------------------------------------------------------------

LENGTHS = st.floats(0.2, 5.0)


def grashof_by_hand(r1, r2, r3, r6):
    """Grashof's inequality and Barker's table, written out: the class of a four-bar."""
    s, p, q, l = sorted((r1, r2, r3, r6))  # noqa: E741
    if s + l > p + q:
        return "triple-rocker"
    shortest = min(r1, r2, r3, r6)
    if r6 == shortest:
        return "double-crank"
    if r1 == shortest:
        return "crank-rocker"
    return "rocker-crank" if r3 == shortest else "double-rocker"


@pytest.mark.parametrize(
    "links, expected",
    [
        (CRANK_ROCKER, "crank-rocker"),
        (DOUBLE_CRANK, "double-crank"),
        (TRIPLE_ROCKER, "triple-rocker"),
        ((3.0, 3.5, 1.0, 3.0), "rocker-crank"),
        ((3.0, 1.0, 3.5, 3.0), "double-rocker"),
        ((1.0, 2.0, 2.0, 1.0), "change-point"),  # a parallelogram: 1 + 2 = 2 + 1
        ((0.15, 0.35, 0.3, 0.2), "change-point"),  # 0.15 + 0.35 = 0.3 + 0.2, to round-off
    ],
)
def test_grashof_classes(links, expected):
    assert linkage.grashof_class(*links) == expected
    assert linkage.is_grashof(*links) == (expected != "triple-rocker")


@given(links=st.tuples(LENGTHS, LENGTHS, LENGTHS, LENGTHS))
def test_grashof_class_is_the_inequality(links):
    s, p, q, l = sorted(links)  # noqa: E741
    assume(abs(s + l - p - q) > 1e-9)
    assert linkage.grashof_class(*links) == grashof_by_hand(*links)


@given(links=st.tuples(LENGTHS, LENGTHS, LENGTHS, LENGTHS))
def test_the_input_turns_fully_where_the_links_span_every_gap(links):
    # |AD| runs from |r1 - r6| to r1 + r6 as theta1 turns; the dyad r2, r3 spans |r2 - r3| to r2 + r3
    r1, r2, r3, r6 = links
    margins = (abs(r1 - r6) - abs(r2 - r3), r2 + r3 - r1 - r6)
    assume(all(abs(margin) > 1e-9 for margin in margins))
    s, p, q, l = sorted(links)  # noqa: E741
    assume(abs(s + l - p - q) > 1e-9)
    assert linkage.input_turns_fully(*links) == all(margin > 0 for margin in margins)


# -- the mechanism assembled, followed and traced (the Mechanisms tab's decisions) ----------------


def four_bar_position(links, theta1, branch):
    theta2, theta3 = half_angle(*links, theta1)[branch]
    return {"theta1": theta1, "theta2": theta2, "theta3": theta3}


def assert_closes(loops, values, tol=1e-12):
    for loop in loops:
        size = sum(abs(v.length) for v in loop if not isinstance(v.length, str))
        assert np.hypot(*linkage.residual(loop, values)) < tol * size


@given(
    links=st.tuples(LENGTHS, LENGTHS, LENGTHS, LENGTHS),
    theta1=st.floats(-7.0, 7.0),
    branch=st.sampled_from([1, -1]),
)
def test_assemble_closes_on_the_branch_asked_for(links, theta1, branch):
    expected = half_angle(*links, theta1)
    assume(set(expected) == {1, -1})
    theta2, theta3 = expected[branch]
    assume(abs(math.sin(theta3 - theta2)) > 1e-3)
    loops = [linkage.four_bar_loop(*links)]
    (closed,) = linkage.assemble(loops, {"theta1": theta1}, [branch])
    assert closed.branch == branch
    assert_same_angles((closed["theta2"], closed["theta3"]), expected[branch], tol=1e-9)


@pytest.mark.parametrize("branches", [(1, 1), (1, -1), (-1, 1), (-1, -1)])
def test_the_six_bar_assembles_each_loop_on_its_branch(branches):
    d = SIX_BAR
    loops = linkage.watt_six_bar_loops(**d)
    closed = linkage.assemble(loops, {"theta1": 1.0}, branches)
    v = closed[-1].values
    one = half_angle(1.0, 3.0, 2.5, 3.0, 1.0)[branches[0]]
    two = half_angle(d["r3p"], d["r4"], d["r5"], d["r6p"], one[1] + d["beta"])[branches[1]]
    assert_same_angles((v["theta2"], v["theta3"], v["theta4"], v["theta5"]), (*one, *two))
    assert tuple(c.branch for c in closed) == branches
    assert_closes(loops, v)


def test_the_six_bars_joints_are_its_links_apart():
    d = SIX_BAR
    loops = linkage.watt_six_bar_loops(**d)
    p = linkage.mechanism_joints(loops, linkage.assemble(loops, {"theta1": 0.3}, (1, 1))[-1].values)
    assert list(p) == list("OABDCFE")
    pairs = {("O", "A"): 1.0, ("A", "B"): 3.0, ("B", "D"): 2.5, ("D", "C"): 1.5, ("C", "F"): 2.5}
    pairs.update({("F", "E"): 2.0, ("D", "E"): 2.5, ("O", "D"): 3.0})
    for (a, b), length in pairs.items():
        assert math.dist(p[a], p[b]) == pytest.approx(length, rel=1e-12), (a, b)
    # B, D and C are one rigid link: the angle BDC is beta
    arm, output = p["C"] - p["D"], p["B"] - p["D"]
    turn = math.atan2(arm[1], arm[0]) - math.atan2(output[1], output[0])
    assert angle_gap(turn, d["beta"]) < 1e-12
    assert linkage.output_joint(loops) == "F"


@pytest.mark.parametrize("branch", [1, -1])
@pytest.mark.parametrize("target", [3.0, -2.0, 9.0])
def test_follow_branch_moves_a_crank_rocker_along_its_branch(branch, target):
    loops = [linkage.four_bar_loop(*CRANK_ROCKER)]
    moved = linkage.follow_branch(loops, four_bar_position(CRANK_ROCKER, 0.5, branch), target)
    v = moved.closures[-1].values
    assert moved.stop is None and v["theta1"] == target
    assert_same_angles((v["theta2"], v["theta3"]), half_angle(*CRANK_ROCKER, target)[branch])
    assert moved.closures[-1].branch == branch
    # Closed from the position one step before: a few Newton steps, not a cold start
    assert 1 <= moved.closures[-1].iterations <= 4


@pytest.mark.parametrize("direction", [1, -1])
def test_follow_branch_stops_at_the_end_of_a_rocking_input(direction):
    r1, r2, r3, r6 = TRIPLE_ROCKER
    limit = math.acos((r1**2 + r6**2 - (r2 + r3) ** 2) / (2 * r1 * r6))
    loops = [linkage.four_bar_loop(*TRIPLE_ROCKER)]
    moved = linkage.follow_branch(loops, four_bar_position(TRIPLE_ROCKER, 0.0, 1), direction * 3.0)
    reached = moved.closures[-1]["theta1"]
    assert limit - linkage.STEP <= abs(reached) < limit and reached * direction > 0
    assert isinstance(moved.stop, NoClosure) and moved.stop.reason == NoClosure.CANNOT_CLOSE
    assert_closes(loops, moved.closures[-1].values)


def test_the_coupler_path_of_a_crank_rocker_is_a_closed_curve_of_b():
    loops = [linkage.four_bar_loop(*CRANK_ROCKER)]
    position = four_bar_position(CRANK_ROCKER, 1.0, -1)
    path = linkage.coupler_path(loops, position)
    theta1 = 1.0 + linkage.STEP * np.arange(-180, 181)
    assert path.shape == (361, 2)
    r1, r2, r3, r6 = CRANK_ROCKER
    for point, t1 in zip(path, theta1, strict=True):
        theta2, _ = half_angle(*CRANK_ROCKER, t1)[-1]
        B = r1 * np.array([math.cos(t1), math.sin(t1)]) + r2 * np.array(
            [math.cos(theta2), math.sin(theta2)]
        )
        np.testing.assert_allclose(point, B, atol=1e-10)
        assert math.dist(point, (r6, 0.0)) == pytest.approx(r3)
    np.testing.assert_allclose(path[0], path[-1], atol=1e-10)  # a turn back meets a turn on
    # Continuous: B moves at most (r1 + r2 dtheta2/dtheta1) per step, well under a link
    assert np.max(np.hypot(*np.diff(path, axis=0).T)) < 0.5


def test_the_reach_of_a_rocking_input_is_between_its_limits():
    r1, r2, r3, r6 = TRIPLE_ROCKER
    limit = math.acos((r1**2 + r6**2 - (r2 + r3) ** 2) / (2 * r1 * r6))
    loops = [linkage.four_bar_loop(*TRIPLE_ROCKER)]
    reach = linkage.branch_reach(loops, four_bar_position(TRIPLE_ROCKER, 0.2, 1))
    theta1 = reach["theta1"]
    assert np.all(np.diff(theta1) > 0)  # in the input's order
    assert (
        limit - linkage.STEP <= theta1[-1] < limit and -limit < theta1[0] <= -limit + linkage.STEP
    )
    for k in range(len(theta1)):
        expected = half_angle(*TRIPLE_ROCKER, theta1[k])[1]
        assert_same_angles((reach["theta2"][k], reach["theta3"][k]), expected)
    assert np.all(np.abs(np.diff(reach["theta3"])) < 0.2)  # one branch, no jump to the other


# -- bad input: every argument of the public functions, by name ----------------------------------

NOT_NUMBERS = st.one_of(
    st.sampled_from([math.nan, math.inf, -math.inf, None, True, "1.0", b"1", [1.0], (1.0,), {}]),
    st.text(max_size=4),
    st.lists(st.floats(allow_nan=False), max_size=3),
)
BAD = {
    # link lengths [m]: from 1e-100 to 1e100
    "length": st.one_of(
        NOT_NUMBERS,
        st.sampled_from([0.0, -0.0, -1.0, 1e300, -1e300, 1e-300, 5e-324, 1e101, 9e-101]),
        st.floats(max_value=0.0, allow_nan=False),
        st.floats(min_value=1.01e100, allow_infinity=False),
        st.floats(min_value=0.0, max_value=0.99e-100, exclude_min=True),
    ),
    # angles and signed lengths [rad, m]: within +-1e100
    "angle": st.one_of(
        NOT_NUMBERS,
        st.sampled_from([1e300, -1e300, 1.1e100]),
        st.floats(min_value=1.01e100, allow_infinity=False).map(lambda x: x * (-1) ** int(x)),
    ),
    "tol": st.one_of(
        NOT_NUMBERS, st.sampled_from([0.0, -1e-13, 1e300, 0.2]), st.floats(max_value=0.0)
    ),
    "step": st.one_of(
        NOT_NUMBERS, st.sampled_from([0.0, -0.1, 1e-300, 1e-9]), st.floats(max_value=0.0)
    ),
    "branch": st.one_of(NOT_NUMBERS, st.sampled_from([0, 2, -2, 0.5, 1e300])),
    "iterations": st.one_of(NOT_NUMBERS, st.sampled_from([-1, 2.5, 10**6, 1e300, -1e300])),
    # None is a guess's default: the compass construction
    "pair": st.one_of(
        st.sampled_from(["ab", 1.0, [1.0], [1.0, 2.0, 3.0], (math.nan, 0.0), (0.0, 1e300)]),
        st.tuples(NOT_NUMBERS, st.floats(-1.0, 1.0)),
    ),
    "mapping": st.sampled_from(
        [
            None,
            "theta1",
            [1.0],
            1.0,
            {"theta1": math.nan},
            {"theta1": "a"},
            {"theta1": None},
            {"theta1": 1e300},
            {1: 1.0},
            {"theta1": [1.0]},
        ]
    ),
    "optional mapping": st.sampled_from(
        ["theta1", [1.0], 1.0, {"theta1": math.nan}, {"theta1": "a"}, {1: 1.0}]
    ),
    # a length or an angle of a Vector: a number within +-1e100, or a name
    "number or name": st.one_of(
        NOT_NUMBERS.filter(lambda x: not isinstance(x, str)),
        st.sampled_from(["", 1e300, -1e300, 1.1e100, math.nan]),
    ),
    "loops": st.sampled_from([None, "loop", 1.0, [], [None], [[1.0]], [[]], [(1.0, 2.0)]]),
    "loop": st.sampled_from([None, "loop", 1.0, [], [None], [1.0], ["theta"]]),
    "inputs": st.one_of(
        st.sampled_from([[], (), np.zeros(0), "abc", None, [[0.0, 1.0]], [math.nan], [1e300]]),
        st.lists(st.sampled_from([math.inf, -math.inf, math.nan]), min_size=1, max_size=3),
    ),
    "name": st.sampled_from([None, 1.0, "theta9", ["theta1"], ""]),
    "sign": st.sampled_from([0, 2, -2, math.nan, "1", None, [1], True, 0.5]),
    "label": st.sampled_from([1, None, [], 1.0]),
    "unknowns": st.sampled_from([None, "theta2", ["theta2"], ["theta2", "theta9"], [1, 2]]),
    "branches": st.sampled_from([None, "+1", 1, [], [1, 1], [0], [math.nan], ["1"], [None]]),
}

LOOP = linkage.four_bar_loop(*CRANK_ROCKER)
POSITION = {"theta1": 1.0, "theta2": 0.5856417730643093, "theta3": 1.5546456692877555}
FOUR = dict(r1=1.0, r2=3.0, r3=2.5, r6=3.0)
# function: (valid keyword arguments, {argument: kind of bad value})
CALLS = {
    linkage.four_bar: (
        {**FOUR, "theta1": 1.0},
        {
            **dict.fromkeys(FOUR, "length"),
            "theta1": "angle",
            "phi6": "angle",
            "guess": "pair",
            "tol": "tol",
        },
    ),
    linkage.branch_guess: (
        {**FOUR, "theta1": 1.0},
        {**dict.fromkeys(FOUR, "length"), "theta1": "angle", "phi6": "angle", "branch": "branch"},
    ),
    linkage.four_bar_loop: (FOUR, {**dict.fromkeys(FOUR, "length"), "phi6": "angle"}),
    linkage.four_bar_branch: (
        {"theta2": 0.5, "theta3": 1.5},
        dict.fromkeys(["theta2", "theta3"], "angle"),
    ),
    linkage.is_grashof: (FOUR, dict.fromkeys(FOUR, "length")),
    linkage.grashof_class: (FOUR, dict.fromkeys(FOUR, "length")),
    linkage.input_turns_fully: (FOUR, dict.fromkeys(FOUR, "length")),
    linkage.watt_six_bar_loops: (
        {k: v for k, v in SIX_BAR.items() if k != "beta"},
        {
            **dict.fromkeys(["r1", "r2", "r3", "r6", "r3p", "r4", "r5", "r6p"], "length"),
            **dict.fromkeys(["phi6", "phi6p", "beta"], "angle"),
        },
    ),
    linkage.slider_crank: (
        {"theta": 1.0, "R": 0.04, "L": 0.15},
        {"theta": "angle", "R": "length", "L": "length", "guess": "pair"},
    ),
    linkage.slider_crank_pose: (
        {"theta": 1.0, "R": 0.04, "L": 0.15},
        {"theta": "angle", "R": "length", "L": "length", "guess": "pair"},
    ),
    linkage.slider_crank_loop: ({"R": 0.04, "L": 0.15}, {"R": "length", "L": "length"}),
    linkage.solve_loop: (
        {"loop": LOOP, "known": {"theta1": 1.0}, "guess": {"theta2": 0.5, "theta3": 1.5}},
        {
            "loop": "loop",
            "known": "mapping",
            "guess": "mapping",
            "tol": "tol",
            "max_iterations": "iterations",
        },
    ),
    linkage.solve_loops: (
        {"loops": [LOOP], "known": {"theta1": 1.0}, "guess": {"theta2": 0.5, "theta3": 1.5}},
        {"loops": "loops", "known": "mapping", "guess": "mapping", "tol": "tol"},
    ),
    linkage.trace_branch: (
        {"loops": [LOOP], "input": "theta1", "inputs": [1.0, 1.1], "guess": POSITION},
        {
            "loops": "loops",
            "input": "name",
            "inputs": "inputs",
            "guess": "mapping",
            "known": "optional mapping",
            "tol": "tol",
        },
    ),
    linkage.follow_branch: (
        {"loops": [LOOP], "position": POSITION, "target": 1.2},
        {
            "loops": "loops",
            "position": "mapping",
            "target": "angle",
            "input": "name",
            "step": "step",
        },
    ),
    linkage.branch_reach: (
        {"loops": [LOOP], "position": POSITION},
        {"loops": "loops", "position": "mapping", "input": "name", "step": "step"},
    ),
    linkage.coupler_path: (
        {"loops": [LOOP], "position": POSITION},
        {"loops": "loops", "position": "mapping", "step": "step"},
    ),
    linkage.assemble: (
        {"loops": [LOOP], "known": {"theta1": 1.0}, "branches": [1]},
        {"loops": "loops", "known": "mapping", "branches": "branches"},
    ),
    linkage.assembly_guess: (
        {"loops": [LOOP], "known": {"theta1": 1.0}, "branches": [1]},
        {"loops": "loops", "known": "mapping", "branches": "branches"},
    ),
    linkage.mechanism_joints: (
        {"loops": [LOOP], "values": POSITION},
        {"loops": "loops", "values": "mapping"},
    ),
    linkage.joints: (
        {"loop": LOOP, "values": POSITION},
        {"loop": "loop", "values": "mapping", "origin": "pair"},
    ),
    linkage.residual: ({"loop": LOOP, "values": POSITION}, {"loop": "loop", "values": "mapping"}),
    linkage.jacobian: (
        {"loop": LOOP, "values": POSITION, "unknowns": ("theta2", "theta3")},
        {"loop": "loop", "values": "mapping", "unknowns": "unknowns"},
    ),
    linkage.Vector: (
        {"length": 1.0, "angle": "theta1"},
        {
            "length": "number or name",
            "angle": "number or name",
            "sign": "sign",
            "offset": "angle",
            "label": "label",
        },
    ),
}
ARGUMENTS = [
    pytest.param(function, argument, kind, id=f"{function.__name__}-{argument}")
    for function, (_, arguments) in CALLS.items()
    for argument, kind in arguments.items()
]


@pytest.mark.parametrize("function, argument, kind", ARGUMENTS)
@settings(max_examples=25)
@given(data=st.data())
def test_a_bad_argument_is_named_with_its_allowed_range(function, argument, kind, data):
    valid, _ = CALLS[function]
    function(**valid)  # the call is good but for the argument drawn
    bad = data.draw(BAD[kind], label=argument)
    with pytest.raises(windpump.ParameterError) as caught:
        function(**{**valid, argument: bad})
    error = caught.value
    assert error.name.startswith(argument), (error.name, argument)
    assert str(error).startswith(f"{error.name} = ") and error.allowed in str(error)
    assert "is not allowed" in str(error)


def test_an_empty_trace_is_refused_by_name():
    with pytest.raises(windpump.ParameterError, match="^inputs = .*at least one number"):
        linkage.sweep([LOOP], "theta1", [], POSITION)


@pytest.mark.parametrize("links", [(1e-300,) * 4, (1e-200, 3e-200, 2.5e-200, 3e-200), (1e300,) * 4])
def test_links_out_of_range_are_refused_by_name(links):
    # Once ZeroDivisionError (tiny) or OverflowError (huge) from the compass construction
    with pytest.raises(windpump.ParameterError, match="^r1 = .* from 1e-100 to 1e[+]100"):
        linkage.four_bar(*links, theta1=1.0)


@pytest.mark.parametrize("scale", [1e-98, 1e-30, 1e30, 1e98])  # 0.04 scale to 3 scale: in range
def test_tiny_and_huge_four_bars_close_as_the_unit_one_does(scale):
    # Angles do not depend on the scale: the closed form of the unit linkage is the answer
    links = [scale * r for r in CRANK_ROCKER]
    for branch in (1, -1):
        guess = linkage.branch_guess(*links, 1.0, branch=branch)
        found = linkage.four_bar(*links, 1.0, guess=guess)
        assert_same_angles(found, half_angle(*CRANK_ROCKER, 1.0)[branch], tol=1e-9)
    assert linkage.grashof_class(*links) == "crank-rocker"
    x, theta_c = linkage.slider_crank(0.7, scale * 0.04, scale * 0.15)
    assert x == pytest.approx(scale * float(windpump.piston_position(0.7, 0.04, 0.15)), rel=1e-9)


@given(
    links=st.tuples(*[st.floats(-100.0, 100.0).map(lambda e: 10.0**e)] * 4),
    theta1=st.floats(-1e100, 1e100),
)
def test_any_allowed_four_bar_closes_or_says_why(links, theta1):
    try:
        theta2, theta3 = linkage.four_bar(*links, theta1)
    except NoClosure:
        return
    r1, r2, r3, r6 = links
    values = {"theta1": theta1, "theta2": theta2, "theta3": theta3}
    F = linkage.residual(linkage.four_bar_loop(*links), values)
    assert np.hypot(*F) <= 1e-9 * (r1 + r2 + r3 + r6)


@pytest.mark.parametrize("theta1", [0.0, -0.0, -1.0, 1e-300, -7.5, 1e6, -1e100])
def test_edge_angles_are_answered_rightly(theta1):
    expected = half_angle(*CRANK_ROCKER, theta1)
    for branch in (1, -1):
        guess = linkage.branch_guess(*CRANK_ROCKER, theta1, branch=branch)
        assert_same_angles(linkage.four_bar(*CRANK_ROCKER, theta1, guess=guess), expected[branch])
