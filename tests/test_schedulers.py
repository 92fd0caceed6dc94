"""Schedulers as plug-in parts: the protocol, the registry, and a scheduler
added from outside the package running on both engines, the CLI and the scenario loader."""

from __future__ import annotations

import json
from collections.abc import Iterator

import numpy as np
import pytest

from gather_verify.cli import main
from gather_verify.engine.explore import explore_reference
from gather_verify.engine.fast_explore import explore_fast
from gather_verify.model.configuration import Configuration
from gather_verify.scenario import ScenarioError, parse_scenario
from schedulers import SCHEDULERS, Event, Frontier, Successors, get_scheduler
from schedulers.base import MoveSets, State, bulk_rounds, configuration_of, subsets_matrix

YARD = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)


class Centralized:
    """A new scheduler, written as a user would: one robot per round (the centralized
    adversary), so SSYNC restricted to the activated sets of size one."""

    name = "one-at-a-time"
    kinds = ("round",)

    def successors(self, state: State, move_sets: MoveSets) -> Iterator[tuple[Event, State]]:
        options = move_sets(configuration_of(state))
        for i, (node, _) in enumerate(state):
            for d in sorted(options[node]):
                moves = ((i, node, d),) if d != node else ()
                yield (Event("round", (i,), moves),
                       tuple((d if j == i else v, None) for j, (v, _) in enumerate(state)))

    def bulk_successors(self, frontier: Frontier, budget: int) -> Successors:
        n = frontier.codes.shape[1]
        return bulk_rounds(frontier, budget, subsets_matrix([[i] for i in range(n)], n))


class Skipping(Centralized):
    """Broken: its bulk face forgets the last robot's events (the engines must disagree)."""

    name = "skipping"

    def bulk_successors(self, frontier: Frontier, budget: int) -> Successors:
        n = frontier.codes.shape[1]
        return bulk_rounds(frontier, budget, subsets_matrix([[i] for i in range(n - 1)], n))


@pytest.fixture
def registered(monkeypatch):
    """Register the two schedulers for one test: the one registry line."""
    monkeypatch.setitem(SCHEDULERS, "one-at-a-time", Centralized)
    monkeypatch.setitem(SCHEDULERS, "skipping", Skipping)


def test_every_registered_scheduler_has_the_protocol():
    for name, cls in SCHEDULERS.items():
        s = get_scheduler(name)
        assert s.name == name and s.kinds
        # a phase scheduler (§13's sub-models) runs on the finite and rendezvous worlds only:
        # its one face is ``luminous`` (Z² refuses it in one line, tests/test_phase_schedulers.py)
        members = ("luminous",) if getattr(cls, "phased", False) else (
            "successors", "bulk_successors")
        for member in members:
            assert callable(getattr(cls, member)), (name, member)


def test_unknown_scheduler():
    with pytest.raises(ValueError, match="unknown scheduler 'lockstep': use one of fsync, ssync, async, centralized, round-robin"):
        get_scheduler("lockstep")


def test_new_scheduler_runs_on_both_engines(registered):
    ref = explore_reference(YARD, "go-to-target", "one-at-a-time", reduction=False)
    fast = explore_fast(YARD, "go-to-target", "one-at-a-time", reduction=False)
    assert (fast.states, fast.transitions) == (ref.states, ref.transitions)
    assert list(fast.keys) == list(ref.keys) and list(fast.targets) == list(ref.targets)
    # go-to-target: any SSYNC round is a sequence of single moves, hence the same 216 states
    assert ref.states == 216


def test_broken_bulk_face_is_caught(registered):
    ref = explore_reference(YARD, "go-to-target", "skipping", reduction=False)
    fast = explore_fast(YARD, "go-to-target", "skipping", reduction=False)
    assert (fast.states, fast.transitions) != (ref.states, ref.transitions)


def test_new_scheduler_in_cli_and_scenarios(registered, capsys):
    code = main(["check", "--robots", "0,0 3,1 1,4", "--meeting", "2,2", "--algorithm",
                 "go-to-target", "--scheduler", "one-at-a-time", "--no-reduction", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["verdict"] == "VERIFIED" and out["scheduler"] == "one-at-a-time"
    s = parse_scenario({"robots": [[0, 0]], "meeting_nodes": [[1, 1]],
                        "scheduler": "one-at-a-time"}, "inline")
    assert s.scheduler == "one-at-a-time"


def test_scenario_loader_reads_the_registry():
    with pytest.raises(ScenarioError, match="use one of fsync, ssync, async, centralized, round-robin"):
        parse_scenario({"robots": [[0, 0]], "meeting_nodes": [[1, 1]],
                        "scheduler": "one-at-a-time"}, "inline")


def test_budget_takes_leading_states():
    """A round scheduler asked for fewer events than a frontier holds takes the leading
    states whose events fit (at least one), and says how many."""
    codes = np.array([[0, 35], [5, 40], [10, 45]], dtype=np.int64)
    masks = np.full((3, 2), 0b10011, dtype=np.uint8)  # STEPS[0], STEPS[1] or stay: 3 choices
    neighbour = np.arange(40).reshape(10, 4)
    f = Frontier(codes, masks, neighbour)
    ssync = get_scheduler("ssync")
    assert ssync.bulk_successors(f, 10**6).states == 3
    one = ssync.bulk_successors(f, 1)
    assert one.states == 1 and len(one.source) == 3 + 3 + 9 and set(one.source.tolist()) == {0}
    assert ssync.bulk_successors(f, 30).states == 2
