# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""docs/tutorial_tray_tilting.md reproduces: every command and Python call in it is run and
its output compared with the text (so every number in the tutorial is asserted).

* ```console blocks: lines ``$ wrenchcone ...`` are run through ``wrenchcone_ros.cli.main``
  (the code behind the ``wrenchcone`` script) and must print exactly the lines that follow;
* ```pycon blocks are doctests (run in order, sharing one namespace per block).

After a deliberate change of the outputs, regenerate them with
``PYTHONPATH=test .venv/bin/python test/core/test_tutorial_tray_tilting.py --update`` and review the diff.
"""

from __future__ import annotations

import doctest
import io
import sys
from pathlib import Path

import pytest

from helpers.tutorial import console_cases, in_root, pycon_blocks, run_command, update

ROOT = Path(__file__).resolve().parents[2]
TUTORIAL = ROOT / "docs" / "tutorial_tray_tilting.md"
def test_tutorial_has_the_steps():
    text = TUTORIAL.read_text()
    cmds = [c for c, _ in console_cases(text)]
    assert any("--exclusive" in c for c in cmds) and any("sweep" in c for c in cmds)
    assert any("--point" in c for c in cmds) and len(pycon_blocks(text)) >= 3
    for fig in ("figures/tutorial_directions.png", "figures/tutorial_sweep.png"):
        assert fig in text and (ROOT / "docs" / fig).exists()
    assert "docs/tutorial_tray_tilting.md" in (ROOT / "README.md").read_text()


@pytest.mark.parametrize("cmd, expected", list(console_cases(TUTORIAL.read_text())))
def test_console_outputs(cmd, expected):
    with in_root():
        assert run_command(cmd).rstrip("\n") == expected.rstrip("\n")


@pytest.mark.slow
@pytest.mark.parametrize("k", range(len(pycon_blocks(TUTORIAL.read_text()))))
def test_python_outputs(k):
    block = pycon_blocks(TUTORIAL.read_text())[k]
    test = doctest.DocTestParser().get_doctest(block, {}, f"tutorial block {k}",
                                               str(TUTORIAL), 0)
    runner = doctest.DocTestRunner(optionflags=doctest.NORMALIZE_WHITESPACE)
    out = io.StringIO()
    with in_root():
        runner.run(test, out=out.write)
    assert runner.failures == 0, out.getvalue()


if __name__ == "__main__":
    if "--update" in sys.argv:
        with in_root():
            TUTORIAL.write_text(update(TUTORIAL.read_text()))
        print(f"updated {TUTORIAL}")


# --- section 6 (uncertain mu and centre of mass): its numbers against nominal answers ------
def _pawl_with(mus):
    import dataclasses

    from wrenchcone_ros.core import Fixel, load_scene

    scene = load_scene(ROOT / "examples" / "pawl_polygon.yaml")
    return dataclasses.replace(scene, fixels=tuple(
        Fixel(f.position, f.radius, mu) for f, mu in zip(scene.fixels, mus)))


def test_robust_tilt_is_the_intersection_over_the_friction_box():
    import itertools
    import math

    from wrenchcone_ros.core import Uncertainty, consistent_modes, force_directions

    scene = _pawl_with([0.3, 0.3, 0.3])
    (iv,) = force_directions(scene, "arr", uncertainty=Uncertainty(friction=(0.2, 0.4)))
    corners = [_pawl_with([0.3, a, b]) for a, b in itertools.product((0.2, 0.4), repeat=2)]
    nominal = [force_directions(c, "arr")[0] for c in corners]
    assert iv.lo == pytest.approx(max(n.lo for n in nominal), abs=1e-9)
    assert iv.hi == pytest.approx(min(n.hi for n in nominal), abs=1e-9)
    assert math.degrees(iv.lo) == pytest.approx(-math.degrees(math.atan(1 / 0.4)), abs=1e-9)
    g = (math.cos(iv.best), math.sin(iv.best), 0.0)
    from wrenchcone_ros.core import wrench_cone

    assert iv.margin == pytest.approx(min(wrench_cone(s, "arr").margin(g) for s in corners),
                                      abs=1e-9)
    assert (round(math.degrees(iv.best), 2), round(iv.margin, 3)) == (-65.21, 0.052)
    # the nominal recommendation: outside; with mu = 0.4 at both pins the pawl sticks there
    phi = math.radians(-68.71)
    assert not iv.contains(phi)
    stuck = [m.mode for m in consistent_modes(_pawl_with([0.3, 0.4, 0.4]),
                                              (math.cos(phi), math.sin(phi), 0.0))]
    assert stuck == ["snn"]


def test_robust_tilt_with_com_uncertainty_numbers():
    import math

    from wrenchcone_ros.core import Uncertainty, force_directions, load_scene

    scene = load_scene(ROOT / "examples" / "pawl_polygon.yaml")
    U = Uncertainty(friction=(0.2, 0.4), com_radius=0.001)
    (iv,) = force_directions(scene, "arr", uncertainty=U)
    assert str(iv.guarantee) == "scenario(eps=0.05, beta=0.001, N=220)"
    assert (round(math.degrees(iv.lo), 2), round(math.degrees(iv.hi), 2)) == (-68.2, 0.0)
    assert (round(math.degrees(iv.best), 2), round(iv.margin, 3)) == (-66.41, 0.031)
