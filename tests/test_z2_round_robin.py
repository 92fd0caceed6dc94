"""The round-robin adversary on the paper's world, Z²: its order and turn are part of the
state, in the reference and both bulk engines alike (field by field, with the reductions on
and off, with lights and without), state counts equal to a naive search written here, a
broken algorithm caught with a trace that replays and names its order, and invariance under
the grid's symmetries."""

from __future__ import annotations

import json
from collections import deque
from itertools import permutations
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gather_verify.cli import main
from gather_verify.engine.encoding import Limits
from gather_verify.engine.explore import Exploration, explore_reference
from gather_verify.engine.fast_explore import explore_fast
from gather_verify.model import geometry
from gather_verify.model.configuration import Configuration
from gather_verify.model.view import Lights
from gather_verify.plane_check import run_check
from gather_verify.replay import replay

YARDSTICK = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)
"""SEMANTICS.md §4's yardstick configuration (go-to-target)."""
TWO = Configuration([(1, 1), (3, 2)], [(0, 0), (4, 0)], initial=True)
THREE = Configuration([(0, 0), (2, 1), (1, 3)], [(1, 1)], initial=True)
SMALL = Limits(margin=1, max_states=20_000)


def fields(e: Exploration) -> dict[str, Any]:
    """What two engines must agree on."""
    return {"states": e.states, "transitions": e.transitions, "stopped": e.stopped,
            "keys": list(e.keys), "parents": list(e.parents), "offsets": list(e.offsets),
            "targets": list(e.targets), "weights": list(e.weights),
            "changed_loops": e.changed_loops, "violations": {
                k: (v.state, v.reason) for k, v in e.violations.items()},
            "starts": e.starts}


@pytest.mark.parametrize("reduction", [False, True])
@pytest.mark.parametrize(("configuration", "algorithm", "scheduler"), [
    (YARDSTICK, "go-to-target", "round-robin"),
    (YARDSTICK, "go-to-target", "round-robin:order=2 0 1"),
    (YARDSTICK, "broken-stay", "round-robin"),
    (THREE, "broken-away", "round-robin"),
])
def test_the_bulk_engine_is_the_reference(configuration: Configuration, algorithm: str,
                                          scheduler: str, reduction: bool) -> None:
    ref = explore_reference(configuration, algorithm, scheduler, reduction=reduction,
                            limits=SMALL)
    bulk = explore_fast(configuration, algorithm, scheduler, reduction=reduction, limits=SMALL)
    assert bulk.engine == "bulk" and ref.turns is not None and bulk.turns is not None
    assert fields(bulk) == fields(ref)


@pytest.mark.parametrize("reduction", [False, True])
@pytest.mark.parametrize(("configuration", "algorithm", "scheduler"), [
    (TWO, "beacon", "round-robin"),
    (TWO, "beacon", "round-robin:order=1 0"),
    (THREE, "bounce", "round-robin"),
])
def test_the_lit_bulk_engine_is_the_reference(configuration: Configuration, algorithm: str,
                                              scheduler: str, reduction: bool) -> None:
    ref = explore_reference(configuration, algorithm, scheduler, reduction=reduction,
                            limits=SMALL, lights=Lights(2))
    bulk = explore_fast(configuration, algorithm, scheduler, reduction=reduction, limits=SMALL,
                        lights=Lights(2))
    assert fields(bulk) == fields(ref)


def naive_round_robin(robots: list[tuple[int, int]], m: tuple[int, int],
                      anonymity: bool) -> tuple[int, int]:
    """States and transitions of go-to-target under round-robin (SEMANTICS.md §4), by a plain
    BFS over (robots by identity, order, turn); with ``anonymity``, states equal up to a
    relabelling of the robots (applied to the order too), tried one by one."""
    n = len(robots)

    def moves(v: tuple[int, int]) -> list[tuple[int, int]]:
        if v == m:
            return [v]
        d = abs(v[0] - m[0]) + abs(v[1] - m[1])
        return [w for w in ((v[0] + 1, v[1]), (v[0] - 1, v[1]), (v[0], v[1] + 1),
                            (v[0], v[1] - 1))
                if abs(w[0] - m[0]) + abs(w[1] - m[1]) < d]

    def key(state: tuple[Any, ...]) -> tuple[Any, ...]:
        if not anonymity:
            return state
        at, order, turn = state
        return min((tuple(at[p.index(i)] for i in range(n)), tuple(p[r] for r in order), turn)
                   for p in permutations(range(n)))

    starts = [(tuple(robots), order, 0) for order in permutations(range(n))]
    seen = {key(s) for s in starts}
    queue, transitions = deque(starts), 0
    while queue:
        at, order, turn = queue.popleft()
        i = order[turn]
        for w in moves(at[i]):
            transitions += 1
            succ = (at[:i] + (w,) + at[i + 1:], order, (turn + 1) % n)
            if key(succ) not in seen:
                seen.add(key(succ))
                queue.append(succ)
    return len(seen), transitions


