# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The tilt controller's states without ROS (wrenchcone_ros.sim.controller_states): the
open-loop rule, what counts as a change, the diagnostic levels, a new run. (That the
module imports no ROS is an import contract in pyproject.toml.)"""

import pytest

from wrenchcone_ros.sim.controller_states import (
    INITIAL,
    LEVELS,
    STATES,
    ControllerStates,
)


def test_a_run_starts_idle_waiting_for_a_pose_and_reset_returns_there():
    states = ControllerStates()
    assert (states.state, states.reason) == ("IDLE", "waiting for the first pose") == INITIAL
    assert states.enter("FAILED", "the pose stopped arriving")
    states.reset()
    assert (states.state, states.reason) == INITIAL


def test_only_a_new_state_or_reason_is_a_change():
    states = ControllerStates()
    assert states.enter("EXECUTING", "segment 1: arr")
    assert not states.enter("EXECUTING", "segment 1: arr")  # the same: nothing to log
    assert states.enter("EXECUTING", "segment 2: nss")  # same state, new reason
    assert states.enter("HOLDING", "segment 2: nss")  # new state, same reason
    assert (states.state, states.reason) == ("HOLDING", "segment 2: nss")


@pytest.mark.parametrize("state", ["EXECUTING", "HOLDING"])
def test_open_loop_turns_executing_and_holding_into_open_loop(state):
    states = ControllerStates()
    assert states.enter(state, "segment 3: lsl", open_loop=True)
    assert states.state == "OPEN_LOOP"
    assert states.reason == "open loop (no plan from here, no back-off): segment 3: lsl"
    assert not states.enter(state, "segment 3: lsl", open_loop=True)


@pytest.mark.parametrize("state", ["SEATED", "FAILED", "REPLANNING", "BACKING_OFF",
                                   "PLANNING", "IDLE"])
def test_open_loop_leaves_the_other_states_as_they_are(state):
    states = ControllerStates()
    states.enter(state, "why", open_loop=True)
    assert (states.state, states.reason) == (state, "why")


def test_the_diagnostic_levels():
    states = ControllerStates()
    seen = {}
    for state in STATES:
        states.enter(state, "why")
        seen[state] = states.level
    assert seen == {"IDLE": "OK", "PLANNING": "OK", "EXECUTING": "OK", "HOLDING": "OK",
                    "SEATED": "OK", "REPLANNING": "WARN", "BACKING_OFF": "WARN",
                    "OPEN_LOOP": "WARN", "FAILED": "ERROR"}
    assert set(LEVELS) <= set(STATES)


def test_an_unknown_state_is_refused_and_changes_nothing():
    states = ControllerStates()
    with pytest.raises(ValueError, match="unknown controller state 'DONE'"):
        states.enter("DONE", "why")
    assert (states.state, states.reason) == INITIAL

