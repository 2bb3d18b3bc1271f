# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""`wrenchcone design` refuses bad input with one line on stderr and exit code 2 (what
was wrong and what is allowed); the plate file's schema."""

import contextlib
import io

import pytest

from wrenchcone_ros import cli
from wrenchcone_ros.design.problem import DesignError, Plate, load_plate, plate_from_dict


def run(*argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = cli.main(list(argv))
        except SystemExit as exc:
            code = exc.code
    return code, out.getvalue(), err.getvalue()


def test_the_plate_is_required():
    code, _out, err = run("design", "examples/pawl_seating.yaml", "--out", "x.parquet")
    assert code == 2 and "--plate" in err


@pytest.mark.parametrize("plate,words", [
    ({"pitch": 0.01, "extent": [4, 4], "pin_radius": 0.006}, "pin_radius must be in [0, pitch / 2)"),
    ({"pitch": 0.01, "extent": [4, 4]}, "missing required key 'pin_radius'"),
    ({"pitch": -1, "extent": [4, 4], "pin_radius": 0.001}, "plate pitch (m) must be"),
    ({"pitch": 0.01, "extent": [4, 4], "pin_radius": 0.001, "fixed_pins": [[9, 0]]},
     "fixed pin 1 must be a hole [i, j] with 0 <= i < 4"),
    ({"pitch": 0.01, "extent": [4, 4], "pin_radius": 0.001, "holes": 3}, "unknown key"),
    ({"pitch": 0.01, "extent": [4, 4], "pin_radii": [0.002, 0.005]},
     "pin_radii 2 must be in [0, pitch / 2) = [0, 0.005) m"),
    ({"pitch": 0.01, "extent": [4, 4], "pin_radii": [0.002, 0.003], "fixed_pins": [[1, 0]]},
     "fixed pin 1 must give its radius [i, j, r] (m): the plate offers several"),
])
def test_bad_plates_are_refused_with_what_is_allowed(tmp_path, plate, words):
    import yaml

    f = tmp_path / "plate.yaml"
    f.write_text(yaml.safe_dump(plate))
    with pytest.raises(DesignError, match=".*"):
        load_plate(f)
    code, _out, err = run("design", "examples/pawl_seating.yaml", "--plate", str(f),
                          "--out", str(tmp_path / "d.parquet"), "--workers", "0")
    assert code == 2 and words in err and err.count("\n") == 1, err


def test_a_disc_part_is_refused(tmp_path):
    f = tmp_path / "plate.yaml"
    f.write_text("pitch: 0.01\nextent: [4, 4]\npin_radius: 0.001\n")
    code, _out, err = run("design", "examples/paper_disc.yaml", "--plate", str(f),
                          "--out", str(tmp_path / "d.parquet"), "--workers", "0")
    assert code == 2 and "the part must be a polygon" in err


@pytest.mark.parametrize("option, value, words", [
    ("--plan-candidates", "0", "--plan-candidates must be a whole number >= 1, got 0"),
    ("--batch", "0", "--batch must be a whole number >= 1, got 0")])
def test_bad_counts_are_refused_with_what_is_allowed(tmp_path, option, value, words):
    f = tmp_path / "plate.yaml"
    f.write_text("pitch: 0.01\nextent: [4, 4]\npin_radius: 0.001\n")
    code, _out, err = run("design", "examples/pawl_seating.yaml", "--plate", str(f), option,
                          value, "--out", str(tmp_path / "d.parquet"), "--workers", "0")
    assert code == 2 and words in err and err.count("\n") == 1, err


def test_plate_geometry():
    p = plate_from_dict({"pitch": 0.01, "extent": [3, 2], "pin_radius": 0.002,
                         "keep_out": [[0.015, -1, 1, 1]]})
    assert p.hole(2, 1) == (0.02, 0.01) and p.bounds == (-0.005, -0.005, 0.025, 0.015)
    assert p.blocked(2, 0) and not p.blocked(1, 0)
    assert isinstance(load_plate(p), Plate)


def _plate(tmp_path):
    f = tmp_path / "plate.yaml"
    f.write_text("pitch: 0.01\nextent: [4, 4]\npin_radius: 0.001\n")
    return str(f)


@pytest.mark.parametrize("extra, words", [
    (["--workers", "-1"], "--workers must be >= 0"),
    (["--workers", "1", "--scheduler", "tcp://127.0.0.1:1"], "give one of them"),
    (["--top", "-1"], "--top must be a whole number >= 0, got -1"),
    (["--runs", "-2"], "--runs must be a whole number >= 0, got -2"),
    (["--seed", "-1"], "--seed must be a whole number >= 0, got -1"),
    (["--rank", "speed"], "rank keys must be a comma-separated list"),
    (["--plot", "{tmp}/missing/sheet.png"], "--plot {tmp}/missing/sheet.png: the folder"),
    (["--plot", "{tmp}/sheet.txt"], "the format must be one of .png, .svg, .pdf, got '.txt'"),
    (["--out", "{tmp}/missing/d.parquet"], "--out {tmp}/missing/d.parquet: the folder"),
    (["--out", "{tmp}"], "is a folder"),
    (["--start-region", "-0.001", "0", "0"], "--start-region takes DX DY (m) and DTHETA "
     "(degrees, at most 180), each finite and >= 0, got -0.001 0 0"),
    (["--start-region", "0.002", "0.002", "200"], "(degrees, at most 180)"),
    (["--start-region", "0.002", "0.002", "5", "--no-start-region"],
     "not allowed with argument"),
])
def test_bad_options_are_refused_before_the_work(tmp_path, extra, words):
    # the pawl on a real plate: were any of these checked only after the work, the run
    # would take tens of seconds and leave OUT.parts/ behind
    extra = [e.format(tmp=tmp_path) for e in extra]
    out = ["--out", str(tmp_path / "d.parquet")] if "--out" not in extra else []
    code, stdout, err = run("design", "examples/pawl_seating.yaml", "--plate",
                            "examples/plates/plate_pawl.yaml", *out, *extra)
    assert code == 2 and words.format(tmp=tmp_path) in err and err.count("\n") == 1, err
    assert not stdout and not list(tmp_path.glob("*.parts"))


def test_a_design_error_does_not_import_the_pipeline(tmp_path):
    # errors as fast as --help: Dask, pyarrow and the planner are imported for the work
    import subprocess
    import sys
    code = ("import sys; from wrenchcone_ros import cli; "
            "rc = cli.main(['design', 'examples/pawl_seating.yaml', '--plate', "
            "'examples/plates/plate_pawl.yaml', '--out', 'x.parquet', '--top', '-1']); "
            "heavy = [m for m in ('dask', 'distributed', 'pyarrow', 'pymunk') "
            "if m in sys.modules]; print(rc, heavy)")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120)
    assert res.stdout.strip() == "2 []", (res.stdout, res.stderr)


@pytest.mark.slow  # one small design run in this process: a few seconds
def test_a_complete_run_says_what_it_wrote_and_removes_its_parts(tmp_path):
    plate = tmp_path / "plate.yaml"
    plate.write_text("pitch: 0.01\nextent: [9, 6]\npin_radius: 0.003\n"
                     "fixed_pins: [[2, 2], [5, 2], [6, 2]]\n")
    out, sheet = tmp_path / "d.parquet", tmp_path / "sheet.png"
    args = ["design", "examples/pawl_seating.yaml", "--plate", str(plate), "--plans", "0",
            "--runs", "0", "--workers", "0", "--out", str(out)]
    code, stdout, err = run(*args, "--plot", str(sheet))
    assert code == 0, err
    assert f"wrote {out} (" in stdout and f"wrote {sheet} (" in stdout
    assert out.exists() and sheet.stat().st_size > 10_000
    assert not (tmp_path / "d.parquet.parts").exists()
    code, stdout, err = run(*args, "--keep-parts")
    assert code == 0 and (tmp_path / "d.parquet.parts").is_dir() and "kept" in stdout
