# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The examples in README.md and docs/*.md, extracted for the tests that run them.

What the docs promise, and these helpers extract:

* ```console blocks: each ``$ `` line is a command, the lines after it (up to the next
  ``$ `` line) its output, standard output and standard error together.
* ```pycon blocks: doctests (one namespace per block).
* a ```python block directly followed by a ```text block: a program and what it prints.

Plain indented blocks are shell recipes with no claimed output (``make run``, builds);
they are not run. The tutorials have their own tests and are left out here:
docs/tutorial_tray_tilting.md (test/core/test_tutorial_tray_tilting.py) and
docs/planning.md (test/cli/test_plan.py), docs/fixture_design.md
(test/design/test_tutorial_fixture_design.py), docs/closed_loop.md
(test/sim/test_closed_loop_tutorial.py); docs/benchmarks.md has no examples.

Outputs are compared as text with the numbers in it taken out: the text must be equal
(runs of white space count as one blank), and each number equal to a relative
:data:`NUMBER_RTOL` (absolute :data:`NUMBER_ATOL` near 0), so a documented output that
changes fails, while the last digits of a float may differ between machines.
"""

from __future__ import annotations

import doctest
import math
import re
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
#: dimensionless: numbers in a documented output are equal within this relative tolerance
NUMBER_RTOL = 1e-6
#: same unit as the number: the absolute tolerance for numbers near 0 (e.g. -0.0 and 1e-17)
NUMBER_ATOL = 1e-9
SKIPPED = {"tutorial_tray_tilting.md", "planning.md", "benchmarks.md", "fixture_design.md",
           "closed_loop.md"}

_FENCE = re.compile(r"^```([a-z]*)\n(.*?)^```\s*$", re.S | re.M)
_NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?|[-+]?\b(?:nan|inf)\b")


def doc_files() -> list[Path]:
    """README.md and every docs/*.md with examples to run."""
    return [ROOT / "README.md", *sorted(p for p in (ROOT / "docs").glob("*.md")
                                        if p.name not in SKIPPED)]


@dataclass(frozen=True)
class Command:
    """One ``$ `` line of a console block and the output the docs show for it."""

    path: Path
    line: int
    command: str
    output: str

    def __str__(self) -> str:
        return f"{self.path.name}:{self.line}: $ {self.command}"


@dataclass(frozen=True)
class Block:
    """A fenced block: its language, its text and the line where it starts."""

    path: Path
    line: int
    lang: str
    text: str


def blocks(path: Path) -> list[Block]:
    text = path.read_text()
    return [Block(path, text.count("\n", 0, m.start()) + 1, m.group(1), m.group(2))
            for m in _FENCE.finditer(text)]


def commands(path: Path) -> list[Command]:
    """Every ``$ `` command of the file's console blocks, with its documented output."""
    out = []
    for b in blocks(path):
        if b.lang != "console":
            continue
        cmd, start, lines = None, 0, []
        for i, line in enumerate(b.text.splitlines()):
            if line.startswith("$ "):
                if cmd is not None:
                    out.append(Command(path, start, cmd, "\n".join(lines)))
                cmd, start, lines = line[2:], b.line + 1 + i, []
            elif cmd is None:
                raise AssertionError(f"{path.name}:{b.line}: console block must start with '$ '")
            else:
                lines.append(line)
        if cmd is not None:
            out.append(Command(path, start, cmd, "\n".join(lines)))
    return out


def programs(path: Path) -> list[tuple[Block, Block]]:
    """(```python block, the ```text block right after it) pairs: a program and its output."""
    bs = blocks(path)
    text = path.read_text()
    pairs = []
    for a, b in zip(bs, bs[1:]):
        if a.lang == "python" and b.lang == "text":
            between = text.splitlines()[a.line + a.text.count("\n"):b.line - 1]
            if len([s for s in between if s.strip()]) <= 2:  # "prints", a blank line
                pairs.append((a, b))
    return pairs


def _split(text: str) -> tuple[list[str], list[float]]:
    words, numbers, pos = [], [], 0
    for m in _NUMBER.finditer(text):
        words.append(text[pos:m.start()])
        numbers.append(float(m.group()))
        pos = m.end()
    words.append(text[pos:])
    return [" ".join(w.split()) for w in words], numbers


def same_output(documented: str, actual: str) -> bool:
    """The text equal (white space runs as one blank), every number within the tolerance."""
    w1, n1 = _split(documented.strip())
    w2, n2 = _split(actual.strip())
    if w1 != w2 or len(n1) != len(n2):
        return False
    for a, b in zip(n1, n2):
        if math.isnan(a) or math.isnan(b):
            if not (math.isnan(a) and math.isnan(b)):
                return False
        elif a != b and not math.isclose(a, b, rel_tol=NUMBER_RTOL, abs_tol=NUMBER_ATOL):
            return False
    return True


class NumberTolerantChecker(doctest.OutputChecker):
    """doctest's checker, with numbers compared as :func:`same_output` does."""

    def check_output(self, want: str, got: str, optionflags: int) -> bool:
        return super().check_output(want, got, optionflags) or same_output(want, got)


def doctests(block: Block, globs: dict | None = None) -> doctest.DocTest:
    return doctest.DocTestParser().get_doctest(block.text, globs or {}, str(block.path.name),
                                               str(block.path), block.line)


def run_doctest(block: Block) -> tuple[int, str]:
    """Run a pycon block; (failures, report)."""
    import io

    out = io.StringIO()
    runner = doctest.DocTestRunner(checker=NumberTolerantChecker(),
                                   optionflags=doctest.NORMALIZE_WHITESPACE)
    result = runner.run(doctests(block), out=out.write)
    return result.failed, out.getvalue()


# --- the node's current figures (docs/node.md, "Current figures") ----------------------
RESULTS = ROOT / "benchmarks" / "results"


def _ms(d: dict, *path: str) -> str:
    for key in path:
        d = d[key]
    return f"{d:.2f}"


def node_figures() -> str:
    """The markdown of docs/node.md's "Current figures" tables, from the results files.

    The docs quote exactly this text, so a results file rerun by its command (INDEX.md)
    and not copied into the docs fails test_docs_examples.py. Print it with
    ``.venv/bin/python test/helpers/docs_examples.py`` after a rerun.
    """
    import json

    lat = json.loads((RESULTS / "node_latency.json").read_text())
    s = lat["services_ms"]
    f = lat["pose_to_F_ms"]
    rows = [
        "| call (`node_latency.json`) | median ms | p99 ms | median / empty Trigger |",
        "| --- | --- | --- | --- |",
        f"| empty `std_srvs/Trigger` (the floor) | {_ms(s, 'trigger', 'median')} | "
        f"{_ms(s, 'trigger', 'p99')} | 1.00 |",
        f"| `check_wrench`, cached cone | {_ms(s, 'check_cached', 'median')} | "
        f"{_ms(s, 'check_cached', 'p99')} | {lat['ratio_cached_vs_empty']:.2f} |",
        f"| `check_wrench`, new pose before every call | {_ms(s, 'check_new_pose', 'median')} | "
        f"{_ms(s, 'check_new_pose', 'p99')} | {lat['ratio_new_pose_vs_empty']:.2f} |",
    ] + [f"| a pose to the published F of {k} monitored mode{'s' if k != '1' else ''} | "
         f"{_ms(f, k, 'median')} | {_ms(f, k, 'p99')} | |" for k in ("1", "4", "16")]
    rows += ["", "| 1 kHz poses, 16 modes: executor (run) | check_wrench median / p99 ms | "
             "empty Trigger median / p99 ms | pose age p99 ms | F lag median / p99 ms | "
             "poses covered by an F | node CPU % |",
             "| --- | --- | --- | --- | --- | --- | --- |"]
    runs: dict[str, int] = {}
    for r in json.loads((RESULTS / "node_stream_1khz_16modes.json").read_text())["results"]:
        kind = r.get("executor", "lane")
        runs[kind] = runs.get(kind, 0) + 1
        covered = 100.0 * r["F_poses_covered"] / r["poses_sent"]
        rows.append(f"| {kind} ({runs[kind]}) | {_ms(r, 'check_ms', 'median')} / "
                    f"{_ms(r, 'check_ms', 'p99')} | {_ms(r, 'trigger_ms', 'median')} / "
                    f"{_ms(r, 'trigger_ms', 'p99')} | {_ms(r, 'pose_age_ms', 'p99')} | "
                    f"{_ms(r, 'F_lag_ms', 'median')} / {_ms(r, 'F_lag_ms', 'p99')} | "
                    f"{covered:.1f} % | {r['node_cpu_pct']:.0f} |")
    return "\n".join(rows) + "\n"


def plan_arrival_figures() -> str:
    """The markdown of docs/planning.md's table of guarantees per kind of task (section
    7) and the sentences after it, from benchmarks/results/plan_arrival.json.

    The docs quote exactly this text (test_docs_examples.py); print it with
    ``.venv/bin/python test/helpers/docs_examples.py`` after a rerun.
    """
    import json

    from statistics import median as med

    rec = json.loads((RESULTS / "plan_arrival.json").read_text())
    rows = ["| kind | tasks | plans | guaranteed | guaranteed, >= 99 % of 100 models and "
            "nominal run seated | smallest rate | nominal run seats | one tilt seats, the "
            "plan does not | planning time median / max (wall) | CPU median / max |",
            "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for kind in ("example", "seating", "disc", "pivot", "bounce"):
        k = rec["summary"][kind]
        ok = k["guaranteed"] - k["guaranteed_below_99"] - k["guaranteed_refuted_nominal"]
        rate = ("-" if k["smallest_guaranteed_rate"] is None
                else f"{100 * k['smallest_guaranteed_rate']:.0f} %")
        rows.append(f"| {kind} | {k['tasks']} | {k['feasible']} | {k['guaranteed']} | "
                    f"{ok} of {k['guaranteed']} | {rate} | {k['nominal_seated']} | "
                    f"{k['one_tilt_seats_but_plan_does_not']} | "
                    f"{k['planning_s_median']:.1f} s / {k['planning_s_max']:.1f} s | "
                    f"{k['planning_cpu_s_median']:.1f} s / {k['planning_cpu_s_max']:.1f} s |")
    tasks = rec["tasks"]
    g = [t for t in tasks if t["guaranteed"]]
    arrival = [t for t in tasks if t["kind"] in ("disc", "pivot", "bounce")]

    pawl = rec["pawl_plan_100_models"]
    discs = [t for t in g if t["kind"] == "disc"]
    eased = [t for t in discs if any(x <= 0.5 for x in t["scales"][:-1])]
    const = [t for t in tasks if t["constant_tilt"]]
    unseated = [t for t in tasks if not t["nominal_seated"]]
    text2 = (
        f"Of the {len(discs)} guaranteed discs, {len(eased)} needed the eased-off arrival "
        f"(a moving segment at half the pull or less). Plans of one constant tilt, the "
        f"last resort: {len(const)} ("
        + ", ".join(f"{t['name']} at {t['directions_deg'][0]:.0f} deg" for t in const)
        + f"), of which guaranteed: {sum(t['guaranteed'] for t in const)}. Tasks whose "
        f"plan does not seat the part in its nominal run, or without a plan: "
        f"{len(unseated)} ({', '.join(t['name'] for t in unseated)}); the scan finds a "
        f"seating tilt for {sum(bool(t.get('scan_seating_tilts_deg')) for t in unseated)} "
        f"of them.")
    text = (
        f"Guaranteed plans: {len(g)}; sampled runs of them: "
        f"{sum(t['runs'] for t in g):,}, seated: "
        f"{sum(round(t['success_rate'] * t['runs']) for t in g):,}, with other contact "
        f"events than the plan's: {sum(t['contradicted'] for t in g)}; runs at the edges "
        f"of the assumptions: {sum(t['edge_runs'] for t in g)}, failed: "
        f"{sum(len(t['edge_failures']) for t in g)}. Planning time of the "
        f"{len(arrival)} arrival tasks: median {med([t['planning_s'] for t in arrival]):.1f} s,"
        f" max {max(t['planning_s'] for t in arrival):.1f} s wall; CPU time of the "
        f"planning thread median {med([t['planning_cpu_s'] for t in arrival]):.1f} s, max "
        f"{max(t['planning_cpu_s'] for t in arrival):.1f} s; the most work a search "
        f"needed: {max(t['candidates'] for t in tasks)} candidates, "
        f"{max(t['trials'] for t in tasks)} segments planned, and the default work bounds "
        f"ended {sum('limit' in t['reason'] for t in tasks)} of {len(tasks)} searches. "
        f"The pawl's plan with {pawl['runs']} sampled models: median "
        f"{pawl['median_s']:.2f} s wall over {len(pawl['wall_s'])} runs. Load average "
        f"at the start: {rec['machine']['loadavg'].split()[0]}, at the end: "
        f"{rec['load_average_end'].split()[0]} ({rec['machine']['nproc']} cores).")
    return "\n".join(rows) + "\n\n" + text + "\n\n" + text2 + "\n"


def design_figures() -> str:
    """The markdown of docs/performance.md's fixture-design figures, from
    benchmarks/results/design_cost.json (``python benchmarks/design_cost.py``).

    The docs quote exactly this text (test_docs_examples.py, whitespace normalised).
    """
    import json
    import statistics

    rec = json.loads((RESULTS / "design_cost.json").read_text())
    rows = ["| part | geometry + location | hold | funnel + plan | Monte Carlo |",
            "| --- | --- | --- | --- | --- |"]
    for r in rec["rates"]:
        mc = r["monte_carlo"]
        rows.append(
            f"| {r['part']} | {r['triples_per_s']:.1f} triples/s "
            f"({r['placements_per_s']:.1f} placements/s) | {r['hold_per_s']:.1f} designs/s | "
            f"{r['plan_per_s']:.2f} designs/s ({r['plans_feasible']} of {r['plan_designs']} "
            f"feasible) | "
            + (f"{mc['runs']} runs and the plan: {mc['seconds']:.1f} s |" if mc else "- |"))
    w = rec["whole_design"]
    rows += ["", f"The whole design of the pawl (`examples/plates/plate_10mm.yaml`, the "
             f"defaults, a LocalCluster of {w['workers']} workers): {w['wall_seconds']:.0f} s "
             f"wall; {w['rows']:,} placements, {w['located']:,} located, {w['holding']:,} "
             f"holding for every model, {w['guaranteed']} with a guaranteed plan.", "",
             "| stage | batches | tasks | wall s | batch s (sum) | batch s (median, max) |",
             "| --- | --- | --- | --- | --- | --- |"]
    for st in w["stages"]:
        b = st["batch_seconds"]
        rows.append(f"| {st['name']} | {st['batches']} | {st['tasks']:,} | {st['wall']:.1f} | "
                    f"{sum(b):.1f} | {statistics.median(b):.1f}, {max(b):.1f} |")
    sp = rec["speedup"]
    rows += ["", "| stage 1 of that design, first 600 pin triples | wall s | stage s | "
             "batches |", "| --- | --- | --- | --- |"]
    for k, label in (("0", "in this process, no Dask"), ("1", "LocalCluster, 1 worker"),
                     ("2", "LocalCluster, 2 workers")):
        rows.append(f"| {label} | {sp[k]['wall_seconds']:.1f} | {sp[k]['stage_wall']:.1f} | "
                    f"{sp[k]['batches']} |")
    ov, pj = rec["overhead"], rec["projection"]
    batch = statistics.median(sp["2"]["batch_seconds"])
    p10, p5, pp = pj["pawl_10mm_stage1"], pj["pawl_5mm_stage1"], pj["pawl_10mm_plans"]
    text = (
        f"Speed-up from 1 to 2 workers: {sp['speedup_1_to_2']:.2f}. The scheduler's "
        f"overhead: {1e3 * ov['bulk_seconds_per_task']:.1f} ms per task in bulk "
        f"({ov['tasks']} no-op tasks on 2 workers), {1e3 * ov['round_trip_seconds_median']:.1f}"
        f" ms for one task's round trip, against a median batch of {batch:.2f} s "
        f"({100 * ov['bulk_seconds_per_task'] / batch:.2f} %). Projected on 64 workers "
        f"(a projection from the batches' own times, not a measurement): stage 1 of the "
        f"10 mm design, {p10['batches']} batches and {p10['cpu_seconds']:.0f} CPU s, "
        f"{p10['projected_64_workers_seconds']:.0f} s (measured on 2 workers: "
        f"{p10['measured_2_workers_seconds']:.0f} s; its largest batch bounds it); the pawl "
        f"on the 5 mm lattice, {p5['triples']:,} pin triples, about "
        f"{p5['cpu_seconds_estimated']:.0f} CPU s in {p5['batches']} batches, "
        f"{p5['projected_64_workers_seconds']:.0f} s; the plan stage of the 10 mm design, "
        f"{pp['batches']} tasks and {pp['cpu_seconds']:.0f} CPU s, "
        f"{pp['projected_64_workers_seconds']:.0f} s (measured on 2 workers: "
        f"{pp['measured_2_workers_seconds']:.0f} s; its longest search bounds it). "
        f"Load average at the start: "
        f"{rec['machine']['loadavg'].split()[0]}, at the end: "
        f"{rec['load_average_end'].split()[0]} ({rec['machine']['nproc']} cores).")
    return "\n".join(rows) + "\n\n" + text + "\n"



def plan_speed_figures() -> str:
    """The markdown of docs/performance.md's planner CPU-time figures, from
    benchmarks/results/plan_speed.json (``python benchmarks/plan_speed.py --tree ...``).

    The docs quote exactly this text (test_docs_examples.py, whitespace normalised).
    """
    import json

    rec = json.loads((RESULTS / "plan_speed.json").read_text())
    sm = rec["summary"]
    rows = ["| task | CPU s, before | CPU s, now | now / before |", "| --- | --- | --- | --- |"]
    for t in rec["tasks"]:
        rows.append(f"| `{t['task']}` | {t['cpu_s_other']:.2f} | {t['cpu_s_this']:.2f} | "
                    f"{t['ratio_this_over_other']:.2f} |")
    text = (f"All {sm['tasks']} tasks: {sm['cpu_s_other_total']:.1f} CPU s before, "
            f"{sm['cpu_s_this_total']:.1f} s now, a ratio of {sm['ratio_total']:.2f} (the "
            f"median of the tasks' ratios {sm['ratio_median']:.2f}, from "
            f"{sm['ratio_min']:.2f} to {sm['ratio_max']:.2f}); medians of "
            f"{rec['repeat']} rounds; every digest equal: "
            f"{'yes' if sm['digests_equal'] else 'no'}. Load average at the start: "
            f"{rec['machine']['loadavg'].split()[0]}, at the end: "
            f"{rec['load_average_end'].split()[0]} ({rec['machine']['nproc']} cores, shared "
            f"with other jobs: the absolute times vary, the ratios of one run are the "
            f"figures to read).")
    return "\n".join(rows) + "\n\n" + text + "\n"

if __name__ == "__main__":
    print(node_figures(), end="")
    print()
    print(plan_arrival_figures(), end="")
    print()
    print(design_figures(), end="")
    print()
    print(plan_speed_figures(), end="")
