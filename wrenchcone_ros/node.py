"""ROS 2 node ``wrenchcone``: pose and fixels in, wrench cones out.

Data flow (one way): messages / parameters -> immutable :class:`Snapshot` (a Scene and
the stamps of the inputs it was built from, with a version number) -> (snapshot, mode)
-> Cone (cached in the snapshot) -> service answers and published F.

* Subscribes ``workpiece_pose`` (geometry_msgs/PoseStamped) and ``fixels``
  (geometry_msgs/PoseArray), both in the fixture frame (parameter ``fixture_frame``).
* Services ``~/check_wrench`` (wrenchcone_ros/srv/CheckWrench; wildcard modes and an
  optional classification over all modes), ``~/get_cone`` (wrenchcone_ros/srv/GetCone)
  and ``~/classify_wrench`` (wrenchcone_ros/srv/ClassifyWrench): answer for any mode,
  from one snapshot.
* Publishes ``~/cone/<mode>`` (std_msgs/Float64MultiArray, reliable + transient local,
  depth 1) for every mode in the ``modes`` parameter, each time the inputs change.

Every accepted input or parameter change makes a new snapshot; a snapshot is never
modified (its cone cache only grows), so an answer never mixes a pose from one update
with fixels from another. Nothing is computed for a mode that is neither requested nor
monitored. Bad input never raises out of a callback: services answer with a status code
and a message; refused topic messages are logged (at once when the reason changes, at
most every 5 s while it repeats) and leave the snapshot as it was. See docs/node.md for the full interface.
"""

from __future__ import annotations

import math
import threading
import time
from dataclasses import dataclass, field
from typing import Any

import rclpy
from geometry_msgs.msg import PoseArray, PoseStamped
from rcl_interfaces.msg import (
    FloatingPointRange,
    ParameterDescriptor,
    ParameterType,
    SetParametersResult,
)
from rclpy.exceptions import ParameterUninitializedException
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from std_msgs.msg import Float64MultiArray

from wrenchcone_ros import conversions as conv
from wrenchcone_ros.conversions import CheckWrench, ClassifyWrench, GetCone
from wrenchcone_ros.core import (
    MODE_TABLE,
    Cone,
    ConeUnion,
    Disc,
    Fixel,
    ModeError,
    ModeSyntaxError,
    Polygon,
    Scene,
    SceneError,
    Workpiece,
    default_scene,
    load_scene,
    wrench_cone,
)
from wrenchcone_ros.core.classify import ModeClassifier

NODE_NAME = "wrenchcone"
S = CheckWrench.Response  # status codes (GetCone uses the same values)
OK = S.OK
MODE_INFEASIBLE = S.MODE_INFEASIBLE
INVALID_MODE = S.INVALID_MODE
MODE_NOT_ALLOWED = S.MODE_NOT_ALLOWED
INVALID_WRENCH = S.INVALID_WRENCH
NO_INPUTS = S.NO_INPUTS
SCENE_ERROR = S.SCENE_ERROR
INTERNAL_ERROR = S.INTERNAL_ERROR
STATUS_NAMES = {
    OK: "OK", MODE_INFEASIBLE: "MODE_INFEASIBLE", INVALID_MODE: "INVALID_MODE",
    MODE_NOT_ALLOWED: "MODE_NOT_ALLOWED", INVALID_WRENCH: "INVALID_WRENCH",
    NO_INPUTS: "NO_INPUTS", SCENE_ERROR: "SCENE_ERROR", INTERNAL_ERROR: "INTERNAL_ERROR",
}

#: Latched cone topics: a late subscriber gets the current cone at once.
CONE_QOS = QoSProfile(depth=1, history=HistoryPolicy.KEEP_LAST,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL)
#: Inputs: the ROS default (reliable, volatile, depth 10).
INPUT_QOS = QoSProfile(depth=10, history=HistoryPolicy.KEEP_LAST,
                       reliability=ReliabilityPolicy.RELIABLE,
                       durability=DurabilityPolicy.VOLATILE)
