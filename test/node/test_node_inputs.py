"""The pulled pose (node/inputs.py, PoseInbox): a real subscription on a helper node that
no executor spins, real DDS traffic. What the node relies on: the newest message of a
burst is the one taken, a waiting message or a wake() ends a wait, take is safe from
several threads, and after close() nothing is taken and no wait blocks."""

from __future__ import annotations

import itertools
import os
import threading
import time

import pytest
from geometry_msgs.msg import PoseStamped
from node_harness import DEADLINE_S, pose_message
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rclpy.qos_overriding_options import QoSOverridingOptions
from rclpy.serialization import deserialize_message

from wrenchcone_ros.node.inputs import PoseInbox, input_qos

_counter = itertools.count()


@pytest.fixture
def inbox_and_publisher(ros_context):
    ns = f"/inbox{os.getpid()}_{next(_counter)}"
    owner = Node("owner", namespace=ns, context=ros_context)
    qos = input_qos()  # depth 1, as the node's; reliable so that no test message is lost
    qos.reliability = ReliabilityPolicy.RELIABLE
    inbox = PoseInbox(owner, "pose", qos, QoSOverridingOptions([]))
    publisher = owner.create_publisher(PoseStamped, "pose", QoSProfile(depth=10))
    deadline = time.monotonic() + DEADLINE_S  # discovery: until the two are matched
    while publisher.get_subscription_count() == 0 and time.monotonic() < deadline:
        time.sleep(0.01)
    assert publisher.get_subscription_count() == 1
    yield inbox, publisher
    inbox.close()
    inbox.destroy()
    owner.destroy_node()


def taken_stamp(inbox: PoseInbox) -> int | None:
    taken = inbox.take_newest()
    return None if taken is None else deserialize_message(taken[0],
                                                          PoseStamped).header.stamp.sec


def wait_for_message(inbox: PoseInbox) -> None:
    """inbox.wait until something is waiting (a hang guard, not a time limit)."""
    start = time.monotonic()
    inbox.wait(DEADLINE_S)
    assert time.monotonic() - start < DEADLINE_S, "wait ended only on its timeout"


def test_a_waiting_message_ends_the_wait_and_the_newest_of_a_burst_is_taken(
        inbox_and_publisher):
    inbox, publisher = inbox_and_publisher
    assert taken_stamp(inbox) is None  # nothing published yet
    for sec in range(1, 51):
        publisher.publish(pose_message(sec))
    wait_for_message(inbox)
    deadline = time.monotonic() + DEADLINE_S  # the burst may still be arriving
    newest = None
    while newest != 50 and time.monotonic() < deadline:
        newest = taken_stamp(inbox) or newest
    assert newest == 50
    assert taken_stamp(inbox) is None  # taken means gone: nothing older is left over


def test_wake_ends_a_wait_from_another_thread(inbox_and_publisher):
    inbox, _ = inbox_and_publisher
    ended = threading.Event()

    def waiter() -> None:
        inbox.wait(DEADLINE_S)
        ended.set()

    thread = threading.Thread(target=waiter)
    thread.start()
    time.sleep(0.05)
    assert not ended.is_set()  # nothing is waiting: the wait goes on
    inbox.wake()
    assert ended.wait(DEADLINE_S)
    thread.join()
    assert taken_stamp(inbox) is None


def test_concurrent_takes_hand_each_message_to_one_taker(inbox_and_publisher):
    """The node takes from a service thread and the worker thread at once."""
    inbox, publisher = inbox_and_publisher
    got: list[int] = []
    stop = threading.Event()

    def taker() -> None:
        while not stop.is_set():
            sec = taken_stamp(inbox)
            if sec is not None:
                got.append(sec)

    threads = [threading.Thread(target=taker) for _ in range(3)]
    for t in threads:
        t.start()
    for sec in range(1, 201):
        publisher.publish(pose_message(sec))
        time.sleep(0.0005)
    deadline = time.monotonic() + DEADLINE_S
    while 200 not in got and time.monotonic() < deadline:
        time.sleep(0.01)
    stop.set()
    for t in threads:
        t.join()
    assert 200 in got
    assert len(got) == len(set(got))  # no message was taken twice


def test_after_close_nothing_is_taken_and_no_wait_blocks(inbox_and_publisher):
    inbox, publisher = inbox_and_publisher
    publisher.publish(pose_message(7))
    wait_for_message(inbox)
    inbox.close()
    assert inbox.take_newest() is None
    start = time.monotonic()
    inbox.wait(DEADLINE_S)
    assert time.monotonic() - start < DEADLINE_S


def test_a_pose_a_request_took_still_wakes_the_worker(harness):
    """The worker sleeps in PoseInbox.wait until a pose is waiting. When a service request
    takes the newest pose first (it needs a snapshot too), nothing is waiting any more:
    the request's take must wake the worker itself (guard condition), or the snapshot
    of that pose is published only at the next pose or poll. Here the worker is stopped
    and this test waits in its place, after a request took the pose."""
    h = harness
    node = h.node
    node.worker.stop(DEADLINE_S)
    assert not node.worker.thread.is_alive()
    node.inputs.pose_inbox.wait(0.05)  # consume a wake the worker left unconsumed
    h.publish_pose(0.0, 0.0, 0.1, stamp=(3, 0))
    deadline = time.monotonic() + DEADLINE_S
    while node.request_snapshot().pose_stamp != (3, 0) and time.monotonic() < deadline:
        time.sleep(0.01)  # the request path took the pose (store.current pulls it)
    assert node.snapshot.pose_stamp == (3, 0)
    assert taken_stamp(node.inputs.pose_inbox) is None  # nothing left waiting
    wait_for_message(node.inputs.pose_inbox)  # ends at once: the take woke it


def test_receive_stamps_are_the_node_clock_and_strictly_increase(inbox_and_publisher):
    """The lane stamps each take (node clock, ns) and never twice the same: a stamp names
    one take, which is how the compiled lane tells whether a newer pose exists."""
    inbox, publisher = inbox_and_publisher
    stamps = []
    for sec in range(1, 21):
        publisher.publish(pose_message(sec))
        deadline = time.monotonic() + DEADLINE_S
        while (taken := inbox.take_newest()) is None and time.monotonic() < deadline:
            time.sleep(0.001)
        assert taken is not None
        stamps.append(taken[1])
    assert all(b > a for a, b in zip(stamps, stamps[1:]))
    now = inbox.node.get_clock().now().nanoseconds
    assert 0 <= now - stamps[-1] < 60e9
