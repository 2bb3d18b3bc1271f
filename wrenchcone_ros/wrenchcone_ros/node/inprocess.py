# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Wrenchcone nodes constructed in this process, as a user's program does, each spun by
an executor in a background thread: for the test kit (:mod:`wrenchcone_ros.testing`)
and the in-process closed loop (:mod:`wrenchcone_ros.sim.loop`).
"""

from __future__ import annotations

import inspect
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import yaml
from rclpy.context import Context
from rclpy.executors import Executor
from rclpy.node import Node
from rclpy.parameter import Parameter

from wrenchcone_ros.core import Scene
from wrenchcone_ros.node.wrenchcone_node import WrenchConeNode
from wrenchcone_ros.ros.contexts import isolated_context
from wrenchcone_ros.ros.spinning import ExecutorThread


def scene_file(scene: str | os.PathLike | Scene, directory: Path) -> str:
    """The ``scene_file`` parameter value for ``scene``.

    Parameters
    ----------
    scene : str, os.PathLike or wrenchcone_ros.core.Scene
        A scene YAML file (absolute, or relative to the working directory), or a scene
        object, which is written to ``directory`` as YAML.
    directory : pathlib.Path
        Where a scene object is written.

    Returns
    -------
    str
        An absolute path.

    Raises
    ------
    FileNotFoundError
        No file at the given path.
    TypeError
        ``scene`` is neither a path nor a Scene.
    """
    if isinstance(scene, Scene):
        path = Path(directory) / f"scene_{id(scene):x}.yaml"
        path.write_text(yaml.safe_dump(scene.to_dict(), sort_keys=False))
        return str(path.resolve())
    if not isinstance(scene, (str, os.PathLike)):
        raise TypeError(f"scene: a path to a scene YAML file or a wrenchcone_ros.core.Scene, "
                        f"got {type(scene).__name__}")
    path = Path(scene).resolve()
    if not path.is_file():
        raise FileNotFoundError(f"scene file {str(scene)!r} not found (resolved to {path}; "
                                f"a relative path is taken from the working directory "
                                f"{os.getcwd()})")
    return str(path)


def make_node(context: Context, scene_path: str | None = None, *,
              parameters: Mapping[str, Any] | None = None, node_name: str = "wrenchcone",
              namespace: str = "") -> Node:
    """Construct the wrenchcone node in this process, as a user's program does.

    Parameters
    ----------
    context : rclpy.context.Context
        The context the node lives in.
    scene_path : str, optional
        Parameter ``scene_file``; None: no scene file (the node then waits for the
        ``workpiece_pose`` and ``fixels`` messages).
    parameters : mapping, optional
        Further parameter overrides, e.g. ``{"input_timeout": 0.0}`` (dotted names for
        nested parameters: ``"workpiece.mass"``).
    node_name, namespace : str
        The node's name and namespace.

    Returns
    -------
    wrenchcone_ros.node.WrenchConeNode
        The node, started: with a class that takes ``autostart`` (the managed node),
        configured and activated in its constructor.
    """
    cls = WrenchConeNode
    values = dict(parameters or {})
    if scene_path is not None:
        values["scene_file"] = scene_path
    kwargs: dict[str, Any] = {
        "namespace": namespace, "context": context,
        "parameter_overrides": [Parameter(k, value=v) for k, v in values.items()]}
    if "autostart" in inspect.signature(cls).parameters:
        kwargs["autostart"] = True
    return cls(node_name, **kwargs)


class NodeFactory:
    """Wrenchcone nodes in this process, each spun by its own executor in a thread.

    The nodes share one context of their own (one DDS participant) on ``domain_id``,
    made at the first :meth:`make`: a test's nodes, in another context, reach them
    through DDS discovery, as a controller in another process does.

    Parameters
    ----------
    domain_id : int
        The ROS domain (leased by the caller).
    directory : pathlib.Path
        Where scene objects are written as YAML files.
    """

    def __init__(self, domain_id: int, directory: Path) -> None:
        self.domain_id = domain_id
        self.directory = Path(directory)
        self._context_manager: Any = None
        self.context: Context | None = None
        self._made: list[tuple[Node, ExecutorThread]] = []

    def make(self, scene: str | os.PathLike | Scene | None = None, *,
             parameters: Mapping[str, Any] | None = None, node_name: str = "wrenchcone",
             namespace: str = "", executor: type[Executor] | None = None) -> Node:
        """Construct a started wrenchcone node and spin it in a background thread.

        Parameters
        ----------
        scene : str, os.PathLike, wrenchcone_ros.core.Scene or None
            Parameter ``scene_file`` (see :func:`scene_file`); None: no scene file.
        parameters : mapping, optional
            Further parameter overrides.
        node_name, namespace : str
            The node's name and namespace.
        executor : type, optional
            The executor class (default ``SingleThreadedExecutor``).

        Returns
        -------
        wrenchcone_ros.node.WrenchConeNode
            The node (see :func:`make_node`).
        """
        if self.context is None:
            self._context_manager = isolated_context(self.domain_id)
            self.context = self._context_manager.__enter__()
        path = None if scene is None else scene_file(scene, self.directory)
        node = make_node(self.context, path, parameters=parameters, node_name=node_name,
                         namespace=namespace)
        try:
            spinner = ExecutorThread(self.context, executor, name=f"{node_name}-test-executor")
        except BaseException:
            node.destroy_node()
            raise
        self._made.append((node, spinner))
        spinner.add_node(node)
        return node

    def close(self) -> None:
        """Stop every executor (joining its thread), destroy every node (which joins the
        node's own threads), then shut the context down.

        Raises
        ------
        RuntimeError
            An executor's thread had ended with an exception, or did not stop (the first
            such error; everything is closed regardless).
        """
        errors: list[BaseException] = []
        made, self._made = self._made, []
        for node, spinner in reversed(made):
            try:
                spinner.stop()
            except RuntimeError as exc:
                errors.append(exc)
            finally:
                node.destroy_node()
        if self._context_manager is not None:
            manager, self._context_manager, self.context = self._context_manager, None, None
            manager.__exit__(None, None, None)
        if errors:
            raise errors[0]
