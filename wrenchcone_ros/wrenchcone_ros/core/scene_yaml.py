# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Scenes read from YAML files and dicts (the format of docs/theory.md and the examples):
:func:`load_scene`, :func:`scene_from_dict`, the paper's disc (:data:`PAPER_DISC`,
:func:`default_scene`), and the YAML helpers the uncertainty and design readers share
(:func:`read_yaml`, :func:`yaml_problem`, :func:`check_keys`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from .geometry import Disc, Fixel, Polygon, SceneError, Shape, Workpiece, _point
from .scene import Scene
from .tolerances import CONTACT_TOLERANCE_M


#: "uncertainty" is not part of the scene: core.uncertainty.load_uncertainty reads it.
_TOP_KEYS = {"workpiece", "friction", "contact_tolerance", "fixels", "modes", "uncertainty"}
_WP_KEYS = {"mass", "inertia", "com", "shape", "pose"}


def _require(d: Mapping, key: str, where: str) -> Any:
    if key not in d:
        raise SceneError(f"{where}: missing required key {key!r}")
    return d[key]


def check_keys(d: Any, allowed: set[str], where: str,
               error: type[ValueError] = SceneError) -> None:
    """Refuse (``error``) a ``d`` that is not a mapping or has a key not in ``allowed``;
    the message names ``where`` in the file, the unknown keys and the allowed ones.

    Parameters
    ----------
    d : object
        What the file holds at ``where``.
    allowed : set of str
        The keys allowed there.
    where : str
        Where in the file, for the message.
    error : type, optional
        The exception class to raise.

    Raises
    ------
    ValueError
        ``error``: ``d`` is not a mapping or has an unknown key.
    """
    if not isinstance(d, Mapping):
        raise error(f"{where} must be a mapping, got {type(d).__name__}")
    extra = set(d) - allowed
    if extra:
        raise error(f"{where}: unknown key(s) {sorted(map(str, extra))}; "
                    f"allowed: {sorted(allowed)}")



def _shape_from(d: Any) -> Shape:
    if not isinstance(d, Mapping):
        raise SceneError(f"workpiece.shape must be a mapping with a 'type', got {d!r}")
    kind = d.get("type")
    if kind == "disc":
        check_keys(d, {"type", "radius"}, "workpiece.shape (disc)")
        return Disc(_require(d, "radius", "workpiece.shape (disc)"))
    if kind == "polygon":
        check_keys(d, {"type", "vertices"}, "workpiece.shape (polygon)")
        return Polygon(_require(d, "vertices", "workpiece.shape (polygon)"))
    raise SceneError(f"workpiece.shape.type must be 'disc' or 'polygon', got {kind!r}")


def _fixel_from(k: int, d: Any) -> Fixel:
    if isinstance(d, Mapping):
        check_keys(d, {"position", "radius", "friction"}, f"fixel {k + 1}")
        return Fixel(_point(_require(d, "position", f"fixel {k + 1}"), f"fixel {k + 1}"),
                     d.get("radius", 0.0), d.get("friction"))
    return Fixel(_point(d, f"fixel {k + 1}"))


def scene_from_dict(d: Any) -> Scene:
    """A Scene from the YAML schema of the README (``workpiece``, ``fixels``, ``friction``,
    optional ``contact_tolerance`` and ``modes``).

    Parameters
    ----------
    d : Mapping
        The parsed YAML document.

    Returns
    -------
    Scene

    Raises
    ------
    SceneError
        A missing or unknown key, or a value the scene refuses, named in the message.
    """
    check_keys(d, _TOP_KEYS, "scene")
    wp = _require(d, "workpiece", "scene")
    check_keys(wp, _WP_KEYS, "workpiece")
    workpiece = Workpiece(
        mass=_require(wp, "mass", "workpiece"), inertia=_require(wp, "inertia", "workpiece"),
        shape=_shape_from(_require(wp, "shape", "workpiece")),
        com=wp.get("com", (0.0, 0.0)))
    fixels = _require(d, "fixels", "scene")
    if isinstance(fixels, (str, bytes, Mapping)) or not isinstance(fixels, Sequence):
        raise SceneError(f"fixels must be a list of [x, y] or {{position, radius}}, "
                         f"got {fixels!r}")
    modes = d.get("modes", ())
    if isinstance(modes, str):
        modes = [modes]
    if not isinstance(modes, Sequence) or not all(isinstance(m, str) for m in modes):
        raise SceneError(f"modes must be a list of mode strings, got {modes!r}")
    return Scene(
        workpiece=workpiece,
        fixels=tuple(_fixel_from(k, f) for k, f in enumerate(fixels)),
        friction=_require(d, "friction", "scene"),
        pose=wp.get("pose", (0.0, 0.0, 0.0)),
        contact_tolerance=d.get("contact_tolerance", CONTACT_TOLERANCE_M),
        modes=tuple(modes))


def yaml_problem(exc: Exception) -> str:
    """PyYAML's error in one line, with the line and column (1-based) of the problem,
    and of the construct it was reading when that is elsewhere.

    Parameters
    ----------
    exc : Exception
        An error raised by PyYAML.

    Returns
    -------
    str
        One line.
    """
    problem = getattr(exc, "problem", None)
    mark = getattr(exc, "problem_mark", None)
    if problem is None or mark is None:  # not a marked error: PyYAML's first line
        return (str(exc).splitlines() or [type(exc).__name__])[0]
    out = f"line {mark.line + 1}, column {mark.column + 1}: {problem}"
    context, cmark = getattr(exc, "context", None), getattr(exc, "context_mark", None)
    if context and cmark is not None and (cmark.line, cmark.column) != (mark.line,
                                                                       mark.column):
        out += f" ({context}, which starts at line {cmark.line + 1}, column {cmark.column + 1})"
    elif context:
        out += f" ({context})"
    return out


def read_yaml(path: str | Path, error: type[Exception], kind: str = "") -> Any:
    """The parsed content of the YAML file ``path``; ``error`` (one line: ``kind``, e.g.
    "scene file ", the path, and what went wrong, with the line and column of a YAML
    error) when it cannot be read or parsed. The one YAML reader of the scene, uncertainty
    and plate files."""
    import yaml

    path = Path(path)
    try:
        text = path.read_text()
    except OSError as exc:
        raise error(f"cannot read {kind}{str(path)!r}: {exc.strerror}") from None
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise error(f"{kind}{str(path)!r} is not valid YAML: {yaml_problem(exc)}") from None


def load_scene(source: str | Path | Mapping) -> Scene:
    """A scene from a YAML file or an already-parsed mapping (the schema: README).

    Parameters
    ----------
    source : str, Path, Mapping or Scene
        The path of a YAML scene file, its parsed content, or a Scene (returned as is).

    Returns
    -------
    Scene
        The workpiece at its pose, the fixels in the fixture frame (SI units, REP-103:
        metres, kilograms, radians, counter-clockwise from +x).

    Raises
    ------
    SceneError
        The file cannot be read or parsed (with the line and column of a YAML error), or
        a key is missing, unknown or out of range (named in the message with what is
        allowed).
    """
    if isinstance(source, Scene):
        return source
    if isinstance(source, Mapping):
        return scene_from_dict(source)
    data = read_yaml(source, SceneError, "scene file ")
    try:
        return scene_from_dict(data)
    except SceneError as exc:
        raise SceneError(f"{Path(source)}: {exc}") from None


#: The paper's worked example (section 4): unit disc, M = I, mu = 0.2, fixel 1 touching
#: at (0, -1), fixel 2 slightly right of (1, 0).
PAPER_DISC: dict = {
    "workpiece": {"mass": 1.0, "inertia": 1.0, "com": [0.0, 0.0],
                  "shape": {"type": "disc", "radius": 1.0}, "pose": [0.0, 0.0, 0.0]},
    "friction": 0.2,
    "contact_tolerance": 1e-9,
    "fixels": [[0.0, -1.0], [1.001, 0.0]],
    "modes": ["na"],
}


def default_scene() -> Scene:
    """The paper's worked example (Balkcom and Trinkle, 2002, section 4) as a Scene.

    A unit disc (m = 1 kg, I = 1 kg m^2), mu = 0.2, fixel 1 touching at (0, -1) m, fixel
    2 just right of (1, 0) m; its mode "na" has the generators (1, 0, -1),
    (-0.2, -1, -0.2) and (0.2, -1, 0.2) of the paper's Eq. 5.

    Returns
    -------
    Scene
        :data:`PAPER_DISC` as a Scene.
    """
    return scene_from_dict(PAPER_DISC)


__all__ = ["load_scene", "scene_from_dict", "default_scene", "PAPER_DISC", "yaml_problem",
           "check_keys"]
