"""benchmarks/bench_hall.py keeps working: a hall of a few protocol-level students on a real
`panel serve app/`, each of whom gets its readouts and sees its own moves answered, while one more
loads a wind record. How fast is printed by the benchmark, not asserted here."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
import bench_hall  # noqa: E402


@pytest.mark.timeout(600)
def test_a_small_hall_opens_moves_and_uploads(monkeypatch, capsys):
    monkeypatch.setattr(bench_hall, "OPEN_WITHIN", 2.0)
    monkeypatch.setattr(bench_hall, "MOVE_EVERY", (1.0, 3.0))
    monkeypatch.setattr(bench_hall, "UPLOAD_BYTES", 200_000)
    monkeypatch.setattr(bench_hall, "SETTLE_WITHIN", 5.0)
    (hall,) = bench_hall.main(["3", "--minutes", "0.25", "--upload"])
    assert hall.errors == []
    assert len(hall.to_readout) == 3
    assert len(hall.burst) == 3 * bench_hall.BURSTS  # every student moving at once is answered
    assert len(hall.moves) >= 3
    assert all(trip > 0 for trip in hall.moves + hall.burst)
    assert hall.upload["while"] is not None
    witnesses = bench_hall.WITNESSES
    assert len(hall.upload["calm"]) == len(hall.upload["sending"]) == witnesses  # all answered
    printed = capsys.readouterr().out
    assert "hall of 3" in printed and "server CPU per page" in printed


def test_it_talks_only_to_loopback():
    assert bench_hall.loopback("http://127.0.0.1:5006/app")
    with pytest.raises(SystemExit):
        bench_hall.loopback("http://192.168.1.20:5006/app")


def test_a_wind_record_is_a_two_column_csv_within_the_size_asked():
    import windpump

    data = bench_hall.wind_record(50_000)
    assert len(data) <= 50_000
    record = windpump.model.wind.read_csv(data)
    assert len(record.t) == data.count(b"\n")  # every line but the header is a sample
