"""``windpump rate``: a mill's ratings as a catalogue gives them (capacity in each wind, the
stopping and starting winds, the largest heads running and starting), in US or SI units, each
number the core's function's converted by hand (1 ft = 0.3048 m, 1 US gal = 3.785411784 L,
1 mph = 0.44704 m/s)."""

from __future__ import annotations

import pytest
from command_line import windpump_command

import windpump
from windpump.command.ratecli import winds

FT, GAL, MPH = 0.3048, 3.785411784e-3, 0.44704  # [m], [m^3], [m/s]


def columns(stdout: str) -> dict[str, list[str]]:
    """The table's rows by their wind, as the words after it."""
    lines = stdout.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("wind "))
    rows = [line for line in lines[start + 1 :] if line and not line.startswith("(")]
    return {" ".join(row.split()[:2]): row.split()[2:] for row in rows}


def test_rate_in_us_units_is_the_cores_answer_in_feet_gallons_and_mph():
    design = windpump.Design.seed_example().replace(T_0=0.3, h=10 * FT)
    done = windpump_command(
        "rate", "--set", "T_0=0.3", "--set", "h=10 ft", "--winds", "10, 15,20 mph",
        "--units", "us",
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    V_stop, V_start = windpump.wind_thresholds(design)
    assert f"stopping wind        {V_stop / MPH:.3g} mph" in done.stdout
    assert f"starting wind        {V_start / MPH:.3g} mph" in done.stdout
    assert "head                 10 ft" in done.stdout
    table = columns(done.stdout)
    assert list(table) == ["10 mph", "15 mph", "20 mph"]
    for mph in (10, 15, 20):
        V = mph * MPH
        flow = float(windpump.steady_flow(design, V))  # [m^3/s]
        running = windpump.max_head(design, V)
        starting = windpump.max_head(design, V, start=True)
        assert table[f"{mph} mph"] == [
            f"{flow / GAL * 3600:.3g}", "gal/h", f"{running / FT:.3g}", "ft",
            f"{starting / FT:.3g}", "ft",
        ]  # fmt: skip


def test_rate_in_si_by_default_with_its_own_winds():
    done = windpump_command("rate")
    assert done.returncode == 0, done.stderr
    design = windpump.Design.seed_example()
    assert list(columns(done.stdout)) == ["4 m/s", "6 m/s", "8 m/s", "10 m/s"]
    row = columns(done.stdout)["6 m/s"]
    assert row[:2] == [f"{float(windpump.steady_flow(design, 6.0)) * 1000:.3g}", "L/s"]
    assert row[2:4] == [f"{windpump.max_head(design, 6.0):.3g}", "m"]
    assert "starting wind        none: no torque at rest" in done.stdout  # Eq. 11, T_0 = 0


def test_rate_takes_a_rotor_design_file(tmp_path):
    rotor = windpump.Rotor.multiblade(8 * FT)
    design = windpump.Design.from_machine(
        rotor, V_ref=15 * MPH, gear_ratio=3.29, stroke=7.5 * 0.0254, bore=2.5 * 0.0254,
        head=100 * FT, wheel_inertia=30.0,
    )  # fmt: skip
    path = tmp_path / "mill.json"
    path.write_text(design.to_json())
    done = windpump_command("rate", "--design", str(path), "--winds", "15 mph", "--units", "us")
    assert done.returncode == 0, done.stderr
    flow = float(windpump.steady_flow(design, 15 * MPH))
    assert columns(done.stdout)["15 mph"][:2] == [f"{flow / GAL * 3600:.3g}", "gal/h"]
    V_start = windpump.wind_thresholds(design)[1]
    assert V_start is not None  # a multiblade wheel has its largest torque at rest
    assert f"starting wind        {V_start / MPH:.3g} mph" in done.stdout


def test_the_winds_list_lends_its_last_unit_to_bare_numbers():
    assert winds("10, 15, 17.5 mph") == [10 * MPH, 15 * MPH, 17.5 * MPH]
    assert winds("4,6") == [4.0, 6.0]  # bare: m/s, as every number of the command line
    assert winds("10 mph, 5") == [10 * MPH, 5.0]
    assert winds("3 m/s, 10 mph") == [3.0, 10 * MPH]


@pytest.mark.parametrize(
    ("typed", "words"),
    [
        ("10 ft", "--winds = '10 ft' is not allowed: --winds must be a speed"),
        ("10, x mph", "--winds = 'x mph' is not allowed"),
        ("-5", "a wind speed must be 0 or more"),
        (",".join(["5"] * 101), "at most 100 winds"),
    ],
)
def test_a_wind_that_is_not_one_is_refused_naming_winds(typed, words):
    done = windpump_command("rate", "--winds", typed)
    assert done.returncode == 1 and words in done.stderr, done.stderr


def test_rate_a_catalogue_mill_by_its_sizes():
    """The 8-ft Aermotor 702 on a 1 7/8 in cylinder lifting 175 ft, the table's own row."""
    mill = windpump.catalogue.aermotor_702(8, "1 7/8", lift_ft=175)
    done = windpump_command(
        "rate", "--wheel-ft", "8", "--cylinder-in", "1 7/8", "--lift", "175 ft",
        "--winds", "15, 20 mph", "--units", "us",
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert "head                 175 ft" in done.stdout
    table = columns(done.stdout)
    for mph in (15, 20):
        V = mph * MPH
        flow = float(windpump.steady_flow(mill, V))
        running = windpump.max_head(mill, V) / FT
        starting = windpump.max_head(mill, V, start=True) / FT
        assert table[f"{mph} mph"][0] == f"{flow / GAL * 3600:.3g}"
        assert table[f"{mph} mph"][2] == (
            f"{running:.0f}" if running >= 999.5 else f"{running:.3g}"
        )
        assert table[f"{mph} mph"][4] == (
            f"{starting:.0f}" if starting >= 999.5 else f"{starting:.3g}"
        )
    same = windpump_command(
        "rate", "--wheel-ft", "2.4384 m", "--cylinder-in", "1.875", "--lift", "53.34",
        "--winds", "15, 20 mph", "--units", "us",
    )  # fmt: skip
    assert same.stdout == done.stdout
    short = windpump_command(
        "rate", "--wheel-ft", "8", "--cylinder-in", '1 7/8"', "--lift", "175 ft", "--stroke",
        "short", "--set", "eta_t=0.9",
    )  # fmt: skip
    shorter = windpump.catalogue.aermotor_702(8, 1.875, lift_ft=175, stroke="short", eta_t=0.9)
    flow = float(windpump.steady_flow(shorter, 6.0)) * 1000  # [L/s]
    assert columns(short.stdout)["6 m/s"][0] == f"{flow:.3g}"


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--wheel-ft", "7", "--cylinder-in", "1 7/8", "--lift", "100"], "wheel_ft = 7.0 ft is not allowed"),
        (["--wheel-ft", "8", "--cylinder-in", "3", "--lift", "100"], "cylinder_in = 3.0 in is not allowed"),
        (["--wheel-ft", "8", "--cylinder-in", "1 7/8"], "--wheel-ft needs --lift"),
        (["--cylinder-in", "1 7/8"], "--cylinder-in applies only with --wheel-ft"),
        (["--wheel-ft", "8", "--cylinder-in", "2 kg", "--lift", "9"], "--cylinder-in = '2 kg' is not allowed"),
        (["--wheel-ft", "8", "--design", "x.json", "--cylinder-in", "1 7/8", "--lift", "9"], "rate one or the other"),
    ],
)  # fmt: skip
def test_a_catalogue_mill_the_table_has_not_is_refused_by_name(args, words):
    done = windpump_command("rate", *args)
    assert done.returncode == 1 and words in done.stderr, done.stderr


