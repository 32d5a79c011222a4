"""What a designer does with a run: cycle means, intermittency figures, CSV; and the core's isolation."""

from __future__ import annotations

import io
import math
import subprocess
import sys

import numpy as np
import pytest

import windpump
from windpump.units import LITRES_PER_M3

from conftest import SEED
from reference import reference_run


@pytest.fixture(scope="module")
def run():
    return windpump.simulate(SEED, 600.0)


def test_cycle_mean_speed_is_two_pi_over_each_revolutions_duration(run):
    """Against the reference: the time of the 100th revolution, integrated independently."""
    t_mid, speed = run.cycle_mean_speed()
    start, end = run.revolutions()
    theta0 = run.theta[0]

    def time_at(angle):  # the reference run up to the time the run says theta reaches angle
        t = float(np.interp(angle, run.theta, run.t))
        return t, reference_run(SEED, t, theta0, 3.0).theta

    t99, theta99 = time_at(theta0 + 2 * math.pi * 99)
    t100, theta100 = time_at(theta0 + 2 * math.pi * 100)
    assert theta99 == pytest.approx(theta0 + 2 * math.pi * 99, abs=1e-5)
    assert theta100 == pytest.approx(theta0 + 2 * math.pi * 100, abs=1e-5)
    assert speed[99] == pytest.approx(2 * math.pi / (t100 - t99), rel=1e-4)
    assert t_mid[99] == pytest.approx(0.5 * (start[99] + end[99]))


def test_intermittency_of_the_seed_example(run):
    figures = run.intermittency(revolutions=10)
    # At 600 s the pump is still 0.5 % below alpha+: compare with the averaged curve then.
    assert figures.mean_speed == pytest.approx(
        float(windpump.spinup(SEED, [597.0], 3.0)[0]), rel=1e-3
    )
    assert figures.mean_flow == pytest.approx(
        SEED.A * SEED.R * figures.mean_speed / math.pi, rel=1e-9
    )
    # At an almost steady speed the flow peaks where the lever arm does: pi max|lever| x the mean.
    lever = windpump.lever_arm(np.linspace(math.pi, 2 * math.pi, 100_001), SEED.L_over_R)
    assert figures.peak_to_mean == pytest.approx(math.pi * np.max(-lever), rel=5e-3)
    # At a nearly steady speed the windmill supplies the mean load torque P/pi, so the kinetic
    # energy swings by the peak-to-peak of F = P theta/pi + (work of the load, Eq. 1) over a
    # revolution, and the speed by that over I_eff theta_dot^2.
    theta = np.linspace(0, 2 * math.pi, 200_001)
    P = SEED.load_torque
    load_work = np.where(
        theta > math.pi, -P * (2 - windpump.piston_position(theta, SEED.R, SEED.L) / SEED.R), 0
    )
    swing = np.ptp(P * theta / math.pi + load_work)
    settled = windpump.simulate(SEED, 2000.0).intermittency()  # 25 tau: steady to 1e-10
    expected = swing / (SEED.I_eff * settled.mean_speed**2)
    assert settled.speed_ripple == pytest.approx(expected, rel=0.01)


def test_intermittency_needs_a_whole_revolution():
    short = windpump.simulate(SEED, 0.5)
    with pytest.raises(ValueError, match="no complete crank revolution"):
        short.intermittency()
    with pytest.raises(windpump.ParameterError, match="revolutions"):
        windpump.simulate(SEED, 60.0).intermittency(revolutions=0)


def test_csv_round_trip(run, tmp_path):
    text = run.to_csv()
    lines = text.splitlines()
    comments = [line for line in lines if line.startswith("#")]
    header = lines[len(comments)]
    assert header == "t [s],theta [rad],theta_dot [rad/s],volume [m^3],flow [m^3/s],shaft_work [J]"
    table = np.loadtxt(io.StringIO(text), delimiter=",", skiprows=len(comments) + 1)
    np.testing.assert_allclose(table[:, 2], run.theta_dot, rtol=1e-11)
    np.testing.assert_allclose(table[:, 3], run.volume, rtol=1e-11, atol=1e-300)
    path = tmp_path / "run.csv"
    assert run.to_csv(path) is None
    assert path.read_text(encoding="utf-8") == text


