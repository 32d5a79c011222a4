"""The ``windpump`` command: simulate a design, map it, sweep a table of designs, a year of water at
a site (``supply``, ``tank``: :mod:`windpump.command.sitecli`), a mill's ratings (``rate``:
:mod:`windpump.command.ratecli`), serve the explorer.

Every command starts from the paper's example (``Design.seed_example``), or a design file
(``--design FILE.json``, :meth:`Design.to_json`), with fields changed by ``--set NAME=VALUE``
(a field of :class:`Design`, or ``L_over_R`` / ``R_dagger``). Errors are one line on stderr and
exit code 1 (2 for a command line argparse cannot read).
"""

from __future__ import annotations

import argparse
import csv
import importlib.util
import io
import json
import math
import os
import re
import subprocess
import sys
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from ..averaging.averaged import stall_margin, steady_speeds, time_constant
from ..errors import StallError, cut, shown
from ..model.design import UNITS, Design, read_json
from ..progress import Progress, reporter
from ..readers.quantities import format_quantity
from ..run.dynamics import simulate
from ..study.maps import MAX_POINTS, DesignMap, design_map
from ..study.studies import FIGURES, INPUTS, sweep
from ..units import SECONDS_PER_DAY
from .cliargs import (  # noqa: F401 (cli.NAME keeps working)
    LINK_MILLIMETRES,
    MAX_FILE_BYTES,
    MAX_WORKERS,
    RATIOS,
    chosen_design,
    parse_setting,
    read_text,
    typed,
    units_option,
    workers,
)
from .ratecli import add_rate_command
from .sitecli import add_commands, check_writable

SERVE_OPTIONS = """\
options of panel serve, passed on (all of them: its own help follows), e.g.:
  --port PORT           the port to listen on (default 5006)
  --address ADDRESS     the address to listen on (default: all of this machine's)
  --show                open the explorer in a browser
  --allow-websocket-origin HOST[:PORT]
                        a host the page may be opened from (repeatable; behind a proxy, its name)
  --num-procs N         serve from N processes (0: one per core)
"""


def main(argv: list[str] | None = None) -> int:
    """Run the command line ``argv`` (default: the process's); return the exit code."""
    parser = build_parser()
    argv = sys.argv[1:] if argv is None else list(argv)
    args, extra = parser.parse_known_args(numeric_values(argv, parser))
    if extra and args.command != "serve":
        parser.error(f"unrecognized arguments: {' '.join(extra)}")
    try:
        return args.run(args, extra)
    except KeyboardInterrupt:
        print(f"windpump {args.command}: interrupted", file=sys.stderr)
        return 130
    except Exception as error:  # every failure: one line, exit 1, never a traceback
        print(f"windpump {args.command}: error: {one_line(error)}", file=sys.stderr)
        return 1


def numeric_values(argv: list[str], parser: argparse.ArgumentParser) -> list[str]:
    """``argv`` with each option that takes a value and is followed by a negative or signed
    number joined to it (``--shear -inf`` as ``--shear=-inf``): argparse takes a word starting
    with '-' for an option unless it is plain digits (-1, -0.5), so ``-inf``, ``-nan`` and
    ``-1e-3`` (or map's range ``-1:2:10``) were 'expected one argument' instead of a value
    checked in words. Up to ``serve``
    (whose options are panel's) or ``--``.

    Examples
    --------
    >>> numeric_values(["tank", "--shear", "-inf", "--lolp", "-1e-3"], build_parser())
    ['tank', '--shear=-inf', '--lolp=-1e-3']
    """
    takes_value: set[str] = set()
    parsers = [parser]
    while parsers:
        for action in parsers.pop()._actions:
            if isinstance(action, argparse._SubParsersAction):
                parsers.extend(action.choices.values())
            elif action.option_strings and action.nargs is None:
                takes_value.update(action.option_strings)
    joined: list[str] = []
    words = iter(argv)
    for word in words:
        if word in ("serve", "--"):
            return [*joined, word, *words]
        joined.append(word)
        if word in takes_value:
            value = next(words, None)
            if value is None:
                break
            if value.startswith("-") and (_is_number(value) or ":" in value):
                joined[-1] = f"{word}={value}"
            else:
                joined.append(value)
    return joined


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


