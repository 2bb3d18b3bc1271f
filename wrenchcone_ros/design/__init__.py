"""Fixture design on a modular plate: where three pins go so that a planar part is
located, held under an uncertain friction, funnelled into its seat and loadable, ranked,
computed on Dask (docs/fixture_design.md).

Layers (pyproject.toml, [tool.importlinter]), bottom to top: problem; geometry;
enumerate; stages; rank; pipeline; plot. Above the core, below the CLI.
"""
