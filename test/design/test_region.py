# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Designs ranked by the start region they can load (design/stages.py ``plan`` with a
start region, design/rank.py REGION_RANKING).

Two designs of the pawl on its plate, both with a guaranteed loading plan: the pawl
upside down on pins in holes (1,0) (5,0) (6,0) (design 3 of docs/fixture_design.md),
whose plan seats the part from the whole asked box, and the pawl upright with the third
pin against its post, whose plan meets the pins in another order from a start 0.75 mm
off in y.
Each design's region columns are checked against the planner's own region result,
computed here per design from a scene built by hand (the pins as fixels, the part moved
back from its seat) with ``plan_seating`` and ``certify_region``; then the design that
loads the bigger region ranks first, with everything else equal, and even above the
other's larger hold margin. A tiny box (y +- 1 mm), a 2-point cover and one bisection
step keep it to seconds."""

from __future__ import annotations

import math

import pytest

from wrenchcone_ros.core import Fixel, Scene, Uncertainty, Workpiece, load_scene
from wrenchcone_ros.core.plan import (
    GOAL_GUARANTEED,
    StartRegion,
    certify_region,
    plan_seating,
)
from wrenchcone_ros.design.problem import DesignError, DesignProblem, RegionWork, load_plate
from wrenchcone_ros.design.rank import DEFAULT_RANKING, REGION_RANKING, rank_rows
from wrenchcone_ros.design.stages import plan

pytest.importorskip("pymunk")

PART = "examples/pawl_seating.yaml"
FRICTION = (0.2, 0.4)
ASKED = (0.0, 0.001, 0.0)  # m, m, rad
WORK = RegionWork(grid=2, bisections=1, sampled=0, draws=0)
#: (pin centres m, seated pose): pins in holes (1,0) (5,0) (6,0) at the pose the
#: designer solves (theta -150 degrees), and (1,0) (2,2) (5,0)
DESIGNS = {
    "upside-down": ([(0.01, 0.0), (0.05, 0.0), (0.06, 0.0)],
                    (0.04908845726811989, 0.03757883832488648, -2.6179938779914944)),
    "post": ([(0.01, 0.0), (0.02, 0.02), (0.05, 0.0)], (0.002, 0.003, 0.0)),
}


def planner_region(positions, pose, load_direction):
    """The planner's region for a design, from a scene built here: the part of the
    scene file at its seat moved back 2 mm against the direction of arrival, the three
    pins as fixels of the plate's radius (3 mm)."""
    part = load_scene(PART)
    wp = part.workpiece
    x, y, th = pose
    start = Scene(workpiece=Workpiece(wp.mass, wp.inertia, wp.shape, wp.com),
                  fixels=tuple(Fixel(p, 0.003) for p in positions), friction=part.friction,
                  pose=(x - 0.002 * math.cos(load_direction),
                        y - 0.002 * math.sin(load_direction), th),
                  contact_tolerance=1e-9)
    p = plan_seating(start, [1, 2, 3], "tilt", FRICTION, runs=0, workers=1,
                     max_candidates=30, goal=GOAL_GUARANTEED)
    assert p.guaranteed
    return certify_region(start, p, StartRegion(*ASKED), Uncertainty(friction=FRICTION),
                          grid=WORK.grid, bisections=WORK.bisections, sampled=WORK.sampled,
                          draws=WORK.draws, workers=1)


@pytest.mark.slow
def test_the_design_that_loads_the_bigger_region_ranks_first():
    problem = DesignProblem(load_scene(PART), load_plate("examples/plates/plate_pawl.yaml"),
                            Uncertainty(friction=FRICTION), start_region=ASKED,
                            region_work=WORK)
    rows = {}
    for name, (pos, pose) in DESIGNS.items():
        row = plan(problem, pos, pose)
        assert row["plan_guaranteed"], (name, row.get("reason"))
        cert = planner_region(pos, pose, row["load_direction"])
        assert cert.certified is not None, name
        # the row states what the planner certifies for this design
        assert (row["region_dx"], row["region_dy"], row["region_dtheta"]) == \
            cert.certified.half_widths, name
        assert row["region_size"] == cert.certified.dy / ASKED[1], name
        assert row["region_fraction"] == cert.fraction and row["region_runs"] == cert.runs
        rows[name] = row
    small, big = rows["post"], rows["upside-down"]
    assert 0 < small["region_size"] < 1  # a part of the box: the bisection's
    assert big["region_size"] > small["region_size"]
    # everything else equal: the bigger region first
    same = {"plan_guaranteed": True, "hold_margin": 0.4, "locating_accuracy": 1.5}
    table = [{"design_id": "a-small", **same, "region_size": small["region_size"]},
             {"design_id": "b-big", **same, "region_size": big["region_size"]}]
    assert [r["design_id"] for r in rank_rows(table, REGION_RANKING)] == ["b-big", "a-small"]
    # the smaller region's design holds with the larger margin: the region decides first
    table = [{"design_id": name, "plan_guaranteed": True, "hold_margin": m, "region_size":
              rows[name]["region_size"], "locating_accuracy": 1.5}
             for name, m in (("post", 0.5), ("upside-down", 0.3))]
    assert [r["design_id"] for r in rank_rows([dict(r) for r in table], REGION_RANKING)] \
        == ["upside-down", "post"]
    assert [r["design_id"] for r in rank_rows([dict(r) for r in table], DEFAULT_RANKING)] \
        == ["post", "upside-down"]


def test_a_problem_keeps_its_start_region_and_refuses_a_bad_one():
    problem = DesignProblem(load_scene(PART), load_plate("examples/plates/plate_pawl.yaml"),
                            Uncertainty(friction=FRICTION))
    assert problem.start_region is None
    assert DesignProblem.from_dict(problem.to_dict()) == problem
    with_region = DesignProblem(problem.part, problem.plate, problem.uncertainty,
                                start_region=(0.002, 0.002, math.radians(5)),
                                region_work=WORK)
    assert DesignProblem.from_dict(with_region.to_dict()) == with_region
    for bad in ((-0.001, 0.0, 0.0), (0.0, 0.0, 4.0), (0.001, 0.001), "abc"):
        with pytest.raises(DesignError, match="start region"):
            DesignProblem(problem.part, problem.plate, start_region=bad)
    with pytest.raises(DesignError, match="region work: grid must be a whole number >= 1"):
        RegionWork(grid=0)


@pytest.mark.slow
def test_the_monte_carlo_starts_in_the_certified_region():
    """Stage 3 with the region stage 2 certified: every run starts at a pose drawn in
    that box (``mc_start_region``); without one, or with a box of zero size, at the
    loading start. The design whose plan holds from the whole box seats every draw."""
    problem = DesignProblem(load_scene(PART), load_plate("examples/plates/plate_pawl.yaml"),
                            Uncertainty(friction=FRICTION), start_region=ASKED,
                            region_work=WORK)
    pos, pose = DESIGNS["upside-down"]
    row = plan(problem, pos, pose, runs=4, seed=3, region=False, mc_region=ASKED)
    assert row["mc_start_region"] is True and row["mc_runs"] == 4
    assert row["success_rate"] == 1.0
    row = plan(problem, pos, pose, runs=2, seed=3, region=False, mc_region=(0.0, 0.0, 0.0))
    assert row["mc_start_region"] is False and row["mc_runs"] == 2
