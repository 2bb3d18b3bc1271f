# Copyright 2026 wrenchcone_ros developers
# SPDX-License-Identifier: MIT
"""Ranking of designs: lexicographic on a list of columns, each in its own better
direction.

Default (DEFAULT_RANKING): guaranteed loading first (``plan_guaranteed`` true before
false), then the hold margin (larger first), then the locating accuracy (smaller
first: less pose error per unit pin error). With a start region (the loading task's
box of start poses), REGION_RANKING: the certified region's size (``region_size``,
larger first) comes after the guarantee, before the hold margin. A missing value (a
stage the design did not reach) ranks after every present one. The user may give any
list of RANK_KEYS.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

from .problem import DesignError

#: Column -> +1 when larger is better, -1 when smaller is better.
RANK_KEYS: dict[str, int] = {
    "plan_guaranteed": +1, "plan_feasible": +1, "success_rate": +1, "hold_margin": +1,
    "funnel_margin": +1, "locating_accuracy": -1, "placements": +1, "located": +1,
    "region_size": +1, "region_fraction": +1,
}

DEFAULT_RANKING: tuple[str, ...] = ("plan_guaranteed", "hold_margin", "locating_accuracy")
#: The default ranking of a run with a start region.
REGION_RANKING: tuple[str, ...] = ("plan_guaranteed", "region_size", "hold_margin",
                                   "locating_accuracy")


def parse_ranking(value: str | Sequence[str] | None, region: bool = False
                  ) -> tuple[str, ...]:
    """A ranking from "a,b,c" or a list (None: DEFAULT_RANKING, or REGION_RANKING for a
    run with a start region); refuses unknown keys.

    Parameters
    ----------
    value : str, sequence of str or None
        The keys.
    region : bool, optional
        Whether the run has a start region (the default ranking then).

    Returns
    -------
    tuple of str
        The ranking.

    Raises
    ------
    DesignError
        An empty list or a key not in RANK_KEYS.
    """
    if value is None:
        return REGION_RANKING if region else DEFAULT_RANKING
    keys = [k.strip() for k in value.split(",")] if isinstance(value, str) else list(value)
    bad = [k for k in keys if k not in RANK_KEYS]
    if not keys or bad:
        raise DesignError(f"rank keys must be a comma-separated list of {sorted(RANK_KEYS)}, "
                          f"got {value!r}")
    return tuple(keys)


def sort_key(row: Mapping, ranking: Sequence[str]) -> tuple:
    """The sort key of a row (ascending sort puts the best first); ties broken by
    design_id, so that the order is the same however the rows were computed.

    Parameters
    ----------
    row : Mapping
        A design's row.
    ranking : sequence of str
        The ranking keys.

    Returns
    -------
    tuple
        The key.
    """
    key = []
    for k in ranking:
        v = row.get(k)
        if v is None or (isinstance(v, float) and math.isnan(v)):
            key.append((1, 0.0))
        else:
            key.append((0, -RANK_KEYS[k] * float(v)))
    return (*key, str(row["design_id"]))


def rank_rows(rows: list[dict], ranking: Sequence[str]) -> list[dict]:
    """The rows sorted best first, each with its 1-based ``rank``.

    Parameters
    ----------
    rows : list of dict
        The designs' rows (each gets a ``rank``).
    ranking : sequence of str
        The ranking keys.

    Returns
    -------
    list of dict
        The same rows, best first.
    """
    out = sorted(rows, key=lambda r: sort_key(r, ranking))
    for k, r in enumerate(out):
        r["rank"] = k + 1
    return out


__all__ = ["DEFAULT_RANKING", "RANK_KEYS", "REGION_RANKING", "parse_ranking", "rank_rows", "sort_key"]
