# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The node's parameters from one table: declarations, validation, parameters -> Scene.

:data:`SPECS` holds every parameter once (name, type, default, unit, description,
allowed range, read-only flag, group). Derived from it, and nowhere written again:

* the declarations (:func:`declare_parameters`) with their ``ParameterDescriptor``:
  description with unit and range, ``FloatingPointRange`` / ``IntegerRange`` (rclpy
  itself refuses an out-of-range value, with its reason, before any callback of the
  node), ``read_only``;
* the validation of a set of values (:func:`validate_values`): what the table says
  (types, ranges, choices, array lengths) for every parameter, then the checks no single
  row can say (:data:`CROSS_CHECKS`: the workpiece, the uncertainty set, the monitored
  modes, the fixture frame), each a small named function;
* ``config/wrenchcone.yaml`` and the parameters table of ``docs/node.md``
  (:mod:`.parameter_files`, ``python -m wrenchcone_ros.node.parameter_files``).

Everything here is a plain function of a node (declare/read) or of a dict of values
(name -> value, as :func:`read_values` returns it), so validation and the scene build can
run on a candidate set of values before it is accepted. To add a parameter: add its row
to :data:`SPECS` (and, if it depends on others, a check to :data:`CROSS_CHECKS`), then
regenerate the two files.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from rcl_interfaces.msg import (
    FloatingPointRange,
    IntegerRange,
    ParameterDescriptor,
    ParameterType,
)
from rclpy.exceptions import (
    InvalidParameterTypeException,
    InvalidParameterValueException,
    ParameterNotDeclaredException,
    ParameterUninitializedException,
)
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
from wrenchcone_ros.core.uncertainty import (
    NOMINAL,
    Uncertainty,
    UncertaintyError,
    load_uncertainty,
)
from wrenchcone_ros.core.tolerances import (
    MAX_COORDINATE_M,
    MAX_FRICTION,
    MAX_MASS_INERTIA,
    MIN_MASS_INERTIA,
)
from wrenchcone_ros.node import rclpy_boundary

MODE_LETTERS = "".join(MODE_TABLE)
#: At most this many modes may be monitored (each is a topic and a cone per update).
MAX_MONITORED_MODES = 64
#: Largest accepted timeouts and durations (s) of the node's own parameters.
MAX_TIMEOUT_S = 1e6
MAX_FRAME_ID_LENGTH = 256
#: Largest max_publish_rate (Hz).
MAX_PUBLISH_RATE_HZ = 1e6
#: Largest pose_reuse_window (s): a reply's pose may be at most this much older than
#: the newest pose received (the target for a 1 kHz stream is 10 ms, p99).
MAX_POSE_REUSE_WINDOW_S = 0.1
#: Default pose_reuse_window (s): half the 10 ms budget of a reply's pose, and longer
#: than the publishing worker's step for 16 modes (1-3 ms at 1 kHz), so that a request
#: under a 1 kHz stream is answered from the cones the worker computed already.
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
#: Default stamp_reset_threshold (s): a pose or fixels stamp older than the last accepted
#: one of its input by more than this resets that input's history.
DEFAULT_STAMP_RESET_THRESHOLD_S = 1.0

#: The ROS type of each table type name.
TYPES = {
    "string": ParameterType.PARAMETER_STRING,
    "double": ParameterType.PARAMETER_DOUBLE,
    "int": ParameterType.PARAMETER_INTEGER,
    "bool": ParameterType.PARAMETER_BOOL,
    "double[]": ParameterType.PARAMETER_DOUBLE_ARRAY,
    "string[]": ParameterType.PARAMETER_STRING_ARRAY,
}
#: The groups of the table, in order, with their heading (config file and docs).
GROUPS = {
    "start": "Start-up (read-only once the node runs)",
    "scene": "Scene: defaults from scene_file (without one, the values shown)",
    "uncertainty": "Uncertain models: defaults from scene_file's uncertainty: block",
    "inputs": "Inputs: frames, tolerances, staleness",
    "limits": "Request limits",
    "outputs": "Published outputs",
}


class _FromScene:
    """The default of a scene parameter: the scene file's value (:func:`scene_defaults`)."""

    def __repr__(self) -> str:
        return "FROM_SCENE"


#: Default of the scene parameters: taken from ``scene_file`` (without one, from the
#: built-in scene, :func:`wrenchcone_ros.core.default_scene`).
FROM_SCENE: Any = _FromScene()


