# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""The uncertainty options shared by cone, check, classify, directions and sweep.

``--friction LO HI`` (every fixel's mu in [LO, HI]), ``--mass LO HI`` (kg),
``--inertia LO HI`` (kg m^2), ``--com-radius R`` or ``--com-box HX HY`` (m, around the
nominal centre of mass), ``--normal-error DELTA`` (rad, every contact normal),
``--epsilon``/``--beta``/``--seed`` (the scenario approach), ``--uncertainty FILE`` (a
YAML uncertainty, or a scene file's ``uncertainty:`` block). The scene file's own
``uncertainty:`` block applies too; options given on the command line override its
fields. No uncertainty at all: the nominal answers, unchanged.
"""

from __future__ import annotations

import argparse

from ..core.uncertainty import NOMINAL, Uncertainty, load_uncertainty, uncertainty_from_dict

FRAME_HELP = ("wrenches about the nominal com (nominal) or about each model's own com "
              "(com: a load through the centre of mass)")


def add_model_options(g, normal_error_note: str = "") -> None:
    """The uncertain parameters other than friction, on argument group ``g``: --mass,
    --inertia, --com-radius, --com-box, --normal-error (``normal_error_note`` appended
    to the last one's help)."""
    g.add_argument("--mass", nargs=2, type=float, metavar=("LO", "HI"), help="mass interval, kg")
    g.add_argument("--inertia", nargs=2, type=float, metavar=("LO", "HI"),
                   help="inertia interval about the com, kg m^2")
    g.add_argument("--com-radius", type=float, metavar="R",
                   help="the com anywhere within R m of its nominal place")
    g.add_argument("--com-box", nargs=2, type=float, metavar=("HX", "HY"),
                   help="the com anywhere within +-HX, +-HY m of its nominal place")
    g.add_argument("--normal-error", type=float, metavar="DELTA",
                   help="each contact normal turned by up to +-DELTA rad" + normal_error_note)


def add_uncertainty(sp: argparse.ArgumentParser, frame: bool = True) -> None:
    g = sp.add_argument_group("uncertain models (robust answers)")
    g.add_argument("--friction", nargs=2, type=float, metavar=("LO", "HI"),
                   help="every fixel's mu anywhere in [LO, HI] (independently)")
    add_model_options(g)
    g.add_argument("--epsilon", type=float, help="scenario approach: violation probability "
                   "(default 0.05)")
    g.add_argument("--beta", type=float, help="scenario approach: 1 - confidence "
                   "(default 1e-3)")
    g.add_argument("--seed", type=int, help="scenario approach: seed of the sampled models")
    g.add_argument("--uncertainty", metavar="FILE",
                   help="YAML uncertainty (or a scene file with an uncertainty: block)")
    if frame:
        g.add_argument("--frame", choices=("nominal", "com"), default="nominal",
                       help=FRAME_HELP)


_FIELDS = {"friction": "friction", "mass": "mass", "inertia": "inertia",
           "com_radius": "com_radius", "com_box": "com_box", "normal_error": "normal_error",
           "epsilon": "epsilon", "beta": "beta", "seed": "seed"}


def uncertainty_value(args: argparse.Namespace) -> Uncertainty:
    """The uncertainty the options (and the scene file) describe; :data:`NOMINAL` (the
    zero-width uncertainty) for none."""
    base = None
    if getattr(args, "uncertainty", None):
        base = load_uncertainty(args.uncertainty)
    elif getattr(args, "scene", "default") != "default":
        base = load_uncertainty(args.scene)
    d = base.to_dict() if base is not None else {}
    given = {key: getattr(args, attr) for attr, key in _FIELDS.items()
             if getattr(args, attr, None) is not None}
    if not given and base is None:
        return NOMINAL
    d.update((k, list(v) if isinstance(v, (list, tuple)) else v) for k, v in given.items())
    return uncertainty_from_dict(d)


__all__ = ["add_uncertainty", "uncertainty_value"]
