"""Throughput of windpump.sweep: 2,000 seed-sized runs serial, on 2 processes, on a dask cluster.

Run: python benchmarks/bench_sweep.py [runs]

Each run is the paper's example (600 s from a kick of 3 rad/s) with its head and gear ratio
varied over a grid, so runs differ in cost as a real study's do. The baseline is the cost per run:
the same runs through windpump.simulate and the figures, in a plain loop in this process, with no
sweep around them. Each sweep's time over (runs x that cost) is its overhead ratio (1 is none; on
2 workers, 0.5 is a perfect split). The tables are checked equal to the serial one.
"""

from __future__ import annotations

import sys
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

import windpump
from windpump.study.studies import FIGURES, figures_of

SEED = windpump.Design.seed_example()


def designs(count):
    heads = np.linspace(0.5, 6.0, 40)
    ratios = np.linspace(3.0, 8.0, max(1, count // 40))
    return [SEED.with_ratios(R_dagger=r, h=h) for h in heads for r in ratios][:count]


def same(a, b):
    return all(np.array_equal(getattr(a, f), getattr(b, f), equal_nan=True) for f in FIGURES)


def main(count):
    table = designs(count)
    windpump.simulate(SEED, 1.0)  # compile (or load) here, outside every timing
    start = time.perf_counter()
    for design in table:
        figures_of(design, 600.0, np.pi / 2, 3.0)
    per_run = (time.perf_counter() - start) / count
    print(f"{count} seed-sized runs (600 s each); cost per run in a plain loop: "
          f"{per_run * 1e3:.2f} ms ({1 / per_run:.0f} runs/s)")  # fmt: skip

    def report(name, seconds, result):
        ratio = seconds / (count * per_run)
        check = "same table" if same(result, serial) else "TABLE DIFFERS"
        print(f"  {name:<58} {seconds:6.2f} s, {count / seconds:6.0f} runs/s, "
              f"time / (runs x cost) = {ratio:.2f} ({check})")  # fmt: skip

    start = time.perf_counter()
    serial = windpump.sweep(table, 600.0, progress=False)
    report("serial", time.perf_counter() - start, serial)

    start = time.perf_counter()
    with ProcessPoolExecutor(2) as pool:
        spread = windpump.sweep(table, 600.0, executor=pool, progress=False)
    report("2 processes (pool start included)", time.perf_counter() - start, spread)

    import dask
    from distributed import Client, LocalCluster

    # dask's nanny starts workers with MALLOC_TRIM_THRESHOLD_=65536, which turns glibc's every
    # large allocation (a run's sample arrays) into fresh pages: runs cost ~3x more. Unset, a
    # worker runs them at this process's speed. (Unset first: a nanny leaves the variable in this
    # process's environment, where the next cluster's nanny finds it.)
    trim = "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_"
    for name, setting in [("MALLOC_TRIM_THRESHOLD_ unset", None), ("dask's defaults", 65536)]:
        with dask.config.set({trim: setting}):
            cluster = LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None)
            with cluster, Client(cluster) as client:
                client.run(figures_of, SEED, 600.0, np.pi / 2, 3.0)  # each worker loads the kernel
                start = time.perf_counter()
                executor = client.get_executor()
                on_cluster = windpump.sweep(table, 600.0, executor=executor, progress=False)
                seconds = time.perf_counter() - start
        report(f"dask LocalCluster, 2 workers, {name}", seconds, on_cluster)


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 2000)