NUMPY_NUMBER = re.compile(r"np\.(?:float|int|uint|complex)\d*\(([^()]*)\)|np\.(True|False)_")
"""How numpy 2 writes a number in a message (``np.float64(nan)``, ``np.True_``)."""


def one_line(error: BaseException, limit: int = 2000) -> str:
    """An error as one line of bounded length; its type too when it is not one of the messages
    windpump writes for people (a ValueError or an OSError)."""
    text = " ".join(str(error).split()) or type(error).__name__
    text = NUMPY_NUMBER.sub(
        lambda m: m.group(1) or m.group(2), text
    )  # np.float64(nan) -> nan: plain numbers
    if len(text) > limit:
        text = text[: limit - 1] + "…"
    if isinstance(error, ValueError | OSError | ImportError):
        return text
    if isinstance(error, MemoryError):
        return f"out of memory ({text})"
    return f"{type(error).__name__}: {text}"


def build_parser() -> argparse.ArgumentParser:
    """The parser of every command."""
    parser = argparse.ArgumentParser(
        prog="windpump", description="Dynamics of a wind-driven piston pump (Louge 2010)."
    )
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    simulate = commands.add_parser(
        "simulate",
        help="run a design in full and summarise it",
        description="Run a design in full (Eq. 12) and print the averaged theory's stall margin, "
        "speeds and time constant (Eqs. 21, 22, 25) beside the run's flow and volume; --csv "
        "writes its samples.",
    )
    design_options(simulate)
    run_options(simulate)
    simulate.add_argument("--csv", metavar="FILE", help="write the run's samples here")
    simulate.add_argument("--litres", action="store_true", help="volume and flow in L in the CSV")
    units_option(simulate)
    simulate.set_defaults(run=simulate_command)

    mapping = commands.add_parser(
        "map",
        help="the design map over gear ratio and head",
        description="Water a day over the sprocket ratio R+ and the head h, with the stall "
        "boundary and the best ratio (the averaged theory, or --numeric from full runs): a CSV, "
        "and a PNG with --png.",
    )
    design_options(mapping)
    mapping.add_argument("--gear-ratios", metavar="FROM:TO:N", help="default R+/8:2R+:200")
    mapping.add_argument("--heads", metavar="FROM:TO:N", help="default 0:3h:200")
    mapping.add_argument("--numeric", action="store_true", help="from full simulations")
    mapping.add_argument("--csv", metavar="FILE", help="write the map here (default: stdout)")
    mapping.add_argument("--png", metavar="FILE", help="draw the map here (needs matplotlib)")
    mapping.set_defaults(run=map_command)

    sweeping = commands.add_parser(
        "sweep",
        help="run a table of designs",
        description="Run a table of designs (a CSV row, or a JSON design, each) on this "
        "machine's processes or a dask scheduler, and write a row of figures for each.",
    )
    sweeping.add_argument("file", metavar="FILE", help="designs: .csv (a row each) or .json")
    design_options(sweeping, base="the design each row changes")
    run_options(sweeping)
    sweeping.add_argument(
        "--workers", type=workers, default=1, help=f"processes on this machine (1 to {MAX_WORKERS})"
    )
    sweeping.add_argument("--scheduler", metavar="ADDRESS", help="a dask.distributed scheduler")
    sweeping.add_argument("--csv", metavar="FILE", help="write the table here (default: stdout)")
    sweeping.set_defaults(run=sweep_command)

    add_commands(commands, design_options)
    add_rate_command(commands, design_options)

    serve = commands.add_parser(
        "serve",
        help="compile the solver if needed, then start the explorer (panel serve app/)",
        description=(
            "Start the explorer: first the solver's compile step (python -m "
            "windpump_app.compiling: ~1 minute on 2 cores once after an install, then "
            '"nothing to do" within seconds), then panel serve app/, with every other option '
            "passed on."
        ),
        usage="%(prog)s [-h] [--no-compile] [panel serve options]",
        epilog=SERVE_OPTIONS,
        formatter_class=argparse.RawDescriptionHelpFormatter,
        add_help=False,  # its --help adds panel serve's own
    )
    serve.add_argument(
        "-h", "--help", action="store_true", help="show this and panel serve's options, then exit"
    )
    serve.add_argument(
        "--no-compile",
        action="store_true",
        help="skip the compile step: the server then compiles in the background what a page "
        "needs, and a page waits for it",
    )
    serve.set_defaults(run=serve_command, help_text=serve.format_help)
    return parser


