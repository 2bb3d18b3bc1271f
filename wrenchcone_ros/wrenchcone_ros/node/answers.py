# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Answers: (snapshot, mode) -> Answer, cached in the snapshot, within the request limits.

One :class:`Answer` per (snapshot, mode), computed by the core at most once per snapshot
(:func:`cached_answer`; :func:`monitored_answers`: every monitored mode in one batched
call) and shared by the services, the publishers and the compiled lane. :class:`Limits`
(node parameters ``max_*``) bound the work of one request; :func:`over_limit` refuses a
mode over them before anything is computed. At most :data:`CACHE_LIMIT` answers are
cached per snapshot, and never a refusal (:data:`REFUSALS`): the cache is keyed by the
request's mode string, and a refusal is cheap to give again, so a client sending many
distinct long or malformed modes cannot make the node keep them (:func:`cacheable`).

Uncertainty: a snapshot carries the uncertainty set of the parameters it was built from
(``Snapshot.uncertainty``; a parameter change builds a new snapshot, so its cache never
mixes nominal and robust answers). With a set, every answer is the core's robust "all"
cone (:func:`~wrenchcone_ros.core.robust_cone`: the wrenches consistent with the mode for
every model), its message names the set and the guarantee, and its ``uncertainty`` and
``guarantee`` fields say so (the cone topic's fields of the same names). A mode with
wildcards is then refused (INVALID_MODE, :func:`robust_wildcard_refusal`): "for every
model, some mode of the wildcard" is not the union of its modes' robust cones. A robust
classification (every mode for every model, no pruning) is refused before any work when
its mode-model pairs exceed ``max_classify_nodes`` (:func:`over_classify_limit`).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace

from wrenchcone_ros.core import (
    Cone,
    ModeError,
    ModeSyntaxError,
    SceneError,
    Uncertainty,
    WrenchSet,
    robust_cones,
)
from wrenchcone_ros.core.budget import TimeBudgetExceeded
from wrenchcone_ros.core.classify import ModeClassifier
from wrenchcone_ros.core.modes import count_concrete_modes, expand_mode, is_wildcard
from wrenchcone_ros.core.robust import RobustWildcardError
from wrenchcone_ros.core.uncertainty import NOMINAL
from wrenchcone_ros.node.status import (
    INTERNAL_ERROR,
    INVALID_MODE,
    LIMIT_EXCEEDED,
    MODE_INFEASIBLE,
    MODE_NOT_ALLOWED,
    OK,
    SCENE_ERROR,
)
from wrenchcone_ros.node.store import Snapshot

#: At most this many answers are cached per snapshot (a client asking for many distinct
#: modes cannot grow the node's memory without bound).
CACHE_LIMIT = 1024
#: Statuses of a refused request: given again at once, never cached (see the module doc).
REFUSALS = frozenset({INVALID_MODE, MODE_NOT_ALLOWED, LIMIT_EXCEEDED})


def cacheable(cache: dict, status: int) -> bool:
    """Whether an answer of ``status`` may go into a snapshot's answer cache ``cache``:
    not a refusal, and the cache not full."""
    return status not in REFUSALS and len(cache) < CACHE_LIMIT


@dataclass(frozen=True)
class Answer:
    """The outcome of one (snapshot, mode): a status, a message and the mode's set of
    wrenches if any (one cone for a concrete mode, the union of its modes' cones for a
    mode with wildcards, the "all" set under an uncertainty set).

    Parameters
    ----------
    status : int
        A status code of wrenchcone_msgs/msg/Status (OK, NO_INPUTS, INVALID_MODE, ...).
    message : str
        What went wrong, or a note; empty when there is nothing to say.
    wrenches : WrenchSet or None, optional
        The mode's set of wrenches; None when there is none.
    seconds : float, optional
        How long computing it took (s; reported in /diagnostics).
    uncertainty : str, optional
        The uncertainty set it was computed for (``Uncertainty.describe()``; "": nominal).
    guarantee : str, optional
        Its guarantee ("exact" or "scenario(...)"; "" for the nominal model or no cone).
    """

    status: int
    message: str
    wrenches: WrenchSet | None = None
    seconds: float = 0.0  # how long computing it took (reported in /diagnostics)
    #: The uncertainty set it was computed for (Uncertainty.describe(); "": nominal)
    uncertainty: str = ""
    #: Its guarantee ("exact" or "scenario(...)"; "" for the nominal model or no cone)
    guarantee: str = ""

    @property
    def cone(self) -> Cone | None:
        """The convex cone of a concrete mode's answer (None for a wildcard mode's union
        or no set)."""
        w = self.wrenches
        return None if w is None or is_wildcard(w.mode) else w.cone


def compute_answer(snapshot: Snapshot, mode: str) -> Answer:
    """The answer of (snapshot, mode), without caching. Raises only TimeBudgetExceeded
    (when computed under a time budget, see core/budget.py).

    Parameters
    ----------
    snapshot : Snapshot
        The node's inputs.
    mode : str
        The mode asked for, wildcards allowed.

    Returns
    -------
    Answer
        The answer; bad input gives a status and a message, never an exception.

    Raises
    ------
    TimeBudgetExceeded
        The request's time budget ran out.
    """
    if snapshot.scene is None:
        return Answer(snapshot.status, snapshot.message)
    u = snapshot.uncertainty
    try:
        try:
            cone = robust_cones(snapshot.scene, [mode], u, "all")[0]
        except RobustWildcardError:
            return robust_wildcard_refusal(snapshot, mode, u)
    except TimeBudgetExceeded:  # the request's own budget (services.py): not an answer
        raise
    except Exception as exc:  # noqa: BLE001 - a service must answer, not die
        return robust_answer_of(mode, exc, u)
    return robust_answer_of(mode, cone, u)


def robust_wildcard_refusal(snapshot: Snapshot, mode: str, u: Uncertainty) -> Answer:
    """INVALID_MODE for a mode with wildcards under an uncertainty set of nonzero width
    (the core's RobustWildcardError); a wildcard mode that is malformed or not allowed
    raises that ModeError."""
    scene = snapshot.scene
    modes = expand_mode(mode, scene.in_contact, scene.gaps,
                        scene.effective_contact_tolerance)
    shown = ", ".join(modes[:8]) + (", ..." if len(modes) > 8 else "")
    return Answer(INVALID_MODE,
                  f"mode {mode!r} has wildcards: with uncertainty.* set ({u.describe()}) "
                  "the node answers concrete modes only (for every model, some mode of "
                  "the wildcard is not the union of the modes' robust cones); ask each of "
                  f"{len(modes)} mode(s): {shown}", uncertainty=u.describe())


def uncertainty_text(u: Uncertainty) -> str:
    """How an answer names its model set: :meth:`~wrenchcone_ros.core.Uncertainty.describe`,
    or "" for the nominal model (no ``uncertainty.*`` parameter set), whose answers say
    nothing about models. The one place where the node words the nominal model."""
    return "" if u is NOMINAL or u == NOMINAL else u.describe()


def robust_answer_of(mode: str, got: WrenchSet | Exception, u: Uncertainty,
                     seconds: float = 0.0) -> Answer:
    """:func:`answer_of` for what the core gave under the uncertainty ``u``: when one is
    set (:func:`uncertainty_text`), its message names the set and the guarantee."""
    ans = answer_of(mode, got, seconds)
    text = uncertainty_text(u)
    if not text:
        return ans
    if isinstance(got, Exception):
        return replace(ans, uncertainty=text)
    note = f"for every model of {text} (guarantee {got.guarantee})"
    message = f"{ans.message} ({note})" if ans.message else note
    return replace(ans, message=message, uncertainty=text, guarantee=str(got.guarantee))


def answer_of(mode: str, got: WrenchSet | Exception, seconds: float = 0.0) -> Answer:
    """The answer for what the core gave for ``mode``: its set of wrenches, or the
    exception it raised (ModeSyntaxError, ModeError, SceneError, anything else);
    ``seconds``: how long computing it took."""
    if isinstance(got, ModeSyntaxError):
        return Answer(INVALID_MODE, str(got), seconds=seconds)
    if isinstance(got, ModeError):
        return Answer(MODE_NOT_ALLOWED, str(got), seconds=seconds)
    if isinstance(got, SceneError):
        return Answer(SCENE_ERROR, str(got), seconds=seconds)
    if isinstance(got, Exception):
        return Answer(INTERNAL_ERROR,
                      f"cone computation failed: {type(got).__name__}: {got}",
                      seconds=seconds)
    if got.feasible:
        return Answer(OK, "", got, seconds)
    message = (f"mode {mode!r} is infeasible: none of its modes {list(got.impossible)} "
               "is realised by any wrench" if got.impossible else
               f"mode {mode!r} is infeasible: no wrench realises it (no rigid-body "
               "acceleration meets its strict conditions), so no wrench is consistent "
               "with it")
    return Answer(MODE_INFEASIBLE, message, got, seconds)


@dataclass(frozen=True)
class Limits:
    """Bounds on the work of one request (node parameters max_*; docs/node.md)."""

    max_mode_length: int = 64
    max_concrete_modes: int = 64
    max_classify_nodes: int = 2000
    #: Seconds a fast-lane request (check_wrench, get_cone) may compute; 0 = no limit.
    max_request_time: float = 0.05


def over_limit(snapshot: Snapshot, mode: str, limits: Limits) -> Answer | None:
    """LIMIT_EXCEEDED if ``mode`` is over a limit, counted before any expansion; else
    None. Cheap: the length first, then the count of a wildcard's concrete modes."""
    if not isinstance(mode, str) or snapshot.scene is None:
        return None
    if len(mode) > limits.max_mode_length:
        return Answer(LIMIT_EXCEEDED,
                      f"mode string of {len(mode)} characters is longer than max_mode_length "
                      f"({limits.max_mode_length}); give one letter per fixel")
    if is_wildcard(mode):
        scene = snapshot.scene
        try:
            n = count_concrete_modes(mode, scene.in_contact)
        except ModeError:
            return None  # the computation reports the mode error itself
        if n > limits.max_concrete_modes:
            return Answer(LIMIT_EXCEEDED,
                          f"mode {mode!r} expands to {n} concrete modes, more than "
                          f"max_concrete_modes ({limits.max_concrete_modes}); use fewer "
                          "wildcards or raise the parameter")
    return None


def robust_classify_work(snapshot: Snapshot) -> tuple[int, int]:
    """(modes, models) of a robust classification of the snapshot's scene: it computes the
    "all" and "any" cones of every valid mode (no pruning) for each model the core
    computes (one for friction intervals, the scenario sample otherwise)."""
    scene, u = snapshot.scene, snapshot.uncertainty
    modes = count_concrete_modes("*" * scene.n_fixels, scene.in_contact)
    return modes, (u.scenario_size() if u.nonlinear(scene) else 1)


def over_classify_limit(snapshot: Snapshot, limits: Limits) -> Answer | None:
    """LIMIT_EXCEEDED if classifying a wrench under the snapshot's uncertainty set is over
    ``max_classify_nodes`` (each mode for each model counts as one node), else None.
    Nothing is computed. The pruned search of the zero-width uncertainty bounds itself
    (it stops after max_classify_nodes nodes)."""
    if snapshot.scene is None or classifier(snapshot).pruned:
        return None
    modes, models = robust_classify_work(snapshot)
    if modes * models <= limits.max_classify_nodes:
        return None
    per = (f"each of {models} sampled models (scenario approach)" if models > 1
           else "one model (friction intervals: exact)")
    return Answer(LIMIT_EXCEEDED,
                  f"robust classification refused: it computes two cones of each of the "
                  f"scene's {modes} modes ({sum(snapshot.scene.in_contact)} fixel(s) in "
                  f"contact) for {per}, {modes * models} mode-model pairs, more than "
                  f"max_classify_nodes ({limits.max_classify_nodes}); raise the parameter, "
                  "use fewer fixels, or unset uncertainty.* for the nominal classification",
                  uncertainty=snapshot.uncertainty.describe())


def cached_answer(snapshot: Snapshot, mode: str,
                  on_error: Callable[[str], None] | None = None,
                  limits: Limits | None = None) -> Answer:
    """Cached answer of (snapshot, mode): each is computed at most once per snapshot.
    ``on_error`` gets the log line of an INTERNAL_ERROR answer; a mode over ``limits``
    gets LIMIT_EXCEEDED without any computation."""
    ans = snapshot.answers.get(mode) if isinstance(mode, str) else None
    if ans is None:
        start = time.perf_counter()
        ans = over_limit(snapshot, mode, limits or Limits()) or compute_answer(snapshot, mode)
        ans = replace(ans, seconds=time.perf_counter() - start)
        if ans.status == INTERNAL_ERROR and on_error is not None:
            on_error(f"mode {mode!r}: {ans.message}")
        if isinstance(mode, str) and cacheable(snapshot.answers, ans.status):
            snapshot.answers[mode] = ans
    return ans


def monitored_answers(snapshot: Snapshot, modes: Iterable[str],
                      on_error: Callable[[str], None] | None = None,
                      limits: Limits | None = None,
                      pause: Callable[[], None] | None = None) -> dict[str, Answer]:
    """The answers of every monitored mode for one snapshot (mode -> Answer), cached.

    The one place where the per-snapshot work of the published cones is done: every
    publisher receives this dict. The modes not cached yet and within ``limits`` are
    computed in ONE call of the core (:func:`~wrenchcone_ros.core.robust_cones`; for the
    nominal model the batched engine: the pose's arrays once, every mode in one kernel
    pass); each answer's ``seconds`` is its share
    of that call. Should the batch itself fail, each mode is computed on its own, so
    one bad mode never costs the others their answer. ``pause()`` runs before the batch
    and before each mode computed on its own: the node uses it to let service requests
    in progress go first.
    """
    modes = list(modes)
    limits = limits or Limits()
    todo = [m for m in dict.fromkeys(modes) if isinstance(m, str)
            and m not in snapshot.answers and snapshot.scene is not None
            and over_limit(snapshot, m, limits) is None]
    batched: dict[str, Answer] = {}  # this call's answers, refusals (not cached) too
    if todo:
        if pause is not None:
            pause()
        start = time.perf_counter()
        u = snapshot.uncertainty
        try:
            cones = robust_cones(snapshot.scene, todo, u, "all", errors="return")
        except Exception:  # noqa: BLE001 - fall back to one mode at a time below
            cones = None
        if cones:
            share = (time.perf_counter() - start) / len(todo)
            for mode, cone in zip(todo, cones):
                if isinstance(cone, RobustWildcardError):
                    continue  # refused one by one (cached_answer)
                ans = robust_answer_of(mode, cone, u, share)
                if ans.status == INTERNAL_ERROR and on_error is not None:
                    on_error(f"mode {mode!r}: {ans.message}")
                batched[mode] = ans
                if cacheable(snapshot.answers, ans.status):
                    snapshot.answers[mode] = ans
    out = {}
    for mode in modes:
        ans = batched.get(mode) if isinstance(mode, str) else None
        if ans is None:
            if pause is not None and mode not in snapshot.answers:
                pause()
            ans = cached_answer(snapshot, mode, on_error, limits)
        out[mode] = ans
    return out


def classifier(snapshot: Snapshot) -> ModeClassifier:
    """The snapshot's mode classifier under its uncertainty set (created once; caches its
    cones, and under an uncertainty set of nonzero width the "all" and "any" sets of
    every mode, the whole cost of a robust classification: check
    :func:`over_classify_limit` first)."""
    key = ("classifier",)
    clf = snapshot.answers.get(key)
    if clf is None:
        clf = snapshot.answers.setdefault(
            key, ModeClassifier(snapshot.scene, uncertainty=snapshot.uncertainty))
    return clf