#: At most this many answers are cached per snapshot (a client asking for many distinct
#: modes cannot grow the node's memory without bound).
CACHE_LIMIT = 1024
#: A refused input message of the same kind is logged at most once per this period.
REFUSAL_LOG_PERIOD_S = 5.0
MODE_LETTERS = "".join(MODE_TABLE)
#: Every parameter the node declares (besides rclpy's own use_sim_time).
PARAMETERS = (
    "scene_file", "fixture_frame", "workpiece.mass", "workpiece.inertia", "workpiece.com",
    "workpiece.shape", "workpiece.radius", "workpiece.vertices", "friction",
    "contact_tolerance", "fixel_radius", "modes", "tilt_tolerance", "out_of_plane_tolerance",
    "wait_for_inputs",
)


@dataclass(frozen=True)
class Answer:
    """The outcome of one (snapshot, mode): a status, a message and the cone if any."""

    status: int
    message: str
    cone: Cone | None = None
    union: ConeUnion | None = None  # a mode with wildcards: the union of its modes' cones


@dataclass(frozen=True)
class Snapshot:
    """One consistent, immutable version of the node's inputs."""

    version: int
    scene: Scene | None  # None when status != OK
    status: int  # OK, NO_INPUTS or SCENE_ERROR
    message: str
    frame_id: str
    pose_stamp: tuple[int, int] | None
    fixels_stamp: tuple[int, int] | None
    answers: dict = field(default_factory=dict, compare=False, repr=False)


def compute_answer(snapshot: Snapshot, mode: str) -> Answer:
    """The answer of (snapshot, mode), without caching. Never raises."""
    if snapshot.scene is None:
        return Answer(snapshot.status, snapshot.message)
    scene = snapshot.scene
    try:
        cone = wrench_cone(scene, mode)  # a ConeUnion for a mode with wildcards
    except ModeSyntaxError as exc:
        return Answer(INVALID_MODE, str(exc))
    except ModeError as exc:
        return Answer(MODE_NOT_ALLOWED, str(exc))
    except SceneError as exc:
        return Answer(SCENE_ERROR, str(exc))
    except Exception as exc:  # noqa: BLE001 - a service must answer, not die
        return Answer(INTERNAL_ERROR, f"cone computation failed: {type(exc).__name__}: {exc}")
    if isinstance(cone, ConeUnion):
        if not cone.feasible:
            return Answer(MODE_INFEASIBLE,
                          f"mode {mode!r} is infeasible: none of its modes "
                          f"{list(cone.impossible)} is realised by any wrench", union=cone)
        return Answer(OK, "", union=cone)
    if not cone.feasible:
        return Answer(MODE_INFEASIBLE,
                      f"mode {mode!r} is infeasible: no wrench realises it (no rigid-body "
                      "acceleration meets its strict conditions), so no wrench is "
                      "consistent with it", cone)
    return Answer(OK, "", cone)


def _descriptor(description: str, type_: int, *, read_only: bool = False,
                constraints: str = "", low: float | None = None,
                high: float | None = None) -> ParameterDescriptor:
    d = ParameterDescriptor(description=description, type=type_, read_only=read_only,
                            additional_constraints=constraints)
    if low is not None or high is not None:
        d.floating_point_range = [FloatingPointRange(
            from_value=-math.inf if low is None else low,
            to_value=math.inf if high is None else high, step=0.0)]
    return d