def design_options(parser: argparse.ArgumentParser, base: str = "the design") -> None:
    parser.add_argument("--design", metavar="FILE", help=f"{base}, as JSON (default: the paper's)")
    parser.add_argument(
        "--set",
        metavar="NAME=VALUE",
        action="append",
        default=[],
        help="change a field (repeatable), e.g. --set h=5",
    )


def run_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--t-end", type=float, default=600.0, help="duration [s] (600)")
    parser.add_argument("--theta0", type=float, default=math.pi / 2, help="start angle [rad]")
    parser.add_argument("--theta-dot0", type=float, default=3.0, help="kick [rad/s] (3)")


def simulate_command(args: argparse.Namespace, extra: list[str]) -> int:
    """``windpump simulate``: a summary on stdout, the samples in --csv."""
    design = chosen_design(args)
    run = simulate(design, args.t_end, args.theta0, args.theta_dot0)
    for line in summary(design, run, args.units):
        print(line)
    if args.csv:
        run.to_csv(args.csv, litres=args.litres)
        print(f"samples written to {args.csv}")
    return 0


def summary(design: Design, run, units: str = "si") -> list[str]:
    """The lines ``windpump simulate`` prints: the averaged theory, then the run; its water in
    litres and L/s (``units`` ``"si"``) or US gallons and gal/h (``"us"``)."""
    margin = stall_margin(design)
    lines = [f"stall margin (Eq. 22)        {margin:.6g}"]
    try:
        alpha_plus, alpha_minus = steady_speeds(design)
        tau = time_constant(design)
    except StallError:
        lines.append("alpha+, alpha-, tau           none: the windmill cannot carry this load")
    else:
        lines.append(f"alpha+ (Eq. 21)              {alpha_plus:.6g} rad/s")
        if alpha_minus is None:  # a leak hole: no speed below which it stalls
            lines.append("alpha- (Eq. 21)              none: it never stalls from a kick")
        else:
            lines.append(f"alpha- (Eq. 21)              {alpha_minus:.6g} rad/s")
        lines.append(f"tau (Eq. 25)                 {tau:.6g} s")
    turns = (run.theta[-1] - run.theta[0]) / (2 * math.pi)
    if not run.stalled and turns >= 1.0:
        flow = run.intermittency(10).mean_flow
        lines.append(
            f"mean flow, last revolutions  {format_quantity(flow, 'flow', units, 6)} "
            f"({format_quantity(flow * SECONDS_PER_DAY, 'daily flow', units)})"
        )
    volume = format_quantity(run.volume[-1], "volume", units, 6)
    lines.append(f"volume pumped                {volume} in {run.t[-1]:.6g} s")
    if run.stalled:
        lines.append(f"stalled                      at t = {run.t_stall:.6g} s")
    else:
        lines.append("stalled                      no: turning at the end")
    return lines


def grid_option(text: str | None, default: tuple[float, float, int], name: str) -> np.ndarray:
    """``FROM:TO:N`` as N evenly spaced values."""
    if text is None:
        start, stop, count = default
    else:
        parts = text.split(":")
        try:
            start, stop, count = float(parts[0]), float(parts[1]), int(parts[2])
        except (IndexError, ValueError):
            raise ValueError(f"--{name} {shown(text)}: expected FROM:TO:N, e.g. 1:10:200") from None
        if len(parts) != 3 or not 1 <= count <= MAX_POINTS:
            raise ValueError(
                f"--{name} {shown(text)}: expected FROM:TO:N with N from 1 to {MAX_POINTS:,}"
            )
        if not (math.isfinite(start) and math.isfinite(stop)):
            raise ValueError(f"--{name} {shown(text)}: FROM and TO must be finite numbers")
    return np.linspace(start, stop, count)


