# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The region search (core/plan/search.py, ``region_candidates``): with a start region,
the search goes on past its first plan while that plan's certified box is not the whole
asked one, certifies each further plan that meets the goal, and returns the one with
the largest certified region.

The disc of examples/disc_nest.yaml (mu in [0.2, 0.4], asked +-1 mm x +-1 mm x +-5 deg):
its first guaranteed plan (the swing at half the force) holds from no translation, while
a later candidate of the same search (the swing at a tenth of the force: a slower
arrival) holds from the whole box at the small counts used here. The certificates are
checked against :func:`certify_region` called by this test on plans it builds itself
from the search's segments. Small counts keep every test short: a 3 x 3 x 3 cover, no
bisection (a box that fails is shrunk to the scene's pose), 5 drawn starts per box, no
drawn models, and the region's runs without the engine variations (the search's own
capture test keeps them, so that its plans are the real ones).
"""

from __future__ import annotations

import functools
import math
from dataclasses import replace
from pathlib import Path

import pytest

pytest.importorskip("pymunk")

import wrenchcone_ros.core.plan.region as region_module  # noqa: E402
import wrenchcone_ros.core.plan.search as search_module  # noqa: E402
from wrenchcone_ros.cli.render import plan_text  # noqa: E402
from wrenchcone_ros.core import load_scene  # noqa: E402
from wrenchcone_ros.core.plan import (  # noqa: E402
    REGION_CANDIDATES,
    PlanError,
    StartRegion,
    certify_region,
    plan_seating,
)
from wrenchcone_ros.core.uncertainty import as_uncertainty  # noqa: E402

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
BOX = StartRegion(0.001, 0.001, math.radians(5.0))
FRICTION = (0.2, 0.4)
GRID, BISECTIONS, DRAWS = 3, 0, 5


def small_counts(mp: pytest.MonkeyPatch):
    """The certifier the search calls, with this test's small counts (drawn starts, no
    drawn models, no engine variations); returns it, for the test's own calls."""
    mp.setattr(region_module, "ENGINE_VARIATIONS", ())
    certify = functools.partial(certify_region, draws=DRAWS, sampled=0)
    mp.setattr(search_module, "certify_region", certify)
    return certify


def plan(scene, candidates: int, workers: int = 1):
    return plan_seating(scene, [1, 2], uncertainty=FRICTION, simulate_runs=False,
                        workers=workers, start_region=BOX, region_grid=GRID,
                        region_bisections=BISECTIONS, region_candidates=candidates,
                        segment_funnel_draws=DRAWS)


@pytest.fixture(scope="module")
def disc():
    """The disc's scene and its plan without a region, with the test's certifier (its
    small counts patched in for the module's tests)."""
    scene = load_scene(EXAMPLES / "disc_nest.yaml")
    with pytest.MonkeyPatch.context() as mp:
        certify = small_counts(mp)
        yield {"scene": scene, "certify": certify,
               "single": plan_seating(scene, [1, 2], uncertainty=FRICTION,
                                      simulate_runs=False)}


@pytest.fixture(scope="module")
def one(disc):
    """The disc's region plan with region_candidates 1."""
    return plan(disc["scene"], 1)


@pytest.fixture(scope="module")
def three(disc):
    """The disc's region plan with region_candidates 3."""
    return plan(disc["scene"], 3)


def certified(disc, p):
    """The test's own certificate of plan ``p`` (the search's counts and seed)."""
    return disc["certify"](disc["scene"], p, BOX, as_uncertainty(FRICTION, disc["scene"]),
                           grid=GRID, bisections=BISECTIONS, seed=p.seed, workers=1)


@pytest.mark.slow  # plans run in the physics engine
def test_one_candidate_is_the_first_plan_certified_alone(disc, one):
    """region_candidates=1: the plan found from the scene's pose, certified alone (as
    before the region search): the same plan as without a region, the certificate of
    certify_region on it, no comparison recorded."""
    single = disc["single"]
    cert = certified(disc, single)
    # the plan's certificate also carries its segment funnel (checked with DRAWS states;
    # test_plan_segment_funnels.py tests them) and its cone slices
    # (test_plan_region_cones.py), which certify_region alone does not
    (funnel,) = one.region.segment_funnels
    assert funnel.segment == 2 and funnel.draws == DRAWS
    assert one.region.cone_slices and one.region.cone_slices[0].segment == 1
    assert one == replace(single, region=replace(cert, segment_funnels=(funnel,),
                                                 cone_slices=one.region.cone_slices))
    assert cert.compared == () and cert.chosen == 0
    assert not any(line.startswith("region:") for line in one.tried)
    assert "region search" not in plan_text(one)


