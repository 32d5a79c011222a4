"""windpump.simulate against a straightforward port of the paper's ODE45 set-up, on its example.

Run: python benchmarks/bench_simulate.py

The port integrates Eq. (17), dimensionless, in one scipy solve_ivp RK45 call over the whole run with
ODE45's default tolerances and the paper's maximum step, a quarter of the crank period at 2 omega_m
(dt+ < pi R+ / 4). Both sides are warmed up, then timed in this process; the ratio of the medians and
each side's error against the tight reference of tests/reference.py (DOP853, rtol 1e-11, stroke by
stroke) are printed.

Profile: ``perf record -F 4999 -- python benchmarks/bench_simulate.py --profile every 8`` runs the
seed example with every real effect on (or ``ideal``) for 8 s, after writing ``/tmp/perf-PID.map``
with every compiled function's address (numba writes no map: the map is made from the object code
it loads), so that ``perf report --sort sym`` names the kernels.
"""

from __future__ import annotations

import ctypes
import math
import os
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

import windpump

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from real_reference import real_reference_run  # noqa: E402

from reference import general_reference_run, reference_run, rotor_law  # noqa: E402

T_END, THETA0, THETA_DOT0 = 600.0, math.pi / 2, 3.0


def paper_port(design: windpump.Design, t_end: float, theta0: float, theta_dot0: float):
    """Eq. (17) as the paper integrates it: (theta, theta_dot+, V+) in t+ = t omega_m, ODE45."""
    Rd, ratio = design.R_dagger, design.L_over_R
    Tm, Ld = design.Tm_dagger, design.L_dagger

    def rhs(_t, y):
        theta, speed = y[0], y[1]
        theta_c = math.asin(math.sin(theta) / ratio)
        lever = math.sin(theta + theta_c) / math.cos(theta_c)
        exhaust = math.fmod(theta, 2 * math.pi) > math.pi
        force = -1.0 if exhaust else 0.0  # F+
        f2 = -lever / 2 if exhaust else 0.0  # pistonkin
        return [speed, Tm * speed * (2 - Rd * speed) - Ld * force * lever, speed * f2]

    w = design.omega_m
    sol = solve_ivp(
        rhs, (0, t_end * w), [theta0, theta_dot0 / w, 0.0], method="RK45", max_step=math.pi * Rd / 4
    )
    theta, speed, strokes = sol.y[:, -1]
    return theta, speed * w, strokes * design.stroke_volume


def windpump_final(design, t_end, theta0, theta_dot0):
    run = windpump.simulate(design, t_end, theta0, theta_dot0)
    return run.theta[-1], run.theta_dot[-1], run.volume[-1]


def median_time(function, repeats):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return statistics.median(times), result


def median_times(function, repeats):
    """(median wall time, median CPU time of this thread, the last result). On a shared machine
    a run is preempted for a scheduler slice (~4 ms) more often the longer it is: the real
    machine's runs (2-6 ms) were, the ideal's (1 ms) seldom, so the wall ratio grew with the load
    (every effect 4.4x by CPU time, up to 6-8x by wall time at a load of 5 on 2 cores)."""
    wall, cpu = [], []
    for _ in range(repeats):
        start, start_cpu = time.perf_counter(), time.thread_time()
        result = function()
        cpu.append(time.thread_time() - start_cpu)
        wall.append(time.perf_counter() - start)
    return statistics.median(wall), statistics.median(cpu), result


def alternated(first, second, repeats):
    """:func:`median_times` of two functions run in turn, ``repeats`` times each: a ratio of the
    two holds whatever else the machine does meanwhile (the ideal machine timed once and the real
    runs over the next minute, between their references, made every effect 4.0-4.4x by CPU time
    where alternated runs gave 2.8x). Also the median of each one's minor page faults a run
    (:func:`steady_heap`). Returns ((wall, CPU) of the first, of the second, faults of the first,
    of the second), the second's last result."""
    times = ([], [], [], [], [], [])
    for _ in range(repeats):
        for k, function in enumerate((first, second)):
            faults = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
            start, start_cpu = time.perf_counter(), time.thread_time()
            result = function()
            times[2 * k + 1].append(time.thread_time() - start_cpu)
            times[2 * k].append(time.perf_counter() - start)
            times[4 + k].append(resource.getrusage(resource.RUSAGE_SELF).ru_minflt - faults)
    return tuple(statistics.median(t) for t in times), result


