# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Newton-Euler in contact coordinates: J (section 2) and M, nondimensionalised.

g = M xdd - J c, with g = (f_x, f_y, tau) in world axes about the com, xdd = (a_x, a_y,
alpha), c = [c_1n..c_nn, c_1t..c_nt]. Every method works on the nondimensional problem

    g_hat = S g / m,   xdd_hat = S^-1 xdd,   J_hat = S J,   M_hat = diag(1, 1, kappa),

with S = diag(1, 1, 1/L), L = ``scene.length_scale`` and kappa = I / (m L^2). Consistency
is invariant under this change of variables (positive scalings of g and c, an invertible
map of xdd), so the cone of g_hat maps back to the cone of g by F = F_hat S.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from fractions import Fraction

import numpy as np

from .modes import Interaction, parse_mode
from .numbers import Scalar, arithmetic
from .geometry import ContactFrame
from .scene import Scene


def jacobian(frames: tuple[ContactFrame, ...], exact: bool = False) -> np.ndarray:
    """J (3 x 2n), section 2: column of a unit force v at p_i is (v_x, v_y, r_i x v).

    Columns ordered n_1..n_n, t_1..t_n.

    Parameters
    ----------
    frames : tuple of ContactFrame
        The contact frames of the fixels (``scene.contacts``), in fixel order.
    exact : bool, optional
        Keep the frames' exact numbers (an object array) instead of floats.

    Returns
    -------
    numpy.ndarray
        J, 3 x 2n, in SI units (N per unit contact force; the third row in m).
    """
    dtype = object if exact else float
    cols = [(f.n[0], f.n[1], f.r_n) for f in frames] + [(f.t[0], f.t[1], f.r_t) for f in frames]
    return np.array(cols, dtype=dtype).T.reshape(3, len(cols))


@dataclass(frozen=True)
class Problem:
    """The nondimensional inverse-dynamics problem of one (scene, mode).

    Parameters
    ----------
    mode : str
        The concrete mode, one letter per fixel.
    interactions : tuple of Interaction
        The fixels' interactions, parsed from ``mode``.
    in_contact : tuple of bool
        Which fixels touch the workpiece.
    J : numpy.ndarray
        J_hat = S J, 3 x 2n (nondimensional).
    M : numpy.ndarray
        M_hat = diag(1, 1, kappa), 3 x 3 (nondimensional).
    mu : tuple of Scalar
        The friction coefficient of each fixel.
    length_scale : float
        L, the length that makes the torque row nondimensional (m).
    exact : bool
        Whether J, M and mu hold exact numbers (Fractions or algebraic numbers).
    scene : Scene or None, optional
        The scene the problem came from, for an exact recomputation.
    """

    mode: str
    interactions: tuple[Interaction, ...]
    in_contact: tuple[bool, ...]
    J: np.ndarray  # J_hat, 3 x 2n
    M: np.ndarray  # M_hat, 3 x 3
    mu: tuple[Scalar, ...]
    length_scale: float  # L (m)
    exact: bool
    scene: Scene | None = None  # where it came from (for an exact recomputation)

    @property
    def n(self) -> int:
        """The number of fixels, n."""
        return len(self.interactions)


def nondimensional(scene: Scene, exact: bool = False) -> tuple[np.ndarray, np.ndarray, tuple]:
    """J_hat (3 x 2n), M_hat = diag(1, 1, I / (m L^2)) and the fixels' mu, cached per scene.

    The cache lives on the (immutable) scene object itself: no hashing of the scene.

    Parameters
    ----------
    scene : Scene
        The scene.
    exact : bool, optional
        Exact arithmetic (object arrays) instead of floats.

    Returns
    -------
    J_hat : numpy.ndarray
        3 x 2n, read-only.
    M_hat : numpy.ndarray
        diag(1, 1, kappa), 3 x 3, read-only.
    mu : tuple
        The friction coefficient of each fixel.
    """
    cache = scene.__dict__.setdefault("_nondimensional", {})
    if exact not in cache:
        cache[exact] = _nondimensional(scene, exact)
    return cache[exact]