def map_command(args: argparse.Namespace, extra: list[str]) -> int:
    """``windpump map``: the map as CSV (stdout or --csv), and a plot with --png."""
    design = chosen_design(args)
    ratios = grid_option(
        args.gear_ratios, (design.R_dagger / 8, 2 * design.R_dagger, 200), "gear-ratios"
    )
    heads = grid_option(args.heads, (0.0, 3 * design.h if design.h > 0 else 10.0, 200), "heads")

    for option, path in (("--csv", args.csv), ("--png", args.png)):
        if path:
            check_writable(path, option)  # before the work, which may take hours
    if args.png:
        import_matplotlib()  # before the work: a missing plotter is found at once
    progress = TimeLeft(ratios.size * heads.size) if args.numeric else None
    result = design_map(design, ratios, heads, numeric=args.numeric, progress=progress)
    write(result.to_csv(), args.csv)
    if args.png:
        plot_map(result, args.png)
        print(f"map drawn in {args.png}", file=sys.stderr)
    return 0


class TimeLeft:
    """A numeric map's progress: says up front how many full simulations it runs, and once the
    first batch is done how long the rest will take (on stderr; a bar too in a terminal)."""

    SAY_FROM = 10.0
    """Remaining times [s] worth saying."""

    def __init__(self, runs: int):
        print(f"windpump map: {runs:,} full simulations", file=sys.stderr)
        self.started, self.said = time.monotonic(), False
        self.bar: Progress | None = None

    def __call__(self, done: int, total: int) -> None:
        if self.bar is None:
            self.bar = reporter(None, total, "design map")
        self.bar(done, total)
        if self.said or not 0 < done < total:
            return
        self.said = True
        left = (time.monotonic() - self.started) / done * (total - done)
        if left >= self.SAY_FROM:
            print(f"windpump map: about {duration(left)} left", file=sys.stderr)


def duration(seconds: float) -> str:
    """``seconds`` in words: ``"40 s"``, ``"12 min"``, ``"3.5 h"``."""
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def import_matplotlib():
    try:
        import matplotlib
    except ImportError:
        raise ImportError("--png needs matplotlib: pip install matplotlib") from None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_map(result: DesignMap, path: str) -> None:
    """Draw :func:`map_figure` into the PNG file ``path``."""
    plt = import_matplotlib()
    figure = map_figure(result)
    # A PNG unless the name says another format: matplotlib would add ".png" to a name without
    # one, and "map drawn in NAME" would name another file.
    try:
        figure.savefig(path, format=Path(path).suffix[1:].lower() or "png")
    except OSError as error:
        raise OSError(f"--png {path}: {error.strerror or error}") from None
    finally:
        plt.close(figure)


def map_figure(result: DesignMap):
    """Mean flow [m³/day] over gear ratio and head on a log colour scale, labelled contours at 1,
    2 and 5 × 10^k, the stall boundary, the best gear and the design: a matplotlib Figure.

    The flows of a map span one to three decades (the seed's: 16 to 276 m³/day, most below 60):
    on a linear scale most of the map is one colour. Where the pump stalls there is no flow and
    no colour.
    """
    plt = import_matplotlib()
    from matplotlib.colors import LogNorm
    from matplotlib.ticker import FuncFormatter

    figure, axes = plt.subplots(figsize=(8, 5.5), dpi=120)
    per_day = result.mean_flow * SECONDS_PER_DAY  # m^3/day
    flowing = np.isfinite(per_day) & (per_day > 0)
    if flowing.any():
        low, high = float(per_day[flowing].min()), float(per_day[flowing].max())
        high = max(high, low * 1.01)  # a map of one flow still gets a scale
        shown = np.where(flowing, per_day, np.nan)
        x, y = result.gear_ratios, result.heads
        norm = LogNorm(low, high)
        filled = axes.contourf(x, y, shown, levels=np.geomspace(low, high, 17), norm=norm)
        marks = nice_levels(low, high) or [low, high]
        bar = figure.colorbar(filled, ax=axes, ticks=marks)
        bar.set_label("mean flow [m³/day], log scale")
        bar.ax.yaxis.set_major_formatter(FuncFormatter(lambda value, _: f"{value:g}"))
        bar.ax.minorticks_off()
        lines = axes.contour(x, y, shown, levels=marks, colors="white", linewidths=0.8)
        axes.clabel(lines, fmt=lambda value: f"{value:g}", fontsize=8)
    axes.plot(result.stall_gear_ratio, result.heads, "k-", lw=2, label="stall boundary (margin 1)")
    axes.plot(result.best_gear_ratio, result.heads, "w--", lw=2, label="best gear ratio")
    design = result.design
    axes.plot(design.R_dagger, design.h, "r*", ms=14, label="the design")
    axes.set_xlim(result.gear_ratios[0], result.gear_ratios[-1])
    axes.set_xlabel("gear ratio R1/R0 [-]")
    axes.set_ylabel("head h [m]")
    kind = "full simulations" if result.numeric else "averaged theory"
    axes.set_title(f"Design map ({kind}); blank: the pump stalls")
    axes.legend(loc="lower right")
    return figure


