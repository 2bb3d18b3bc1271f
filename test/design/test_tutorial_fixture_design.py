# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""docs/fixture_design.md runs as shown: its `wrenchcone design` commands print what the
tutorial shows (numbers to a relative 1e-6, test/helpers/docs_examples.py) and write their
Parquet files; its pycon block is a doctest. In a scratch directory holding
``examples/``."""

import contextlib
import io
import math
import os
import shlex

import pyarrow.parquet as pq
import pytest

from helpers.docs_examples import ROOT, blocks, commands, run_doctest, same_output  # noqa: E402

TUTORIAL = ROOT / "docs" / "fixture_design.md"


@pytest.fixture(scope="module")
def scratch(tmp_path_factory):
    d = tmp_path_factory.mktemp("tutorial")
    (d / "examples").symlink_to(ROOT / "examples")
    old = os.getcwd()
    os.chdir(d)
    try:
        yield d
    finally:
        os.chdir(old)


@pytest.mark.heavy
@pytest.mark.slow  # three designs with plans and 45 simulated runs, three start regions
def test_the_tutorial_commands_print_what_it_shows(scratch):
    from wrenchcone_ros import cli

    cases = commands(TUTORIAL)
    assert [c.command.split()[2] for c in cases] == ["examples/pawl_seating.yaml",
                                                     "examples/tbar_swing.yaml",
                                                     "examples/pawl_seating.yaml",
                                                     "examples/pawl_seating.yaml"]
    # sections 2 to 4 from the loading start only; section 5 with the default region
    assert ["--no-start-region" in c.command for c in cases] == [True, True, True, False]
    for c in cases:
        out = io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
            assert cli.main(shlex.split(c.command)[1:]) == 0, str(c)
        assert same_output(c.output, out.getvalue()), (str(c), out.getvalue())
    table = pq.read_table(scratch / "pawl.parquet")
    rows = table.to_pylist()
    assert table.num_rows == 24 and rows[1]["features"] == "e0,e0,e1"
    assert sum(r["mc_runs"] or 0 for r in rows) == 30  # 10 runs for each of the top 3
    # the fixed pins keep their radii, the third pin takes either size
    third = set()
    for r in pq.read_table(scratch / "pawl_mixed.parquet").to_pylist():
        radius = {(r[f"pin{k}_i"], r[f"pin{k}_j"]): r[f"pin{k}_r"] for k in (1, 2, 3)}
        assert radius.pop((1, 0)) == 0.002 and radius.pop((5, 0)) == 0.004
        third |= set(radius.values())
    assert third == {0.002, 0.004}
    # the start regions: only the planned designs have one, sized as its half-widths say
    rows = pq.read_table(scratch / "pawl_region.parquet").to_pylist()
    planned = [r for r in rows if r["stage"] == "plan"]
    assert len(planned) == 3 and all(r["region_size"] is None for r in rows
                                     if r["stage"] != "plan")
    for r in planned:
        asked = (0.002, 0.002, math.radians(5.0))
        got = (r["region_dx"], r["region_dy"], r["region_dtheta"])
        assert r["region_size"] == pytest.approx(sum(g / a for g, a in zip(got, asked)) / 3)
    assert [r["region_size"] for r in planned] == sorted(
        (r["region_size"] for r in planned), reverse=True)


@pytest.mark.slow
def test_the_tutorial_python(scratch):
    pycon = [b for b in blocks(TUTORIAL) if b.lang == "pycon"]
    assert len(pycon) == 1
    failures, report = run_doctest(pycon[0])
    assert failures == 0, report


def test_the_tutorial_figure_exists():
    text = TUTORIAL.read_text()
    assert "figures/design_pawl.png" in text
    assert (ROOT / "docs" / "figures" / "design_pawl.png").stat().st_size > 10_000