def test_the_csv_header_records_every_parameter_and_litres_on_request(run):
    text = run.to_csv(litres=True)
    recorded = {}
    for line in text.splitlines():
        if line.startswith("# ") and " = " in line and "," not in line:
            name, value = line[2:].split(" = ")
            word = value.split()[0]
            recorded[name] = {"True": True, "False": False}.get(word, None)
            if recorded[name] is None:
                recorded[name] = float(word)
    assert recorded == pytest.approx(run.design.as_dict(), rel=1e-11)
    comments = sum(line.startswith("#") for line in text.splitlines())
    table = np.loadtxt(io.StringIO(text), delimiter=",", skiprows=comments + 1)
    litres = LITRES_PER_M3  # the CSV's volume [L] and flow [L/s]
    np.testing.assert_allclose(table[:, 3], litres * run.volume, rtol=1e-11, atol=1e-300)
    np.testing.assert_allclose(table[:, 4], litres * run.flow, rtol=1e-11, atol=1e-300)
    assert "volume [L],flow [L/s]" in text and "t_end = 600 s, ran to its end" in text


@pytest.mark.parametrize("h", [3.0, 21.0])
def test_last_revolutions_run_to_the_end_of_the_run(h):
    run = windpump.simulate(SEED.replace(h=h), 600.0)
    window = run.last_revolutions(3)
    theta = run.theta[window]
    assert window.stop == len(run.t)  # to the end: the last turns before a stall included
    start, _ = run.revolutions()
    assert run.t[window][0] >= start[-3] and run.t[window.start - 1] < start[-3]
    assert 3.0 <= (theta[-1] - theta[0]) / (2 * math.pi) < 4.0 + 1e-9


def test_importing_the_core_does_not_import_the_app_libraries():
    code = (
        "import sys, windpump; windpump.simulate(windpump.Design.seed_example(), 1.0); "
        "assert 'panel' not in sys.modules and 'bokeh' not in sys.modules, 'app library imported'"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def test_a_leaky_runs_deferred_fields_are_frozen_arrays_that_pickle():
    """A leak hole's flow and leak loss are worked out when first read (dynamics.Deferred): the
    same read-only array every time, not settable, and a pickled or copied run carries them (a
    function in the pickle would fail: pickle refuses lambdas)."""
    import copy
    import dataclasses
    import pickle

    run = windpump.simulate(SEED.replace(d_leak=0.0015, L_main=10.0, D_main=0.025), 20.0)
    copied = copy.copy(run)
    flow, leak = run.flow, run.leak_loss
    assert run.flow is flow and run.leak_loss is leak
    assert not flow.flags.writeable and not leak.flags.writeable
    with pytest.raises(dataclasses.FrozenInstanceError):
        run.flow = flow  # type: ignore[misc]
    for other in (pickle.loads(pickle.dumps(windpump.simulate(run.design, 20.0))), copied):
        np.testing.assert_array_equal(other.flow, flow)
        np.testing.assert_array_equal(other.leak_loss, leak)
    # What it is: what the face delivers past its hole (one single-acting cylinder: its exhaust)
    d = run.design
    arms = np.abs(windpump.model.kinematics.lever_arm(run.theta, d.L_over_R))
    delivering = np.sin(run.theta) < 0.0
    swept = d.A * d.R * arms * run.theta_dot
    expected = np.where(delivering, np.maximum(swept - d.leak_capacity, 0.0), 0.0)
    np.testing.assert_allclose(flow, expected, rtol=1e-12, atol=1e-15 * d.leak_capacity)
    assert leak[-1] > 0.0 and np.all(np.isfinite(leak))
