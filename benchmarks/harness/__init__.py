# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The benchmark harness: paths, timing, one percentile summary, machine facts, output.

Every script in ``benchmarks/`` is a short program on this package:

* :mod:`harness` (this module, no ROS): where things are (``ROOT``, ``DOCS``,
  ``RESULTS``), timing (:func:`time_once`, :func:`time_per_call`), statistics
  (:func:`median`, :func:`summary`: THE percentile helper), machine facts
  (:func:`machine_facts`), output (:func:`write_json`, :func:`write_generated` for the
  generated sections of docs/, :func:`fmt_time`, :func:`fmt_ratio`);
* :mod:`harness.core`: the cone-building variants the core benchmarks compare;
* :mod:`harness.ros`: the node in its own process under a watchdog, service calls, the
  empty-service floor, the benchmark scenes (needs ``install/setup.bash`` sourced);
* :mod:`harness.watch`: in-process watchers (late wake-ups, long garbage collections);
* programs the node benchmarks start: ``harness/instrumented_node.py`` (the node program
  with its public timing hooks recorded to a file), ``harness/pose_stream.py`` (a pose
  stream at a fixed rate), ``harness/empty_service.py`` (the empty-service floor).

Importing this module puts ``test/`` on ``sys.path``, so that the test suite's helper
package is importable (``from helpers.strategies import random_scene``: the seeded scene
generators of test/helpers/); tests never import from ``benchmarks/``. Core benchmarks import :mod:`harness.source_tree` first, so that they
measure this checkout's package whatever else is installed; node benchmarks do not (they
need the install tree's generated message modules).
"""

from __future__ import annotations

import json
import os
import platform
import statistics
import subprocess
import sys
import time
from collections.abc import Callable, Iterable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
RESULTS = ROOT / "benchmarks" / "results"

if str(ROOT / "test") not in sys.path:  # the helper package test/helpers/
    sys.path.insert(1, str(ROOT / "test"))


# ----------------------------------------------------------------------------- timing


def time_once(fn: Callable[[], object]) -> float:
    """Wall time of one call (s), ``time.perf_counter``."""
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def time_per_call(fn: Callable[[], object], min_time: float = 2e-3, max_loops: int = 10_000,
                  clock: Callable[[], float] = time.perf_counter) -> float:
    """Seconds per call of a fast function: loops until ``min_time`` has elapsed on
    ``clock`` (wall time by default; ``time.process_time`` for CPU time)."""
    loops = 1
    while True:
        t0 = clock()
        for _ in range(loops):
            fn()
        dt = clock() - t0
        if dt >= min_time or loops >= max_loops:
            return dt / loops
        loops = min(max_loops, loops * max(2, int(min_time / max(dt, 1e-9)) + 1))


# ----------------------------------------------------------------------------- statistics


def median(xs: Iterable[float | None]) -> float:
    """The median of the values that are not None (nan when there are none)."""
    xs = [x for x in xs if x is not None]
    return statistics.median(xs) if xs else float("nan")


def summary(samples: Iterable[float], scale: float = 1.0) -> dict:
    """n, median, p90, p99, max and mean of ``samples`` times ``scale`` (1e3: s to ms).

    The one percentile rule of every benchmark: ``numpy.percentile``'s default (linear
    interpolation between the closest ranks). ``{"n": 0}`` for no samples."""
    import numpy as np

    a = np.asarray(list(samples), dtype=float) * scale
    if a.size == 0:
        return {"n": 0}
    p90, p99 = np.percentile(a, [90, 99])
    return {"n": int(a.size), "median": float(np.median(a)), "p90": float(p90),
            "p99": float(p99), "max": float(a.max()), "mean": float(a.mean())}


# ----------------------------------------------------------------------------- machine


def _cmd(args: list[str]) -> str:
    try:
        return subprocess.run(args, capture_output=True, text=True, timeout=10).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return "?"


def loadavg() -> str:
    """The 1/5/15-minute load averages, as one string."""
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def _version(dist: str) -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version(dist)
    except PackageNotFoundError:
        return "-"


def machine_facts() -> dict[str, str]:
    """Facts recorded with every result: CPU count and model, Python and library
    versions, the ROS middleware, the load average and the time of the start."""
    model = "?"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return {
        "nproc": _cmd(["nproc"]) or str(os.cpu_count()),
        "cpu": model,
        "python": platform.python_version(),
        "platform": platform.platform(),
        "numpy": _version("numpy"),
        "scipy": _version("scipy"),
        "pycddlib": _version("pycddlib"),
        "numba": _version("numba"),
        "rmw": os.environ.get("RMW_IMPLEMENTATION", "default (rmw_fastrtps_cpp)"),
        "loadavg": loadavg(),
        "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
        "git": _cmd(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"]),
    }


def facts_markdown(facts: dict[str, str], load_end: str | None = None) -> str:
    """The machine facts as the bullet list the generated docs carry (no date or commit:
    those go to the JSON results)."""
    return "\n".join([
        f"- `nproc`: {facts['nproc']} ({facts['cpu']})",
        f"- Python {facts['python']}, numpy {facts['numpy']}, scipy {facts['scipy']}, "
        f"pycddlib {facts['pycddlib']}; {facts['platform']}",
        f"- load average (1/5/15 min) at start: {facts['loadavg']}"
        + (f"; at end: {load_end}" if load_end else "")])


def header_line(facts: dict[str, str], load_end: str, *extra: str) -> str:
    """One line for a benchmark's printed table: when, where, the load."""
    return "; ".join([f"run {facts['date']}, {facts['nproc']} CPUs, load average "
                      f"{facts['loadavg']} at start, {load_end} at end", *extra])


