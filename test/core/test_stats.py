# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""stats.py: the core's counters and caches live in one module, with one reset."""

from wrenchcone_ros.core import cones, constraints, default_scene, engine, paper, planar, stats
from wrenchcone_ros.core import wrench_cone, wrench_cones


def test_the_algorithm_modules_count_into_the_stats_module():
    assert planar.PLANAR_FALLBACKS is stats.PLANAR_FALLBACKS
    assert paper.PAPER_FALLBACKS is stats.PAPER_FALLBACKS
    assert cones.FALLBACKS is stats.FALLBACKS
    assert engine.KERNEL_STATS is stats.KERNEL_STATS
    assert constraints._PLANS is stats.PLANS


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
