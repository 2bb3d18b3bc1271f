"""The node's parameters: declarations, validation, and parameters -> Workpiece / Scene.

Everything here is a plain function of a node (for declare/read) or of a dict of values
(name -> value, as :func:`read_values` returns it), so validation and the scene build can
run on a candidate set of values before it is accepted. To add a parameter: declare it in
:func:`declare_parameters`, add its name to :data:`PARAMETERS`, check it in
:func:`validate_values`.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Mapping
from typing import Any

from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor, ParameterType
from rclpy.exceptions import ParameterUninitializedException
from rclpy.node import Node
from rclpy.parameter import Parameter

from wrenchcone_ros.ros import conversions as conv
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
from wrenchcone_ros.core.modes import is_wildcard
from wrenchcone_ros.core.uncertainty import Uncertainty, UncertaintyError, load_uncertainty
from wrenchcone_ros.core.tolerances import MAX_COORDINATE_M, MAX_FRICTION

MODE_LETTERS = "".join(MODE_TABLE)
#: Every parameter the node declares (besides rclpy's own use_sim_time and the QoS
#: override parameters of the input topics).
PARAMETERS = (
    "scene_file", "fixture_frame", "workpiece.mass", "workpiece.inertia", "workpiece.com",
    "workpiece.shape", "workpiece.radius", "workpiece.vertices", "friction",
    "contact_tolerance", "fixel_radius", "modes", "tilt_tolerance", "out_of_plane_tolerance",
    "wait_for_inputs", "input_timeout", "fixels_timeout", "max_fixels", "max_mode_length",
    "max_concrete_modes", "max_classify_nodes", "max_queued_requests", "max_request_time",
    "publish_markers",
    "max_publish_rate", "pose_reuse_window", "fast_check", "worker_nice", "diagnostics_rate",
    "uncertainty.friction", "uncertainty.mass", "uncertainty.inertia",
    "uncertainty.com_radius", "uncertainty.normal_error",
)
#: Parameters rclpy declares itself (not reported as unknown when given at start).
RCLPY_PARAMETERS = ("use_sim_time", "start_type_description_service")
#: Parameters declared as double (array): an integer given for one is taken as that
#: double (``-p friction:=1`` means 1.0).
DOUBLE_PARAMETERS = frozenset({
    "workpiece.mass", "workpiece.inertia", "workpiece.radius", "friction",
    "contact_tolerance", "fixel_radius", "tilt_tolerance", "out_of_plane_tolerance",
    "input_timeout", "fixels_timeout", "max_request_time", "max_publish_rate",
    "pose_reuse_window", "diagnostics_rate", "uncertainty.com_radius",
    "uncertainty.normal_error"})
DOUBLE_ARRAY_PARAMETERS = frozenset({"workpiece.com", "workpiece.vertices",
                                     "uncertainty.friction", "uncertainty.mass",
                                     "uncertainty.inertia"})
#: Integer limits: name -> (default, largest value accepted).
LIMIT_PARAMETERS = {
    "max_fixels": (32, 100_000),
    "max_mode_length": (64, 100_000),
    "max_concrete_modes": (64, 10_000_000),
    "max_classify_nodes": (2000, 100_000_000),
    "max_queued_requests": (64, 100_000),
}
#: At most this many modes may be monitored (each is a topic and a cone per update).
MAX_MONITORED_MODES = 64
#: Largest accepted timeouts and tolerances of the node's own (non-scene) parameters.
MAX_TIMEOUT_S = 1e6
MAX_FRAME_ID_LENGTH = 256
#: Largest max_publish_rate (Hz).
MAX_PUBLISH_RATE_HZ = 1e6
#: The environment variable that gives parameter ``fast_check`` its default (CI runs the
#: node tests with it 0 as well: the node without the compiled lane).
FAST_CHECK_ENV = "WRENCHCONE_FAST_CHECK"
_BOOLEAN_WORDS = {"": True, "1": True, "true": True, "yes": True, "on": True,
                  "0": False, "false": False, "no": False, "off": False}
#: Largest pose_reuse_window (s): a reply's pose may be at most this much older than
#: the newest pose received; the issue-11 target for a 1 kHz stream is 10 ms (p99).
MAX_POSE_REUSE_WINDOW_S = 0.1
#: Default pose_reuse_window (s): half the issue-11 budget of 10 ms for a reply's pose,
#: and longer than the publishing worker's step for 16 modes (1-3 ms at 1 kHz), so
#: that the compiled lane answers from the last published cones under a 1 kHz stream.
DEFAULT_POSE_REUSE_WINDOW_S = 0.005
#: Default and largest worker_nice: the publishing worker's scheduling niceness (Linux,
#: 0 = as the node, 19 = the lowest priority).
DEFAULT_WORKER_NICE, MAX_WORKER_NICE = 10, 19
#: Largest diagnostics_rate (Hz).
MAX_DIAGNOSTICS_RATE_HZ = 1000.0
#: Smallest nonzero max_publish_rate and diagnostics_rate (Hz): one period of at most
#: 1000 s. A rate of 1e-300 Hz made a wait of 1e300 s, which Python cannot represent
#: (OverflowError in the publishing worker).
MIN_RATE_HZ = 1e-3


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


def _as_double(param: Parameter) -> Parameter:
    """An integer (array) parameter for a double (array) one, as that double (array)."""
    if param.name in DOUBLE_PARAMETERS and param.type_ == Parameter.Type.INTEGER:
        return Parameter(param.name, Parameter.Type.DOUBLE, float(param.value))
    if (param.name in DOUBLE_ARRAY_PARAMETERS
            and param.type_ == Parameter.Type.INTEGER_ARRAY):
        return Parameter(param.name, Parameter.Type.DOUBLE_ARRAY,
                         [float(v) for v in param.value])
    return param


def coerce_types(parameters: list[Parameter]) -> list[Parameter]:
    """Pre-set callback: integers given for double parameters become doubles."""
    return [_as_double(p) for p in parameters]


def _coerce_overrides(node: Node) -> None:
    """The same for start-up overrides (``--ros-args -p friction:=1``), which rclpy
    applies at declaration, before any set-parameters callback exists."""
    overrides = getattr(node, "_parameter_overrides", None)
    if isinstance(overrides, dict):
        for name, param in list(overrides.items()):
            overrides[name] = _as_double(param)


def declare_parameters(node: Node) -> Scene:
    """Declare every parameter of the node; return the base scene (parameter scene_file)."""
    P = ParameterType
    _coerce_overrides(node)
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
    declare_uncertainty(node, path)
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
    node.declare_parameter("input_timeout", 1.0, descriptor(
        "Seconds (node clock, respects use_sim_time) after which a received pose is "
        "stale: answers from it get STALE_INPUTS, and cone topics STALE_INPUTS with no rows; 0 = "
        "never stale.", P.PARAMETER_DOUBLE, constraints=">= 0, finite"))
    node.declare_parameter("fixels_timeout", 0.0, descriptor(
        "As input_timeout, for the fixels message (fixtures are often published once, "
        "so 0 = never stale by default).", P.PARAMETER_DOUBLE, constraints=">= 0, finite"))
    for name, text in (
            ("max_fixels", "Largest number of fixels a fixels message may carry."),
            ("max_mode_length", "Longest mode string a request may carry (characters)."),
            ("max_concrete_modes", "Most concrete modes one wildcard mode of a request "
                                   "may expand to (counted before expanding)."),
            ("max_classify_nodes", "Most nodes of the mode search one classification "
                                   "(classify_wrench, check_wrench with classify) may "
                                   "visit."),
            ("max_queued_requests", "Most check_wrench requests that may wait for the "
                                    "Python handler (those the compiled lane does not "
                                    "answer itself).")):
        default, high = LIMIT_PARAMETERS[name]
        node.declare_parameter(name, default, descriptor(
            text + " Over it: LIMIT_EXCEEDED (requests) or a refusal (messages).",
            P.PARAMETER_INTEGER, constraints=f"integer in [1, {high}]"))
    node.declare_parameter("max_request_time", 0.05, descriptor(
        "Seconds of computation a check_wrench or get_cone request may take (they share "
        "one thread, the fast lane); over it: LIMIT_EXCEEDED. classify_wrench and "
        "force_directions run in their own thread and have no time limit. 0 = no limit.",
        P.PARAMETER_DOUBLE, constraints=">= 0, finite"))
    node.declare_parameter("wait_for_inputs", False, descriptor(
        "If true, answer NO_INPUTS until a pose and a fixel message have arrived; if "
        "false, the scene's own pose and fixels are used until then.",
        P.PARAMETER_BOOL))
    node.declare_parameter("publish_markers", True, descriptor(
        "Publish ~/markers (visualization_msgs/MarkerArray, latched) for RViz; false "
        "clears them once and stops.", P.PARAMETER_BOOL))
    node.declare_parameter("max_publish_rate", 0.0, descriptor(
        "Most snapshots per second the cone topics and markers are published for (Hz); "
        "0 = as fast as the monitored cones can be computed. A cap lowers the node's CPU "
        "under fast pose streams at the cost of up to 1 / rate s of lag.",
        P.PARAMETER_DOUBLE,
        constraints=f"0 or >= {MIN_RATE_HZ:g}, <= {MAX_PUBLISH_RATE_HZ:g}"))
    node.declare_parameter("pose_reuse_window", DEFAULT_POSE_REUSE_WINDOW_S, descriptor(
        "Seconds (s): a service request is answered from the current snapshot (and "
        "check_wrench by the compiled lane from the last published cones) when the "
        "newest pose arrived at most this long after that snapshot's pose, else from the "
        "newest pose. The reply's pose_stamp says which pose was used. 0 = always the "
        "newest pose.",
        P.PARAMETER_DOUBLE, constraints=f">= 0, <= {MAX_POSE_REUSE_WINDOW_S:g}"))
    node.declare_parameter("fast_check", fast_check_default(), descriptor(
        "If true, check_wrench for a monitored concrete mode is answered by the compiled "
        "lane from the cones last published (no Python, no GIL; within "
        "pose_reuse_window of the newest pose); false: every request by the Python "
        f"handler. Read at start only; default from the environment ({FAST_CHECK_ENV}), "
        "else true.", P.PARAMETER_BOOL, read_only=True))
    node.declare_parameter("worker_nice", DEFAULT_WORKER_NICE, descriptor(
        "Scheduling niceness of the publishing worker thread (0 = as the node, up to "
        f"{MAX_WORKER_NICE}): the worker is the node's one long CPU consumer; at a lower "
        "priority it yields the CPU to requests and to other processes. Read at start "
        "only.", P.PARAMETER_INTEGER, read_only=True,
        constraints=f"integer in [0, {MAX_WORKER_NICE}]"))
    node.declare_parameter("diagnostics_rate", 1.0, descriptor(
        "Rate (Hz) of the node's /diagnostics status; 0 = none.", P.PARAMETER_DOUBLE,
        constraints=f"0 or >= {MIN_RATE_HZ:g}, <= {MAX_DIAGNOSTICS_RATE_HZ:g}"))
    return base


def fast_check_default(environ: Mapping[str, str] | None = None) -> bool:
    """The default of parameter ``fast_check``: environment variable
    :data:`FAST_CHECK_ENV` (1/true/yes/on or 0/false/no/off, any case), true when unset
    or empty; ValueError for anything else."""
    environ = os.environ if environ is None else environ
    text = environ.get(FAST_CHECK_ENV, "").strip().lower()
    if text not in _BOOLEAN_WORDS:
        raise ValueError(f"{FAST_CHECK_ENV}={environ[FAST_CHECK_ENV]!r} is not a boolean; "
                         "use 1/true/yes/on or 0/false/no/off")
    return _BOOLEAN_WORDS[text]


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


def declare_uncertainty(node: Node, path: str) -> None:
    """The ``uncertainty.*`` parameters (force_directions answers for every model of the
    set they describe); defaults from the scene file's ``uncertainty:`` block."""
    P = ParameterType
    try:
        u = load_uncertainty(path) if path else None
    except UncertaintyError as exc:
        raise SceneError(f"parameter scene_file: {exc}") from None
    d = u.to_dict() if u is not None else {}
    if isinstance(d.get("normal_error"), list) or (d.get("friction") and isinstance(
            d["friction"][0], list)) or "com_box" in d:
        raise SceneError("parameter scene_file: the node takes one friction interval, one "
                         "normal_error and a com_radius (per-fixel values and com_box: "
                         "the core and the CLI)")
    for name, what in (("friction", "Friction interval [lo, hi] of every fixel"),
                       ("mass", "Mass interval [lo, hi] (kg)"),
                       ("inertia", "Inertia interval [lo, hi] (kg m^2)")):
        desc = descriptor(f"{what}; empty: the nominal value. force_directions then "
                          "answers for every model.", P.PARAMETER_DOUBLE_ARRAY,
                          constraints="empty or [lo, hi], 0 <= lo <= hi")
        value = d.get(name)
        node.declare_parameter(f"uncertainty.{name}",
                               [float(x) for x in value] if value else
                               Parameter.Type.DOUBLE_ARRAY, desc)
    node.declare_parameter("uncertainty.com_radius", float(d.get("com_radius") or 0.0),
                           descriptor("The com anywhere within this distance (m) of its "
                                      "nominal place; 0: exact.", P.PARAMETER_DOUBLE,
                                      constraints=">= 0, finite"))
    node.declare_parameter("uncertainty.normal_error", float(d.get("normal_error") or 0.0),
                           descriptor("Each contact normal turned by up to +- this (rad); "
                                      "0: exact.", P.PARAMETER_DOUBLE,
                                      constraints="[0, pi/2)"))


