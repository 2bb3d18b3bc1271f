"""The node's parameters: declarations, validation, and parameters -> Workpiece / Scene.

Everything here is a plain function of a node (for declare/read) or of a dict of values
(name -> value, as :func:`read_values` returns it), so validation and the scene build can
run on a candidate set of values before it is accepted. To add a parameter: declare it in
:func:`declare_parameters`, add its name to :data:`PARAMETERS`, check it in
:func:`validate_values`.
"""

from __future__ import annotations

import math
from typing import Any

from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor, ParameterType
from rclpy.exceptions import ParameterUninitializedException
from rclpy.node import Node
from rclpy.parameter import Parameter

from wrenchcone_ros import conversions as conv
from wrenchcone_ros.core import (
    MODE_TABLE,
    Disc,
    Fixel,
    Polygon,
    Scene,
    SceneError,
    Workpiece,
    default_scene,
    load_scene,
)

MODE_LETTERS = "".join(MODE_TABLE)
#: Every parameter the node declares (besides rclpy's own use_sim_time).
PARAMETERS = (
    "scene_file", "fixture_frame", "workpiece.mass", "workpiece.inertia", "workpiece.com",
    "workpiece.shape", "workpiece.radius", "workpiece.vertices", "friction",
    "contact_tolerance", "fixel_radius", "modes", "tilt_tolerance", "out_of_plane_tolerance",
    "wait_for_inputs", "publish_markers", "diagnostics_rate", "input_stale_after",
)
#: Parameters rclpy declares itself (not reported as unknown when given at start).
RCLPY_PARAMETERS = ("use_sim_time", "start_type_description_service")


def descriptor(description: str, type_: int, *, read_only: bool = False,
               constraints: str = "", low: float | None = None,
               high: float | None = None) -> ParameterDescriptor:
    d = ParameterDescriptor(description=description, type=type_, read_only=read_only,
                            additional_constraints=constraints)
    if low is not None or high is not None:
        d.floating_point_range = [FloatingPointRange(
            from_value=-math.inf if low is None else low,
            to_value=math.inf if high is None else high, step=0.0)]
    return d


