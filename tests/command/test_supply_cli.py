"""``windpump supply`` and ``windpump tank``, run as tests/command_line.py runs the command: their tables, figures, files and
one-line failures (exit 1)."""

from __future__ import annotations

import csv
import io

import numpy as np
import pytest
from command_line import windpump_command

import windpump

pytest.importorskip("pvlib")
DESIGN = windpump.Design.seed_example().replace(T_0=0.3)


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
    lines = done.stdout.splitlines()
    assert lines[-1].split()[:3] == ["tank", f"{size:.6g}", "m^3"]
    # what it sized for, echoed: the site, its height, the demand and the target
    assert lines[0].startswith("site") and "at 10 m" in lines[0] and "over 8760 h" in lines[0]
    assert lines[1].split() == [
        "demand",
        "3",
        "m^3/day,",
        "loss",
        "of",
        "load",
        "at",
        "most",
        "0.05",
    ]


def test_tank_says_why_no_tank_is_enough():
    """Exit 0 (an answer, documented in its --help), and the reason supply gives: the paper's
    pump (no torque at rest) left to restart on its own never runs."""
    done = windpump_command(
        "tank", "--site", "greensboro", "--demand", "1", "--hub-height", "15", "--restart", "self"
    )
    assert done.returncode == 0, done.stderr
    assert "at 15 m" in done.stdout
    never = windpump.supply(
        windpump.Design.seed_example(), windpump.sample_site("greensboro"), 1, 0, restart="self"
    )
    last = done.stdout.splitlines()[-1]
    assert "no tank is enough: the pump never runs" in last and never.why in last
    assert "--restart attended" in last
    assert "Exit code 0" in windpump_command("tank", "--help").stdout.replace("\n", " ")


def test_a_short_record_has_fixed_decimals_and_its_own_span(tmp_path):
    path = tmp_path / "mast.csv"
    hours = [f"2026-06-0{1 + h // 24}T{h % 24:02d}:00,{6.0 + (h % 5)}" for h in range(72)]
    path.write_text("time,speed\n" + "\n".join(hours) + "\n")
    done = windpump_command(
        "supply", "--weather", str(path), "--demand", "2", "--tank", "1", "--set", "T_0=0.3"
    )
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert "over 72 h" in lines[0]
    year = windpump.supply(DESIGN, windpump.read_weather(path), 2.0, 1.0)
    june = next(line for line in lines if line.startswith("Jun")).split()
    table = year.monthly
    assert june[1:5] == [
        f"{x:.1f}"
        for x in (table.pumped[0], table.demand[0], table.delivered[0], table.shortfall[0])
    ]
    passes = "1 pass)" if year.passes == 1 else f"{year.passes} passes)"
    assert any(line.startswith("spilled") and line.endswith(passes) for line in lines)


def test_supply_says_why_a_pump_never_runs():
    done = windpump_command("supply", "--site", "greensboro", "--demand", "1", "--restart", "self")
    assert done.returncode == 0 and "never runs" in done.stdout and "T_0 = 0" in done.stdout
    said = next(line for line in done.stdout.splitlines() if line.startswith("never runs"))
    assert "--restart attended" in said and "restart=" not in said


