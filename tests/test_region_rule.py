"""The region rule (``run_check``): the margin grows while the region stops a search that has
found no violation; ``keep_growing`` grows it after a violation too.

What the rule rests on: a search stopped by the region is a prefix of the same search in a
larger region (the same states in the same BFS order, up to the first step out), so every
violation the smaller search found, the larger one finds with the same trace.
"""

from __future__ import annotations

import json

import pytest

from gather_verify.cli import main
from gather_verify.engine import union
from gather_verify.model.configuration import Configuration
from gather_verify.plane_check import AUTO_MARGIN_MAX, run_check
from gather_verify.sweeps.census import enumerate_configurations
from gather_verify.sweeps.mclass import class_tasks, decide_class
from gather_verify.sweeps.sweep import SweepSettings, configuration_key

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
    """A lone robot off M walks east for ever (broken-wander): no safety violation, so the
    margin grows to the largest, and the region stops the last search too; that search's
    stored graph then holds a run over the move bound (and, without it, a drift)."""
    c = Configuration([(0, 0)], [(0, 1)], initial=True)
    r = check(c, "broken-wander", max_states=100_000)
    assert (r["verdict"], r["property"]) == ("VIOLATED", "move-bound")
    assert r["limits"]["margin"] == AUTO_MARGIN_MAX
    r = check(c, "broken-wander", max_states=100_000, properties=["final", "termination"])
    assert (r["verdict"], r["reason"]) == ("INCOMPLETE", "drift")
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


def test_the_union_hands_back_violations_past_the_first_margin(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """A seed whose own search needs a margin past 2 and reaches a violation: its margin-2
    search is stopped by the region, and whether that prefix already meets the violation
    (ending the search there) only its own search can say, so the union hands it back.
    (None of the 3 x 3 and 4 x 4 boxes with n, m <= 3 has one; forced here.)"""
    monkeypatch.setattr(union, "margin_needed", lambda c, group, box: 4)
    items = list(enumerate(enumerate_configurations(2, 1, 3, 3)))

    def decided(keep_growing: bool) -> tuple[set[int], set[int]]:
        s = SweepSettings(robots=2, meeting=1, box=(3, 3), algorithm="broken-stay",
                          scheduler="async", max_memory_mb=8000, keep_growing=keep_growing)
        violated, handed = set(), set()
        for members in class_tasks(items):
            d = decide_class(s, members, configuration_key)
            violated |= {r["index"] for r in d.rows if r["verdict"] == "VIOLATED"}
            handed |= {i for i, _ in d.fallback}
        return violated, handed

    violated, _ = decided(keep_growing=True)
    none, handed = decided(keep_growing=False)
    assert violated and not none and violated <= handed


def test_stores_keep_each_rule_apart() -> None:
    """Rows of one rule are never found under the other; rows stored before the rule was a
    setting (every region grown to the end) are found under ``keep_growing``."""
    def key(**kw: object) -> dict:
        return SweepSettings(robots=3, meeting=3, box=(4, 4), algorithm="paper",
                             scheduler="async", **kw).key()

    assert key(keep_growing=False) != key(keep_growing=True)
    assert key(keep_growing=False)["keep_growing"] is False
    assert "keep_growing" not in key(keep_growing=True)  # the settings such stores hold
