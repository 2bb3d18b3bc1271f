# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The scan of constant tilts of docs/planning.md, section 4: each tilt run in the engine
(core/simulate.py, the nominal model) from the start pose as a one-tilt plan through
``plan.trace``, the very code that runs the plans (same time limits, same test of
"seated"); a run is cut short only once the part is free and can never touch a fixel
again (:func:`gone`), which cannot seat it.

``.venv/bin/python test/helpers/tilt_scan.py`` prints the summary docs/planning.md quotes.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from pathlib import Path

from wrenchcone_ros.core import DirectionInterval, load_scene
from wrenchcone_ros.core.plan import HOLD_LIMIT, SEGMENT_TIMEOUT, Plan, Segment, trace
from wrenchcone_ros.core.simulate import Actuator, Simulation
from wrenchcone_ros.core.tolerances import SIM_CONTACT_BAND, SIM_SLOP

ROOT = Path(__file__).resolve().parents[2]
TBAR = ROOT / "examples" / "tbar_swing.yaml"
TARGET = (1, 2)
#: The scan: every SCAN_STEP degrees over the full circle.
SCAN_STEP = 2
NEVER = "never reaches pin 2"
SWINGS = "reaches pin 2 but is not seated at the end"


@dataclass(frozen=True)
class Outcome:
    """One constant tilt (degrees): seated at the end, the fixels (1-based) reached in
    order, and whether the part ended free for good (:func:`gone`)."""

    direction_deg: float
    seated: bool
    reached: tuple[int, ...]
    gone: bool


def one_tilt_plan(scene, phi: float, target) -> Plan:
    """A plan of one tilt phi (rad): move until every target fixel not yet touched is
    reached, then hold, all under phi; run by ``plan.trace`` like any plan."""
    todo = tuple(i for i in target if not scene.in_contact[i - 1])
    pose = tuple(scene.pose)

    def segment(hold: bool) -> Segment:
        return Segment(mode="", interval=DirectionInterval(phi, phi, phi, 0.0), direction=phi,
                       margin=0.0,
                       start_pose=pose, end_pose=pose, event="", predicted_event="",
                       reached=() if hold else todo, hold=hold)
    return Plan(((segment(False),) if todo else ()) + (segment(True),), True, "",
                tuple(target), Actuator(), None)


def gone(sim: Simulation, scene) -> bool:
    """The part is free and can never touch a fixel again: for every fixel f, the com c
    is farther than L + rho + band (+ the engine's slop) from it and both the com's
    velocity v and the pull F point away from it ((f - c).v <= 0, (f - c).F <= 0, so
    |f - c| only grows: the pull is at the com, the part spins freely and no point of
    it is farther than L from c)."""
    body = sim.sp.body
    c = body.local_to_world(scene.workpiece.com)
    v = body.velocity
    fx, fy = (math.cos(sim.direction), math.sin(sim.direction))
    reach = sim.sp.length_scale * (1.0 + SIM_CONTACT_BAND + SIM_SLOP)  # the engine's pins
    for f in scene.fixels:
        dx, dy = f.position[0] - c.x, f.position[1] - c.y
        if math.hypot(dx, dy) <= reach + f.radius or dx * v.x + dy * v.y > 0 \
                or dx * fx + dy * fy > 0:
            return False
    return True


def constant_tilt(scene, degrees: float, target=TARGET) -> Outcome:
    """The part under one tilt from the scene's pose (nominal model): first run until it
    is gone (then it is not seated) or for as long as a plan may run; if it is not gone,
    the verdict is ``plan.trace``'s for the one-tilt plan."""
    phi = math.radians(degrees)
    sim = Simulation(scene, Actuator(), phi)
    band = SIM_CONTACT_BAND * sim.sp.length_scale
    touching = {i for i, c in enumerate(scene.in_contact) if c}
    reached: list[int] = []
    while sim.t < (SEGMENT_TIMEOUT + HOLD_LIMIT) * sim.sp.time_scale:
        sim.step()
        for i, g in enumerate(sim.gaps()):
            if i not in touching and g <= band:
                touching.add(i)
                reached.append(i + 1)
        if gone(sim, scene):
            return Outcome(degrees, False, tuple(reached), True)
    run = trace(scene, one_tilt_plan(scene, phi, target), None, record_every=0)[0]
    return Outcome(degrees, run.success, run.events, False)


def scan(scene) -> list[Outcome]:
    """Every constant tilt, SCAN_STEP degrees apart over the full circle."""
    return [constant_tilt(scene, d) for d in range(-180, 180, SCAN_STEP)]


def summarise(outcomes: list[Outcome]) -> dict[str, list[tuple[float, float]]]:
    """Consecutive tilts with the same fate, as (first, last) degree ranges."""
    out: dict[str, list[tuple[float, float]]] = {}
    for o in outcomes:
        f = "seated" if o.seated else SWINGS if 2 in o.reached else NEVER
        runs = out.setdefault(f, [])
        if runs and runs[-1][1] == o.direction_deg - SCAN_STEP:
            runs[-1] = (runs[-1][0], o.direction_deg)
        else:
            runs.append((o.direction_deg, o.direction_deg))
    return out


def summary_lines(summary: dict[str, list[tuple[float, float]]]) -> list[str]:
    """The summary as docs/planning.md quotes it, one line per fate."""
    return [f"* {fate}: " + ", ".join(f"{lo:g} .. {hi:g}" for lo, hi in ranges)
            for fate, ranges in summary.items()]


if __name__ == "__main__":
    print("\n".join(summary_lines(summarise(scan(load_scene(TBAR))))))
    sys.exit(0)