@dataclass(frozen=True)
class ParameterSpec:
    """One parameter of the node. ``default`` None: declared with its type and no value;
    :data:`FROM_SCENE`: the scene file's. A range ``[low, high]`` bounds a number (of an
    array: each element); rclpy's ranges are closed, so ``low_open`` / ``high_open``
    (a strict bound) is checked by :func:`validate_values` only. ``min_nonzero``: 0 means
    off, any other value is at least this. ``read_only``: rclpy refuses a change once
    declared (given at start only); ``start_only``: read when the node starts (implied
    by ``read_only``)."""

    name: str
    type: str
    default: Any
    unit: str
    description: str
    group: str
    low: float | None = None
    high: float | None = None
    step: float = 0
    low_open: bool = False
    high_open: bool = False
    min_nonzero: float | None = None
    choices: tuple[str, ...] = ()
    length: int | None = None
    read_only: bool = False
    start_only: bool = False
    example: Any = None
    see: str = ""

    def __post_init__(self) -> None:
        if self.type not in TYPES or self.group not in GROUPS:
            raise ValueError(f"{self.name}: type {self.type!r} / group {self.group!r}")
        if self.read_only and not self.start_only:
            object.__setattr__(self, "start_only", True)

    @property
    def ros_type(self) -> int:
        return TYPES[self.type]

    @property
    def is_number(self) -> bool:
        return self.type in ("double", "int", "double[]")

    def allowed(self) -> str:
        """What values are allowed, in words (descriptor, docs, refusals)."""
        if self.choices:
            return " or ".join(repr(c) for c in self.choices)
        if self.low is None and self.high is None:
            return {"bool": "true or false", "string": "a string",
                    "string[]": "a list of strings"}.get(self.type, "")
        lo = "(" if self.low_open else "["
        hi = ")" if self.high_open else "]"
        interval = f"{lo}{_num(self.low)}, {_num(self.high)}{hi}"
        if self.min_nonzero is not None:
            interval = f"0 (off) or [{_num(self.min_nonzero)}, {_num(self.high)}{hi}"
        if self.type == "int":
            return f"an integer in {interval}"
        if self.type == "double":
            return f"a finite number in {interval}"
        count = f"{self.length} numbers" if self.length else "numbers"
        return f"{count}, each in {interval}"

    def contains(self, x: float) -> bool:
        """Whether the number ``x`` (an element of an array) lies in the range."""
        if not math.isfinite(x):
            return False
        if self.low is not None and (x < self.low or (self.low_open and x == self.low)):
            return False
        if self.high is not None and (x > self.high or (self.high_open and x == self.high)):
            return False
        return not (self.min_nonzero is not None and 0 < x < self.min_nonzero)


def _num(x: float | None) -> str:
    if x is None:
        return "-inf"
    if x == math.pi / 2:
        return "pi/2"
    if x == math.pi:
        return "pi"
    return f"{x:g}"


