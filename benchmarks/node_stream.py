# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The node under a pose stream, as a controller back end uses it.

The node runs in its OWN process (``python -m wrenchcone_ros.node``, its executors and
publishing worker, as deployed; ``harness.ros.NodeProcess``); this process publishes poses at a fixed
rate (100 Hz, 1 kHz), calls check_wrench at 100 Hz from another thread, and listens to
the monitored cone topics, for 1, 4 and 16 monitored modes of a square on two pins (17
feasible modes). Measured, per configuration:

* ``pose_age``: for each check_wrench reply, how much older the pose it used (its
  ``pose_stamp``) is than the newest pose sent when the request was sent (0 if newer);
* ``check``: check_wrench round trip, and ``trigger``: an empty std_srvs/Trigger service
  in a third process, called alternately with check_wrench (the floor of any service
  call on this machine at that moment);
* ``F_lag``: for each pose sent, the time until a published F that reflects it or a newer
  pose arrives (the F of the alphabetically last monitored mode, published last; a
  message is matched to its pose by its rows: the stream cycles through 100 poses with
  distinct cones);
* ``accepted``: poses/s the node took (``inputs_version`` rises per snapshot used, so
  this counts distinct poses seen by the replies, not a queue);
* node CPU (% of one core) and resident memory (MB) at start and end of the stream;
* with ``--decompose``: each check_wrench round trip split at the node's callback (the
  node then runs as benchmarks/harness/instrumented_node.py, which records each
  callback's start and end on CLOCK_MONOTONIC through the node's ``on_request`` hook): ``to_callback`` (client send, DDS, the node's executor
  taking the request), ``callback`` (the node's Python handler), ``back`` (the node
  sending the reply, DDS, the client's executor) and ``wake`` (the client's waiting
  thread resuming). The Trigger's round trip has the same parts but an empty callback.

With ``--listener process`` the cone topic is heard by a process of its own instead of
the measuring one (which otherwise takes hundreds of cone messages a second under the
same GIL as the calls it times).

Usage: python benchmarks/node_stream.py [--seconds 10] [--json FILE] [--decompose]
       [--listener inprocess|process]
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable

import harness
from harness.ros import (
    CYCLE,
    SQUARE,
    STEP,
    NodeProcess,
    conv,
    feasible_modes,
    scene_file,
    spin,
    start_pose_stream,
    start_trigger_server,
    wait_for_services,
)
from harness.watch import watch_gc, watch_pauses

import numpy as np
import rclpy
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from std_srvs.srv import Trigger

from wrenchcone_ros.core import load_scene, wrench_cone
from wrenchcone_ros.node import CONE_QOS
from wrenchcone_msgs.msg import WrenchCone
from wrenchcone_msgs.srv import CheckWrench

LISTENER_QOS = {"reliable": CONE_QOS,
                "best_effort": QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT)}


def _key(data) -> bytes:
    return np.round(np.asarray(data, dtype=float), 7).tobytes()


def message_key(msg) -> bytes:
    """The rows a published cone message (WrenchCone) carries."""
    return _key(list(msg.inequalities) + [np.inf] + list(msg.equalities))


def cone_key(cone) -> bytes:
    """The same key for a core Cone."""
    return _key(list(conv.rows_flat(cone.F)) + [np.inf] + list(conv.rows_flat(cone.equalities)))


def listen(ns: str, mode: str, out: str) -> None:
    """``--listen``: subscribe to ``<ns>/wrenchcone/cone/<mode>`` in this process and,
    when stdin closes, write every arrival as [wall time s, message key hex] and this
    process's pauses to ``out`` (JSON). The measuring process then matches them as it
    does its own arrivals."""
    rclpy.init()
    node = Node("stream_cone_listener", namespace=ns)
    arrivals: list[tuple[float, str]] = []
    node.create_subscription(
        WrenchCone, f"wrenchcone/cone/{mode}",
        lambda msg: arrivals.append((time.time_ns() * 1e-9, message_key(msg).hex())),
        CONE_QOS)
    spinner = spin([node], "stream-cone-listener")
    while node.count_publishers(f"wrenchcone/cone/{mode}") == 0:  # discovery
        time.sleep(0.05)
    watch_pauses(CLIENT_PAUSES)
    print("ready", flush=True)
    sys.stdin.read()  # until the measuring process closes it
    spinner.stop()
    with open(out, "w") as f:
        json.dump({"arrivals": arrivals, "pauses": CLIENT_PAUSES}, f)
    node.destroy_node()
    rclpy.try_shutdown()


