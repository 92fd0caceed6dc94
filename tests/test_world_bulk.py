"""The finite-world bulk engine (gather_verify/engine/world_bulk.py) against the reference
search (gather_verify/engine/world_search.py), field by field: the states in BFS order,
their parents, every edge with its event, the final and stay facts, the transitions, the
halt and the stop under a state limit; and the tasks' findings on both (the compiled tests
on the bulk engine's arrays, the Python reading on the reference's). On every scenario of
scenarios/worlds/, on whole sweeps of small worlds under every scheduler, with and without
the reductions, with lights, and on SEMANTICS §9's and §10's numbers."""

from __future__ import annotations

import itertools
import json
from dataclasses import replace
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gather_verify import kernels
from gather_verify.algorithms import get_algorithm
from gather_verify.algorithms.base import Unhandled
from gather_verify.engine import world_bulk, world_search
from gather_verify.engine.encoding import Limits
from gather_verify.scenario import load_scenario
from gather_verify.tasks import Context, get_task
from gather_verify.world_check import run_world_check
from gather_verify.worlds import get_world
from gather_verify.worlds.base import World
from gather_verify.worlds.moves import WorldMoves, parse_lights

pytestmark = pytest.mark.skipif(not kernels.available(), reason="numba is not installed")

SCHEDULERS = ("fsync", "ssync", "async", "centralized", "round-robin")
TASK_STATES = 20_000
"""The tasks' Python reading (one Tarjan per node for perpetual exploration) runs on
searches up to this size."""
ROOT = Path(__file__).resolve().parent.parent
HOUSE = "0 1\n1 2\n2 3\n3 0\n2 4\n3 4\n"
"""A small graph file with few automorphisms (a square with a roof)."""


class Chaotic:
    """A test algorithm that reads everything: a deterministic function of the view (the
    distances to the robots it sees, their multiplicity, its light), so configurations,
    multiplicities and colours all matter; with lights it answers a colour too."""

    name = "chaotic"

    def __init__(self, colours: int = 1, salt: int = 0):
        self.colours, self.salt = colours, salt

    def decide(self, view: Any) -> Any:
        me = view.me
        nbrs = view.neighbours()
        h = self.salt
        for k, r in enumerate(sorted(view.robots, key=repr)):
            h = h * 7 + (k + 2) * view.distance(me, r)
        h += 3 * view.multiplicity()
        if self.colours > 1:
            h += 5 * view.light
        k = h % (len(nbrs) + 1)
        node = me if k == len(nbrs) else nbrs[k]
        return (node, h % self.colours) if self.colours > 1 else node


class Picky(Chaotic):
    """:class:`Chaotic` with no rule for some views (``defined``) and a bug in others
    (``crash``), so a search halts part-way through."""

    name = "picky"

    def decide(self, view: Any) -> Any:
        spread = sum(view.distance(view.me, r) for r in view.robots)
        if spread == 3:
            raise Unhandled("a spread of three")
        if spread == 5 and view.multiplicity():
            return 1 // 0
        return super().decide(view)


class NodePicky:
    """An algorithm that answers by its node only (the ``answers_by_node`` hook on), with no
    rule two hops from the meeting node and a bug four hops from it."""

    name = "node-picky"

    def answers_by_node(self) -> bool:
        return True

    def decide(self, view: Any) -> Any:
        d = min(view.distance(view.me, m) for m in view.meeting_nodes)
        if d == 2:
            raise Unhandled("two hops from the meeting node")
        if d == 4:
            return 1 // 0
        return view.neighbours()[-1] if d else view.me


