"""The rendezvous rules (SEMANTICS.md §13) against the naive referee, and the referee
against the published results.

The referee (``tests/rendezvous_referee.py``) is a plain breadth-first search written from
§13 alone; :mod:`gather_verify.worlds.rendezvous_rules` is the module the world builds on.
Their End-Move and Look rules must agree on every input; the referee must reproduce what
the papers prove, fail a deliberately broken algorithm with a trace that replays, and
order the synchrony models as they nest (a run of a sub-model is a run of the larger one).
"""

from __future__ import annotations

import itertools

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from rendezvous_referee import (
    MODELS,
    Referee,
    check,
)

from gather_verify.errors import InvalidInput
from gather_verify.worlds import rendezvous_rules as rr

A = rr.ALGORITHMS


def test_end_move_agrees_with_the_referee_on_every_input():
    for pos, mine, theirs in itertools.product(range(3), (1, 2, 3), range(4)):
        assert rr.end_move(pos, mine, theirs) == Referee.land(pos, mine, theirs)


@pytest.mark.parametrize("name", list(A))
def test_look_agrees_with_the_referee(name):
    """decide() against the referee's Look, for every colour read, position, and whether
    the other robot is moving."""
    alg = A[name]
    ref = Referee(alg, "async")
    for own, seen, pos, moving in itertools.product(range(alg.colours), range(alg.colours),
                                                    range(3), (False, True)):
        other = (rr.END_MOVE, seen, seen, rr.TO_HALF) if moving else (rr.LOOK, seen, seen, 0)
        after = ref.step((pos, (rr.LOOK, own, own, 0), other), 0, seen)
        assert (after[1][3], after[1][2]) == rr.decide(alg, own, seen, pos, moving)


# --- the published results ---------------------------------------------------------------

@pytest.mark.parametrize("name, model, movement, expected", [
    # Viglietta (ALGOSENSORS 2013): 2 colours suffice in SSYNC (non-rigid), 3 in ASYNC
    # (non-rigid); 2 colours do not suffice in ASYNC (his table fails there)
    ("vig-2cols", "ssync", "non-rigid", "PASS"),
    ("vig-2cols", "async", "rigid", "FAIL"),
    ("vig-3cols", "async", "non-rigid", "PASS"),
    # Heriban, Défago, Tixeuil (ICDCN 2018): 2 colours in non-rigid ASYNC, telling zero
    # distance apart
    ("optimal", "async", "non-rigid", "PASS"),
    # the trivial moves: to the midpoint solves FSYNC only; to the other fails FSYNC (the
    # robots swap) and solves the centralized model
    ("to-half", "fsync", "non-rigid", "PASS"),
    ("to-half", "ssync", "rigid", "FAIL"),
    ("to-other", "fsync", "rigid", "FAIL"),
    ("to-other", "centralized", "non-rigid", "PASS"),
    ("no-move", "fsync", "rigid", "FAIL"),
])
def test_published_results(name, model, movement, expected):
    assert check(A[name], model, movement).verdict == expected


def test_a_broken_algorithm_fails_with_a_trace_that_replays():
    """vig-3cols with one row broken (white seeing red stays instead of going to the
    other) fails under ASYNC; its counterexample replays event by event and its cycle is
    fair and never gathered."""
    good = A["vig-3cols"]
    rules = tuple(((o, t, p), (rr.STAY, rr.WHITE) if (o, t) == (rr.WHITE, rr.RED) else ans)
                  for (o, t, p), ans in good.table.items())
    broken = rr.RendezvousAlgorithm("vig-3cols-broken", 3, rules)
    verdict = check(broken, "async")
    assert verdict.verdict == "FAIL"
    assert_replays(broken, "async", verdict)


def assert_replays(alg, model, verdict, movement="non-rigid", colours="all"):
    ref = Referee(alg, model, movement, colours)
    assert verdict.prefix[0][1] in ref.starts
    walk = verdict.prefix + verdict.cycle[1:]
    robots = 0
    for (_, a), (label, b) in itertools.pairwise(walk):
        events = {(lab, succ) for _, lab, succ in ref.events(a)}
        assert (label, b) in events
    for (_, a), (label, b) in itertools.pairwise(verdict.cycle):
        robots |= next(m for m, lab, succ in ref.events(a) if (lab, succ) == (label, b))
    assert verdict.cycle[0][1] == verdict.cycle[-1][1] == verdict.prefix[-1][1]
    assert robots == 3, "the cycle is fair: both robots step in it"
    assert not any(Referee.goal(s) for _, s in verdict.cycle)


@pytest.mark.parametrize("name, model", [("vig-2cols", "async"), ("to-half", "ssync"),
                                         ("flo-algo3ext", "async-lc-atomic"),
                                         ("vig-3cols", "async-safe")])