_M = "m"
_S = "s"
_HZ = "Hz"
#: Every parameter the node declares (besides rclpy's own use_sim_time and
#: start_type_description_service, and the QoS override parameters of its subscriptions).
SPECS: tuple[ParameterSpec, ...] = (
    # --- start-up ---------------------------------------------------------------------
    ParameterSpec(
        "scene_file", "string", "", "",
        "Core YAML scene to start from: the workpiece, the initial pose, the fixels (radii, "
        "friction), the monitored modes, and the defaults of the scene and uncertainty "
        "parameters. Empty: no built-in scene; the node answers NO_INPUTS until the "
        "user's pose and fixels arrive, and the workpiece then comes from the workpiece.* "
        "parameters.", "start", read_only=True),
    ParameterSpec(
        "autostart", "bool", True, "",
        "The lifecycle node configures and activates itself when it is constructed, so "
        "that ros2 run gives a working node; false: it stays unconfigured until a "
        "lifecycle manager (or ros2 lifecycle set) configures and activates it.", "start",
        read_only=True),
    ParameterSpec(
        "worker_nice", "int", DEFAULT_WORKER_NICE, "",
        "Scheduling niceness of the publishing worker thread (Linux, per thread; 0: as the "
        "node), so that it yields the CPU to the service threads and to other processes; "
        "where lowering the priority is not allowed, a warning says so.", "start",
        low=0, high=MAX_WORKER_NICE, read_only=True),
    ParameterSpec(
        "request_lane", "bool", True, "",
        "check_wrench and get_cone are served from a thread of the node's own with a wait "
        "set of those two services alone (requests that compute long on its pool), "
        "beside the executor that spins the node; false: they run on that executor like "
        "every other callback (a reentrant callback group).", "start", read_only=True),
    # --- scene ------------------------------------------------------------------------
    ParameterSpec(
        "workpiece.mass", "double", FROM_SCENE, "kg", "Workpiece mass.", "scene",
        low=MIN_MASS_INERTIA, high=MAX_MASS_INERTIA),
    ParameterSpec(
        "workpiece.inertia", "double", FROM_SCENE, "kg m^2",
        "Moment of inertia of the workpiece about its centre of mass.", "scene",
        low=MIN_MASS_INERTIA, high=MAX_MASS_INERTIA),
    ParameterSpec(
        "workpiece.com", "double[]", FROM_SCENE, _M,
        "Centre of mass [x, y] in the workpiece frame.", "scene",
        low=-MAX_COORDINATE_M, high=MAX_COORDINATE_M, length=2),
    ParameterSpec(
        "workpiece.shape", "string", FROM_SCENE, "",
        "Workpiece shape: disc (centred at the workpiece-frame origin) or polygon.",
        "scene", choices=("disc", "polygon")),
    ParameterSpec(
        "workpiece.radius", "double", FROM_SCENE, _M,
        "Disc radius, used when workpiece.shape is disc (checked whatever the shape).",
        "scene", low=0.0, high=MAX_COORDINATE_M, low_open=True),
    ParameterSpec(
        "workpiece.vertices", "double[]", FROM_SCENE, _M,
        "Polygon vertices flattened [x1, y1, x2, y2, ...] in the workpiece frame, "
        "counter-clockwise, simple, at least 3; used when workpiece.shape is polygon.",
        "scene", low=-MAX_COORDINATE_M, high=MAX_COORDINATE_M,
        example=[0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0]),
    ParameterSpec(
        "friction", "double", FROM_SCENE, "",
        "Coulomb friction coefficient mu of every fixel; setting it replaces the scene "
        "file's per-fixel values.", "scene", low=0.0, high=MAX_FRICTION),
    ParameterSpec(
        "contact_tolerance", "double", FROM_SCENE, _M,
        "A fixel with |gap| <= this is in contact (gap > this: free; gap < -this: a "
        "penetration, refused). For a pose measured by a vision system or another sensor, "
        "set it on the scale of the sensor's error (e.g. 2e-3 m for millimetre noise): "
        "1e-9 m refuses a pose that penetrates a fixel by 1 mm.", "scene",
        low=0.0, high=MAX_COORDINATE_M, low_open=True),
    ParameterSpec(
        "modes", "string[]", FROM_SCENE, "",
        f"Concrete modes (letters {MODE_LETTERS}, one per fixel) whose cone is published "
        f"on ~/cone/<mode>, drawn in ~/markers and reported in /diagnostics; at most "
        f"{MAX_MONITORED_MODES}, each a valid topic name.", "scene"),
    # --- uncertainty ------------------------------------------------------------------
    ParameterSpec(
        "uncertainty.friction", "double[]", FROM_SCENE, "",
        "Interval [lo, hi] of every fixel's mu (each fixel independently), or one interval "
        "per fixel, flattened [lo1, hi1, lo2, hi2, ...] (then the fixture must have that "
        "many fixels: a fixture of another count gets SCENE_ERROR, never a guess); empty: "
        "the nominal value. With any uncertainty.* set, force_directions, check_wrench, "
        "get_cone and the cone topics answer for every model of the set.", "uncertainty",
        low=0.0, high=MAX_FRICTION, example=[0.2, 0.4], see="Uncertain models"),
    ParameterSpec(
        "uncertainty.mass", "double[]", FROM_SCENE, "kg",
        "Interval [lo, hi] of the workpiece mass; empty: the nominal value.",
        "uncertainty", low=0.0, high=MAX_MASS_INERTIA, length=2, example=[0.9, 1.1]),
    ParameterSpec(
        "uncertainty.inertia", "double[]", FROM_SCENE, "kg m^2",
        "Interval [lo, hi] of the inertia about the centre of mass; empty: the nominal "
        "value.", "uncertainty", low=0.0, high=MAX_MASS_INERTIA, length=2,
        example=[0.9, 1.1]),
    ParameterSpec(
        "uncertainty.com_radius", "double", FROM_SCENE, _M,
        "The centre of mass anywhere within this distance of its nominal place; 0: exact.",
        "uncertainty", low=0.0, high=MAX_COORDINATE_M),
    ParameterSpec(
        "uncertainty.normal_error", "double", FROM_SCENE, "rad",
        "Each contact normal turned by up to +- this; 0: exact.", "uncertainty",
        low=0.0, high=math.pi / 2, high_open=True),
    # --- inputs -----------------------------------------------------------------------
    ParameterSpec(
        "fixel_radius", "double[]", None, _M,
        "Radii of the fixels received as a geometry_msgs/PoseArray on fixel_poses (which "
        "carries positions only): one radius for every fixel, or one per fixel in pose "
        "order. Empty (the default): a PoseArray is refused, never given radii guessed "
        "from the scene file; a wrenchcone_msgs/Fixels message on fixels carries its own "
        "radii and ignores this.", "inputs", low=0.0, high=MAX_COORDINATE_M,
        example=[0.003, 0.004, 0.004], see="Inputs"),
    ParameterSpec(
        "fixture_frame", "string", "world", "",
        f"frame_id that every workpiece_pose and fixels message must carry (the fixture "
        f"frame); non-empty, at most {MAX_FRAME_ID_LENGTH} characters.", "inputs"),
    ParameterSpec(
        "tilt_tolerance", "double", conv.TILT_TOLERANCE_RAD, "rad",
        "Largest tilt of a pose's orientation out of the fixture plane.", "inputs",
        low=0.0, high=math.pi),
    ParameterSpec(
        "out_of_plane_tolerance", "double", conv.OUT_OF_PLANE_TOLERANCE, "",
        "Largest |(force.z, torque.x/L, torque.y/L)| / |(force.x, force.y, torque.z/L)| "
        "of a wrench in a request (L: the workpiece's characteristic length).", "inputs",
        low=0.0, high=1e6, see="Conventions"),
    ParameterSpec(
        "wait_for_inputs", "bool", False, "",
        "True: answer NO_INPUTS until a pose and a fixels message have arrived; false: "
        "the scene file's pose and fixels are used until then (without scene_file the "
        "node always waits for both).", "inputs"),
    ParameterSpec(
        "input_timeout", "double", 1.0, _S,
        "Age (node clock: respects use_sim_time) after which a received pose is stale: "
        "answers from it get STALE_INPUTS, and the cone topics STALE_INPUTS with no rows; "
        "0: never stale.", "inputs", low=0.0, high=MAX_TIMEOUT_S),
    ParameterSpec(
        "fixels_timeout", "double", 0.0, _S,
        "As input_timeout, for the fixels message (fixtures are often published once, so "
        "0, never stale, by default).", "inputs", low=0.0, high=MAX_TIMEOUT_S),
    ParameterSpec(
        "stamp_reset_threshold", "double", DEFAULT_STAMP_RESET_THRESHOLD_S, _S,
        "A pose or fixels message stamped older than the last accepted one of its input "
        "by more than this (a recorded run played in a loop, a simulation reset) resets "
        "that input's history, with one log line, instead of being refused as out of "
        "order.", "inputs", low=0.0, high=MAX_TIMEOUT_S),
    ParameterSpec(
        "max_fixels", "int", 32, "",
        "Most fixels a fixels message may carry; more: the message is refused (one log "
        "line).", "inputs", low=1, high=100_000),
    # --- limits -----------------------------------------------------------------------
    ParameterSpec(
        "max_mode_length", "int", 64, "",
        "Longest mode string a request (or a monitored mode) may carry; longer: "
        "LIMIT_EXCEEDED before any parsing.", "limits", low=1, high=100_000),
    ParameterSpec(
        "max_concrete_modes", "int", 64, "",
        "Most concrete modes one wildcard mode of a request may expand to (counted before "
        "expanding); more: LIMIT_EXCEEDED.", "limits", low=1, high=10_000_000),
    ParameterSpec(
        "max_classify_nodes", "int", 2000, "",
        "Most nodes of the mode search one classification (classify_wrench, check_wrench "
        "with classify) may visit; more: LIMIT_EXCEEDED. Under uncertainty.*: the modes "
        "of the scene times the models computed, refused before computing.", "limits",
        low=1, high=100_000_000),
    ParameterSpec(
        "max_request_time", "double", 0.05, _S,
        "Computation one check_wrench or get_cone request may take; more: LIMIT_EXCEEDED; "
        "0: no limit. classify_wrench and force_directions run in callback groups of their "
        "own without a time limit (their size is bounded by the limits above).", "limits",
        low=0.0, high=MAX_TIMEOUT_S),
    ParameterSpec(
        "pose_reuse_window", "double", DEFAULT_POSE_REUSE_WINDOW_S, _S,
        "A service request is answered from the current snapshot (its cones are cached) "
        "when the newest pose arrived at most this long after that snapshot's pose; else, and after any fixel or "
        "parameter change, from the newest inputs. The reply's pose_stamp says which "
        "pose was used. 0: always the newest pose.", "limits",
        low=0.0, high=MAX_POSE_REUSE_WINDOW_S),
    # --- outputs ----------------------------------------------------------------------
    ParameterSpec(
        "publish_markers", "bool", True, "",
        "Publish ~/markers (visualization_msgs/MarkerArray, latched) for RViz; false "
        "clears them once and computes none.", "outputs"),
    ParameterSpec(
        "max_publish_rate", "double", 0.0, _HZ,
        "Most snapshots per second the cone topics and markers are published for; 0: as "
        "fast as the monitored cones can be computed. A cap lowers the node's CPU under "
        "fast pose streams at the cost of up to 1 / rate of lag.", "outputs",
        low=0.0, high=MAX_PUBLISH_RATE_HZ, min_nonzero=MIN_RATE_HZ),
    ParameterSpec(
        "diagnostics_rate", "double", 1.0, _HZ,
        "Rate of the node's /diagnostics status; 0: none.", "outputs",
        low=0.0, high=MAX_DIAGNOSTICS_RATE_HZ, min_nonzero=MIN_RATE_HZ),
)
#: name -> its row of :data:`SPECS`.
SPEC: dict[str, ParameterSpec] = {s.name: s for s in SPECS}
#: Every parameter the node declares, in table order.
PARAMETERS: tuple[str, ...] = tuple(SPEC)
#: Parameters rclpy declares itself (not reported as unknown when given at start).
RCLPY_PARAMETERS = ("use_sim_time", "start_type_description_service")
#: Prefix of rclpy's QoS override parameters (declared with the subscriptions).
QOS_OVERRIDES_PREFIX = "qos_overrides."
#: Parameters declared as double (array): an integer given for one is taken as that
#: double (``-p friction:=1`` means 1.0).
DOUBLE_PARAMETERS = frozenset(s.name for s in SPECS if s.type == "double")
DOUBLE_ARRAY_PARAMETERS = frozenset(s.name for s in SPECS if s.type == "double[]")


