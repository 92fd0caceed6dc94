"""Every property fails on a deliberately broken algorithm, with a trace replay confirms;
properties written outside the package (registered, or loaded with ``--property
FILE.py:NAME``) are checked by both engines and confirmed by replay; the graph analyses
give the same answers through networkx and through the hand-written code."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from gather_verify.engine.explore import Limits
from gather_verify.engine.search import explore
from gather_verify.model.configuration import Configuration as C
from gather_verify.model.geometry import manhattan
from gather_verify.plane_check import run_check
from gather_verify.properties import (
    ORDER,
    Property,
    check_property_names,
    get_property,
    names,
    register,
    registered,
    unregister,
)
from gather_verify.properties import graph as graph_module
from gather_verify.properties.registry import load_property
from gather_verify.replay import replay

TWO = C([(0, 0), (3, 1)], [(2, 2)], initial=True)
CASES = [
    ("broken-away", TWO, "termination"),
    ("broken-away", TWO, "move-bound"),
    ("broken-stay", TWO, "final"),
    ("broken-drift", C([(1, 2), (3, 2)], [(0, 0), (4, 0), (0, 3)], initial=True),
     "target-invariance"),
    ("broken-wander", C([(0, 2), (2, 2)], [(0, 0), (3, 0), (1, 1), (2, 1)], initial=True),
     "no-ungatherable"),
    ("broken-undefined", TWO, "defined"),
    ("broken-crash", TWO, "crash"),
    ("broken-answer", TWO, "crash"),
    ("broken-crash-target", TWO, "crash"),
]


@pytest.mark.parametrize("reduction", [True, False])
@pytest.mark.parametrize("scheduler", ["fsync", "ssync", "async"])
@pytest.mark.parametrize("case", range(len(CASES)))
def test_property_fails_with_confirmed_trace(case, scheduler, reduction):
    algo, c, prop = CASES[case]
    r = run_check(c, algorithm=algo, scheduler=scheduler, max_states=10**5, max_seconds=60,
                  properties=None if prop in ("defined", "crash") else [prop],
                  reduction=reduction, margin=4)
    assert r["verdict"] == "VIOLATED" and r["property"] == prop
    assert replay(r["trace"]).confirmed


def test_go_to_target_holds_everything():
    r = run_check(TWO, algorithm="go-to-target", scheduler="async", max_states=10**5,
                  max_seconds=60)
    assert r["verdict"] == "VERIFIED"
    assert all(p["holds"] for p in r["properties"].values())


def test_move_bound_tight_c_fails_with_worst_case_trace():
    r = run_check(TWO, algorithm="go-to-target", scheduler="ssync", max_states=10**5,
                  max_seconds=60, move_bound_c=0.5)
    assert r["property"] == "move-bound" and r["max_moves"] == 6
    assert sum(1 for s in r["trace"]["steps"] for m in s["event"]["moves"]) == 6
    assert replay(r["trace"]).confirmed


def test_unknown_property_name():
    with pytest.raises(ValueError, match="unknown property 'x'"):
        check_property_names(["x"])


def test_not_applicable_in_U():
    r = run_check(C([(0, 2), (3, 2)], [(0, 0), (3, 0), (1, 1), (2, 1)], initial=True), algorithm="go-to-target",
                  scheduler="async", max_states=100, max_seconds=10)
    assert r["verdict"] == "NOT-APPLICABLE" and r["class"] == "I41"


# -- properties written outside the package ------------------------------------------------

ROOT = Path(__file__).resolve().parent.parent


def _outside(s):
    x0, y0, x1, y1 = s.initial.mer()
    return [v for v in s.configuration.robots
            if not (x0 - 1 <= v[0] <= x1 + 1 and y0 - 1 <= v[1] <= y1 + 1)]


STAYS_NEAR = Property(
    "test-stays-near", "state", holds=lambda s: not _outside(s),
    message=lambda s: f"robots {[list(v) for v in _outside(s)]} left the initial MER grown by 1")
"""A state property: no robot ever leaves the initial MER grown by 1 (not symmetric)."""


def _distance(f):
    return sum(min(manhattan(v, m) for m in f.configuration.meeting_nodes)
               for v in f.configuration.robots)


CLOSER = Property(
    "test-closer", "transition", value=_distance, holds=lambda before, after: after <= before,
    message=lambda before, after: f"the robots' distance to M grows from {before} to {after}",
    detail=lambda before, after: {"before": before, "after": after}, symmetric=True)
"""A transition property: the total distance of the robots to M never grows (symmetric)."""


@pytest.fixture
def user_properties():
    for p in (STAYS_NEAR, CLOSER):
        register(p)
    yield
    for p in (STAYS_NEAR, CLOSER):
        unregister(p.name)


def _check(algorithm, prop, scheduler="async", engine="auto", reduction=True, c=TWO):
    return run_check(c, algorithm=algorithm, scheduler=scheduler, max_states=10**5,
                     max_seconds=60, properties=[prop], reduction=reduction, engine=engine,
                     margin=4)


@pytest.mark.parametrize("reduction", [True, False])
@pytest.mark.parametrize("prop", ["test-stays-near", "test-closer"])
def test_new_property_violated_on_both_engines(user_properties, prop, reduction):
    """broken-away walks away from the meeting node: both engines report the new property
    VIOLATED, with the same report, and replay confirms the trace through the property."""
    reports = [_check("broken-away", prop, engine=engine, reduction=reduction)
               for engine in ("reference", "fast")]
    for r in reports:
        r.pop("seconds"), r.pop("peak_rss_mb", None)
        assert r["verdict"] == "VIOLATED" and r["property"] == prop
        assert r["properties"][prop]["holds"] is False
        done = replay(r["trace"])
        assert done.confirmed, done.message
        assert done.message == r["reason"]
    assert reports[0] == reports[1]


@pytest.mark.parametrize("scheduler", ["fsync", "ssync"])
@pytest.mark.parametrize("prop", ["test-stays-near", "test-closer"])
def test_new_property_violated_under_every_scheduler(user_properties, prop, scheduler):
    r = _check("broken-away", prop, scheduler=scheduler)
    assert r["verdict"] == "VIOLATED" and r["property"] == prop
    assert replay(r["trace"]).confirmed


@pytest.mark.parametrize("engine", ["reference", "fast"])
@pytest.mark.parametrize("prop", ["test-stays-near", "test-closer"])
def test_new_property_verified_where_it_holds(user_properties, prop, engine):
    r = _check("go-to-target", prop, engine=engine)
    assert r["verdict"] == "VERIFIED" and r["properties"] == {prop: {"holds": True}}


def test_new_property_is_checked_by_default_once_registered(user_properties):
    r = run_check(TWO, algorithm="broken-away", scheduler="async", max_states=10**5,
                  max_seconds=60, margin=4)
    assert list(r["properties"])[-2:] == ["test-stays-near", "test-closer"]
    assert r["properties"]["test-stays-near"]["holds"] is False
    # the built-ins come first in verdict order; this livelock is named termination
    assert r["property"] == "termination"
    assert r["properties"]["move-bound"]["holds"] is False


def test_a_livelock_is_named_termination_and_a_walk_away_move_bound():
    """Termination is what a livelock breaks: with a fair cycle found, the check is named
    by it (move-bound fails with it: a cycle with moves has no bound). A run over the bound
    whose search stopped before termination was decided stays move-bound, and the
    undecided termination says why."""
    live = run_check(C([(0, 0), (0, 1), (0, 2), (2, 0)], [(1, 1), (2, 2)],
                       initial=True), algorithm="paper", scheduler="fsync",
                     max_seconds=60)
    assert live["property"] == "termination" and live["trace"]["property"] == "termination"
    assert live["properties"]["move-bound"]["holds"] is False
    assert replay(live["trace"]).confirmed
    away = run_check(TWO, algorithm="broken-away", scheduler="fsync", max_seconds=60)
    assert away["property"] == "move-bound" and away["trace"]["cycle_start"] is None
    assert away["properties"]["termination"] == {
        "holds": None, "reason": "search stopped while lifting the reduced graph to check "
                                 "cycles (region)"}


def test_a_property_that_is_not_symmetric_switches_the_symmetry_reduction_off(user_properties):
    on = explore(TWO, "broken-away", "async", properties=["test-closer"])
    off = explore(TWO, "broken-away", "async", properties=["test-stays-near"])
    assert on.symmetry and on.anonymity
    assert not off.symmetry and off.anonymity


def test_a_trace_of_an_unregistered_property_does_not_replay(user_properties):
    trace = _check("broken-away", "test-stays-near")["trace"]
    unregister("test-stays-near")
    with pytest.raises(ValueError, match="bad trace: unknown property 'test-stays-near'"):
        replay(trace)


def test_a_violation_replay_does_not_confirm_is_refused(user_properties):
    """The confirmation re-evaluates the predicate: a trace cut before the violation is not
    confirmed."""
    trace = _check("broken-away", "test-stays-near")["trace"]
    trace["steps"] = trace["steps"][:-1]
    done = replay(trace)
    assert not done.confirmed and done.message == "test-stays-near holds on the last state"


def test_registry_order_and_names(user_properties):
    assert [p.name for p in registered()][:len(ORDER)] == list(ORDER)
    assert ORDER[:2] == ("crash", "defined")  # the pseudo-properties first, as main's verdict order
    assert names()[-2:] == ("test-stays-near", "test-closer")
    assert check_property_names(None)[-2:] == ["test-stays-near", "test-closer"]
    assert get_property("final").kind == "state"


@pytest.mark.parametrize("bad,match", [
    (lambda: register(Property("final", "state", holds=bool)), "another property has that name"),
    (lambda: register(Property("time", "state", holds=bool)), "the name of a search limit"),
    (lambda: register("final"), "not a gather_verify Property"),
    (lambda: unregister("final"), "built-in"),
    (lambda: Property("a b", "state", holds=bool), "bad property name"),
    (lambda: Property("x", "state"), "needs a holds predicate"),
    (lambda: Property("x", "transition", holds=bool), "needs a value function"),
    (lambda: Property("x", "graph"), "needs decide and confirm"),
    (lambda: Property("x", "transition", holds=bool, value=id, halts=True), "stop the search"),
    (lambda: Property("x", "state", holds=bool, when="later"), "when must be"),
    (lambda: check_property_names(["defined"]), "unknown property 'defined'"),
])
def test_registry_refuses_bad_properties(bad, match):
    with pytest.raises(ValueError, match=match):
        bad()


# -- --property FILE.py:NAME ---------------------------------------------------------------

EXAMPLE = "docs/examples/stays_near.py:STAYS_NEAR"


@pytest.fixture
def example(monkeypatch):
    monkeypatch.chdir(ROOT)  # the path is relative to the working directory
    yield
    unregister("stays-near")


def test_property_file_on_the_command_line(example, tmp_path, capsys):
    from gather_verify.cli import main

    trace = tmp_path / "t.json"
    argv = ["check", "--robots", "0,0 3,1", "--meeting", "2,2", "--property", EXAMPLE]
    assert main([*argv, "--algorithm", "broken-away", "--trace-out", str(trace)]) == 1
    assert "property stays-near: robots [[-2, 2]] left" in capsys.readouterr().out
    assert main(["replay", str(trace), "--quiet", "--property", EXAMPLE]) == 1
    assert "CONFIRMED: stays-near" in capsys.readouterr().out
    assert main([*argv, "--algorithm", "go-to-target", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["properties"] == {"stays-near": {"holds": True}}


def test_replay_needs_the_property_file(example, tmp_path, capsys):
    from gather_verify.cli import main

    trace = tmp_path / "t.json"
    main(["check", "--robots", "0,0 3,1", "--meeting", "2,2", "--property", EXAMPLE,
          "--algorithm", "broken-away", "--trace-out", str(trace)])
    unregister("stays-near")
    capsys.readouterr()
    assert main(["replay", str(trace), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "load one with --property FILE.py:NAME" in err


def test_property_file_on_a_sweep(example, tmp_path, capsys):
    from gather_verify.cli import main

    db = tmp_path / "s.sqlite"
    code = main(["sweep", "--robots", "2", "--meeting", "1", "--box", "3x3", "--algorithm",
                 "broken-away", "--property", EXAMPLE, "--db", str(db), "--workers", "1",
                 "--limit", "4", "--json"])
    summary = json.loads(capsys.readouterr().out)
    assert code == 1 and "stays-near" in json.dumps(summary["failing_properties"])


BAD_FILES = {
    "missing.py:P": (None, "no file missing.py"),
    "syntax.py:P": ("def (:\n", "raised SyntaxError"),
    "raises.py:P": ("raise RuntimeError('no\\nway')\n", "raised RuntimeError: no way"),
    "noname.py:P": ("Q = 1\n", "defines no 'P'"),
    "wrong.py:P": ("P = 'final'\n", "P is a str, not a gather_verify.properties.Property"),
}


@pytest.mark.parametrize("spec", sorted(BAD_FILES))
def test_bad_property_file_is_one_line_exit_2(spec, tmp_path, monkeypatch, capsys):
    from gather_verify.cli import main

    text, match = BAD_FILES[spec]
    monkeypatch.chdir(tmp_path)
    if text is not None:
        (tmp_path / spec.split(":")[0]).write_text(text)
    with pytest.raises(ValueError, match=match):
        load_property(spec)
    assert main(["check", "--robots", "0,0 3,1", "--meeting", "2,2", "--property", spec]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and match in err


# -- the graph analyses: networkx on small graphs, the hand-written code on large ones ---


@pytest.mark.parametrize("algo,c", [(a, c) for a, c, p in CASES[:4]] + [
    ("paper", C([(0, 0), (0, 1), (3, 3)], [(1, 2), (2, 1)], initial=True)),
    ("go-to-target", C([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True))])
@pytest.mark.parametrize("scheduler", ["ssync", "async"])
def test_networkx_and_hand_written_analyses_agree(algo, c, scheduler, monkeypatch):
    e = explore(c, algo, scheduler, reduction=False, limits=Limits(max_states=20_000, margin=4))
    assert e.stopped is None
    e.targets = list(e.targets)  # the per-state code (not the bulk columns)
    small = (graph_module.strongly_connected(e), graph_module.longest_path(e),
             graph_module.livelock(e), graph_module.any_cycle(e))
    monkeypatch.setattr(graph_module, "NX_MAX_STATES", 0)
    large = (graph_module.strongly_connected(e), graph_module.longest_path(e),
             graph_module.livelock(e), graph_module.any_cycle(e))
    assert small == large


def test_docs_examples_run(monkeypatch):
    """The Python blocks of docs/properties.md run as written."""
    import re

    text = (ROOT / "docs" / "properties.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert len(blocks) == 3
    monkeypatch.chdir(ROOT)
    try:
        exec(compile("\n".join(blocks), "docs/properties.md", "exec"), {})
    finally:
        unregister("stays-near")


def test_a_halting_pseudo_property_stops_both_engines_at_the_same_state():
    """The shape of ``defined`` and ``crash``: always checked, and the search
    stops at its first failing state, on both engines alike."""
    from gather_verify.engine.explore import explore_reference
    from gather_verify.engine.fast_explore import explore_fast

    arrived = Property("test-arrived", "state", pseudo=True, halts=True, symmetric=True,
                       holds=lambda s: not set(s.configuration.robots) & s.initial.meeting_nodes,
                       message="a robot reached a meeting node")
    register(arrived)
    try:
        c = C([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)
        ref = explore_reference(c, "go-to-target", "async", properties=[])
        fast = explore_fast(c, "go-to-target", "async", properties=[])
        assert ref.stopped == fast.stopped == "test-arrived"
        assert (ref.states, ref.transitions, list(ref.keys)) == \
            (fast.states, fast.transitions, list(fast.keys))
        assert ref.violations == fast.violations and list(ref.violations) == ["test-arrived"]
        r = run_check(c, algorithm="go-to-target", scheduler="async", properties=["final"],
                      max_states=10**5, max_seconds=60)
        assert r["verdict"] == "VIOLATED" and r["property"] == "test-arrived"
        assert r["properties"] == {"final": {"holds": None,
                                             "reason": "search stopped (test-arrived)"},
                                   "test-arrived": {"holds": False,
                                                    "reason": "a robot reached a meeting node",
                                                    "cause": "test-arrived"}}
        assert replay(r["trace"]).confirmed
        with pytest.raises(ValueError, match="unknown property 'test-arrived'"):
            check_property_names(["test-arrived"])  # always on, never requested
    finally:
        unregister("test-arrived")


@pytest.mark.parametrize("scheduler", ["fsync", "async"])
def test_crash_wins_over_defined_on_both_engines(scheduler):
    """``crash`` and ``defined`` fail in the same configuration (decide has no rule, target
    raises): both engines and the report name ``crash``, the first in verdict order, with
    the crash's detail; the fast engine's flags mark the crash as the reference's facts do."""
    from gather_verify.algorithms.broken import Undefined
    from gather_verify.engine.explore import explore_reference
    from gather_verify.engine.fast_explore import explore_fast

    class UndefinedAndCrash(Undefined):
        name = "test-undefined-and-crash"

        def target(self, configuration):
            if any(manhattan(v, m) == 1 for v in configuration.robots
                   for m in configuration.meeting_nodes):
                raise KeyError("no plan")
            return super().target(configuration)

    algo = UndefinedAndCrash()
    ref = explore_reference(TWO, algo, scheduler)
    fast = explore_fast(TWO, algo, scheduler)
    assert ref.stopped == fast.stopped == "crash"
    assert {k: vars(v) for k, v in ref.violations.items()} == \
        {k: vars(v) for k, v in fast.violations.items()}
    assert ref.violations["crash"].detail["call"] == "target"
    r = run_check(TWO, algorithm=algo, scheduler=scheduler, engine="fast")
    assert (r["verdict"], r["property"]) == ("VIOLATED", "crash")
    assert r["trace"]["detail"]["exception"] == "KeyError: 'no plan'"
    assert "defined" not in r["properties"]