def uncertainty_from_values(v: dict[str, Any]) -> Uncertainty | None:
    """The Uncertainty of the ``uncertainty.*`` values (None when none is set); SceneError
    naming the parameter when a value is wrong."""
    kw: dict[str, Any] = {}
    for name in ("friction", "mass", "inertia"):
        value = list(v[f"uncertainty.{name}"] or [])
        if value:
            kw[name] = value
    for name in ("com_radius", "normal_error"):
        if v[f"uncertainty.{name}"]:
            kw[name] = v[f"uncertainty.{name}"]
    if not kw:
        return None
    try:
        return Uncertainty(**kw)
    except UncertaintyError as exc:
        raise SceneError(f"parameters uncertainty.*: {exc}") from None


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
        raise SceneError(f"workpiece.shape must be 'disc' or 'polygon', got {str(kind)[:40]!r}")
    com = list(v["workpiece.com"])
    if len(com) != 2:
        raise SceneError(f"workpiece.com must be [x, y], got {com!r}")
    return Workpiece(mass=v["workpiece.mass"], inertia=v["workpiece.inertia"],
                     shape=shape, com=tuple(com))


def _number(v: dict[str, Any], name: str, low: float, high: float,
            strict: bool = False) -> None:
    x = v[name]
    if (isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x)
            or x < low or (strict and x == low) or x > high):
        raise SceneError(f"{name} must be a finite number {'>' if strict else '>='} {low:g} "
                         f"and <= {high:g}, got {x!r}")