def descriptor(spec: ParameterSpec) -> ParameterDescriptor:
    """The ParameterDescriptor of a row: description with unit, allowed values, range
    (FloatingPointRange / IntegerRange for a scalar number, so rclpy refuses an
    out-of-range value itself), read-only flag. A new object each time (rclpy writes
    into the descriptor it is given)."""
    d = ParameterDescriptor(
        name=spec.name, type=spec.ros_type, description=descriptor_text(spec),
        additional_constraints=spec.allowed(), read_only=spec.read_only)
    if spec.type == "double" and spec.low is not None and spec.high is not None:
        d.floating_point_range = [FloatingPointRange(
            from_value=float(spec.low), to_value=float(spec.high), step=float(spec.step))]
    elif spec.type == "int" and spec.low is not None and spec.high is not None:
        d.integer_range = [IntegerRange(from_value=int(spec.low), to_value=int(spec.high),
                                        step=int(spec.step))]
    return d


def descriptor_text(spec: ParameterSpec) -> str:
    """The description of a row as the descriptor, the config file and ``ros2 param
    describe`` show it: the text, the unit, what is read-only, where the docs say more."""
    text = spec.description
    if spec.unit:
        text += f" Unit: {spec.unit}."
    if spec.read_only:
        text += " Read-only: given at start only."
    if spec.default is FROM_SCENE:
        text += " Default: scene_file's."
    if spec.see:
        text += f" See docs/node.md, {spec.see}."
    return text


