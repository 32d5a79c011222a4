"""``windpump supply`` and ``windpump tank``, run as subprocesses: their tables, figures, files and
one-line failures (exit 1)."""

from __future__ import annotations

import csv
import io
import subprocess
import sys

import numpy as np
import pytest

import windpump

pytest.importorskip("pvlib")
DESIGN = windpump.Design.seed_example().replace(T_0=0.3)


def windpump_command(*args) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "windpump", *args], capture_output=True, text=True, timeout=300
    )


def test_supply_prints_the_months_and_the_figures(tmp_path):
    hours = tmp_path / "hours.csv"
    done = windpump_command(
        "supply", "--site", "greensboro", "--demand", "2", "--tank", "10", "--set", "T_0=0.3",
        "--hub-height", "15", "--csv", str(hours),
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    year = windpump.supply(DESIGN, windpump.sample_site("greensboro").at_height(15.0), 2.0, 10.0)
    lines = done.stdout.splitlines()
    for name in ("Jan", "Jun", "Dec", "year"):
        assert any(line.startswith(name) for line in lines)
    assert f"loss-of-load prob.   {year.lolp:.4g}" in lines
    assert (
        f"dry days             {year.dry_days} (longest spell {year.longest_dry_spell} days)"
        in lines
    )
    june = next(line for line in lines if line.startswith("Jun")).split()
    assert float(june[1]) == pytest.approx(year.monthly.pumped[5], rel=1e-3)
    rows = list(csv.reader(io.StringIO(hours.read_text())))
    assert len(rows) == 8761 and rows[0][:3] == ["hour", "month", "V [m/s]"]
    pumped = np.array([float(row[4]) for row in rows[1:]])
    np.testing.assert_allclose(pumped, year.pumped, rtol=1e-8)


def test_tank_prints_the_size():
    done = windpump_command(
        "tank", "--site", "sand_point", "--demand", "3", "--lolp", "0.05", "--set", "T_0=0.3"
    )
    assert done.returncode == 0, done.stderr
    size = windpump.tank_for(DESIGN, windpump.sample_site("sand_point"), 3.0, 0.05)
    assert done.stdout.split()[:3] == ["tank", f"{size:.6g}", "m^3"]


def test_supply_says_why_a_pump_never_runs():
    done = windpump_command("supply", "--site", "greensboro", "--demand", "1")
    assert done.returncode == 0 and "never runs" in done.stdout and "T_0 = 0" in done.stdout


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["supply", "--site", "greensboro", "--demand", "-1"], "demand"),
        (["supply", "--site", "greensboro", "--demand", "1", "--tank", "-1"], "tank"),
        (["supply", "--site", "greensboro", "--demand", "1", "--hub-height", "0"], "hub_height"),
        (["tank", "--site", "greensboro", "--demand", "1", "--lolp", "1"], "lolp"),
        (["tank", "--weather", "/no/such/file.csv", "--demand", "1"], "cannot read"),
        (["supply", "--site", "greensboro", "--demand", "1", "--profile", "1,2"], "profile"),
    ],
)
def test_failures_are_one_line_and_exit_1(args, message):
    done = windpump_command(*args)
    assert done.returncode == 1 and done.stdout == ""
    assert len(done.stderr.splitlines()) == 1 and message in done.stderr
    assert done.stderr.startswith(f"windpump {args[0]}: error:")


def test_supply_in_full_from_a_csv(tmp_path):
    path = tmp_path / "mast.csv"
    hours = [f"2026-06-01T{h:02d}:00,{6.0 if h < 18 else 1.0}" for h in range(24)]
    path.write_text("time,speed\n" + "\n".join(hours) + "\n")
    done = windpump_command(
        "supply", "--weather", str(path), "--demand", "1", "--tank", "0.5", "--set", "T_0=0.3",
        "--full", "--workers", "2",
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    record = windpump.read_weather(path)
    year = windpump.supply(DESIGN, record, 1.0, 0.5, method="full")
    gap = f"({year.quasi_steady_gap:+.2%})"
    assert any(
        line.startswith("quasi-steady year") and gap in line for line in done.stdout.splitlines()
    )
    assert any(line.startswith("Jun") for line in done.stdout.splitlines())
