"""Reading a large wind CSV: the time and the memory of ``windpump.model.wind.read_csv`` and
``windpump.read_weather`` on a file near the limit (``MAX_CSV_BYTES``, 50 MB).

Run: python benchmarks/bench_read.py [megabytes] [seconds|iso]

Writes a record of the given size (50 MB by default) in a temporary folder, one sample every 3 s
(times in seconds, or ISO timestamps), then reads it in a fresh process per reader, printing the
wall time and the process's peak resident memory above what it held once windpump was imported
(``resource.getrusage``'s ``ru_maxrss``), also as a multiple of the file's size.
"""

from __future__ import annotations

import datetime
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

CHILD = """
import resource, sys, time
import windpump, windpump.model.wind, windpump.sites.weather
reader = {"read_csv": windpump.model.wind.read_csv, "read_weather": windpump.read_weather}[sys.argv[2]]
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
start = time.perf_counter()
record = reader(sys.argv[1])
took = time.perf_counter() - start
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print(len(record.t), took, before, peak)
"""


def write_record(path: Path, megabytes: float, kind: str) -> int:
    """A wind CSV of at most ``megabytes`` MB, one sample every 3 s; its size [bytes]."""
    rng = np.random.default_rng(1)
    origin = datetime.datetime(2026, 1, 1)
    with open(path, "w", encoding="utf-8") as file:
        file.write("time,speed [m/s]\n")
        written, i = 0, 0
        while written < megabytes * 1e6:
            speeds = rng.uniform(0.0, 20.0, 10_000)
            if kind == "iso":
                lines = [
                    f"{(origin + datetime.timedelta(seconds=3 * (i + j))).isoformat()},{v:.2f}\n"
                    for j, v in enumerate(speeds)
                ]
            else:
                lines = [f"{3 * (i + j)},{v:.2f}\n" for j, v in enumerate(speeds)]
            block = "".join(lines)
            if written + len(block) > megabytes * 1e6:
                break
            file.write(block)
            written += len(block)
            i += len(speeds)
    return path.stat().st_size


def main() -> None:
    megabytes = float(sys.argv[1]) if len(sys.argv) > 1 else 50.0
    kinds = sys.argv[2:] or ["seconds", "iso"]
    with tempfile.TemporaryDirectory() as folder:
        for kind in kinds:
            path = Path(folder) / f"wind-{kind}.csv"
            size = write_record(path, megabytes, kind)
            for reader in ("read_csv", "read_weather"):
                done = subprocess.run(
                    [sys.executable, "-c", CHILD, str(path), reader],
                    capture_output=True,
                    text=True,
                )
                if done.returncode:
                    print(f"{kind} {reader}: failed: {done.stderr.strip().splitlines()[-1]}")
                    continue
                samples, took, before, peak = done.stdout.split()
                grown = (int(peak) - int(before)) * 1024  # ru_maxrss is in KiB on Linux
                print(
                    f"{kind:8} {reader:12} {size / 1e6:5.1f} MB, {int(samples):,} samples: "
                    f"{float(took):5.1f} s, peak memory +{grown / 1e6:,.0f} MB "
                    f"({grown / size:.1f}x the file)"
                )


if __name__ == "__main__":
    main()