def steady_heap() -> bool:
    """Keep glibc's malloc from giving freed memory back to the kernel: a run's arrays (~5 MB)
    then come from pages the process already has, whatever ran before. Without it, the heap
    that the references' scipy runs left behind made the next runs of both machines fault in
    fresh pages, ~400 a run (zeroed by the kernel, counted as this thread's CPU time): the
    ideal machine's runs, alternated with a rising main's, took 1.6-1.9 ms, not 1.1-1.2 ms, and
    the ratio moved with it (the "main" line 1.8x, then 2.1x with this). False when it cannot
    (not glibc)."""
    try:
        libc = ctypes.CDLL("libc.so.6")
    except OSError:
        return False
    M_TRIM_THRESHOLD, M_MMAP_THRESHOLD = -1, -3  # glibc's malloc.h
    # (the largest mmap threshold glibc takes is 32 MB; the trim threshold is unbounded)
    return bool(
        libc.mallopt(M_MMAP_THRESHOLD, 32 << 20) and libc.mallopt(M_TRIM_THRESHOLD, 1 << 30)
    )


def main():
    heap = steady_heap()
    design = windpump.Design.seed_example()
    args = (design, T_END, THETA0, THETA_DOT0)
    ref = reference_run(*args)
    truth = np.array([ref.theta, ref.theta_dot, ref.volume])

    windpump_final(*args), paper_port(*args)  # warm-up: compile (or load the cache), import paths
    fast, fast_result = median_time(lambda: windpump_final(*args), 101)
    slow, slow_result = median_time(lambda: paper_port(*args), 7)

    print(
        f"seed example: theta0 = pi/2, theta_dot0 = {THETA_DOT0} rad/s, {T_END:.0f} s "
        f"({ref.theta / (2 * math.pi):.0f} crank revolutions)"
    )
    print(f"{'':28s}{'median time':>14s}{'theta':>11s}{'theta_dot':>11s}{'volume':>11s}")
    print(f"{'':28s}{'':>14s}{'(relative error against the reference)':>33s}")
    for name, seconds, result in [
        ("windpump.simulate", fast, fast_result),
        ("paper port (solve_ivp RK45)", slow, slow_result),
    ]:
        errors = np.abs(np.array(result) - truth) / np.abs(truth)
        print(f"{name:28s}{seconds * 1e3:11.2f} ms" + "".join(f"{e:11.1e}" for e in errors))
    print(f"speed-up: {slow / fast:.0f}x")
    print()
    configurations(design, fast)
    print()
    rotors(design)
    print()
    real_machine(design, heap)


def parabola_rotor(design: windpump.Design, points: int = 21) -> windpump.Design:
    """The same machine with its windmill as a rotor: a C_Q table of Eq. (11) on ``points``
    tip-speed ratios (a 1.5 m wheel), PCHIP between them."""
    r, V = 0.75, design.V_ref
    scale = 0.5 * 1.225 * math.pi * r**3 * V**2
    lam = np.linspace(0.0, 2.5 * design.runaway_speed * r / V, points)
    x = lam * V / (r * design.omega_m)
    cq = (design.T_0 + (design.T_m - design.T_0) * x * (2 - x)) / scale
    rotor = windpump.Rotor.from_cq(2 * r, lam, cq)
    return windpump.Design.from_rotor(rotor, V_ref=V, **design.geometry())


