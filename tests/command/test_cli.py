"""The windpump command: its outputs, files, errors and exit codes (in this process, and as a
process of its own where only a process shows it: tests/command_line.py)."""

from __future__ import annotations

import csv
import io
import re
import shutil
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import numpy as np
import pytest
from command_line import windpump_command

import windpump
from windpump import Design
from windpump.units import SECONDS_PER_DAY

SEED = Design.seed_example()


def test_the_console_script_is_installed():
    script = shutil.which("windpump")
    assert script is not None
    done = subprocess.run([script, "--help"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0
    assert all(command in done.stdout for command in ("simulate", "map", "sweep", "serve"))


def test_simulate_prints_the_papers_example_and_writes_its_csv(tmp_path):
    out = tmp_path / "run.csv"
    done = windpump_command("simulate", "--csv", str(out))
    assert done.returncode == 0, done.stderr
    margin = float(done.stdout.split("stall margin (Eq. 22)")[1].split()[0])
    alpha_plus = float(done.stdout.split("alpha+ (Eq. 21)")[1].split()[0])
    assert margin == pytest.approx(windpump.stall_margin(SEED), rel=1e-5)
    assert alpha_plus == pytest.approx(windpump.steady_speeds(SEED)[0], rel=1e-5)
    assert "turning at the end" in done.stdout
    header = [line for line in out.read_text().splitlines() if line.startswith("# h ")]
    assert header == ["# h = 3 m"]  # the CSV records its design
    data = np.genfromtxt(out, delimiter=",", comments="#", skip_header=1)
    run = windpump.simulate(SEED, 600.0)
    assert data[-1, 0] == pytest.approx(600.0) and data[-1, 3] == pytest.approx(run.volume[-1])


def test_set_and_design_files_choose_the_design(tmp_path):
    changed = SEED.replace(h=5.0, cylinders=2)
    file = tmp_path / "pump.json"
    file.write_text(changed.to_json())
    by_file = windpump_command("simulate", "--design", str(file), "--t-end", "60")
    by_set = windpump_command("simulate", "--set", "h=5", "--set", "cylinders=2", "--t-end", "60")
    assert by_file.returncode == 0 == by_set.returncode
    assert by_file.stdout == by_set.stdout
    assert f"{windpump.stall_margin(changed):.6g}" in by_file.stdout


def test_set_takes_the_real_machines_fields(tmp_path):
    real = SEED.replace(m_r=2.0, d_leak=0.003, eta_t=0.9, L_main=12.0, D_main=0.02)
    file = tmp_path / "real.json"
    file.write_text(real.to_json())
    settings = ["m_r=2", "d_leak=0.003", "eta_t=0.9", "L_main=12", "D_main=0.02"]
    by_set = windpump_command(
        "simulate", *(f"--set={text}" for text in settings), "--t-end", "5",
        "--csv", str(tmp_path / "set.csv"),
    )  # fmt: skip
    by_file = windpump_command(
        "simulate", "--design", str(file), "--t-end", "5", "--csv", str(tmp_path / "file.csv")
    )
    assert by_set.returncode == 0 == by_file.returncode, by_set.stderr + by_file.stderr
    assert by_set.stdout.replace("set.csv", "file.csv") == by_file.stdout
    header = [line for line in (tmp_path / "set.csv").read_text().splitlines() if "#" in line]
    for line in ("# m_r = 2 kg", "# d_leak = 0.003 m", "# eta_t = 0.9", "# L_main = 12 m",
                 "# D_main = 0.02 m", "# f_main = 0.02", "# Cd_leak = 0.6"):  # fmt: skip
        assert line in header
    assert (tmp_path / "set.csv").read_text() == (tmp_path / "file.csv").read_text()


@pytest.mark.parametrize(
    "args, words",
    [
        (["simulate", "--set", "h=-1"], "h = -1.0 m is not allowed"),
        (["simulate", "--set", "m_r=-2"], "m_r = -2.0 kg is not allowed: m_r must be"),
        (["simulate", "--set", "eta_t=1.5"], "eta_t = 1.5 is not allowed: eta_t must be"),
        (["simulate", "--set", "D_main=0"], "D_main = 0.0 m is not allowed: D_main must be"),
        (["simulate", "--set", "f_main=0.3"], "f_main = 0.3 is not allowed: f_main must be"),
        (["simulate", "--set", "d_leak=0.05"], "d_leak = 0.05 m is not allowed: d_leak must be"),
        (["simulate", "--set", "Cd_leak=0"], "Cd_leak = 0.0 is not allowed: Cd_leak must be"),
        (["simulate", "--set", "L_main=-3"], "L_main = -3.0 m is not allowed: L_main must be"),
        (["simulate", "--set", "m_r=heavy"], "m_r = 'heavy' is not allowed: m_r must be a number"),
        (["simulate", "--set", "bore=1"], "--set 'bore=1': bore is not a field of the design"),
        (["simulate", "--set", "h"], "expected NAME=VALUE"),
        # the explorer's link names are in millimetres: say which field it is, in metres
        (["simulate", "--set", "d_leak_mm=3"], "d_leak_mm is the explorer's link name: use d_leak"),
        (["simulate", "--set", "D_main_mm=25"], "--set D_main=0.025 (in metres)"),
        (["simulate", "--set", "double_acting=maybe"], "double_acting"),
        (["simulate", "--t-end", "1e9"], "t_end"),
        (["simulate", "--design", "no-such-file.json"], "no-such-file.json"),
        (["map", "--heads", "1:2"], "FROM:TO:N"),
        (["map", "--gear-ratios", "3:1:5"], "gear_ratios"),
        (["sweep", "no-such-table.csv"], "no-such-table.csv"),
    ],
)
def test_errors_are_one_line_and_exit_1(args, words):
    done = windpump_command(*args)
    assert done.returncode == 1
    assert done.stdout == ""
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("windpump ") and words in lines[0]


@pytest.mark.parametrize(
    "text, words",
    [
        ("", "pump.json: not JSON"),
        ('{"fields": {"h": 3}}', 'pump.json: not a design file: it needs "schema"'),
        (SEED.replace(m_r=15.0).to_json().replace('"m_r": 15.0', '"m_r": -2'), "pump.json: m_r"),
    ],
    ids=["empty", "no-schema", "negative-m_r"],
)
@pytest.mark.parametrize("command", ["simulate", "map", "tank"])
def test_a_bad_design_file_is_named_in_its_error(short_tmp_path, text, words, command):
    """Every command's --design names the file it could not read, as ``sweep`` does."""
    (short_tmp_path / "pump.json").write_text(text)
    site = ["--site", "greensboro", "--demand", "2"] if command == "tank" else []
    done = windpump_command(command, "--design", str(short_tmp_path / "pump.json"), *site)
    assert done.returncode == 1 and done.stdout == ""
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and words in lines[0], done.stderr


@pytest.mark.parametrize("command", ["simulate", "map", "sweep", "supply", "tank", "serve"])
def test_every_commands_help_says_what_it_does(command):
    """``windpump COMMAND --help`` opens with a sentence on what the command does, not the bare
    list of options (a newcomer's ``windpump supply --help`` had none)."""
    if command == "serve":  # its help is panel serve's, after its own
        pytest.importorskip("panel")
    done = windpump_command(command, "--help", process=command == "serve")
    assert done.returncode == 0
    before_options = done.stdout.split("\noptions:")[0].split("\n\n")
    assert len(before_options) >= 2 and before_options[1].strip()[:1].isupper(), done.stdout


def test_a_command_line_argparse_cannot_read_exits_2():
    done = windpump_command("simulate", "--t-end", "soon")
    assert done.returncode == 2 and "--t-end" in done.stderr
    assert windpump_command("fly").returncode == 2


@pytest.mark.parametrize(
    "args",
    [["simulate", "--set", "h=-1"], ["simulate", "--t-end", "soon"], ["map", "--help"],
     ["simulate", "--t-end", "30"]],
    ids=["refused", "unreadable", "help", "run"],
)  # fmt: skip
def test_a_process_says_and_exits_as_the_command_run_here(args):
    """What the other tests read in this process is what ``python -m windpump`` prints and
    exits with: the same code, the same stdout, the same stderr, and no traceback."""
    here, process = windpump_command(*args), windpump_command(*args, process=True)
    assert (process.returncode, process.stdout, process.stderr) == (
        here.returncode, here.stdout, here.stderr,
    )  # fmt: skip
    assert "Traceback" not in process.stderr


def test_map_writes_the_design_maps_csv_and_png(tmp_path):
    out, png = tmp_path / "map.csv", tmp_path / "map.png"
    done = windpump_command(
        "map", "--gear-ratios", "1:8:8", "--heads", "0:9:4", "--csv", str(out), "--png", str(png)
    )
    assert done.returncode == 0, done.stderr
    rows = list(csv.DictReader(io.StringIO(out.read_text())))
    expected = windpump.design_map(SEED, np.linspace(1, 8, 8), np.linspace(0, 9, 4))
    assert len(rows) == 32
    flows = np.array([float(row["mean_flow [m^3/s]"]) for row in rows]).reshape(4, 8)
    np.testing.assert_allclose(flows, expected.mean_flow, rtol=1e-11)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_map_is_drawn_in_the_file_named_and_a_folder_is_refused_before_the_work(tmp_path):
    """matplotlib adds ".png" to a name without a suffix: "map drawn in NAME" named another
    file, and a folder or /dev/full got a NAME.png beside it."""
    plain = tmp_path / "map"
    done = windpump_command(
        "map", "--gear-ratios", "1:8:4", "--heads", "0:9:3", "--png", str(plain)
    )
    assert done.returncode == 0, done.stderr
    assert plain.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and f"map drawn in {plain}" in done.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["map"]
    for option in ("--png", "--csv"):
        done = windpump_command("map", "--numeric", option, str(tmp_path))
        assert done.returncode == 1 and "full simulations" not in done.stderr  # nothing run
        assert (
            done.stderr.strip() == f"windpump map: error: {option} {tmp_path}: a folder, not a file"
        )
    assert sorted(p.name for p in tmp_path.iterdir()) == ["map"]


@pytest.mark.parametrize("port", ["99999999", "-1", "abc"])
def test_serve_refuses_a_port_that_is_not_one_in_words(port):
    done = windpump_command("serve", f"--port={port}", process=True)
    assert done.returncode == 1
    assert done.stderr.strip() == (
        f"windpump serve: error: --port '{port}': a port must be a whole number from 0 to 65535"
    )


def test_the_map_png_has_a_log_colour_scale_with_labelled_contours():
    from matplotlib.colors import LogNorm
    from matplotlib.contour import ContourSet

    from windpump.command.cli import map_figure

    result = windpump.design_map(SEED, np.linspace(0.5, 8, 200), np.linspace(0, 9, 200))
    per_day = result.mean_flow[result.mean_flow > 0] * SECONDS_PER_DAY
    low, high = per_day.min(), per_day.max()  # 16 to 276 m³/day
    nice = [m * 10.0**k for k in range(-1, 5) for m in (1, 2, 5) if low <= m * 10.0**k <= high]
    assert nice == [20, 50, 100, 200]
    figure = map_figure(result)
    axes, bar = figure.axes
    contours = [c for c in axes.get_children() if isinstance(c, ContourSet)]
    filled = [c for c in contours if c.filled]
    lines = [c for c in contours if not c.filled]
    assert isinstance(filled[0].norm, LogNorm)
    assert (filled[0].norm.vmin, filled[0].norm.vmax) == pytest.approx((low, high))
    assert list(lines[0].levels) == pytest.approx(nice)
    assert sorted(float(t.get_text()) for t in axes.texts) == pytest.approx(nice)  # labelled
    assert [t.get_text() for t in bar.get_yticklabels()] == ["20", "50", "100", "200"]
    assert "m³/day" in bar.get_ylabel() and "log" in bar.get_ylabel()


def test_the_map_png_is_not_nearly_all_one_colour(tmp_path):
    """The PNG read back: the map's pixels spread over many colours (on a linear scale 43 % were
    one colour and 76 % three)."""
    from matplotlib import image

    from windpump.command.cli import map_figure

    png = tmp_path / "map.png"
    done = windpump_command("map", "--csv", str(tmp_path / "map.csv"), "--png", str(png))
    assert done.returncode == 0, done.stderr
    pixels = image.imread(png)
    result = windpump.design_map(SEED, np.linspace(0.5, 8, 200), np.linspace(0, 9, 200))
    box = map_figure(result).axes[0].get_window_extent()  # the map's pixels, the same layout
    height = pixels.shape[0]
    inside = pixels[int(height - box.y1) + 2 : int(height - box.y0) - 2,
                    int(box.x0) + 2 : int(box.x1) - 2, :3]  # fmt: skip
    _, counts = np.unique((255 * inside).round().reshape(-1, 3), axis=0, return_counts=True)
    shares = np.sort(counts / counts.sum())[::-1]
    assert shares[0] < 0.25 and shares[:3].sum() < 0.5, shares[:3]
    assert np.count_nonzero(shares > 0.02) >= 8


def test_serve_help_lists_the_panel_options_it_passes_on():
    done = windpump_command("serve", "--help", process=True)
    assert done.returncode == 0, done.stderr
    for option in ("--port", "--address", "--show", "--allow-websocket-origin", "--num-procs"):
        assert option in done.stdout.split("usage: panel serve")[0]  # described in ours
    panel = subprocess.run(
        [sys.executable, "-m", "panel", "serve", "--help"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    options = set(re.findall(r"^  (--[a-z][a-z-]+)", panel.stdout, flags=re.M))
    assert len(options) > 30 and options <= set(re.findall(r"--[a-z][a-z-]+", done.stdout))


def test_sweep_runs_a_table_of_designs_on_two_workers(tmp_path):
    table = tmp_path / "designs.csv"
    table.write_text("h [m],R_dagger,t_end\n1,4,100\n3,6,100\n20,4,90\n")
    out = tmp_path / "out.csv"
    done = windpump_command("sweep", str(table), "--workers", "2", "--csv", str(out), process=True)
    assert done.returncode == 0, done.stderr
    rows = list(csv.DictReader(io.StringIO(out.read_text())))
    designs = [SEED.replace(h=1.0), SEED.with_ratios(R_dagger=6.0, h=3.0), SEED.replace(h=20.0)]
    expected = windpump.sweep(designs, [100.0, 100.0, 90.0])
    assert [float(row["volume [m^3]"]) for row in rows] == pytest.approx(expected.volume, rel=1e-11)
    assert [row["stalled"] for row in rows] == ["False", "False", "True"]
    # the table reads back as designs (its figure columns are ignored)
    again = windpump_command("sweep", str(out), "--csv", str(tmp_path / "again.csv"))
    assert again.returncode == 0, again.stderr
    assert (tmp_path / "again.csv").read_text() == out.read_text()


def test_sweep_reads_and_writes_the_real_machines_columns(tmp_path):
    table = tmp_path / "designs.csv"
    table.write_text(
        "h [m],m_r [kg],d_leak [m],eta_t,L_main [m],t_end\n3,4,0.002,0.8,20,30\n5,0,0,1,0,30\n"
    )
    out = tmp_path / "out.csv"
    done = windpump_command("sweep", str(table), "--csv", str(out))
    assert done.returncode == 0, done.stderr
    rows = list(csv.DictReader(io.StringIO(out.read_text())))
    for name, unit in [("m_r", "kg"), ("eta_t", ""), ("L_main", "m"), ("D_main", "m"),
                       ("f_main", ""), ("d_leak", "m"), ("Cd_leak", "")]:  # fmt: skip
        assert f"{name} [{unit}]".replace(" []", "") in rows[0]
    column = {key.split(" [")[0]: key for key in rows[0]}
    assert [float(row[column["m_r"]]) for row in rows] == [4.0, 0.0]
    assert [float(row[column["d_leak"]]) for row in rows] == [0.002, 0.0]
    assert [float(row[column["eta_t"]]) for row in rows] == [0.8, 1.0]
    assert [float(row[column["D_main"]]) for row in rows] == [0.05, 0.05]  # the default
    designs = [SEED.replace(m_r=4.0, d_leak=0.002, eta_t=0.8, L_main=20.0), SEED.replace(h=5.0)]
    expected = windpump.sweep(designs, 30.0)
    assert [float(row["volume [m^3]"]) for row in rows] == pytest.approx(expected.volume, rel=1e-11)
    again = windpump_command("sweep", str(out), "--csv", str(tmp_path / "again.csv"))
    assert again.returncode == 0, again.stderr
    assert (tmp_path / "again.csv").read_text() == out.read_text()


def test_the_docs_designs_csv_is_what_sweep_reads():
    docs = Path(__file__).resolve().parents[2] / "docs"
    table = docs / "examples" / "designs.csv"
    # the designers' guide shows this very file
    assert ".. literalinclude:: examples/designs.csv" in (docs / "designers.rst").read_text("utf-8")
    done = windpump_command("sweep", str(table))
    assert done.returncode == 0, done.stderr
    rows = list(csv.DictReader(io.StringIO(done.stdout)))
    designs = [SEED.replace(h=2.0), SEED.with_ratios(R_dagger=6.0, h=5.0, T_m=0.8)]
    expected = windpump.sweep(designs, [600.0, 1200.0])
    assert [float(row["volume [m^3]"]) for row in rows] == pytest.approx(expected.volume, rel=1e-11)


def test_a_bad_row_names_its_line(short_tmp_path):
    table = short_tmp_path / "designs.csv"
    table.write_text("h,T_m\n1,0.6\n2,-0.6\n")
    done = windpump_command("sweep", str(table))
    assert done.returncode == 1 and "line 3" in done.stderr and "T_m" in done.stderr
    table.write_text("h,colour\n1,red\n")
    assert "unknown column(s) ['colour']" in windpump_command("sweep", str(table)).stderr
    designs = short_tmp_path / "designs.json"
    designs.write_text(f'[{SEED.to_json()}, {{"schema": "other"}}]')
    done = windpump_command("sweep", str(designs))
    assert done.returncode == 1 and "designs.json, design 2: not a design file" in done.stderr
    designs.write_text("[{")
    assert "designs.json: not JSON" in windpump_command("sweep", str(designs)).stderr


def test_serve_starts_the_explorer(tmp_path):
    with socket.socket() as probe:  # a free port
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    log = (tmp_path / "serve.log").open("w")
    server = subprocess.Popen(
        [sys.executable, "-m", "windpump", "serve", "--port", str(port)],
        stdout=log,
        stderr=subprocess.STDOUT,
    )
    try:
        deadline = time.monotonic() + 240  # a busy machine compiles slowly
        status = None
        while time.monotonic() < deadline and server.poll() is None:
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/app?h=5", timeout=60) as r:
                    status = r.status
                    break
            except OSError:
                time.sleep(1.0)
        assert status == 200, (tmp_path / "serve.log").read_text()[-2000:]
    finally:
        server.terminate()
        server.wait(timeout=60)
        log.close()


def test_sweep_goes_to_a_dask_scheduler_by_its_address(tmp_path):
    distributed = pytest.importorskip("distributed")
    table = tmp_path / "designs.json"
    designs = [SEED.replace(h=2.0), SEED.replace(cylinders=2, T_0=0.3)]
    table.write_text("[" + ",".join(d.to_json() for d in designs) + "]")
    out = tmp_path / "out.csv"
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=1, dashboard_address=None
    ) as cluster:
        done = windpump_command(
            "sweep", str(table), "--scheduler", cluster.scheduler_address, "--csv", str(out),
            "--t-end", "120", process=True,
        )  # fmt: skip
    assert done.returncode == 0, done.stderr
    rows = list(csv.DictReader(io.StringIO(out.read_text())))
    expected = windpump.sweep(designs, 120.0)
    assert [float(row["volume [m^3]"]) for row in rows] == list(expected.volume)


def test_progress_is_a_bar_on_request_and_a_callback_as_given(capsys):
    from windpump.progress import reporter

    bar = reporter(True, 4, "sweep")
    for done in range(1, 5):
        bar(done, 4)
    assert "sweep:" in capsys.readouterr().err  # a tqdm bar, cleared when done
    calls = []
    windpump.sweep([SEED, SEED], 10.0, chunksize=1, progress=lambda *a: calls.append(a))
    assert calls == [(1, 2), (2, 2)]
    assert reporter(False, 4, "quiet")(4, 4) is None and capsys.readouterr().err == ""


@pytest.mark.parametrize("skip", [False, True])
def test_serve_runs_the_readmes_compile_step_before_the_server(monkeypatch, skip):
    """``windpump serve`` is the README's ``python -m windpump_app.compiling && panel serve app/``
    (it ran the server alone, which then compiled in the background while a page waited);
    ``--no-compile`` skips the step, and a failed step is said and the server started all the
    same. Faked: no compile, no server."""
    from windpump import cli

    ran: list[tuple[str, list[str]]] = []

    def compile_step(command):
        ran.append(("compile", list(command)))
        return 1

    class Served(Exception):
        """A real execv does not return: the process becomes the server."""

    def serve(path, command):
        ran.append(("serve", list(command)))
        raise Served

    monkeypatch.setattr(cli.subprocess, "call", compile_step)
    monkeypatch.setattr(cli.os, "execv", serve)
    monkeypatch.setattr(cli.os, "name", "posix")
    options = ["--no-compile"] if skip else []
    with pytest.raises(Served):
        cli.serve_command(
            *cli.build_parser().parse_known_args(["serve", *options, "--port", "5999"])
        )
    served = ("serve", [sys.executable, "-m", "panel", "serve", str(cli.explorer_folder()),
                        "--port", "5999"])  # fmt: skip
    compiled = ("compile", [sys.executable, "-m", "windpump_app.compiling"])
    assert ran == ([served] if skip else [compiled, served])


def test_serve_help_says_it_compiles_first_and_how_to_skip_it():
    from windpump.command.cli import build_parser

    parser = build_parser()
    serve = parser._subparsers._group_actions[0].choices["serve"]  # type: ignore[union-attr]
    text = serve.format_help()
    assert "windpump_app.compiling" in text and "--no-compile" in text
