# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Plans of tilts (or spring pulls) from a start pose to a seated part, checked in pymunk.

``plan_seating(scene, target, actuator)`` answers: which sequence of force directions
(and force magnitudes) brings the workpiece from the scene's pose to a pose where every
``target`` fixel touches it, and holds it there. It is the paper's own task (its
Figure 1: "slide right over fixels 2 and 3 until fixel 1 is reached") made into a
search. One concern per module:

* :mod:`.results`: the answers (Segment, RunResult, Plan, FunnelCheck) and what
  "guaranteed" means on them;
* :mod:`.poses`: poses near contact (one Gauss-Newton solve: simulated poses put back
  onto their contacts, near-seated poses);
* :mod:`.segments`: one segment (a mode, its directions along the simulated path, the
  worst-case margin) and the seat (hold and funnel);
* :mod:`.execution`: a plan run in the engine for one model, the capture test's models,
  the Monte Carlo over sampled models;
* :mod:`.region`: one plan checked over a box of start poses, and runs from sampled
  starts;
* :mod:`.segment_funnels`: each later segment's entry region, checked as a funnel of
  the plan's rest;
* :mod:`.region_cones`: the poses of a box at which the part rests on a segment's
  contacts, where the cones decide;
* :mod:`.search`: the search that uses its own evidence, under a time budget.

docs/planning.md explains the plans, docs/theory.md what the guarantee covers and
assumes.
"""

from .execution import (
    ENGINE_VARIATIONS,
    HOLD_LIMIT,
    HOLD_TIME,
    SEGMENT_TIMEOUT,
    TraceFrame,
    capture_models,
    execute,
    run_models,
    sample_models,
    trace,
)
from .region import (
    REGION_BATCH,
    REGION_BETA,
    REGION_BISECTIONS,
    REGION_DRAWS,
    REGION_EPSILON,
    REGION_GRID,
    REGION_SAMPLED_MODELS,
    SAMPLE_ATTEMPTS,
    certify_region,
    cover,
    run_region_samples,
    run_starts,
    check_segment_funnels,
    sample_starts,
)
from .segment_funnels import FUNNEL_DRAWS, certify_segment_funnels, sample_states
from .region_cones import SLICE_GRID, check_region_cones, slice_cover
from .poses import GAP_CONVERGENCE, lifted_scene, project_pose, solve_pose, start_scene
from .results import (
    DEFAULT_RUNS,
    DEFAULT_SEED,
    DEFAULT_WORKERS,
    FunnelCheck,
    Plan,
    PlanCancelled,
    PlanError,
    RegionCandidate,
    RegionCertificate,
    RunResult,
    STATE_AXES,
    SegmentFunnel,
    ConeSlice,
    Segment,
    StartRegion,
)
from .search import (
    DEFAULT_BUDGET,
    DEFAULT_MAX_CANDIDATES,
    DEFAULT_MAX_TRIALS,
    FORCE_SCALES,
    GOAL_GUARANTEED,
    GOAL_SEATED,
    GOALS,
    MAX_SEGMENTS,
    REGION_CANDIDATES,
    capture,
    plan_seating,
)
from .segments import (
    FUNNEL_LIFTS,
    PATH_POSES,
    PLAN_REFINEMENTS,
    candidate_modes,
    exclusive_margin,
    funnel_checks,
    hold_segments,
    plan_segment,
    robust_directions,
)

__all__ = ["DEFAULT_BUDGET", "DEFAULT_MAX_CANDIDATES", "DEFAULT_MAX_TRIALS", "DEFAULT_RUNS", "DEFAULT_SEED", "DEFAULT_WORKERS",
           "ENGINE_VARIATIONS", "FORCE_SCALES", "FUNNEL_LIFTS", "FunnelCheck", "GAP_CONVERGENCE", "GOALS",
           "GOAL_GUARANTEED", "GOAL_SEATED", "HOLD_LIMIT",
           "HOLD_TIME", "MAX_SEGMENTS", "PATH_POSES", "PLAN_REFINEMENTS", "Plan",
           "PlanCancelled", "PlanError", "REGION_BATCH", "REGION_BETA", "REGION_BISECTIONS",
           "REGION_CANDIDATES", "REGION_DRAWS", "REGION_EPSILON",
           "REGION_GRID", "REGION_SAMPLED_MODELS", "RegionCandidate", "RegionCertificate",
           "RunResult", "SAMPLE_ATTEMPTS", "STATE_AXES", "SegmentFunnel", "FUNNEL_DRAWS",
           "check_segment_funnels", "certify_segment_funnels", "sample_states",
           "StartRegion", "certify_region", "cover", "run_region_samples", "run_starts",
           "sample_starts", "ConeSlice", "SLICE_GRID", "check_region_cones", "slice_cover",
           "exclusive_margin",
           "start_scene", "SEGMENT_TIMEOUT", "Segment",
           "TraceFrame", "candidate_modes", "capture", "capture_models",
           "execute", "funnel_checks", "hold_segments", "lifted_scene", "plan_seating",
           "plan_segment", "project_pose", "robust_directions", "run_models",
           "sample_models", "solve_pose", "trace"]
