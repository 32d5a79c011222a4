"""Loop closure by Newton-Raphson against closed forms: four-bars, the double loop, the slider-crank."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

import windpump
from windpump import linkage
from windpump.linkage import NoClosure

TWO_PI = 2 * math.pi
CRANK_ROCKER = (1.0, 3.0, 2.5, 3.0)  # Grashof, shortest link the input: it turns fully
DOUBLE_CRANK = (3.0, 3.5, 3.0, 1.0)  # Grashof, shortest link the ground: it turns fully too
TRIPLE_ROCKER = (2.0, 2.5, 2.0, 3.0)  # non-Grashof: the input rocks between limits


def half_angle(r1, r2, r3, r6, theta1, phi6=0.0):
    """Both assemblies of the seed's four-bar in closed form, as {branch: (theta2, theta3)}.

    With P = r6 e(phi6) - r1 e(theta1) the loop reads r2 e(theta2) = r3 e(theta3) + P; squaring it
    leaves Px cos theta3 + Py sin theta3 = C, C = (r2^2 - r3^2 - |P|^2) / (2 r3), and t = tan(theta3/2)
    turns that into (C + Px) t^2 - 2 Py t + (C - Px) = 0. Returns {} when the roots are complex.
    """
    px = r6 * math.cos(phi6) - r1 * math.cos(theta1)
    py = r6 * math.sin(phi6) - r1 * math.sin(theta1)
    c = (r2**2 - r3**2 - px**2 - py**2) / (2 * r3)
    a, b, k = c + px, -2 * py, c - px
    disc = b * b - 4 * a * k
    if disc < 0:
        return {}
    q = -0.5 * (b + math.copysign(math.sqrt(disc), b))  # the stable pair of roots q/a and k/q
    solutions = {}
    for theta3 in (2 * math.atan2(q, a), 2 * math.atan2(k, q)):
        theta2 = math.atan2(r3 * math.sin(theta3) + py, r3 * math.cos(theta3) + px)
        branch = int(np.sign(math.sin(theta3 - theta2)))
        solutions[branch] = (theta2 % TWO_PI, theta3 % TWO_PI)
    return solutions


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
