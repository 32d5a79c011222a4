"""The command line's site commands: ``windpump supply`` (a year of water with a tank) and
``windpump tank`` (the tank a demand needs), registered by :mod:`windpump.command.cli`.

Both exit with 0 when they answer (``tank`` also when no tank is enough: it says why), 1 on an
error (one line on stderr), 2 for a command line argparse cannot read.
"""

from __future__ import annotations

import argparse
import csv
import io
import math
import os
from pathlib import Path

import numpy as np

from ..errors import ParameterError, cut
from ..model.wind import WindRecord
from ..readers.labdata import LabDataError
from ..readers.quantities import display_unit
from ..sites.weather import read_weather, sample_site
from ..sites.yearly import DEFAULT_RESTART, MONTH_NAMES, RESTARTS, Supply, supply, tank_for
from ..units import LITRES_PER_M3
from .cliargs import MAX_WORKERS, chosen_design, quantity, units_option, workers


def add_commands(commands, design_options) -> None:
    """Add ``supply`` and ``tank`` to the command line's subparsers."""
    year = commands.add_parser(
        "supply",
        help="a year of water at a site, with a tank",
        description="A year at a site, hour by hour (the quasi-steady year, or --full): the "
        "water pumped, delivered and short month by month for a demand and a tank, the "
        "loss-of-load probability and the dry days. Exit code 0, 1 on an error.",
    )
    _site_options(year, design_options)
    year.add_argument(
        "--tank",
        type=quantity("m^3", "--tank"),
        default=0.0,
        help="tank capacity [m^3, or with its unit: '500 gal'] (0: none)",
    )
    year.add_argument("--full", action="store_true", help="integrate the year in full (minutes)")
    year.add_argument(
        "--turbulence", type=float, default=None, help="--full: gusts' turbulence intensity (0)"
    )
    year.add_argument(
        "--workers", type=workers, default=None, help=f"--full: processes, 1 to {MAX_WORKERS} (1)"
    )
    year.add_argument("--csv", metavar="FILE", help="write the hours here")
    year.set_defaults(run=supply_command)

    sizing = commands.add_parser(
        "tank",
        help="the smallest tank for a loss-of-load probability",
        description="The smallest tank [m^3] whose quasi-steady year loses at most --lolp of the "
        "demand. Exit code 0 with the size, and also when no tank is enough (it says why); "
        "1 on an error.",
    )
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
    parser.add_argument(
        "--height",
        type=quantity("m", "--height"),
        help="anemometer height of a CSV's winds [m, or with its unit: '33 ft'] (10 m)",
    )
    parser.add_argument(
        "--hub-height",
        type=quantity("m", "--hub-height"),
        help="the rotor's height [m, or with its unit: '40 ft'] (the anemometer's)",
    )
    parser.add_argument("--shear", type=float, default=1 / 7, help="wind shear exponent (1/7)")
    parser.add_argument(
        "--demand",
        type=quantity("m^3/day", "--demand"),
        required=True,
        help="water asked for [m^3/day, or with its unit: '500 gal/day', '0.5 gpm']",
    )
    parser.add_argument(
        "--restart",
        choices=RESTARTS,
        default=DEFAULT_RESTART,
        help=f"who restarts a pump a calm stopped: attended ({RESTART_WORDS['attended']}) or "
        f"self ({RESTART_WORDS['self']}); {DEFAULT_RESTART} by default, as the explorer's "
        "Site tab",
    )
    parser.add_argument("--profile", metavar="W1,...,W24", help="the demand's hourly weights")
    units_option(parser)


RESTART_WORDS = {
    "attended": "someone restarts it whenever the wind can carry it, V >= V_stop",
    "self": "it restarts on its own, V >= V_start: never without torque at rest, T_0 = 0",
}
"""What each ``--restart`` means, in the help and the output."""