def searches(world: World, robots: tuple[int, ...], meeting: tuple[int, ...], algorithm: Any,
             scheduler: str, *, task: str = "gathering", detection: str = "local-weak",
             frames: str = "all", visibility: int | None = None, lights: str | None = None,
             colours: list[int] | None = None, reduce: bool = False,
             max_states: int = 10**9) -> tuple[world_search.WorldSearch,
                                              world_search.WorldSearch]:
    """The reference search and the bulk search of one instance, each with its own move
    sets (nothing shared but the world)."""
    t = get_task(task)
    light = parse_lights(lights)
    algo = get_algorithm(algorithm) if isinstance(algorithm, str) else algorithm
    options: dict[str, Any] = dict(
        colours=colours, visits=t.visits, anonymity=reduce,
        symmetries=world.symmetries(frames) if reduce else (), meeting=frozenset(meeting),
        limits=Limits(max_states=max_states))
    why = world_bulk.unsupported(world, len(robots), scheduler, light.colours,
                                 visits=t.visits, anonymity=reduce,
                                 symmetries=options["symmetries"], meeting=frozenset(meeting))
    assert why is None, why

    def moves() -> WorldMoves:
        return WorldMoves(world, algo, frozenset(meeting), detection, frames, visibility, light)

    ref = world_search.search(world, robots, moves().actions, scheduler, **options)
    bulk = world_bulk.search(world, robots, moves(), scheduler, **options)
    return ref, bulk


def assert_same(ref: world_search.WorldSearch, bulk: world_search.WorldSearch) -> None:
    """Every field of the two searches, and every task's findings on them."""
    assert bulk.engine == "bulk" and ref.engine == "reference"
    assert (bulk.states, bulk.transitions, bulk.stopped, bulk.reduced) == \
        (ref.states, ref.transitions, ref.stopped, ref.reduced)
    assert bulk.halt == ref.halt
    assert list(bulk.keys) == ref.keys
    assert list(bulk.parents) == ref.parents
    assert list(bulk.final) == ref.final
    assert list(bulk.stay) == ref.stay
    assert len(bulk.edges) == len(ref.edges)
    assert list(bulk.edges) == ref.edges
    assert bulk.arrays is not None
    assert bulk.arrays.nodes.tolist() == [[v for v, _, _ in k[0]] for k in ref.keys]
    if ref.keys:
        assert bulk.canonical(ref.keys[-1]) == ref.canonical(ref.keys[-1])


def assert_same_tasks(ref: world_search.WorldSearch, bulk: world_search.WorldSearch,
                      world: World, n: int, meeting: tuple[int, ...], scheduler: str) -> None:
    """Each task's findings: the Python reading of the reference search, the compiled tests
    on the bulk search's arrays, and the compiled tests on the reference's own arrays."""
    if ref.halt is not None or ref.states > TASK_STATES:
        return
    ctx = Context(n, world.size, frozenset(meeting), scheduler,
                  tuple(world.format_node(v) for v in range(world.size)))
    tasks = ["gathering", "exclusive-perpetual-exploration"]
    if meeting:
        tasks.append("gathering-on-meeting-nodes")
    if ref.keys and ref.keys[0][1]:  # the visited nodes are in the state
        tasks = ["exploration-with-stop"]
    for name in tasks:
        task = get_task(name)
        want = task.check(ref, ctx)
        assert task.check(bulk, ctx) == want, name
        assert task.check(replace(ref, arrays=world_search.arrays_of(ref)), ctx) == want, name


def configurations(world: World, sizes: tuple[int, ...]) -> list[tuple[int, ...]]:
    return [c for k in sizes for c in itertools.combinations(range(world.size), k)]


# -- SEMANTICS §9 and §10 ----------------------------------------------------------------

@pytest.mark.parametrize(("scheduler", "states", "transitions"),
                         [("fsync", 5, 4), ("ssync", 45, 264), ("async", 225, 560),
                          ("centralized", 45, 96), ("round-robin", 84, 84)])
