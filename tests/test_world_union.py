"""The union engine of finite worlds (sweeps/world_union.py): every row equal to the
per-configuration check's, on every configuration of small worlds, under every scheduler and
task, with lights and reductions; the union decides the configurations it can, and a broken
union (a bad state not counted) is caught by the same comparison."""

from __future__ import annotations

import sqlite3
from pathlib import Path

import numpy as np
import pytest

from gather_verify.cli import main
from gather_verify.sweeps import world_union
from gather_verify.sweeps.classes import verify_class
from gather_verify.sweeps.sweep import SweepSettings
from gather_verify.sweeps.world_census import verify_world_one, world_configurations
from gather_verify.sweeps.world_union import decide_world_class, world_class_tasks
from gather_verify.worlds import get_world
from gather_verify.worlds.moves import parse_lights

ROOT = Path(__file__).resolve().parent.parent
HOUSE = "0 1\n1 2\n2 3\n3 0\n2 4\n3 4\n"
"""The house graph: a square with a roof, two automorphisms."""


def _without_seconds(row: dict) -> dict:
    return {k: v for k, v in row.items() if k != "seconds"}


def assert_rows_equal(world: str, n: int, m: int, algorithm: str, scheduler: str, **options
                      ) -> dict[str, int]:
    """Every configuration of the world: the class rows equal the per-configuration rows.
    Returns how many the union decided, how many were checked on their own, and how many
    are VERIFIED."""
    task = options.pop("task", "gathering-on-meeting-nodes" if m else "gathering")
    s = SweepSettings(robots=n, meeting=m, box=(0, 0), algorithm=algorithm,
                      scheduler=scheduler, world=world, task=task, max_memory_mb=8000,
                      **options)
    w = get_world(world)
    k = parse_lights(s.lights).colours if s.initial_colours == "all" else 1
    items = list(enumerate(world_configurations(w, n, m, s.frames, k)))
    seen: dict[int, dict] = {}
    settled = 0
    for members in world_class_tasks(s, items):
        decided = decide_world_class(s, members)
        settled += len(decided.rows)
        assert sorted(decided.reasons) == [i for i, _ in decided.fallback]  # each with why
        rows, rest = verify_class(s, members, decide_world_class, verify_world_one)
        assert [r["index"] for r in rows] == [i for i, _ in members] and rest == []
        kept, handed = verify_class(s, members, decide_world_class, verify_world_one,
                                    hand_off=0.0)
        assert len(kept) == len(decided.rows)
        assert [i for i, _ in handed] == [i for i, _ in members if i not in
                                          {r["index"] for r in kept}]
        seen.update((r["index"], r) for r in rows)
    assert sorted(seen) == [i for i, _ in items]
    verified = 0
    for i, c in items:
        own = verify_world_one(s, i, c)
        assert _without_seconds(seen[i]) == _without_seconds(own), (i, c)
        verified += own["verdict"] == "VERIFIED"
    return {"settled": settled, "own": len(items) - settled, "verified": verified}


SCHEDULERS = ["fsync", "ssync", "async", "centralized", "round-robin"]
EVERY = [(w, sched) for w in ("ring:6", "grid:3x3", "torus:3x3") for sched in SCHEDULERS]
QUICK = [("ring:6", sched) for sched in SCHEDULERS] + [("grid:3x3", "async"),
                                                         ("torus:3x3", "ssync")]


@pytest.mark.parametrize("world, scheduler", [
    pytest.param(*case, marks=[] if case in QUICK else [pytest.mark.slow]) for case in EVERY])
def test_go_to_target_rows_equal_per_config_rows(world, scheduler):
    counts = assert_rows_equal(world, 2, 1, "go-to-target", scheduler)
    assert counts["settled"] == counts["verified"] > 0  # all from the union: none fails


@pytest.mark.parametrize("scheduler", ["fsync", "ssync", "async"])
def test_every_task_with_violations(scheduler):
    """Tasks whose rows are mostly VIOLATED: those are checked on their own, the others come
    from the union, and both agree with the per-configuration rows."""
    assert_rows_equal("ring:6", 3, 0, "ring-gather", scheduler, detection="global-weak")
    assert_rows_equal("ring:6", 3, 0, "broken-ring-gather", scheduler,
                      detection="global-weak")
    assert_rows_equal("ring:6", 3, 0, "ring-explore", scheduler,
                      task="exclusive-perpetual-exploration", frames="chirality")
    assert_rows_equal("ring:5", 2, 1, "go-to-target", scheduler, task="exploration-with-stop")


