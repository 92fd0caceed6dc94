"""The bulk explorer against the reference one (issues 8 and 13): same states, same ids,
same graph, same witnesses, under every registered scheduler; and through ``run_check``
the same verdicts, max moves and traces on every scenario under ``scenarios/``."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gather_verify.algorithms import Unhandled, get_algorithm
from gather_verify.algorithms.go_to_target import GoToTarget
from gather_verify.algorithms.moves import move_sets
from gather_verify.engine.explore import Limits, explore_reference
from gather_verify.engine.fast_explore import explore_fast, supports
from gather_verify.model.configuration import Configuration
from gather_verify.plane_check import run_check
from gather_verify.properties.base import Property
from gather_verify.properties.registry import register, unregister
from gather_verify.scenario import load_scenario
from gather_verify.sweeps.census import enumerate_configurations
from schedulers import SCHEDULERS, initial_state, plane_schedulers

YARD = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)
ROOT = Path(__file__).resolve().parent.parent / "scenarios"


def same(c, algorithm, scheduler="async", **kw):
    """Explore both ways; assert every observable is identical."""
    ref = explore_reference(c, algorithm, scheduler, **kw)
    fast = explore_fast(c, algorithm, scheduler, **kw)
    assert (fast.states, fast.transitions, fast.stopped, fast.changed_loops) == \
        (ref.states, ref.transitions, ref.stopped, ref.changed_loops)
    assert list(fast.keys) == list(ref.keys)
    assert list(fast.parents) == list(ref.parents)
    assert list(fast.offsets) == list(ref.offsets)
    assert list(fast.targets) == list(ref.targets)
    assert list(fast.weights) == list(ref.weights)
    assert fast.vacuous == ref.vacuous
    assert {k: vars(v) for k, v in fast.violations.items()} == \
        {k: vars(v) for k, v in ref.violations.items()}
    return fast


ALL = list(plane_schedulers())
YARD_STATES = {"fsync": 18, "ssync": 216, "async": 2184,  # SEMANTICS.md §4
               "centralized": 216}  # docs/worlds.md


@pytest.mark.parametrize("scheduler", ALL)
@pytest.mark.parametrize("reduction", [False, True])
def test_yardstick(reduction, scheduler):
    e = same(YARD, "go-to-target", scheduler, reduction=reduction)
    if not reduction:
        assert e.states == YARD_STATES[scheduler]
        if scheduler == "async":
            assert e.transitions == 7032


def test_yardstick_without_graph():
    e = explore_fast(YARD, "go-to-target", "async", reduction=False, graph=False)
    assert (e.states, e.transitions, e.stopped) == (2184, 7032, None)
    assert len(e.targets) == 0


@pytest.mark.parametrize("scheduler", ALL)
@pytest.mark.parametrize("reduction", [False, True])
@pytest.mark.parametrize("anonymity", [None, False])
def test_reductions_one_at_a_time(reduction, anonymity, scheduler):
    c = Configuration([(0, 1), (3, 3), (2, 0)], [(1, 1), (3, 1)], initial=True)
    same(c, "go-to-target", scheduler, reduction=reduction, anonymity=anonymity)


@pytest.mark.parametrize("scheduler", ALL)
@pytest.mark.parametrize("fraction", [0, 0.001, 0.02, 0.15, 0.999, 1])
def test_states_limit(fraction, scheduler):
    total = YARD_STATES[scheduler]
    max_states = max(1, min(total, round(fraction * total)))
    same(YARD, "go-to-target", scheduler, reduction=False, limits=Limits(max_states=max_states))


@pytest.mark.parametrize("scheduler", ALL)
@pytest.mark.parametrize("margin", [0, 1])
def test_region_limit(margin, scheduler):
    # nearest-centre and the paper walk outside the MER; a small margin cuts them
    c = Configuration([(0, 0), (0, 1), (3, 3)], [(1, 2), (2, 1)], initial=True)
    for algorithm in ("nearest-centre", "paper", "broken-wander"):
        same(c, algorithm, scheduler, reduction=False, limits=Limits(margin=margin))


@pytest.mark.parametrize("scheduler", ALL)
def test_target_change_witness(scheduler):
    """A target-invariance witness: the event comes from the scheduler (a round of several
    robots under FSYNC/SSYNC, a Look or a Move under ASYNC), the same in both engines."""
    c = Configuration([(0, 0), (0, 1), (1, 0)], [(0, 2), (2, 1)], initial=True)
    for reduction in (False, True):
        e = same(c, "broken-drift", scheduler, reduction=reduction)
        v = e.violations["target-invariance"]
        assert v.event.kind in SCHEDULERS[scheduler].kinds
        if scheduler == "fsync" and not reduction:
            assert len(v.event.moves) == 3  # one event, three robots moved


@pytest.mark.parametrize("scheduler", ALL)
def test_small_budget_same_result(scheduler, monkeypatch):
    """The scheduler may take fewer states than offered (its event budget): the engine
    expands the rest in later steps, with the same result."""
    from gather_verify.engine import fast_explore

    want = explore_fast(YARD, "go-to-target", scheduler, reduction=False)
    monkeypatch.setattr(fast_explore, "EVENTS", 7)
    got = same(YARD, "go-to-target", scheduler, reduction=False)
    assert list(got.keys) == list(want.keys)


def test_every_scheduler_runs_on_the_bulk_engine():
    for name in plane_schedulers():
        assert supports(YARD, name)
    # beyond 64-bit keys the reference path runs instead
    wide = Configuration([(0, 0), (40, 0), (0, 40), (40, 40), (20, 20), (20, 0)], [(20, 10)],
                         initial=True)
    assert not supports(wide, "ssync")


def _bulk_order(scheduler, c):
    """Events of the bulk interface, as (source, successor) codes, for one state."""
    import numpy as np

    from gather_verify.engine.encoding import Encoding
    from gather_verify.engine.facts_table import BIT

    enc = Encoding((-1, -1, 5, 5))
    algo = get_algorithm("go-to-target")
    ms = move_sets(algo, c)
    masks = np.array([[sum(BIT[x - v[0], y - v[1]] for x, y in ms[v]) for v in c.robots]],
                     dtype=np.uint8)
    codes = np.array([[enc.code(v, None) for v in c.robots]], dtype=np.int64)
    bulk = SCHEDULERS[scheduler]().bulk_successors(enc.frontier(codes, masks), 1 << 20)
    out = [list(codes[0]) for _ in bulk.source]
    for k, (r, code) in enumerate(zip(bulk.robot, bulk.code, strict=True)):
        out[k if bulk.event is None else bulk.event[k]][r] = int(code)
    return enc, out, bulk.weight.tolist()


@pytest.mark.parametrize("scheduler", ALL)
def test_bulk_interface_matches_successors(scheduler):
    """The two faces of a scheduler agree event by event, in order, on one state."""
    c = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)
    enc, bulk, weights = _bulk_order(scheduler, c)
    algo = get_algorithm("go-to-target")
    ms = lambda robots: move_sets(algo, Configuration.trusted(robots, c.meeting_nodes))  # noqa: E731
    one = list(SCHEDULERS[scheduler]().successors(initial_state(c.robots), ms))
    assert bulk == [[enc.code(v, p) for v, p in succ] for _, succ in one]
    assert weights == [event.distance for event, _ in one]


def _scenario_cases():
    cases = []
    for path in sorted(ROOT.rglob("*.json")):
        s = load_scenario(path)
        if s.world != "grid":  # a finite world's scenario: tests/test_worlds.py
            continue
        slow = {(e.algorithm, e.scheduler) for e in s.expectations if e.options.get("slow")}
        algorithms = {e.algorithm for e in s.expectations} | {s.algorithm or "paper"}
        for algorithm in sorted(algorithms):
            # the paper's schedulers on every scenario, not only those recorded (centralized:
            # test_yardstick and the whole-box sweeps)
            for scheduler in ("fsync", "ssync", "async"):
                marks = [pytest.mark.slow] if (algorithm, scheduler) in slow else []
                cases.append(pytest.param(path, algorithm, scheduler, marks=marks,
                                          id=f"{path.relative_to(ROOT)}[{algorithm}/{scheduler}]"))
    return cases


@pytest.mark.parametrize("path,algorithm,scheduler", _scenario_cases())
def test_scenarios_same_report(path, algorithm, scheduler):
    s = load_scenario(path)
    c = s.configuration
    for reduction in (True, False):
        kw = dict(algorithm=algorithm, scheduler=scheduler, reduction=reduction,
                  max_states=200_000, max_seconds=120, force=True)
        ref = run_check(c, engine="reference", **kw)
        fast = run_check(c, engine="fast", **kw)
        for r in (ref, fast):
            r.pop("seconds"), r.pop("peak_rss_mb", None)
        if ref["verdict"] == "INCOMPLETE":  # a limit: where it stops may differ (time)
            assert fast["verdict"] == "INCOMPLETE"
            continue
        assert fast == ref


ALGORITHMS = ["go-to-target", "paper", "broken-away", "broken-stay", "broken-drift",
              "broken-wander", "broken-undefined", "broken-crash", "broken-answer",
              "broken-crash-target"]


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    robots=st.lists(st.tuples(st.integers(0, 3), st.integers(0, 3)), min_size=1, max_size=3,
                    unique=True),
    meeting=st.lists(st.tuples(st.integers(0, 3), st.integers(0, 3)), min_size=1, max_size=2,
                     unique=True),
    algorithm=st.sampled_from(ALGORITHMS),
    scheduler=st.sampled_from(ALL),
    reduction=st.booleans(),
)
def test_random_configurations(robots, meeting, algorithm, scheduler, reduction):
    from gather_verify import properties as props

    c = Configuration(robots, meeting, initial=True)
    limits = Limits(max_states=20_000, margin=1)
    fast = same(c, algorithm, scheduler, reduction=reduction, limits=limits)
    if fast.stopped is None:
        plain = explore_reference(c, algorithm, scheduler, reduction=reduction, limits=limits)
        assert props.longest_path(fast) == props.longest_path(plain)


CENSUS = [(n, m) for n in (1, 2, 3) for m in (1, 2, 3)]


@pytest.mark.parametrize("scheduler", ["fsync", "ssync"])
@pytest.mark.parametrize("n,m", [pytest.param(n, m, marks=[pytest.mark.slow] if n * m > 2 else [])
                                 for n, m in CENSUS])
def test_census_box(n, m, scheduler):
    """Every configuration of a 3x3 box (once per symmetry class), the paper's algorithm,
    reductions on and off: the bulk engine equals the reference field by field."""
    for c in enumerate_configurations(n, m, 3, 3):
        for reduction in (False, True):
            same(c, "paper", scheduler, reduction=reduction,
                 limits=Limits(max_states=20_000, margin=1))


@pytest.mark.parametrize("scheduler", ALL)
@pytest.mark.parametrize("reduction", [False, True])
@pytest.mark.parametrize("case", [
    (YARD, "go-to-target"),
    (Configuration([(0, 0), (4, 0), (2, 3)], [(2, 1)], initial=True), "go-to-target"),
    (Configuration([(0, 0), (0, 1), (3, 3)], [(1, 2), (2, 1)], initial=True), "paper"),
])
def test_longest_path_bulk(case, reduction, scheduler):
    from gather_verify import properties as props

    c, algorithm = case
    e = explore_fast(c, algorithm, scheduler, reduction=reduction)
    bulk = props.longest_path(e)
    if e.changed_loops:
        return
    e.targets = list(e.targets)  # plain columns: the per-state reference code
    assert props.longest_path(e) == bulk


@pytest.mark.slow
def test_grid_instance_counts():
    """The SPIN yardstick: 4,939,200 states and 27,377,280 transitions (closed form in
    bench/spin/make_model.py), without edges kept."""
    c = Configuration([(0, 0), (5, 1), (1, 5), (6, 6), (3, 0)], [(3, 3)], initial=True)
    e = explore_fast(c, "go-to-target", "async", reduction=False, properties=[], graph=False)
    assert (e.states, e.transitions, e.stopped) == (4_939_200, 27_377_280, None)


class NodeRules(GoToTarget):
    """go-to-target that answers by its node (the ``answers_by_node`` hook on) and has no rule
    where its meeting node lies ``unhandled_at`` steps away (L1: the same in every frame) and
    crashes where it lies ``crash_at`` steps away; with ``target_crash`` its target crashes
    once a robot is on the meeting node. The bulk engine asks each node once; the reference
    asks every configuration."""

    name = "node-rules"

    def __init__(self, unhandled_at: int = -1, crash_at: int = -1, target_crash: bool = False):
        self.unhandled_at, self.crash_at, self.target_crash = unhandled_at, crash_at, target_crash

    def answers_by_node(self) -> bool:
        return True

    def decide(self, view):
        ((x, y),) = view.meeting_nodes
        if abs(x) + abs(y) == self.crash_at:
            raise ZeroDivisionError("a bug at this distance")
        if abs(x) + abs(y) == self.unhandled_at:
            raise Unhandled("no rule at this distance")
        return super().decide(view)

    def target(self, configuration):
        if self.target_crash and configuration.meeting_nodes & set(configuration.robots):
            raise KeyError("a bug in target")
        return super().target(configuration)


@pytest.mark.parametrize("scheduler", ALL)
@pytest.mark.parametrize("frames", ["all", "chirality"])
@pytest.mark.parametrize("rules, fails", [
    (dict(unhandled_at=1), "defined"), (dict(crash_at=2), "crash"), ({}, None),
    (dict(target_crash=True), "crash"),
    # the initial configuration's first robot (0, 0) has no rule, (1, 4) would crash: as
    # move_sets asks the nodes in order, no rule
    (dict(unhandled_at=4, crash_at=3), "defined")])
def test_answers_by_node_are_the_per_configuration_answers(rules, fails, frames, scheduler):
    """The facts table of an algorithm that answers by node (masks from each node's move set,
    flags in bulk, the target per configuration) gives the reference engine's exploration,
    witnesses included: no rule, a crash in decide, a crash in target, none, and a node
    without a rule before a node that crashes."""
    algorithm = NodeRules(**rules)
    assert algorithm.answers_by_node() and get_algorithm("go-to-target").answers_by_node()
    for reduction in (False, True):
        e = same(YARD, algorithm, scheduler, reduction=reduction, frames=frames)
        assert set(e.violations) == ({fails} if fails else set())


def test_answers_by_node_asks_each_node_once(monkeypatch):
    """go-to-target's move sets come from one ``decide`` per node and frame, not per
    configuration (the per-configuration path asks ``move_sets`` per orbit)."""
    from gather_verify.engine import facts_table

    asked: list[tuple[int, int]] = []
    real = facts_table.move_set
    monkeypatch.setattr(facts_table, "move_set",
                        lambda algorithm, c, v, *rest: asked.append(v) or real(algorithm, c, v, *rest))
    monkeypatch.setattr(facts_table, "move_sets", None)  # the per-configuration path is not taken
    e = explore_fast(YARD, "go-to-target", "ssync", reduction=False)
    assert e.states == YARD_STATES["ssync"]
    assert len(asked) == len(set(asked)) > 0


FLAGS_ONLY = Property("test-never-gathered", "state", holds=lambda s: not s.gathered,
                      message="gathered", symmetric=True)
"""A state property that reads a flag of the facts table's rows only (shared per flags)."""
ROW_READER = Property("test-off-the-meeting-node", "state",
                      holds=lambda s: not (s.configuration.meeting_nodes
                                           & set(s.configuration.robots)) or s.stuck,
                      message="a robot on the meeting node", symmetric=True)
