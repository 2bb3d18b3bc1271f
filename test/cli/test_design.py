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
    ("--plan-candidates", "0", "plan_candidates must be a whole number >= 1, got 0"),
    ("--batch", "0", "batch_triples must be a whole number >= 1, got 0")])
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