def nice_levels(low: float, high: float) -> list[float]:
    """The values 1, 2 and 5 × 10^k from ``low`` to ``high`` (both > 0).

    Examples
    --------
    >>> nice_levels(15.9, 276.5)
    [20.0, 50.0, 100.0, 200.0]
    """
    decades = range(math.floor(math.log10(low)), math.ceil(math.log10(high)) + 1)
    values = [float(f"{m}e{k}") for k in decades for m in (1, 2, 5)]
    return [value for value in values if low <= value <= high]


def write(text: str, path: str | None) -> None:
    """Text to a file, or to stdout."""
    if path:
        Path(path).write_text(text, encoding="utf-8")
    else:
        sys.stdout.write(text)


def read_json_designs(path: str, text: str) -> list[Design]:
    """A JSON design document, or a list of them; an error names the file and the design."""
    try:
        documents = read_json(text)
    except ValueError as error:
        raise ValueError(f"{cut(path)}: {error}") from None
    if not isinstance(documents, list):
        documents = [documents]
    designs = []
    for number, document in enumerate(documents, start=1):
        try:
            designs.append(Design.from_json(json.dumps(document)))
        except ValueError as error:
            raise ValueError(f"{cut(path)}, design {number}: {error}") from None
    return designs


def read_designs(path: str, base: Design) -> tuple[list[Design], dict[str, list[float]]]:
    """Designs from a CSV (a row each: field columns, optional t_end/theta0/theta_dot0; a header
    like ``h [m]`` is read as ``h``) or a JSON list of design documents; and per-run inputs."""
    text = read_text(path, "FILE")
    if path.endswith(".json"):
        return read_json_designs(path, text), {}
    rows = csv_rows(text)
    if not rows:
        raise ValueError(f"{cut(path)}: empty")
    names = [cell.split("[")[0].strip() for cell in rows[0]]
    known = set(UNITS) | set(RATIOS) | set(INPUTS) | set(FIGURES)  # (a sweep's table reads back)
    unknown = [name for name in names if name not in known]
    if unknown:
        raise ValueError(
            f"{cut(path)}: unknown column(s) {shown(unknown)}; columns are fields of Design"
        )
    designs: list[Design] = []
    inputs: dict[str, list[float]] = {name: [] for name in INPUTS if name in names}
    for line, row in enumerate(rows[1:], start=2):
        if not row:
            continue
        if len(row) != len(names):
            raise ValueError(f"{cut(path)}, line {line}: {len(row)} cells for {len(names)} columns")
        values = dict(zip(names, row, strict=True))
        try:
            changes: dict[str, Any] = {
                n: typed(n, v) for n, v in values.items() if n in UNITS or n in RATIOS
            }
            ratios = {n: changes.pop(n) for n in RATIOS if n in changes}
            designs.append(base.with_ratios(**ratios, **changes))
            for name in inputs:
                inputs[name].append(float(typed(name, values[name])))
        except ValueError as error:
            raise ValueError(f"{cut(path)}, line {line}: {error}") from None
    return designs, inputs


