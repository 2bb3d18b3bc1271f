# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Tests of the independent LP oracle (wrenchcone_ros.core.lp_check) and of Table 2.

Everything here is derived by hand from Newton-Euler + Coulomb friction and from Table 2
of Devin J. Balkcom and Jeffrey C. Trinkle, "Computing wrench cones for planar rigid body
contact tasks", The International Journal of Robotics Research, 21(12):1053-1066, 2002
(restated in docs/theory.md), never from the paper's matrices or the cone code.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from wrenchcone_ros.core.lp_check import (
    LP_FEASIBILITY_TOLERANCE,
    contact_jacobian,
    lp_consistent,
    lp_mode_feasible,
)
from wrenchcone_ros.core.modes import (
    MODE_TABLE,
    Contact,
    Friction,
    ModeError,
    Sign,
    allowed_letters,
)
from wrenchcone_ros.core.scene_yaml import load_scene

# --------------------------------------------------------------------------- Table 2

#: The paper's Table 2 (docs/theory.md), transcribed literally:
#: letter: (contact needed, a_in in contact, a_in without contact, a_it, c_in, c_it)
#: None where the contact state does not allow the letter.
TABLE_2 = {
    "a": ("no", None, "< 0", "free", "= 0", "= 0"),
    "s": ("either", "> 0", ">= 0", "free", "= 0", "= 0"),
    "l": ("yes", "= 0", None, "> 0", ">= 0", "= -mu c_in"),
    "r": ("yes", "= 0", None, "< 0", ">= 0", "= +mu c_in"),
    "n": ("yes", "= 0", None, "= 0", ">= 0", "abs(c_it) <= mu c_in"),
}

_CONTACT = {"no": Contact.FORBIDDEN, "either": Contact.EITHER, "yes": Contact.REQUIRED}
_SIGN = {"free": Sign.FREE, "= 0": Sign.ZERO, ">= 0": Sign.NONNEG, "<= 0": Sign.NONPOS,
         "> 0": Sign.POS, "< 0": Sign.NEG}
# friction rule -> the set of (c_in, c_it) it allows is pos{(1, s mu) : s in edges}
_EDGES = {"= 0": (), "= -mu c_in": (-1,), "= +mu c_in": (1,), "abs(c_it) <= mu c_in": (-1, 1)}


def test_mode_table_letters_match_table_2():
    assert set(MODE_TABLE) == set(TABLE_2)
    for letter, inter in MODE_TABLE.items():
        assert inter.letter == letter


@pytest.mark.parametrize("letter", sorted(TABLE_2))
def test_mode_table_row_matches_table_2(letter):
    contact, an_c, an_f, at, cn, ct = TABLE_2[letter]
    inter = MODE_TABLE[letter]
    assert inter.contact is _CONTACT[contact]
    assert inter.allowed(True) == (an_c is not None)
    assert inter.allowed(False) == (an_f is not None)
    if an_c is not None:
        assert inter.a_n(True) is _SIGN[an_c]
    if an_f is not None:
        assert inter.a_n(False) is _SIGN[an_f]
    assert inter.a_t is _SIGN[at]
    assert inter.c_n is _SIGN[cn]
    assert tuple(sorted(inter.c_t.edges)) == _EDGES[ct]
    assert inter.loaded == (cn != "= 0")


def test_sign_semantics():
    assert {s for s in Sign if s.strict} == {Sign.POS, Sign.NEG}
    assert Sign.POS.closure is Sign.NONNEG and Sign.NEG.closure is Sign.NONPOS
    for s in (Sign.FREE, Sign.ZERO, Sign.NONNEG, Sign.NONPOS):
        assert s.closure is s
    assert [s.direction for s in (Sign.POS, Sign.NONNEG, Sign.NEG, Sign.NONPOS,
                                  Sign.ZERO, Sign.FREE)] == [1, 1, -1, -1, 0, 0]
    assert Friction.CONE.edges and not Friction.ZERO.edges


