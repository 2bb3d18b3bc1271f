# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The tilt controller's states, without ROS: which state it is in and why, the
transitions allowed between them, the rule that turns executing into open loop, and each
state's diagnostic level.

:class:`~.tilt_controller.TiltControllerNode` decides when to enter a state (its module
docstring); :class:`ControllerStates` holds the state it entered, refuses a transition
that :data:`TRANSITIONS` does not allow, applies the open-loop rule and says whether
anything changed (the node then logs and publishes it).

The state machine (a state may always be entered again, with a new reason)::

    IDLE --> PLANNING --> EXECUTING <--> HOLDING <--> SEATED
                |            |  ^          |            |
                v            v  |          v            v
              FAILED <-- REPLANNING <--> BACKING_OFF   (any state but IDLE)
                             |
                             v
                         OPEN_LOOP --> SEATED / FAILED

* IDLE: the first plan is asked (PLANNING), or the first plan is reused (EXECUTING), or
  no pose came (FAILED).
* EXECUTING, HOLDING, SEATED: the segments and the seat; a deviation -> REPLANNING.
* REPLANNING: a new plan (PLANNING -> EXECUTING), a back-off (BACKING_OFF), the plan it
  has open loop (OPEN_LOOP), at rest in the seat (SEATED), or FAILED.
* OPEN_LOOP is final but for SEATED and FAILED: no more plans or back-offs in that run.
* FAILED is final: only a new run (:meth:`ControllerStates.reset`) leaves it.
"""

from __future__ import annotations

#: States of the controller (ControllerState.state).
STATES = ("IDLE", "PLANNING", "EXECUTING", "HOLDING", "SEATED", "REPLANNING", "BACKING_OFF",
          "OPEN_LOOP", "FAILED")
#: The state and reason of a run that has seen no pose yet.
INITIAL = ("IDLE", "waiting for the first pose")
#: The states that become OPEN_LOOP once the controller executes the plan it has open
#: loop (no plan from where the part is, no back-off).
EXECUTING_STATES = ("EXECUTING", "HOLDING")
#: The diagnostic level of a state (``/diagnostics``); every other state is "OK".
LEVELS = {"FAILED": "ERROR", "REPLANNING": "WARN", "BACKING_OFF": "WARN", "OPEN_LOOP": "WARN"}
_RUNNING = ("EXECUTING", "HOLDING", "SEATED", "REPLANNING", "FAILED")
#: The states each state may be followed by within one run (besides itself, always
#: allowed). OPEN_LOOP is entered, never asked for: an executing state entered with
#: ``open_loop`` (:meth:`ControllerStates.enter`).
TRANSITIONS: dict[str, frozenset[str]] = {
    "IDLE": frozenset({"PLANNING", "EXECUTING", "FAILED"}),
    "PLANNING": frozenset({"EXECUTING", "REPLANNING", "FAILED"}),
    "EXECUTING": frozenset(_RUNNING),
    "HOLDING": frozenset(_RUNNING),
    "SEATED": frozenset(_RUNNING + ("OPEN_LOOP",)),  # seated open loop, then disturbed
    "REPLANNING": frozenset(_RUNNING + ("PLANNING", "BACKING_OFF", "OPEN_LOOP")),
    "BACKING_OFF": frozenset(_RUNNING + ("OPEN_LOOP",)),
    "OPEN_LOOP": frozenset({"SEATED", "FAILED"}),
    "FAILED": frozenset(),
}


class ControllerStates:
    """The state the controller is in, and why.

    Attributes
    ----------
    state : str
        One of :data:`STATES`.
    reason : str
        Why it is in that state, in words.
    """

    def __init__(self) -> None:
        self.state, self.reason = INITIAL

    def reset(self) -> None:
        """Back to :data:`INITIAL` (a new run)."""
        self.state, self.reason = INITIAL

    def enter(self, state: str, reason: str, *, open_loop: bool = False) -> bool:
        """Enter ``state`` for ``reason``.

        Parameters
        ----------
        state : str
            One of :data:`STATES`.
        reason : str
            Why.
        open_loop : bool, optional
            Whether the controller executes its plan open loop: then an executing state
            (:data:`EXECUTING_STATES`) is entered as OPEN_LOOP, its reason prefixed.

        Returns
        -------
        bool
            Whether the state or the reason changed.

        Raises
        ------
        ValueError
            ``state`` is not one of :data:`STATES`, or :data:`TRANSITIONS` does not allow
            it after the current state (the state is then unchanged).
        """
        if state not in STATES:
            raise ValueError(f"unknown controller state {state!r}; one of {list(STATES)}")
        if open_loop and state in EXECUTING_STATES:
            state, reason = "OPEN_LOOP", f"open loop (no plan from here, no back-off): {reason}"
        allowed = TRANSITIONS[self.state]
        if state != self.state and state not in allowed:
            raise ValueError(f"controller state {self.state} cannot be followed by {state} "
                             f"({reason}); after {self.state}: "
                             f"{sorted(allowed) or 'nothing but a new run'}")
        changed = (state, reason) != (self.state, self.reason)
        self.state, self.reason = state, reason
        return changed

    @property
    def level(self) -> str:
        """The diagnostic level of the state: "OK", "WARN" or "ERROR" (:data:`LEVELS`)."""
        return LEVELS.get(self.state, "OK")
