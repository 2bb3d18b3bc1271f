# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""``wrenchcone plan`` (wrenchcone_ros/cli/plan.py) and its tutorial, docs/planning.md:
every command and Python call in the tutorial is run and its output compared with the
text, so every number there is asserted.

After a deliberate change of the outputs, regenerate them with
``PYTHONPATH=test .venv/bin/python test/cli/test_plan.py --update`` and review the diff.
"""

from __future__ import annotations

import contextlib
import doctest
import io
import json
import math
import shlex
import sys

import pytest

pytest.importorskip("pymunk")

from helpers.docs_examples import ROOT  # noqa: E402
from helpers.tutorial import console_cases, in_root, pycon_blocks  # noqa: E402

from wrenchcone_ros import cli  # noqa: E402
from wrenchcone_ros.cli import plan as cli_plan  # noqa: E402

TUTORIAL = ROOT / "docs" / "planning.md"
SEATING = "examples/pawl_seating.yaml"
TBAR = "examples/tbar_swing.yaml"
DISC = "examples/disc_nest.yaml"


def run(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with in_root(), contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = cli.main(argv)
    return code, out.getvalue(), err.getvalue()


@pytest.mark.slow
def test_json_plan():
    code, out, _ = run(["plan", SEATING, "--target", "1", "2", "3", "--friction", "0.2",
                        "0.4", "--runs", "4", "--json"])
    assert code == 0
    d = json.loads(out)
    assert d["feasible"] and d["runs"] == 4 and d["success_rate"] == 1.0
    assert [s["mode"] for s in d["segments"]] == ["arr", "nnn"]
    assert d["segments"][0]["event"] == "fixel 1 reached"
    assert d["friction"] == [[0.2, 0.4]] * 3


@pytest.mark.slow
def test_spring_and_per_fixel_friction():
    code, out, _ = run(["plan", SEATING, "--target", "1", "2", "3", "--actuator", "spring",
                        "--point", "0.0075", "0.035", "--friction", "0.2", "0.4", "0.25",
                        "0.35", "0.3", "0.3", "--runs", "2", "--json"])
    assert code == 0
    d = json.loads(out)
    assert d["actuator"]["kind"] == "spring" and d["actuator"]["point"] == [0.0075, 0.035]
    assert d["friction"] == [[0.2, 0.4], [0.25, 0.35], [0.3, 0.3]]
    assert d["feasible"] and d["segments"][0]["mode"] == "arr"


def test_no_plan_exits_1(tmp_path):
    import yaml

    data = yaml.safe_load((ROOT / "examples" / "pawl_polygon.yaml").read_text())
    data["workpiece"]["pose"] = [0.092, 0.2, 0.0]  # 12 mm left of its seat: it tips
    f = tmp_path / "tips.yaml"
    f.write_text(yaml.safe_dump(data))
    code, out, _ = run(["plan", str(f), "--target", "1", "2", "3"])
    assert code == 1
    assert "no plan: step 1:" in out


@pytest.mark.parametrize("argv, msg", [
    (["--target", "0"], "1..3"),
    (["--target", "1", "--friction", "0.2", "0.3", "0.4"], "--friction takes LO HI"),
    (["--target", "1", "--actuator", "spring"], "needs --point"),
    (["--target", "1", "--point", "0", "0"], "use it with --actuator spring"),
    (["--target", "1", "--tilt", "0"], "(0, 90]"),
    (["--target", "1", "--workers", "0"], "--workers"),
    (["--target", "1", "--friction", "0.4", "0.2"], "friction"),
    (["--target", "1", "--max-candidates", "0"], "--max-candidates must be a whole number >= 1"),
    (["--target", "1", "--max-trials", "-2"], "--max-trials must be a whole number >= 1"),
    (["--target", "1", "--start-region", "0.001", "0", "0", "--region-candidates", "0"],
     "--region-candidates must be a whole number >= 1"),
    (["--target", "1", "--budget", "0"], "--budget must be a positive number of seconds"),
    (["--target", "1", "--budget", "nan"], "--budget must be a positive number of seconds"),
    (["--target", "1", "--start-region", "0.002", "-0.001", "5"],
     "--start-region takes DX DY (m) and DTHETA (degrees, at most 180), each a finite "
     "number >= 0, got 0.002 -0.001 5"),
    (["--target", "1", "--start-region", "0.002", "0.002", "190"], "at most 180"),
    (["--target", "1", "--draw", "region.png"], "--draw needs --start-region DX DY DTHETA"),
    (["--target", "1", "--start-region", "0.001", "0.001", "2", "--draw", "region.txt"],
     "--draw region.txt: the format must be .png, .svg or .pdf"),
])
def test_bad_input_exits_2(argv, msg):
    code, out, err = run(["plan", SEATING, *argv])
    assert code == 2 and out == ""
    assert err.startswith("wrenchcone: error:") and msg in err and "Traceback" not in err


@pytest.mark.slow
def test_exit_code():
    """--exit-code: 0 for a guaranteed plan, 1 for a plan that is not (the T-bar's swing
    is reached by momentum), 2 for no plan; the verdict line says which."""
    code, out, _ = run(["plan", DISC, "--target", "1", "2", "--exit-code"])
    assert code == 0 and "\nguaranteed (the nominal model)" in out
    code, out, _ = run(["plan", TBAR, "--target", "1", "2", "--friction", "0.2", "0.4",
                        "--runs", "0", "--exit-code", "--max-candidates", "3"])
    assert code == 1
    assert "NOT guaranteed: missing a positive worst-case margin in segment(s) 1" in out
    code, out, _ = run(["plan", TBAR, "--target", "1", "2", "--friction", "0.2", "0.4",
                        "--runs", "0", "--max-candidates", "3"])
    assert code == 0  # without --exit-code: a plan was found


@pytest.mark.heavy
def test_no_plan_exit_code_2_and_no_friction_talk(tmp_path):
    """No plan: --exit-code gives 2; without a friction range the reason speaks of no
    friction models."""
    import yaml

    data = yaml.safe_load((ROOT / "examples" / "pawl_polygon.yaml").read_text())
    data["workpiece"]["pose"] = [0.092, 0.2, 0.0]  # 12 mm left of its seat: it tips
    f = tmp_path / "tips.yaml"
    f.write_text(yaml.safe_dump(data))
    code, out, _ = run(["plan", str(f), "--target", "1", "2", "3", "--exit-code"])
    assert code == 2 and "no plan: step 1:" in out and "friction" not in out
    code, out, _ = run(["plan", str(f), "--target", "1", "2", "3", "--exit-code",
                        "--friction", "0.2", "0.4", "--runs", "0"])
    assert code == 2 and "for every model of the uncertainty" in out


@pytest.mark.heavy
@pytest.mark.slow
def test_animation(tmp_path):
    gif = tmp_path / "plan.gif"
    code, out, _ = run(["plan", SEATING, "--target", "1", "2", "3", "--runs", "0",
                        "--animate", str(gif)])
    assert code == 0 and f"animation: {gif}" in out
    data = gif.read_bytes()
    assert data[:6] in (b"GIF87a", b"GIF89a") and len(data) < 2_000_000
    code, _, err = run(["plan", SEATING, "--target", "1", "2", "3", "--runs", "0",
                        "--animate", str(tmp_path / "plan.txt")])
    assert code == 2 and ".gif or .mp4" in err


# --- the tutorial (parsed as docs/tutorial_tray_tilting.md is) ---------------------------
def tutorial_output(cmd: str) -> str:
    argv = shlex.split(cmd)
    assert argv[0] == "wrenchcone", cmd
    code, out, _ = run(argv[1:])
    assert code == 0, cmd
    return out.rstrip("\n")


@pytest.mark.heavy
@pytest.mark.slow
def test_tutorial_commands(monkeypatch, tmp_path):
    """The plans of the tutorial (seeded; the pawl of section 1 and the T-bar of section
    4 with 100 runs, the disc of section 5, the pawl from a box of starts of section 9),
    output exactly as printed there. Then the last one's JSON: the certified box
    (``start_region``, in m and rad) and the certificate, the same figures as the text.
    --draw writes the region's picture. The JSON and --draw runs print the plan the text
    run made (the planner is asked once: those flags change only how the answer is
    given, and a region plan takes half a minute)."""
    cases = list(console_cases(TUTORIAL.read_text()))
    assert len(cases) == 4 and all("--friction 0.2 0.4" in c for c, _ in cases[:2])
    assert [c.split()[2] for c, _ in cases] == [SEATING, TBAR, DISC, SEATING]
    assert "--start-region 0.002 0.002 5" in cases[3][0]
    made = []
    planner = cli_plan.plan_seating
    monkeypatch.setattr(cli_plan, "plan_seating",
                        lambda *a, **kw: made.append(planner(*a, **kw)) or made[-1])
    for cmd, expected in cases:
        assert tutorial_output(cmd) == expected, cmd
    monkeypatch.setattr(cli_plan, "plan_seating", lambda *a, **kw: made[-1])
    code, out, _ = run(shlex.split(cases[3][0])[1:] + ["--json"])
    assert code == 0
    d = json.loads(out)
    assert d["start_region"] == {"dx": 0.002, "dy": 0.002, "dtheta": pytest.approx(
        math.radians(5.0)), "dtheta_deg": pytest.approx(5.0)}
    reg = d["region"]
    assert reg["whole"] and reg["fraction"] == 1.0 and reg["boxes"] == 1
    assert reg["grid"] == 5 and len(reg["models"]) == 9 and reg["sampled"] == 8
    assert f"({reg['boxes']} box(es) checked, {reg['runs']} runs;" in cases[3][1]
    assert d["runs"] == 100 and d["successes"] == 100
    # --draw writes the region's picture (of the same plan)
    picture = tmp_path / "region.png"
    code, out, _ = run(shlex.split(cases[3][0])[1:] + ["--draw", str(picture)])
    assert code == 0
    assert f"\npicture: {picture} (the certified box, 2 segments' entry regions" in out
    assert picture.stat().st_size > 20_000


@pytest.mark.slow
def test_tutorial_python():
    blocks = pycon_blocks(TUTORIAL.read_text())
    assert len(blocks) == 3
    for k, block in enumerate(blocks):
        test = doctest.DocTestParser().get_doctest(block, {}, f"planning.md block {k}",
                                                   str(TUTORIAL), 0)
        runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
        with in_root():
            runner.run(test)
        assert runner.failures == 0, f"pycon block {k} of docs/planning.md"


def test_tutorial_links():
    text = TUTORIAL.read_text()
    for fig in ("figures/plan_pawl_seating.gif", "figures/plan_pawl_tipped.gif",
                "figures/plan_tbar_swing.gif"):
        assert fig in text
        path = ROOT / "docs" / fig
        assert path.exists() and path.stat().st_size < 2_000_000
    assert (ROOT / "docs" / "figures" / "plan_tbar_swing.gif").stat().st_size < 1_500_000
    # each animation is regenerated by the command printed under it
    for fig in ("plan_pawl_seating.gif", "plan_pawl_tipped.gif", "plan_tbar_swing.gif"):
        assert f"--runs 0 --animate docs/figures/{fig}" in text


@pytest.mark.slow
def test_tbar_json():
    """The T-bar of section 4 from the CLI's JSON: two segments, two tilts whose
    intervals are disjoint."""
    code, out, _ = run(["plan", TBAR, "--target", "1", "2", "--friction", "0.2", "0.4",
                        "--runs", "2", "--json"])
    assert code == 0
    d = json.loads(out)
    assert d["feasible"] and [s["mode"] for s in d["segments"]] == ["na", "nn"]
    (lo1, hi1), (lo2, hi2) = (s["interval"] for s in d["segments"])
    assert hi2 < lo1 or hi1 < lo2
    assert d["segments"][0]["direction"] != d["segments"][1]["direction"]


def _update() -> None:
    text = TUTORIAL.read_text()
    for cmd, expected in console_cases(text):
        text = text.replace(f"$ {cmd}\n{expected}", f"$ {cmd}\n{tutorial_output(cmd)}")
    TUTORIAL.write_text(text)


if __name__ == "__main__" and "--update" in sys.argv:
    _update()