def decomposition(client: list[tuple[float, float, float]], requests: list) -> dict:
    """The parts of each check_wrench round trip (ms): client (send, future done, thread
    resumed) against the node's callback (start, end; the node's ``on_request`` records,
    harness/instrumented_node.py), matched in order (one call at a time); the 8 slowest
    round trips in full."""
    node = [(a, b) for service, a, b in requests if service == "check_wrench"]
    n = min(len(node), len(client))
    if n == 0:
        return {}
    c, s = np.array(client[:n]), np.array(node[:n])
    parts = {"to_callback": s[:, 0] - c[:, 0], "callback": s[:, 1] - s[:, 0],
             "back": c[:, 1] - s[:, 1], "wake": c[:, 2] - c[:, 1],
             "total": c[:, 2] - c[:, 0]}
    out: dict = {k: harness.summary(v, 1e3) for k, v in parts.items()}
    out["slowest"] = [{k: round(float(v[i]) * 1e3, 2) for k, v in parts.items()}
                      for i in np.argsort(parts["total"])[-8:]]
    return out


def probe_program() -> str:
    """The installed wrenchcone_probe (src/probe.c): check_wrench and Trigger round trips
    from a compiled rcl client."""
    from ament_index_python.packages import get_package_prefix

    return os.path.join(get_package_prefix("wrenchcone_ros"), "lib", "wrenchcone_ros",
                        "wrenchcone_probe")


def read_probe(path: str) -> tuple[list, list[float]]:
    """wrenchcone_probe's lines as (replies, triggers) in run_config's layout: replies
    (round trip s, sent ns, pose stamp ns, inputs_version), or Nones when unanswered."""
    replies, triggers = [], []
    with open(path) as f:
        next(f)  # the header
        for line in f:
            kind, *numbers = line.split()
            sent, rtt, _status, _consistent, stamp, version = map(int, numbers)
            if kind == "trigger":
                if rtt >= 0:
                    triggers.append(rtt * 1e-9)
            elif rtt < 0:
                replies.append((None, None, None, None))
            else:
                replies.append((rtt * 1e-9, sent, stamp, version))
    return replies, triggers