@pytest.mark.slow  # plans run in the physics engine
def test_the_plan_with_the_largest_region_is_chosen(disc, one, three):
    """region_candidates=3: the first plan does not hold from the whole box; the search
    goes on and certifies the next candidate, which does. Every certificate compared is
    the test's own certificate of that plan, and the one returned is the largest."""
    single = disc["single"]
    cert = three.region
    assert single.guaranteed and three.guaranteed
    assert not one.region.whole and len(cert.compared) >= 2
    # the first plan compared is the search's first plan, with the same certificate
    first = cert.compared[0]
    assert first.plan == search_module.describe(single.segments)
    assert first.certificate == replace(one.region, segment_funnels=(), cone_slices=())
    assert len(cert.segment_funnels) == 1  # the chosen plan's funnel alone is checked
    # the test's own plans: the first plan's swing at each force scale of the compared
    # ones (the search's later candidates are the same segments, eased off further)
    mine = [first.certificate]  # the first plan's: test_one_candidate_... certifies it
    for c in cert.compared[1:]:
        scale = float(c.plan.split(" x")[1].split(",")[0]) if " x" in c.plan else 1.0
        p = replace(single, segments=tuple(
            s if s.hold else replace(s, scale=scale) for s in single.segments))
        assert search_module.describe(p.segments) == c.plan
        own = certified(disc, p)
        assert (own.certified, own.fraction, own.boxes, own.runs) == (
            c.certificate.certified, c.certificate.fraction, c.certificate.boxes,
            c.certificate.runs)
        mine.append(own)
    assert cert.fraction == max(m.fraction for m in mine) >= first.certificate.fraction
    assert cert.fraction > one.region.fraction and cert.whole
    best = max(range(len(mine)), key=lambda i: (mine[i].fraction, mine[i].axis_fraction, -i))
    assert cert.chosen == best + 1
    assert three.segments == replace(single, segments=tuple(
        s if s.hold else replace(s, scale=float(cert.compared[best].plan.split(" x")[1]
                                                  .split(",")[0]))
        for s in single.segments)).segments
    # what was compared is said: in tried, in the JSON and in the CLI's text
    lines = [t for t in three.tried if t.startswith("region: ")]
    assert lines[0].startswith(f"region: candidate 1 of at most 3 (plan {first.plan}")
    assert lines[-1].startswith(f"region: {len(cert.compared)} candidate plan(s) "
                                f"certified (at most 3; the last holds from the whole box)"
                                f"; chosen: candidate {cert.chosen} ")
    d = three.to_dict()["region"]
    assert d["chosen"] == cert.chosen and len(d["compared"]) == len(cert.compared)
    assert d["compared"][0]["fraction"] == first.certificate.fraction
    text = plan_text(three)
    assert (f"region search: {len(cert.compared)} candidate plans certified (at most 3), "
            f"chosen: candidate {cert.chosen}") in text


@pytest.mark.slow  # plans run in the physics engine
def test_the_region_search_is_deterministic(disc, three):
    """The same inputs and seed give the same plan, certificates and tried list, run
    again, and on 2 worker processes instead of 1."""
    again = plan(disc["scene"], 3, workers=2)
    assert again == three
    assert again.tried == three.tried


@pytest.mark.parametrize("value", [0, -1, 1.5, True, "3", None])
def test_a_bad_region_candidates_is_refused(value):
    scene = load_scene(EXAMPLES / "disc_nest.yaml")
    with pytest.raises(PlanError) as err:
        plan_seating(scene, [1, 2], start_region=BOX, region_candidates=value)
    assert str(err.value) == f"region_candidates must be a whole number >= 1, got {value!r}"


def test_the_default_is_a_count():
    assert isinstance(REGION_CANDIDATES, int) and REGION_CANDIDATES >= 1