class WrenchConeNode(Node):
    """The wrench-cone node; see the module docstring and docs/node.md."""

    def __init__(self, node_name: str = NODE_NAME, **kwargs: Any) -> None:
        super().__init__(node_name, **kwargs)
        self._lock = threading.Lock()
        self._declare_parameters()
        self._out_of_plane_tolerance = self._p("out_of_plane_tolerance")
        self._pose: tuple[float, float, float] = self._base_scene.pose
        self._pose_stamp: tuple[int, int] | None = None
        self._fixel_positions: list[tuple[float, float]] | None = None  # None: scene's
        self._fixels_stamp: tuple[int, int] | None = None
        self._radius_overridden = False
        self._version = 0
        self._snapshot: Snapshot = Snapshot(0, None, NO_INPUTS, "starting", "", None, None)
        self._cone_pubs: dict[str, Any] = {}
        self._reported: dict[str, tuple[int, str]] = {}
        self._refusals: dict[str, tuple[list[str], float, int]] = {}

        self.add_on_set_parameters_callback(self._validate_parameters)
        self.add_post_set_parameters_callback(self._parameters_changed)

        self.create_subscription(PoseStamped, "workpiece_pose", self._on_pose, INPUT_QOS)
        self.create_subscription(PoseArray, "fixels", self._on_fixels, INPUT_QOS)
        self.create_service(CheckWrench, "~/check_wrench", self._on_check_wrench)
        self.create_service(GetCone, "~/get_cone", self._on_get_cone)
        self.create_service(ClassifyWrench, "~/classify_wrench", self._on_classify_wrench)
        self._sync_publishers()
        self._rebuild("start")
        snap = self._snapshot
        self.get_logger().info(
            f"ready: {snap.scene.n_fixels if snap.scene else '?'} fixel(s), frame "
            f"{self._p('fixture_frame')!r}, monitoring modes {self._values()['modes']}")

    # --- parameters -----------------------------------------------------------------
    def _declare_parameters(self) -> None:
        P = ParameterType
        path = self.declare_parameter(
            "scene_file", "", _descriptor(
                "Scene YAML (core schema) to start from; empty = the built-in default, the "
                "paper's disc example. Read at start only.", P.PARAMETER_STRING,
                read_only=True)).value
        try:
            self._base_scene = load_scene(path) if path else default_scene()
        except SceneError as exc:
            raise SceneError(f"parameter scene_file: {exc}") from None
        base = self._base_scene
        wp = base.workpiece
        shape = wp.shape
        radii = {f.radius for f in base.fixels}
        self.declare_parameter("fixture_frame", "world", _descriptor(
            "frame_id that pose and fixel messages must carry (the fixture frame).",
            P.PARAMETER_STRING))
        self.declare_parameter("workpiece.mass", float(wp.mass), _descriptor(
            "Workpiece mass (kg), > 0.", P.PARAMETER_DOUBLE, constraints="> 0, finite"))
        self.declare_parameter("workpiece.inertia", float(wp.inertia), _descriptor(
            "Moment of inertia about the centre of mass (kg m^2), > 0.", P.PARAMETER_DOUBLE,
            constraints="> 0, finite"))
        self.declare_parameter("workpiece.com", [float(v) for v in wp.com], _descriptor(
            "Centre of mass [x, y] in the workpiece frame (m).", P.PARAMETER_DOUBLE_ARRAY,
            constraints="2 finite numbers"))
        is_disc = isinstance(shape, Disc)
        self.declare_parameter("workpiece.shape", "disc" if is_disc else "polygon",
                               _descriptor("Workpiece shape: 'disc' or 'polygon'.",
                                           P.PARAMETER_STRING,
                                           constraints="'disc' or 'polygon'"))
        self.declare_parameter(
            "workpiece.radius", float(shape.radius) if is_disc else 1.0, _descriptor(
                "Disc radius (m), used when workpiece.shape is 'disc'.", P.PARAMETER_DOUBLE,
                constraints="> 0, finite"))
        vdesc = _descriptor(
            "Polygon vertices, flattened [x1, y1, x2, y2, ...] in the workpiece frame (m), "
            "counter-clockwise, simple; used when workpiece.shape is 'polygon'.",
            P.PARAMETER_DOUBLE_ARRAY, constraints=">= 3 vertices, simple polygon")
        if is_disc:
            self.declare_parameter("workpiece.vertices", Parameter.Type.DOUBLE_ARRAY, vdesc)
        else:
            self.declare_parameter("workpiece.vertices",
                                   [float(c) for v in shape.vertices for c in v], vdesc)
        self.declare_parameter("friction", float(base.friction), _descriptor(
            "Coulomb friction coefficient mu (all fixels), >= 0.", P.PARAMETER_DOUBLE,
            constraints=">= 0, finite"))
        self.declare_parameter("contact_tolerance", float(base.contact_tolerance), _descriptor(
            "A fixel with |gap| <= this (m) is in contact.", P.PARAMETER_DOUBLE,
            constraints="> 0, finite"))
        self.declare_parameter("fixel_radius", float(min(radii)) if radii else 0.0, _descriptor(
            "Radius (m) of the fixels received on the fixels topic (pins); setting it at "
            "run time applies it to every fixel.", P.PARAMETER_DOUBLE,
            constraints=">= 0, finite"))
        self.declare_parameter("modes", list(base.modes) or Parameter.Type.STRING_ARRAY,
                               _descriptor(
            "Modes whose cone is published on ~/cone/<mode> whenever the inputs change.",
            P.PARAMETER_STRING_ARRAY, constraints=f"letters from {MODE_LETTERS!r}"))
        self.declare_parameter("tilt_tolerance", conv.TILT_TOLERANCE_RAD, _descriptor(
            "Largest tilt (rad) of a pose's orientation out of the fixture plane.",
            P.PARAMETER_DOUBLE, constraints=">= 0, finite"))
        self.declare_parameter("out_of_plane_tolerance", conv.OUT_OF_PLANE_TOLERANCE,
                               _descriptor(
            "Largest |(force.z, torque.x/L, torque.y/L)| / |(force.x, force.y, torque.z/L)| "
            "accepted in a check_wrench request (dimensionless).", P.PARAMETER_DOUBLE,
            constraints=">= 0, finite"))
        self.declare_parameter("wait_for_inputs", False, _descriptor(
            "If true, answer NO_INPUTS until a pose and a fixel message have arrived; if "
            "false, the scene's own pose and fixels are used until then.",
            P.PARAMETER_BOOL))

    def _p(self, name: str) -> Any:
        try:
            return self.get_parameter(name).value
        except ParameterUninitializedException:  # declared with a type, no value yet
            return None

    def _values(self, overrides: dict[str, Any] | None = None) -> dict[str, Any]:
        vals = {p: self._p(p) for p in PARAMETERS}
        vals.update(overrides or {})
        vals["modes"] = [m for m in (vals["modes"] or []) if m]
        return vals

    @staticmethod
    def _workpiece(v: dict[str, Any]) -> Workpiece:
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

    def _validate_parameters(self, params: list[Parameter]) -> SetParametersResult:
        """Refuse values that cannot make a scene, whatever the pose and fixels."""
        try:
            v = self._values({p.name: p.value for p in params})
            self._workpiece(v)
            for name, low, strict in (("friction", 0.0, False),
                                      ("contact_tolerance", 0.0, True),
                                      ("fixel_radius", 0.0, False),
                                      ("tilt_tolerance", 0.0, False),
                                      ("out_of_plane_tolerance", 0.0, False)):
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
        except (SceneError, ValueError, TypeError) as exc:
            return SetParametersResult(successful=False, reason=str(exc))
        return SetParametersResult(successful=True)

    def _parameters_changed(self, params: list[Parameter]) -> None:
        if not hasattr(self, "_snapshot"):  # during __init__'s declarations
            return
        names = {p.name for p in params}
        if "fixel_radius" in names:
            self._radius_overridden = True
        if "modes" in names:
            self._sync_publishers()
        self._out_of_plane_tolerance = self._p("out_of_plane_tolerance")
        self._rebuild("parameters " + ", ".join(sorted(names)))

    # --- inputs -----------------------------------------------------------------------
    def _refuse(self, what: str, why: str) -> None:
        """Log a refused input: at once when the reason changes, else at most every 5 s."""
        now = time.monotonic()
        last = self._refusals.get(what)
        kind = why.split(" ", 3)[:3]  # the reason's gist, without its numbers
        if last is not None and last[0] == kind and now - last[1] < REFUSAL_LOG_PERIOD_S:
            self._refusals[what] = (kind, last[1], last[2] + 1)
            return
        repeats = f" ({last[2]} similar refusal(s) not logged)" if last and last[2] else ""
        self._refusals[what] = (kind, now, 0)
        self.get_logger().warning(f"{what} message refused: {why}{repeats}")

    def _frame_ok(self, what: str, frame_id: str) -> bool:
        expected = self._p("fixture_frame")
        if frame_id != expected:
            self._refuse(what, f"frame_id {frame_id!r} is not the fixture frame "
                               f"{expected!r} (parameter fixture_frame)")
            return False
        return True

    def _on_pose(self, msg: PoseStamped) -> None:
        def store(pose, stamp):
            self._pose, self._pose_stamp = pose, stamp

        self._on_input("workpiece_pose", msg, lambda m: conv.pose_to_planar(
            m.pose, self._p("tilt_tolerance")), store, "pose")

    def _on_fixels(self, msg: PoseArray) -> None:
        def store(positions, stamp):
            self._fixel_positions, self._fixels_stamp = positions, stamp

        self._on_input("fixels", msg, conv.fixels_from_pose_array, store, "fixels")

    def _on_input(self, topic: str, msg: Any, convert, store, reason: str) -> None:
        """Check the frame, convert, store the value with its stamp under the lock and
        rebuild the snapshot; refuse (with a reason) instead of ever raising."""
        try:
            if not self._frame_ok(topic, msg.header.frame_id):
                return
            value = convert(msg)
            with self._lock:
                store(value, (msg.header.stamp.sec, msg.header.stamp.nanosec))
            self._rebuild(reason)
        except conv.ConversionError as exc:
            self._refuse(topic, str(exc))
        except Exception as exc:  # noqa: BLE001 - never die on input
            self.get_logger().error(f"{topic} handling failed: {exc!r}")

    # --- snapshots --------------------------------------------------------------------
    def _build_scene(self, v: dict[str, Any]) -> Scene:
        radius = v["fixel_radius"]
        if self._fixel_positions is not None:
            fixels = tuple(Fixel(p, radius) for p in self._fixel_positions)
        elif self._radius_overridden:
            fixels = tuple(Fixel(f.position, radius, f.friction)
                           for f in self._base_scene.fixels)
        else:
            fixels = self._base_scene.fixels
        friction = v["friction"]
        if friction != self._base_scene.friction:  # a set friction applies to all fixels
            fixels = tuple(Fixel(f.position, f.radius) for f in fixels)
        return Scene(workpiece=self._workpiece(v), fixels=fixels, friction=friction,
                     pose=self._pose, contact_tolerance=v["contact_tolerance"],
                     modes=tuple(m for m in v["modes"] if m))

    def _rebuild(self, reason: str) -> None:
        """Make a new snapshot from the current inputs, then publish monitored modes."""
        with self._lock:
            v = self._values()
            self._version += 1
            frame = v["fixture_frame"]
            status, message, scene = OK, "", None
            missing = [name for name, have in (
                ("workpiece_pose", self._pose_stamp is not None),
                ("fixels", self._fixel_positions is not None)) if not have]
            if v["wait_for_inputs"] and missing:
                status = NO_INPUTS
                message = ("no input yet on " + " and ".join(missing) + " (parameter "
                           "wait_for_inputs is true)")
            else:
                try:
                    scene = self._build_scene(v)
                except (SceneError, ValueError) as exc:
                    status, message = SCENE_ERROR, f"current inputs make no valid scene: {exc}"
            snap = Snapshot(self._version, scene, status, message, frame,
                            self._pose_stamp, self._fixels_stamp)
            self._snapshot = snap
        if status == SCENE_ERROR:
            self.get_logger().warning(f"{reason}: {message}", throttle_duration_sec=5.0)
        self._publish(snap)

    def answer(self, snapshot: Snapshot, mode: str) -> Answer:
        """Cached answer of (snapshot, mode): each is computed at most once."""
        ans = snapshot.answers.get(mode) if isinstance(mode, str) else None
        if ans is None:
            ans = compute_answer(snapshot, mode)
            if ans.status == INTERNAL_ERROR:
                self.get_logger().error(f"mode {mode!r}: {ans.message}")
            if isinstance(mode, str) and len(snapshot.answers) < CACHE_LIMIT:
                snapshot.answers[mode] = ans
        return ans

    @property
    def snapshot(self) -> Snapshot:
        return self._snapshot

    # --- publishing -------------------------------------------------------------------
    def _sync_publishers(self) -> None:
        wanted = set(self._values()["modes"])
        for mode in list(self._cone_pubs):
            if mode not in wanted:
                self.destroy_publisher(self._cone_pubs.pop(mode))
                self._reported.pop(mode, None)
        for mode in sorted(wanted - set(self._cone_pubs)):
            self._cone_pubs[mode] = self.create_publisher(
                Float64MultiArray, f"~/cone/{mode}", CONE_QOS)

    def _publish(self, snap: Snapshot) -> None:
        for mode, pub in list(self._cone_pubs.items()):
            try:
                ans = self.answer(snap, mode)
                if ans.status == OK:
                    msg = conv.cone_to_multiarray(ans.cone.F, ans.cone.equalities)
                elif ans.status == MODE_INFEASIBLE:
                    msg = conv.marker_multiarray(conv.KIND_INFEASIBLE)
                else:
                    msg = conv.marker_multiarray(conv.KIND_INVALID)
                self._report(mode, ans)
                pub.publish(msg)
            except Exception as exc:  # noqa: BLE001 - keep serving the other modes
                self.get_logger().error(f"publishing cone of {mode!r} failed: {exc!r}")

    def _report(self, mode: str, ans: Answer) -> None:
        """Log a monitored mode's state when it changes (not on every update)."""
        key = (ans.status, ans.message if ans.status != OK else "")
        previous = self._reported.get(mode)
        if previous is not None and previous[0] == ans.status:
            return
        self._reported[mode] = key
        if ans.status == OK:
            if previous is not None:
                self.get_logger().info(f"mode {mode!r} is valid again")
        else:
            self.get_logger().warning(
                f"mode {mode!r}: {STATUS_NAMES[ans.status]}: {ans.message} (published as "
                "the NaN marker row until it changes; reported once)")

    # --- services ---------------------------------------------------------------------
    @staticmethod
    def _stamp_response(resp: Any, snap: Snapshot) -> None:
        resp.frame_id = snap.frame_id
        resp.inputs_version = snap.version
        if snap.pose_stamp is not None:
            resp.pose_stamp.sec, resp.pose_stamp.nanosec = snap.pose_stamp
        if snap.fixels_stamp is not None:
            resp.fixels_stamp.sec, resp.fixels_stamp.nanosec = snap.fixels_stamp

    def classifier(self, snapshot: Snapshot) -> ModeClassifier:
        """The snapshot's mode classifier (created once, caches its cones)."""
        key = ("classifier",)
        clf = snapshot.answers.get(key)
        if clf is None:
            clf = snapshot.answers.setdefault(key, ModeClassifier(snapshot.scene))
        return clf

    def _wrench(self, snap: Snapshot, wrench: Any) -> tuple[float, float, float]:
        return conv.wrench_to_planar(wrench, snap.scene.length_scale,
                                     self._out_of_plane_tolerance)

    def _on_check_wrench(self, req: CheckWrench.Request, resp: CheckWrench.Response
                         ) -> CheckWrench.Response:
        snap = self._snapshot
        resp.consistent = False
        resp.margin = -1.0
        try:
            self._stamp_response(resp, snap)
            ans = self.answer(snap, req.mode)
            if ans.status not in (OK, MODE_INFEASIBLE):
                resp.status, resp.message = ans.status, ans.message
                return resp
            try:
                g = self._wrench(snap, req.wrench)
            except conv.ConversionError as exc:
                resp.status, resp.message = INVALID_WRENCH, str(exc)
                return resp
            resp.status, resp.message = ans.status, ans.message
            if ans.status == OK:
                if ans.union is not None:
                    resp.consistent = bool(ans.union.contains(g))
                    resp.margin = float(ans.union.margin(g))
                else:
                    resp.consistent, resp.margin = ans.cone.check(g)
            if req.classify:
                mine = set(ans.union.modes) if ans.union is not None else {req.mode}
                others = [m for m in self.classifier(snap).consistent_modes(g)
                          if m.mode not in mine]
                resp.other_modes = [m.mode for m in others]
                resp.other_margins = [float(m.margin) for m in others]
                resp.only_mode = bool(resp.consistent and not others)
        except Exception as exc:  # noqa: BLE001 - a service must answer, not die
            resp.consistent, resp.margin, resp.only_mode = False, -1.0, False
            resp.status = INTERNAL_ERROR
            resp.message = f"check_wrench failed: {type(exc).__name__}: {exc}"
            self.get_logger().error(resp.message)
        return resp

    def _on_classify_wrench(self, req: ClassifyWrench.Request, resp: ClassifyWrench.Response
                            ) -> ClassifyWrench.Response:
        snap = self._snapshot
        try:
            self._stamp_response(resp, snap)
            if snap.scene is None:
                resp.status, resp.message = snap.status, snap.message
                return resp
            try:
                g = self._wrench(snap, req.wrench)
            except conv.ConversionError as exc:
                resp.status, resp.message = INVALID_WRENCH, str(exc)
                return resp
            matches = self.classifier(snap).consistent_modes(g)
            resp.modes = [m.mode for m in matches]
            resp.margins = [float(m.margin) for m in matches]
            resp.status = OK
            if not matches:
                resp.message = "the wrench is consistent with no mode of the current scene"
        except Exception as exc:  # noqa: BLE001 - a service must answer, not die
            resp.modes, resp.margins = [], []
            resp.status = INTERNAL_ERROR
            resp.message = f"classify_wrench failed: {type(exc).__name__}: {exc}"
            self.get_logger().error(resp.message)
        return resp

    def _on_get_cone(self, req: GetCone.Request, resp: GetCone.Response) -> GetCone.Response:
        snap = self._snapshot
        resp.feasible = False
        try:
            self._stamp_response(resp, snap)
            ans = self.answer(snap, req.mode)
            resp.status, resp.message = ans.status, ans.message
            if ans.union is not None:
                resp.status = INVALID_MODE
                resp.message = (f"mode {req.mode!r} has wildcards: it is the union of the cones "
                                f"of {list(ans.union.modes)}, not one cone; call get_cone "
                                "for each, or check_wrench with the wildcard mode")
                return resp
            if ans.cone is not None:
                resp.length_scale = float(ans.cone.length_scale)
            if ans.status == OK:
                cone = ans.cone
                resp.feasible = True
                resp.inequalities = conv.rows_flat(cone.F)
                resp.equalities = conv.rows_flat(cone.equalities)
                resp.generators = conv.rows_flat(cone.G)
                resp.lineality = conv.rows_flat(cone.lineality)
        except Exception as exc:  # noqa: BLE001 - a service must answer, not die
            resp.feasible = False
            resp.inequalities, resp.equalities, resp.generators, resp.lineality = [], [], [], []
            resp.status = INTERNAL_ERROR
            resp.message = f"get_cone failed: {type(exc).__name__}: {exc}"
            self.get_logger().error(resp.message)
        return resp


def main(args: list[str] | None = None) -> int:
    """Console entry point ``wrenchcone_node`` (``ros2 run wrenchcone_ros wrenchcone_node``)."""
    rclpy.init(args=args)
    node = None
    executor = SingleThreadedExecutor()
    try:
        node = WrenchConeNode()
        executor.add_node(node)
        executor.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except SceneError as exc:
        if node is None:
            rclpy.logging.get_logger(NODE_NAME).fatal(str(exc))
            return 2
        raise
    finally:
        executor.shutdown()
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
