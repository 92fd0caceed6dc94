"""Runs that walk away: the move bound decided on an unfinished search (the fewest-events
execution over c * D * n, confirmed by replay), and the drift pattern of a run that leaves
every region (evidence, never a proof)."""

from __future__ import annotations

import json
from collections import deque
from pathlib import Path

import pytest

from gather_verify.cli import main
from gather_verify.engine.explore import Limits
from gather_verify.engine.search import explore
from gather_verify.errors import InvalidInput
from gather_verify.model.configuration import Configuration
from gather_verify.plane_check import run_check
from gather_verify.properties.drift import find_drift
from gather_verify.properties.graph import most_moves, real_edges
from gather_verify.replay import replay

EAST = '''\
class WalkEast:
    """Every robot steps +x forever (with a common compass: one move)."""

    name = "walk-east"

    def decide(self, view):
        return (1, 0)
'''
TWO = Configuration([(0, 0), (0, 1)], [(2, 2)], initial=True)
I22 = Configuration([(0, 0), (0, 1), (1, 2), (3, 0)], [(0, 1), (3, 0)], initial=True)


@pytest.fixture
def east(tmp_path: Path) -> str:
    path = tmp_path / "walk_east.py"
    path.write_text(EAST)
    return f"{path}:WalkEast"


def _moves(trace: dict) -> int:
    return sum(abs(a[0] - b[0]) + abs(a[1] - b[1]) for step in trace["steps"]
               for _, a, b in step["event"]["moves"] if step["event"]["kind"] != "look")


@pytest.mark.parametrize("scheduler", ["fsync", "ssync", "async"])
def test_walking_away_violates_the_move_bound_before_the_search_ends(east: str, scheduler: str) -> None:
    r = run_check(TWO, algorithm=east, scheduler=scheduler, frames="compass",
                  max_states=10**5, max_seconds=60)
    assert r["verdict"] == "VIOLATED" and r["property"] == "move-bound"
    assert r["properties"]["move-bound"]["holds"] is False
    assert r["properties"]["final"]["holds"] is None  # the search did not finish
    assert _moves(r["trace"]) > r["bound"] == 16
    assert replay(r["trace"]).confirmed
    drift = r["drift"]
    assert drift["vector"] == [1, 0] and drift["periods_checked"] >= 3
    assert r["trace"]["detail"]["drift"] == drift


def test_a_drift_under_the_bound_is_incomplete_with_its_evidence(east: str, capsys) -> None:
    r = run_check(TWO, algorithm=east, scheduler="async", frames="compass",
                  max_states=10**5, max_seconds=60, move_bound_c=100)
    assert (r["verdict"], r["reason"], r["trace"]) == ("INCOMPLETE", "drift", None)
    assert set(r["drift"]) == {"vector", "period", "periods_checked", "start"}
    assert r["drift"]["vector"] == [1, 0] and r["drift"]["period"] == 4  # look, move, look, move
    code = main(["check", "--robots", "0,0 0,1", "--meeting", "2,2", "--algorithm", east,
                 "--frames", "compass", "--scheduler", "async", "--move-bound-c", "100"])
    out = capsys.readouterr().out
    assert code == 3 and "reason: drift" in out and "not a proof" in out


def test_a_finished_graph_is_still_needed_for_verified() -> None:
    r = run_check(Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True),
                  algorithm="go-to-target", scheduler="async", max_states=100)
    assert r["verdict"] == "INCOMPLETE" and "drift" not in r


def test_the_i22_run_that_walks_away() -> None:
    """The paper's algorithm, ASYNC: a 4-event fair cycle (two robots, on two rows, take
    turns as guard) repeats shifted by (1, 0); the move bound falls on the way."""
    r = run_check(I22, algorithm="paper", scheduler="async", max_states=10**6, max_seconds=600)
    assert r["verdict"] == "VIOLATED" and r["property"] == "move-bound"
    assert _moves(r["trace"]) > r["bound"] == 48
    assert replay(r["trace"]).confirmed
    assert r["drift"]["period"] == 4 and r["drift"]["vector"] in ([1, 0], [-1, 0], [0, 1], [0, -1])


def _fewest_events_over(e, bound: float) -> int | None:
    """Brute force: BFS over every (state, moves) pair, moves capped past the bound."""
    cap = int(bound) + 1
    seen = {(0, 0)}
    queue = deque([(0, 0, 0)])
    expanded = len(e.offsets) - 1
    while queue:
        s, m, k = queue.popleft()
        if m > bound:
            return k
        if s >= expanded:
            continue
        for t, w in real_edges(e, s):
            node = (t, min(m + w, cap))
            if node not in seen:
                seen.add(node)
                queue.append((*node, k + 1))
    return None


@pytest.mark.parametrize("bound", [3, 7, 20])
def test_most_moves_has_the_fewest_events(bound: int) -> None:
    for margin in (2, 4):
        e = explore(I22, "paper", "async", limits=Limits(margin=margin))
        walk = most_moves(e, bound)
        want = _fewest_events_over(e, bound)
        if want is None:
            assert walk is None or walk.moves <= bound
        else:
            assert walk.moves > bound and len(walk.path) - 1 == want
            assert sum(walk.weights) == walk.moves