# --- declaration -----------------------------------------------------------------------
def _as_double(param: Parameter) -> Parameter:
    """An integer (array) parameter for a double (array) one, as that double (array)."""
    if param.name in DOUBLE_PARAMETERS and param.type_ == Parameter.Type.INTEGER:
        return Parameter(param.name, Parameter.Type.DOUBLE, float(param.value))
    if (param.name in DOUBLE_ARRAY_PARAMETERS
            and param.type_ == Parameter.Type.INTEGER_ARRAY):
        return Parameter(param.name, Parameter.Type.DOUBLE_ARRAY,
                         [float(v) for v in param.value])
    return param


def is_known(name: str) -> bool:
    """Whether ``name`` is a parameter of the node (its table, rclpy's own, a QoS
    override)."""
    return name in SPEC or name in RCLPY_PARAMETERS or name.startswith(QOS_OVERRIDES_PREFIX)


def closest_names(name: str, n: int = 3) -> list[str]:
    """The declared names closest to ``name`` (difflib), best first."""
    return difflib.get_close_matches(name, PARAMETERS + RCLPY_PARAMETERS, n=n, cutoff=0.6)


class UnknownParameterError(ParameterNotDeclaredException):
    """A set of a name the node does not declare. A ParameterNotDeclaredException (what
    rclpy raises, and what its parameter services turn into the refusal's reason) whose
    message names the parameter and the closest declared names."""

    def __init__(self, name: str) -> None:
        close = closest_names(name)
        hint = (f"did you mean {' or '.join(repr(c) for c in close)}?" if close
                else "no declared name is close")
        Exception.__init__(
            self, f"{name!r} is not a parameter of this node ({hint}); `ros2 param list` "
            "and docs/node.md (Parameters) list its parameters")
        self.name = name


def coerce_types(parameters: list[Parameter]) -> list[Parameter]:
    """Pre-set callback (``add_pre_set_parameters_callback``): integers given for double
    parameters become doubles; a name the node does not declare is refused with
    :class:`UnknownParameterError`, naming the closest declared names (rclpy's own check
    comes later and says "Invalid access to undeclared parameter(s): []")."""
    for p in parameters:
        if not is_known(p.name):
            raise UnknownParameterError(p.name)
    return [_as_double(p) for p in parameters]


