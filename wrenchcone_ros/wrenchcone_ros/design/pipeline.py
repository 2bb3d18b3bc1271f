# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The staged design run on Dask (dask.distributed), resumable, streamed to Parquet.

Stages, cheap first (every stage's figures are kept in the design's row):

1. geometry, location and hold on every candidate: batches of pin triples
   (:func:`geometry_batch`: :mod:`.enumerate`, then :func:`.stages.hold` for every
   located placement);
2. funnel and loading plan (:func:`.stages.plan`) for the ``plans`` best holding
   designs that can be loaded in the plane (not enclosed by their pins) under the ranking (the plan columns still empty then, so the hold margin and
   the locating accuracy decide);
   and, when the problem has a start region, the region each planned design's plan
   certifies (:func:`.stages.plan`; only these designs, once each);
3. Monte Carlo (``runs`` sampled models in pymunk) for the ``top`` best planned designs
   (from the loading start; the region of stage 2 is kept).

Engine: an embedded ``LocalCluster`` (one single-threaded worker process per core:
cddlib, numba and pymunk hold the GIL) or any Dask scheduler by its address. Each worker
compiles or loads the numba kernel once (:class:`WarmUp`, a worker plugin); pymunk
spaces are built inside the tasks (the planner's), never sent. A task is one batch;
stage 1's batches are sized to take tens of seconds on a real problem
(DEFAULT_BATCH_TRIPLES). A worker that dies loses nothing: the scheduler runs its
batches again elsewhere.

Resumable: every finished batch is written at once to ``OUT.parts/`` as its own Parquet
file (atomically: a temporary file renamed), named by the stage, a hash of everything
the batch depends on, and its number; a run that finds the file does not compute the
batch again. At the end the rows are merged, ranked (:mod:`.rank`) and written to OUT.

The rows do not depend on the engine, the number of workers or the order in which
batches finish: each design's numbers come from its own inputs only, and the final table
is sorted by the ranking with the design id as the last key.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq

from .enumerate import Enumerator, Placement, Triple, pin_triples
from .problem import (
    DEFAULT_BATCH_PLANS,
    DEFAULT_BATCH_TRIPLES,
    DEFAULT_PLAN_CANDIDATES,
    DEFAULT_PLANS,
    DEFAULT_RUNS,
    DEFAULT_SEED,
    DEFAULT_TOP,
    DesignError,
    DesignProblem,
)
from .rank import parse_ranking, rank_rows
from .stages import ENCLOSED, hold, plan

#: The columns of the Parquet file: name, type, meaning (docs/fixture_design.md).
COLUMNS: tuple[tuple[str, pa.DataType, str], ...] = (
    ("rank", pa.int64(), "1 = best under the ranking"),
    ("design_id", pa.string(), "offsets of pins 2 and 3 from pin 1 (holes), '#' the pose's "
                               "number among that triple's poses"),
    *[(f"pin{k}_{a}", pa.int64(), f"hole {a} of pin {k}") for k in (1, 2, 3) for a in "ij"],
    *[(f"pin{k}_{a}", pa.float64(), f"pin {k}'s {a} (m, plate frame)")
      for k in (1, 2, 3) for a in "xy"],
    *[(f"pin{k}_r", pa.float64(), f"pin {k}'s radius (m)") for k in (1, 2, 3)],
    ("x", pa.float64(), "seated pose: part frame origin x (m, plate frame)"),
    ("y", pa.float64(), "seated pose: y (m)"),
    ("theta", pa.float64(), "seated pose: angle (rad)"),
    ("features", pa.string(), "contact features of pins 1, 2, 3 (eK edge K, vK vertex K; "
                              "'+' joins the features one pin touches)"),
    ("placements", pa.int64(), "translations of this design that fit the plate"),
    ("located", pa.bool_(), "sigma_min of the contact Jacobian (every contact) > "
                            "LOCATING_SIGMA_MIN, normals not parallel exactly"),
    ("locating_accuracy", pa.float64(), "worst pose error per unit pin error (m/m)"),
    ("hold_lo", pa.float64(), "hold interval: lowest pull direction (rad)"),
    ("hold_hi", pa.float64(), "hold interval: highest pull direction (rad), >= hold_lo "
                              "(may exceed pi)"),
    ("best_tilt", pa.float64(), "the hold interval's direction of largest margin (rad)"),
    ("hold_margin", pa.float64(), "its worst-case margin over the models"),
    ("funnel_tilt", pa.float64(), "the seat's direction (hold and funnel), rad"),
    ("funnel_margin", pa.float64(), "its margin: smallest of hold and funnel margins"),
    ("funnel_ok", pa.bool_(), "some direction holds and funnels for every model"),
    ("load_direction", pa.float64(), "direction of arrival at the seat (rad)"),
    ("plan_feasible", pa.bool_(), "a seating plan from the loading start exists"),
    ("plan_guaranteed", pa.bool_(), "every plan segment's worst-case margin > 0"),
    ("plan_nominal_seated", pa.bool_(), "the nominal simulation seats the part"),
    ("plan_modes", pa.string(), "the plan's modes, ';'-separated"),
    ("plan_directions", pa.string(), "the plan's directions (rad), ';'-separated"),
    ("region_size", pa.float64(), "start region: mean over the asked axes of the certified "
                                  "half-width over the asked one (0..1)"),
    ("region_fraction", pa.float64(), "start region: certified volume over the asked one"),
    ("region_dx", pa.float64(), "start region certified: half-width in x (m)"),
    ("region_dy", pa.float64(), "start region certified: half-width in y (m)"),
    ("region_dtheta", pa.float64(), "start region certified: half-width in theta (rad)"),
    ("region_runs", pa.int64(), "start region: engine runs made"),
    ("region_failure", pa.string(), "start region: the last box that failed and why"),
    ("success_rate", pa.float64(), "Monte Carlo: share of sampled models seated"),
    ("mc_runs", pa.int64(), "Monte Carlo: models run"),
    ("mc_start_region", pa.bool_(), "Monte Carlo: each run started at a pose drawn "
                                    "uniformly in the certified start region (false: at "
                                    "the loading start)"),
    ("stage", pa.string(), "last stage reached: geometry, location, hold, plan, "
                           "monte_carlo"),
    ("reason", pa.string(), "why the design stopped there (empty: it did not fail)"),
)
SCHEMA = pa.schema([(n, t) for n, t, _ in COLUMNS])


# --- per worker -------------------------------------------------------------------------------
_PROBLEMS: dict[str, DesignProblem] = {}
_WARM: list[float] = []


def warm_up() -> float:
    """Compile or load the numba kernel once in this process (seconds spent).

    Returns
    -------
    float
        The seconds the first call spent.
    """
    if not _WARM:
        from ..core import batch
        t = time.perf_counter()
        batch.warm_up()
        _WARM.append(time.perf_counter() - t)
    return _WARM[0]


try:  # the worker plugin exists only where distributed is installed
    from distributed.diagnostics.plugin import WorkerPlugin

    class WarmUp(WorkerPlugin):
        """Warms the numba kernel once on every worker when it joins."""

        name = "wrenchcone-warm-up"

        def setup(self, worker) -> None:
            """Warm the kernel on a worker that joins (:func:`warm_up`).

            Parameters
            ----------
            worker : distributed.Worker
                The worker.
            """
            warm_up()
except ImportError:  # pragma: no cover
    WarmUp = None  # type: ignore[assignment,misc]


def _problem(d: dict, key: str) -> DesignProblem:
    if key not in _PROBLEMS:
        _PROBLEMS[key] = DesignProblem.from_dict(d)
    return _PROBLEMS[key]


def _base_row(p: Placement) -> dict:
    row = {"design_id": p.design_id, "x": p.pose[0], "y": p.pose[1], "theta": p.pose[2],
           "features": ",".join(p.features), "placements": p.placements,
           "located": p.located,
           "locating_accuracy": p.accuracy if math.isfinite(p.accuracy) else None}
    for k in range(3):
        row[f"pin{k + 1}_i"], row[f"pin{k + 1}_j"] = p.holes[k]
        row[f"pin{k + 1}_x"], row[f"pin{k + 1}_y"] = p.positions[k]
        row[f"pin{k + 1}_r"] = p.radii[k]
    return row


def geometry_batch(problem: dict, key: str, triples: Sequence[Triple]) -> dict:
    """Stage 1 for a batch of pin triples: one row per placement (and the seconds spent,
    the placements outside the plate).

    Parameters
    ----------
    problem : dict
        The problem (:meth:`DesignProblem.to_dict <.problem.DesignProblem.to_dict>`).
    key : str
        The problem's hash: a worker rebuilds each problem once.
    triples : sequence of Triple
        The pin triples of the batch.

    Returns
    -------
    dict
        ``rows``, ``outside``, ``seconds``, ``tasks``.
    """
    warm_up()
    t0 = time.perf_counter()
    prob = _problem(problem, key)
    en = Enumerator(prob)
    rows, outside = [], 0
    for t in triples:
        found, out = en.placements(tuple(tuple(h) for h in t))
        outside += out
        for p in found:
            row = _base_row(p)
            if not p.located:
                row.update(stage="geometry", reason="not located: the contact normals are "
                           "concurrent or parallel (first order)")
            else:
                h = hold(prob, p.positions, p.pose, p.contacts, p.radii)
                h.pop("hold_intervals", None)
                if "reason" in h:
                    row.update(stage="location", **h)
                else:
                    enclosed = h.pop("enclosed")
                    row.update(stage="hold", reason=ENCLOSED if enclosed else "", **h)
            rows.append(row)
    return {"rows": rows, "outside": outside, "seconds": time.perf_counter() - t0,
            "tasks": len(triples)}


def plan_batch(problem: dict, key: str, designs: Sequence[dict], runs: int = 0,
               seed: int = DEFAULT_SEED,
               max_candidates: int = DEFAULT_PLAN_CANDIDATES) -> dict:
    """Stages 2 (runs = 0; with the problem's start region) and 3 (runs > 0: the Monte
    Carlo, from starts drawn in the region stage 2 certified when a design has one) for
    a batch of designs (their pin positions and seated pose).

    Parameters
    ----------
    problem : dict
        The problem (:meth:`DesignProblem.to_dict <.problem.DesignProblem.to_dict>`).
    key : str
        The problem's hash: a worker rebuilds each problem once.
    designs : sequence of dict
        Rows of stage 1 (pin positions and radii, seated pose, design_id).
    runs : int, optional
        Monte Carlo runs per design (0: stage 2).
    seed : int, optional
        The seed of the sampled models.
    max_candidates : int, optional
        The most candidate plans a design's search tries.

    Returns
    -------
    dict
        ``rows``, ``seconds``, ``tasks``.
    """
    warm_up()
    t0 = time.perf_counter()
    prob = _problem(problem, key)
    rows = []
    for d in designs:
        pos = [(d[f"pin{k}_x"], d[f"pin{k}_y"]) for k in (1, 2, 3)]
        radii = [d.get(f"pin{k}_r") for k in (1, 2, 3)]
        box = [d.get(f"region_d{a}") for a in ("x", "y", "theta")]
        out = plan(prob, pos, (d["x"], d["y"], d["theta"]), runs=runs, seed=seed,
                   max_candidates=max_candidates,
                   radii=None if None in radii else radii, region=runs == 0,
                   mc_region=None if runs == 0 or None in box else box)
        out.pop("plan_segments", None)
        out["design_id"] = d["design_id"]
        out["stage"] = "monte_carlo" if runs else "plan"
        out.setdefault("reason", "")
        rows.append(out)
    return {"rows": rows, "seconds": time.perf_counter() - t0, "tasks": len(designs)}


# --- the run ------------------------------------------------------------------------------------
def _hash(obj) -> str:
    return hashlib.sha256(json.dumps(obj, sort_keys=True, default=str).encode()).hexdigest()[:12]


def _table(rows: list[dict]) -> pa.Table:
    return pa.Table.from_pylist([{n: r.get(n) for n in SCHEMA.names} for r in rows],
                                schema=SCHEMA)


@dataclass
class StageStats:
    """What a stage did: batches computed and reused (resume), designs, the seconds the
    batches took inside the workers, and the stage's wall time.

    Parameters
    ----------
    name : str
        The stage.
    batches : int, optional
        Batches in the stage.
    computed : int, optional
        Batches computed in this run.
    reused : int, optional
        Batches read back from a previous run.
    tasks : int, optional
        Pin triples or designs.
    batch_seconds : list of float, optional
        The seconds each computed batch took in its worker.
    wall : float, optional
        The stage's wall time (s).
    """

    name: str
    batches: int = 0
    computed: int = 0
    reused: int = 0
    tasks: int = 0
    batch_seconds: list[float] = field(default_factory=list)
    wall: float = 0.0

    def to_dict(self) -> dict:
        """The statistics as JSON-able data.

        Returns
        -------
        dict
            The fields by name.
        """
        return {"name": self.name, "batches": self.batches, "computed": self.computed,
                "reused": self.reused, "tasks": self.tasks,
                "batch_seconds": self.batch_seconds, "wall": self.wall}


@dataclass
class DesignResult:
    """The ranked designs (``rows``, best first; ``table`` the same as Parquet), the
    stages' statistics, the poses that touch three pins but fit no translation on the
    plate (``outside``; -1 when every geometry batch was read back from a previous run,
    which does not store that count), and the ranking used.

    Parameters
    ----------
    rows : list of dict
        The ranked designs, best first.
    stats : list of StageStats
        One per stage.
    outside : int
        Poses that fit no translation on the plate (-1: not known).
    ranking : tuple of str
        The ranking keys.
    path : Path or None, optional
        The Parquet file written.
    """

    rows: list[dict]
    stats: list[StageStats]
    outside: int
    ranking: tuple[str, ...]
    path: Path | None = None

    @property
    def table(self) -> pa.Table:
        """The rows as a pyarrow Table of the Parquet schema."""
        return _table(self.rows)

    def top(self, k: int) -> list[dict]:
        """The ``k`` best designs.

        Parameters
        ----------
        k : int
            How many.

        Returns
        -------
        list of dict
            The first ``k`` rows.
        """
        return self.rows[:k]


class _Engine:
    """Runs batches: in this process (workers=0), or on a Dask client."""

    def __init__(self, scheduler: str | None, workers: int | None):
        self.client = self.cluster = None
        if workers == 0 and scheduler is None:
            return
        from dask.distributed import Client, LocalCluster

        if scheduler:
            self.client = Client(scheduler)
        else:
            n = workers or len(os.sched_getaffinity(0))
            self.cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                        dashboard_address=None, worker_dashboard_address=None,
                                        silence_logs=40)
            self.client = Client(self.cluster)
        self.client.register_plugin(WarmUp())

    def run(self, fn: Callable, jobs: list[tuple[str, tuple]], done: Callable[[str, dict], None]
            ) -> None:
        if not jobs:
            return
        if self.client is None:
            for name, args in jobs:
                done(name, fn(*args))
            return
        from dask.distributed import as_completed

        futures = {self.client.submit(fn, *args, key=f"wrenchcone-{name}", retries=2,
                                      pure=False): name for name, args in jobs}
        for fut in as_completed(futures):
            done(futures[fut], fut.result())
            fut.release()

    def close(self) -> None:
        if self.client is not None:
            self.client.close()
        if self.cluster is not None:
            self.cluster.close()


