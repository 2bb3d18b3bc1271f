# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Fixture design on a modular plate: where three pins go so that a planar part is
located, held under an uncertain friction, funnelled into its seat and loadable, ranked,
computed on Dask (docs/fixture_design.md).

Layers (pyproject.toml, [tool.importlinter]), bottom to top: problem; geometry;
enumerate; stages; rank; pipeline; plot. Above the core, below the CLI. The pipeline
(and so :func:`design_fixtures`) needs pyarrow and dask.distributed (``pip install
.[design]``); it is imported when first used.
"""

from .problem import DesignError, DesignProblem, Plate, load_plate


def design_fixtures(*args, **kwargs):
    """:func:`wrenchcone_ros.design.pipeline.design_fixtures` (imported on first use).

    Parameters
    ----------
    *args
        As :func:`wrenchcone_ros.design.pipeline.design_fixtures`.
    **kwargs
        As :func:`wrenchcone_ros.design.pipeline.design_fixtures`.

    Returns
    -------
    DesignResult
        The ranked designs.
    """
    from .pipeline import design_fixtures as run
    return run(*args, **kwargs)


__all__ = ["DesignError", "DesignProblem", "Plate", "design_fixtures", "load_plate"]