@pytest.mark.parametrize(("robots", "meeting"), [
    ([(0, 0), (3, 1), (1, 4)], (2, 2)),
    ([(0, 0), (2, 0)], (1, 1)),
    ([(0, 0), (1, 2), (3, 0)], (2, 1)),
])
def test_state_counts_are_a_naive_searchs(robots: list[tuple[int, int]],
                                          meeting: tuple[int, int]) -> None:
    c = Configuration(robots, [meeting], initial=True)
    for anonymity in (False, True):
        want = naive_round_robin(list(c.robots), meeting, anonymity)
        for run in (explore_reference, explore_fast):
            e = run(c, "go-to-target", "round-robin", anonymity=anonymity, symmetry=False)
            assert (e.states, e.transitions) == want, (run.__name__, anonymity)


def test_the_yardstick_counts() -> None:
    """The counts docs/worlds.md gives for round-robin on the plane."""
    counts = {(s, red): (e.states, e.transitions) for s in ("round-robin",
                                                            "round-robin:order=2 0 1")
              for red in (False, True)
              for e in [explore_fast(YARDSTICK, "go-to-target", s, reduction=red)]}
    assert counts == {("round-robin", False): (304, 413), ("round-robin", True): (249, 357),
                      ("round-robin:order=2 0 1", False): (48, 64),
                      ("round-robin:order=2 0 1", True): (43, 59)}


@pytest.mark.parametrize("engine", ["reference", "fast"])
def test_a_broken_algorithm_fails_with_a_trace_that_names_its_order(engine: str) -> None:
    r = run_check(YARDSTICK, algorithm="broken-stay", scheduler="round-robin", engine=engine,
                  max_states=10**5, max_seconds=120)
    assert r["verdict"] == "VIOLATED" and r["property"] == "final"
    trace = r["trace"]
    assert trace["scheduler"].startswith("round-robin:order=")
    assert replay(trace).confirmed
    other = run_check(YARDSTICK, algorithm="broken-stay", scheduler="round-robin",
                      engine="reference" if engine == "fast" else "fast",
                      max_states=10**5, max_seconds=120)
    assert other["trace"] == trace  # the same BFS, the same witness


def test_a_livelock_replays_only_in_its_order() -> None:
    """broken-away oscillates: under round-robin that is a fair cycle (every robot acts in
    turn). Its trace replays in the order it names; in another order the first step is not
    the scheduler's."""
    r = run_check(THREE, algorithm="broken-away", scheduler="round-robin", reduction=False,
                  max_states=10**5, max_seconds=120, properties=["termination"], margin=2)
    assert r["properties"]["termination"]["holds"] is False
    trace = r["trace"]
    assert trace["cycle_start"] is not None and replay(trace).confirmed
    order = trace["scheduler"].split("=", 1)[1].split()
    moved = dict(trace, scheduler="round-robin:order=" + " ".join(order[1:] + order[:1]))
    with pytest.raises(ValueError, match="not allowed"):
        replay(moved)


def test_a_cycle_must_return_to_its_turn() -> None:
    """One activation in which robot 0 stays returns to the same robots but not the same
    turn: no cycle under round-robin (the replay does not confirm it), a fair one-step
    cycle under the centralized adversary (robot 1 is idle and may stay)."""
    c = Configuration([(1, 1), (2, 1)], [(1, 1)], initial=True)  # broken-stay: both stay
    trace = run_check(c, algorithm="broken-stay", scheduler="round-robin:order=0 1",
                      max_states=10**4, max_seconds=60)["trace"]
    state = [{"node": list(v), "pending": None} for v in c.robots]
    loop = dict(trace, property="termination", reason="livelock", cycle_start=0,
                steps=[{"event": {"kind": "round", "robots": [0], "moves": []},
                        "state": state}])
    assert not replay(loop).confirmed
    assert replay(dict(loop, scheduler="centralized")).confirmed


def test_go_to_target_gathers_and_terminates_under_round_robin() -> None:
    """The turn going round gathered robots is a cycle that makes no move: moves are still
    bounded and termination holds (a run in it has reached a final state)."""
    r = run_check(YARDSTICK, algorithm="go-to-target", scheduler="round-robin",
                  max_states=10**5, max_seconds=120)
    assert r["verdict"] == "VERIFIED" and r["max_moves"] == 9


def test_the_broken_beacon_fails_under_round_robin_with_lights() -> None:
    r = run_check(TWO, algorithm="broken-beacon", scheduler="round-robin", lights="2",
                  max_states=10**5, max_seconds=120)
    assert r["verdict"] == "VIOLATED"
    assert r["trace"]["scheduler"].startswith("round-robin:order=")
    assert replay(r["trace"]).confirmed


def test_an_order_naming_an_unknown_robot_is_one_line(capsys: Any) -> None:
    assert main(["check", "--robots", "0,0 3,1 1,4", "--meeting", "2,2", "--algorithm",
                 "go-to-target", "--scheduler", "round-robin:order=0 1 3"]) == 2
    err = capsys.readouterr().err
    assert "each of the robots 0..2" in err and len(err.strip().splitlines()) == 1