def _chunks(seq: list, size: int) -> list[list]:
    return [seq[i:i + size] for i in range(0, len(seq), size)]


def design_fixtures(part, plate, uncertainty=None, *, actuator="tilt",
                    start_offset: float | None = None, plans: int = DEFAULT_PLANS,
                    top: int = DEFAULT_TOP, runs: int = DEFAULT_RUNS,
                    seed: int = DEFAULT_SEED, ranking=None, out: str | Path | None = None,
                    scheduler: str | None = None, workers: int | None = None,
                    batch_triples: int = DEFAULT_BATCH_TRIPLES,
                    batch_plans: int = DEFAULT_BATCH_PLANS, triples: Sequence | None = None,
                    progress: bool = False,
                    on_batch: Callable[[str, str], None] | None = None,
                    plan_candidates: int = DEFAULT_PLAN_CANDIDATES,
                    start_region=None, region_work=None) -> DesignResult:
    """Every three-pin design of ``part`` on ``plate`` (module docstring), ranked.

    Parameters
    ----------
    part : Scene or str
        The part: a scene, or the path of a scene YAML (its workpiece and friction).
    plate : Plate, str or dict
        The plate, or the path / dict of a plate YAML (:mod:`.problem`).
    uncertainty : Uncertainty, tuple or None, optional
        The uncertainty, or a (lo, hi) friction interval of every pin, or None.
    actuator : str, optional
        "tilt" (default) or "spring:X,Y".
    start_offset : float or None, optional
        The loading task's start offset (m; default DEFAULT_START_OFFSET_M).
    plans : int, optional
        Designs planned.
    top : int, optional
        Designs run in Monte Carlo.
    runs : int, optional
        Models per design in the Monte Carlo.
    seed : int, optional
        The sampling seed.
    ranking : str or None, optional
        Comma-separated RANK_KEYS (default: plan_guaranteed, hold_margin,
        locating_accuracy; with a start region plan_guaranteed, region_size,
        hold_margin, locating_accuracy).
    out : str or None, optional
        Parquet path (its batches under OUT.parts/, reused when the run is resumed).
    scheduler : str or None, optional
        Address of a Dask scheduler (default: an embedded LocalCluster).
    workers : int or None, optional
        LocalCluster workers (default: one per core; 0: no Dask, this process).
    batch_triples : int, optional
        Batch size of stage 1 (pin triples).
    batch_plans : int, optional
        Batch size of stage 2 (designs planned).
    triples : sequence or None, optional
        Only these pin triples (tests, benchmarks); default every triple.
    progress : bool, optional
        A progress bar (tqdm) per stage on stderr.
    on_batch : callable or None, optional
        Called with (stage, batch name) after each batch is stored.
    plan_candidates : int, optional
        The most candidate plans a design's loading search tries
        (:data:`.problem.DEFAULT_PLAN_CANDIDATES`).
    start_region : StartRegion, sequence of 3 float or None, optional
        The loading task's start region, half-widths (dx m, dy m, dtheta rad) around the
        loading start, e.g. :data:`.problem.DEFAULT_START_REGION`; each planned design
        then plans the region its plan certifies and the default ranking puts its size
        after the guarantee. None (default): the loading start only.
    region_work : RegionWork or None, optional
        The work counts of the start region (None: :class:`.problem.RegionWork`'s
        defaults).

    Returns
    -------
    DesignResult
        The rows best first, one per placement that fits the plate.

    Raises
    ------
    DesignError
        A count (plans, top, runs, a batch size, workers) that is not a whole number in
        range, an invalid plate or problem (:class:`.problem.DesignProblem`), or an
        unknown ranking key.
    SceneError
        The part's scene cannot be loaded.
    UncertaintyError
        An invalid friction interval.
    """
    from ..core.scene_yaml import load_scene
    from ..core.uncertainty import as_uncertainty
    from .problem import DEFAULT_START_OFFSET_M, RegionWork, load_plate

    scene = load_scene(part)
    problem = DesignProblem(scene, load_plate(plate), as_uncertainty(uncertainty), actuator,
                            DEFAULT_START_OFFSET_M if start_offset is None else start_offset,
                            start_region, RegionWork() if region_work is None else region_work)
    for name, v, least in (("plans", plans, 0), ("top", top, 0), ("runs", runs, 0),
                           ("batch_triples", batch_triples, 1),
                           ("batch_plans", batch_plans, 1),
                           ("plan_candidates", plan_candidates, 1)):
        if isinstance(v, bool) or not isinstance(v, int) or v < least:
            raise DesignError(f"{name} must be a whole number >= {least}, got {v!r}")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int)
                                or workers < 0):
        raise DesignError(f"workers must be None (one per core) or a whole number >= 0 "
                          f"(0: this process), got {workers!r}")
    rank_keys = parse_ranking(ranking, problem.start_region is not None)
    pdict = problem.to_dict()
    pkey = _hash(pdict)
    parts = None
    if out is not None:
        parts = Path(str(out) + ".parts")
        parts.mkdir(parents=True, exist_ok=True)
    all_triples = [tuple(map(tuple, t)) for t in (pin_triples(problem) if triples is None
                                                  else triples)]
    engine = _Engine(scheduler, workers)
    stats: list[StageStats] = []
    try:
        def stage(name: str, fn: Callable, batches: list[tuple], key: str) -> list[dict]:
            st = StageStats(name, batches=len(batches))
            stats.append(st)
            results: dict[str, list[dict]] = {}
            jobs = []
            for k, args in enumerate(batches):
                bname = f"{name}-{key}-{k:05d}"
                f = None if parts is None else parts / f"{bname}.parquet"
                if f is not None and f.exists():
                    results[bname] = pq.read_table(f).to_pylist()
                    st.reused += 1
                else:
                    jobs.append((bname, args))
            bar = None
            if progress and jobs:
                from tqdm import tqdm
                bar = tqdm(total=len(batches), initial=st.reused, desc=name, unit="batch")
            t0 = time.perf_counter()

            def done(bname: str, res: dict) -> None:
                rows = res["rows"]
                if parts is not None:
                    tmp = parts / f".{bname}.tmp"
                    pq.write_table(pa.Table.from_pylist(rows) if rows else
                                   pa.table({"design_id": pa.array([], pa.string())}), tmp)
                    os.replace(tmp, parts / f"{bname}.parquet")
                results[bname] = rows
                st.computed += 1
                st.tasks += res["tasks"]
                st.batch_seconds.append(res["seconds"])
                if "outside" in res:
                    outside_count.append(res["outside"])
                if bar is not None:
                    bar.update(1)
                if on_batch is not None:
                    on_batch(name, bname)

            try:
                engine.run(fn, jobs, done)
            finally:
                if bar is not None:
                    bar.close()
            st.wall = time.perf_counter() - t0
            return [r for b in sorted(results) for r in results[b]]

        outside_count: list[int] = []
        key1 = _hash([pkey, batch_triples, all_triples])
        rows = stage("geometry", geometry_batch,
                     [(pdict, pkey, c) for c in _chunks(all_triples, batch_triples)], key1)
        byid = {r["design_id"]: dict(r) for r in rows}
        holding = rank_rows([dict(r) for r in byid.values()
                             if r.get("hold_margin") is not None and not r["reason"]],
                            rank_keys)
        chosen = holding[:plans]
        key2 = _hash([key1, [r["design_id"] for r in chosen], batch_plans, plan_candidates])
        for r in stage("plan", plan_batch, [(pdict, pkey, c, 0, seed, plan_candidates)
                                            for c in _chunks(chosen, batch_plans)], key2):
            byid[r["design_id"]].update(r)
        for r in holding[plans:]:
            byid[r["design_id"]]["reason"] = f"not planned: below the best {plans} holding " \
                                             "designs under the ranking"
        ranked = rank_rows([dict(r) for r in byid.values()
                            if r.get("plan_feasible")], rank_keys)[:top]
        key3 = _hash([key2, [r["design_id"] for r in ranked], runs, seed])
        if runs > 0:
            for r in stage("monte_carlo", plan_batch,
                           [(pdict, pkey, [c], runs, seed, plan_candidates) for c in ranked],
                           key3):
                byid[r["design_id"]].update(r)
    finally:
        engine.close()
    final = rank_rows([{n: r.get(n) for n in SCHEMA.names} for r in byid.values()],
                      rank_keys)
    outside = sum(outside_count) if outside_count else 0
    if parts is not None and not outside_count:  # every geometry batch was reused
        outside = -1
    result = DesignResult(final, stats, outside, rank_keys,
                          None if out is None else Path(out))
    if out is not None:
        tmp = Path(str(out) + ".tmp")
        pq.write_table(result.table, tmp)
        os.replace(tmp, out)
    return result


__all__ = ["COLUMNS", "DEFAULT_BATCH_PLANS", "DEFAULT_BATCH_TRIPLES", "DEFAULT_PLANS",
           "DEFAULT_RUNS", "DEFAULT_SEED", "DEFAULT_TOP", "DesignResult", "SCHEMA",
           "StageStats", "WarmUp", "design_fixtures", "geometry_batch", "plan_batch",
           "warm_up"]