def test_the_restart_is_said_with_what_on_its_own_would_give():
    """Issue 37: --help says what each restart means and which is the default; the output says
    which was used and, when the pump restarting on its own gives another year, that year."""
    for command in ("supply", "tank"):
        said = " ".join(windpump_command(command, "--help").stdout.split())
        assert "attended (someone restarts it whenever the wind can carry it, V >= V_stop)" in said
        assert "self (it restarts on its own, V >= V_start" in said
        assert "attended by default, as the explorer's Site tab" in said
    hub = windpump.sample_site("greensboro").at_height(15.0)
    where = ["--site", "greensboro", "--hub-height", "15", "--demand", "2", "--set", "T_0=0.3"]
    done = windpump_command("supply", *where, "--tank", "5")
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert lines[2].startswith("restart              attended: someone restarts it")
    assert lines[2].endswith("(the default)")
    alone = windpump.supply(DESIGN, hub, 2.0, 5.0, restart="self")
    assert (
        lines[3].split()
        == (
            f"On its own (--restart self) it would pump {alone.totals.pumped:.1f} m^3 and deliver "
            f"{alone.totals.delivered:.1f} m^3 (loss-of-load prob. {alone.lolp:.4g})."
        ).split()
    )
    chosen = windpump_command("supply", *where, "--tank", "5", "--restart", "self")
    assert chosen.returncode == 0, chosen.stderr
    assert "(the default is attended)" in chosen.stdout and "On its own" not in chosen.stdout
    sized = windpump_command("tank", *where)
    assert sized.returncode == 0, sized.stderr
    lines = sized.stdout.splitlines()
    assert lines[2].startswith("restart              attended") and lines[2].endswith(
        "(the default)"
    )
    needs = windpump.tank_for(DESIGN, hub, 2.0, 0.05, restart="self")
    assert (
        lines[3].split()
        == (f"On its own (--restart self) it would need a tank of {needs:.6g} m^3.").split()
    )
    assert lines[-1].split()[:2] == ["tank", f"{windpump.tank_for(DESIGN, hub, 2.0, 0.05):.6g}"]


def test_in_full_the_year_on_its_own_is_said_to_be_quasi_steady(tmp_path):
    """4 m/s carries the pump (V_stop 2.21 m/s) but does not start it on its own (V_start
    5.65 m/s): attended it runs from the first hour, on its own from the seventh."""
    path = tmp_path / "mast.csv"
    hours = [f"2026-06-01T{h:02d}:00,{4.0 if h < 6 else 6.0}" for h in range(24)]
    path.write_text("time,speed\n" + "\n".join(hours) + "\n")
    done = windpump_command(
        "supply", "--weather", str(path), "--demand", "1", "--set", "T_0=0.3", "--full"
    )
    assert done.returncode == 0, done.stderr
    alone = windpump.supply(DESIGN, windpump.read_weather(path), 1.0, 0.0, restart="self")
    assert alone.running.tolist() == [False] * 6 + [True] * 18
    said = done.stdout.splitlines()[3].strip()
    assert said.startswith("On its own (--restart self) it would pump")
    assert f"{alone.totals.pumped:.1f} m^3" in said and said.endswith(", quasi-steady).")


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["supply", "--site", "greensboro", "--demand", "-1"], "demand"),
        (["supply", "--site", "greensboro", "--demand", "1", "--tank", "-1"], "tank"),
        (
            ["supply", "--site", "greensboro", "--demand", "1", "--hub-height", "0"],
            "> 0 and <= 500",
        ),
        (["supply", "--site", "greensboro", "--demand", "1", "--workers", "2"], "--workers apply"),
        (
            ["supply", "--site", "greensboro", "--demand", "1", "--turbulence", "0.1"],
            "--turbulence apply only with --full",
        ),
        (
            ["supply", "--site", "greensboro", "--demand", "1", "--csv", "/no/such/dir/h.csv"],
            "--csv /no/such/dir/h.csv",
        ),
        (["tank", "--site", "greensboro", "--demand", "1", "--lolp", "1"], "lolp"),
        (["tank", "--weather", "/no/such/file.csv", "--demand", "1"], "there is no file"),
        (["supply", "--site", "greensboro", "--demand", "1", "--profile", "1,2"], "profile"),
    ],
)
def test_failures_are_one_line_and_exit_1(args, message):
    done = windpump_command(*args)
    assert done.returncode == 1 and done.stdout == ""
    assert len(done.stderr.splitlines()) == 1 and message in done.stderr
    assert done.stderr.startswith(f"windpump {args[0]}: error:")


def test_a_weather_files_error_names_the_file(short_tmp_path):
    path = short_tmp_path / "gappy.csv"
    path.write_text("time,speed\n0,4\n3600,5\n10800,6\n")
    done = windpump_command("supply", "--weather", str(path), "--demand", "1")
    assert done.returncode == 1
    assert done.stderr.startswith(f"windpump supply: error: --weather {path}: line 4: a gap of 2 h")


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
