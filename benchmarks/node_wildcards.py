"""Heavy requests beside cheap ones against the node program (issue 11, bounded work).

The node runs in its own process (``python -m wrenchcone_ros.node``) on 8 fixels touching
a disc's rim, every fixel in contact, with ``max_concrete_modes`` raised to 100,000 so
that the wildcards below pass the count limit and meet the time budget
(``max_request_time``, default 0.05 s) instead. One thread sends the heavy requests one
after another (check_wrench "cccccccc", "********", "cccccccn", "******nn", then a
classify_wrench in the slow lane); the main thread meanwhile calls a cheap check_wrench
("nnnnnnnn") in a loop. Reported: each heavy request's status and round trip, the cheap
checks' median and maximum round trip (what the heavy ones cost the others), and the
node's exit code and whether its log has a traceback after Ctrl-C.

Usage (install/setup.bash sourced): python benchmarks/node_wildcards.py [--json FILE]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import tempfile
import threading
import time

os.environ.setdefault("ROS_DOMAIN_ID", str(1 + (os.getpid() + 40) % 100))
os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")

import rclpy  # noqa: E402
import yaml  # noqa: E402
from node_stream import NodeProcess, call_and_wait, pstats  # noqa: E402
from rclpy.node import Node  # noqa: E402

from wrenchcone_ros.node.executors import SpinThread  # noqa: E402
from wrenchcone_ros.node.status import STATUS_NAMES  # noqa: E402
from wrenchcone_ros.srv import CheckWrench, ClassifyWrench  # noqa: E402

RIM = {"workpiece": {"mass": 1.0, "inertia": 0.5, "com": [0.0, 0.0],
                     "shape": {"type": "disc", "radius": 1.0}},
       "friction": 0.3,
       "fixels": [[math.cos(2 * math.pi * k / 8), math.sin(2 * math.pi * k / 8)]
                  for k in range(8)]}
HEAVY = ("cccccccc", "********", "cccccccn", "******nn")
CHEAP = "nnnnnnnn"


def check(mode: str) -> CheckWrench.Request:
    req = CheckWrench.Request()
    req.mode = mode
    req.wrench.force.y = 1.0
    return req


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", default=None)
    args = ap.parse_args()
    path = tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False).name
    with open(path, "w") as f:
        yaml.safe_dump(RIM, f)
    ns = f"/wild{os.getpid()}"
    node = NodeProcess(ns, ["-p", f"scene_file:={path}", "-p", "max_concrete_modes:=100000",
                            "-p", "input_timeout:=0.0", "-p", f"modes:=['{CHEAP}']"])
    rclpy.init()
    client = Node("wildcard_client", namespace=ns)
    spinner = SpinThread([client], client.get_logger(), "wildcard-client")
    chk = client.create_client(CheckWrench, "wrenchcone/check_wrench")
    cls = client.create_client(ClassifyWrench, "wrenchcone/classify_wrench")
    for c in (chk, cls):
        if not c.wait_for_service(timeout_sec=30):
            raise RuntimeError(f"{c.srv_name} not available")
    heavy: dict[str, tuple[float, object]] = {}

    def heavy_calls() -> None:
        for mode in HEAVY:
            heavy[mode] = call_and_wait(chk, check(mode), 60.0)
        req = ClassifyWrench.Request()
        req.wrench.force.y = 1.0
        heavy["classify_wrench"] = call_and_wait(cls, req, 60.0)

    thread = threading.Thread(target=heavy_calls)
    started = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    thread.start()
    cheap = []
    while thread.is_alive():
        cheap.append(call_and_wait(chk, check(CHEAP), 60.0)[0])
    thread.join()
    spinner.stop()
    client.destroy_node()
    rclpy.shutdown()
    node.proc.send_signal(2)  # Ctrl-C: the program must end cleanly
    code = node.proc.wait(30)
    log = node.log_text()
    out = {"started": started, "load_average_end": os.getloadavg(),
           "heavy": {m: {"status": STATUS_NAMES[r.status], "ms": 1e3 * s,
                         "message": r.message[:120]} for m, (s, r) in heavy.items()},
           "cheap_ms": pstats(cheap), "node_exit_code": code,
           "traceback": "Traceback" in log}
    for m, h in out["heavy"].items():
        print(f"{m}: {h['status']} in {h['ms']:.1f} ms")
    c = out["cheap_ms"]
    print(f"cheap checks beside them: n={c['n']} median {c['median']:.2f} ms "
          f"max {c['max']:.2f} ms")
    print(f"node exit code {code}, traceback in its log: {out['traceback']}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