def csv_rows(text: str) -> list[list[str]]:
    """A CSV's rows of cells, separated by tabs, semicolons or commas as the header row is (a
    spreadsheet in a locale with decimal commas writes ``;`` and ``2,5``: read as 2.5)."""
    lines = text.splitlines()
    header = next((line for line in lines if line.strip()), "")
    separator = next((s for s in ("\t", ";") if s in header), ",")
    rows = list(csv.reader(io.StringIO(text), delimiter=separator))
    if separator != ",":
        rows = [[cell.replace(",", ".") for cell in row] for row in rows]
    return rows


def sweep_command(args: argparse.Namespace, extra: list[str]) -> int:
    """``windpump sweep FILE``: the table as CSV, on --workers processes or a dask scheduler."""
    designs, inputs = read_designs(args.file, chosen_design(args))
    runs = {
        "t_end": inputs.get("t_end", args.t_end),
        "theta0": inputs.get("theta0", args.theta0),
        "theta_dot0": inputs.get("theta_dot0", args.theta_dot0),
    }
    with warnings.catch_warnings():  # the runs that failed: a line each, below
        warnings.filterwarnings("ignore", r"\d+ of \d+ runs failed", RuntimeWarning)
        table = run_sweep(designs, runs, args.scheduler, args.workers)
    write(table.without_failures().to_csv(), args.csv)
    for index, reason in table.failed.items():
        print(
            f"windpump sweep: error: design {index + 1} of {cut(args.file)}: {reason}",
            file=sys.stderr,
        )
    return 1 if table.failed else 0


def run_sweep(designs: list[Design], runs: dict, scheduler: str | None, workers: int):
    """The sweep on a dask scheduler, on ``workers`` processes, or here."""
    if scheduler:
        try:
            from distributed import Client
        except ImportError:
            raise ImportError(
                "--scheduler needs dask.distributed: pip install distributed"
            ) from None
        with Client(scheduler) as client:
            return sweep(designs, **runs, executor=client.get_executor())
    if workers > 1:
        from concurrent.futures import ProcessPoolExecutor

        with ProcessPoolExecutor(workers) as pool:
            return sweep(designs, **runs, executor=pool)
    return sweep(designs, **runs)


def explorer_folder() -> Path:
    """The installed explorer's folder (the package ``windpump_app``, the repository's app/),
    which ``panel serve`` serves; found without importing it (the core never imports the app)."""
    spec = importlib.util.find_spec("windpump_app")
    folders = list(spec.submodule_search_locations or []) if spec is not None else []
    if not folders or not (Path(folders[0]) / "main.py").is_file():
        raise OSError(
            'the explorer (the package windpump_app) is not installed: pip install -e ".[app]"'
        )
    return Path(folders[0]).resolve()  # an editable install's is app/: the page's URL is /app


COMPILE_STEP = ["-m", "windpump_app.compiling"]  # the README's, before panel serve app/


def serve_command(args: argparse.Namespace, extra: list[str]) -> int:
    """``windpump serve [--no-compile] [panel serve options]``: the README's serve command,
    ``python -m windpump_app.compiling && panel serve app/``. The compile step (in a process of
    its own: the core never imports the app) compiles each part of the solver not yet in numba's
    cache and says "nothing to do" when all are; a failed step is said, and the server then
    compiles what a page needs itself."""
    if args.help:
        print(args.help_text())
        panel = [sys.executable, "-m", "panel", "serve", "--help"]
        listed = subprocess.run(panel, capture_output=True, text=True, timeout=300)
        print(
            listed.stdout
            if listed.returncode == 0
            else "(panel is not installed: pip install panel)"
        )
        return 0
    port = next((v for o, v in zip(extra, extra[1:], strict=False) if o == "--port"), None)
    port = next((o[7:] for o in extra if o.startswith("--port=")), port)
    if port is not None and not (port.isdigit() and int(port) <= 65535):
        raise ValueError(f"--port {shown(port)}: a port must be a whole number from 0 to 65535")
    command = [sys.executable, "-m", "panel", "serve", str(explorer_folder()), *extra]
    if not args.no_compile:
        failed = subprocess.call([sys.executable, *COMPILE_STEP])
        if failed:
            print(
                f"windpump serve: the compile step exited with {failed}: "
                "the server compiles what a page needs itself",
                file=sys.stderr,
            )
    if os.name == "posix":  # become the server: a signal to this process reaches it
        os.execv(sys.executable, command)
    return subprocess.call(command)
