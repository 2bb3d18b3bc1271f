# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The controller authors' test kit (wrenchcone_ros.testing): isolation and clean-up."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import pytest
from rclpy.executors import MultiThreadedExecutor
from rclpy.node import Node
from wrenchcone_msgs.msg import Status

from wrenchcone_ros.core import load_scene
from wrenchcone_ros.testing import domains
from wrenchcone_ros.testing.harness import ExecutorThread, NodeFactory, isolated_context

ROOT = Path(__file__).resolve().parents[2]
DISC = ROOT / "examples" / "paper_disc.yaml"
PAWL = ROOT / "examples" / "pawl_seating.yaml"
DEADLINE_S = 60.0  # only a guard against a hang; never asserted on


def wait_until(predicate, what: str, deadline_s: float = DEADLINE_S) -> None:
    deadline = time.monotonic() + deadline_s
    while not predicate():
        assert time.monotonic() < deadline, f"never: {what}"
        time.sleep(0.02)


# --- domains --------------------------------------------------------------------------
def test_candidate_domain_ids():
    assert domains.candidate_domain_ids("") == domains.DEFAULT_DOMAIN_IDS
    assert domains.candidate_domain_ids("3, 10-12") == (3, 10, 11, 12)
    for bad in ("x", "5-", "-5", "200-240", "3,,4"):
        with pytest.raises(ValueError, match=domains.DOMAIN_IDS_ENV):
            domains.candidate_domain_ids(bad)


def test_two_leases_in_one_process_get_different_domains():
    with domains.lease_domain([150, 151]) as a, domains.lease_domain([150, 151]) as b:
        assert {a.domain_id, b.domain_id} == {150, 151}
        with pytest.raises(domains.NoFreeDomain):
            domains.lease_domain([150, 151])
    with domains.lease_domain([150]) as c:  # both given back
        assert c.domain_id == 150


HOLDER = """
import sys
from wrenchcone_ros.testing.domains import lease_domain
lease = lease_domain([int(sys.argv[1])])
print(lease.domain_id, flush=True)
sys.stdin.readline()
"""


