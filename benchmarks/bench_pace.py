"""How far a run's pace at about 1e6 steps is from its final one (``stepping.LATE_MARGIN``).

Draws designs as tests/test_ranges.py does (hypothesis), runs each for t_end in (2, 60, 600,
3600) s to ``LATE_STEPS`` without a pace check, and for those still running projects their total
steps from the pace so far (LATE_STEPS t_end / t); those projected under 3 MAX_STEPS run again
to the end (or MAX_STEPS), and the final steps over the projection are printed. Slow (a run to
MAX_STEPS takes 10-60 s): ``python benchmarks/bench_pace.py [examples] [seed]``.
"""

from __future__ import annotations

import math
import sys
import time
import warnings
from pathlib import Path

from hypothesis import HealthCheck, given, seed, settings
from hypothesis import strategies as st

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from test_ranges import designs  # noqa: E402

from windpump import dynamics  # noqa: E402
from windpump._kernels import OVER_BUDGET, REACHED_T_END, run  # noqa: E402
from windpump._kernels.stepping import LATE_STEPS  # noqa: E402


def measure(design, t_end, theta_dot0):
    machine = dynamics.kernel_machine(design, None)
    first = run(machine, math.pi / 2, theta_dot0, t_end, 4, None, dynamics.RTOL, LATE_STEPS, 64)
    if first.outcome != OVER_BUDGET or first.t.size < 2:
        return None
    t_late = float(first.t[-1])  # the last sample before LATE_STEPS: about the pace's t
    projected = LATE_STEPS * t_end / t_late if t_late > 0 else math.inf
    if projected > 3 * dynamics.MAX_STEPS:
        return projected, None, None
    began = time.perf_counter()
    whole = run(machine, math.pi / 2, theta_dot0, t_end, 4, None, dynamics.RTOL,
                dynamics.MAX_STEPS, 64)  # fmt: skip
    took = time.perf_counter() - began
    final = whole.steps if whole.outcome == REACHED_T_END else None
    return projected, final, took


def main(examples: int, chosen: int) -> None:
    rows = []

    @seed(chosen)
    @settings(max_examples=examples, deadline=None, suppress_health_check=list(HealthCheck),
              database=None)  # fmt: skip
    @given(designs(), st.sampled_from([2.0, 60.0, 600.0, 3600.0]), st.sampled_from([0.0, 3.0]))
    def probe(design, t_end, theta_dot0):
        if design is None:
            return
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                dynamics.check_work(design, t_end)
                dynamics.checked_kick("theta_dot0", theta_dot0)
                got = measure(design, t_end, theta_dot0)
        except ValueError:
            return
        if got is not None:
            rows.append((got, t_end))
            projected, final, took = got
            ratio = "" if final is None else f" final/projected {final / projected:.3f}"
            print(f"t_end {t_end:g}: projected {projected:.3g} final {final} "
                  f"({took and round(took, 1)} s){ratio}", flush=True)  # fmt: skip

    probe()
    ratios = [f / p for (p, f, _), _ in rows if f is not None]
    print(f"{len(rows)} runs past {LATE_STEPS:,} steps; finished within budget: {len(ratios)}")
    if ratios:
        print(f"final / projected: {min(ratios):.3f} to {max(ratios):.3f}")


if __name__ == "__main__":
    main(
        int(sys.argv[1]) if len(sys.argv) > 1 else 300, int(sys.argv[2]) if len(sys.argv) > 2 else 1
    )
