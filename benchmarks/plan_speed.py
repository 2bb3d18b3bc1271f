# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""CPU time of the seating planner on fixed tasks, this checkout against another tree,
with a digest of every plan (the plans must be identical bit for bit).

The tasks (planned with the default work bounds, ``simulate_runs=False``):

* ``scene:<file>[@x,y,theta]``: the six documented scenes of
  test/core/test_plan_search.py (SCENES): the pawl, the tipped pawl, the T-bar, the disc
  in its nest (each fixel's mu in [0.2, 0.4]) and the polygon pawl at the two start
  poses of docs/planning.md, section 3 (the nominal model);
* ``arrival:<name>``: the seeded arrival family, ``arrival_family(3, seed=0)``
  (test/helpers/arrival_family.py; each fixel's mu in the task's mu +- 0.1);
* ``seating:<name>``: the seeded seating family, ``seating_family(2, seed=0)``
  (test/helpers/seating_family.py; mu in [0.2, 0.4]);
* ``design:rectangle``: the small fixture design of test/design/test_pipeline.py (a 30 x
  20 mm rectangle, six pin triples on a 10 mm plate, mu in [0.25, 0.35], one plan and
  three Monte Carlo runs) in this process (``workers=0``), every stage; its digest is
  over the design's rows.

Each tree runs in a child process of its own (``PYTHONPATH`` the tree's package; the
task definitions are this checkout's), which plans one task untimed first (the kernels
load outside every row), then every task, recording the CPU time of the planning
(``time.process_time``) and a digest: the sha256 of a canonical text of every field of
the Plan (dataclasses field by field, each Segment's accuracy, floats as
``float.hex()``). ``--repeat`` rounds interleave the two trees (the order alternates);
a task's time is the median over the rounds, and its ratio this / other. The run fails
when a digest differs between the trees or between the rounds.

    python benchmarks/plan_speed.py --tree /path/to/other/checkout
"""

from __future__ import annotations

import argparse
import dataclasses
import hashlib
import json
import math
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import harness  # noqa: E402

OUT = harness.RESULTS / "plan_speed.json"
EX = harness.ROOT / "examples"

#: test/core/test_plan_search.py's SCENES: file, start pose or None, target, friction.
SCENES = (("pawl_seating.yaml", None, (1, 2, 3), (0.2, 0.4)),
          ("pawl_tipped.yaml", None, (1, 2, 3), (0.2, 0.4)),
          ("tbar_swing.yaml", None, (1, 2), (0.2, 0.4)),
          ("disc_nest.yaml", None, (1, 2), (0.2, 0.4)),
          ("pawl_polygon.yaml", (0.092, 0.2, 0.0), (1, 2, 3), None),
          ("pawl_polygon.yaml", (0.096, 0.2, 0.0), (1, 2, 3), None))


def tasks() -> list[tuple[str, object, tuple, object]]:
    """(name, scene, target, friction) of every task, in order."""
    from helpers.arrival_family import arrival_family
    from helpers.seating_family import seating_family

    from wrenchcone_ros.core import load_scene
    from wrenchcone_ros.core.scene_yaml import scene_from_dict

    out = []
    for name, pose, target, friction in SCENES:
        scene = load_scene(EX / name)
        label = f"scene:{name}"
        if pose is not None:
            scene = scene.with_pose(*pose)
            label += "@" + ",".join(f"{v:g}" for v in pose)
        out.append((label, scene, target, friction))
    for t in arrival_family(3, seed=0):
        scene = scene_from_dict(t.scene)
        mu = scene.friction
        out.append((f"arrival:{t.name}", scene, tuple(t.target), (max(0.0, mu - 0.1), mu + 0.1)))
    for t in seating_family(2, seed=0):
        out.append((f"seating:{t.name}", scene_from_dict(t.scene), (1, 2, 3), (0.2, 0.4)))
    out.append(("design:rectangle", None, (), None))
    return out


#: test/design/test_pipeline.py's problem: the part, the plate, the pin triples.
RECTANGLE = {"workpiece": {"mass": 0.02, "inertia": 2e-6, "com": [0.015, 0.01],
                           "shape": {"type": "polygon",
                                     "vertices": [[0, 0], [0.03, 0], [0.03, 0.02], [0, 0.02]]}},
             "friction": 0.3, "fixels": [[1.0, 1.0]]}
TRIPLES = [((1, 4), (2, 3)), ((1, -1), (4, 1)), ((3, -2), (4, -1)), ((1, 1), (2, -3)),
           ((1, 0), (0, 3)), ((2, 0), (4, 1))]


def design_rows() -> list:
    """The rectangle's design in this process: its rows (every stage)."""
    from wrenchcone_ros.design import design_fixtures
    from wrenchcone_ros.design.problem import Plate

    res = design_fixtures(RECTANGLE, Plate(0.01, (6, 5), 0.003), (0.25, 0.35), out=None,
                          plans=1, top=1, runs=3, batch_triples=1, batch_plans=1,
                          triples=TRIPLES, workers=0)
    return list(res.rows)


def canonical(x) -> object:
    """A JSON-able canonical form: floats as float.hex(), dataclasses field by field."""
    if isinstance(x, bool) or x is None or isinstance(x, (int, str)):
        return x
    if isinstance(x, float):
        return x.hex()
    if dataclasses.is_dataclass(x) and not isinstance(x, type):
        d = {f.name: canonical(getattr(x, f.name)) for f in dataclasses.fields(x)}
        if type(x).__name__ == "Segment":
            d["accuracy"] = canonical(x.accuracy)
        return [type(x).__name__, d]
    if isinstance(x, dict):
        return {str(k): canonical(v) for k, v in sorted(x.items(), key=lambda kv: str(kv[0]))}
    if isinstance(x, (list, tuple)):
        return [canonical(v) for v in x]
    if hasattr(x, "tolist"):  # numpy arrays and scalars
        return canonical(x.tolist())
    return repr(x)


def digest(plan) -> str:
    """The sha256 of the plan's (or the design rows') canonical text."""
    text = json.dumps(canonical(plan), sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def child(only: list[str] | None) -> None:
    """Plan every task in this process; print one JSON line per task."""
    import wrenchcone_ros
    from wrenchcone_ros.core import load_scene
    from wrenchcone_ros.core.plan import plan_seating

    plan_seating(load_scene(EX / "disc_nest.yaml"), [1, 2], uncertainty=(0.2, 0.4),
                 simulate_runs=False)  # warm: the kernels load outside every row
    print(json.dumps({"package": str(Path(wrenchcone_ros.__file__).resolve().parent)}),
          flush=True)
    for name, scene, target, friction in tasks():
        if only and name not in only:
            continue
        t0 = time.process_time()
        if scene is None:
            rows = design_rows()
            cpu = time.process_time() - t0
            print(json.dumps({"task": name, "cpu_s": cpu, "digest": digest(rows),
                              "feasible": None, "candidates": len(rows), "trials": None}),
                  flush=True)
            continue
        plan = plan_seating(scene, list(target), uncertainty=friction, simulate_runs=False)
        cpu = time.process_time() - t0
        print(json.dumps({"task": name, "cpu_s": cpu, "digest": digest(plan),
                          "feasible": plan.feasible, "candidates": plan.candidates,
                          "trials": plan.trials}), flush=True)


def run_tree(tree: Path, only: list[str] | None) -> tuple[str, dict[str, dict]]:
    """The child's answers for the package of ``tree``."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(tree / "wrenchcone_ros"), str(harness.ROOT / "test")]))
    cmd = [sys.executable, "-P", str(Path(__file__).resolve()), "--child"]
    if only:
        cmd += ["--only", *only]
    out = subprocess.run(cmd, capture_output=True, text=True, env=env, check=True).stdout
    lines = [json.loads(s) for s in out.splitlines() if s.startswith("{")]
    package = lines[0]["package"]
    expected = (tree / "wrenchcone_ros" / "wrenchcone_ros").resolve()
    if Path(package) != expected:
        raise SystemExit(f"the child imported {package}, not {expected}")
    return package, {d["task"]: d for d in lines[1:]}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tree", type=Path, help="the other checkout (e.g. a worktree of the "
                    "main branch); without it only this checkout runs")
    ap.add_argument("--repeat", type=int, default=3, help="rounds (median over them)")
    ap.add_argument("--only", nargs="+", help="task names (default: every task)")
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        child(args.only)
        return 0
    facts = harness.machine_facts()
    trees = {"this": harness.ROOT}
    if args.tree is not None:
        trees["other"] = args.tree.resolve()
    rounds: dict[str, list[dict[str, dict]]] = {k: [] for k in trees}
    for r in range(args.repeat):
        order = list(trees) if r % 2 == 0 else list(reversed(trees))
        for key in order:
            _, res = run_tree(trees[key], args.only)
            rounds[key].append(res)
            print(f"round {r + 1} {key}: " + ", ".join(
                f"{t} {d['cpu_s']:.2f}" for t, d in res.items()), file=sys.stderr)
    names = list(rounds["this"][0])
    rows, failures = [], []
    for name in names:
        row: dict = {"task": name}
        digests = set()
        for key in trees:
            row[f"cpu_s_{key}"] = statistics.median(rd[name]["cpu_s"] for rd in rounds[key])
            row[f"cpu_s_{key}_all"] = [rd[name]["cpu_s"] for rd in rounds[key]]
            digests |= {rd[name]["digest"] for rd in rounds[key]}
        first = rounds["this"][0][name]
        row.update(digest=first["digest"], feasible=first["feasible"],
                   candidates=first["candidates"], trials=first["trials"],
                   digests_equal=len(digests) == 1)
        if len(digests) != 1:
            failures.append(name)
        if "other" in trees:
            row["ratio_this_over_other"] = row["cpu_s_this"] / row["cpu_s_other"]
        rows.append(row)
    summary: dict = {"tasks": len(rows), "digests_equal": not failures,
                     "cpu_s_this_total": sum(r["cpu_s_this"] for r in rows)}
    if "other" in trees:
        ratios = [r["ratio_this_over_other"] for r in rows]
        summary.update(
            cpu_s_other_total=sum(r["cpu_s_other"] for r in rows),
            ratio_total=summary["cpu_s_this_total"] / sum(r["cpu_s_other"] for r in rows),
            ratio_median=statistics.median(ratios),
            ratio_geometric_mean=math.exp(statistics.fmean(math.log(x) for x in ratios)),
            ratio_min=min(ratios), ratio_max=max(ratios))
    for r in rows:
        print(f"{r['task']:42s} this {r['cpu_s_this']:7.2f} s"
              + (f"  other {r['cpu_s_other']:7.2f} s  ratio {r['ratio_this_over_other']:.3f}"
                 if "other" in trees else "") + ("" if r["digests_equal"] else "  DIGESTS DIFFER"))
    print(json.dumps(summary, indent=1))
    if not args.no_write:
        harness.write_json(OUT, facts, {"repeat": args.repeat, "summary": summary,
                                        "tasks": rows})
    if failures:
        print(f"plans differ: {failures}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