"""A state property that reads the configuration (evaluated per row)."""


@pytest.mark.parametrize("scheduler", ALL)
def test_state_properties_shared_per_flags_only_when_they_read_no_row(scheduler, monkeypatch):
    """A state property that reads only the rows' flags is evaluated once per (flags, idle)
    in the bulk engine; one that reads a row's configuration, per row: both give the
    reference engine's witnesses (a robot first on the meeting node, then gathered)."""
    calls = []
    counted = Property("test-never-gathered", "state",
                       holds=lambda s: calls.append(1) or FLAGS_ONLY.holds(s),
                       message="gathered", symmetric=True)
    for p in (counted, ROW_READER):
        register(p)
    try:
        names = [counted.name, ROW_READER.name]
        c = Configuration([(0, 0), (3, 1), (1, 3)], [(2, 2)], initial=True)
        for reduction in (False, True):
            e = same(c, "go-to-target", scheduler, reduction=reduction, properties=names)
            assert set(e.violations) == set(names)
        calls.clear()
        explore_fast(c, "go-to-target", scheduler, reduction=False, properties=names)
        assert 0 < len(calls) <= 2 * 12  # per (flags, idle): at most 12 flag values
    finally:
        for p in (counted, ROW_READER):
            unregister(p.name)


@pytest.mark.parametrize("scheduler", ["ssync", "fsync"])
@pytest.mark.parametrize("frames", ["all", "chirality"])
def test_rounds_of_many_robots(scheduler, frames):
    """Six robots: 63 activated subsets a state under SSYNC; the states limit stops both
    engines at the same state, with the reductions on and off."""
    c = Configuration([(0, 0), (2, 0), (4, 1), (0, 3), (3, 4), (1, 4)], [(2, 2)], initial=True)
    assert supports(c, scheduler, reduction=False)
    for reduction in (False, True):
        e = same(c, "go-to-target", scheduler, reduction=reduction, frames=frames,
                 limits=Limits(max_states=1500))
        assert e.stopped is not None or scheduler == "fsync"