def site_record(args: argparse.Namespace) -> WindRecord:
    """The wind at the rotor from --site or --weather, --height, --hub-height and --shear."""
    if args.site:
        if args.height is not None:  # (it was ignored: --height -inf ran the year)
            raise ParameterError(
                "--height",
                args.height,
                "given only with --weather (a sample site's anemometer height is its own)",
                "m",
            )
        record = sample_site(args.site)
    else:
        try:
            record = read_weather(args.weather, height=args.height)
        except LabDataError as error:  # the line at fault, in the file named
            raise LabDataError(f"--weather {cut(args.weather)}: {error}") from None
        except ParameterError as error:  # a path that cannot be one: named as the option
            if error.name != "source":
                raise
            raise ParameterError("--weather", error.value, error.allowed, why=error.why) from None
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
    full_only = [
        f"--{name}" for name in ("turbulence", "workers") if getattr(args, name) is not None
    ]
    if full_only and not args.full:
        raise ValueError(f"{' and '.join(full_only)} apply only with --full")
    if args.csv:
        check_writable(args.csv)
    design = chosen_design(args)
    record = site_record(args)
    options: dict = {"restart": args.restart, "profile": profile(args.profile)}
    if args.full:
        options.update(method="full", turbulence=args.turbulence or 0.0, progress=None)
        if (args.workers or 1) > 1:
            import concurrent.futures

            with concurrent.futures.ProcessPoolExecutor(args.workers) as pool:
                year = supply(design, record, args.demand, args.tank, executor=pool, **options)
        else:
            year = supply(design, record, args.demand, args.tank, **options)
    else:
        year = supply(design, record, args.demand, args.tank, **options)
    alone = None
    if args.restart != "self":  # quasi-steady, whatever the method: milliseconds
        alone = supply(
            design, record, args.demand, args.tank, restart="self", profile=options["profile"]
        )
    for line in report(year, record, alone, args.units):
        print(line)
    if args.csv:
        try:
            with open(args.csv, "w", encoding="utf-8", newline="") as file:
                file.write(hours_csv(year))
        except OSError as error:
            raise OSError(f"--csv {args.csv}: {error.strerror or error}") from None
        print(f"hours written to {args.csv}")
    return 0


def check_writable(path: str, option: str = "--csv") -> None:
    """``option``'s file can be written (checked before the work is done), or an OSError
    naming it."""
    target = Path(path)
    folder = target.parent
    if target.is_dir():
        raise OSError(f"{option} {path}: a folder, not a file")
    if not folder.is_dir():
        raise OSError(f"{option} {path}: there is no folder {folder}")
    if not os.access(folder, os.W_OK) or (target.exists() and not os.access(target, os.W_OK)):
        raise OSError(f"{option} {path}: not allowed to write there")


def restart_line(restart: str) -> str:
    """The restart a command used, what it means and whether it is the default."""
    which = "the default" if restart == DEFAULT_RESTART else f"the default is {DEFAULT_RESTART}"
    return f"restart              {restart}: {RESTART_WORDS[restart]} ({which})"


def self_differs(year: Supply, alone: Supply | None) -> bool:
    """Whether the pump restarting on its own (``alone``, quasi-steady) runs other hours than
    ``year``'s quasi-steady year."""
    if alone is None:
        return False
    steady = year if year.quasi_steady is None else year.quasi_steady
    return not np.array_equal(steady.running, alone.running)


def self_sentence(alone: Supply, what: str) -> str:
    """The sentence that says the pump restarting on its own gives another answer (``what``:
    that answer, when it runs)."""
    if alone.why:
        return f"On its own (--restart self) the pump would never run: {alone.why}."
    return f"On its own (--restart self) {what}."


def attended_hint(year: Supply) -> str:
    """How the command line's user has someone restart the pump, when that would help."""
    if year.why and year.restart == "self":
        return " (--restart attended has someone do it, whenever the wind can carry it)"
    return ""


def site_line(year: Supply, record: WindRecord, units: str = "si") -> str:
    """Where the year is, the anemometer's height and the mean wind, in ``units``."""
    metres, length = display_unit("height", units)
    per_second, speed = display_unit("wind speed", units)
    return (
        f"site                 {record.name or 'the record'} at {record.height * metres:g} "
        f"{length}, mean wind {float(year.V.mean()) * per_second:.3g} {speed} over {year.hours} h"
    )


