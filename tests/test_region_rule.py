"""The region rule (``run_check``): the margin grows while the region stops a search that has
found no violation; ``keep_growing`` grows it after a violation too.

What the rule rests on: a search stopped by the region is a prefix of the same search in a
larger region (the same states in the same BFS order, up to the first step out), so every
violation the smaller search found, the larger one finds with the same trace.
"""

from __future__ import annotations

import json

import pytest

from gather_verify.check import AUTO_MARGIN_MAX, run_check
from gather_verify.cli import main
from gather_verify.model.configuration import Configuration

# broken-wander walks away: at margin 2 it already meets a configuration in U
WANDER = Configuration([(0, 0), (0, 1)], [(1, 1), (1, 2)], initial=True)
# the paper's algorithm from an I22 configuration of the 4 x 4 box that walks away
# (docs/findings.md): a deadlock at margin 2; with keep_growing it runs to margin 32
WALK = Configuration([(0, 0), (0, 1), (3, 2)], [(1, 3), (2, 0)], initial=True)


def check(c: Configuration, algorithm: str, **kw: object) -> dict:
    return run_check(c, algorithm=algorithm, **{"scheduler": "async", "max_seconds": 600, **kw})


def test_a_violation_ends_the_growth() -> None:
    r = check(WANDER, "broken-wander", max_states=100_000)
    assert r["verdict"] == "VIOLATED" and r["limits"]["margin"] == 2
    assert r["property"] == "no-ungatherable" and not r["limits"]["keep_growing"]
    grown = check(WANDER, "broken-wander", max_states=100_000, keep_growing=True)
    assert grown["verdict"] == "VIOLATED" and grown["limits"]["margin"] > 2
    # the larger search meets a property first in the verdict order as well, and the
    # one the smaller search found with the same reason
    assert grown["property"] == "final"
    assert grown["properties"]["no-ungatherable"] == r["properties"]["no-ungatherable"]
    assert r["properties"]["final"]["holds"] is None  # not met in the smaller region


@pytest.mark.parametrize(("c", "algorithm", "prop", "scheduler", "engine"), [
    (WANDER, "broken-wander", "no-ungatherable", "async", "fast"),
    (WANDER, "broken-wander", "no-ungatherable", "async", "reference"),
    (WANDER, "broken-wander", "no-ungatherable", "ssync", "auto"),
    (WANDER, "broken-wander", "no-ungatherable", "fsync", "auto"),
    (WALK, "paper", "final", "async", "auto"),
])
def test_the_larger_search_reports_the_same_trace(c: Configuration, algorithm: str, prop: str,
                                                  scheduler: str, engine: str) -> None:
    kw = {"max_states": 20_000, "properties": [prop], "scheduler": scheduler, "engine": engine}
    first = check(c, algorithm, **kw)
    grown = check(c, algorithm, keep_growing=True, **kw)
    assert first["limits"]["margin"] == 2 < grown["limits"]["margin"]
    assert first["verdict"] == grown["verdict"] == "VIOLATED"
    assert first["property"] == grown["property"] == prop
    assert first["trace"] == grown["trace"]
    assert first["states"] < grown["states"]


def test_without_a_violation_the_region_still_grows() -> None:
    """A lone robot off M walks east for ever (broken-wander): no violation, so the margin
    grows to the largest, and the region stops the last search too."""
    r = check(Configuration([(0, 0)], [(0, 1)], initial=True), "broken-wander",
              max_states=100_000)
    assert (r["verdict"], r["reason"]) == ("INCOMPLETE", "region")
    assert r["limits"]["margin"] == AUTO_MARGIN_MAX


def test_keep_growing_from_the_command_line(capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["check", "--robots", "0,0 0,1", "--meeting", "1,1 1,2", "--algorithm",
            "broken-wander", "--max-states", "100000", "--json"]
    assert main(argv) == 1
    first = json.loads(capsys.readouterr().out)
    assert main([*argv, "--keep-growing"]) == 1
    grown = json.loads(capsys.readouterr().out)
    assert (first["limits"]["margin"], first["property"]) == (2, "no-ungatherable")
    assert grown["limits"]["margin"] > 2 and grown["limits"]["keep_growing"]