ROUNDS = [name for name in ALL if getattr(SCHEDULERS[name], "rounds", False)]


@pytest.mark.parametrize("scheduler", ROUNDS)
@pytest.mark.parametrize("properties", [[], ["crash", "final"], ["target-invariance", "final"]])
def test_rounds_keyed_without_transition_properties(scheduler, properties, monkeypatch):
    """With no transition property to feed, a round scheduler's events come with their keys
    from one compiled pass (``bulk_round_keys``, no changes listed): the same search as the
    reference's, through a region limit, a states limit and a small event budget (with
    ``target-invariance``: once its counterexample is found, under ``broken-wander``)."""
    from gather_verify.engine import fast_explore

    c = Configuration([(0, 0), (0, 1), (3, 3)], [(1, 2), (2, 1)], initial=True)
    for algorithm in ("nearest-centre", "paper", "broken-wander"):
        for margin in (0, 1):
            same(c, algorithm, scheduler, reduction=False, properties=properties,
                 limits=Limits(margin=margin))
    for max_states in (1, 40, 150):
        same(YARD, "go-to-target", scheduler, reduction=False, properties=properties,
             limits=Limits(max_states=max_states))
    monkeypatch.setattr(fast_explore, "EVENTS", 7)
    same(YARD, "go-to-target", scheduler, reduction=False, properties=properties)
    for graph in (False, True):
        e = explore_fast(YARD, "go-to-target", scheduler, reduction=False,
                         properties=properties, graph=graph)
        assert e.states == YARD_STATES[scheduler]
