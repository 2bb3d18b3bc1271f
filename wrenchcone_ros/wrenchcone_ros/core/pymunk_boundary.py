# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The one module that reads pymunk's internals: its cffi bindings to Chipmunk
(``pymunk._chipmunk_cffi``) and the Chipmunk pointers of its shapes and bodies
(``Shape._shape``, ``Body._body``), for the planner's two hottest reads (point queries
after every step, the fixels' impulses). Each reader checks itself against pymunk's
public calls when it is made and returns None from :meth:`of` when this pymunk is not as
expected; :mod:`.simulate` then uses the public calls (the same doubles, slower).
pymunk is not pinned: tests compare both paths bit for bit (test/core/test_simulate.py).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

class ShapeQuery:
    """Point queries on a workpiece's pymunk shapes without pymunk's per-call objects.

    ``Shape.point_query`` allocates a query struct, looks the shape up again and builds a
    named tuple with two vectors on every call; the gaps of every fixel after every
    step made it the planner's largest cost. This calls the same Chipmunk function
    (``cpShapePointQuery``) on one reused struct and reads the same doubles, so the
    distances, points and gradients are the ones ``point_query`` returns, bit for bit
    (tested against it). :meth:`of` gives None when this pymunk does not expose its
    cffi bindings as expected; the callers then use ``point_query``.
    """

    def __init__(self, shapes: Sequence, ffi, lib, vec) -> None:
        self._cp = tuple(s._shape for s in shapes)
        self._info = ffi.new("cpPointQueryInfo *")
        self._call = lib.cpShapePointQuery
        self._vec = vec

    @classmethod
    def of(cls, shapes: Sequence) -> ShapeQuery | None:
        """The query for ``shapes``, or None when pymunk's bindings are not as expected.

        Parameters
        ----------
        shapes : sequence of pymunk.Shape
            The workpiece's shapes.

        Returns
        -------
        ShapeQuery or None
        """
        try:
            from pymunk import Vec2d
            from pymunk._chipmunk_cffi import ffi, lib

            q = cls(shapes, ffi, lib, Vec2d)
            if shapes:  # the same answer as the public call, or not used at all
                ref = min((s.point_query((0.25, -0.5)) for s in shapes),
                          key=lambda r: r.distance)
                if q.closest((0.25, -0.5)) != (ref.distance, ref.point, -ref.gradient):
                    return None
            return q
        except Exception:  # pragma: no cover - a pymunk without these bindings
            return None

    def distance(self, p) -> float:
        """``min(s.point_query(p).distance for s in shapes)``.

        Parameters
        ----------
        p : tuple of 2 float
            The point (m, fixture frame).

        Returns
        -------
        float
            The signed distance (m; negative inside), the first smallest over the
            shapes.
        """
        call, info = self._call, self._info
        best = None
        for s in self._cp:
            call(s, p, info)
            d = info.distance
            if best is None or d < best:  # min(): the first smallest
                best = d
        return best

    def closest(self, p) -> tuple[float, object, object]:
        """The distance, closest point and minus the gradient of the shape nearest to
        ``p`` (the first of the nearest): ``point_query``'s ``distance``, ``point`` and
        ``-gradient``.

        Parameters
        ----------
        p : tuple of 2 float
            The point (m, fixture frame).

        Returns
        -------
        distance : float
            m.
        point : pymunk.Vec2d
            The closest point.
        normal : pymunk.Vec2d
            Minus the gradient of the signed distance.
        """
        call, info = self._call, self._info
        best = point = grad = None
        for s in self._cp:
            call(s, p, info)
            d = info.distance
            if best is None or d < best:
                best = d
                point = (info.point.x, info.point.y)
                grad = (info.gradient.x, info.gradient.y)
        vec = self._vec
        return best, vec(*point), -vec(*grad)


class ArbiterImpulses:
    """Each fixel's impulse in the last step, without pymunk's per-arbiter objects.

    ``Body.each_arbiter`` wraps every arbiter in an Arbiter object and its shapes and
    impulse in new Python objects. This walks the same arbiters in the same order
    (Chipmunk's ``cpBodyEachArbiter``) with a callback of its own, reads the same
    doubles (``cpArbiterGetShapes``, ``cpArbiterTotalImpulse``) and sums the same
    lengths (``Vec2d.length``'s formula) in the same order, so the impulses are the
    ones of :meth:`Simulation._impulses_reference`, bit for bit (tested). :meth:`of`
    gives None when pymunk's bindings are not as expected.
    """

    def __init__(self, body, fixels: Sequence, ffi, lib) -> None:
        self._index = {f._shape: i for i, f in enumerate(fixels)}
        self._n = len(fixels)
        self._a = ffi.new("cpShape *[1]")
        self._b = ffi.new("cpShape *[1]")
        self._body = body._body
        self._each = lib.cpBodyEachArbiter
        self._get_shapes = lib.cpArbiterGetShapes
        self._total = lib.cpArbiterTotalImpulse
        self._null = ffi.NULL
        self._imp: list[float] = []
        self._callback = ffi.callback("void(cpBody *, cpArbiter *, void *)", self._collect)

    @classmethod
    def of(cls, body, fixels: Sequence) -> ArbiterImpulses | None:
        """The reader for ``body`` and the fixels' shapes, or None.

        Parameters
        ----------
        body : pymunk.Body
            The workpiece.
        fixels : sequence of pymunk.Shape
            One static circle per fixel.

        Returns
        -------
        ArbiterImpulses or None
        """
        try:
            from pymunk._chipmunk_cffi import ffi, lib

            return cls(body, fixels, ffi, lib)
        except Exception:  # pragma: no cover - a pymunk without these bindings
            return None

    def _collect(self, _body, arbiter, _data) -> None:
        self._get_shapes(arbiter, self._a, self._b)
        for shape in (self._a[0], self._b[0]):
            i = self._index.get(shape)
            if i is not None:
                v = self._total(arbiter)
                self._imp[i] += math.sqrt(v.x**2 + v.y**2)  # Vec2d.length

    def impulses(self) -> list[float]:
        """The impulses of the last step, one per fixel (N s).

        Returns
        -------
        list of float
        """
        self._imp = imp = [0.0] * self._n
        self._each(self._body, self._callback, self._null)
        self._imp = []
        return imp
