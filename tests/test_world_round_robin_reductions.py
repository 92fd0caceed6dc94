"""The reductions on finite worlds under round-robin, a scheduler that keeps its own state
(SEMANTICS.md §4, §9): anonymity relabels identical robots as the scheduler says (its order
made the first it may fix) and Aut(G), fixing the meeting nodes, moves nodes and leaves the
order and turn alone. Checked here: the reference and bulk engines agree field by field with
the reductions on; verdicts are those of the unreduced search; the reduced counts are the
orbit counts of a plain search written here; a deliberately unsound reduction is caught; and
moving the initial configuration by an automorphism changes nothing."""

from __future__ import annotations

import itertools
from collections import deque
from collections.abc import Callable
from pathlib import Path
from typing import Any

import networkx as nx
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from networkx.algorithms.isomorphism import GraphMatcher

from gather_verify import kernels
from gather_verify.engine import world_bulk, world_search
from gather_verify.world_check import run_world_check
from gather_verify.worlds import get_world
from gather_verify.worlds.base import World
from schedulers.round_robin import RoundRobin
from tests.test_world_bulk import Chaotic, assert_same, searches

pytestmark = pytest.mark.skipif(not kernels.available(), reason="numba is not installed")

ROOT = Path(__file__).resolve().parent.parent
PETERSEN = ROOT / "scenarios" / "worlds" / "petersen.graphml"
WORLDS = ["ring:5", "ring:6", "ring:7", "grid:3x3", "torus:3x3", "petersen"]
SLOW_PETERSEN = [pytest.param(w, marks=pytest.mark.slow) if w == "petersen" else w
                 for w in WORLDS]
"""The engine comparisons on the Petersen graph (120 automorphisms, a frame each) run under
``-m slow``; its counts against the plain search run by default."""
ENGINES = ("reference", "bulk")


def world_of(name: str) -> World:
    return get_world(f"graph:{PETERSEN}") if name == "petersen" else get_world(name)


