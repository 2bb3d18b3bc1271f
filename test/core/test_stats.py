# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""stats.py: the core's counters and caches live in one module, with one reset."""

from helpers.paper_example import PAPER_G, same_rays

from wrenchcone_ros.core import default_scene, paper, planar, stats
from wrenchcone_ros.core import wrench_cone, wrench_cones


def test_the_counts_the_algorithms_make_are_the_ones_stats_reports():
    """What the algorithms count is read through stats (its counters, not copies): one
    float cone on the numpy engine, one through the paper's method, each counted once."""
    scene = default_scene()
    stats.reset()
    wrench_cone(scene, "na", engine="numpy")
    assert stats.counters()["PLANAR_FALLBACKS"]["float_cones"] == 1
    wrench_cone(scene, "na", method="paper")
    assert stats.counters()["PAPER_FALLBACKS"]["float_cones"] == 1


def test_the_caches_only_save_work():
    """The paper's worked example (its generators, Eq. 5) with cold caches, warm caches and
    after a reset: the caches change how long a cone takes, never which cone."""
    stats.reset()
    for _ in range(2):
        assert not any(stats.CACHES)
        (cold,) = wrench_cones(default_scene(), ["na"])
        assert any(stats.CACHES)
        (warm,) = wrench_cones(default_scene(), ["na"])
        assert same_rays(cold.G, PAPER_G) and same_rays(warm.G, PAPER_G)
        stats.reset()


def test_reset_zeroes_every_counter_and_empties_every_cache_in_place():
    scene = default_scene()
    before = planar.PLANAR_FALLBACKS["float_cones"]
    wrench_cone(scene, "na", engine="numpy")
    assert planar.PLANAR_FALLBACKS["float_cones"] == before + 1
    before = paper.PAPER_FALLBACKS["float_cones"]
    wrench_cone(scene, "na", method="paper")
    assert paper.PAPER_FALLBACKS["float_cones"] == before + 1
    wrench_cones(scene, ["na", "c*"])  # fills the plan caches on either engine
    assert stats.PLANS
    stats.reset()
    assert all(v == 0 for d in stats.COUNTERS for v in d.values())
    assert not any(stats.CACHES)
    assert stats.counters()["PLANAR_FALLBACKS"] == {"float_cones": 0, "exact_fallbacks": 0,
                                                    "exact_ill_conditioned": 0}
    wrench_cone(scene, "na", engine="numpy")  # the same objects count again
    assert planar.PLANAR_FALLBACKS["float_cones"] == 1
    assert stats.PLANS


def test_reset_of_the_counters_only_keeps_the_caches():
    wrench_cones(default_scene(), ["na"])
    stats.reset(caches=False)
    assert stats.PLANS and all(v == 0 for d in stats.COUNTERS for v in d.values())