def test_ring9_numbers_of_semantics_9(scheduler: str, states: int, transitions: int) -> None:
    report = run_world_check("ring:9", "0 3 5", "7", "go-to-target", scheduler,
                             reduction=False, engine="bulk")
    assert report["engine"] == "bulk" and report["verdict"] == "VERIFIED"
    assert (report["states"], report["transitions"]) == (states, transitions)
    w = get_world("ring:9")
    ref, bulk = searches(w, (0, 3, 5), (7,), "go-to-target", scheduler,
                         task="gathering-on-meeting-nodes")
    assert_same(ref, bulk)


@pytest.mark.parametrize(("scheduler", "states", "transitions"),
                         [("fsync", 36, 90), ("ssync", 144, 756), ("async", 576, 1440),
                          ("centralized", 144, 432)])
def test_bounce_numbers_of_semantics_10(scheduler: str, states: int, transitions: int) -> None:
    report = run_world_check("ring:6", "0 2", "", "bounce", scheduler, task="gathering",
                             lights="2", reduction=False, engine="bulk")
    assert (report["states"], report["transitions"]) == (states, transitions)
    ref, bulk = searches(get_world("ring:6"), (0, 2), (), "bounce", scheduler, lights="2")
    assert_same(ref, bulk)


# -- every scenario of scenarios/worlds --------------------------------------------------

SCENARIOS = sorted((ROOT / "scenarios" / "worlds").glob("*.scenario.json"))


@pytest.mark.parametrize("path", SCENARIOS, ids=[p.name for p in SCENARIOS])
def test_every_world_scenario_gives_the_same_report(path: Path) -> None:
    scenario = load_scenario(str(path))
    world = scenario.raw["world"]
    if world.startswith("graph:"):
        world = "graph:" + str(path.parent / world[6:])
    robots, meeting = scenario.nodes
    algorithms = {e.algorithm for e in scenario.expectations} | {scenario.algorithm}
    for algorithm, scheduler, reduction in itertools.product(sorted(algorithms), SCHEDULERS,
                                                             (True, False)):
        kw = dict(task=scenario.task, detection=scenario.multiplicity, frames=scenario.frames,
                  visibility=scenario.visibility, lights=scenario.lights,
                  colours=scenario.colours, reduction=reduction)
        ref = run_world_check(world, list(robots), list(meeting), algorithm, scheduler,
                              engine="reference", **kw)
        bulk = run_world_check(world, list(robots), list(meeting), algorithm, scheduler,
                               engine="bulk", **kw)
        assert bulk.pop("engine") == "bulk" and ref.pop("engine") == "reference"
        bulk.pop("seconds"), ref.pop("seconds"), bulk.pop("search_seconds"), ref.pop("search_seconds")
        assert json.dumps(bulk, sort_keys=True) == json.dumps(ref, sort_keys=True)
        w = get_world(world)
        for reduce in (False, True):
            a, b = searches(w, tuple(robots), tuple(meeting), algorithm, scheduler,
                            task=scenario.task or "gathering", detection=scenario.multiplicity,
                            frames=scenario.frames, visibility=scenario.visibility,
                            lights=scenario.lights, colours=scenario.colours, reduce=reduce)
            assert_same(a, b)


# -- whole sweeps of small worlds --------------------------------------------------------

SWEEP_WORLDS = ["ring:5", "ring:6", "ring:7", "grid:3x3", "torus:3x3", "house"]


