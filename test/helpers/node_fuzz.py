# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Seeded mixed-input fuzzing of a live node (used by test_node_fuzz.py and by
benchmarks/node_fuzz.py for the long run).

Each step is one of: a parameter set (any declared name, or a made-up one, with a value
drawn from good values, NaN, inf, 1e200, ints, wrong types, long strings, big arrays), a
pose or fixture message (a Fixels message with good and absurd radii, friction and names,
or a PoseArray on fixel_poses; NaN, wrong frame, huge, older stamps), or a request
(check_wrench with or without classify, get_cone, classify_wrench) with a random mode
(letters, wildcards, wrong lengths, long strings) and a random wrench. Requests are
answered synchronously, so every published message is followed by requests that can see
it. The run records every reply status and counts replies that never came.
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass, field

import numpy as np
from geometry_msgs.msg import Pose, PoseArray, PoseStamped
from rcl_interfaces.srv import SetParameters
from rclpy.parameter import Parameter

from wrenchcone_ros.ros import conversions as conv
from wrenchcone_ros.node import PARAMETERS
from wrenchcone_msgs.msg import Fixel, Fixels, Status
from wrenchcone_msgs.srv import CheckWrench, ClassifyWrench, GetCone

WILD = [math.nan, math.inf, -math.inf, 1e200, -1e200, 1e-300, 0.0, -1.0, 1e9, 1e10]
LETTERS = "aslrnc*xyz?"
#: Parameter values a fuzz step may set (valid ones are kept small: a limit of 10^7 would
#: let one wildcard request run for minutes, which the limits exist to prevent).
GOOD = {
    "fixture_frame": ["world", "world"], "workpiece.mass": [1.0, 2.5, 0.1],
    "workpiece.inertia": [1.0, 0.5], "workpiece.com": [[0.0, 0.0], [0.1, -0.2]],
    "workpiece.shape": ["disc", "polygon"], "workpiece.radius": [1.0, 0.5],
    "workpiece.vertices": [[-1.0, -1.0, 1.0, -1.0, 1.0, 1.0, -1.0, 1.0],
                           [0.0, 0.0, 1.0, 0.0, 0.0, 1.0]],
    "friction": [0.2, 0.0, 1.0, 1], "contact_tolerance": [1e-9, 1e-3],
    "fixel_radius": [[], [0.0], [0.05], [0.0, 0.01]], "uncertainty.friction": [
        [], [0.2, 0.4], [0.1, 0.2, 0.3, 0.4]], "modes": [["na"], ["na", "ns"], [], ["nnnn"]],
    "tilt_tolerance": [1e-4], "out_of_plane_tolerance": [1e-6], "wait_for_inputs": [False],
    "input_timeout": [0.0, 0.0, 5.0], "fixels_timeout": [0.0], "max_fixels": [32, 8],
    "max_mode_length": [64, 8], "max_concrete_modes": [64, 16],
    "max_classify_nodes": [2000, 50],
}


@dataclass
class FuzzResult:
    steps: int = 0
    statuses: Counter = field(default_factory=Counter)  # (service, status) -> count
    unanswered: int = 0
    internal_errors: list = field(default_factory=list)
    parameter_sets: Counter = field(default_factory=Counter)  # accepted/refused


def _rand_float(rng: np.random.Generator) -> float:
    r = rng.random()
    if r < 0.3:
        return float(rng.choice(WILD))
    if r < 0.6:
        return float(rng.normal() * 2)
    return float(rng.uniform(-1.5, 1.5))


def _rand_value(rng: np.random.Generator, name: str):
    r = rng.random()
    if r < 0.45 and name in GOOD:
        options = GOOD[name]
        return options[int(rng.integers(len(options)))]
    kind = int(rng.integers(9))
    if kind == 0:
        return _rand_float(rng)
    if kind == 1:
        return int(rng.choice([0, -1, 1, 3, 10**12, -(2**62)]))
    if kind == 2:
        return "x" * int(rng.choice([0, 1, 231, 5000]))
    if kind == 3:
        return [_rand_float(rng) for _ in range(int(rng.choice([0, 1, 2, 6, 8, 1000])))]
    if kind == 4:
        return ["".join(rng.choice(list(LETTERS), size=int(rng.integers(0, 300))))
                for _ in range(int(rng.choice([1, 2, 70])))]
    if kind == 5:
        return bool(rng.integers(2))
    if kind == 6:
        return [int(v) for v in rng.integers(-5, 5, size=int(rng.choice([2, 6, 8])))]
    if kind == 7:
        return ["n" * int(rng.integers(1, 9))]
    return "polygon" if rng.random() < 0.5 else "disc"


def _param_msg(name: str, value):
    try:
        return Parameter(name, value=value).to_parameter_msg()
    except Exception:  # noqa: BLE001 - a value rclpy cannot even represent: skip it
        return None


def _mode(rng: np.random.Generator) -> str:
    r = rng.random()
    if r < 0.1:
        return "".join(rng.choice(list(LETTERS), size=int(rng.choice([100, 10_000]))))
    n = int(rng.choice([0, 1, 2, 2, 2, 3, 4, 8]))
    letters = "aslrn" if rng.random() < 0.6 else LETTERS
    return "".join(rng.choice(list(letters), size=n))