def scene_defaults(base: Scene, path: str) -> dict[str, Any]:
    """The defaults of the :data:`FROM_SCENE` parameters: the values of scene ``base``
    (loaded from ``path``; the built-in scene when empty) and of ``path``'s
    ``uncertainty:`` block. SceneError naming scene_file when the block is one the node
    cannot take."""
    try:
        u = load_uncertainty(path) if path else None
    except UncertaintyError as exc:
        raise SceneError(f"parameter scene_file: {exc}") from None
    d = u.to_dict() if u is not None else {}
    if isinstance(d.get("normal_error"), list) or "com_box" in d:
        raise SceneError("parameter scene_file: the node takes one normal_error and a "
                         "com_radius (per-fixel normal errors and com_box: the core and "
                         "the CLI)")
    if d.get("friction") and isinstance(d["friction"][0], list) or (
            d.get("friction") and d["friction"][0] is None):
        # one interval per fixel (null: the fixel's nominal mu), flattened
        try:
            d["friction"] = [x for iv in u.friction_intervals(base) for x in iv]
        except UncertaintyError as exc:
            raise SceneError(f"parameter scene_file: {exc}") from None
    wp = base.workpiece
    shape = wp.shape
    is_disc = isinstance(shape, Disc)
    return {
        "workpiece.mass": float(wp.mass),
        "workpiece.inertia": float(wp.inertia),
        "workpiece.com": [float(v) for v in wp.com],
        "workpiece.shape": "disc" if is_disc else "polygon",
        "workpiece.radius": float(shape.radius) if is_disc else 1.0,
        "workpiece.vertices": None if is_disc else [float(c) for v in shape.vertices
                                                    for c in v],
        "friction": float(base.friction),
        "contact_tolerance": float(base.contact_tolerance),
        # without a scene file no mode is monitored until the user says which
        "modes": list(base.modes) if path else [],
        **{f"uncertainty.{k}": [float(x) for x in d[k]] if d.get(k) else None
           for k in ("friction", "mass", "inertia")},
        "uncertainty.com_radius": float(d.get("com_radius") or 0.0),
        "uncertainty.normal_error": float(d.get("normal_error") or 0.0),
    }


def builtin_defaults() -> dict[str, Any]:
    """Every parameter's default without scene_file (the docs and the config file)."""
    scene = scene_defaults(default_scene(), "")
    return {s.name: scene[s.name] if s.default is FROM_SCENE else s.default for s in SPECS}


def _declare(node: Node, spec: ParameterSpec, default: Any,
             overrides: Mapping[str, Parameter]) -> None:
    """Declare one row: the value given at start (an integer for a double taken as that
    double), else ``default``; a value rclpy refuses (type, range) is a SceneError naming
    the parameter, rclpy's reason and what is allowed."""
    value = _as_double(overrides[spec.name]).value if spec.name in overrides else default
    if value is None or (isinstance(value, (list, tuple)) and not value):
        value = Parameter.Type(spec.ros_type)  # declared with its type, no value
    try:
        node.declare_parameter(spec.name, value, descriptor(spec), ignore_override=True)
    except (InvalidParameterValueException, InvalidParameterTypeException) as exc:
        raise SceneError(f"parameter {spec.name}: {exc}; allowed: {spec.allowed()}") \
            from None


def declare_parameters(node: Node) -> Scene:
    """Declare every parameter of :data:`SPECS` on the node; return the base scene
    (parameter scene_file; the built-in scene when it is empty)."""
    overrides = rclpy_boundary.parameter_overrides(node)
    _declare(node, SPEC["scene_file"], "", overrides)
    path = node.get_parameter("scene_file").value
    try:
        base = load_scene(path) if path else default_scene()
    except SceneError as exc:
        raise SceneError(f"parameter scene_file: {exc}") from None
    from_scene = scene_defaults(base, path)
    for spec in SPECS:
        if spec.name != "scene_file":
            default = from_scene[spec.name] if spec.default is FROM_SCENE else spec.default
            _declare(node, spec, default, overrides)
    return base


def unknown_start_parameters(node: Node) -> list[str]:
    """Names given to the node at start (a ``--params-file``, ``-p name:=value``,
    parameter_overrides) that it does not declare: misspellings, silently ignored by ROS.

    rclpy has no public getter of those values (:func:`.rclpy_boundary.parameter_overrides`);
    without one the answer is empty, never wrong."""
    given = rclpy_boundary.parameter_overrides(node)
    return sorted(name for name in given if not is_known(name))


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