def test_lights_every_initial_colouring():
    counts = assert_rows_equal("ring:7", 2, 0, "ring-inchworm", "async", lights="2",
                               initial_colours="all", visibility=2,
                               task="exclusive-perpetual-exploration")
    assert counts["settled"] > 0 and counts["own"] > 0


@pytest.mark.parametrize("scheduler", ["ssync", "round-robin"])
def test_reductions_on_safety_parts(scheduler):
    """Only a safety part checked: the per-configuration search is reduced (anonymity and
    the symmetries fixing M; under round-robin, anonymity relabels the robots with the
    order), and so is the union; the counts agree."""
    counts = assert_rows_equal("ring:7", 3, 1, "go-to-target", scheduler, properties=("final",))
    assert counts["settled"] > 0


def test_a_graph_file(tmp_path):
    graph = tmp_path / "house.edgelist"
    graph.write_text(HOUSE)
    counts = assert_rows_equal(f"graph:{graph}", 2, 1, "go-to-target", "async")
    assert counts["settled"] > 0


def test_a_crash_falls_back_to_the_own_checks():
    counts = assert_rows_equal("grid:3x2", 2, 0, "ring-explore", "fsync")
    assert counts["settled"] == 0


def test_a_union_that_misses_a_bad_state_is_caught(monkeypatch):
    """The comparison fails on a union that does not count deadlocks as bad."""
    real = world_union._Union._bad

    def blind(self, sources, targets):
        bad = real(self, sources, targets)
        return bad & ~np.asarray(self.search.arrays.final, dtype=bool)

    monkeypatch.setattr(world_union._Union, "_bad", blind)
    with pytest.raises(AssertionError):
        assert_rows_equal("ring:6", 2, 0, "ring-gather", "fsync", detection="global-weak")


def test_a_union_that_finds_no_livelock_is_caught(monkeypatch):
    """... on one that finds no fair component (bounce never ends: every row is VIOLATED)."""
    monkeypatch.setattr(world_union._Union, "_fair",
                        lambda self, inside, *_, **__: np.zeros(len(inside), dtype=bool))
    with pytest.raises(AssertionError):
        assert_rows_equal("ring:5", 2, 0, "bounce", "ssync", lights="2")


@pytest.mark.parametrize("scheduler", ["ssync", "async", "centralized"])
def test_the_union_decides_every_verified_row_of_a_liveness_task(scheduler):
    """A fair component is a livelock, an unfair one is not: the union settles every
    VERIFIED row of perpetual exploration itself (a union that took every cycle, or every
    state a robot cannot leave, for a livelock would leave them to the own checks)."""
    counts = assert_rows_equal("ring:6", 3, 0, "ring-explore", scheduler,
                               task="exclusive-perpetual-exploration", frames="chirality")
    assert counts["verified"] > 0 and counts["settled"] == counts["verified"]


def test_a_union_that_takes_every_cycle_for_a_livelock_settles_less(monkeypatch):
    def every_cycle(self, inside, sources, targets, *, skip_final, single_states):
        from gather_verify.kernels import world as kw

        labels, _ = kw.scc_labels(self.search.arrays.offsets, self.search.arrays.targets,
                                  np.ascontiguousarray(inside))
        member = labels >= 0
        size = np.bincount(labels[member])
        return member & ((size[np.maximum(labels, 0)] > 1) | single_states)

    monkeypatch.setattr(world_union._Union, "_fair", every_cycle)
    counts = assert_rows_equal("ring:6", 3, 0, "ring-explore", "ssync",
                               task="exclusive-perpetual-exploration", frames="chirality")
    assert counts["settled"] < counts["verified"]


@pytest.mark.parametrize("workers, algorithm, verdicts", [
    ("1", "go-to-target", 0), ("2", "ring-gather", 1)])
def test_the_sweep_command_stores_the_same_rows(tmp_path, capsys, workers, algorithm,
                                                verdicts):
    """Both engines through the command; with two workers the own checks of a class are
    handed to the other worker."""
    rows = {}
    for engine in ("union", "per-config"):
        db = tmp_path / f"{engine}.sqlite"
        assert main(["sweep", "--world", "ring:5-6", "--robots", "2-3", "--meeting", "1",
                     "--scheduler", "ssync", "--db", str(db), "--engine", engine,
                     "--algorithm", algorithm, "--multiplicity", "global-weak",
                     "--workers", workers, "--json"]) == verdicts
        with sqlite3.connect(db) as con:
            rows[engine] = con.execute(
                "SELECT r.key, robots, meeting_nodes, class, verdict, property, reason, states,"
                " transitions, trace, failing FROM results r ORDER BY r.sweep, r.key").fetchall()
    capsys.readouterr()
    assert rows["union"] == rows["per-config"] and len(rows["union"]) == 33