def declare_parameters(node: Node) -> Scene:
    """Declare every parameter of the node; return the base scene (parameter scene_file)."""
    P = ParameterType
    path = node.declare_parameter(
        "scene_file", "", descriptor(
            "Scene YAML (core schema) to start from; empty = the built-in default, the "
            "paper's disc example. Read at start only.", P.PARAMETER_STRING,
            read_only=True)).value
    try:
        base = load_scene(path) if path else default_scene()
    except SceneError as exc:
        raise SceneError(f"parameter scene_file: {exc}") from None
    wp = base.workpiece
    shape = wp.shape
    radii = {f.radius for f in base.fixels}
    node.declare_parameter("fixture_frame", "world", descriptor(
        "frame_id that pose and fixel messages must carry (the fixture frame).",
        P.PARAMETER_STRING))
    node.declare_parameter("workpiece.mass", float(wp.mass), descriptor(
        "Workpiece mass (kg), > 0.", P.PARAMETER_DOUBLE, constraints="> 0, finite"))
    node.declare_parameter("workpiece.inertia", float(wp.inertia), descriptor(
        "Moment of inertia about the centre of mass (kg m^2), > 0.", P.PARAMETER_DOUBLE,
        constraints="> 0, finite"))
    node.declare_parameter("workpiece.com", [float(v) for v in wp.com], descriptor(
        "Centre of mass [x, y] in the workpiece frame (m).", P.PARAMETER_DOUBLE_ARRAY,
        constraints="2 finite numbers"))
    is_disc = isinstance(shape, Disc)
    node.declare_parameter("workpiece.shape", "disc" if is_disc else "polygon",
                           descriptor("Workpiece shape: 'disc' or 'polygon'.",
                                      P.PARAMETER_STRING,
                                      constraints="'disc' or 'polygon'"))
    node.declare_parameter(
        "workpiece.radius", float(shape.radius) if is_disc else 1.0, descriptor(
            "Disc radius (m), used when workpiece.shape is 'disc'.", P.PARAMETER_DOUBLE,
            constraints="> 0, finite"))
    vdesc = descriptor(
        "Polygon vertices, flattened [x1, y1, x2, y2, ...] in the workpiece frame (m), "
        "counter-clockwise, simple; used when workpiece.shape is 'polygon'.",
        P.PARAMETER_DOUBLE_ARRAY, constraints=">= 3 vertices, simple polygon")
    if is_disc:
        node.declare_parameter("workpiece.vertices", Parameter.Type.DOUBLE_ARRAY, vdesc)
    else:
        node.declare_parameter("workpiece.vertices",
                               [float(c) for v in shape.vertices for c in v], vdesc)
    node.declare_parameter("friction", float(base.friction), descriptor(
        "Coulomb friction coefficient mu (all fixels), >= 0.", P.PARAMETER_DOUBLE,
        constraints=">= 0, finite"))
    node.declare_parameter("contact_tolerance", float(base.contact_tolerance), descriptor(
        "A fixel with |gap| <= this (m) is in contact.", P.PARAMETER_DOUBLE,
        constraints="> 0, finite"))
    node.declare_parameter("fixel_radius", float(min(radii)) if radii else 0.0, descriptor(
        "Radius (m) of the fixels received on the fixels topic (pins); setting it at "
        "run time applies it to every fixel.", P.PARAMETER_DOUBLE,
        constraints=">= 0, finite"))
    node.declare_parameter("modes", list(base.modes) or Parameter.Type.STRING_ARRAY,
                           descriptor(
        "Modes whose cone is published on ~/cone/<mode> whenever the inputs change.",
        P.PARAMETER_STRING_ARRAY, constraints=f"letters from {MODE_LETTERS!r}"))
    node.declare_parameter("tilt_tolerance", conv.TILT_TOLERANCE_RAD, descriptor(
        "Largest tilt (rad) of a pose's orientation out of the fixture plane.",
        P.PARAMETER_DOUBLE, constraints=">= 0, finite"))
    node.declare_parameter("out_of_plane_tolerance", conv.OUT_OF_PLANE_TOLERANCE,
                           descriptor(
        "Largest |(force.z, torque.x/L, torque.y/L)| / |(force.x, force.y, torque.z/L)| "
        "accepted in a check_wrench request (dimensionless).", P.PARAMETER_DOUBLE,
        constraints=">= 0, finite"))
    node.declare_parameter("wait_for_inputs", False, descriptor(
        "If true, answer NO_INPUTS until a pose and a fixel message have arrived; if "
        "false, the scene's own pose and fixels are used until then.",
        P.PARAMETER_BOOL))
    node.declare_parameter("publish_markers", True, descriptor(
        "Publish ~/markers (visualization_msgs/MarkerArray, latched) for RViz; false "
        "clears them once and stops.", P.PARAMETER_BOOL))
    node.declare_parameter("diagnostics_rate", 1.0, descriptor(
        "Rate (Hz) of the node's /diagnostics status; 0 = none.", P.PARAMETER_DOUBLE,
        constraints=">= 0, finite"))
    node.declare_parameter("input_stale_after", 0.0, descriptor(
        "An input older than this (s since it was received) makes /diagnostics WARN; 0 = "
        "input age never warns (a static fixture).", P.PARAMETER_DOUBLE,
        constraints=">= 0, finite"))
    return base


def unknown_start_parameters(node: Node) -> list[str]:
    """Names given to the node at start (a ``--params-file``, ``-p name:=value``,
    parameter_overrides) that it does not declare: misspellings, silently ignored by ROS.

    rclpy keeps those values in ``Node._parameter_overrides`` (there is no public getter);
    without it the answer is empty, never wrong.
    """
    given = getattr(node, "_parameter_overrides", None) or {}
    known = set(PARAMETERS) | set(RCLPY_PARAMETERS)
    return sorted(name for name in given if name not in known
                  and not name.startswith("qos_overrides."))  # rclpy's QoS overrides