def test_allowed_letters():
    assert sorted(allowed_letters(True)) == sorted("slrn")
    assert sorted(allowed_letters(False)) == sorted("as")


# --------------------------------------------------------------------------- the paper's example

PAPER = {
    "workpiece": {"mass": 1.0, "inertia": 1.0, "com": [0.0, 0.0],
                  "shape": {"type": "disc", "radius": 1.0}, "pose": [0.0, 0.0, 0.0]},
    "friction": 0.2,
    "contact_tolerance": 1e-9,
    "fixels": [[0.0, -1.0], {"position": [1.001, 0.0], "radius": 0.0}],
}
#: The paper's worked example (section 4; docs/theory.md, "The worked example"): the
#: consistent wrenches of "na" are pos(G).
G_PAPER = np.array([[1.0, 0.0, -1.0], [-0.2, -1.0, -0.2], [0.2, -1.0, 0.2]])


@pytest.fixture(scope="module")
def paper():
    return load_scene(PAPER)


def test_jacobian_of_paper_example(paper):
    # n_1 = (0, 1), t_1 = (-1, 0) at p_1 = (0, -1); n_2 = (-1, 0), t_2 = (0, -1) at (1, 0)
    # columns (v_x, v_y, r x v) ordered n_1, n_2, t_1, t_2
    expected = np.array([[0.0, -1.0, -1.0, 0.0],
                         [1.0, 0.0, 0.0, -1.0],
                         [0.0, 0.0, -1.0, -1.0]])
    np.testing.assert_allclose(contact_jacobian(paper), expected, atol=1e-12)


def test_paper_generators(paper):
    g1, g2, g3 = G_PAPER
    # g1 is realised by the open mode (rolls on fixel 1 while approaching fixel 2)
    assert lp_consistent(paper, "na", g1).consistent
    # g2, g3 are friction-cone edges reversed: balanced with xdd = 0, so a_2n = 0, which
    # the open mode (a_2n < 0) excludes but its closure accepts
    for g in (g2, g3):
        res = lp_consistent(paper, "na", g)
        assert not res.consistent and abs(res.slack) < 1e-9
        assert lp_consistent(paper, "na", g, closure=True).consistent
    for g in G_PAPER:
        assert not lp_consistent(paper, "na", -g).consistent
        assert not lp_consistent(paper, "na", -g, closure=True).consistent


def test_paper_positive_combinations(paper):
    rng = np.random.default_rng(20261121)
    f = lp_mode_feasible(paper, "na")
    for _ in range(40):
        w = rng.uniform(0.05, 1.0, 3)
        g = w @ G_PAPER * 10 ** rng.uniform(-3, 3)
        assert lp_consistent(paper, "na", g, feasibility=f).consistent, (w, g)
        assert lp_consistent(paper, "na", g, closure=True).consistent
        assert not lp_consistent(paper, "na", -g, feasibility=f).consistent
        assert not lp_consistent(paper, "na", -g, closure=True).consistent


@pytest.mark.slow
def test_paper_random_wrenches_against_pos_G(paper):
    """Random directions: consistent iff strictly inside pos(G) (a band of 1e-6 skipped)."""
    rng = np.random.default_rng(7)
    Ginv = np.linalg.inv(G_PAPER.T)
    f = lp_mode_feasible(paper, "na")
    checked = 0
    for _ in range(150):
        g = rng.normal(size=3)
        w = Ginv @ g
        w_rel = w / np.linalg.norm(w)
        if abs(w_rel.min()) < 1e-6:
            continue
        inside = bool(w_rel.min() > 0)
        assert lp_consistent(paper, "na", g, feasibility=f).consistent == inside, g
        assert lp_consistent(paper, "na", g, closure=True).consistent == inside, g
        checked += 1
    assert checked > 120


