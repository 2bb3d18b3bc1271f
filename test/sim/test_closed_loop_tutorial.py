# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""docs/closed_loop.md reproduces: its pycon blocks run in order in one namespace
(doctest, ``...`` for what changes from run to run), its ``$ wrenchcone ...`` commands
print what it shows, and its figures (the pawl's tasks, the families' sums and their
per-task tables) are those of benchmarks/results/closed_loop_*.json.

    .venv/bin/python test/sim/test_closed_loop_tutorial.py   # prints section 5's figures
"""

from __future__ import annotations

import contextlib
import doctest
import io
import json
import os
import shlex
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "closed_loop.md"
RESULTS = ROOT / "benchmarks" / "results"
from helpers.docs_examples import blocks, commands  # noqa: E402

pytestmark = pytest.mark.slow  # the tutorial runs the loop

FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
TASK_LABELS = {"pawl_seating": "the pawl 8 mm from its seat (examples/pawl_seating.yaml)",
               "pawl_wedged": "the wedged pawl (examples/pawl_polygon.yaml)"}


def load_results() -> dict:
    """The closed-loop results, one file per task: {task: (record, results)}."""
    out = {}
    for name in TASK_LABELS:
        record = json.loads((RESULTS / f"closed_loop_{name}.json").read_text())
        out[name] = (record, record[name])
    return out


def figures(results: dict) -> tuple[str, str]:
    """Section 5's table rows and latency paragraph, from the results files."""
    rows = []
    for name, (_, r) in results.items():
        plan = "guaranteed" if r["plan_guaranteed"] else "not guaranteed"
        says = ", ".join(f"{k} {v}" for k, v in sorted(r["controller_final_states"].items()))
        rows.append(f"| {TASK_LABELS[name]} | {' -> '.join(r['plan_modes'])}, {plan} | "
                    f"{r['open_loop_seated']} of {r['models']} | {r['closed_loop_seated']} of "
                    f"{r['models']} | {r['closed_only']} | {says} |")
    lat = [r["latency_pose_to_command_ms"] for _, r in results.values()]
    T = [r["time_scale_T_ms"] for _, r in results.values()][0]
    lag = max(r["tray_largest_lag_s"] for _, r in results.values())
    loads = " and ".join(rec["machine"]["loadavg"].split()[0] for rec, _ in results.values())
    per_task = lambda key: " and ".join(  # noqa: E731
        f"{r['controller_calls_ms'][key]['median']:.0f} ms" for _, r in results.values())
    text = ("Latency, from the tray publishing a pose to the tray receiving the command "
            "computed from it, wall clock: median "
            + " and ".join(f"{x['median']:.0f} ms (90th percentile {x['p90']:.0f} ms)"
                           for x in lat)
            + f" in the two tasks, against the motion's time scale T = sqrt(m L / |F|) = "
            f"{T:.0f} ms (the pawl's 8 mm slide takes about 2 T). Where the time goes: a "
            f"control step's command waits for the node's force_directions answer at "
            f"that pose (the call's round trip, median {per_task('force_directions')} in "
            f"the two tasks), and the next step starts after the step's classify_wrench "
            f"check (every classify_wrench call, a back-off's scan of pulls included: "
            f"median {per_task('classify_wrench')}); the commands that hold the "
            f"part while it comes to rest, and those of a back-off, go out at once without "
            f"a call (most of the wedged task's commands: its lower median). The tray's "
            f"largest slip behind real "
            f"time in one step was {lag:.2f} s. The machine: "
            f"{next(iter(results.values()))[0]['machine']['nproc']} cores shared with other "
            f"work (the two tasks ran at the same time), load average {loads} at the start; "
            f"the round trips were not measured on an idle machine.")
    step = json.loads((RESULTS / "closed_loop_step_cost.json").read_text())
    cost = step["closed_loop_step_cost"]["ms"]
    text += (f" Of those round trips, the core's computation at a new pose "
             f"(benchmarks/closed_loop_step_cost.py, without ROS, load average "
             f"{step['machine']['loadavg'].split()[0]}): force_directions of the segment's "
             f"mode, exclusive, for every model median "
             f"{cost['force_directions_robust']['median']:.0f} ms, the robust "
             f"classification {cost['classify_robust']['median']:.0f} ms; the rest is "
             f"spent outside the core (DDS, the executors, three nodes sharing one Python "
             f"process), not broken down further.")
    return "\n".join(rows), text


FAMILIES = ("seating", "arrival")


def load_family(family: str) -> dict:
    """benchmarks/results/closed_loop_family_<family>.json."""
    return json.loads((RESULTS / f"closed_loop_family_{family}.json").read_text())


def against(t: dict) -> str:
    """The closed loop's seated count against the open loop's, in words."""
    d = t["closed_loop_seated"] - t["open_loop_seated"]
    if d == 0 and t["open_loop_seated"] == t["models"]:
        return f"0 (open loop seats all {t['models']})"
    return f"{d:+d}" if d else "0"


