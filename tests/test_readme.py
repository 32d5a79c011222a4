"""The README's Python examples run as written, each in a fresh namespace."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[1] / "README.md"
BLOCKS = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), flags=re.S)


@pytest.mark.parametrize("number", range(len(BLOCKS)))
def test_a_readme_example_runs(number, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # run.to_csv("run.csv") writes here
    code = compile(BLOCKS[number], f"README.md python block {number + 1}", "exec")
    exec(code, {"__name__": "__main__"})  # as a script runs it


def test_the_readme_has_examples():
    assert len(BLOCKS) >= 2