def run_config(path: str, modes: list[str], rate_hz: float, seconds: float,
               expected: dict, node_args: list[str] = (), decompose: bool = False,
               caller_kind: str = "thread", listener: str = "inprocess",
               watch: bool = False, cone_qos: str = "reliable",
               executor: str = "lane") -> dict:
    ns = f"/stream{os.getpid()}"
    watch_file = (tempfile.NamedTemporaryFile(suffix=".json", delete=False).name
                  if watch or decompose else None)
    node = NodeProcess(ns, ["-p", f"scene_file:={path}", "-p", f"modes:={modes!r}",
                            "-p", "input_timeout:=0.0", *node_args], watch_file, executor)
    client = Node("stream_client", namespace=ns)
    cli = client.create_client(CheckWrench, "wrenchcone/check_wrench")
    trigger_proc = start_trigger_server(ns)
    trigger_cli = client.create_client(Trigger, "trigger")
    watched = modes[-1]
    arrivals: list[tuple[float, int | None]] = []  # (t, cycle index of the F)
    table = {key: i for i, key in enumerate(expected[watched])}

    def on_cone(msg) -> None:
        t = time.time_ns() * 1e-9
        arrivals.append((t, table.get(message_key(msg))))

    listener_proc = listener_file = None
    listener_pauses: list = []  # the listener process's own pauses (--listener process)
    if listener == "inprocess":
        client.create_subscription(WrenchCone, f"wrenchcone/cone/{watched}", on_cone,
                                   LISTENER_QOS[cone_qos])
    else:  # the F lag measured in a process of its own (see --listener)
        listener_file = tempfile.NamedTemporaryFile(suffix=".json", delete=False).name
        listener_proc = subprocess.Popen(
            [sys.executable, os.path.abspath(__file__), "--listen", ns, watched,
             listener_file], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        listener_proc.stdout.readline()  # "ready": subscribed and matched
    # the measuring client spins on the same executor kind as the node (executors.py):
    # on a 2-core machine a MultiThreadedExecutor client was itself the bottleneck
    # (its empty Trigger calls had a p99 of 100+ ms)
    spinner = spin([client], "stream-client")
    wait_for_services(cli, trigger_cli)
    if caller_kind == "compiled":  # wrenchcone_probe: the same alternating calls
        probe_file = tempfile.NamedTemporaryFile(suffix=".txt", delete=False).name
        probe = subprocess.Popen(
            [probe_program(), "--mode", modes[0], "--wrench", "0,1,0", "--rate", "100",
             "--seconds", "3600", "--wait-for-signal", "--service",
             f"{ns}/wrenchcone/check_wrench", "--trigger", f"{ns}/trigger",
             "--out", probe_file], stderr=subprocess.PIPE, text=True)
        probe.stderr.readline()  # "ready": both services found
    stop = threading.Event()
    stream_file = tempfile.NamedTemporaryFile(suffix=".json", delete=False).name
    pub_proc = start_pose_stream(ns, rate_hz, seconds, stream_file)  # it starts now

    replies = []  # (round trip s, pose age s, inputs_version)
    triggers = []  # round trip s of the empty service, interleaved with check_wrench
    times = []  # (sent, future done, thread resumed): perf_counter s, for --decompose

    def caller() -> None:
        g = conv.planar_to_wrench((0.0, 1.0, 0.0))
        while not stop.is_set():
            done = threading.Event()
            t0 = time.perf_counter()
            fut = trigger_cli.call_async(Trigger.Request())
            fut.add_done_callback(lambda _f, ev=done: ev.set())
            if done.wait(5):
                triggers.append(time.perf_counter() - t0)
            sent_ns = time.time_ns()
            done = threading.Event()
            t0 = time.perf_counter()
            fut = cli.call_async(CheckWrench.Request(mode=modes[0], wrench=g))
            done_at = []
            fut.add_done_callback(
                lambda _f, ev=done, at=done_at: (at.append(time.perf_counter()), ev.set()))
            if not done.wait(5):
                replies.append((None, None, None, None))
                continue
            rt = time.perf_counter() - t0
            times.append((t0, done_at[0], t0 + rt))
            r = fut.result()
            used = r.pose_stamp.sec * 10**9 + r.pose_stamp.nanosec
            replies.append((rt, sent_ns, used, r.inputs_version))
            time.sleep(max(0.0, 0.01 - rt))  # about 100 Hz of each

    def chained() -> Callable[[], None]:
        """The same alternating calls, made from the client's executor: a 200 Hz timer
        sends the next call when none is in flight, and the reply's done callback (on
        the spin thread) records the round trip; no other thread waits for a reply."""
        g = conv.planar_to_wrench((0.0, 1.0, 0.0))
        state = {"busy": False, "next": "trigger"}

        def on_trigger(_fut, t0: float) -> None:
            triggers.append(time.perf_counter() - t0)
            state["busy"] = False

        def on_check(fut, t0: float, sent_ns: int) -> None:
            t = time.perf_counter()
            r = fut.result()
            used = r.pose_stamp.sec * 10**9 + r.pose_stamp.nanosec
            replies.append((t - t0, sent_ns, used, r.inputs_version))
            times.append((t0, t, t))
            state["busy"] = False

        def tick() -> None:
            if state["busy"] or stop.is_set():
                return
            state["busy"] = True
            t0 = time.perf_counter()
            if state["next"] == "trigger":
                state["next"] = "check"
                trigger_cli.call_async(Trigger.Request()).add_done_callback(
                    lambda f, t0=t0: on_trigger(f, t0))
            else:
                state["next"] = "trigger"
                sent_ns = time.time_ns()
                t0 = time.perf_counter()
                cli.call_async(CheckWrench.Request(mode=modes[0], wrench=g)).add_done_callback(
                    lambda f, t0=t0, s=sent_ns: on_check(f, t0, s))

        timer = client.create_timer(0.005, tick)
        return timer.cancel

    cpu0, rss0, t0, t_wall0 = node.cpu_s(), node.rss_mb(), time.perf_counter(), time.time()
    if caller_kind == "thread":
        call_thread = threading.Thread(target=caller)
        call_thread.start()
    elif caller_kind == "compiled":
        os.kill(probe.pid, signal.SIGUSR1)  # start calling now
    else:
        cancel = chained()
    pub_proc.proc.wait()
    elapsed = time.perf_counter() - t0  # the stream's length: the rate and CPU are per it
    t_wall1 = time.time()
    cpu1, rss1 = node.cpu_s(), node.rss_mb()
    stop.set()
    if caller_kind == "thread":
        call_thread.join()
    elif caller_kind == "compiled":
        probe.send_signal(signal.SIGINT)  # ends after the call in flight
        probe.communicate(timeout=60)
        probe_replies, triggers[:] = read_probe(probe_file)
        replies.extend(probe_replies)
        os.unlink(probe_file)
    else:
        cancel()
        time.sleep(0.1)  # the call in flight, if any
    time.sleep(0.6 if watch_file else 0.3)  # the watched node writes every 0.5 s
    spinner.stop()
    client.destroy_node()
    node.stop()
    trigger_proc.stop(signal.SIGTERM)
    if listener_proc is not None:
        listener_proc.communicate(timeout=30)  # closes its stdin: it writes and ends
        with open(listener_file) as f:
            heard = json.load(f)
        arrivals.extend((t, table.get(bytes.fromhex(key))) for t, key in heard["arrivals"])
        listener_pauses = heard["pauses"]
        os.unlink(listener_file)
    # the publisher's records: the stamps sent, and (wall s, ms) its publish() calls over
    # 15 ms ("stalls") and late wake-ups ("pauses")
    with open(stream_file) as f:
        publisher = json.load(f)
    os.unlink(stream_file)
    sent_ns_all = np.array(publisher["stamps"], dtype=np.int64)
    node_watch, requests = {}, []
    if watch_file is not None:
        with open(watch_file) as f:  # what the node recorded during the stream
            recorded = json.load(f)
        requests = recorded.pop("requests")
        node_watch = {k: [x for x in v if t_wall0 <= x[0] <= t_wall1]
                      for k, v in recorded.items()}
        # an idle interval is stamped at its start: only those that ended in the stream
        # (the last one before the node's end is the stream's end, not a stall)
        node_watch["idle"] = [x for x in node_watch.get("idle", [])
                              if x[0] + x[1] * 1e-3 <= t_wall1]
        os.unlink(watch_file)
    sent = [(t * 1e-9, t) for t in sent_ns_all]  # (wall s, stamp ns)

    # F lag: match each F to the pose index it reflects (the newest index sent before its
    # arrival with its cycle position), then for each pose j the first arrival whose
    # running-max index is >= j
    sent_t = np.array([t for t, _ in sent])
    arr = [(t, k) for t, k in arrivals if k is not None]
    lags = []
    if arr and sent:
        t_arr = np.array([t for t, _ in arr])
        newest = np.searchsorted(sent_t, t_arr) - 1
        idx = newest - ((newest - np.array([k for _, k in arr])) % CYCLE)
        runmax = np.maximum.accumulate(idx)
        first = np.searchsorted(runmax, np.arange(len(sent)))
        covered = first < len(arr)
        lags = list(t_arr[first[covered]] - sent_t[covered])
    ok = [r for r in replies if r[0] is not None]
    versions = {r[3] for r in ok}
    ages = []
    for _rt, sent_at, used, _v in ok:  # newest pose sent before the request vs used
        k = np.searchsorted(sent_ns_all, sent_at, side="right") - 1
        if k >= 0 and used:
            ages.append(max(0, int(sent_ns_all[k]) - used) * 1e-9)
    parts = {}
    if decompose and len(replies) == len(times):  # every call answered: the orders match
        parts = decomposition(times, requests)
    return {
        "check_parts_ms": parts,
        "modes": len(modes), "rate_hz": rate_hz, "seconds": elapsed,
        "poses_sent": len(sent), "sent_rate_hz": len(sent) / elapsed,
        "replies": len(ok), "unanswered": len(replies) - len(ok),
        "pose_age_ms": harness.summary(ages, 1e3),
        "check_ms": harness.summary([r[0] for r in ok], 1e3),
        "trigger_ms": harness.summary(triggers, 1e3),
        "F_lag_ms": harness.summary(lags, 1e3), "F_messages": len(arrivals),
        # when the worst moments were (wall clock s): the longest silence of the cone
        # topic and the slowest check_wrench, to match with other processes' records
        "F_longest_gap": longest_gap([t for t, _ in arrivals if t_wall0 <= t <= t_wall1]),
        "check_slowest": (max(((r[0] * 1e3, r[1] * 1e-9) for r in ok), default=None)),
        "client_gc_pauses": [x for x in CLIENT_GC if t_wall0 <= x[0] <= t_wall1],
        "publisher_stalls": publisher["stalls"], "node_watch": node_watch,
        "client_pauses": [x for x in CLIENT_PAUSES if t_wall0 <= x[0] <= t_wall1],
        "publisher_pauses": publisher["pauses"],
        "listener_pauses": [x for x in listener_pauses if t_wall0 <= x[0] <= t_wall1],
        "F_unmatched": sum(1 for _t, k in arrivals if k is None),
        "F_poses_covered": len(lags), "distinct_versions_seen": len(versions),
        "node_cpu_pct": 100 * (cpu1 - cpu0) / elapsed,
        "node_rss_mb": [rss0, rss1],
    }


#: (wall s at the end, generation, ms): this process's collections over 5 ms
CLIENT_GC: list[tuple[float, int, float]] = []
watch_gc(CLIENT_GC)
#: (wall s, ms): this process held up (harness.watch.watch_pauses), so what it timed then
#: includes that
CLIENT_PAUSES: list[tuple[float, float]] = []


def longest_gap(times: list[float]) -> dict | None:
    """The longest interval between consecutive arrivals: its length (ms) and its end
    (wall clock s)."""
    if len(times) < 2:
        return None
    t = np.sort(np.asarray(times))
    k = int(np.argmax(np.diff(t)))
    return {"ms": float(t[k + 1] - t[k]) * 1e3, "ended_at": float(t[k + 1])}


def expected_cones(modes: list[str]) -> dict:
    scene = load_scene(SQUARE)
    out = {}
    for m in modes:
        out[m] = [cone_key(wrench_cone(scene.with_pose(STEP * k, 0.0, 0.0), m))
                  for k in range(CYCLE)]
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seconds", type=float, default=10.0, help="stream length per config")
    ap.add_argument("--rates", type=float, nargs="+", default=[100.0, 1000.0])
    ap.add_argument("--modes", type=int, nargs="+", default=[1, 4, 16])
    ap.add_argument("--json", help="also write the results to this file")
    ap.add_argument("--caller", choices=["thread", "callbacks", "compiled"],
                    default="thread",
                    help="thread: a client thread calls and waits for each reply (the "
                         "default, as all earlier figures); callbacks: the calls are made "
                         "and timed on the client's executor (no thread wake-up in the "
                         "round trip); compiled: by wrenchcone_probe, a compiled rcl "
                         "client in a process of its own, as a C++ controller would call")
    ap.add_argument("--decompose", action="store_true",
                    help="split each check_wrench round trip at the node's Python "
                         "callback")
    ap.add_argument("--listener", choices=["inprocess", "process"], default="inprocess",
                    help="inprocess: the cone topic is heard by the measuring process, "
                         "which also makes the calls (the default, as all earlier "
                         "figures); process: by a process of its own, so that hundreds of "
                         "cone messages a second do not share the caller's GIL")
    ap.add_argument("--watch", action="store_true",
                    help="run the node as benchmarks/harness/instrumented_node.py, which "
                         "records its own pauses (a thread woken > 50 ms late), worker "
                         "steps > 15 ms, idle intervals > 50 ms and long garbage "
                         "collections during the stream (node_watch in the JSON)")
    ap.add_argument("--cone-qos", choices=sorted(LISTENER_QOS), default="reliable",
                    help="the in-process cone listener's QoS: reliable (the node's "
                         "CONE_QOS, the default) or best_effort (depth 1, volatile: the "
                         "newest cone without waiting for a lost one to be repaired)")
    ap.add_argument("--listen", nargs=3, metavar=("NS", "MODE", "OUT"),
                    help=argparse.SUPPRESS)  # the listener process itself
    ap.add_argument("--executors", nargs="+", default=["lane"],
                    choices=["lane", "multi_threaded", "single_threaded"],
                    help="the executors the node program spins the node on "
                         "(harness/node_program.py), each configuration run once per "
                         "executor, interleaved: lane (the program's default), rclpy's "
                         "multi_threaded (4 threads) and single_threaded")
    ap.add_argument("--repeat", type=int, default=1,
                    help="run every configuration this many times, interleaved")
    ap.add_argument("--node-args", default="", type=str.split,
                    help="extra node arguments in one string, e.g. "
                         "'-p publish_markers:=false -p diagnostics_rate:=0.0'")
    args = ap.parse_args()
    if args.listen:
        listen(*args.listen)
        return 0
    feasible = feasible_modes(SQUARE)
    facts = harness.machine_facts()
    rclpy.init()
    watch_pauses(CLIENT_PAUSES)
    results = []
    try:
        with scene_file(SQUARE) as path:
            for n in args.modes:
                modes = sorted(feasible[:n])
                expected = expected_cones([modes[-1]])
                for rate in args.rates:
                    for _ in range(args.repeat):
                        for kind in args.executors:
                            r = run_config(path, modes, rate, args.seconds, expected,
                                           args.node_args, args.decompose, args.caller,
                                           args.listener, args.watch, args.cone_qos, kind)
                            r["executor"] = kind
                            results.append(r)
    finally:
        rclpy.try_shutdown()
    print(harness.header_line(facts, harness.loadavg(), f"{args.seconds:g} s per row",
                              f"caller {args.caller}",
                              f"listener {args.listener}"))
    print()
    print("| executor | modes | rate Hz | poses sent/s | pose age p50 / p99 ms | check_wrench p50 / "
          "p99 ms | empty Trigger p50 / p99 ms | F lag p50 / p99 ms | F msgs | node CPU % | "
          "node RSS MB start -> end |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    nan = float("nan")
    for r in results:
        pa, ck, fl, tr = r["pose_age_ms"], r["check_ms"], r["F_lag_ms"], r["trigger_ms"]
        print(f"| {r['executor']} | {r['modes']} | {r['rate_hz']:g} | "
              f"{r['sent_rate_hz']:.0f} | "
              f"{pa.get('median', nan):.2f} / {pa.get('p99', nan):.2f} | "
              f"{ck.get('median', nan):.2f} / {ck.get('p99', nan):.2f} | "
              f"{tr.get('median', nan):.2f} / {tr.get('p99', nan):.2f} | "
              f"{fl.get('median', nan):.2f} / {fl.get('p99', nan):.2f} | "
              f"{r['F_messages']} | {r['node_cpu_pct']:.0f} | "
              f"{r['node_rss_mb'][0]:.0f} -> {r['node_rss_mb'][1]:.0f} |")
    print()
    print("Stalls during the stream (wall-clock matched): the pose publisher's publish() "
          "over 15 ms, this process's garbage collections over 5 ms and its pauses (a "
          "thread woken over 50 ms late), and with --watch the "
          "node's own pauses over 50 ms, worker steps over 15 ms and collections over 5 ms "
          "(count, longest ms):")
    for r in results:
        cells = [("publisher", [x[1] for x in r["publisher_stalls"]]),
                 ("publisher pauses", [x[1] for x in r["publisher_pauses"]]),
                 ("listener pauses", [x[1] for x in r["listener_pauses"]]),
                 ("client gc", [x[2] for x in r["client_gc_pauses"]]),
                 ("client pauses", [x[1] for x in r["client_pauses"]])]
        cells += [(f"node {k}", [x[-1] if k == "gc" else x[1] for x in v])
                  for k, v in r["node_watch"].items()]
        print(f"- {r['modes']} modes, {r['rate_hz']:g} Hz: " + "; ".join(
            f"{name} {len(v)}" + (f" ({max(v):.0f})" if v else "") for name, v in cells))
    if args.decompose:
        print()
        print("| modes | rate Hz | check_wrench p50 / p99 ms: to callback | callback | back "
              "| wake | total |")
        print("| --- | --- | --- | --- | --- | --- | --- |")
        for r in results:
            p = r["check_parts_ms"]
            if not p:
                continue
            cells = " | ".join(f"{p[k]['median']:.2f} / {p[k]['p99']:.2f}" for k in (
                "to_callback", "callback", "back", "wake", "total"))
            print(f"| {r['modes']} | {r['rate_hz']:g} | {cells} |")
    harness.write_json(args.json, facts, {
        "caller": args.caller, "listener": args.listener, "cone_qos": args.cone_qos,
        "watch": args.watch, "results": results})
    return 0


if __name__ == "__main__":
    sys.exit(main())
