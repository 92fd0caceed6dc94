"""§13's synchrony models on the graph worlds with lights (SEMANTICS.md §10, §13): the same
scheduler module as on the rendezvous world (:mod:`schedulers.phases`).

- ``async`` on a graph world keeps §10's model and its counts (test data);
- §10's ``async`` is the phase model "Look-Compute atomic and strict, Move atomic" with a
  Look that stays and keeps its colour collapsed: the same states and edges once a robot
  that decided to stay, unchanged, is read as idle;
- a luminous ring algorithm under LC-atomic and safe-read ASYNC; a failing one's trace
  replays, and a trace whose read colours were changed does not;
- what does not run them says so in one line.
"""

from __future__ import annotations

import copy

import pytest

from gather_verify.algorithms import get_algorithm
from gather_verify.engine.world_search import search
from gather_verify.errors import InvalidInput
from gather_verify.world_check import run_world_check
from gather_verify.world_replay import replay_world
from gather_verify.worlds import get_world
from gather_verify.worlds.moves import WorldMoves, parse_lights
from schedulers import SCHEDULERS, get_scheduler
from schedulers.phases import (
    BEGIN_COMPUTE,
    BEGIN_MOVE,
    END_COMPUTE,
    END_MOVE,
    LOOK,
    MODELS,
    PhaseModel,
    PhaseScheduler,
)

PHASED = [name for name, cls in SCHEDULERS.items() if getattr(cls, "phased", False)]


def bounce(scheduler: str, **kw):
    return run_world_check("ring:6", "0 2", "", "bounce", scheduler, task="gathering",
                           lights="2", reduction=False, engine="reference", **kw)


@pytest.mark.parametrize("name, states, transitions", [
    ("fsync", 36, 90), ("ssync", 144, 756), ("async", 576, 1440)])
def test_the_graph_schedulers_keep_their_counts(name, states, transitions):
    """§10's test data: ``bounce`` on ring:6, robots on 0 and 2, reductions off."""
    r = bounce(name)
    assert (r["states"], r["transitions"]) == (states, transitions)


def test_every_sub_model_is_registered_and_phased():
    assert set(PHASED) == set(MODELS) - {"centralized", "fsync", "ssync", "async"}
    for name in PHASED:
        assert get_scheduler(name).model is MODELS[name]


def graph(scheduler):
    """bounce on ring:6 under ``scheduler``: the states and edges of the reference search."""
    world = get_world("ring:6")
    moves = WorldMoves(world, get_algorithm("bounce"), frozenset(), lights=parse_lights("2"))
    return search(world, (0, 2), moves.actions, scheduler, palette=2)


def collapsed(state):
    """A phase state as §10 reads it: the records are forgotten, so a robot between its Look
    and its Move that decided to stay (with its new colour shown) is idle."""
    return state[0]


def test_async_is_lc_strict_move_atomic_with_the_null_look_collapsed():
    """§10's ``async`` and the phase model (Look+Begin-Compute+End-Compute)(Begin-Move+
    End-Move), one robot at a time, reach the same configurations by the same events once
    the phases are forgotten (a phase run with its null cycles dropped is an ``async`` run,
    and back)."""
    bridge = PhaseScheduler("async-lc-strict")
    bridge.model = PhaseModel(((LOOK, BEGIN_COMPUTE, END_COMPUTE), (BEGIN_MOVE, END_MOVE)))
    phased, plain = graph(bridge), graph("async")
    assert {collapsed(k) for k in phased.keys} == {k[0] for k in plain.keys}
    phase_edges = {(collapsed(phased.keys[v]), collapsed(phased.keys[w]))
                   for v, out in enumerate(phased.edges) for w, _, _ in out}
    plain_edges = {(plain.keys[v][0], plain.keys[w][0])
                   for v, out in enumerate(plain.edges) for w, _, _ in out}
    assert {e for e in phase_edges if e[0] != e[1]} == plain_edges
    assert len(phased.keys) > len(plain.keys)  # the null cycles' middle states


@pytest.mark.parametrize("name", PHASED)
def test_a_luminous_ring_algorithm_under_every_sub_model(name):
    """``ring-inchworm`` (exclusive perpetual exploration with two colours) holds under
    LC-atomic, safe-read ASYNC and every other sub-model."""
    r = run_world_check("ring:6", "0 1", "", "ring-inchworm", name,
                        task="exclusive-perpetual-exploration", lights="2", colours=[1, 0],
                        visibility=2, reduction=False, engine="reference")
    assert r["verdict"] == "VERIFIED", r["reason"]
    assert r["reductions"] == "off"


def test_safe_reads_are_more_than_regular_and_atomic():
    counts = {name: run_world_check("ring:6", "0 1", "", "ring-inchworm", name,
                                    task="exclusive-perpetual-exploration", lights="2",
                                    colours=[1, 0], visibility=2, reduction=False)["transitions"]
              for name in ("async-lc-strict", "async-regular", "async-safe")}
    assert counts["async-safe"] > counts["async-regular"]


@pytest.mark.parametrize("name", PHASED)
def test_a_livelock_under_every_sub_model_replays(name):
    """``bounce`` never gathers: a fair cycle (every robot steps in it), confirmed by replay."""
    r = bounce(name)
    assert r["verdict"] == "VIOLATED" and r["property"] == "termination"
    done = replay_world(r["trace"])
    assert done.confirmed, done.message


def test_the_reductions_are_off_under_them():
    """Their records name robots: a safety part alone, reductions asked for, still searches
    every state (the count of the unreduced search)."""
    r = bounce("async-lc-atomic", properties=["gathered-when-final"])
    r2 = run_world_check("ring:6", "0 2", "", "bounce", "async-lc-atomic", task="gathering",
                         lights="2", properties=["gathered-when-final"])
    assert r2["reductions"] == "off: a phase scheduler's records name the robots"
    assert r2["states"] == r["states"]


def test_a_changed_command_does_not_replay():
    """A Look's command recorded in the trace (its next colour, carried out at End-Compute)
    must be the one the scheduler and the algorithm give: changed, the trace does not match
    itself."""
    trace = bounce("async-safe")["trace"]
    looks = [k for k, step in enumerate(trace["steps"]) if step["event"] and
             step["event"].get("chosen")]
    assert looks
    bad = copy.deepcopy(trace)
    step = bad["steps"][looks[0]]["event"]["chosen"][0]
    step[2] = 1 - step[2]  # the next colour it chose
    with pytest.raises(InvalidInput):
        replay_world(bad)


def test_what_does_not_run_them_says_so():
    from gather_verify.model.configuration import Configuration
    from gather_verify.plane_check import run_check

    with pytest.raises(InvalidInput, match="phase schedulers"):
        run_check(Configuration([(0, 0), (2, 1)], [(1, 1)], initial=True),
                  algorithm="go-to-target", scheduler="async-lc-atomic")
    with pytest.raises(InvalidInput, match="reference engine"):
        run_world_check("ring:6", "0 2", "", "bounce", "async-safe", task="gathering",
                        lights="2", engine="bulk")
    r = run_world_check("ring:6", "0 2", "", "bounce", "async-safe", task="gathering",
                        lights="2")
    assert r["engine"] == "reference" and "reference engine" in r["engine_fallback"]
