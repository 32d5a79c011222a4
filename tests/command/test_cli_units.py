"""The command line in a builder's units: lengths, winds, flows and volumes typed with their
units (``--set h='175 ft'``, ``--demand '500 gal/day'``) are the SI numbers converted by hand,
and ``--units us`` shows gallons, feet and mph; without units, everything is as it was."""

from __future__ import annotations

import pytest
from command_line import windpump_command

import windpump

FT, INCH, GAL, MPH = 0.3048, 0.0254, 3.785411784e-3, 0.44704  # [m], [m], [m^3], [m/s]


@pytest.mark.parametrize(
    ("typed", "number"),
    [
        (["h=17.5 ft"], f"h={17.5 * FT!r}"),
        (["V_ref=15 mph"], f"V_ref={15 * MPH!r}"),
        (["R=1 7/8 in"], f"R={(1 + 7 / 8) * INCH!r}"),
        (["A=2.76 in^2"], f"A={2.76 * INCH**2!r}"),
        (["m_r=22 lb", "L=2 ft"], f"m_r={22 * 0.45359237!r}"),
    ],
)
def test_set_takes_a_fields_value_with_its_unit(typed, number):
    with_units = windpump_command(
        "simulate", "--t-end", "30", *(w for t in typed for w in ("--set", t))
    )
    numbers = [number] + [f"L={2 * FT!r}"] * (len(typed) - 1)
    in_si = windpump_command(
        "simulate", "--t-end", "30", *(w for n in numbers for w in ("--set", n))
    )
    assert with_units.returncode == 0 == in_si.returncode, with_units.stderr + in_si.stderr
    assert with_units.stdout == in_si.stdout


@pytest.mark.parametrize(
    ("setting", "words"),
    [
        ("h=3 kg", "h = '3 kg' is not allowed: h must be a length, e.g. 175 ft, 53 m or 1 7/8 in (kg is a mass)"),
        ("V_ref=15 ft", "V_ref = '15 ft' is not allowed: V_ref must be a speed, e.g. 15 mph or 6.7 m/s (ft is a length)"),
        ("h=-3 ft", "h must be a length, e.g. 175 ft, 53 m or 1 7/8 in (a negative length)"),
        ("h=3 cubits", "('cubits' is not a unit)"),
        ("h=nan ft", "(not a finite number)"),
        ("m_r=heavy", "m_r = 'heavy' is not allowed: m_r must be a number, or a mass"),
        ("eta_t=0.5 ft", "eta_t = '0.5 ft' is not allowed: eta_t must be a number"),
    ],
)  # fmt: skip
def test_a_wrong_unit_is_refused_by_the_fields_name(setting, words):
    done = windpump_command("simulate", "--set", setting)
    assert done.returncode == 1 and done.stdout == ""
    assert words in done.stderr, done.stderr
    assert len(done.stderr.splitlines()) == 1


def test_simulate_shows_its_water_in_gallons():
    si = windpump_command("simulate", "--t-end", "120")
    us = windpump_command("simulate", "--t-end", "120", "--units", "us")
    assert si.returncode == 0 == us.returncode
    assert windpump_command("simulate", "--t-end", "120", "--units", "si").stdout == si.stdout
    run = windpump.simulate(windpump.Design.seed_example(), 120.0)
    flow = run.intermittency(10).mean_flow  # [m^3/s]
    gallons = run.volume[-1] / GAL
    assert f"volume pumped                {gallons:.6g} gal in" in us.stdout
    assert f"mean flow, last revolutions  {flow / GAL * 3600:.6g} gal/h" in us.stdout
    assert f"({flow * 86400 / GAL:.4g} gal/day)" in us.stdout
    assert f"{run.volume[-1] * 1000:.6g} L in" in si.stdout
    assert without_water(si.stdout) == without_water(us.stdout)


def without_water(text: str) -> list[str]:
    return [line for line in text.splitlines() if "flow" not in line and "volume" not in line]


def test_units_takes_si_or_us_only():
    done = windpump_command("simulate", "--units", "imperial")
    assert done.returncode == 2 and "--units" in done.stderr and "'us'" in done.stderr


DESIGN = windpump.Design.seed_example().replace(T_0=0.3)