def test_static_rolling_and_mu_zero():
    """One fixel under a disc: xdd = 0 balance inside the friction cone rolls ("n")."""
    scene = {
        "workpiece": {"mass": 2.0, "inertia": 0.5, "shape": {"type": "disc", "radius": 1.0},
                      "pose": [0.0, 0.0, 0.0]},
        "friction": 0.2,
        "fixels": [[0.0, -1.0]],
    }
    s = load_scene(scene)
    # contact force (-0.1, 1) at (0, -1) has moment (0)(1) - (-1)(-0.1) = -0.1 about the
    # centre, so g = (0.1, -1, 0.1) is balanced with xdd = 0 and |c_t| = 0.1 < 0.2 c_n
    assert lp_consistent(s, "n", [0.1, -1.0, 0.1]).consistent
    assert lp_consistent(s, "n", [0.0, -1.0, 0.0]).consistent
    # outside the friction cone: no rolling
    assert not lp_consistent(s, "n", [0.5, -1.0, 0.5]).consistent
    # lifting off
    assert lp_consistent(s, "s", [0.0, 1.0, 0.0]).consistent
    assert not lp_consistent(s, "s", [0.0, -1.0, 0.0]).consistent
    # mu = 0: a push along +x slides the contact point along +x = -t: sliding right
    s0 = load_scene({**scene, "friction": 0.0})
    assert lp_consistent(s0, "r", [1.0, -1.0, 0.0]).consistent
    assert not lp_consistent(s0, "l", [1.0, -1.0, 0.0]).consistent
    assert not lp_consistent(s0, "n", [1.0, -1.0, 0.0]).consistent
    assert lp_consistent(s0, "l", [-1.0, -1.0, 0.0]).consistent
    # mu = 0 still rolls under a pure normal push through the centre
    assert lp_consistent(s0, "n", [0.0, -3.0, 0.0]).consistent
    assert not lp_consistent(s0, "n", [0.1, -1.0, 0.1]).consistent
    # per-fixel friction overrides the scene's
    s1 = load_scene({**scene, "friction": 0.0,
                     "fixels": [{"position": [0.0, -1.0], "friction": 0.2}]})
    assert lp_consistent(s1, "n", [0.1, -1.0, 0.1]).consistent


def test_sliding_direction_and_friction_sign():
    """Sliding left (+t) needs friction -mu c_n t: derived by hand for a pinned-torque case."""
    # square on the ground, com at the centre, fixel under the middle of the bottom edge
    scene = load_scene({
        "workpiece": {"mass": 1.0, "inertia": 1.0,
                      "shape": {"type": "polygon",
                                "vertices": [[-1, -1], [1, -1], [1, 1], [-1, 1]]},
                      "pose": [0.0, 0.0, 0.0]},
        "friction": 0.5,
        "fixels": [[0.0, -1.0]],
    })
    ct = scene.contacts[0]
    np.testing.assert_allclose(ct.n, [0.0, 1.0], atol=1e-15)
    np.testing.assert_allclose(ct.t, [-1.0, 0.0], atol=1e-15)
    # r = p - com = (0, -1): a_n = a_y (r x n = 0), a_t = -a_x + (r x t) alpha, r x t = -1.
    # Sliding left (+t = -x): c = c_n n - 0.5 c_n t = c_n (0.5, 1). With g = (-1, -1, -0.5):
    # a_n = 0 needs c_n = 1; the moment of c about the com is 0(1) - (-1)(0.5) = 0.5, so
    # alpha = 0.5 - 0.5 = 0 and a_x = 0.5 - 1 = -0.5, a_t = 0.5 > 0: consistent with "l"
    # (and its friction opposes the motion), not with "r", "n" or "s".
    g = [-1.0, -1.0, -0.5]
    assert lp_consistent(scene, "l", g).consistent
    assert not lp_consistent(scene, "r", g).consistent
    assert not lp_consistent(scene, "n", g).consistent
    assert not lp_consistent(scene, "s", g).consistent


