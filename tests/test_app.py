"""The explorer in-process: set widgets, and check the data sources and readouts against windpump."""

from __future__ import annotations

import logging
import math
import sys
from pathlib import Path

import numpy as np
import pytest

import windpump

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "app"))
from envelope import band  # noqa: E402
from explorer import BINS, Explorer  # noqa: E402
from figures import WIDTH  # noqa: E402

SEED = windpump.Design.seed_example()


@pytest.fixture
def app():
    return Explorer()


def expected(design=SEED, t_end=600.0, theta0=math.pi / 2, theta_dot0=3.0):
    return windpump.explore(design, t_end, theta0, theta_dot0)


def readout_text(app, name):
    return app.readouts[name].object


def test_the_default_is_the_papers_example(app):
    seen = expected()
    assert app.design() == SEED
    speed = app.sources["speed"].data
    assert max(speed["upper"]) == pytest.approx(seen.run.theta_dot.max(), rel=1e-12)
    assert min(speed["lower"]) == pytest.approx(seen.run.theta_dot.min(), rel=1e-12)
    np.testing.assert_allclose(app.sources["spinup"].data["speed"], seen.spinup_speed)
    assert app.sources["alpha_plus"].data["speed"] == [seen.alpha_plus] * 2
    assert f"{1e3 * seen.mean_flow:.4f} L/s" in readout_text(app, "mean_flow")
    assert f"{1e3 * seen.pumped_volume:.1f} L" in readout_text(app, "volume")
    assert f"{seen.tau:.1f} s" in readout_text(app, "tau")
    assert f"{seen.margin:.3f}" in readout_text(app, "margin")
    assert "Running" in app.status.object and f"{seen.alpha_plus:.2f}" in app.status.object
    assert not app.error.visible


def test_a_slider_move_recomputes_everything(app):
    app.sliders["h"].value = 6.0
    seen = expected(SEED.replace(h=6.0))
    assert max(app.sources["flow"].data["upper"]) == pytest.approx(
        1e3 * seen.run.flow.max(), rel=1e-12
    )
    np.testing.assert_allclose(app.sources["spinup"].data["speed"], seen.spinup_speed)
    op = seen.operating_point
    assert app.sources["stable"].data == {"omega": [op.omega], "power": [op.power]}
    assert f"{seen.margin:.3f}" in readout_text(app, "margin")
    values = np.array(app.sources["stall"].data["value"])
    assert values[0] / values[1] == pytest.approx(seen.margin, rel=1e-12)


def test_the_closeup_holds_every_sample_of_the_last_revolutions(app):
    run = expected().run
    start, end = run.revolutions()
    window = (run.t >= start[-3]) & (run.t <= end[-1])
    np.testing.assert_array_equal(app.sources["closeup"].data["t"], run.t[window])
    np.testing.assert_allclose(app.sources["closeup"].data["flow"], 1e3 * run.flow[window])


def test_no_more_points_than_pixels(app):
    for name in ("speed", "flow", "cycle_mean"):
        assert len(app.sources[name].data["t"]) <= BINS <= WIDTH


@pytest.mark.parametrize(
    "changes, status",
    [
        ({"h": 20.0}, "Stalled"),
        ({"theta_dot0": 0.0}, "Never started"),
        ({"theta_dot0": 1.0}, "Never started"),
    ],
)
def test_status_reads_at_a_glance(app, changes, status):
    app.set_values(**changes)
    assert app.status.object.startswith(f"**{status}")
    if (
        "h" in changes
    ):  # no steady state past the stall criterion: no alpha lines, no operating point
        assert (
            app.sources["alpha_plus"].data["t"] == [] and app.sources["stable"].data["omega"] == []
        )
        assert "none" in readout_text(app, "tau")


def test_a_rejected_value_shows_its_message_and_the_next_move_redraws(app):
    before = dict(app.sources["speed"].data)
    app.sliders["L_over_R"].value = 1.0
    assert app.error.visible
    assert app.error.object.startswith("L/R, rod / crank = 1 cannot be run: ")
    assert "L = 0.04 m is not allowed" in app.error.object and "> R = 0.04 m" in app.error.object
    assert app.sources["speed"].data["upper"] is before["upper"]  # the last good plot stays
    app.sliders["L_over_R"].value = 2.0
    assert not app.error.visible
    seen = expected(SEED.replace(L=2 * SEED.R))
    assert max(app.sources["speed"].data["upper"]) == pytest.approx(
        seen.run.theta_dot.max(), rel=1e-12
    )


def test_a_run_too_long_for_the_sample_bound_is_refused(app):
    app.set_values(R_dagger=0.5, omega_m=150.0, t_end=3000.0)
    assert app.error.visible and "t_end" in app.error.object and "<=" in app.error.object
    app.set_values(t_end=100.0)
    assert not app.error.visible


def test_an_unexpected_exception_is_shown_logged_and_survived(app, monkeypatch, caplog):
    def broken(*_args, **_kwargs):
        raise RuntimeError("boom")

    monkeypatch.setattr(windpump, "explore", broken)
    with caplog.at_level(logging.ERROR, logger="windpump.app"):
        app.sliders["h"].value = 4.0
    assert app.error.visible and "RuntimeError: boom" in app.error.object
    assert any("update failed" in record.message for record in caplog.records)
    monkeypatch.undo()
    app.sliders["h"].value = 5.0
    assert not app.error.visible and "Running" in app.status.object


def test_reset_brings_back_the_papers_example(app):
    app.set_values(h=12.0, T_m=2.0, t_end=100.0, I0=5.0)
    app.reset_button.clicks += 1
    assert app.design() == SEED and app.value("t_end") == 600.0
    assert max(app.sources["speed"].data["upper"]) == pytest.approx(expected().run.theta_dot.max())


def test_lab_data_sets_the_windmill_curve(app):
    omega = np.linspace(5, 95, 10)
    torque = 0.8 * (omega / 45) * (2 - omega / 45)
    app.lab_data.value = "".join(f"{w},{q}\n" for w, q in zip(omega, torque, strict=True)).encode()
    assert app.value("T_m") == pytest.approx(0.8) and app.value("omega_m") == pytest.approx(45.0)
    np.testing.assert_allclose(app.sources["data"].data["power"], omega * torque)
    assert "Tₘ = 0.800 N·m" in app.lab_note.object
    assert app.design().T_m == pytest.approx(0.8)


def test_lab_data_that_cannot_be_fitted_is_explained(app):
    app.lab_data.value = b"speed,torque\n1,1\n2,2\n3,3\n"
    assert app.error.visible and app.error.object.startswith("Could not use that file")
    assert app.value("T_m") == SEED.T_m


def test_download_is_the_run_as_csv(app):
    assert app._csv().getvalue() == expected().run.to_csv()


def test_band_keeps_each_bins_extremes():
    rng = np.random.default_rng(3)
    x = np.sort(rng.uniform(0, 100, 20_000))
    y = rng.normal(size=x.size)
    mid, lower, upper = band(x, y, 50)
    assert len(mid) <= 50
    assert lower.min() == y.min() and upper.max() == y.max()
    edges = np.linspace(x[0], x[-1], 51)
    for k in range(50):
        inside = (x >= edges[k]) & (x < edges[k + 1])
        assert lower[k] == y[inside].min() and upper[k] == y[inside].max()
        assert edges[k] <= mid[k] <= edges[k + 1]
