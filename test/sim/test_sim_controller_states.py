# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The tilt controller's states without ROS (wrenchcone_ros.sim.controller_states): the
transitions, the open-loop rule, what counts as a change, the diagnostic levels, a new run. (That the
module imports no ROS is an import contract in pyproject.toml.)"""

import pytest

from wrenchcone_ros.sim.controller_states import (
    INITIAL,
    LEVELS,
    STATES,
    TRANSITIONS,
    ControllerStates,
)


def at(*path: str) -> ControllerStates:
    """A controller's states after entering ``path`` from IDLE."""
    states = ControllerStates()
    for state in path:
        states.enter(state, f"into {state}")
    return states


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
    states = at("PLANNING", "EXECUTING", "REPLANNING")
    assert states.enter(state, "segment 3: lsl", open_loop=True)
    assert states.state == "OPEN_LOOP"
    assert states.reason == "open loop (no plan from here, no back-off): segment 3: lsl"
    assert not states.enter(state, "segment 3: lsl", open_loop=True)


@pytest.mark.parametrize("state", ["SEATED", "FAILED", "REPLANNING", "BACKING_OFF",
                                   "PLANNING", "IDLE"])
def test_open_loop_leaves_the_other_states_as_they_are(state):
    path = {"IDLE": (), "PLANNING": (), "BACKING_OFF": ("PLANNING", "EXECUTING", "REPLANNING")}
    states = at(*path.get(state, ("PLANNING", "EXECUTING")))
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



# --- transitions ---------------------------------------------------------------------------
# The runs the controller's docstring describes, written out by hand from it (not from
# TRANSITIONS): each must be accepted step by step.
RUNS = {
    "seated at once": ["PLANNING", "EXECUTING", "HOLDING", "SEATED"],
    "the first plan reused": ["EXECUTING", "HOLDING", "SEATED"],
    "no first plan": ["PLANNING", "FAILED"],
    "no pose": ["FAILED"],
    "a replan": ["PLANNING", "EXECUTING", "REPLANNING", "PLANNING", "EXECUTING", "HOLDING",
                 "SEATED"],
    "a back-off": ["PLANNING", "EXECUTING", "REPLANNING", "PLANNING", "REPLANNING",
                   "BACKING_OFF", "EXECUTING", "HOLDING", "SEATED"],
    "open loop, seated": ["PLANNING", "EXECUTING", "REPLANNING", "OPEN_LOOP", "SEATED"],
    "open loop, failed": ["PLANNING", "EXECUTING", "REPLANNING", "BACKING_OFF", "OPEN_LOOP",
                          "FAILED"],
    "seated, then disturbed": ["PLANNING", "EXECUTING", "HOLDING", "SEATED", "HOLDING",
                               "REPLANNING", "SEATED"],
    "at rest in the seat while replanning": ["PLANNING", "EXECUTING", "REPLANNING",
                                             "SEATED"],
}


@pytest.mark.parametrize("run", sorted(RUNS))
def test_every_run_the_controller_describes_is_allowed(run):
    states = at(*RUNS[run])
    assert states.state == RUNS[run][-1]


# Transitions the controller never makes, by its docstring: each refused, the state kept.
FORBIDDEN = [
    ((), "HOLDING"), ((), "SEATED"), ((), "REPLANNING"), ((), "BACKING_OFF"),
    ((), "OPEN_LOOP"),  # IDLE: nothing runs before a plan
    (("PLANNING",), "SEATED"), (("PLANNING",), "BACKING_OFF"),
    (("PLANNING", "EXECUTING"), "PLANNING"),  # a replan is announced first
    (("PLANNING", "EXECUTING"), "BACKING_OFF"),
    (("PLANNING", "EXECUTING"), "OPEN_LOOP"),  # open loop follows a failed replan
    (("PLANNING", "EXECUTING", "REPLANNING", "OPEN_LOOP"), "REPLANNING"),  # no more plans
    (("PLANNING", "EXECUTING", "REPLANNING", "OPEN_LOOP"), "BACKING_OFF"),
    (("PLANNING", "EXECUTING", "REPLANNING", "OPEN_LOOP"), "PLANNING"),
    (("FAILED",), "PLANNING"), (("FAILED",), "EXECUTING"), (("FAILED",), "SEATED"),
    (("PLANNING", "EXECUTING"), "IDLE"),  # only a new run goes back to IDLE
]


@pytest.mark.parametrize(("path", "state"), FORBIDDEN)
def test_a_transition_the_controller_never_makes_is_refused(path, state):
    states = at(*path)
    before = (states.state, states.reason)
    with pytest.raises(ValueError, match=f"cannot be followed by {state}"):
        states.enter(state, "why")
    assert (states.state, states.reason) == before


def test_a_state_may_be_entered_again_with_a_new_reason_and_failed_only_left_by_a_new_run():
    states = at("FAILED")
    assert states.enter("FAILED", "another reason")  # e.g. the node stopped answering
    states.reset()
    assert states.enter("PLANNING", "plan 1")


def test_the_table_names_only_states_and_every_state_but_failed_has_a_way_out():
    assert set(TRANSITIONS) == set(STATES)
    for state, nxt in TRANSITIONS.items():
        assert nxt <= set(STATES) and "IDLE" not in nxt
        assert bool(nxt) == (state != "FAILED")
        if state != "FAILED":
            assert "FAILED" in nxt  # a run can always fail