@pytest.mark.parametrize("units", ["us", "si"])
def test_rate_names_a_catalogue_mill_and_gives_its_tables_row(units):
    """A catalogue mill's rating names it and gives the maker's row as printed in the package's
    table (read here with the csv module): 180 gal/h and 175 ft for the 8-ft mill on 1 7/8 in."""
    import csv
    from importlib import resources

    with resources.files("windpump.catalogue").joinpath("aermotor_702.csv").open() as f:
        found = list(csv.DictReader(line for line in f if not line.startswith("#")))
    (row,) = [
        r for r in found
        if (r["source"], r["stroke"], r["cylinder"], r["wheel_ft"]) == ("aermotor", "long", "1 7/8", "8")
    ]  # fmt: skip
    done = windpump_command(
        "rate", "--wheel-ft", "8", "--cylinder-in", "1 7/8", "--lift", "175 ft", "--units", units
    )
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert (
        lines[0].split() == "mill Aermotor 702, 8-ft wheel, 1 7/8 in cylinder, long stroke".split()
    )
    gph, lift_ft = float(row["capacity_gph"]), float(row["lift_ft"])
    if units == "us":
        shown = f"{gph:.3g} gal/h, maximum lift {lift_ft:.3g} ft"
    else:
        shown = f"{gph * GAL / 3600 * 1000:.3g} L/s, maximum lift {lift_ft * FT:.3g} m"
    assert lines[1].split() == f"catalogue {shown} (in a 15-20 mph wind)".split()
    assert list(columns(done.stdout))  # the table follows, its notes each in parentheses
