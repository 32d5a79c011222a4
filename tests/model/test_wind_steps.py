"""A wind record's times too close to integrate are refused, naming the field, the value and
the range (a record spanning 1e-300 s was accepted and run)."""

from __future__ import annotations

import numpy as np
import pytest

from windpump import Design, ParameterError, simulate
from windpump.model.wind import MIN_STEP, WindRecord, read_csv

SHORT = [
    [0.0, 1e-300],  # a span of 1e-300 s
    [0.0, 5e-324],
    [0.0, 1.0, 1.0 + 1e-9],  # a nanosecond step
    [1e11, 1e11 + 1e-3],  # a millisecond near 1e11 s: 7,800 ulps, below 1e-13 of the time
    [-1e12, -1e12 + 0.05],
]


@pytest.mark.parametrize("t", SHORT)
def test_a_record_too_short_to_integrate_is_refused_by_name(t):
    V = np.full(len(t), 5.0)
    with pytest.raises(ParameterError) as caught:
        WindRecord(np.array(t), V)
    assert caught.value.name == "t" and "at least 1e-06 s" in str(caught.value)
    assert f"t[{len(t) - 1}]" in str(caught.value)
    with pytest.raises(ParameterError) as caught:
        simulate(Design.seed_example(), 1.0, wind=(t, V))
    assert caught.value.name == "wind" and "at least 1e-06 s" in str(caught.value)


def test_a_file_with_times_too_close_names_them(tmp_path):
    path = tmp_path / "wind.csv"
    path.write_text("t,V\n0,5\n1e-300,6\n")
    with pytest.raises(ValueError, match="at least 1e-06 s"):
        read_csv(path)


@pytest.mark.parametrize("t", [[0.0, MIN_STEP], [1e12 - 0.125, 1e12], [0.0, 1e-3, 2e-3]])
def test_the_closest_times_allowed_are_taken(t):
    record = WindRecord(np.array(t), np.full(len(t), 5.0))
    assert record.t.size == len(t)


def test_a_short_run_in_a_wind_function_samples_it_no_closer_than_allowed():
    run = simulate(Design.seed_example(), 1e-7, wind=lambda t: 5.0 + 0.0 * t)
    assert np.min(np.diff(run.wind.t)) >= MIN_STEP and run.t[-1] == 1e-7
