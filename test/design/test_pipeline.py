# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The staged run on Dask: the same Parquet content with one worker, a LocalCluster of
two, and a separately started `dask scheduler` with two `dask worker` processes; a
worker killed mid-run loses no design; an interrupted run resumes without computing its
finished batches again. A tiny problem (a rectangle, a few pin triples), at most two
workers."""

import fcntl
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pyarrow.parquet as pq
import pytest

from wrenchcone_ros.design import design_fixtures
from wrenchcone_ros.design.pipeline import SCHEMA
from wrenchcone_ros.design.problem import Plate

pytestmark = [pytest.mark.slow, pytest.mark.heavy]  # Dask clusters and worker processes: a minute and more

pytest.importorskip("distributed")

ROOT = Path(__file__).resolve().parents[2]
PART = {"workpiece": {"mass": 0.02, "inertia": 2e-6, "com": [0.015, 0.01],
                      "shape": {"type": "polygon",
                                "vertices": [[0, 0], [0.03, 0], [0.03, 0.02], [0, 0.02]]}},
        "friction": 0.3, "fixels": [[1.0, 1.0]]}
PLATE = Plate(0.01, (6, 5), 0.003)
TRIPLES = [((1, 4), (2, 3)), ((1, -1), (4, 1)), ((3, -2), (4, -1)), ((1, 1), (2, -3)),
           ((1, 0), (0, 3)), ((2, 0), (4, 1))]
KW = dict(plans=1, top=1, runs=3, batch_triples=1, batch_plans=1, triples=TRIPLES)


def run(out, **kw):
    return design_fixtures(PART, PLATE, (0.25, 0.35), out=out, **{**KW, **kw})


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The one-worker table, computed once for the whole run: the first pytest-xdist
    worker to need it writes it under a lock in the run's shared temporary directory,
    the others read it (a module fixture would compute it once per worker)."""
    base = tmp_path_factory.getbasetemp()
    worker = os.environ.get("PYTEST_XDIST_WORKER")  # gw0, gw1, ... under pytest-xdist
    shared = (base.parent if worker else base) / "design_reference"
    shared.mkdir(exist_ok=True)
    out, done = shared / "one.parquet", shared / "done"
    with open(shared / "lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not done.exists():
            res = run(out, workers=1)
            assert res.table.num_rows > 0
            # every stage runs: the plan stage, then the Monte Carlo on its feasible plan
            # (this rectangle's loading plan is the planner's last resort, one constant
            # tilt the engine seats it under, not guaranteed)
            mc = [r for r in res.rows if r["stage"] == "monte_carlo"]
            assert mc and all(r["plan_feasible"] and not r["plan_guaranteed"] for r in mc)
            done.touch()
    return pq.read_table(out)


def test_the_table_has_the_documented_columns(reference):
    assert reference.schema.equals(SCHEMA)


def test_a_local_cluster_of_two_gives_the_same_table(reference, tmp_path):
    out = tmp_path / "two.parquet"
    run(out, workers=2)
    assert pq.read_table(out).equals(reference)


@pytest.fixture()
def cluster(tmp_path):
    """`dask scheduler` and two `dask worker` processes (no nanny: a killed worker stays
    dead) on localhost; yields (address, worker processes)."""
    # the workers import the package under test (its source directory first), not another
    # copy the interpreter's site-packages may point at
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT / "wrenchcone_ros"),
                                                        str(ROOT)])}
    sfile = tmp_path / "scheduler.json"
    dask = str(Path(sys.executable).parent / "dask")
    procs = [subprocess.Popen([dask, "scheduler", "--host", "127.0.0.1", "--port", "0",
                               "--no-dashboard", "--scheduler-file", str(sfile)], env=env,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        for _ in range(200):
            if sfile.exists() and sfile.stat().st_size:
                break
            time.sleep(0.1)
        import json
        addr = json.loads(sfile.read_text())["address"]
        workers = [subprocess.Popen([dask, "worker", addr, "--nthreads", "1", "--no-nanny",
                                     "--no-dashboard"], env=env, stdout=subprocess.DEVNULL,
                                    stderr=subprocess.DEVNULL) for _ in range(2)]
        procs += workers
        from dask.distributed import Client
        with Client(addr) as c:
            c.wait_for_workers(2, timeout=60)
        yield addr, workers
    finally:
        for p in reversed(procs):  # the workers first, then the scheduler
            if p.poll() is None:
                p.send_signal(signal.SIGTERM)
            try:
                p.wait(5)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()


@pytest.mark.slow  # starts a scheduler and two worker processes: 10 to 40 s
def test_a_separate_scheduler_and_two_workers_give_the_same_table_even_when_one_dies(
        reference, cluster, tmp_path):
    addr, workers = cluster
    out = tmp_path / "cluster.parquet"
    killed = []

    def kill_one(stage, name):
        if not killed:  # one batch is stored, the others are queued or running
            workers[0].send_signal(signal.SIGKILL)
            killed.append(name)

    res = run(out, scheduler=addr, on_batch=kill_one)
    assert killed and workers[0].wait(10) == -signal.SIGKILL
    assert pq.read_table(out).equals(reference)
    assert res.stats[0].computed == len(TRIPLES)


def test_an_interrupted_run_resumes_without_recomputing_finished_batches(reference, tmp_path):
    out = tmp_path / "resumed.parquet"

    class Stop(Exception):
        pass

    done = []

    def stop_after_three(stage, name):
        done.append(name)
        if len(done) == 3:
            raise Stop

    with pytest.raises(Stop):
        run(out, workers=0, on_batch=stop_after_three)
    assert not out.exists()
    res = run(out, workers=0)
    geometry = res.stats[0]
    assert (geometry.reused, geometry.computed) == (3, len(TRIPLES) - 3)
    assert pq.read_table(out).equals(reference)
    again = run(out, workers=0)  # everything stored: nothing computed
    assert all(s.computed == 0 for s in again.stats)
    assert pq.read_table(out).equals(reference)