def test_counterexamples_replay(name, model):
    verdict = check(A[name], model)
    assert verdict.verdict == "FAIL"
    assert_replays(A[name], model, verdict)


# --- the models nest ----------------------------------------------------------------------

SUBMODELS = [("async", "async-lc-atomic"), ("async-lc-atomic", "async-lc-strict"),
             ("async", "async-cm-atomic"), ("async", "async-move-atomic"),
             ("async-safe", "async-regular"), ("async-regular", "async"),
             ("async-move-safe", "async-move-regular"),
             ("async-move-regular", "async-move-atomic"), ("async-safe", "async-move-safe"),
             ("async", "ssync"), ("ssync", "fsync"), ("ssync", "centralized")]
"""(larger, smaller): every run of the smaller model is a run of the larger one, fair runs
included, so what the larger one verifies the smaller one verifies."""


@st.composite
def tables(draw, colours=2):
    """A random full-light algorithm with ``colours`` colours."""
    rules = []
    for own, other, pos in itertools.product(range(colours), range(colours), range(3)):
        move = draw(st.sampled_from((rr.STAY, rr.TO_HALF, rr.TO_OTHER)))
        rules.append(((own, other, pos), (move, draw(st.integers(0, colours - 1)))))
    return rr.RendezvousAlgorithm("random", colours, tuple(rules))


@settings(max_examples=40, deadline=None)
@given(tables(), st.sampled_from(SUBMODELS), st.sampled_from(("rigid", "non-rigid")))
def test_verdicts_nest_along_the_submodels(alg, pair, movement):
    big, small = pair
    if check(alg, big, movement).verdict == "PASS":
        assert check(alg, small, movement).verdict == "PASS"


@settings(max_examples=10, deadline=None)
@given(tables(), st.sampled_from(sorted(MODELS)))
def test_bounded_fairness_only_loses_counterexamples(alg, model):
    """Every run that starves no robot for long is fair: a counterexample under the SPIN
    model's bounded fairness is one under §13's fairness."""
    if check(alg, model, fairness="bounded").verdict == "FAIL":
        assert check(alg, model).verdict == "FAIL"


def test_gathered_is_absorbing():
    """From a gathered state every event leads to a gathered state (so ◇□ gathered is
    ◇ gathered), on every model and algorithm (small ones)."""
    for name in ("vig-2cols", "vig-3cols", "optimal"):
        for model in MODELS:
            ref = Referee(A[name], model)
            ref.explore()
            for v, s in enumerate(ref.states):
                if Referee.goal(s):
                    assert all(Referee.goal(ref.states[w]) for w, _, _ in ref.edges[v])


def test_tables_refuse_what_their_lights_hide():
    with pytest.raises(InvalidInput, match="hide"):
        rr.RendezvousAlgorithm("x", 2, (((0, rr.ANY, rr.ANY), (0, 0)),), lights="external")
    with pytest.raises(InvalidInput, match="no rule answers"):
        rr.RendezvousAlgorithm("x", 2, (((0, rr.ANY, rr.ANY), (0, 0)),))
    with pytest.raises(InvalidInput, match="unknown rendezvous algorithm"):
        rr.get_algorithm("vig-4cols")
    assert rr.get_algorithm("viglietta-2") is A["vig-2cols"]


# --- the stored SPIN table ---------------------------------------------------------------

def _stored(name):
    import json
    from pathlib import Path

    return json.loads((Path(__file__).parent.parent / "bench/spin/light" / name).read_text())


def test_every_spin_algorithm_is_built_in_and_every_stored_cell_agrees():
    """The SPIN model's 15 algorithms are the built-ins (by its names), each cell of the
    stored SPIN run checked the algorithm it names, and the referee gives the stored SPIN
    verdict on a sample of cells (the whole table: tests/rendezvous_table.py)."""
    spin = _stored("results.json")["cells"]
    assert {key.split("|")[0] for key in spin} == set(A)
    assert {a.spin for a in A.values()} == {c["algorithm_name"] for c in spin.values()}
    for key, c in spin.items():
        assert c["algorithm_name"] == A[key.split("|")[0]].spin
        assert c["verdict"] in ("PASS", "FAIL")
    for key in ("vig-2cols|async|rigid|same", "wada-4ext|fsync|non-rigid|all",
                "wada-4ext|fsync|non-rigid|same", "3ext-nonqss|async-lc-strict|rigid|all",
                "regular4|async-move-regular|non-rigid|all", "optimal|async-regular|rigid|all"):
        name, model, movement, colours = key.split("|")
        assert check(A[name], model, movement, colours).verdict == spin[key]["verdict"], key