# --------------------------------------------------------------------------- impossible mode


def _pinned_disc(mu: float = 0.5) -> dict:
    fixels = [[math.cos(a), math.sin(a)] for a in (math.pi / 2, 7 * math.pi / 6,
                                                   11 * math.pi / 6)]
    fixels.append([1.5, 0.2])  # free
    return {
        "workpiece": {"mass": 1.0, "inertia": 0.5, "shape": {"type": "disc", "radius": 1.0},
                      "pose": [0.0, 0.0, 0.0]},
        "friction": mu,
        "fixels": fixels,
    }


def test_impossible_mode_is_inconsistent_for_every_wrench():
    """Three rolling fixels pin the body (xdd = 0); a fourth "a" needs a_n < 0: impossible.

    The closure accepts xdd = 0 and the friction cones balance every wrench, so a check
    with non-strict inequalities would answer "consistent" for all of R^3.
    """
    scene = load_scene(_pinned_disc())
    assert scene.in_contact == (True, True, True, False)
    rng = np.random.default_rng(3)
    for _ in range(40):
        g = rng.normal(size=3) * 10 ** rng.uniform(-3, 3)
        res = lp_consistent(scene, "nnna", g)
        assert not res.consistent and res.feasibility_slack <= LP_FEASIBILITY_TOLERANCE
        assert lp_consistent(scene, "nnna", g, closure=True).consistent
        # the same contacts with the free fixel separating are fine (no strict condition)
        assert lp_consistent(scene, "nnns", g).consistent


def test_mode_feasibility():
    scene = load_scene(_pinned_disc())
    f = lp_mode_feasible(scene, "nnna")
    assert not f.consistent and abs(f.slack) < 1e-9
    assert lp_mode_feasible(scene, "nnns").consistent  # no strict condition at all
    # three contacts at 120 degrees on a disc: n_1 + n_2 + n_3 = 0 and r x n = 0, so the
    # normal accelerations sum to zero and cannot all be positive
    assert not lp_mode_feasible(scene, "ssss").consistent
    assert lp_mode_feasible(scene, "snns").consistent is False
    assert lp_mode_feasible(scene, "lrsa").consistent is False
    # pinned by three rolling fixels: no contact can slide
    assert not lp_mode_feasible(scene, "lnns").consistent
    paper = load_scene(PAPER)
    assert lp_mode_feasible(paper, "na").slack > 0.1
    # the result can be reused for many wrenches
    f = lp_mode_feasible(paper, "na")
    assert lp_consistent(paper, "na", G_PAPER.sum(axis=0), feasibility=f).consistent


@pytest.mark.parametrize("d", [1e-3, 1e-6, 1e-8])
def test_nearly_coincident_fixels(d):
    """Two point fixels on the bottom edge of a square, a distance d apart.

    With n = (0, 1), t = (-1, 0), r_1 = (0, -1), r_2 = (d, -1) (com at the centre):
    a_n1 = a_y, a_n2 = a_y + d alpha, a_t1 = a_t2 = -a_x - alpha (r x t = -1 for both).
    "sn" (lift fixel 1, pivot on fixel 2) needs a_x = -alpha, a_y = -d alpha > 0: possible,
    although a_n1 is of order d (the LP preconditions its rows, so its slack is not).
    xdd = (1, d, -1) with c = 0 realises it, so the wrench g = M xdd = (1, d, -1) is
    consistent. "ln" needs a_t1 > 0 = a_t2: impossible.
    """
    scene = load_scene({
        "workpiece": {"mass": 1.0, "inertia": 1.0,
                      "shape": {"type": "polygon",
                                "vertices": [[-1, -1], [1, -1], [1, 1], [-1, 1]]},
                      "pose": [0.0, 0.0, 0.0]},
        "friction": 0.3,
        "fixels": [[0.0, -1.0], [d, -1.0]],
    })
    f = lp_mode_feasible(scene, "sn", witness=True)
    assert f.consistent and f.slack > 0.1
    ax, ay, alpha = f.witness
    assert ay > 0 and ax == pytest.approx(-alpha) and ay == pytest.approx(-d * alpha)
    r = lp_consistent(scene, "sn", [1.0, d, -1.0], feasibility=f)
    assert r.consistent and r.relative_slack > 1e-3
    assert not lp_mode_feasible(scene, "ln").consistent
    assert not lp_mode_feasible(scene, "lr").consistent
    assert not lp_consistent(scene, "ln", [1.0, d, -1.0]).consistent


