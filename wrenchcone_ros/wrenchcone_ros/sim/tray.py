# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The simulated tray without ROS: a scene's workpiece on its fixels under a tilt command.

The physics is the core's (:class:`wrenchcone_ros.core.simulate.Simulation`: pymunk,
Coulomb friction, inelastic impacts, the same world as the planner's checks); this module
adds what a tray in a loop needs:

* a **tilt command** (direction phi of the gravity component in the fixture frame, rad;
  its magnitude a = g sin(alpha), m/s^2): the part is pulled with m a (cos phi, sin phi)
  at its centre of mass; with a spring actuator
  (:class:`~wrenchcone_ros.core.simulate.Actuator` ``"spring:X,Y"``) the same force
  pulls at the spring's hook instead (the planner's spring: fixed in the fixture frame,
  or turning with the part when its ``follow`` is set). A command that is not finite, or
  whose magnitude is negative or above g (a tray tilted past vertical), is refused with
  a :class:`CommandError` that says what is allowed; the previous command stays in
  force.
* **reset** to a pose at rest (refused, :class:`CommandError`, when the pose is not
  finite or a fixel penetrates the workpiece beyond the scene's contact tolerance), the
  tray level and the part **held** there (the engine is not stepped, the clock runs on)
  until the first command after the reset, as a hand that lets go when the run starts;
* a **model** of the uncertainty (each fixel's mu, mass, inertia, centre of mass) drawn
  with :func:`wrenchcone_ros.core.plan.sample_models`, the planner's own sampler.

Time: :meth:`TrayPhysics.advance` steps the engine (step SIM_TIME_STEP T; while the part
is held, only the clock); ``clock`` is the simulated time in seconds since the tray was
made, monotonic across resets.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from ..core.tilt import STANDARD_GRAVITY
from ..core.plan import sample_models
from ..core.plan.execution import model_scene
from ..core.geometry import SceneError
from ..core.scene import Scene
from ..core.simulate import DEFAULT_TILT, Actuator, Readout, Simulation
from ..core.uncertainty import NOMINAL, Model, Uncertainty, as_uncertainty, nominal_model

#: Largest tilt command magnitude (m/s^2): gravity itself, a tray tilted to vertical.
MAX_TILT_ACCELERATION: float = STANDARD_GRAVITY


class CommandError(ValueError):
    """A tilt command, reset pose or model request the tray refuses (the message says
    what was wrong and what is allowed)."""


@dataclass(frozen=True)
class TiltCommand:
    """Direction (rad, fixture frame) and magnitude (m/s^2) of the pull of gravity in the
    tray plane.

    Parameters
    ----------
    direction : float
        rad, fixture frame, in [-pi, pi].
    magnitude : float
        m/s^2, in [0, MAX_TILT_ACCELERATION].
    """

    direction: float
    magnitude: float


def validate_command(direction: float, magnitude: float) -> TiltCommand:
    """The command, or CommandError naming what is wrong.

    Parameters
    ----------
    direction : float
        rad, fixture frame.
    magnitude : float
        m/s^2 (0: level, g: vertical).

    Returns
    -------
    TiltCommand
        The command, its direction wrapped to [-pi, pi].

    Raises
    ------
    CommandError
        A value not finite, or a magnitude outside [0, MAX_TILT_ACCELERATION].
    """
    if not (math.isfinite(direction) and math.isfinite(magnitude)):
        raise CommandError(f"tilt command refused: direction {direction!r} rad and magnitude "
                           f"{magnitude!r} m/s^2 must be finite")
    if not 0.0 <= magnitude <= MAX_TILT_ACCELERATION:
        raise CommandError(f"tilt command refused: magnitude {magnitude!r} m/s^2 is outside "
                           f"[0, {MAX_TILT_ACCELERATION}] (0: level, g: vertical)")
    return TiltCommand(math.remainder(direction, 2.0 * math.pi), magnitude)


class TrayPhysics:
    """A scene's workpiece in the engine under a tilt command (module docstring).

    Parameters
    ----------
    scene : Scene
        The workpiece, its start pose and the fixels (with the nominal friction).
    uncertainty : Uncertainty, optional
        What :meth:`sample` draws models from (None: only the nominal model).
    actuator : Actuator or str, optional
        What pulls the part: a tilt (default) or a spring (``"spring:X,Y"``).
    """

    def __init__(self, scene: Scene, uncertainty: Uncertainty | None = None,
                 actuator: Actuator | str | None = None) -> None:
        self.start = scene
        self.uncertainty = as_uncertainty(uncertainty)
        self.actuator = (Actuator("tilt", DEFAULT_TILT) if actuator is None
                         else Actuator.parse(actuator))
        self.model: Model = nominal_model(scene)
        self.command = TiltCommand(0.0, 0.0)
        self._offset = 0.0
        self.held = True  # the part at its pose until the first command (module docstring)
        self._build(scene.pose)

    # --- the engine ----------------------------------------------------------------------
    def _build(self, pose: Sequence[float]) -> None:
        scene = model_scene(self.start, self.model).with_pose(*pose)
        self.sim = Simulation(scene, self.actuator, self.command.direction,
                              self.model.friction)
        self.sim.set_direction(self.command.direction, self._scale(self.command))

    def _scale(self, cmd: TiltCommand) -> float:
        """The command's pull m a as a fraction of the engine actuator's force."""
        return cmd.magnitude * self.sim.scene.workpiece.mass / self.sim.force

    @property
    def clock(self) -> float:
        """Simulated time (s), monotonic across resets."""
        return self._offset + self.sim.t

    @property
    def dt(self) -> float:
        """The engine's time step (s)."""
        return self.sim.dt

    def set_command(self, direction: float, magnitude: float) -> TiltCommand:
        """Pull along ``direction`` (rad) with ``magnitude`` (m/s^2) from the next step;
        CommandError (the previous command kept) when it is not allowed.

        Parameters
        ----------
        direction : float
            rad, fixture frame.
        magnitude : float
            m/s^2.

        Returns
        -------
        TiltCommand
            The command applied.

        Raises
        ------
        CommandError
            As :func:`validate_command`.
        """
        cmd = validate_command(float(direction), float(magnitude))
        self.command = cmd
        self.held = False
        self.sim.set_direction(cmd.direction, self._scale(cmd))
        return cmd

    def advance(self, duration: float) -> None:
        """Step the engine for ``duration`` seconds of simulated time (whole steps); while
        the part is held, advance only the clock.

        Parameters
        ----------
        duration : float
            Simulated time (s).
        """
        steps = max(1, int(round(duration / self.sim.dt)))
        if self.held:
            self._offset += steps * self.sim.dt
            return
        for _ in range(steps):
            self.sim.step()

    def readout(self) -> Readout:
        """Pose, gaps, contact speeds and letters now (core.simulate.Readout).

        Returns
        -------
        Readout
            The state now.
        """
        return self.sim.readout()

    def speed(self) -> float:
        """Speed of the com plus |omega| L (m/s).

        Returns
        -------
        float
            m/s.
        """
        return self.sim.speed()

    # --- reset and models ------------------------------------------------------------------
    def reset(self, pose: Sequence[float] | None = None) -> tuple[float, float, float]:
        """The part at rest at ``pose`` (default: the start pose), the tray level, the
        part held until the next command.

        Parameters
        ----------
        pose : sequence of 3 float or None, optional
            (x m, y m, theta rad); None: the start pose.

        Returns
        -------
        tuple of 3 float
            The pose the part rests at.

        Raises
        ------
        CommandError
            The pose is not three finite numbers or makes a fixel penetrate the workpiece.
        """
        pose = tuple(self.start.pose if pose is None else pose)
        if len(pose) != 3 or not all(isinstance(v, (int, float)) and math.isfinite(v)
                                     for v in pose):
            raise CommandError(f"reset refused: the pose must be three finite numbers "
                               f"(x m, y m, theta rad), got {pose!r}")
        try:
            self.start.with_pose(*pose)
        except SceneError as exc:
            raise CommandError(f"reset refused: {' '.join(str(exc).split())}") from None
        self._offset += self.sim.t
        self.command = TiltCommand(0.0, 0.0)
        self.held = True
        self._build(pose)
        return self.sim.pose

    def sample(self, seed: int, nominal: bool = False) -> Model:
        """Draw a model of the uncertainty (seeded; ``nominal``: the scene's own) and
        reset to the start pose. CommandError without an uncertainty to draw from.

        Parameters
        ----------
        seed : int
            The seed of the draw.
        nominal : bool, optional
            Take the scene's own model instead.

        Returns
        -------
        Model
            The model simulated from now on.

        Raises
        ------
        CommandError
            As above.
        """
        if nominal:
            self.model = nominal_model(self.start)
        elif self.uncertainty == NOMINAL:  # none given
            raise CommandError("sample refused: the tray has no uncertainty to draw from "
                               "(give one, or ask for the nominal model)")
        else:
            self.model = sample_models(self.start, self.uncertainty, 1, int(seed))[0]
        self.reset(None)
        return self.model

    def set_model(self, model: Model) -> None:
        """Simulate ``model`` from now on (reset to the start pose).

        Parameters
        ----------
        model : Model
            The model.
        """
        self.model = model
        self.reset(None)


__all__ = ["CommandError", "MAX_TILT_ACCELERATION", "TiltCommand", "TrayPhysics",
           "validate_command"]
