"""The modules' paths before the core's sub-packages (issue 38) keep working: each old path is the
new module itself, so a name read or patched through it is the new module's."""

from __future__ import annotations

import importlib
import pickle
import subprocess
import sys

import pytest

import windpump
from windpump._old_paths import MOVED


@pytest.mark.parametrize("old", sorted(MOVED))
def test_an_old_path_imports_the_module_now_holding_its_names(old):
    module = importlib.import_module(f"windpump.{old}")
    new = MOVED[old]
    if isinstance(new, str):
        assert module is importlib.import_module(new)
        assert module.__spec__.name == new  # its own spec, not the old path's
    else:
        for part in map(importlib.import_module, new):
            public = [name for name in dir(part) if not name.startswith("_")]
            assert all(
                getattr(module, name) is getattr(part, name)
                for name in public
                if name in vars(part)
            )


def test_the_windmill_s_old_path_offers_both_halves():
    from windpump.windmill import fit_torque_curve, load_power, operating_point, windmill_torque

    assert (
        windmill_torque is windpump.windmill_torque and operating_point is windpump.operating_point
    )
    assert load_power is windpump.load_power and fit_torque_curve is windpump.fit_torque_curve
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        windpump.windmill.nothing  # noqa: B018


def test_a_patch_through_an_old_path_reaches_the_code(monkeypatch):
    """``monkeypatch.setattr("windpump.dynamics.MAX_STEPS", ...)``, as scripts written before the move
    do, changes what the run reads."""
    import windpump.run.dynamics

    monkeypatch.setattr("windpump.dynamics.MAX_STEPS", 7)
    assert windpump.run.dynamics.MAX_STEPS == 7


def test_an_old_attribute_of_the_package_is_the_moved_module():
    assert windpump.dynamics is importlib.import_module("windpump.run.dynamics")
    assert windpump.theory is importlib.import_module("windpump.averaging.theory")
    with pytest.raises(AttributeError, match="has no attribute 'not_a_module'"):
        windpump.not_a_module  # noqa: B018


def test_a_result_pickles_to_the_new_path_and_loads():
    design = windpump.Design.seed_example()
    assert pickle.loads(pickle.dumps(design)) == design
    assert type(design).__module__ == "windpump.model.design"


def test_old_paths_import_in_a_fresh_interpreter_without_numba():
    """``import windpump.theory`` (an old path kept) in a fresh process: the averaged theory's and
    the model's old paths load no numba; the full run's and the kernels' load it, as their new
    paths do."""
    code = (
        "import sys, windpump.theory, windpump.design; "
        "import windpump.averaging.theory as t; "
        "assert windpump.theory is t; "
        "light = 'numba' not in sys.modules; "
        "import windpump.yearly, windpump.cli, windpump._kernels.equations as e; "
        "assert e.lever_arm is windpump.model.equations.lever_arm; "
        "assert windpump.yearly.supply is windpump.supply; "
        "print(light, 'numba' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["True", "True"]