def cover(worlds: list[str], slow_worlds: tuple[str, ...] = ("ring:6",)
          ) -> list[Any]:
    """Every (world, scheduler) pair of a whole-sweep comparison. The default run keeps a
    diagonal in which every world meets two schedulers or more and every scheduler meets a
    world; the other pairs, and ``slow_worlds`` (ring:6: ring:5 and ring:7 make the same
    comparison, and the even ring keeps its default halts and exploration tests), run under
    ``-m slow``."""
    fast = [w for w in worlds if w not in slow_worlds]
    per_world = max(2, -(-len(SCHEDULERS) // len(fast)))
    return [(world, scheduler)
            if world in fast and (j - per_world * fast.index(world)) % len(SCHEDULERS) < per_world
            else pytest.param(world, scheduler, marks=pytest.mark.slow)
            for world in worlds for j, scheduler in enumerate(SCHEDULERS)]


def sweep_world(name: str, tmp_path: Path) -> World:
    if name == "house":
        path = tmp_path / "house.edgelist"
        path.write_text(HOUSE, encoding="utf-8")
        return get_world(f"graph:{path}")
    return get_world(name)


@pytest.mark.parametrize(("world_name", "scheduler"), cover(SWEEP_WORLDS))
def test_sweep_go_to_target_every_configuration(world_name: str, scheduler: str,
                                                tmp_path: Path) -> None:
    """Every initial configuration of 2 and 3 robots, meeting node 0, reductions on and
    off."""
    w = sweep_world(world_name, tmp_path)
    for robots in configurations(w, (2, 3)):
        for reduce in (False, True):
            ref, bulk = searches(w, robots, (0,), "go-to-target", scheduler,
                                 task="gathering-on-meeting-nodes", reduce=reduce)
            assert_same(ref, bulk)
            assert_same_tasks(ref, bulk, w, len(robots), (0,), scheduler)


@pytest.mark.parametrize(("world_name", "scheduler"), cover(SWEEP_WORLDS))
def test_sweep_an_algorithm_that_reads_everything(world_name: str, scheduler: str,
                                                  tmp_path: Path) -> None:
    """Every initial configuration of 2 robots (and of 3 on the smaller worlds) under
    :class:`Chaotic` (deadlocks, livelocks, towers), reductions on and off, with
    multiplicity detection."""
    w = sweep_world(world_name, tmp_path)
    for robots in configurations(w, (2, 3) if w.size <= 6 else (2,)):
        for reduce in (False, True):
            ref, bulk = searches(w, robots, (), Chaotic(salt=sum(robots)), scheduler,
                                 reduce=reduce)
            assert_same(ref, bulk)
            assert_same_tasks(ref, bulk, w, len(robots), (), scheduler)


SLOW = pytest.mark.slow


@pytest.mark.parametrize(("world_name", "scheduler"),
                         cover(["ring:5", "ring:6", "grid:3x3", "house"],
                               slow_worlds=("ring:6", "grid:3x3")))
def test_sweep_with_lights(world_name: str, scheduler: str, tmp_path: Path) -> None:
    """Two luminous robots, every placement and every initial colouring: bounce and a
    luminous :class:`Chaotic` under full, external and internal lights."""
    w = sweep_world(world_name, tmp_path)
    for robots in configurations(w, (2,)):
        for colours in itertools.product(range(2), repeat=2):
            for algorithm, lights in (("bounce", "2"), (Chaotic(2), "2"),
                                      (Bounce3(), "3:internal")):
                lit = list(colours)
                ref, bulk = searches(w, robots, (), algorithm, scheduler, lights=lights,
                                     colours=lit)
                assert_same(ref, bulk)
                assert_same_tasks(ref, bulk, w, 2, (), scheduler)
            ref, bulk = searches(w, robots, (), Chaotic(2), scheduler, lights="2",
                                 colours=list(colours), reduce=True)
            assert_same(ref, bulk)


class Bounce3:
    """A luminous algorithm for internal lights: reads only its own colour."""

    name = "bounce3"

    def decide(self, view: Any) -> Any:
        c = view.light
        nbrs = view.neighbours()
        return (nbrs[0] if c == 2 else view.me, (c + 1) % 3)


@pytest.mark.parametrize("scheduler", SCHEDULERS)
@pytest.mark.parametrize("world_name", ["ring:5", "ring:6", pytest.param("ring:7", marks=SLOW),
                                        pytest.param("grid:3x3", marks=SLOW), "house"])
def test_sweep_exploration_with_the_visited_nodes(world_name: str, scheduler: str,
                                                  tmp_path: Path) -> None:
    """exploration-with-stop carries the visited nodes in the state; with the reductions
    they move with the symmetries."""
    w = sweep_world(world_name, tmp_path)
    for robots in configurations(w, (1, 2)):
        for reduce in (False, True):
            ref, bulk = searches(w, robots, (), Chaotic(salt=1), scheduler,
                                 task="exploration-with-stop", reduce=reduce)
            assert_same(ref, bulk)
            assert_same_tasks(ref, bulk, w, len(robots), (), scheduler)


class NodeWalk:
    """An algorithm that answers by its node only: it walks to its last neighbour but one hop
    from the meeting node, where it stays."""

    name = "node-walk"

    def answers_by_node(self) -> bool:
        return True

    def decide(self, view: Any) -> Any:
        d = min(view.distance(view.me, m) for m in view.meeting_nodes)
        return view.me if d == 1 else view.neighbours()[-1]


class NodeBlink:
    """An algorithm with lights that answers by its node and its own colour only: off the
    meeting node it turns its light on, then moves to its last neighbour with the light
    off."""

    name = "node-blink"

    def answers_by_node(self) -> bool:
        return True

    def decide(self, view: Any) -> Any:
        c = view.light
        if view.me in view.meeting_nodes:
            return view.me, c
        return (view.neighbours()[-1], 0) if c else (view.me, 1)


@pytest.mark.parametrize("world_name", ["ring:5", "ring:6", "house"])
def test_the_by_node_kernel_carries_visited_nodes_and_colours(world_name: str,
                                                              tmp_path: Path) -> None:
    """ASYNC's one-pass kernel for an algorithm that answers by node: with the visited
    nodes in the state (a Move adds its destination), and with lights (a Look may change
    the robot's colour)."""
    w = sweep_world(world_name, tmp_path)
    for robots in configurations(w, (1, 2)):
        for reduce in (False, True):
            ref, bulk = searches(w, robots, (0,), NodeWalk(), "async",
                                 task="exploration-with-stop", reduce=reduce)
            assert_same(ref, bulk)
            assert_same_tasks(ref, bulk, w, len(robots), (0,), "async")
        for colours in itertools.product(range(2), repeat=len(robots)):
            ref, bulk = searches(w, robots, (0,), NodeBlink(), "async", lights="2",
                                 colours=list(colours))
            assert_same(ref, bulk)
            assert_same_tasks(ref, bulk, w, len(robots), (0,), "async")


@pytest.mark.parametrize("scheduler", SCHEDULERS)
@pytest.mark.parametrize("size", [5, pytest.param(6, marks=SLOW), pytest.param(7, marks=SLOW)])
def test_sweep_ring_algorithms(size: int, scheduler: str) -> None:
    """ring-gather (global-weak), ring-explore with and without a common direction, and the
    inchworm (lights, visibility 2), every configuration of 2 and 3 robots on rings 5-7."""
    w = get_world(f"ring:{size}")
    for robots in configurations(w, (2, 3)):
        runs = [("ring-gather", dict(detection="global-weak")),
                ("broken-ring-gather", dict(detection="global-weak")),
                ("ring-explore", dict(frames="chirality")),
                ("ring-explore", dict(frames="all")),
                ("broken-ring-explore", dict(frames="chirality"))]
        if len(robots) == 2:
            runs += [("ring-inchworm", dict(lights="2", visibility=2, colours=[1, 0])),
                     ("broken-ring-inchworm", dict(lights="2", visibility=2,
                                                   colours=[0, 0]))]
        for algorithm, kw in runs:
            ref, bulk = searches(w, robots, (), algorithm, scheduler, **kw)
            assert_same(ref, bulk)
            assert_same_tasks(ref, bulk, w, len(robots), (), scheduler)


# -- halts and limits --------------------------------------------------------------------

@pytest.mark.parametrize("scheduler", SCHEDULERS)
@pytest.mark.parametrize("world_name", ["ring:6", "ring:7", "grid:3x3",
                                        pytest.param("torus:3x3", marks=SLOW)])
def test_halts_are_the_same(world_name: str, scheduler: str) -> None:
    """An algorithm with no rule here and a bug there: the search stops at the same state,
    for the same reason, with the same detail."""
    w = get_world(world_name)
    halted = 0
    for robots in configurations(w, (2, 3)):
        ref, bulk = searches(w, robots, (), Picky(), scheduler)
        assert_same(ref, bulk)
        halted += ref.halt is not None
        ref, bulk = searches(w, robots, (0,), NodePicky(), scheduler)
        assert_same(ref, bulk)
        halted += ref.halt is not None
    assert halted


@pytest.mark.parametrize("scheduler", SCHEDULERS)
def test_state_limits_stop_at_the_same_state(scheduler: str) -> None:
    w = get_world("ring:7")
    for robots in [(0, 1), (0, 2, 3), (0, 1, 4)]:
        ref, _ = searches(w, robots, (), Chaotic(), scheduler)
        for limit in sorted({1, 2, 3, 5, 8, 13, 40, ref.states - 1, ref.states} - {0}):
            a, b = searches(w, robots, (), Chaotic(), scheduler, max_states=limit)
            assert_same(a, b)


def test_state_limits_stop_at_the_same_state_by_node() -> None:
    """The same with an algorithm that answers by node (ASYNC's one-pass kernel)."""
    w = get_world("ring:9")
    ref, _ = searches(w, (0, 3, 5), (7,), "go-to-target", "async")
    for limit in (1, 2, 7, 50, ref.states - 1, ref.states):
        a, b = searches(w, (0, 3, 5), (7,), "go-to-target", "async", max_states=limit)
        assert_same(a, b)


def test_a_crash_report_and_its_trace_are_the_same() -> None:
    for engine in ("reference", "bulk"):
        report = run_world_check("ring:6", "0 2", "4", "broken-crash", "async", engine=engine)
        assert report["engine"] == engine
        assert report["verdict"] == "VIOLATED" and report["property"] == "crash"
    kw: dict[str, Any] = dict(task="gathering")
    a = run_world_check("ring:7", "0 1 3", "", "ring-gather", "async", engine="reference", **kw)
    b = run_world_check("ring:7", "0 1 3", "", "ring-gather", "async", engine="bulk", **kw)
    assert a["trace"] == b["trace"] and a["trace"] is not None


def test_auto_names_the_engine_and_why_it_fell_back() -> None:
    report = run_world_check("ring:9", "0 3 5", "7", "go-to-target", "async")
    assert report["engine"] == "bulk" and "engine_fallback" not in report  # the default
    kernels.use(False)
    try:
        report = run_world_check("ring:9", "0 3 5", "7", "go-to-target", "async",
                                 engine="auto")
        assert report["engine"] == "reference"
        assert "kernels are off" in report["engine_fallback"]
        with pytest.raises(Exception, match="bulk engine cannot run"):
            run_world_check("ring:9", "0 3 5", "7", "go-to-target", "async", engine="bulk")
    finally:
        kernels.use(None)
    report = run_world_check("ring:9", "0 3 5", "7", "go-to-target", "async",
                             engine="reference")
    assert report["engine"] == "reference" and "engine_fallback" not in report


# -- random instances --------------------------------------------------------------------

INSTANCES = dict(
    world_name=st.sampled_from(["ring:3", "ring:5", "ring:8", "grid:2x3", "grid:3x3",
                                "torus:3x4", "grid:1x4"]),
    data=st.data(), scheduler=st.sampled_from(SCHEDULERS), reduce=st.booleans(),
    luminous=st.booleans(), limit=st.sampled_from([10**9, 7, 60]),
    detection=st.sampled_from(["local-weak", "global-strong"]),
    visibility=st.sampled_from([None, 1, 2]), salt=st.integers(0, 50))


def random_instance(world_name: str, data: st.DataObject, scheduler: str, reduce: bool,
                    luminous: bool, limit: int, detection: str, visibility: int | None,
                    salt: int, lit_robots: int = 3) -> None:
    """One random instance, both engines; at most ``lit_robots`` robots when lit."""
    w = get_world(world_name)
    n = data.draw(st.integers(1, lit_robots if luminous else 3))
    robots = tuple(data.draw(st.lists(st.integers(0, w.size - 1), min_size=n, max_size=n)))
    colours = data.draw(st.lists(st.integers(0, 1), min_size=n, max_size=n)) if luminous \
        else None
    ref, bulk = searches(w, robots, (), Chaotic(2 if luminous else 1, salt), scheduler,
                         detection=detection, visibility=visibility,
                         lights="2" if luminous else None, colours=colours, reduce=reduce,
                         max_states=limit)
    assert_same(ref, bulk)
    assert_same_tasks(ref, bulk, w, n, (), scheduler)


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(**INSTANCES)
def test_random_instances(**kw: Any) -> None:
    """Random worlds, robots (towers too), colours, schedulers, detection, visibility,
    reductions and state limits (three lit robots: under ``-m slow``)."""
    random_instance(**kw, lit_robots=2)


@SLOW
@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(**INSTANCES)
def test_random_instances_many(**kw: Any) -> None:
    random_instance(**kw)


# -- go-to-target's answers by node ------------------------------------------------------

class PlainGoToTarget(get_algorithm("go-to-target").__class__):  # type: ignore[misc]
    """go-to-target asked view by view (a subclass: the answers-by-node hook is off)."""

    def decide(self, view: Any) -> Any:
        return super().decide(view)


@pytest.mark.parametrize("world_name", ["ring:7", "grid:3x4", "torus:3x3", "torus:4x4",
                                        "grid:1x5", "house"])
def test_go_to_target_answers_by_node_are_its_answers(world_name: str, tmp_path: Path) -> None:
    """The hook (a node's actions asked once, whatever the other robots) gives what asking
    every view gives, on every node, colour, visibility, frame set and detection."""
    w = sweep_world(world_name, tmp_path)
    assert get_algorithm("go-to-target").answers_by_node()
    assert not PlainGoToTarget().answers_by_node()
    frame_sets = ["all", "compass"] + ([] if world_name == "house" else ["chirality"])
    for meeting, frames, visibility, detection, lights in itertools.product(
            [(0,), (w.size - 1,), (1, w.size - 2)], frame_sets, [None, 1, 2],
            ["local-weak", "global-strong"], ["1", "2"]):
        light = parse_lights(lights)
        fast = WorldMoves(w, get_algorithm("go-to-target"), frozenset(meeting), detection,
                          frames, visibility, light)
        plain = WorldMoves(w, PlainGoToTarget(), frozenset(meeting), detection, frames,
                           visibility, light)
        assert fast._by_node is not None and plain._by_node is None
        for robots in itertools.combinations(range(w.size), 2):
            for c in range(light.colours):
                seen = tuple(sorted((v, c) for v in robots))
                assert fast.table(seen) == plain.table(seen)


def test_the_engine_asks_the_scheduler_which_robots_its_rounds_activate() -> None:
    """The bulk engine reads a scheduler's ``activations``, never its class: a scheduler of
    the user's with SSYNC's rounds under a name of its own runs on it and agrees with the
    reference field by field; one that declares no rounds is refused with the reason."""
    from schedulers.ssync import SSync

    class Mine(SSync):
        name = "mine"

    w = get_world("ring:6")
    ref, bulk = searches(w, (0, 1, 3), (), Chaotic(salt=4), Mine())  # type: ignore[arg-type]
    assert_same(ref, bulk)
    assert bulk.states > 1 and bulk.transitions > bulk.states

    class Silent:
        name = "silent"
        kinds = ("round",)

    why = world_bulk.unsupported(w, 3, Silent(), 1)  # type: ignore[arg-type]
    assert why == "the scheduler silent does not say which robots its rounds activate"