def _wrench(rng: np.random.Generator, req) -> None:
    w = req.wrench
    w.force.x, w.force.y, w.torque.z = (_rand_float(rng) for _ in range(3))
    if rng.random() < 0.2:
        w.force.z, w.torque.x, w.torque.y = (_rand_float(rng) for _ in range(3))


def _positions(rng: np.random.Generator) -> list[tuple[float, float]]:
    r = rng.random()
    if r < 0.65:  # touching the unit disc: interesting contact scenes
        n = int(rng.integers(1, 6))
        return [(math.cos(a), math.sin(a)) for a in rng.uniform(0, 2 * math.pi, n)]
    if r < 0.72:
        return [(2.0 + 0.01 * k, 0.0) for k in range(int(rng.choice([40, 1000, 5000])))]
    if r < 0.75:
        return []
    n = int(rng.integers(1, 5))
    return [(_rand_float(rng), _rand_float(rng)) for _ in range(n)]


def run_fuzz(h, n_steps: int, seed: int) -> FuzzResult:
    """Drive harness ``h`` (node_harness.Harness) through ``n_steps`` fuzz steps."""
    rng = np.random.default_rng(seed)
    res = FuzzResult()
    stamp = 1
    names = list(PARAMETERS) + ["no_such_parameter", "use_sim_time"]
    for _ in range(n_steps):
        res.steps += 1
        kind = rng.random()
        if kind < 0.12:  # parameters: one, or a few at once
            req = SetParameters.Request()
            for _k in range(int(rng.choice([1, 1, 2, 3]))):
                name = names[int(rng.integers(len(names)))]
                msg = _param_msg(name, _rand_value(rng, name))
                if msg is not None:
                    req.parameters.append(msg)
            reply = _call(h, h.param_cli, req, res)
            if reply is not None:
                for r in reply.results:
                    res.parameter_sets["accepted" if r.successful else "refused"] += 1
            continue
        if kind < 0.3:  # a pose
            msg = PoseStamped()
            msg.header.frame_id = "world" if rng.random() < 0.85 else "x" * 300
            stamp += int(rng.choice([1, 1, 1, -5]))
            msg.header.stamp.sec = max(stamp, 0)
            msg.pose.position.x, msg.pose.position.y = (
                (_rand_float(rng) * 0.01, _rand_float(rng) * 0.01) if rng.random() < 0.5
                else (_rand_float(rng), _rand_float(rng)))
            q = (conv.yaw_to_quaternion(float(rng.normal() * 0.01)) if rng.random() < 0.7
                 else tuple(_rand_float(rng) for _ in range(4)))
            (msg.pose.orientation.x, msg.pose.orientation.y, msg.pose.orientation.z,
             msg.pose.orientation.w) = q
            h.pose_pub.publish(msg)
            continue
        if kind < 0.4:  # a fixture: Fixels (radii, friction, names) or a PoseArray
            stamp += 1
            if rng.random() < 0.7:
                msg = Fixels()
                for x, y in _positions(rng):
                    f = Fixel(radius=float(rng.choice([0.0, 0.0, 0.05, _rand_float(rng)])),
                              name=str(rng.choice(["", "pin", "x" * 300])))
                    f.position.x, f.position.y = x, y
                    f.friction = float(rng.choice([Fixel.FRICTION_UNSET, 0.2, 0.5,
                                                   _rand_float(rng)]))
                    msg.fixels.append(f)
                pub = h.fixel_pub
            else:
                msg = PoseArray()
                for x, y in _positions(rng):
                    p = Pose()
                    p.position.x, p.position.y = x, y
                    msg.poses.append(p)
                pub = h.fixel_pose_pub
            msg.header.frame_id = "world" if rng.random() < 0.9 else ""
            msg.header.stamp.sec = stamp
            pub.publish(msg)
            continue
        r = rng.random()  # a request
        if r < 0.5:
            req = CheckWrench.Request(mode=_mode(rng), classify=bool(rng.random() < 0.2))
            _wrench(rng, req)
            _record(res, "check_wrench", _call(h, h.check_cli, req, res))
        elif r < 0.8:
            _record(res, "get_cone", _call(h, h.cone_cli, GetCone.Request(mode=_mode(rng)),
                                           res))
        else:
            req = ClassifyWrench.Request()
            _wrench(rng, req)
            _record(res, "classify_wrench", _call(h, h.classify_cli, req, res))
    return res


#: Unanswered requests after which a run stops (each costs the harness's deadline).
MAX_UNANSWERED = 3


def _call(h, client, request, res: FuzzResult):
    try:
        return h._call(client, request)
    except AssertionError:  # the harness's hang guard: no reply within its deadline
        res.unanswered += 1
        if res.unanswered >= MAX_UNANSWERED:  # a dead node: fail now, not after hours
            raise
        return None


def _record(res: FuzzResult, service: str, reply) -> None:
    if reply is None:
        return
    res.statuses[(service, int(reply.status))] += 1
    if reply.status == Status.INTERNAL_ERROR:
        res.internal_errors.append((service, reply.message[:200]))
