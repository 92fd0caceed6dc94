"""Explorer benchmark: states/s, transitions/s and bytes per stored state (whole process).

The instance of issue 4: go-to-target, ASYNC, reductions off, robots
``0,0 5,1 1,5 6,6 3,0``, meeting node ``3,3`` (4,939,200 states); ``quick``
uses the SEMANTICS.md yardstick (2184 states). Bytes per state are the growth
of the process RSS during the search divided by the states stored.
"""

from __future__ import annotations

from typing import Any

from gather_verify.configuration import Configuration
from gather_verify.explore import Limits, explore, rss_mb

FULL = ([(0, 0), (5, 1), (1, 5), (6, 6), (3, 0)], [(3, 3)])
QUICK = ([(0, 0), (3, 1), (1, 4)], [(2, 2)])


def bench(quick: bool = False, algorithm: str = "go-to-target", scheduler: str = "async",
          reduction: bool = False, max_seconds: float = 3600.0) -> dict[str, Any]:
    """One measured exploration (the properties are not evaluated, only the search)."""
    robots, meeting = QUICK if quick else FULL
    c = Configuration(robots, meeting, initial=True)
    before = rss_mb()
    e = explore(c, algorithm, scheduler, reduction=reduction, properties=[],
                limits=Limits(max_seconds=max_seconds))
    grown = max(e.peak_rss_mb - before, 0.0) * 2**20
    return {"instance": "quick" if quick else "issue-4", "algorithm": algorithm,
            "scheduler": scheduler, "reduction": reduction, "states": e.states,
            "transitions": e.transitions, "seconds": round(e.seconds, 3),
            "states_per_second": round(e.states / e.seconds), "complete": e.stopped is None,
            "transitions_per_second": round(e.transitions / e.seconds),
            "bytes_per_state": round(grown / e.states, 1)}
