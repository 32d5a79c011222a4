"""The command line's rating: ``windpump rate``, a mill as a catalogue rates it (the capacity in
each wind, the stopping and starting winds, the largest heads it keeps running against and starts
against), in a builder's units or SI, for a design (the paper's, ``--design FILE``, ``--set``) or
a catalogue mill (``--wheel-ft 8 --cylinder-in '1 7/8' --lift '175 ft'``); registered by
:mod:`windpump.command.cli`.
"""

from __future__ import annotations

import argparse
import math

from ..averaging.ratings import max_head
from ..averaging.theory import steady_flow
from ..catalogue.aermotor import aermotor_702, aermotor_702_row
from ..model.design import Design
from ..readers.quantities import display_unit, format_quantity, parse_quantity, unit_of
from ..sites.site import wind_thresholds
from ..units import METRES_PER_FOOT, METRES_PER_INCH
from .cliargs import chosen_design, quantity, units_option

WINDS = {"us": "10, 15, 17.5, 20 mph", "si": "4, 6, 8, 10 m/s"}
"""The winds rated when ``--winds`` is not given: the catalogues' (US: 15 to 20 mph) and round
SI ones."""

NOTES = (
    "(capacity at the design's head; the averaged theory in steady winds)",
    "(max head running: the head at which a running pump stalls in that wind, Eq. 22's margin 1)",
    "(max head starting: the head it starts against from rest at every crank angle)",
    "(a catalogue's maximum lift is a rating well below both: docs/validation.rst compares them)",
)
"""What the table's columns mean, printed under it."""

MAX_WINDS = 100
"""Most winds one ``--winds`` may list."""


def add_rate_command(commands, design_options) -> None:
    """Add ``rate`` to the command line's subparsers."""
    rating = commands.add_parser(
        "rate",
        help="a mill's ratings: capacity in each wind, starting wind, largest heads",
        description="A design as a catalogue rates a mill (the averaged theory in steady "
        "winds): the capacity at its head in each wind, the largest head it keeps running "
        "against and the largest it starts against from rest, and the winds below which a "
        "running pump stops and above which one at rest starts. Exit code 0, 1 on an error.",
    )
    design_options(rating)
    mill = rating.add_argument_group(
        "a catalogue mill (in place of --design): the Aermotor 702 (windpump.catalogue)"
    )
    mill.add_argument("--wheel-ft", metavar="FT", help="its wheel's diameter: 6, 8, ... 16 ft")
    mill.add_argument(
        "--cylinder-in", metavar="IN", help="its cylinder's bore, e.g. '1 7/8' or 2.5 [in]"
    )
    mill.add_argument("--stroke", choices=("long", "short"), help="its stroke setting (long)")
    mill.add_argument(
        "--lift",
        type=quantity("m", "--lift"),
        help="the lift from the water to the outlet [m, or with its unit: '175 ft']",
    )
    rating.add_argument(
        "--winds",
        metavar="V1,V2,...",
        help="the winds rated, each with its unit or one unit after the last "
        f"(e.g. '10,15,20 mph'; bare numbers in m/s); default {WINDS['us']} with --units us, "
        f"else {WINDS['si']}",
    )
    units_option(rating)
    rating.set_defaults(run=rate_command)


def winds(text: str) -> list[float]:
    """``--winds``: wind speeds [m/s] from a list such as ``"10, 15, 20 mph"`` (a unit after
    the last number is every bare number's; with none, bare numbers are in m/s).

    Examples
    --------
    >>> winds("10, 15 mph"), winds("4,6")
    ([4.4704, 6.7056], [4.0, 6.0])
    """
    parts = [part.strip() for part in text.split(",")]
    if len(parts) > MAX_WINDS:
        raise ValueError(f"--winds: at most {MAX_WINDS} winds, not {len(parts):,}")
    unit = unit_of(parts[-1])
    speeds = []
    for part in parts:
        bare = unit and not unit_of(part)
        speeds.append(parse_quantity("--winds", f"{part} {unit}" if bare else part, "m/s"))
    negative = [v for v in speeds if v < 0.0]
    if negative:
        raise ValueError(f"--winds {text[:60]!r}: a wind speed must be 0 or more")
    return speeds


def rate_command(args: argparse.Namespace, extra: list[str]) -> int:
    """``windpump rate``: the design's ratings, a line for each wind, in ``--units``."""
    design = chosen_design(args, catalogue_mill(args))
    for line in catalogue_lines(args) + ratings(
        design, winds(args.winds or WINDS[args.units]), args.units
    ):
        print(line)
    return 0


