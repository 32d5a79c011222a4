"""Every numeric option of the windpump command takes a negative, infinite or NaN value as its
value and answers in words naming the option (argparse took ``-inf`` or ``-1e-3`` for an option
and said 'expected one argument'). In-process (:func:`windpump.command.cli.main`)."""

from __future__ import annotations

import pytest

from windpump.command.cli import build_parser, main, numeric_values

SITE = ["--site", "greensboro", "--demand", "1"]
CASES = [
    (["simulate", "--t-end"], "t_end"),
    (["simulate", "--theta0"], "theta0"),
    (["simulate", "--theta-dot0"], "theta_dot0"),
    (["sweep", "designs.csv", "--t-end"], "t_end"),
    (["tank", *SITE, "--shear"], "shear"),
    (["tank", *SITE, "--lolp"], "lolp"),
    (["tank", "--site", "greensboro", "--demand"], "demand"),
    (["tank", *SITE, "--hub-height"], "hub_height"),
    (["tank", *SITE, "--height"], "--height"),
    (["supply", *SITE, "--tank"], "tank"),
    (["supply", *SITE, "--full", "--turbulence"], "turbulence"),
    (["supply", *SITE, "--full", "--workers"], "--workers"),
    (["sweep", "designs.csv", "--workers"], "--workers"),
    (["simulate", "--set"], "--set"),  # not a number: NAME=VALUE expected, said so
]


@pytest.mark.parametrize("value", ["-inf", "-1e-3", "-nan", "-Infinity"])
@pytest.mark.parametrize(("words", "name"), CASES, ids=[c[0][-1] for c in CASES])
def test_a_negative_or_infinite_value_is_the_options_value(words, name, value, capsys, tmp_path):
    if name == "theta0" and value == "-1e-3":
        pytest.skip("any finite start angle is allowed")
    (tmp_path / "designs.csv").write_text("h\n5\n")
    words = [w if w != "designs.csv" else str(tmp_path / w) for w in words]
    try:
        code = main([*words, value])
    except SystemExit as stop:  # argparse's usage errors (--workers' own check)
        code = stop.code
    err = capsys.readouterr().err
    assert "expected one argument" not in err
    assert code in (1, 2), err
    if name == "--set":
        assert f"--set '{value}': expected NAME=VALUE" in err
        return
    assert name in err and ("not allowed" in err or "only with --full" in err), err
    assert value in err or repr(float(value)) in err or "only with --full" in err, err


@pytest.mark.parametrize("option", ["--gear-ratios", "--heads"])
def test_a_maps_range_may_start_below_zero(option, capsys):
    assert main(["map", option, "-inf:2:10"]) == 1
    err = capsys.readouterr().err
    assert "expected one argument" not in err and option in err and "-inf" in err, err


def test_serve_keeps_its_options_and_words_stay():
    parser = build_parser()
    assert numeric_values(["serve", "--port", "-1"], parser) == ["serve", "--port", "-1"]
    assert numeric_values(["simulate", "--csv", "-x.csv"], parser) == [
        "simulate", "--csv", "-x.csv"
    ]  # fmt: skip
    assert numeric_values(["simulate", "--t-end", "-5"], parser) == ["simulate", "--t-end=-5"]