@settings(max_examples=12, deadline=None)
@given(robots=st.lists(st.tuples(st.integers(0, 3), st.integers(0, 3)), min_size=2,
                       max_size=3, unique=True),
       meeting=st.tuples(st.integers(0, 3), st.integers(0, 3)),
       g=st.sampled_from(geometry.ALL), t=st.tuples(st.integers(-5, 5), st.integers(-5, 5)),
       reduction=st.booleans())
def test_an_isometric_image_has_the_same_counts_and_verdict(
        robots: list[tuple[int, int]], meeting: tuple[int, int], g: int,
        t: tuple[int, int], reduction: bool) -> None:
    """Every order is a start, so an isometry (which renumbers the sorted robots) maps the
    starts onto each other: the same state counts, the same verdicts."""
    def image(v: tuple[int, int]) -> tuple[int, int]:
        return geometry.add(geometry.apply(g, v), t)

    c = Configuration(robots, [meeting], initial=True)
    d = Configuration([image(v) for v in robots], [image(meeting)], initial=True)
    a, b = (run_check(x, algorithm="go-to-target", scheduler="round-robin", reduction=reduction,
                      max_states=10**5, max_seconds=120) for x in (c, d))
    assert (a["states"], a["transitions"], a["verdict"]) == \
        (b["states"], b["transitions"], b["verdict"])
    assert json.dumps(a["properties"], sort_keys=True) == json.dumps(b["properties"],
                                                                     sort_keys=True)


WANDER = Configuration([(0, 0), (0, 1)], [(1, 1), (1, 2)], initial=True)
"""broken-wander walks east: at margin 2 it already meets a configuration in U."""


@pytest.mark.parametrize("engine", ["fast", pytest.param("reference", marks=pytest.mark.slow)])
def test_the_region_grows_with_the_order_and_turn(engine: str) -> None:
    """A search stopped by the region runs again in a larger one: with keep_growing the
    larger search (keys over a larger box, the order and turn above them) reports the same
    trace, and more states."""
    kw: dict[str, Any] = {"algorithm": "broken-wander", "scheduler": "round-robin",
                          "engine": engine, "max_states": 20_000, "max_seconds": 300,
                          "properties": ["no-ungatherable"]}
    first = run_check(WANDER, **kw)
    grown = run_check(WANDER, keep_growing=True, **kw)
    assert first["limits"]["margin"] == 2 < grown["limits"]["margin"]
    assert first["verdict"] == grown["verdict"] == "VIOLATED"
    assert first["trace"] == grown["trace"] and replay(first["trace"]).confirmed
    assert first["states"] < grown["states"]


def test_a_lone_wanderer_grows_the_region_to_the_last_margin() -> None:
    c = Configuration([(0, 0)], [(0, 1)], initial=True)
    r = run_check(c, algorithm="broken-wander", scheduler="round-robin", max_states=100_000,
                  max_seconds=300)
    assert (r["verdict"], r["property"]) == ("VIOLATED", "move-bound")
    assert r["limits"]["margin"] == 32 and replay(r["trace"]).confirmed


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_simulated_run_activates_the_robots_in_one_cyclic_order(seed: int) -> None:
    from gather_verify.algorithms import get_algorithm
    from gather_verify.simulate import simulate

    run = simulate(YARDSTICK, get_algorithm("go-to-target"), "round-robin", seed=seed)
    assert run.outcome == "gathered"
    active = [e.robots[0] for e in run.events]
    order = active[:YARDSTICK.n]
    assert sorted(order) == list(range(YARDSTICK.n))
    assert active == [order[k % YARDSTICK.n] for k in range(len(active))]


def test_the_walk_over_the_bound_starts_from_every_start() -> None:
    """On an unfinished graph, the walk with the most moves (the move bound's witness and the
    drift's run) is looked for from each start of the scheduler, as the finished graph's
    longest run is: here the second start (id 1) has the worse run, 2 moves against 1."""
    from types import SimpleNamespace

    from gather_verify.properties.graph import most_moves

    edges = [[(2, 1)], [(3, 1)], [], [(4, 1)], []]  # 0 -> 2; 1 -> 3 -> 4
    off = [0]
    for out in edges:
        off.append(off[-1] + len(out))
    e = SimpleNamespace(states=5, changed_loops=0, transitions=off[-1], offsets=off,
                        targets=[t for out in edges for t, _ in out],
                        weights=[w for out in edges for _, w in out], starts=["s0", "s1"],
                        successors=lambda s: range(off[s], off[s + 1]))
    over = most_moves(e, 1)  # type: ignore[arg-type]
    assert over is not None and (over.path, over.weights, over.moves) == ([1, 3, 4], [1, 1], 2)
    one = SimpleNamespace(**{**vars(e), "starts": None})  # one start: id 0's run only
    walk = most_moves(one, 1)  # type: ignore[arg-type]
    assert walk is not None and (walk.path, walk.moves) == ([0, 2], 1)