def family_sums_rows() -> str:
    """Section 5's table of the families' sums, from the results files."""
    rows = []
    for family in FAMILIES:
        sums = load_family(family)["sums"]
        for kind, label in (("guaranteed", "guaranteed"), ("not_guaranteed", "not guaranteed")):
            x = sums[kind]
            rows.append(f"| {family} | {label} | {x['tasks']} | {x['models']} | "
                        f"{x['open_loop_seated']} | {x['closed_loop_seated']} | "
                        f"{x['tasks_closed_fewer']} |")
    return "\n".join(rows)


def family_task_rows(family: str) -> str:
    """Section 5's per-task table of one family, from its results file: each task's plan
    (modes, guaranteed or not, or why there is none), models, seated open and closed
    loop, the difference, the controller's final states, the pose-to-command latency
    (wall ms, median / 99th percentile) and the motion's time scale T (ms)."""
    def tail(t: dict) -> str:
        lat = t["latency_pose_to_command_ms"]
        return f"{lat['median']:.0f} / {lat['p99']:.0f} | {t['time_scale_T_ms']:.0f}"
    return "\n".join(task_row(t, tail) for t in load_family(family)["tasks"])


def task_row(t: dict, tail) -> str:
    """One task's row of a per-task table: name, plan, models, seated open and closed
    loop, the difference, the controller's final states, then ``tail(t)`` (two cells)."""
    if "no_plan" in t:
        return (f"| {t['name']} | none ({t['no_plan']}) | {t['models']} | - | - | - | - | - "
                f"| - |")
    plan = "guaranteed" if t["plan_guaranteed"] else "not guaranteed"
    says = ", ".join(f"{k} {v}" for k, v in sorted(t["controller_final_states"].items()))
    return (f"| {t['name']} | {' -> '.join(t['plan_modes'])}, {plan} | {t['models']} | "
            f"{t['open_loop_seated']} | {t['closed_loop_seated']} | {against(t)} | {says} | "
            f"{tail(t)} |")


#: The families run in lockstep (benchmarks/results/closed_loop_lockstep_family_*.json).
LOCKSTEP_FAMILIES = ("seating", "arrival", "users")


def load_lockstep(family: str) -> dict:
    """benchmarks/results/closed_loop_lockstep_family_<family>.json."""
    return json.loads((RESULTS / f"closed_loop_lockstep_family_{family}.json").read_text())


def disagrees(t: dict) -> int:
    """Runs of a task whose controller's verdict (SEATED or not) is not the tray's truth
    (from the runs the benchmark lists: every run not seated or not SEATED)."""
    return sum(x["seated"] != (x["state"] == "SEATED") for x in t["closed_loop_misses"])


def lockstep_pawl_rows() -> str:
    """Section 5's pawl rows in lockstep (closed_loop_lockstep_<task>.json)."""
    rows = []
    for name in TASK_LABELS:
        r = json.loads((RESULTS / f"closed_loop_lockstep_{name}.json").read_text())[name]
        plan = "guaranteed" if r["plan_guaranteed"] else "not guaranteed"
        says = ", ".join(f"{k} {v}" for k, v in sorted(r["controller_final_states"].items()))
        rows.append(f"| {TASK_LABELS[name]} | {' -> '.join(r['plan_modes'])}, {plan} | "
                    f"{r['open_loop_seated']} of {r['models']} | {r['closed_loop_seated']} of "
                    f"{r['models']} | {r['closed_only']} | {says} | {disagrees(r)} |")
    return "\n".join(rows)


def lockstep_sums_rows() -> str:
    """Section 5's table of the families' sums in lockstep, from the results files."""
    rows = []
    for family in LOCKSTEP_FAMILIES:
        record = load_lockstep(family)
        tasks = [t for t in record["tasks"] if "no_plan" not in t]
        for kind, want in (("guaranteed", True), ("not guaranteed", False)):
            sel = [t for t in tasks if t["plan_guaranteed"] == want]
            rows.append(f"| {family} | {kind} | {len(sel)} | {sum(t['models'] for t in sel)} "
                        f"| {sum(t['open_loop_seated'] for t in sel)} | "
                        f"{sum(t['closed_loop_seated'] for t in sel)} | "
                        f"{sum(t['closed_loop_seated'] < t['open_loop_seated'] for t in sel)} "
                        f"| {sum(disagrees(t) for t in sel)} |")
        rows.append(f"| {family} | none | {len(record['tasks']) - len(tasks)} | - | - | - | - "
                    f"| - |")
    return "\n".join(rows)


def lockstep_task_rows(family: str) -> str:
    """Section 5's per-task table of one family in lockstep: the plan, models, seated
    open and closed loop, the difference, the controller's final states, its verdicts
    that are not the tray's truth, the lockstep timeouts."""
    return "\n".join(task_row(t, lambda t: f"{disagrees(t)} | {t['lockstep_timeouts']}")
                     for t in load_lockstep(family)["tasks"])