# --- values -> scene -------------------------------------------------------------------
def uncertainty_from_values(v: dict[str, Any]) -> Uncertainty:
    """The Uncertainty of the ``uncertainty.*`` values (:data:`NOMINAL`, the zero-width
    uncertainty, when none is set); SceneError naming the parameter when a value is
    wrong."""
    kw: dict[str, Any] = {}
    for name in ("friction", "mass", "inertia"):
        value = list(v[f"uncertainty.{name}"] or [])
        if value:
            kw[name] = value
    friction = kw.get("friction")
    if friction is not None and len(friction) != 2:
        if len(friction) % 2:
            raise SceneError(f"parameter uncertainty.friction must hold [lo, hi] or one "
                             f"[lo, hi] per fixel, flattened (an even count), got "
                             f"{len(friction)} number(s)")
        kw["friction"] = [friction[k:k + 2] for k in range(0, len(friction), 2)]
    for name in ("com_radius", "normal_error"):
        if v[f"uncertainty.{name}"]:
            kw[name] = v[f"uncertainty.{name}"]
    if not kw:
        return NOMINAL
    try:
        return Uncertainty(**kw)
    except UncertaintyError as exc:
        raise SceneError(f"parameters uncertainty.*: {exc}") from None


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


# --- validation ------------------------------------------------------------------------
def _is_number(x: Any, integer: bool) -> bool:
    if isinstance(x, bool):
        return False
    return isinstance(x, int) if integer else isinstance(x, (int, float))


def _is_sequence(x: Any) -> bool:
    """A list, tuple or array.array (rclpy's arrays), not a string."""
    return isinstance(x, Sequence) and not isinstance(x, (str, bytes))


def check_row(spec: ParameterSpec, x: Any) -> None:
    """What the table says about one value: its type, choices, range (of each element of
    an array), array length. SceneError naming the parameter and what is allowed."""
    def refuse(got: Any) -> SceneError:
        return SceneError(f"{spec.name} must be {spec.allowed()}, got {str(got)[:60]}")

    if spec.type == "bool":
        if not isinstance(x, bool):
            raise refuse(repr(x))
    elif spec.type == "string":
        if not isinstance(x, str) or (spec.choices and x not in spec.choices):
            raise refuse(repr(x))
    elif spec.type in ("double", "int"):
        if not _is_number(x, spec.type == "int") or not spec.contains(float(x)):
            raise refuse(repr(x))
    elif x is None:  # an array declared without a value
        return
    elif not _is_sequence(x):
        raise refuse(repr(x))
    elif spec.type == "string[]":
        if not all(isinstance(e, str) for e in x):
            raise refuse(repr(list(x)))
    else:  # double[]
        items = list(x)
        for k, e in enumerate(items):
            if not _is_number(e, False) or not spec.contains(float(e)):
                raise SceneError(f"{spec.name}[{k}] must be a finite number in "
                                 f"[{_num(spec.low)}, {_num(spec.high)}], got {e!r}")
        if spec.length is not None and items and len(items) != spec.length:
            raise refuse(f"{len(items)} number(s)")


def check_workpiece(v: dict[str, Any], topic_error: Any = None) -> None:
    """The workpiece the ``workpiece.*`` values make (the core's limits: the disc radius
    whatever the shape, a simple counter-clockwise polygon of >= 3 vertices)."""
    Disc(v["workpiece.radius"])
    workpiece_from_values(v)


def check_uncertainty(v: dict[str, Any], topic_error: Any = None) -> None:
    """The uncertainty set the ``uncertainty.*`` values make (lo <= hi, positive mass)."""
    uncertainty_from_values(v)


def check_modes(v: dict[str, Any],
                topic_error: Callable[[str], str | None] | None = None) -> None:
    """The monitored modes: at most :data:`MAX_MONITORED_MODES`, each concrete, of mode
    letters, no longer than max_mode_length, and a valid topic name ``~/cone/<mode>``
    (``topic_error(mode)`` says why not, None if it is)."""
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
                             f"concrete modes (letters {MODE_LETTERS!r})")
        if any(c not in MODE_TABLE for c in mode):
            raise SceneError(f"modes: {mode!r} is not a mode string (letters "
                             f"{MODE_LETTERS!r}, one per fixel)")
        why = topic_error(mode) if topic_error is not None else None
        if why:
            raise SceneError(f"modes: {mode!r} makes no valid topic name: {why}")


def check_fixture_frame(v: dict[str, Any], topic_error: Any = None) -> None:
    """fixture_frame: a frame id, non-empty and at most :data:`MAX_FRAME_ID_LENGTH`."""
    frame = v["fixture_frame"]
    if not frame or len(frame) > MAX_FRAME_ID_LENGTH:
        raise SceneError(f"fixture_frame must be a non-empty string of at most "
                         f"{MAX_FRAME_ID_LENGTH} characters, got {str(frame)[:40]!r}")