def catalogue_lines(args: argparse.Namespace) -> list[str]:
    """For a catalogue mill, the lines that name it and give its table's row (capacity and
    maximum lift in the table's 15-20 mph wind), in ``--units``: a rating names what it rates,
    and a builder compares the model's heads with the catalogue's lift."""
    if args.wheel_ft is None:
        return []
    wheel = in_unit(args.wheel_ft, "--wheel-ft", "ft", METRES_PER_FOOT)
    bore = in_unit(args.cylinder_in, "--cylinder-in", "in", METRES_PER_INCH)
    stroke = args.stroke or "long"
    row = aermotor_702_row(wheel, bore, stroke=stroke)
    cylinder = row.cylinder if row is not None else f"{bore:g}"
    named = f"mill                 Aermotor 702, {wheel:g}-ft wheel, {cylinder} in cylinder, {stroke} stroke"
    if row is None:
        return [named, "catalogue            no row for it in the maker's table", ""]
    capacity = format_quantity(row.capacity, "flow", args.units, 3)
    lift = format_quantity(row.lift, "head", args.units, 3)
    return [
        named,
        f"catalogue            {capacity}, maximum lift {lift} (in a 15-20 mph wind)",
        "",
    ]


def catalogue_mill(args: argparse.Namespace) -> Design | None:
    """The Aermotor 702 of ``--wheel-ft``, ``--cylinder-in``, ``--stroke`` and ``--lift``
    (:func:`windpump.catalogue.aermotor_702`), or None without ``--wheel-ft``."""
    mill = {"--cylinder-in": args.cylinder_in, "--stroke": args.stroke, "--lift": args.lift}
    if args.wheel_ft is None:
        given = [option for option, value in mill.items() if value is not None]
        if given:
            verb = "apply" if len(given) > 1 else "applies"
            raise ValueError(f"{' and '.join(given)} {verb} only with --wheel-ft")
        return None
    if args.design:
        raise ValueError("--wheel-ft and --design: rate one or the other")
    missing = [option for option in ("--cylinder-in", "--lift") if mill[option] is None]
    if missing:
        raise ValueError(f"--wheel-ft needs {' and '.join(missing)}")
    return aermotor_702(
        in_unit(args.wheel_ft, "--wheel-ft", "ft", METRES_PER_FOOT),
        in_unit(args.cylinder_in, "--cylinder-in", "in", METRES_PER_INCH),
        stroke=args.stroke or "long",
        lift_ft=args.lift / METRES_PER_FOOT,
    )


def in_unit(text: str, option: str, unit: str, metres: float) -> float:
    """A length typed for ``option``, whose bare numbers (and fractions) are in ``unit``
    (``metres`` [m] each), as a number of ``unit``, to six decimals (``"1 7/8"`` is 1.875 in,
    ``"2.44 m"`` 8.005 ft).

    Examples
    --------
    >>> in_unit("1 7/8", "--cylinder-in", "in", 0.0254), in_unit("8 ft", "--wheel-ft", "ft", 0.3048)
    (1.875, 8.0)
    """
    typed = text if unit_of(text) else f"{text} {unit}"
    return round(parse_quantity(option, typed, "m") / metres, 6)


def ratings(design: Design, speeds: list[float], units: str = "si") -> list[str]:
    """The lines ``windpump rate`` prints for ``design`` in the winds ``speeds`` [m/s]."""

    def show(value: float, kind: str) -> str:  # 3 digits, or every digit of a whole number
        if math.isinf(value):
            return "no limit"
        whole = len(f"{abs(value * display_unit(kind, units)[0]):.0f}")
        return format_quantity(value, kind, units, max(3, whole))

    V_stop, V_start = wind_thresholds(design)
    if V_start is None:
        starting = "none: no torque at rest, it must be turned by hand"
    elif math.isinf(V_start):
        starting = "none: too little torque at rest in any wind"
    else:
        starting = f"{show(V_start, 'wind speed')} (a pump at rest starts above it)"
    lines = [
        f"head                 {show(design.h, 'head')}",
        f"stopping wind        {show(V_stop, 'wind speed')} (a running pump stops below it)",
        f"starting wind        {starting}",
        "",
        f"{'wind':<12}{'capacity':>14}{'max head running':>20}{'max head starting':>20}",
    ]
    flows = steady_flow(design, speeds)
    for V, flow in zip(speeds, flows, strict=True):
        lines.append(
            f"{show(V, 'wind speed'):<12}{show(float(flow), 'flow'):>14}"
            f"{show(max_head(design, V), 'head'):>20}"
            f"{show(max_head(design, V, start=True), 'head'):>20}"
        )
    lines.extend(NOTES)
    return lines