@pytest.mark.parametrize("d", [1e-4, 1e-11])
def test_preconditioning_sees_tiny_consequences(d):
    """Same square, twin fixels d apart, mode "ns" (roll on 1, separate from 2).

    Rolling on fixel 1 forces c_n1 = 0 for g = (+-1, 0, -+1) (a_y = c_n1 = 0), hence
    c = 0 and xdd = g (m = I = 1): a_n2 = a_y + d alpha = d alpha. So g = (1, 0, -1)
    (alpha = -1) is outside even the closure (a_n2 = -d < 0), and g = (-1, 0, 1) is
    consistent (alpha = 1, a_t1 = -a_x - alpha = 0). With d = 1e-11 the violation is far
    below any solver tolerance; only the preconditioned rows (alpha >= 0) see it.
    """
    scene = load_scene({
        "workpiece": {"mass": 1.0, "inertia": 1.0,
                      "shape": {"type": "polygon",
                                "vertices": [[-1, -1], [1, -1], [1, 1], [-1, 1]]},
                      "pose": [0.0, 0.0, 0.0]},
        "friction": 0.3,
        "fixels": [[0.0, -1.0], [d, -1.0]],
    })
    assert not lp_consistent(scene, "ns", [1.0, 0.0, -1.0], closure=True).consistent
    assert not lp_consistent(scene, "ns", [1.0, 0.0, -1.0]).consistent
    assert lp_consistent(scene, "ns", [-1.0, 0.0, 1.0]).consistent
    assert lp_consistent(scene, "ns", [-1.0, 0.0, 1.0], closure=True).consistent


def test_scale_invariance():
    """The decision and the slack do not depend on units or on the wrench magnitude."""
    base = load_scene(PAPER)
    g = np.array([0.7, -0.4, -0.3])
    ref = lp_consistent(base, "na", g)
    for k in (1e-6, 1.0, 1e6):
        res = lp_consistent(base, "na", k * g)
        assert res.consistent == ref.consistent
        assert res.slack == pytest.approx(ref.slack, rel=1e-6, abs=1e-12)
    # millimetres and grams: lengths x1000, mass x1000, inertia x1e9, torque x1000 per N
    mm = {
        "workpiece": {"mass": 1000.0, "inertia": 1e9, "com": [0.0, 0.0],
                      "shape": {"type": "disc", "radius": 1000.0}, "pose": [0.0, 0.0, 0.0]},
        "friction": 0.2,
        "contact_tolerance": 1e-6,
        "fixels": [[0.0, -1000.0], [1001.0, 0.0]],
    }
    res = lp_consistent(load_scene(mm), "na", [0.7, -0.4, -300.0])
    assert res.consistent == ref.consistent
    assert res.slack == pytest.approx(ref.slack, rel=1e-6)


# --------------------------------------------------------------------------- errors


@pytest.mark.parametrize("mode", ["n", "nas", "xa", "aa", "nn", "sn", "", 3])
def test_bad_modes_raise_mode_error(paper, mode):
    with pytest.raises(ModeError):
        lp_consistent(paper, mode, [1.0, 0.0, 0.0])


def test_nonfinite_wrench_raises(paper):
    with pytest.raises(ValueError):
        lp_consistent(paper, "na", [float("nan"), 0.0, 0.0])
