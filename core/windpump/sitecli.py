"""The command line's site commands: ``windpump supply`` (a year of water with a tank) and
``windpump tank`` (the tank a demand needs), registered by :mod:`windpump.cli`.
"""

from __future__ import annotations

import argparse
import csv
import io
import math
import sys

from .errors import ParameterError
from .units import LITRES_PER_M3
from .wind import WindRecord
from .yearly import MONTH_NAMES, RESTARTS, Supply, supply, tank_for


def add_commands(commands, design_options) -> None:
    """Add ``supply`` and ``tank`` to the command line's subparsers."""
    year = commands.add_parser("supply", help="a year of water at a site, with a tank")
    _site_options(year, design_options)
    year.add_argument("--tank", type=float, default=0.0, help="tank capacity [m^3] (0: none)")
    year.add_argument("--full", action="store_true", help="integrate the year in full (minutes)")
    year.add_argument(
        "--turbulence", type=float, default=0.0, help="--full: gusts' turbulence intensity (0)"
    )
    year.add_argument("--workers", type=int, default=1, help="--full: processes (1)")
    year.add_argument("--csv", metavar="FILE", help="write the hours here")
    year.set_defaults(run=supply_command)

    sizing = commands.add_parser("tank", help="the smallest tank for a loss-of-load probability")
    _site_options(sizing, design_options)
    sizing.add_argument(
        "--lolp", type=float, default=0.05, help="loss-of-load probability allowed (0.05)"
    )
    sizing.set_defaults(run=tank_command)


def _site_options(parser: argparse.ArgumentParser, design_options) -> None:
    design_options(parser)
    where = parser.add_mutually_exclusive_group(required=True)
    where.add_argument("--site", choices=("greensboro", "sand_point"), help="pvlib's sample year")
    where.add_argument("--weather", metavar="FILE", help="TMY3, EPW or a wind CSV")
    parser.add_argument("--height", type=float, help="anemometer height of a CSV's winds [m] (10)")
    parser.add_argument(
        "--hub-height", type=float, help="the rotor's height [m] (the anemometer's)"
    )
    parser.add_argument("--shear", type=float, default=1 / 7, help="wind shear exponent (1/7)")
    parser.add_argument("--demand", type=float, required=True, help="water asked for [m^3/day]")
    parser.add_argument("--restart", choices=RESTARTS, default="self", help="who restarts it")
    parser.add_argument("--profile", metavar="W1,...,W24", help="the demand's hourly weights")


def site_record(args: argparse.Namespace) -> WindRecord:
    """The wind at the rotor from --site or --weather, --height, --hub-height and --shear."""
    from .weather import read_weather, sample_site

    if args.site:
        record = sample_site(args.site)
    else:
        record = read_weather(args.weather, height=args.height)
    if args.hub_height is not None or args.shear != 1 / 7:
        hub = record.height if args.hub_height is None else args.hub_height
        try:
            record = record.at_height(hub, args.shear)
        except ParameterError as error:  # named as the option
            name = "hub_height" if error.name == "z" else error.name
            raise ParameterError(name, error.value, error.allowed, error.unit, error.why) from None
    return record


def profile(text: str | None) -> list[float] | None:
    """``--profile`` as 24 numbers (their checks are :func:`windpump.supply`'s)."""
    if text is None:
        return None
    try:
        return [float(part) for part in text.split(",")]
    except ValueError:
        raise ValueError(
            f"--profile {text[:60]!r}: expected 24 numbers separated by commas"
        ) from None


def supply_command(args: argparse.Namespace, extra: list[str]) -> int:
    """``windpump supply``: the month table and the year's figures; the hours in --csv."""
    from .cli import chosen_design

    design = chosen_design(args)
    record = site_record(args)
    options: dict = {"restart": args.restart, "profile": profile(args.profile)}
    if args.full:
        options.update(method="full", turbulence=args.turbulence, progress=None)
        if args.workers > 1:
            import concurrent.futures

            with concurrent.futures.ProcessPoolExecutor(args.workers) as pool:
                year = supply(design, record, args.demand, args.tank, executor=pool, **options)
        else:
            year = supply(design, record, args.demand, args.tank, **options)
    else:
        year = supply(design, record, args.demand, args.tank, **options)
    for line in report(year, record):
        print(line)
    if args.csv:
        with open(args.csv, "w", encoding="utf-8", newline="") as file:
            file.write(hours_csv(year))
        print(f"hours written to {args.csv}")
    return 0


def report(year: Supply, record: WindRecord) -> list[str]:
    """The lines ``windpump supply`` prints: the site, the month table, the figures."""
    totals = year.totals
    lines = [
        f"site                 {record.name or 'the record'} at {record.height:g} m, "
        f"mean wind {float(year.V.mean()):.3g} m/s over {year.hours} h",
        f"V_stop, V_start      {year.V_stop:.3g} m/s, "
        + ("none (no torque at rest)" if year.V_start is None else f"{year.V_start:.3g} m/s"),
        "",
        "month      pumped    demand delivered shortfall   hours  starts",
    ]
    table = year.monthly
    for i, month in enumerate(table.month):
        lines.append(
            f"{MONTH_NAMES[month - 1]:<5}{table.pumped[i]:>12.4g}{table.demand[i]:>10.4g}"
            f"{table.delivered[i]:>10.4g}{table.shortfall[i]:>10.4g}"
            f"{table.running_hours[i]:>8d}{table.starts[i]:>8d}"
        )
    lines += [
        f"{'year':<5}{totals.pumped:>12.4g}{totals.demand:>10.4g}{totals.delivered:>10.4g}"
        f"{totals.shortfall:>10.4g}{totals.running_hours:>8d}{totals.starts:>8d}",
        "(water in m^3)",
        "",
        f"loss-of-load prob.   {year.lolp:.4g}",
        f"dry days             {year.dry_days} (longest spell {year.longest_dry_spell} days)",
        f"spilled              {totals.spilled:.4g} m^3 (tank {year.tank:g} m^3, "
        f"{year.passes} passes)",
    ]
    if year.why:
        lines.append(f"never runs           {year.why}")
    if year.quasi_steady is not None:
        gap = year.quasi_steady_gap
        shown = "n/a" if math.isnan(gap) else f"{gap:+.2%}"
        lines.append(f"quasi-steady year    {year.quasi_steady.totals.pumped:.4g} m^3 ({shown})")
    return lines


def hours_csv(year: Supply) -> str:
    """The year's hours as CSV: hour, month, V, running, then the water [m^3]."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    names = ["pumped", "delivered", "shortfall", "spilled", "level"]
    writer.writerow(["hour", "month", "V [m/s]", "running", *(f"{n} [m^3]" for n in names)])
    for h in range(year.hours):
        row = [h, int(year.month[h]), f"{year.V[h]:.6g}", int(year.running[h])]
        writer.writerow(row + [f"{getattr(year, n)[h]:.9g}" for n in names])
    return out.getvalue()


def tank_command(args: argparse.Namespace, extra: list[str]) -> int:
    """``windpump tank``: the smallest tank for --lolp, in m^3 (and litres)."""
    from .cli import chosen_design

    design = chosen_design(args)
    record = site_record(args)
    size = tank_for(
        design, record, args.demand, args.lolp, restart=args.restart, profile=profile(args.profile)
    )
    if math.isinf(size):
        print(
            f"no tank is enough: the year pumps less than {1 - args.lolp:.4g} of the demand",
            file=sys.stdout,
        )
        return 0
    print(f"tank                 {size:.6g} m^3 ({size * LITRES_PER_M3:.0f} L)")
    return 0