# ----------------------------------------------------------------------------- output


def command_line() -> str:
    """How this script was called, as a line to paste (relative to the repository)."""
    script = Path(sys.argv[0]).resolve()
    try:
        script = script.relative_to(ROOT)
    except ValueError:
        pass
    return " ".join(["python", str(script), *sys.argv[1:]])


def write_json(path: str | os.PathLike | None, facts: dict[str, str], results: dict) -> None:
    """Write ``results`` with the command, the machine facts and the end load to ``path``
    (JSON; nothing when ``path`` is None)."""
    if path is None:
        return
    record = {"command": command_line(), "machine": facts, "load_average_end": loadavg(),
              **results}
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w") as f:
        json.dump(record, f, indent=1, default=float)
        f.write("\n")
    print(f"wrote {path}", file=sys.stderr)


def fmt_time(seconds: float) -> str:
    """Human time with a unit (us below 1 ms, ms below 1 s)."""
    if seconds != seconds:  # nan
        return "-"
    if seconds < 1e-3:
        return f"{seconds * 1e6:.1f} us"
    if seconds < 1.0:
        return f"{seconds * 1e3:.2f} ms"
    return f"{seconds:.2f} s"


def fmt_ratio(r: float) -> str:
    if r != r:
        return "-"
    return f"{r:.1f}x" if r < 100 else f"{r:.0f}x"


def generated_begin(script: str) -> str:
    """The marker opening the section of a doc that ``benchmarks/<script>`` writes."""
    return f"<!-- BEGIN GENERATED by benchmarks/{script} -->"


GENERATED_END = "<!-- END GENERATED -->"


def write_generated(out: Path, script: str, title: str, text: str) -> None:
    """Put ``text`` (which starts with the BEGIN marker of ``script`` and ends with
    GENERATED_END) into the doc ``out`` in place of its generated section; the prose
    around it stays. A new doc gets the heading ``title``."""
    begin = generated_begin(script)
    doc = out.read_text() if out.exists() else f"# {title}\n\n{begin}\n{GENERATED_END}\n"
    if begin not in doc:
        doc += f"\n{begin}\n{GENERATED_END}\n"
    head, rest = doc.split(begin, 1)
    tail = rest.split(GENERATED_END, 1)[1] if GENERATED_END in rest else "\n"
    out.write_text(head + text + tail)
    print(f"wrote {out}")


def publish_generated(text: str, out: Path, script: str, title: str, facts: dict[str, str],
                      results: dict, write: bool = True) -> None:
    """Print a generated section; with ``write``, put it into the doc ``out``
    (:func:`write_generated`) and record the run (when, where, the figures) in
    ``benchmarks/results/<script stem>.json``: the doc itself carries no date or commit."""
    print(text)
    if write:
        write_generated(out, script, title, text)
        write_json(RESULTS / f"{Path(script).stem}.json", facts, results)