def _rate(v: dict[str, Any], name: str, high: float) -> None:
    """0 (off) or a finite rate in [MIN_RATE_HZ, high] Hz."""
    _number(v, name, 0.0, high)
    if 0.0 < v[name] < MIN_RATE_HZ:
        raise SceneError(f"{name} must be 0 (off) or between {MIN_RATE_HZ:g} and {high:g} "
                         f"Hz, got {v[name]!r}")


def validate_values(v: dict[str, Any],
                    topic_error: Callable[[str], str | None] | None = None) -> None:
    """Raise SceneError if the values are wrong, whatever the pose and fixels; the message
    says what is wrong and what is allowed. Every number is checked finite and in range,
    including the ones only used later (the radius while the shape is a polygon, the
    vertices while it is a disc). ``topic_error(mode)`` says why ``~/cone/<mode>`` is no
    valid topic name (None if it is)."""
    for name in ("workpiece.mass", "workpiece.inertia", "workpiece.radius"):
        _number(v, name, 0.0, math.inf, strict=True)
    Disc(v["workpiece.radius"])  # the core's limits, whatever the shape
    for name in DOUBLE_ARRAY_PARAMETERS:
        for k, x in enumerate(v[name] or []):
            if not isinstance(x, float) or not math.isfinite(x) or abs(x) > MAX_COORDINATE_M:
                raise SceneError(f"{name}[{k}] must be a finite number within "
                                 f"+-{MAX_COORDINATE_M:g} m, got {x!r}")
    workpiece_from_values(v)
    uncertainty_from_values(v)
    _number(v, "friction", 0.0, MAX_FRICTION)
    _number(v, "contact_tolerance", 0.0, MAX_COORDINATE_M, strict=True)
    _number(v, "fixel_radius", 0.0, MAX_COORDINATE_M)
    _number(v, "tilt_tolerance", 0.0, math.pi)
    _number(v, "out_of_plane_tolerance", 0.0, 1e6)
    _number(v, "input_timeout", 0.0, MAX_TIMEOUT_S)
    _number(v, "fixels_timeout", 0.0, MAX_TIMEOUT_S)
    _number(v, "max_request_time", 0.0, MAX_TIMEOUT_S)
    _rate(v, "max_publish_rate", MAX_PUBLISH_RATE_HZ)
    _number(v, "pose_reuse_window", 0.0, MAX_POSE_REUSE_WINDOW_S)
    _rate(v, "diagnostics_rate", MAX_DIAGNOSTICS_RATE_HZ)
    nice = v["worker_nice"]
    if isinstance(nice, bool) or not isinstance(nice, int) or not 0 <= nice <= MAX_WORKER_NICE:
        raise SceneError(f"worker_nice must be an integer in [0, {MAX_WORKER_NICE}], "
                         f"got {nice!r}")
    for name, (_default, high) in LIMIT_PARAMETERS.items():
        x = v[name]
        if isinstance(x, bool) or not isinstance(x, int) or not 1 <= x <= high:
            raise SceneError(f"{name} must be an integer in [1, {high}], got {x!r}")
    modes = v["modes"]
    if len(modes) > MAX_MONITORED_MODES:
        raise SceneError(f"modes: at most {MAX_MONITORED_MODES} modes can be monitored, "
                         f"got {len(modes)}")
    for mode in modes:
        if len(mode) > v["max_mode_length"]:
            raise SceneError(f"modes: a mode of {len(mode)} letters is longer than "
                             f"max_mode_length ({v['max_mode_length']})")
        if is_wildcard(mode):
            raise SceneError(f"modes: {mode!r} has wildcards; a wildcard mode is a union of "
                             "cones, not one cone, so it cannot be published: monitor its "
                             "concrete modes (letters " f"{MODE_LETTERS!r})")
        if any(c not in MODE_TABLE for c in mode):
            raise SceneError(f"modes: {mode!r} is not a mode string (letters "
                             f"{MODE_LETTERS!r}, one per fixel)")
        why = topic_error(mode) if topic_error is not None else None
        if why:
            raise SceneError(f"modes: {mode!r} makes no valid topic name: {why}")
    frame = v["fixture_frame"]
    if not isinstance(frame, str) or not frame or len(frame) > MAX_FRAME_ID_LENGTH:
        raise SceneError(f"fixture_frame must be a non-empty string of at most "
                         f"{MAX_FRAME_ID_LENGTH} characters, got {str(frame)[:40]!r}")
    if v["workpiece.shape"] not in ("disc", "polygon"):
        raise SceneError("workpiece.shape must be 'disc' or 'polygon', got "
                         f"{str(v['workpiece.shape'])[:40]!r}")


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