def float_rows(scene: Scene, rows: np.ndarray | None = None
               ) -> tuple[np.ndarray, float, np.ndarray]:
    """Float J_hat^T (2n x 3, C-contiguous: row k the coefficients of acceleration k over
    xdd_hat), kappa = I / (m L^2) and mu (n,): the per-pose arrays of the batch engine,
    built with a few array operations. :func:`nondimensional` (float) is made from them.

    Parameters
    ----------
    scene : Scene
        The scene.
    rows : numpy.ndarray or None, optional
        J_hat^T when it is already computed (the kernel's contact geometry computes the
        same doubles with the contact frames, :func:`.kernel.contact_geometry`).

    Returns
    -------
    A : numpy.ndarray
        J_hat^T, 2n x 3, C-contiguous.
    kappa : float
        I / (m L^2), dimensionless.
    mu : numpy.ndarray
        The friction coefficient of each fixel, shape (n,).
    """
    L = scene.length_scale
    if rows is None:
        ca = scene.contact_arrays
        k = ca.n.shape[0]
        A = np.empty((2 * k, 3))
        A[:k, :2] = ca.n  # normal rows (n, r x n / L)
        A[:k, 2] = ca.r_n / L
        A[k:, 0] = -ca.n[:, 1]  # tangential rows: t = n rotated by +90 degrees
        A[k:, 1] = ca.n[:, 0]
        A[k:, 2] = ca.r_t / L
    else:
        A = rows
    wp = scene.workpiece
    kappa = wp.inertia / (wp.mass * L * L)
    return A, kappa, scene.fixel_friction.copy()  # writeable: the kernel is compiled for that


def _nondimensional(scene: Scene, exact: bool) -> tuple[np.ndarray, np.ndarray, tuple]:
    if not exact:
        A, kappa, mu = float_rows(scene)
        J = A.T
        M = np.diag([1.0, 1.0, kappa])
        J.flags.writeable = False
        M.flags.writeable = False
        return J, M, tuple(mu.tolist())
    ar = arithmetic(exact)
    frames = scene.contacts if not exact else scene.contact_frames(ar)
    J = jacobian(frames, exact)
    L = ar.convert(scene.length_scale)
    J[2, :] = J[2, :] / L
    m, inertia = ar.convert(scene.workpiece.mass), ar.convert(scene.workpiece.inertia)
    one, zero = ar.convert(1), ar.convert(0)
    kappa = inertia / (m * L * L)
    M = np.array([[one, zero, zero], [zero, one, zero], [zero, zero, kappa]],
                 dtype=object if exact else float)
    J.flags.writeable = False
    M.flags.writeable = False
    mu = tuple(ar.convert(scene.mu(i)) for i in range(scene.n_fixels))
    return J, M, mu


def problem_from(scene: Scene, mode: str, interactions: tuple[Interaction, ...],
                 exact: bool = False) -> Problem:
    """A Problem for already-validated interactions (also relaxations, see .classify).

    Parameters
    ----------
    scene : Scene
        The scene.
    mode : str
        The mode the interactions were parsed from.
    interactions : tuple of Interaction
        One interaction per fixel, already validated against ``scene``.
    exact : bool, optional
        Exact arithmetic instead of floats.

    Returns
    -------
    Problem
        The nondimensional problem.
    """
    J, M, mu = nondimensional(scene, exact)
    return Problem(mode, interactions, scene.in_contact, J, M, mu, scene.length_scale, exact,
                   scene)


def problem(scene: Scene, mode: str, exact: bool = False) -> Problem:
    """Validate ``mode`` against ``scene`` and build the nondimensional J_hat, M_hat, mu.

    Parameters
    ----------
    scene : Scene
        The scene.
    mode : str
        A concrete mode, one letter per fixel (modes.MODE_TABLE).
    exact : bool, optional
        Exact arithmetic instead of floats.

    Returns
    -------
    Problem
        The nondimensional problem of (scene, mode).

    Raises
    ------
    ModeError
        ``mode`` is malformed or not valid for the scene's contacts.
    """
    interactions = parse_mode(mode, scene.in_contact, scene.gaps, scene.effective_contact_tolerance)
    return problem_from(scene, mode, interactions, exact)


def exact_problem(prob: Problem) -> Problem:
    """The problem in exact arithmetic: recomputed from its scene's numbers as written when
    it has a scene (the ground truth; rounded float data of a degenerate scene, e.g. three
    normals through a disc's centre, can have a very different exact cone), else its float
    data converted exactly to Fractions.

    Parameters
    ----------
    prob : Problem
        A float or exact problem.

    Returns
    -------
    Problem
        The same problem in exact arithmetic.
    """
    if prob.scene is not None:
        return problem(prob.scene, prob.mode, exact=True)
    def fr(a):
        return np.array([[Fraction(float(x)) for x in row] for row in a], dtype=object)

    return replace(prob, J=fr(prob.J), M=fr(prob.M),
                   mu=tuple(Fraction(float(m)) for m in prob.mu), exact=True)