def test_the_engines_name_no_property():
    """The engines and the checker loop take every property from the registry."""
    root = Path(__file__).resolve().parent.parent / "gather_verify" / "engine"
    for path in ("explore.py", "fast_explore.py", "bulk_step.py", "facts_table.py",
                 "canonical_keys.py", "key_index.py", "columns.py", "checks.py", "search.py"):
        text = (root / path).read_text(encoding="utf-8")
        for name in ORDER:
            assert f'"{name}"' not in text and f"'{name}'" not in text, (path, name)


def test_the_unbounded_cycle_is_one_that_moves() -> None:
    """A component whose first cycle changes only colours (0 -> 1 -> 0, no move) and whose
    other cycle moves (1 -> 2 -> 1): the witness of unbounded moves goes through the move;
    a component without a moving edge has none."""
    from types import SimpleNamespace

    def graph(edges: list[list[tuple[int, int]]]) -> SimpleNamespace:
        off = [0]
        for out in edges:
            off.append(off[-1] + len(out))
        return SimpleNamespace(states=len(edges), changed_loops=0,
                               targets=[t for out in edges for t, _ in out],
                               weights=[w for out in edges for _, w in out],
                               successors=lambda s: range(off[s], off[s + 1]))

    e = graph([[(1, 0)], [(0, 0), (2, 1)], [(1, 0)]])
    assert graph_module.any_cycle(e) == [0, 1, 0]  # type: ignore[arg-type]
    assert graph_module.moving_cycle(e) == [0, 1, 2, 1, 0]  # type: ignore[arg-type]
    assert graph_module.moving_cycle(graph([[(1, 0)], [(0, 0)]])) is None  # type: ignore[arg-type]