#: The checks no single row of the table can say, run after every row's check.
CROSS_CHECKS = (check_fixture_frame, check_workpiece, check_uncertainty, check_modes)


def validate_values(v: dict[str, Any],
                    topic_error: Callable[[str], str | None] | None = None) -> None:
    """Raise SceneError if the values are wrong, whatever the pose and fixels; the message
    says what is wrong and what is allowed. Every row is checked (:func:`check_row`),
    including the values used only later (the radius while the shape is a polygon, the
    vertices while it is a disc), then :data:`CROSS_CHECKS`."""
    for spec in SPECS:
        check_row(spec, v[spec.name])
    for check in CROSS_CHECKS:
        check(v, topic_error)


@dataclass(frozen=True)
class FixelPositions:
    """Fixel positions received without radii (a PoseArray on ``fixel_poses``): their
    radii are parameter ``fixel_radius``'s, applied when a scene is built, so that a new
    ``fixel_radius`` applies to them at once.

    Parameters
    ----------
    positions : tuple of (float, float)
        The fixel centres (m, fixture frame), in pose order.
    """

    positions: tuple[tuple[float, float], ...]

    def with_radii(self, radii: Sequence[float] | None) -> tuple[Fixel, ...]:
        """The fixels with ``radii`` (one for all, or one per fixel).

        Parameters
        ----------
        radii : sequence of float or None
            Parameter ``fixel_radius`` (m).

        Returns
        -------
        tuple of Fixel
            One per position, without friction of its own.

        Raises
        ------
        SceneError
            No radius, or a count neither 1 nor the number of positions.
        """
        n, radii = len(self.positions), list(radii or [])
        if len(radii) not in (1, n):
            raise SceneError(
                f"the fixels received on fixel_poses (a PoseArray: positions only) are "
                f"{n} and parameter fixel_radius gives {len(radii)} radii: set one radius "
                f"(m) for all fixels or exactly {n}, or publish wrenchcone_msgs/Fixels on "
                f"fixels")
        return tuple(Fixel(p, radii[0] if len(radii) == 1 else radii[k])
                     for k, p in enumerate(self.positions))


def build_scene(base: Scene, v: dict[str, Any], pose: tuple[float, float, float],
                fixels: Sequence[Fixel] | FixelPositions | None) -> Scene:
    """The Scene of parameter values ``v``, a pose and the fixture received.

    Parameters
    ----------
    base : Scene
        The scene file's scene (the built-in one without a file).
    v : dict
        Parameter values (:func:`read_values`).
    pose : (x, y, theta)
        The workpiece pose (m, m, rad).
    fixels : sequence of Fixel, FixelPositions or None
        The fixture received: fixels with their radii and friction (a
        wrenchcone_msgs/Fixels message: each fixel keeps the friction it carries, the
        others get parameter ``friction``), positions whose radii are ``fixel_radius``'s
        (a PoseArray), or None: the scene file's fixels (parameter ``friction``, once set
        to another value than the file's, replaces their per-fixel values).

    Returns
    -------
    Scene
        The scene.

    Raises
    ------
    SceneError
        The values, pose and fixels make no valid scene.
    """
    friction = v["friction"]
    if isinstance(fixels, FixelPositions):
        fixels = fixels.with_radii(v["fixel_radius"])
    elif fixels is None:
        fixels = base.fixels
        if friction != base.friction:  # a set friction applies to all of the file's fixels
            fixels = tuple(Fixel(f.position, f.radius) for f in fixels)
    return Scene(workpiece=workpiece_from_values(v), fixels=tuple(fixels), friction=friction,
                 pose=pose, contact_tolerance=v["contact_tolerance"],
                 modes=tuple(m for m in v["modes"] if m))


def fixture_agrees(uncertainty: Uncertainty, scene: Scene) -> None:
    """Whether the uncertainty parameters fit the fixture: per-fixel friction intervals
    name exactly the scene's fixels.

    Parameters
    ----------
    uncertainty : Uncertainty
        The uncertainty set of the parameters.
    scene : Scene
        The scene of the current inputs.

    Raises
    ------
    SceneError
        uncertainty.friction gives one interval per fixel for another number of fixels.
    """
    f = uncertainty.friction
    if f is not None and not isinstance(f[0], (int, float)) and len(f) != scene.n_fixels:
        raise SceneError(
            f"parameter uncertainty.friction gives {len(f)} per-fixel interval(s) "
            f"({2 * len(f)} numbers) but the fixture has {scene.n_fixels} fixel(s): set "
            f"uncertainty.friction to [lo, hi] or {2 * scene.n_fixels} numbers, or "
            f"publish a fixture of {len(f)} fixels")