def test_a_domain_leased_by_another_process_is_skipped_until_it_ends():
    holder = subprocess.Popen([sys.executable, "-c", HOLDER, "152"], stdin=subprocess.PIPE,
                              stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "152"
        with domains.lease_domain([152, 153]) as lease:
            assert lease.domain_id == 153
        with pytest.raises(domains.NoFreeDomain):
            domains.lease_domain([152])
    finally:
        holder.kill()  # no release: the kernel drops the lock of a dead process
        holder.wait()
    with domains.lease_domain([152]) as lease:
        assert lease.domain_id == 152


# --- contexts, nodes, teardown ----------------------------------------------------------
def test_the_context_is_on_its_domain_and_leaves_the_environment_as_it_was():
    before = dict(os.environ)
    with domains.lease_domain() as lease, isolated_context(lease.domain_id) as context:
        assert context.ok() and context.get_domain_id() == lease.domain_id
        assert dict(os.environ) == before
    assert not context.ok()


def test_closing_the_factory_leaves_no_node_and_no_thread(wrenchcone_domain_id,
                                                         wrenchcone_test_node, tmp_path):
    """What the wrenchcone_node fixture does after each test (the same NodeFactory)."""
    def listed() -> bool:
        return ("wrenchcone", "/") in wrenchcone_test_node.get_node_names_and_namespaces()

    before = set(threading.enumerate())
    factory = NodeFactory(wrenchcone_domain_id, tmp_path)
    try:
        node = factory.make(DISC)
        wait_until(listed, "the node is seen over DDS")
        assert set(threading.enumerate()) > before  # the executor's and the node's threads
    finally:
        factory.close()
    assert set(threading.enumerate()) == before
    assert not node.context.ok()
    # a destroyed node's DDS participant says goodbye at once; 20 s: a lost announcement
    wait_until(lambda: not listed(), "the node is gone from the ROS graph", 20.0)


def test_an_exception_in_the_executor_thread_fails_at_teardown(wrenchcone_context):
    node = Node("raiser", context=wrenchcone_context)
    node.create_timer(0.01, lambda: 1 / 0)
    spinner = ExecutorThread(wrenchcone_context)
    spinner.add_node(node)
    try:
        spinner.thread.join(DEADLINE_S)
        with pytest.raises(RuntimeError, match="ZeroDivisionError"):
            spinner.stop()
    finally:
        node.destroy_node()


def test_a_scene_object_is_the_node_scene(wrenchcone_node_factory, wrenchcone_test_node):
    """A core Scene (here the pawl lifted 5 mm off its pins) becomes the scene_file."""
    from wrenchcone_ros.testing.harness import make_client

    lifted = load_scene(PAWL).with_pose(0.096, 0.205, 0.0)
    assert not any(lifted.in_contact)
    with make_client(wrenchcone_test_node, wrenchcone_node_factory(lifted)) as client:
        r = client.check_wrench("arr", (1.0, -1.0, 0.0))
        assert r.status == Status.MODE_NOT_ALLOWED, r.message
        assert client.check_wrench("aaa", (1.0, -1.0, 0.0)).status == Status.OK


def test_a_node_spun_by_a_multi_threaded_executor(wrenchcone_node_factory,
                                                 wrenchcone_test_node):
    from wrenchcone_ros.testing.harness import make_client

    node = wrenchcone_node_factory(DISC, executor=MultiThreadedExecutor)
    with make_client(wrenchcone_test_node, node) as client:
        r = client.check_wrench("na", (0.1, -1.0, 0.0))
        assert r.status == Status.OK and r.consistent
        assert client.classify_wrench((0.1, -1.0, 0.0)).status == Status.OK


def test_a_missing_scene_file_is_named(wrenchcone_node_factory):
    with pytest.raises(FileNotFoundError, match="no_such_scene.yaml"):
        wrenchcone_node_factory("no_such_scene.yaml")


def test_published_fixels_and_pose_are_used(wrenchcone_node_factory, wrenchcone_inputs,
                                            wrenchcone_test_node):
    """The pawl's scene file, then its pins moved 5 mm down by a fixels message: no pin
    touches the foot; then the pawl put down onto them by a pose message."""
    from wrenchcone_ros.testing.harness import make_client

    node = wrenchcone_node_factory(PAWL, parameters={"input_timeout": 0.0})
    scene = load_scene(PAWL)
    pins = [(x, y - 0.005) for (x, y) in (f.position for f in scene.fixels)]
    with make_client(wrenchcone_test_node, node) as client:
        assert client.check_wrench("arr", (1.0, -1.0, 0.0)).status == Status.OK
        msg = wrenchcone_inputs.publish_fixels(pins, [f.radius for f in scene.fixels])
        wrenchcone_inputs.wait_until_used(client, msg)
        assert client.check_wrench("arr", (1.0, -1.0, 0.0)).status == Status.MODE_NOT_ALLOWED
        x, y, theta = scene.pose
        msg = wrenchcone_inputs.publish_pose(x, y - 0.005, theta)
        wrenchcone_inputs.wait_until_used(client, msg)
        assert client.check_wrench("arr", (1.0, -1.0, 0.0)).status == Status.OK


# --- the plugin in other pytest runs ---------------------------------------------------
INNER_TEST = textwrap.dedent('''
    import os
    import threading
    import time
    from pathlib import Path

    import pytest
    from wrenchcone_msgs.msg import Status


    @pytest.fixture
    def wrenchcone_scene():
        return os.environ["KIT_SCENE"]


    def test_own_node_while_the_other_run_is_on(wrenchcone_client, wrenchcone_domain_id):
        barrier = Path(os.environ["KIT_BARRIER"])
        (barrier / str(os.getpid())).write_text(str(wrenchcone_domain_id))
        deadline = time.monotonic() + 60
        while len(list(barrier.iterdir())) < 2:
            assert time.monotonic() < deadline, "the other run never started"
            time.sleep(0.05)
        for _ in range(10):  # with a shared domain, the other node would answer some
            r = wrenchcone_client.check_wrench(os.environ["KIT_MODE"], (0.0, -1.0, 0.0))
            assert r.status == Status.OK, r.message
            r = wrenchcone_client.check_wrench(os.environ["KIT_OTHER_MODE"], (0.0, -1.0, 0.0))
            assert r.status == Status.INVALID_MODE, r.message


    def test_nothing_left_after_teardown():
        assert [t.name for t in threading.enumerate()] == ["MainThread"]
''')


@pytest.mark.slow
def test_two_parallel_runs_get_their_own_domain_and_node(tmp_path):
    """Two pytest runs at once (each the kit through its entry point, each its own
    scene): both pass, on different domains, and leave no thread behind."""
    (tmp_path / "test_inner.py").write_text(INNER_TEST)
    barrier = tmp_path / "barrier"
    barrier.mkdir()
    runs = []
    for scene, mode, other in ((DISC, "na", "arr"), (PAWL, "arr", "na")):
        # the numpy cone engine: these runs are about isolation, not the compiled kernel
        # (not this run's PYTEST_* variables: under pytest-xdist they would make the
        # inner runs start xdist's own threads)
        base = {k: v for k, v in os.environ.items() if not k.startswith("PYTEST_")}
        env = {**base, "WRENCHCONE_ENGINE": "numpy", "KIT_SCENE": str(scene),
               "KIT_MODE": mode,
               "KIT_OTHER_MODE": other, "KIT_BARRIER": str(barrier)}
        runs.append(subprocess.Popen(
            [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-p", "no:xdist",
             "-p", "no:rerunfailures", "test_inner.py"],
            cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
            text=True))
    outputs = [run.communicate(timeout=300)[0] for run in runs]
    for run, output in zip(runs, outputs):
        assert run.returncode == 0, output[-3000:]
        assert "2 passed" in output, output[-3000:]
    ids = {p.read_text() for p in barrier.iterdir()}
    assert len(ids) == 2, ids


BLOCK_ROS = textwrap.dedent('''
    import sys


    class Block:
        def find_spec(self, name, path=None, target=None):
            if name.split(".")[0] in ("rclpy", "geometry_msgs", "wrenchcone_msgs"):
                raise ImportError("blocked for this test: " + name)


    sys.meta_path.insert(0, Block())
''')


@pytest.mark.slow
def test_without_ros_the_plugin_loads_and_a_fixture_says_what_to_source(tmp_path):
    (tmp_path / "conftest.py").write_text(BLOCK_ROS)
    (tmp_path / "test_no_ros.py").write_text(textwrap.dedent('''
        import sys


        def test_plain():
            assert not any(m.split(".")[0] == "rclpy" for m in sys.modules)


        def test_kit(wrenchcone_context):
            pass
    '''))
    out = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                          "-p", "no:launch_testing", "test_no_ros.py"], cwd=tmp_path,
                         capture_output=True, text=True, timeout=120, check=False)
    assert "1 passed, 1 error" in out.stdout, out.stdout[-3000:] + out.stderr[-2000:]
    failure = [line for line in out.stdout.splitlines() if "wrenchcone fixtures need" in line]
    assert failure and "source install/setup.bash" in failure[0], out.stdout[-3000:]
