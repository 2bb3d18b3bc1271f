# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""One JSON shape per answer: ``--json`` of cone, check, classify, directions and sweep has
the same keys (at every level) for the nominal model and under an uncertainty, and the
nominal answer is the zero-width uncertainty's (its "every model" and "some model"
verdicts agree), in-process through ``cli.main`` (the code a user runs)."""

import json

import pytest

from wrenchcone_ros import cli

PAWL = "examples/pawl_polygon.yaml"
POSES = "examples/pawl_slide_poses.yaml"
ROBUST = ["--friction", "0.2", "0.4"]


def answer(capsys, *args) -> dict:
    assert cli.main([*args, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def shape(d):
    """The keys of a JSON value at every level (lists: the shape of their first item)."""
    if isinstance(d, dict):
        return {k: shape(v) for k, v in d.items() if k != "uncertainty"} | {
            "uncertainty": "present" if "uncertainty" in d else "absent"}
    if isinstance(d, list):
        return [shape(d[0])] if d else []
    return None


@pytest.mark.parametrize("args", [
    ("cone", PAWL, "--mode", "arr"),
    ("check", PAWL, "--mode", "arr", "--wrench", "0.362", "-0.932", "0"),
    ("classify", PAWL, "--wrench", "0.362", "-0.932", "0"),
    ("directions", PAWL, "--mode", "arr"),
    ("sweep", PAWL, "--mode", "arr", "--poses", POSES),
])
def test_one_json_shape_whatever_the_uncertainty(capsys, args):
    nominal, robust = answer(capsys, *args), answer(capsys, *args, *ROBUST)
    assert shape(nominal) == shape(robust)
    assert nominal["uncertainty"] == {"epsilon": 0.05, "beta": 0.001, "seed": 0}
    assert robust["uncertainty"]["friction"] == [0.2, 0.4]


def test_the_nominal_check_is_the_zero_width_answer(capsys):
    """Nominal: one cone, so "every model" and "some model" agree with "consistent",
    and the worst-case and best-case margins with "margin"; under the friction interval
    the wrench at -68.71 deg slides the pawl for some mu only (mu = 0.4 holds it:
    atan(1 / 0.4) = 68.20 deg)."""
    g = ["0.362", "-0.932", "0"]
    d = answer(capsys, "check", PAWL, "--mode", "arr", "--wrench", *g)
    assert d["consistent"] is d["consistent_every_model"] is d["consistent_some_model"] is True
    assert d["margin"] == d["margin_all"] == d["margin_any"] > 0
    r = answer(capsys, "check", PAWL, "--mode", "arr", "--wrench", *g, *ROBUST)
    assert r["consistent"] is r["consistent_every_model"] is False
    assert r["consistent_some_model"] is True and r["margin_all"] < 0 < r["margin_any"]
