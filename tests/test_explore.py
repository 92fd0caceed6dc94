"""Explorer: the SEMANTICS.md yardstick counts, reductions, the §6 lower bound, limits."""

from __future__ import annotations

from collections import deque

import pytest

from gather_verify.engine.explore import Limits
from gather_verify.engine.search import explore
from gather_verify.model.configuration import Configuration
from gather_verify.plane_check import run_check
from schedulers import get_scheduler, initial_state

YARD = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)


@pytest.mark.parametrize("scheduler,states", [("fsync", 18), ("ssync", 216), ("async", 2184)])
def test_yardstick_counts_without_reduction(scheduler, states):
    e = explore(YARD, "go-to-target", scheduler, reduction=False)
    assert e.stopped is None and e.states == states
    if scheduler == "async":
        assert e.transitions == 7032


def test_yardstick_matches_independent_bfs():
    from gather_verify.algorithms import get_algorithm
    from gather_verify.algorithms.moves import move_sets
    algo = get_algorithm("go-to-target")

    def ms(robots):
        return move_sets(algo, Configuration.trusted(robots, YARD.meeting_nodes))
    seen = {initial_state(YARD.robots)}
    queue = deque(seen)
    while queue:
        s = queue.popleft()
        for _, t in get_scheduler("async").successors(s, ms):
            if t not in seen:
                seen.add(t)
                queue.append(t)
    assert len(seen) == 2184


CASES = [
    (YARD, "go-to-target"),
    (Configuration([(0, 0), (4, 0), (2, 3)], [(2, 1)], initial=True), "go-to-target"),
    (Configuration([(0, 1), (3, 3)], [(1, 1), (3, 1)], initial=True), "go-to-target"),
]


@pytest.mark.parametrize("scheduler", ["fsync", "ssync", "async"])
@pytest.mark.parametrize("case", range(len(CASES)))
def test_reductions_same_verdict_fewer_states(case, scheduler):
    c, algo = CASES[case]
    on = run_check(c, algorithm=algo, scheduler=scheduler, max_states=10**6, max_seconds=60,
                   force=True)
    off = run_check(c, algorithm=algo, scheduler=scheduler, max_states=10**6, max_seconds=60,
                    reduction=False, force=True)
    assert on["verdict"] == off["verdict"] and on["property"] == off["property"]
    assert on["max_moves"] == off["max_moves"]
    assert on["states"] <= off["states"]


def test_reduction_strictly_smaller_on_symmetric_m():
    on = explore(YARD, "go-to-target", "async")
    off = explore(YARD, "go-to-target", "async", reduction=False)
    assert on.states < off.states


@pytest.mark.parametrize("algorithm", ["go-to-target", "paper"])
@pytest.mark.parametrize("scheduler", ["fsync", "ssync", "async"])
@pytest.mark.parametrize("n", [2, 3, 4, 5, 6])
def test_lower_bound_path(n, scheduler, algorithm):
    """§6: n robots on (1,0)..(n,0), meeting node (0,0): exactly n(n+1)/2 moves (finding F2)."""
    c = Configuration([(i, 0) for i in range(1, n + 1)], [(0, 0)], initial=True)
    r = run_check(c, algorithm=algorithm, scheduler=scheduler, max_states=10**6,
                  max_seconds=120, properties=["move-bound"], force=True)
    assert r["verdict"] == "VERIFIED"
    assert r["max_moves"] == n * (n + 1) // 2


@pytest.mark.parametrize("limit", [{"max_states": 10}, {"max_seconds": 0.0}, {"margin": 0}])
def test_limits_give_incomplete(limit):
    c = Configuration([(0, 0), (5, 1), (1, 5)], [(3, 3)], initial=True)
    kwargs = {"max_states": 10**6, "max_seconds": 60.0, **limit}
    if "margin" in limit:  # broken-away leaves the MER
        r = run_check(YARD, algorithm="broken-away", scheduler="async", properties=["termination"],
                      **kwargs)
    else:
        r = run_check(c, algorithm="go-to-target", scheduler="async", **kwargs)
    assert r["verdict"] == "INCOMPLETE" and r["reason"]


def test_memory_limit_gives_incomplete():
    e = explore(YARD, "go-to-target", "async", limits=Limits(max_memory_mb=1))
    assert e.stopped == "memory"
