"""The facts table's shared facts (one target asked for every configuration when the
algorithm's target reads only the meeting nodes; ``in_U`` false everywhere when no
configuration over ``M`` is in U) against its reference path (``fast_facts`` off: every
target asked of the algorithm row by row, every row's facts read as its own), field by
field: every scenario of the plane, random configurations, a hook that lies."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gather_verify.algorithms import get_algorithm
from gather_verify.algorithms.broken import Drift
from gather_verify.algorithms.go_to_target import GoToTarget
from gather_verify.engine import facts_table, fast_explore
from gather_verify.engine.explore import Limits
from gather_verify.engine.facts_table import FactsTable
from gather_verify.model.configuration import Configuration
from gather_verify.scenario import load_scenario

ROOT = Path(__file__).resolve().parent.parent / "scenarios"
BY_MEETING = ["go-to-target", "broken-away", "broken-stay", "broken-wander", "broken-undefined",
              "broken-crash", "broken-answer"]
"""The algorithms whose target reads only the meeting nodes (go-to-target's)."""


def explored(c, algorithm, scheduler="async", *, fast, **kw):
    """The bulk search and its facts table, with the shared facts on (``fast``) or off."""
    made: list[FactsTable] = []

    class Recorded(FactsTable):
        fast_facts = fast

        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            made.append(self)

    real = fast_explore.FactsTable
    fast_explore.FactsTable = Recorded  # type: ignore[misc]
    try:
        e = fast_explore.explore_fast(c, algorithm, scheduler, **kw)
    finally:
        fast_explore.FactsTable = real  # type: ignore[misc]
    return e, made[0]


def fields(table: FactsTable) -> list[tuple]:
    """Every row's facts: its robots, move masks, flags, class and target."""
    out = []
    for r in range(table.size):
        t = table.target_id_of(r)
        out.append((table.configuration(r).robots, table.masks[r].tolist(),
                    table.flags[r].tolist(), table.in_u_of(r),
                    None if t < 0 else table.target_nodes[t]))
    return out


def assert_same(c, algorithm, scheduler="async", **kw):
    """The search with the shared facts and without: the same exploration, row by row the
    same facts."""
    fast, fast_table = explored(c, algorithm, scheduler, fast=True, **kw)
    ref, ref_table = explored(c, algorithm, scheduler, fast=False, **kw)
    assert (fast.states, fast.transitions, fast.stopped) == (ref.states, ref.transitions,
                                                             ref.stopped)
    assert list(fast.keys) == list(ref.keys) and list(fast.targets) == list(ref.targets)
    assert {k: vars(v) for k, v in fast.violations.items()} == \
        {k: vars(v) for k, v in ref.violations.items()}
    assert fast.vacuous == ref.vacuous
    assert fields(fast_table) == fields(ref_table)
    return fast_table


def _scenarios():
    out = []
    for path in sorted(ROOT.rglob("*.json")):
        s = load_scenario(path)
        if s.world == "grid" and s.lights is None:
            algorithms = {e.algorithm for e in s.expectations} | {s.algorithm or "paper"}
            out.append(pytest.param(path, sorted(algorithms | {"go-to-target"}),
                                    id=str(path.relative_to(ROOT))))
    return out


@pytest.mark.parametrize("path,algorithms", _scenarios())
def test_every_scenario_same_facts(path, algorithms):
    c = load_scenario(path).configuration
    for algorithm in algorithms:
        for reduction in (False, True):
            assert_same(c, algorithm, reduction=reduction,
                        limits=Limits(max_states=3_000, margin=2))


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    robots=st.lists(st.tuples(st.integers(0, 4), st.integers(0, 4)), min_size=1, max_size=4,
                    unique=True),
    meeting=st.lists(st.tuples(st.integers(0, 4), st.integers(0, 4)), min_size=1, max_size=3,
                     unique=True),
    algorithm=st.sampled_from(BY_MEETING + ["paper", "broken-drift", "broken-crash-target"]),
    scheduler=st.sampled_from(["async", "ssync", "fsync"]),
    reduction=st.booleans(),
)
def test_random_configurations_same_facts(robots, meeting, algorithm, scheduler, reduction):
    c = Configuration(robots, meeting, initial=True)
    assert_same(c, algorithm, scheduler, reduction=reduction,
                limits=Limits(max_states=5_000, margin=1))


def test_hook_only_for_go_to_target_own_target():
    assert all(get_algorithm(name).target_by_meeting() for name in BY_MEETING)
    assert not Drift().target_by_meeting()
    assert not get_algorithm("broken-crash-target").target_by_meeting()


class Lying(Drift):
    """Drift's target (the meeting node nearest the lowest robot), claimed to read only the
    meeting nodes."""

    name = "test-lying-drift"

    def target_by_meeting(self) -> bool:
        return True


def test_a_lying_hook_is_caught():
    """The comparison sees a wrong hook: a target that reads the robots, asked once."""
    c = Configuration([(0, 0), (4, 1), (1, 4)], [(0, 2), (4, 3)], initial=True)
    fast, _ = explored(c, Lying(), fast=True, reduction=False)
    ref, ref_table = explored(c, Lying(), fast=False, reduction=False)
    assert "target-invariance" in ref.violations and "target-invariance" not in fast.violations
    assert len(ref_table.target_nodes) == 2


def test_one_target_asked(monkeypatch):
    """go-to-target's target is asked once for the whole search (per orbit on the
    reference path), and the transition property reads it once per row code."""
    asked = []
    real = facts_table.target_of
    monkeypatch.setattr(facts_table, "target_of",
                        lambda algorithm, c: asked.append(c) or real(algorithm, c))
    c = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)
    table = assert_same(c, GoToTarget(), reduction=False)
    assert table.by_meeting and table.size > 100
    asked.clear()
    explored(c, GoToTarget(), fast=True, reduction=False)
    assert len(asked) == 1
