"""The hypothesis profile every test runs under (conftest.py): a busy machine fails no test.

These stand in for a machine so busy that drawing one example takes a second (the design-file
test drew 1 valid input in 4.67 s) and running one takes longer than hypothesis's 200 ms deadline.
"""

from __future__ import annotations

import time

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st


def slowly_drawn(value: int) -> int:
    time.sleep(0.5)  # a machine busy with other work
    return value


@settings(max_examples=5)
@given(st.builds(slowly_drawn, st.integers(0, 10)))
def test_slowly_drawn_examples_pass_the_health_checks(value):
    assert 0 <= value <= 10


@settings(max_examples=2)
@given(st.integers(0, 10))
def test_a_slowly_run_example_has_no_deadline(value):
    time.sleep(0.3)  # over hypothesis's default deadline of 200 ms
    assert 0 <= value <= 10


def test_the_loaded_profile_times_nothing():
    assert settings().deadline is None
    assert HealthCheck.too_slow in settings().suppress_health_check