def test_supply_takes_gallons_and_feet_and_shows_them():
    pytest.importorskip("pvlib")
    si = windpump_command(
        "supply", "--site", "greensboro", "--set", "T_0=0.3", "--demand", "2", "--tank", "10",
        "--hub-height", "15",
    )  # fmt: skip
    us = windpump_command(
        "supply", "--site", "greensboro", "--set", "T_0=0.3", "--demand", f"{2 / GAL!r} gal/day",
        "--tank", f"{10 / GAL!r} gal", "--hub-height", f"{15 / FT!r} ft", "--units", "us",
    )  # fmt: skip
    assert si.returncode == 0 == us.returncode, si.stderr + us.stderr
    record = windpump.sample_site("greensboro").at_height(15.0)
    year = windpump.supply(DESIGN, record, 2.0, 10.0)
    lines = us.stdout.splitlines()
    assert f"mean wind {float(year.V.mean()) / MPH:.3g} mph" in lines[0]
    assert f"at {record.height / FT:g} ft" in lines[0]
    assert f"V_stop, V_start      {year.V_stop / MPH:.3g} mph" in lines[1]
    assert "(water in gal)" in lines
    june = next(line for line in lines if line.startswith("Jun")).split()
    assert float(june[1]) == pytest.approx(year.monthly.pumped[5] / GAL, rel=1e-3)
    assert f"loss-of-load prob.   {year.lolp:.4g}" in lines  # the same year as in m^3
    assert f"loss-of-load prob.   {year.lolp:.4g}" in si.stdout.splitlines()


def test_tank_sizes_in_gallons():
    pytest.importorskip("pvlib")
    si = windpump_command("tank", "--site", "greensboro", "--set", "T_0=0.3", "--demand", "2")
    us = windpump_command(
        "tank", "--site", "greensboro", "--set", "T_0=0.3", "--demand", "2 m^3/day",
        "--units", "us",
    )  # fmt: skip
    assert si.returncode == 0 == us.returncode, si.stderr + us.stderr
    record = windpump.sample_site("greensboro")
    size = windpump.tank_for(DESIGN, record, 2.0, 0.05)
    assert f"demand               {2 / GAL:g} gal/day" in us.stdout
    if size == float("inf"):
        assert "no tank is enough" in us.stdout and "gal" in us.stdout
    else:
        assert f"tank                 {size / GAL:.6g} gal" in us.stdout
        assert f"tank                 {size:.6g} m^3 ({size * 1000:.0f} L)" in si.stdout


@pytest.mark.parametrize(
    ("option", "typed", "words"),
    [
        ("--demand", "3 ft", "--demand = '3 ft' is not allowed: --demand must be a flow"),
        ("--hub-height", "-3 ft", "--hub-height must be a length, e.g. 175 ft"),
        ("--tank", "lots", "--tank = 'lots' is not allowed: --tank must be a number, or a volume"),
    ],
)
def test_an_options_wrong_unit_is_a_usage_error_naming_it(option, typed, words):
    pytest.importorskip("pvlib")
    args = ["tank", "--site", "greensboro", "--demand", "2"]
    if option == "--tank":
        args[0] = "supply"
    done = windpump_command(*args, option, typed)
    assert done.returncode == 2 and words in done.stderr, done.stderr


def test_a_sweeps_cells_take_units_too(tmp_path):
    (tmp_path / "units.csv").write_text("h,V_ref\n10 ft,15 mph\n")
    (tmp_path / "si.csv").write_text(f"h,V_ref\n{10 * FT!r},{15 * MPH!r}\n")
    with_units = windpump_command("sweep", str(tmp_path / "units.csv"), "--t-end", "30")
    in_si = windpump_command("sweep", str(tmp_path / "si.csv"), "--t-end", "30")
    assert with_units.returncode == 0 == in_si.returncode, with_units.stderr + in_si.stderr
    assert with_units.stdout == in_si.stdout


def test_the_links_millimetres_are_suggested_with_their_unit():
    done = windpump_command("simulate", "--set", "D_main_mm=25")
    assert "--set D_main=0.025 (in metres) or --set 'D_main=25 mm'" in done.stderr
    assert windpump_command("simulate", "--set", "D_main=25 mm", "--t-end", "10").returncode == 0