def test_replay_rejects_a_move_bound_trace_with_a_false_d(east: str) -> None:
    r = run_check(TWO, algorithm=east, scheduler="fsync", frames="compass",
                  max_states=10**5, max_seconds=60)
    trace = json.loads(json.dumps(r["trace"]))
    trace["detail"]["D"] = 1
    with pytest.raises(InvalidInput, match="D = 1"):
        replay(trace)


def test_no_drift_on_a_run_that_gathers() -> None:
    e = explore(Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True),
                "go-to-target", "async")
    walk = most_moves(e, 10**6)
    steps = e.concretise(walk.path, weights=walk.weights)
    states = [e.initial_state, *(s for _, s in steps)]
    assert find_drift(states, [ev for ev, _ in steps], lambda r: e.facts(r).move_sets) is None


@pytest.mark.parametrize("algorithm,prop,cause", [
    ("broken-undefined", "defined", "one step from the target"),
    ("broken-crash", "crash", "ZeroDivisionError"),
    ("broken-stay", "final", "final"),  # go-to-target names no phase: the property
])
def test_every_violation_names_its_cause(algorithm: str, prop: str, cause: str) -> None:
    r = run_check(Configuration([(0, 0), (3, 1)], [(2, 2)], initial=True), algorithm=algorithm,
                  scheduler="async", max_states=10**5, max_seconds=60)
    assert r["property"] == prop
    assert r["cause"] == r["trace"]["cause"] == r["properties"][prop]["cause"] == cause


def test_the_paper_names_its_phase_in_the_cause() -> None:
    r = run_check(Configuration([(0, 0), (0, 1), (3, 3)], [(1, 2), (2, 1)], initial=True),
                  algorithm="paper", scheduler="fsync", max_states=10**5, max_seconds=60)
    assert r["property"] == "target-invariance" and r["cause"] == "I2 make multiplicity"
    assert r["properties"]["termination"]["cause"] == "I2 make multiplicity"  # its cycle's phases
    assert replay(r["trace"]).confirmed  # a cause in the trace is no obstacle to replay


def test_an_old_database_gains_the_cause_column_and_its_rows_say_unknown(tmp_path: Path) -> None:
    import sqlite3

    from gather_verify.sweeps.store import CAUSE_UNKNOWN, Store
    from gather_verify.sweeps.sweep import format_summary, summarise_totals

    path = tmp_path / "old.sqlite"
    db = sqlite3.connect(path)
    db.executescript("""
        CREATE TABLE sweeps (id INTEGER PRIMARY KEY, settings TEXT NOT NULL UNIQUE);
        CREATE TABLE results (sweep INTEGER NOT NULL, key TEXT NOT NULL, "index" INTEGER NOT NULL,
            robots TEXT, meeting_nodes TEXT, class TEXT, verdict TEXT, property TEXT, reason TEXT,
            states INTEGER, transitions INTEGER, max_moves INTEGER, D INTEGER, n INTEGER,
            ratio REAL, trace TEXT, failing TEXT, PRIMARY KEY (sweep, key));
        CREATE TABLE timings (sweep INTEGER NOT NULL, key TEXT NOT NULL, seconds REAL,
            PRIMARY KEY (sweep, key));
        INSERT INTO sweeps VALUES (1, '{}');
        INSERT INTO results (sweep, key, "index", class, verdict, property, failing)
            VALUES (1, 'k', 0, 'I22', 'VIOLATED', 'defined', '["defined"]');
    """)
    db.commit()
    db.close()
    store = Store(path)
    store.add(1, [{"key": "k2", "index": 1, "class": "I22", "verdict": "VIOLATED",
                   "property": "defined", "failing": ["defined"], "cause": "I2 guard placement"}])
    summary = summarise_totals(store.totals(1), [])
    assert summary["causes"] == {"defined": {CAUSE_UNKNOWN: 1, "I2 guard placement": 1}}
    lines: list[str] = []
    format_summary(summary, lines.append)
    assert any(line.startswith("  defined x 2: ") and CAUSE_UNKNOWN in line for line in lines)


def test_sweep_rows_keep_their_cause(tmp_path: Path, capsys) -> None:
    db = tmp_path / "x.sqlite"
    code = main(["sweep", "--robots", "2", "--meeting", "1", "--box", "3x3", "--algorithm",
                 "broken-undefined", "--scheduler", "fsync", "--db", str(db)])
    out = capsys.readouterr().out
    assert code in (0, 1) and "defined x" in out and "one step from the target" in out
    from gather_verify.sweeps.store import Store

    store = Store(db)
    ((sweep, _),) = store.sweeps()
    rows = [r for r in store.results(sweep) if r["verdict"] == "VIOLATED"]
    assert rows and all(r["cause"] == r["trace"]["cause"] for r in rows)


def test_drift_handles_two_robots_on_one_node_one_pending() -> None:
    a = (((0, 0), None), ((0, 0), (1, 0)), ((5, 5), None))
    states = [tuple(((x + k, y), p if p is None else (p[0] + k, p[1])) if (x, y) != (5, 5)
                    else ((x, y), p) for (x, y), p in a) for k in range(4)]
    got = find_drift(states, [type("E", (), {"robots": (0, 1, 2)})()] * 3,
                     lambda robots: {v: frozenset([v]) for v in robots})
    assert got == {"vector": [1, 0], "period": 1, "periods_checked": 3, "start": 0}
