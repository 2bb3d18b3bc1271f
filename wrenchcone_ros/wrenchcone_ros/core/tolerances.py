# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Every numerical tolerance of the core, named once, with its unit.

Wrench-space tolerances are *dimensionless*: they apply in the nondimensional wrench
space ``g_hat = (f_x, f_y, tau / L)`` (``L`` the workpiece's characteristic length,
see :func:`wrenchcone_ros.core.scene.Scene.length_scale`) to vectors scaled to unit
length, so they do not depend on the choice of units or on the magnitude of a wrench.
See docs/numerics.md for how each one was chosen.
"""

from __future__ import annotations

#: Default contact tolerance, metres: a fixel whose gap satisfies ``|gap| <= tol`` is in
#: contact; ``gap > tol`` is a free fixel; ``gap < -tol`` is a penetration (input error).
CONTACT_TOLERANCE_M: float = 1e-9

#: Dimensionless: the contact tolerance applied is at least this many units in the last
#: place of the largest world coordinate of the scene (Scene.effective_contact_tolerance):
#: 8 ulp of 1e7 m is 1.5e-8 m. Below that, float and exact arithmetic round the same
#: written coordinates differently enough to disagree about contact.
COORDINATE_RESOLUTION_ULPS: float = 8.0

#: Dimensionless: ``cone.contains(g)`` accepts ``F_hat u <= CONE_TOLERANCE`` and
#: ``|E_hat u| <= CONE_TOLERANCE`` for the unit nondimensional direction ``u`` of g.
#: That is an angular band of about 1e-9 rad around the boundary of the cone.
CONE_TOLERANCE: float = 1e-9

#: Dimensionless: an open (strict) acceleration condition ``d . xdd > 0`` counts as
#: satisfiable when some unit-length generator of the closed acceleration cone reaches
#: ``d_hat . x_hat > FEASIBILITY_TOLERANCE`` (``d_hat`` a unit row).  Float only; the
#: exact path decides with ``> 0``.
FEASIBILITY_TOLERANCE: float = 1e-9

#: Dimensionless: the mode search (classify.py) skips a subtree only when the unit wrench
#: is farther than this from the relaxed cone. Much looser than CONE_TOLERANCE so that no
#: mode ``Cone.contains`` would accept is pruned (a thin cone's distance can exceed its
#: facet residual); complete modes are decided by ``Cone.contains`` itself.
PRUNE_TOLERANCE: float = 1e-6

#: Dimensionless, relative: singular values below RANK_TOLERANCE * (largest) count as zero
#: when equalities and lines are orthonormalised, and rows shorter than it (after
#: projection, for unit-scale inputs) are dropped as zero.
RANK_TOLERANCE: float = 1e-12

# --- wrenchcone_ros.core.cone3d (float cones in R^3 without cddlib; docs/cone3d.md) ---
# Both apply to *unit* vectors, so they are angles (radians) or sines of angles.

#: Dimensionless (radians): two generator directions closer than this are one direction
#: (duplicates merged; anti-parallel ones span a line); a ray within this angle of the
#: lineality space is dropped; singular values of unit line rows below this (relative)
#: count as zero when the lineality's rank is taken; a gap in a planar angular sort that
#: is within this of pi makes a half-plane.
CONE3_ANGLE_TOLERANCE: float = 1e-10

#: Dimensionless: the fixed part of the band ``|r . f| <= band`` in which a unit generator
#: r counts as lying on the plane of a unit candidate facet normal f (and ``r . f <= band``
#: as on the right side of it).  Backward error of the float cone3d result.
CONE3_FACET_TOLERANCE: float = 1e-11


#: Dimensionless: a float paper-method cone passes its checks when, for each of its unit
#: extreme rays and lines g, the distance of P g / |P g| to pos(K) is at most this
#: (paper.theorem1_holds), and each facet is within this distance (~ angle, rad) of one
#: of the planar closure's (paper.same_cone); otherwise it is recomputed exactly.
VERIFY_TOLERANCE: float = 1e-7

#: Radians: when two acceleration rows of a mode are closer than this (up to sign) but not
#: exactly parallel (nearly coincident fixels), the float methods compute that cone exactly
#: from the scene instead: float rounding of the geometry (~1e-16) would be amplified by
#: 1/angle, and at 1e-6 rad that is still 1e-10, far inside the 1e-8 band of the
#: stability study (docs/error_vs_runtime.md).
PARALLEL_GUARD: float = 1e-6

# --- wrenchcone_ros.core.directions (force directions at a point) ---------------------

#: Radians: absolute tolerance of the bounded optimiser that finds the most robust
#: direction (``best``) inside a direction interval.
BEST_DIRECTION_XATOL: float = 1e-9

#: Dimensionless: margins within this of the largest sampled margin are ties when
#: ``best`` is chosen (the one nearest the middle of the interval wins, so cones with an
#: empty interior, margin 0 everywhere, give the middle).
MARGIN_TIE_TOLERANCE: float = 1e-12

#: Radians: two float angles closer than this are the same direction when interval lists
#: are combined (sweep intersections, ``DirectionInterval.contains``); far below the
#: ~1e-9 rad accuracy of float endpoints (CONE_TOLERANCE).
ANGLE_RESOLUTION: float = 1e-12
# --- input limits (Scene validation, scene.py) ---
# Finite but absurd numbers (1e200 m) overflow later (squared distances, ulps, cddlib);
# a scene outside these limits is refused with a SceneError naming the value and the limit.

#: Metres: largest |value| of any length of a scene: pose x, y, fixel positions, polygon
#: vertices, the centre of mass, disc and pin radii, the contact tolerance. 1e9 m (a
#: million km) keeps squared distances (1e18) and products of them far from overflow
#: while leaving room for world offsets of 1e7 m (test_stability.py).
MAX_COORDINATE_M: float = 1e9

#: Radians: largest |theta| of a pose. ulp(1e6) is 1.2e-10 rad; beyond that the angle
#: itself has no precision left.
MAX_ANGLE_RAD: float = 1e6

#: Workpiece mass (kg) and inertia (kg m^2) must lie in [MIN_MASS_INERTIA,
#: MAX_MASS_INERTIA]: wide enough for grams-and-millimetres to tonnes-and-kilometres
#: (inertia down to 1e-26 kg m^2 in test_stability.py), narrow enough that m L^2 and the
#: nondimensional M never underflow or overflow.
MIN_MASS_INERTIA: float = 1e-30
MAX_MASS_INERTIA: float = 1e30

#: Dimensionless: the range of I / (m L^2) (inertia about the com over mass times the
#: characteristic length squared; a rigid body has at most 1) over which the answers to
#: one question agree. The error-vs-runtime study finds no misclassification against exact
#: arithmetic outside its band over the whole accepted range (docs/error_vs_runtime.md),
#: but the angle by which a wrench's margin grows away from a cone's boundary shrinks with
#: I / (m L^2), so the tolerance of contains() reaches deeper into a neighbouring
#: direction interval: force_directions and consistent_modes agree farther than
#: AGREEMENT_ANGLE_RAD from an interval's edge only from 1e-3 up
#: (benchmarks/agreement_vs_inertia.py: the classification may list a neighbouring mode
#: up to 1e-8 rad inside an edge from 1e-2 to 1e6, 1e-7 rad at 1e-3, 1e-6 rad at 1e-4,
#: 1e-4 rad at 1e-6, 1e-2 rad at 1e-8). A workpiece outside it but inside
#: ACCEPTED_INERTIA_RATIO is accepted and its cones are computed, with a caveat: the core
#: warns once per workpiece (UnverifiedRangeWarning), the CLI prints that line and the
#: node logs it.
VERIFIED_INERTIA_RATIO: tuple[float, float] = (1e-3, 1e6)

#: Dimensionless: the range of I / (m L^2) a workpiece may have at all (load_scene, the
#: CLI and the node refuse others, naming this range). Both studies cover it to its
#: edges: docs/error_vs_runtime.md (the default float method against exact arithmetic:
#: no misclassification, no missing or extra face) and benchmarks/agreement_vs_inertia.py
#: (directions against classification). Beyond it the default float method's faces go
#: wrong (missing and extra faces were seen at 1e-10 and 1e8), so such a workpiece is
#: refused rather than answered unchecked.
ACCEPTED_INERTIA_RATIO: tuple[float, float] = (1e-8, 1e6)

#: Radians: inside VERIFIED_INERTIA_RATIO, a direction farther than this from the edge of
#: an exclusive force_directions interval is classified as that interval's mode alone
#: (benchmarks/agreement_vs_inertia.py measures how far inside an edge the classification
#: may also list a neighbouring mode whose cone it misses by less than CONE_TOLERANCE).
AGREEMENT_ANGLE_RAD: float = 1e-6

#: Metres: smallest characteristic length L of a workpiece (the largest distance from
#: its com to its shape). Wrenches are compared as (f_x, f_y, tau / L) and M_hat holds
#: I / (m L^2): with L >= 1e-12 m and m >= MIN_MASS_INERTIA, m L^2 >= 1e-54 and 1 / L
#: <= 1e12, so neither underflows to 0 nor overflows (a disc of radius 1e-300 m would
#: make m L^2 = 0 and (tau / L)^2 overflow).
MIN_LENGTH_SCALE_M: float = 1e-12

#: Dimensionless: largest friction coefficient mu (scene or fixel). 1e12 is far beyond
#: any physical mu (mu = 1e9 is tested) and keeps mu * c_n finite.
MAX_FRICTION: float = 1e12

#: N and N m: a wrench whose largest component magnitude is above this, or (nonzero and)
#: below its inverse, is multiplied by an exact power of two before use
#: (:func:`.numbers.rescale_wrench`): consistency and margins depend only on a wrench's
#: direction (a cone is a cone), and the squares of 1e200 N would overflow (1e-200 N
#: underflow). The node and the CLI apply the same rule.
WRENCH_RESCALE_ABOVE: float = 1e100

#: Dimensionless: the CLI prints an entry of a cone's row (F, E, G, lineality) as 0 when
#: its magnitude in the nondimensional metric ``g_hat``, where the rows are unit vectors,
#: is below this: round-off (about 1e-16), not a value. Only the text printed changes;
#: the cone, its JSON and every decision keep the computed values.
PRINT_ZERO: float = 1e-12

# --- wrenchcone_ros.core.simulate (forward simulation in pymunk; docs/planning.md) -----
# Lengths are relative to the workpiece's characteristic length L, times to its time
# scale T = sqrt(m L / |F|) (the time a free body needs to move about L / 2 under the
# applied force F), so the simulation does not depend on the choice of units.

#: Dimensionless (times L): Chipmunk's collision slop, the overlap it allows without
#: pushing the shapes apart. Every fixel's circle is inflated by half of it, so a fixel
#: that touches exactly (gap 0) overlaps by SIM_SLOP / 2 and is a contact from the first
#: step; a point fixel is a circle of that radius (its corner is rounded by 5e-5 L).
SIM_SLOP: float = 1e-4

#: Dimensionless (times L): a fixel whose gap (distance to the workpiece minus its pin
#: radius) is at most this is a contact in the simulation's readout.
SIM_CONTACT_BAND: float = 2e-4

#: Dimensionless (times T): the time step.
SIM_TIME_STEP: float = 2.5e-3

#: Dimensionless: a contact point moves (letters a, s, l, r rather than n, s rather than
#: a) when its speed along the normal or the tangent exceeds this fraction of the speed a
#: free body reaches under the applied force in min(t, T) (t: time since the start).
SIM_VELOCITY_TOLERANCE: float = 2e-3
