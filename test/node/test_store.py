# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The node's input store (node/store.py), without a ROS graph: coalesced inputs, the
pose reuse window, and the scene moved to a new pose equal to the one built anew."""

from __future__ import annotations

import pytest

from wrenchcone_ros.node import store as st


def fx(positions):
    """Point fixels at ``positions`` (what the node's inputs make of a Fixels message)."""
    from wrenchcone_ros.core import Fixel

    return tuple(Fixel(p) for p in positions)


def _disc_store() -> st.InputStore:
    """An InputStore on the paper's disc, poses 'decoded' from b'x,y,theta,sec'."""
    from wrenchcone_ros.core import default_scene

    base = default_scene()
    shape = base.workpiece.shape
    values = {"fixture_frame": "world", "wait_for_inputs": False, "modes": ["na"],
              "scene_file": "paper_disc.yaml",  # its own fixels count until others come
              "fixel_radius": [], "friction": base.friction,
              "contact_tolerance": base.contact_tolerance,
              "workpiece.shape": "disc", "workpiece.radius": shape.radius,
              "workpiece.vertices": [], "workpiece.com": list(base.workpiece.com),
              "workpiece.mass": base.workpiece.mass,
              "workpiece.inertia": base.workpiece.inertia}
    store = st.InputStore(base, values)

    def decode(data: bytes):
        x, y, th, sec = data.decode().split(",")
        return (float(x), float(y), float(th)), (int(sec), 0)

    store.decode_pose = decode
    return store


def test_pose_reuse_window_answers_from_the_current_snapshot_only_within_it():
    """pose_reuse_window (node parameter): a pose that arrived within the window after the
    snapshot's pose is left for later, and the current snapshot (with its cached cones)
    is used; outside the window, with the window 0 (the default), or after any other
    change, the newest inputs are taken, as before."""
    ms = 1_000_000
    store = _disc_store()
    store.set_raw_pose(b"0,0,0,1", 100 * ms)
    first = store.current()
    assert first.pose_stamp == (1, 0) and first.pose_received_ns == 100 * ms

    store.set_raw_pose(b"0,0,0,2", 102 * ms)  # 2 ms after the snapshot's pose
    assert store.current(reuse_window_ns=3 * ms) is first  # within: reused
    assert store.current(reuse_window_ns=2 * ms) is first  # the bound is inclusive
    assert store.current(reuse_window_ns=1 * ms).pose_stamp == (2, 0)  # outside: newest

    store.set_raw_pose(b"0,0,0,3", 103 * ms)
    assert store.current().pose_stamp == (3, 0)  # window 0: always the newest pose

    third = store.current()
    store.set_raw_pose(b"0,0,0,4", 103 * ms + 1)
    store.set_fixels(fx([(0.0, -1.0), (1.0, 0.0)]), (5, 0), 103 * ms + 2)
    newest = store.current(reuse_window_ns=10 * ms)  # fixels changed: no reuse
    assert newest is not third
    assert newest.pose_stamp == (4, 0) and newest.fixels_stamp == (5, 0)


def test_a_new_pose_moves_the_last_scene_and_any_other_change_rebuilds_it():
    """InputStore._scene: with only the pose new, the last scene is moved to it; the
    result must be exactly what build_scene makes of the same inputs, and a fixel
    message or new parameter values must never be answered from the old scene."""
    from wrenchcone_ros.node.parameters import build_scene

    store = _disc_store()

    def expected():
        return build_scene(store.base_scene, store.values, store.pose.value,
                           store.fixels.value)

    for k in range(1, 4):  # poses only
        store.set_raw_pose(f"0,0,0.{k},{k}".encode(), k)  # turns about the centre
        assert store.current().scene == expected()
    store.set_fixels(fx([(0.0, -1.0), (1.0, 0.0), (-1.0, 0.0)]), (5, 0), 5)
    snap = store.current()
    assert snap.scene == expected() and snap.scene.n_fixels == 3
    store.set_raw_pose(b"0,0,-0.3,6", 6)
    assert store.current().scene == expected()
    store.set_values({**store.values, "friction": 0.9})
    snap = store.current()
    assert snap.scene == expected() and snap.scene.friction == 0.9
    store.set_raw_pose(b"0.5,0,0,7", 7)  # a pose that penetrates: no scene
    assert store.current().scene is None and "penetrates" in store.current().message
    store.set_raw_pose(b"0,0,0,8", 8)  # and back
    assert store.current().scene == expected()


def test_stamps_that_jump_back_by_more_than_the_threshold_reset_the_history():
    """A recorded run played in a loop or a simulation reset: stamps jump back. Refused
    while within stamp_reset_threshold of the newest (the newest wins), a reset with one
    log line beyond it; later stamps are then taken from the new origin. 0: never."""
    store = _disc_store()
    resets = []
    store.on_reset = lambda what, why: resets.append((what, why))
    store.set_fixels(fx([(0.0, -1.0), (1.001, 0.0)]), (100, 0), 1)
    with pytest.raises(st.StampOrderError):
        store.set_fixels(fx([(0.0, -1.0), (1.001, 0.0)]), (99, 500_000_000), 2)  # 0.5 s back
    assert not resets
    store.set_fixels(fx([(0.0, -1.0), (1.001, 0.0)]), (3, 0), 3)  # 97 s back: reset
    assert store.fixels.stamp == (3, 0) and [w for w, _ in resets] == ["fixels"]
    assert "jumped back by 97.000 s" in resets[0][1]
    store.set_fixels(fx([(0.0, -1.0), (1.001, 0.0)]), (4, 0), 4)
    assert store.fixels.stamp == (4, 0)
    store.set_values({**store.values, "stamp_reset_threshold": 0.0})
    with pytest.raises(st.StampOrderError):
        store.set_fixels(fx([(0.0, -1.0), (1.001, 0.0)]), (1, 0), 5)
