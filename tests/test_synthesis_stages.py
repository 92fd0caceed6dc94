"""A candidate's exploration in stages (synthesis/search.py, ``staged``) answers as the
whole search does: the same tables fail, each failure found on a stage's prefix replays
from scratch as a violation with the candidate's own answers, and remembered passes
(``_Search.passed``) skip only explorations that would read the same answers."""

from __future__ import annotations

import random
from unittest import mock

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

pytest.importorskip("pysat", reason="synthesize needs python-sat (extra synth)")

from gather_verify.engine.encoding import Limits  # noqa: E402
from gather_verify.synthesis import search as S  # noqa: E402
from gather_verify.synthesis.certificate import replay  # noqa: E402
from gather_verify.synthesis.views import Views, make_instance  # noqa: E402

CASES = [
    ("ring:6", "3", "ssync", "gathering"),
    ("ring:7", "3", "centralized", "exploration-with-stop"),
    ("ring:7", "3", "async", "exclusive-perpetual-exploration"),
    ("ring:5", "2", "async", "gathering"),
]
_VIEWS: dict[tuple[str, ...], Views] = {}


def _views(case: tuple[str, ...]) -> Views:
    if case not in _VIEWS:
        world, robots, sched, task = case
        _VIEWS[case] = Views(make_instance(world, robots, "", sched, task, "global-weak"))
    return _VIEWS[case]


def _explore(views: Views, choice: S.Table, idx: int, stage: int):
    with mock.patch.object(S, "STAGE_STATES", stage), mock.patch.object(S, "STAGE_GROWTH", 2):
        return S.explore(views.inst, views, choice, idx, set(), Limits(max_seconds=60))


@settings(max_examples=25, deadline=None)
@given(case=st.sampled_from(CASES), seed=st.integers(0, 2**32 - 1), data=st.data())
def test_a_staged_exploration_fails_exactly_when_the_whole_one_does(
        case: tuple[str, ...], seed: int, data: st.DataObject) -> None:
    views = _views(case)
    inst = views.inst
    idx = data.draw(st.integers(0, len(inst.configurations) - 1))
    rng = random.Random(seed)
    choice = S.Table({}, lambda k: rng.randrange(len(views.options[k])))
    whole, whole_found = _explore(views, choice, idx, 10**9)
    staged, found = _explore(views, choice, idx, 2)
    assert whole.complete and staged.complete
    assert bool(found) == bool(whole_found)
    assert staged.states <= whole.states
    for f in found:
        cex = S.counterexample(inst, views, choice, idx, staged, f)
        lits = replay(views, cex).literals  # a violation from scratch, or CertificateError
        assert all(choice[k] == o for k, o in lits.items())


def test_stages_find_a_livelock_on_a_prefix() -> None:
    """A table whose robots all step forward for ever on ring:7 (exploration with stop)
    fails termination within the first stage: fewer states than the whole space."""
    views = _views(("ring:7", "3", "centralized", "exploration-with-stop"))
    choice = S.Table({}, lambda k: len(views.options[k]) - 1)
    whole, whole_found = _explore(views, choice, 0, 10**9)
    staged, found = _explore(views, choice, 0, 4)
    assert [f.property for f in found] == [f.property for f in whole_found] == ["termination"]
    assert staged.states < whole.states


def test_a_remembered_pass_is_used_only_with_the_same_answers() -> None:
    reached: set[int] = set()
    passes = [((1, 0), (4, 2)), ((2, 1),)]
    assert S._Search.passed(S.Table({1: 0, 4: 2, 2: 0}), passes, reached)
    assert reached == {1, 4}
    assert not S._Search.passed(S.Table({1: 0, 4: 1, 2: 0}), passes, set())
    assert S._Search.passed(S.Table({1: 1, 4: 1, 2: 1}), passes, set())
    assert passes[0] == ((2, 1),)  # the one used last comes first


@pytest.mark.parametrize(("world", "robots", "sched", "task", "frames"), [
    ("ring:5", "3", "fsync", "exploration-with-stop", "all"),
    ("ring:5", "2", "async", "exclusive-perpetual-exploration", "chirality"),
])
def test_a_witness_found_in_stages_passes_the_whole_exploration(
        world: str, robots: str, sched: str, task: str, frames: str) -> None:
    inst = make_instance(world, robots, "", sched, task, "global-weak", frames)
    views = Views(inst)
    with mock.patch.object(S, "STAGE_STATES", 2), mock.patch.object(S, "STAGE_GROWTH", 2):
        got = S.synthesize(inst, views=views, max_seconds=60)
    assert got.answer == "exists"
    table = S.Table(got.table)
    for idx in range(len(inst.configurations)):
        whole, found = _explore(views, table, idx, 10**9)
        assert whole.complete and found == []