def parameter_value(node: Node, name: str) -> Any:
    """The parameter's value; None when it was declared with a type and has no value."""
    try:
        return node.get_parameter(name).value
    except ParameterUninitializedException:
        return None


def read_values(node: Node, overrides: dict[str, Any] | None = None) -> dict[str, Any]:
    """Every parameter's value (name -> value), with candidate ``overrides`` applied."""
    vals = {p: parameter_value(node, p) for p in PARAMETERS}
    vals.update(overrides or {})
    vals["modes"] = [m for m in (vals["modes"] or []) if m]
    return vals


def workpiece_from_values(v: dict[str, Any]) -> Workpiece:
    """The Workpiece the ``workpiece.*`` values describe; SceneError if they make none."""
    kind = v["workpiece.shape"]
    if kind == "disc":
        shape = Disc(v["workpiece.radius"])
    elif kind == "polygon":
        flat = list(v["workpiece.vertices"] or [])
        if len(flat) % 2 or len(flat) < 6:
            raise SceneError("workpiece.vertices must hold >= 3 (x, y) pairs, flattened "
                             f"[x1, y1, x2, y2, ...]; got {len(flat)} number(s)")
        shape = Polygon(tuple(zip(flat[0::2], flat[1::2])))
    else:
        raise SceneError(f"workpiece.shape must be 'disc' or 'polygon', got {kind!r}")
    com = list(v["workpiece.com"])
    if len(com) != 2:
        raise SceneError(f"workpiece.com must be [x, y], got {com!r}")
    return Workpiece(mass=v["workpiece.mass"], inertia=v["workpiece.inertia"],
                     shape=shape, com=tuple(com))


def validate_values(v: dict[str, Any]) -> None:
    """Raise SceneError (or ValueError/TypeError) if the values cannot make a scene,
    whatever the pose and fixels; the message says what is wrong and what is allowed."""
    workpiece_from_values(v)
    for name, low, strict in (("friction", 0.0, False),
                              ("contact_tolerance", 0.0, True),
                              ("fixel_radius", 0.0, False),
                              ("tilt_tolerance", 0.0, False),
                              ("out_of_plane_tolerance", 0.0, False),
                              ("diagnostics_rate", 0.0, False),
                              ("input_stale_after", 0.0, False)):
        x = v[name]
        if not math.isfinite(x) or x < low or (strict and x == low):
            raise SceneError(f"{name} must be {'>' if strict else '>='} {low:g} and "
                             f"finite, got {x!r}")
    for mode in v["modes"]:
        if mode and any(c not in MODE_TABLE for c in mode):
            raise SceneError(f"modes: {mode!r} is not a mode string (letters "
                             f"{MODE_LETTERS!r}, one per fixel)")
    if not v["fixture_frame"]:
        raise SceneError("fixture_frame must not be empty")


def build_scene(base: Scene, v: dict[str, Any], pose: tuple[float, float, float],
                fixel_positions: list[tuple[float, float]] | None,
                radius_overridden: bool) -> Scene:
    """The Scene of parameter values ``v``, a pose and received fixel positions (None:
    the base scene's fixels, with fixel_radius applied if it was ever set)."""
    radius = v["fixel_radius"]
    if fixel_positions is not None:
        fixels = tuple(Fixel(p, radius) for p in fixel_positions)
    elif radius_overridden:
        fixels = tuple(Fixel(f.position, radius, f.friction) for f in base.fixels)
    else:
        fixels = base.fixels
    friction = v["friction"]
    if friction != base.friction:  # a set friction applies to all fixels
        fixels = tuple(Fixel(f.position, f.radius) for f in fixels)
    return Scene(workpiece=workpiece_from_values(v), fixels=fixels, friction=friction,
                 pose=pose, contact_tolerance=v["contact_tolerance"],
                 modes=tuple(m for m in v["modes"] if m))