def report(
    year: Supply, record: WindRecord, alone: Supply | None = None, units: str = "si"
) -> list[str]:
    """The lines ``windpump supply`` prints: the site, the restart, the month table, the
    figures; and, when the pump restarting on its own (``alone``, the quasi-steady year of
    ``--restart self``) runs other hours, what that year would be. Water in m^3 (``units``
    ``"si"``) or US gallons (``"us"``), winds in m/s or mph."""
    totals = year.totals
    per_second, speed = display_unit("wind speed", units)
    w, water = display_unit("tank", units)  # [m^3 or gal per m^3]
    starting = (
        "none (no torque at rest)"
        if year.V_start is None
        else f"{year.V_start * per_second:.3g} {speed}"
    )
    lines = [
        site_line(year, record, units),
        f"V_stop, V_start      {year.V_stop * per_second:.3g} {speed}, {starting}",
        restart_line(year.restart),
    ]
    if alone is not None and self_differs(year, alone):
        totals_alone = alone.totals
        lines.append(
            " " * 21
            + self_sentence(
                alone,
                f"it would pump {totals_alone.pumped * w:.1f} {water} and deliver "
                f"{totals_alone.delivered * w:.1f} {water} (loss-of-load prob. {alone.lolp:.4g}"
                + (", quasi-steady)" if year.quasi_steady is not None else ")"),
            )
        )
    lines += [
        "",
        "month      pumped    demand delivered shortfall   hours  starts",
    ]
    table = year.monthly
    for i, month in enumerate(table.month):
        lines.append(
            f"{MONTH_NAMES[month - 1]:<5}{table.pumped[i] * w:>12.1f}{table.demand[i] * w:>10.1f}"
            f"{table.delivered[i] * w:>10.1f}{table.shortfall[i] * w:>10.1f}"
            f"{table.running_hours[i]:>8d}{table.starts[i]:>8d}"
        )
    lines += [
        f"{'year':<5}{totals.pumped * w:>12.1f}{totals.demand * w:>10.1f}"
        f"{totals.delivered * w:>10.1f}{totals.shortfall * w:>10.1f}"
        f"{totals.running_hours:>8d}{totals.starts:>8d}",
        f"(water in {water})",
        "",
        f"loss-of-load prob.   {year.lolp:.4g}",
        f"dry days             {year.dry_days} (longest spell {year.longest_dry_spell} days)",
        f"spilled              {totals.spilled * w:.1f} {water} (tank {year.tank * w:g} {water}, "
        f"{year.passes} pass{'' if year.passes == 1 else 'es'})",
    ]
    if year.why:
        lines.append(f"never runs           {year.why}{attended_hint(year)}")
    if year.quasi_steady is not None:
        gap = year.quasi_steady_gap
        shown = "n/a" if math.isnan(gap) else f"{gap:+.2%}"
        pumped = year.quasi_steady.totals.pumped * w
        lines.append(f"quasi-steady year    {pumped:.1f} {water} ({shown})")
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
    """``windpump tank``: what it sizes for (site, hub, demand, target), then the smallest tank
    for --lolp in m^3 (and litres), or why no tank is enough."""
    design = chosen_design(args)
    record = site_record(args)
    options: dict = {"restart": args.restart, "profile": profile(args.profile)}
    size = tank_for(design, record, args.demand, args.lolp, **options)
    year = supply(design, record, args.demand, 0.0, **options)  # quasi-steady: quick
    w, water = display_unit("tank", args.units)  # [m^3 or gal per m^3]
    daily, per_day = display_unit("daily flow", args.units)
    print(site_line(year, record, args.units))
    print(
        f"demand               {args.demand * daily:g} {per_day}, "
        f"loss of load at most {args.lolp:g}"
    )
    print(restart_line(args.restart))
    if args.restart != "self":
        alone_options = {**options, "restart": "self"}
        alone = supply(design, record, args.demand, 0.0, **alone_options)
        if self_differs(year, alone):
            alone_size = tank_for(design, record, args.demand, args.lolp, **alone_options)
            if alone_size != size:
                needs = (
                    "no tank would be enough"
                    if math.isinf(alone_size)
                    else f"it would need a tank of {alone_size * w:.6g} {water}"
                )
                print(" " * 21 + self_sentence(alone, needs))
    if math.isinf(size):
        print(f"tank                 no tank is enough: {no_tank_why(year, args.lolp, args.units)}")
        return 0
    litres = "" if args.units == "us" else f" ({size * LITRES_PER_M3:.0f} L)"
    print(f"tank                 {size * w:.6g} {water}{litres}")
    return 0


def no_tank_why(year: Supply, lolp: float, units: str = "si") -> str:
    """Why no tank meets the target: the pump never runs, or it pumps too little (water in
    m^3 or US gallons, as ``units`` says)."""
    if year.why:
        return f"the pump never runs: {year.why}{attended_hint(year)}"
    totals = year.totals
    w, water = display_unit("tank", units)
    return (
        f"the year pumps {totals.pumped * w:.1f} {water} of the {totals.demand * w:.1f} {water} "
        f"asked for, less than {1 - lolp:.4g} of it"
    )