@pytest.fixture(scope="module")
def scratch(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("closed_loop_doc")
    (tmp / "examples").symlink_to(ROOT / "examples")
    (tmp / "runs").mkdir()
    old = os.getcwd()
    os.chdir(tmp)
    try:
        yield tmp
    finally:
        os.chdir(old)


@pytest.fixture(scope="module")
def pycon_run(scratch):
    pytest.importorskip("pymunk")
    pytest.importorskip("rosbags")
    globs: dict = {}
    reports = []
    for b in blocks(DOC):
        if b.lang != "pycon":
            continue
        test = doctest.DocTestParser().get_doctest(b.text, globs, DOC.name, str(DOC), b.line)
        out = io.StringIO()
        runner = doctest.DocTestRunner(optionflags=FLAGS)
        runner.run(test, out=out.write, clear_globs=False)
        reports.append((runner.failures, out.getvalue()))
    return reports


def test_the_python_examples_run_as_shown(pycon_run):
    assert pycon_run, "docs/closed_loop.md has no pycon block"
    for failures, report in pycon_run:
        assert failures == 0, report


@pytest.mark.parametrize("example", commands(DOC), ids=str)
def test_the_commands_print_what_the_docs_show(example, pycon_run):
    from wrenchcone_ros import cli

    argv = shlex.split(example.command)
    assert argv[0] == "wrenchcone"
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
        cli.main(argv[1:])
    checker = doctest.OutputChecker()
    assert checker.check_output(example.output + "\n", out.getvalue(), FLAGS), (
        f"{example}\n--- documented ---\n{example.output}\n--- printed ---\n{out.getvalue()}")


def test_the_figures_are_those_of_the_results_files():
    results = load_results()
    rows, text = figures(results)
    doc = " ".join(DOC.read_text().split())
    for line in rows.splitlines() + [text]:
        assert " ".join(line.split()) in doc, line
    # and what section 5 says of them
    seating, wedged = results["pawl_seating"][1], results["pawl_wedged"][1]
    assert seating["plan_guaranteed"] and not wedged["plan_guaranteed"]
    # the verification of the closed loop: strictly more on the task whose plan is not
    # guaranteed, no fewer on the guaranteed one
    assert wedged["closed_loop_seated"] > wedged["open_loop_seated"]
    assert seating["closed_loop_seated"] >= seating["open_loop_seated"]


def test_the_family_tables_are_those_of_the_results_files():
    doc = " ".join(DOC.read_text().split())
    for line in family_sums_rows().splitlines():
        assert " ".join(line.split()) in doc, line
    for family in FAMILIES:
        record = load_family(family)
        # a record of the tray in real time: its command as the benchmark now runs it so
        # (it runs the loop in lockstep unless told --real-time)
        command = (record["command"] if all(t.get("lockstep") for t in record["tasks"]
                                            if "no_plan" not in t)
                   else record["command"].replace("closed_loop.py ",
                                                  "closed_loop.py --real-time ", 1))
        assert command in doc, command
        for line in family_task_rows(family).splitlines():
            assert " ".join(line.split()) in doc, line
        # the sums are those of the tasks
        tasks = [t for t in record["tasks"] if "no_plan" not in t]
        for kind, want in (("guaranteed", True), ("not_guaranteed", False)):
            sel = [t for t in tasks if t["plan_guaranteed"] == want]
            x = record["sums"][kind]
            assert x["open_loop_seated"] == sum(t["open_loop_seated"] for t in sel)
            assert x["closed_loop_seated"] == sum(t["closed_loop_seated"] for t in sel)
        # the closed loop seats no fewer than the open loop on any guaranteed task
        assert all(t["closed_loop_seated"] >= t["open_loop_seated"]
                   for t in tasks if t["plan_guaranteed"]), family


def test_the_lockstep_tables_are_those_of_the_results_files():
    """Section 5's lockstep tables are the results files', whose runs were all in
    lockstep; and what the closed loop must do on them: every guaranteed task seats every
    model both ways, no task seats fewer closed than open, and the controller's verdict
    is the tray's truth on every run."""
    doc = " ".join(DOC.read_text().split())
    for line in lockstep_pawl_rows().splitlines() + lockstep_sums_rows().splitlines():
        assert " ".join(line.split()) in doc, line
    for family in LOCKSTEP_FAMILIES:
        record = load_lockstep(family)
        assert record["command"] in doc, record["command"]
        for line in lockstep_task_rows(family).splitlines():
            assert " ".join(line.split()) in doc, line
        tasks = [t for t in record["tasks"] if "no_plan" not in t]
        assert all(t["lockstep"] for t in tasks), family
        for t in tasks:
            assert t["closed_loop_seated"] >= t["open_loop_seated"], (family, t["name"])
            assert disagrees(t) == 0, (family, t["name"], t["closed_loop_misses"])
            if t["plan_guaranteed"]:
                assert t["open_loop_seated"] == t["closed_loop_seated"] == t["models"], \
                    (family, t["name"])


if __name__ == "__main__":
    rows, text = figures(load_results())
    print(rows)
    print()
    print(text)
    print()
    print(family_sums_rows())
    for fam in FAMILIES:
        print()
        print(family_task_rows(fam))
    print()
    print(lockstep_pawl_rows())
    print()
    print(lockstep_sums_rows())
    for fam in LOCKSTEP_FAMILIES:
        print()
        print(lockstep_task_rows(fam))