def rotors(seed: windpump.Design):
    """A rotor's run against the same machine with Eq. (11), alternated in this process (the
    issue asks at most 1.2x): the paper's parabola as a 21-point C_Q table, and the multiblade
    wheel on the seed's pump; each against DOP853 of its law (tests/reference.py,
    ``rotor_law``). A first call per design computes its averaged theory (~1 ms, remembered):
    every timed run after it is the one a slider's repeated move pays."""
    print(f"{'600 s runs, a rotor':32s}{'wall x':>8s}{'CPU x':>8s}{'ms':>8s}"
          f"{'theta':>10s}{'speed':>10s}{'volume':>10s}")  # fmt: skip
    wheel = windpump.Design.from_rotor(windpump.Rotor.multiblade(1.5), V_ref=5.0, **seed.geometry())
    for name, design in (("parabola as a C_Q table", parabola_rotor(seed)), ("multiblade", wheel)):
        args = (design, T_END, THETA0, THETA_DOT0)
        windpump.simulate(*args)
        (wall, cpu, rotor_wall, rotor_cpu, _, _), run = alternated(
            lambda: windpump.simulate(seed, T_END, THETA0, THETA_DOT0),
            lambda args=args: windpump.simulate(*args),
            51,
        )
        ref = reference_run(*args, windmill=rotor_law(design.rotor, design.V_ref))
        errors = final_errors(run, ref)
        print(
            f"{name:32s}{rotor_wall / wall:8.2f}{rotor_cpu / cpu:8.2f}{rotor_wall * 1e3:8.2f}"
            + "".join(f"{e:10.1e}" for e in errors)
        )


def final_errors(run, ref) -> list[float]:
    """A run's relative errors in theta, theta_dot and volume at its end against a reference's."""
    return [
        abs(run.theta[-1] - ref.theta) / ref.theta,
        abs(run.theta_dot[-1] - ref.theta_dot) / ref.theta_dot,
        abs(run.volume[-1] - ref.volume) / ref.volume,
    ]


def configurations(seed: windpump.Design, seed_time: float):
    """Past the paper, each against the seed example's time in this process and its own
    reference (tests/reference.py, written from the issue's conventions)."""
    cases = [
        # Six double-acting cylinders carry 12 times the load: the head is cut to keep the margin.
        ("6 double-acting cylinders", seed.replace(cylinders=6, double_acting=True, h=0.25), 3.0),
        ("2 cylinders, from rest (T_0)", seed.replace(cylinders=2, T_0=0.4), 0.0),
    ]
    print(
        f"{'600 s runs':32s}{'median time':>14s}{'x seed':>8s}{'steps':>8s}"
        f"{'theta':>10s}{'speed':>10s}{'volume':>10s}"
    )
    for name, design, kick in cases:
        args = (design, T_END, THETA0, kick)
        windpump.simulate(*args)
        seconds, run = median_time(lambda args=args: windpump.simulate(*args), 51)
        ref = general_reference_run(*args)
        errors = final_errors(run, ref)
        print(
            f"{name:32s}{seconds * 1e3:11.2f} ms{seconds / seed_time:8.2f}{run.steps:8d}"
            + "".join(f"{e:10.1e}" for e in errors)
        )


def real_machine(seed: windpump.Design, heap: bool = False):
    """The seed example with every effect of the real machine on, against the ideal machine timed
    in this process (the issue asks at most 2x), each effect alone, and each against
    tests/real_reference.py (DOP853 of the issue's equations, rtol 1e-11). Wall time and this
    thread's CPU time (:func:`median_times`: the CPU ratio is the one a busy machine leaves
    alone), each real run alternated with an ideal one (:func:`alternated`), and the median page
    faults a run of each (0 with ``heap``, :func:`steady_heap`)."""
    effects = {
        "m_r = 1 kg": {"m_r": 1.0},
        "eta_t = 0.9": {"eta_t": 0.9},
        "main 10 m x 25 mm": {"L_main": 10.0, "D_main": 0.025},
        "leak hole 1.5 mm": {"d_leak": 0.0015},
    }
    every = seed.replace(**{k: v for change in effects.values() for k, v in change.items()})
    windpump.simulate(seed, T_END), windpump.simulate(every, T_END)
    ideal, ideal_cpu, _ = median_times(lambda: windpump.simulate(seed, T_END), 51)
    print(
        f"real machine, 600 s from the kick      (the ideal machine: {ideal * 1e3:.2f} ms, "
        f"CPU {ideal_cpu * 1e3:.2f} ms; malloc keeps freed pages: {'yes' if heap else 'no'})"
    )
    print(
        f"{'':32s}{'median time':>14s}{'x ideal':>9s}{'CPU':>10s}{'x ideal':>9s}{'steps':>8s}"
        f"{'speed':>10s}{'volume':>10s}{'faults':>10s}"
    )
    for name, design in [("every effect on", every)] + [
        (name, seed.replace(**change)) for name, change in effects.items()
    ]:
        windpump.simulate(design, T_END)
        (ideal, ideal_cpu, seconds, cpu, ideal_faults, faults), run = alternated(
            lambda: windpump.simulate(seed, T_END),
            lambda design=design: windpump.simulate(design, T_END),
            31,
        )
        ref = real_reference_run(design, T_END, THETA0, THETA_DOT0)
        errors = [
            abs(run.theta_dot[-1] - ref.theta_dot) / ref.theta_dot,
            abs(run.volume[-1] - ref.volume) / ref.volume,
        ]
        print(
            f"{name:32s}{seconds * 1e3:11.2f} ms{seconds / ideal:9.2f}"
            f"{cpu * 1e3:7.2f} ms{cpu / ideal_cpu:9.2f}{run.steps:8d}"
            + "".join(f"{e:10.1e}" for e in errors)
            + f"{ideal_faults:5.0f}/{faults:<4.0f}"
        )


