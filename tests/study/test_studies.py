"""windpump.sweep: its figures against single runs, and the same table on every executor."""

from __future__ import annotations

import math
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

import windpump
from windpump import Design, ParameterError, sweep
from windpump.study.studies import FIGURES

SEED = Design.seed_example()
DESIGNS = [
    SEED,
    SEED.replace(h=9.0),  # kicked below alpha-: stalls
    SEED.replace(h=20.0),  # margin < 1
    SEED.replace(cylinders=2, T_0=0.3),
    SEED.replace(cylinders=3, double_acting=True, h=1.0),
    SEED.with_ratios(R_dagger=6.0),
]


def same_table(a, b) -> bool:
    """Equal figure by figure, NaN where the other is NaN."""
    return all(np.array_equal(getattr(a, f), getattr(b, f), equal_nan=True) for f in FIGURES)


@pytest.fixture(scope="module")
def serial():
    return sweep(DESIGNS, 300.0, theta_dot0=3.0)


def test_each_row_is_its_design_run_on_its_own(serial):
    for i, design in enumerate(DESIGNS):
        run = windpump.simulate(design, 300.0, math.pi / 2, 3.0)
        assert serial.stalled[i] == run.stalled
        assert serial.volume[i] == run.volume[-1]
        assert serial.steps[i] == run.steps
        assert serial.margin[i] == windpump.stall_margin(design)
        if run.stalled:
            assert serial.t_stall[i] == run.t_stall
            assert serial.mean_flow[i] == 0.0 and np.isnan(serial.ripple[i])
        else:
            figures = run.intermittency(10)
            assert serial.mean_flow[i] == figures.mean_flow
            assert serial.peak_to_mean[i] == figures.peak_to_mean
            assert serial.ripple[i] == figures.speed_ripple
            assert np.isnan(serial.t_stall[i])
        if serial.margin[i] > 1:
            assert (serial.alpha_plus[i], serial.alpha_minus[i]) == windpump.steady_speeds(design)
            assert serial.tau[i] == windpump.time_constant(design)
        else:
            assert np.isnan(serial.alpha_plus[i]) and np.isnan(serial.tau[i])
    assert list(serial.stalled) == [False, True, True, False, False, False]


def test_the_volume_is_the_runs_own_energy_balance(serial):
    # An independent check on the pumped volume: lift work = shaft work - kinetic energy gained.
    for i, design in enumerate(DESIGNS):
        run = windpump.simulate(design, 300.0, math.pi / 2, 3.0)
        lift = design.rho_w * design.g * design.h * serial.volume[i]
        gained = run.kinetic_energy[-1] - run.kinetic_energy[0]
        assert lift == pytest.approx(run.shaft_work[-1] - gained, rel=1e-6, abs=1e-9)


def test_a_process_pool_gives_the_same_table_in_chunks(serial):
    calls = []
    with ProcessPoolExecutor(2) as pool:
        spread = sweep(
            DESIGNS, 300.0, executor=pool, chunksize=2, progress=lambda *a: calls.append(a)
        )
    assert same_table(spread, serial)
    assert spread.designs == serial.designs
    assert sorted(calls)[-1] == (len(DESIGNS), len(DESIGNS))


def test_a_dask_local_cluster_gives_the_same_table(serial):
    distributed = pytest.importorskip("distributed")
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, dashboard_address=None, processes=True
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        on_cluster = sweep(DESIGNS, 300.0, executor=client.get_executor(), chunksize=2)
    assert same_table(on_cluster, serial)


def test_per_design_inputs_and_the_pandas_table():
    kicks = [3.0, 0.5]
    table = sweep([SEED, SEED], [100.0, 50.0], theta0=0.0, theta_dot0=kicks)
    frame = table.to_pandas()
    assert len(frame) == 2 and frame["theta_dot0"].tolist() == kicks
    assert frame["t_end"].tolist() == [100.0, 50.0]
    assert frame["stalled"].dtype == bool and frame["steps"].dtype == np.int64
    assert set(FIGURES) <= set(frame.columns) and "h" in frame.columns
    assert frame["stalled"].tolist() == [False, True]  # 0.5 rad/s is below alpha-
    header = table.to_csv().splitlines()[0].split(",")
    assert "h [m]" in header and "mean_flow [m^3/s]" in header and "stalled" in header


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"t_end": 0.0}, "t_end"),
        ({"t_end": [1.0, 2.0, 3.0]}, "t_end"),
        ({"t_end": 10.0, "theta_dot0": -1.0}, "theta_dot0"),
        ({"t_end": 10.0, "theta0": float("nan")}, "theta0"),
        ({"t_end": 10.0, "chunksize": 0}, "chunksize"),
    ],
)
def test_bad_inputs_are_refused_by_name(kwargs, name):
    with pytest.raises(ParameterError) as caught:
        sweep([SEED, SEED], **kwargs)
    assert caught.value.name == name


def test_a_run_that_fails_names_its_design():
    with pytest.warns(RuntimeWarning, match=r"1 of 2 runs failed .*designs\[1\]: t_end"):
        table = sweep([SEED, SEED], [100.0, 1e6])
    assert list(table.failed) == [1] and table.failed[1].startswith("t_end = 1000000.0 s")
    with pytest.raises(TypeError, match=r"designs\[0\]"):
        sweep(["seed"], 10.0)


def test_the_table_carries_the_real_machines_fields():
    heavy = SEED.replace(m_r=6.0, eta_t=0.75, L_main=40.0, D_main=0.03, f_main=0.025)
    leaky = SEED.replace(d_leak=0.004, Cd_leak=0.65)
    table = sweep([heavy, leaky], 20.0)
    columns = table.columns()
    for name in ("m_r", "eta_t", "L_main", "D_main", "f_main", "d_leak", "Cd_leak"):
        assert columns[name].tolist() == [getattr(heavy, name), getattr(leaky, name)]
    header = table.to_csv().splitlines()[0].split(",")
    for cell in ("m_r [kg]", "eta_t", "L_main [m]", "D_main [m]", "f_main", "d_leak [m]"):
        assert cell in header
    assert "Cd_leak" in header