def spread(w: World, k: int, count: int) -> list[tuple[int, ...]]:
    """``count`` configurations of ``k`` robots on distinct nodes, spread over the list."""
    every = list(itertools.combinations(range(w.size), k))
    step = max(1, len(every) // count)
    return every[::step][:count]


# -- the engines, and the verdicts of the unreduced search ---------------------------------

def runs(w: World, robots: tuple[int, ...]) -> list[tuple[Any, list[int], dict[str, Any]]]:
    """Instances of one configuration: (algorithm, meeting nodes, run_world_check options),
    each with safety parts only (liveness switches the reductions off); with lights on two
    robots (three lit robots make the unreduced reference search slow)."""
    out: list[tuple[Any, list[int], dict[str, Any]]] = [
        ("go-to-target", [0], dict(task="gathering-on-meeting-nodes", properties=["final"])),
        (Chaotic(salt=sum(robots)), [], dict(task="gathering",
                                             properties=["gathered-when-final"])),
    ]
    if len(robots) == 2:
        out += [(Chaotic(2, salt=1), [], dict(task="gathering", lights="2", colours=[0, 1],
                                              properties=["gathered-when-final"])),
                ("bounce", [], dict(task="exclusive-perpetual-exploration",
                                    properties=["exclusivity"], lights="2"))]
    return out


@pytest.mark.parametrize("world_name", SLOW_PETERSEN)
def test_reduced_verdicts_are_the_unreduced_and_the_engines_agree(world_name: str) -> None:
    """Reference and bulk, reductions on and off, lights on and off: one verdict (and failing
    part) for all four; the same counts in both engines; the reduced search is never larger,
    and smaller somewhere (the reductions really are on)."""
    w = world_of(world_name)
    smaller = 0
    for robots in spread(w, 2, 3) + spread(w, 3, 2):
        for algorithm, meeting, kw in runs(w, robots):
            got = {(engine, reduction): run_world_check(
                w, list(robots), meeting, algorithm, "round-robin", engine=engine,
                reduction=reduction, **kw) for engine in ENGINES for reduction in (False, True)}
            outcome = {k: (r["verdict"], r["property"]) for k, r in got.items()}
            assert len(set(outcome.values())) == 1, (robots, algorithm, outcome)
            for reduction in (False, True):
                a, b = got["reference", reduction], got["bulk", reduction]
                assert (a["states"], a["transitions"]) == (b["states"], b["transitions"])
                assert b["engine"] == "bulk" and "engine_fallback" not in b
            on, off = got["bulk", True], got["bulk", False]
            assert on["reductions"].startswith("anonymity (robots relabelled")
            assert off["reductions"] == "off"
            assert on["states"] <= off["states"]
            smaller += on["states"] < off["states"]
            if on["verdict"] == "VERIFIED":  # every state seen: the reduction is a quotient
                assert on["transitions"] <= off["transitions"]
    assert smaller


@pytest.mark.parametrize("world_name", SLOW_PETERSEN)
def test_the_engines_agree_field_by_field_with_the_reductions(world_name: str) -> None:
    """States in BFS order, parents, edges with their events, final and stay facts, with
    lights and without, round-robin over every order and over one given order."""
    w = world_of(world_name)
    for robots in spread(w, 2, 3) + spread(w, 3, 2):
        for scheduler in ("round-robin", "round-robin:order=" + " ".join(
                str(i) for i in reversed(range(len(robots))))):
            ref, bulk = searches(w, robots, (0,), "go-to-target", scheduler,
                                 task="gathering-on-meeting-nodes", reduce=True)
            assert_same(ref, bulk)
            ref, bulk = searches(w, robots, (), Chaotic(2, salt=3), scheduler, lights="2",
                                 colours=[1] + [0] * (len(robots) - 1), reduce=True)
            assert_same(ref, bulk)


# -- the counts against a plain search -----------------------------------------------------

def automorphisms(w: World) -> list[tuple[int, ...]]:
    """Aut(G), computed here from the world's edges (networkx's matcher)."""
    g = nx.Graph()
    g.add_nodes_from(range(w.size))
    g.add_edges_from((v, u) for v, nbrs in enumerate(w.adjacency) for u in nbrs)
    return sorted(tuple(m[v] for v in range(w.size)) for m in GraphMatcher(g, g).isomorphisms_iter())


Robots = tuple[tuple[int, int], ...]
"""Per robot, by identity: its node and colour."""
Moves = Callable[[Robots, int], list[tuple[int, int]]]


def go_to_target(w: World, m: int) -> Moves:
    """go-to-target (SEMANTICS.md §9): a robot off ``m`` steps to any neighbour closer to it."""
    far = {m: 0}
    queue = deque([m])
    while queue:
        v = queue.popleft()
        for u in w.adjacency[v]:
            if u not in far:
                far[u] = far[v] + 1
                queue.append(u)

    def moves(robots: Robots, i: int) -> list[tuple[int, int]]:
        v = robots[i][0]
        return [(v, 0)] if v == m else [(u, 0) for u in w.adjacency[v] if far[u] < far[v]]

    return moves


def bounce(w: World) -> Moves:
    """bounce (SEMANTICS.md §10): colour 0 turns to 1 and stays; 1 turns to 0 and steps to any
    neighbour."""
    def moves(robots: Robots, i: int) -> list[tuple[int, int]]:
        v, c = robots[i]
        return [(v, 1)] if c == 0 else [(u, 0) for u in w.adjacency[v]]

    return moves


def naive(n: int, start: Robots, moves: Moves, group: list[tuple[int, ...]],
          order: tuple[int, ...] | None = None) -> tuple[int, int, int, int]:
    """Unreduced states and transitions under round-robin by a plain BFS over (robots by
    identity, order, turn) from every order (or the one given); then the orbits of the
    reachable states under relabellings of the robots (applied to the order too: with one
    order given, only those that keep it, the identity) times ``group`` (acting on nodes),
    and the transitions of one state per orbit."""
    orders = [order] if order is not None else list(itertools.permutations(range(n)))
    starts = [(start, o, 0) for o in orders]
    seen = set(starts)
    queue = deque(starts)
    degree: dict[Any, int] = {}
    while queue:
        state = queue.popleft()
        robots, order, turn = state
        i = order[turn]
        succ = moves(robots, i)
        degree[state] = len(succ)
        for action in succ:
            nxt = (robots[:i] + (action,) + robots[i + 1:], order, (turn + 1) % n)
            if nxt not in seen:
                seen.add(nxt)
                queue.append(nxt)
    relabellings = [s for s in itertools.permutations(range(n))  # new robot k: old s[k]
                    if tuple(s.index(o) for o in orders[0]) in orders]

    def orbit_key(state: Any) -> Any:
        robots, order, turn = state
        return min((tuple((g[robots[s[k]][0]], robots[s[k]][1]) for k in range(n)),
                    tuple(s.index(o) for o in order), turn)
                   for s in relabellings for g in group)

    orbits: dict[Any, int] = {}
    for state in seen:
        orbits.setdefault(orbit_key(state), degree[state])
    return len(seen), sum(degree.values()), len(orbits), sum(orbits.values())


CASES = [("ring:5", (0, 1, 3), [2]), ("ring:6", (0, 2, 3), [0]), ("ring:7", (1, 2, 5), [0]),
         ("grid:3x3", (0, 4, 8), [2]), ("grid:3x3", (1, 3, 5), [4]),
         ("torus:3x3", (0, 4, 8), [0]), ("torus:3x3", (1, 2, 3), [4]),
         ("petersen", (0, 5, 7), [0]),
         ("ring:6", (0, 3), []), ("ring:7", (0, 2), []), ("grid:3x3", (0, 4), []),
         ("torus:3x3", (0, 5), []), ("petersen", (0, 1), [])]
"""go-to-target with one meeting node (three robots), bounce with lights (two, no meeting
node, the whole of Aut(G))."""


def referee(world_name: str, robots: tuple[int, ...], meeting: list[int],
            order: tuple[int, ...] | None = None) -> None:
    """Both engines' counts, reductions on and off, against :func:`naive`: the unreduced
    counts are the reachable states and transitions, the reduced ones the orbit counts under
    anonymity times the automorphisms fixing the meeting nodes."""
    w = world_of(world_name)
    aut = automorphisms(w)
    assert sorted(w.symmetries("all")) == aut  # the group the reductions claim is Aut(G)
    group = [g for g in aut if all(g[m] == m for m in meeting)]
    if meeting:
        algorithm, moves, kw = "go-to-target", go_to_target(w, meeting[0]), dict(
            task="gathering-on-meeting-nodes", properties=["final"])
    else:
        algorithm, moves, kw = "bounce", bounce(w), dict(
            task="gathering", properties=["gathered-when-final"], lights="2")
    states, transitions, orbits, reduced = naive(len(robots), tuple((v, 0) for v in robots),
                                                 moves, group, order)
    scheduler = "round-robin" + ("" if order is None else ":order=" + " ".join(map(str, order)))
    for engine in ENGINES:
        off = run_world_check(w, list(robots), meeting, algorithm, scheduler,
                              engine=engine, reduction=False, **kw)
        on = run_world_check(w, list(robots), meeting, algorithm, scheduler,
                             engine=engine, reduction=True, **kw)
        assert off["stopped"] is None and on["stopped"] is None
        assert (off["states"], off["transitions"]) == (states, transitions), engine
        assert (on["states"], on["transitions"]) == (orbits, reduced), engine


@pytest.mark.parametrize(("world_name", "robots", "meeting"), CASES)
def test_reduced_counts_are_the_orbits_of_a_plain_search(world_name: str,
                                                         robots: tuple[int, ...],
                                                         meeting: list[int]) -> None:
    referee(world_name, robots, meeting)


@pytest.mark.parametrize(("world_name", "robots", "meeting", "order"), [
    ("grid:3x3", (0, 4, 8), [2], (2, 0, 1)), ("torus:3x3", (1, 2, 3), [4], (1, 2, 0)),
    ("ring:6", (0, 3), [], (1, 0))])
def test_one_given_order_reduces_by_the_automorphisms_alone(
        world_name: str, robots: tuple[int, ...], meeting: list[int],
        order: tuple[int, ...]) -> None:
    """With the order given, no relabelling keeps it but the identity: the reduced counts
    are the orbits under the automorphisms fixing the meeting nodes."""
    referee(world_name, robots, meeting, order)


SOUND_RELABEL = RoundRobin.relabel


def _keeps_the_order(self: RoundRobin, extra: object, n: int) -> tuple[tuple[int, ...], object]:
    """Unsound: the robots relabelled, the order left as it was (whose turn comes when is
    lost)."""
    perm, _ = SOUND_RELABEL(self, extra, n)
    return perm, extra


@pytest.mark.parametrize(("world_name", "robots", "meeting"),
                         [("grid:3x3", (0, 4, 8), [2]), ("ring:6", (0, 3), [])])
def test_an_unsound_relabelling_is_caught(world_name: str, robots: tuple[int, ...],
                                          meeting: list[int],
                                          monkeypatch: pytest.MonkeyPatch) -> None:
    """Relabelling the robots without relabelling the order (both engines ask the scheduler,
    so both are wrong alike): the counts leave the orbit counts and the referee says so."""
    referee(world_name, robots, meeting)
    monkeypatch.setattr(RoundRobin, "relabel", _keeps_the_order)
    with pytest.raises(AssertionError):
        referee(world_name, robots, meeting)


def test_sorting_the_robots_under_round_robin_is_caught(monkeypatch: pytest.MonkeyPatch) -> None:
    """Anonymity as for a scheduler without a state (robots sorted, the order kept) merges
    states with different futures: the referee catches it in both engines."""
    monkeypatch.setattr(world_search, "relabeller", lambda sched, n: None)
    monkeypatch.setattr(world_bulk, "relabeller", lambda sched, n: None)
    with pytest.raises(AssertionError):
        referee("grid:3x3", (0, 4, 8), [2])


# -- an automorphism of the initial configuration ------------------------------------------

@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(world_name=st.sampled_from(WORLDS), data=st.data(), reduction=st.booleans(),
       pick=st.integers(0, 2), salt=st.integers(0, 30))
def test_an_automorphic_image_has_the_same_verdict(world_name: str, data: st.DataObject,
                                                   reduction: bool, pick: int,
                                                   salt: int) -> None:
    """Every order is a start and the reductions are the same up to conjugation, so the image
    of the initial configuration (and meeting node) under an element of Aut(G) has the same
    verdict, failing part and counts."""
    w = world_of(world_name)
    # three lit robots make the unreduced search too large for a default test (see runs)
    n = data.draw(st.integers(2, 2 if pick == 2 else 3))
    robots = data.draw(st.lists(st.integers(0, w.size - 1), min_size=n, max_size=n,
                                unique=True))
    m = data.draw(st.integers(0, w.size - 1))
    g = data.draw(st.sampled_from(automorphisms(w)))
    algorithm, meeting, kw = [
        ("go-to-target", [m], dict(task="gathering-on-meeting-nodes", properties=["final"])),
        (Chaotic(salt=salt), [], dict(task="gathering", properties=["gathered-when-final"])),
        (Chaotic(2, salt=salt), [m], dict(task="gathering", lights="2",
                                          properties=["gathered-when-final"])),
    ][pick]
    a, b = (run_world_check(w, nodes, mm, algorithm, "round-robin", reduction=reduction, **kw)
            for nodes, mm in ((robots, meeting), ([g[v] for v in robots], [g[v] for v in meeting])))
    assert (a["verdict"], a["property"], a["states"], a["transitions"]) == \
        (b["verdict"], b["property"], b["states"], b["transitions"])