class PerfMap:
    """Keeps the object code of every library numba loads from its cache or compiles (hooks on
    numba's private CPUCodeLibrary, set before numba's first compile), and writes perf's map of
    their functions."""

    def __init__(self):
        from numba.core import codegen

        self.libraries = []
        original = codegen.CPUCodeLibrary._set_compiled_object
        kept = self.libraries

        def keep(library, value):
            kept.append((library, value))
            return original(library, value)

        codegen.CPUCodeLibrary._set_compiled_object = keep  # loaded from numba's cache
        compiled = codegen.CPUCodeLibrary._object_compiled_hook.__func__

        def keep_compiled(cls, module, code):
            library = getattr(module, "_CPUCodeLibrary__library", None)
            if library is not None:
                kept.append((library, code))
            return compiled(cls, module, code)

        codegen.CPUCodeLibrary._object_compiled_hook = classmethod(keep_compiled)  # compiled

    def write(self):
        """/tmp/perf-PID.map: each function's address (from one symbol's address in the process,
        the library's others by their offsets in its object code), size and name."""
        lines = []
        for library, code in self.libraries:
            path = f"/tmp/perf-{os.getpid()}-{len(lines)}.o"
            Path(path).write_bytes(code)
            symbols = subprocess.run(
                ["nm", "-S", "--defined-only", path], capture_output=True, text=True
            ).stdout.split("\n")
            Path(path).unlink()
            functions = [line.split() for line in symbols if len(line.split()) == 4]
            functions = [(int(o, 16), int(n, 16), k, name) for o, n, k, name in functions]
            engine = library._codegen._engine._ee
            bases = {
                engine.get_function_address(name) - o for o, _, k, name in functions if k == "T"
            }
            if len(bases) == 1:  # every global symbol agrees on where the code was put
                base = bases.pop()
                lines += [
                    f"{base + o:x} {n:x} {name}" for o, n, k, name in functions if k in "tTwW"
                ]
        Path(f"/tmp/perf-{os.getpid()}.map").write_text("\n".join(lines) + "\n")


def profile(which: str, seconds: float):
    """Run the seed example (every real effect on, or ideal) in a loop for ``seconds``."""
    perf_map = PerfMap()
    design = windpump.Design.seed_example()
    if which == "every":
        design = design.replace(m_r=1.0, eta_t=0.9, L_main=10.0, D_main=0.025, d_leak=0.0015)
    windpump.simulate(design, T_END)
    perf_map.write()
    runs, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        windpump.simulate(design, T_END)
        runs += 1
    print(f"{which}: {runs} runs, {(time.perf_counter() - start) / runs * 1e3:.2f} ms each")


if __name__ == "__main__":
    if sys.argv[1:2] == ["--profile"]:
        profile(
            sys.argv[2] if len(sys.argv) > 2 else "every",
            float(sys.argv[3]) if len(sys.argv) > 3 else 8.0,
        )
    else:
        main()
