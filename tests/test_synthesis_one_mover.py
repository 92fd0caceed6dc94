"""The search's first phase, one class of movers, and its first step, one robot
(synthesis/search.py, ``_Search``): it answers as the search over every table does, its
candidates keep the restriction on every configuration met before them, a first step's
candidate answers alike under FSYNC and ASYNC, and a ``none`` only ever comes from the second
phase (every table), with a certificate that re-checks."""

from __future__ import annotations

import json
import random
from collections import Counter
from pathlib import Path
from unittest import mock

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

pytest.importorskip("pysat", reason="synthesize needs python-sat (extra synth)")

from gather_verify.engine.encoding import Limits  # noqa: E402
from gather_verify.synthesis import search as S  # noqa: E402
from gather_verify.synthesis.certificate import (  # noqa: E402
    verify_certificate,
    write_certificate,
)
from gather_verify.synthesis.views import Views, make_instance  # noqa: E402
from gather_verify.synthesis.witness import check_witness, write_witness  # noqa: E402

CASES = [  # (world, robots, scheduler, task): answer
    (("ring:5", "2", "async", "gathering"), "none"),
    (("ring:6", "3", "ssync", "gathering"), "none"),
    (("ring:7", "3", "async", "gathering"), "exists"),
    (("ring:6", "3", "fsync", "exclusive-perpetual-exploration"), "none"),
    (("ring:7", "3", "async", "exclusive-perpetual-exploration"), "none"),
    (("ring:6", "2", "ssync", "exploration-with-stop"), "none"),
    (("ring:9", "3", "ssync", "exploration-with-stop"), "none"),
]


def _instance(case: tuple[str, ...]):
    world, robots, sched, task = case
    return make_instance(world, robots, "", sched, task, "global-weak")


@pytest.mark.parametrize(("case", "answer"), CASES, ids=lambda c: "-".join(c)
                         if isinstance(c, tuple) else c)
def test_the_answer_is_the_same_with_and_without_the_first_phase(
        case: tuple[str, ...], answer: str) -> None:
    inst = _instance(case)
    on = S.synthesize(inst, max_seconds=60, one_mover=True)
    off = S.synthesize(inst, max_seconds=60, one_mover=False)
    assert on.answer == off.answer == answer
    assert off.one_mover is None
    # a none comes only once the restricted tables are exhausted, from the second phase
    assert on.one_mover == on.one_robot == ("witness" if answer == "exists" else "exhausted")


def _movers_hold(views: Views, table: dict[int, int], upto: int) -> bool:
    """In each of the first ``upto`` configurations with several views, at most one of its
    views leaves its node."""
    return all(sum(table[k] not in views.still[k] for k in keys) <= 1
               for keys in views.movers[:upto])


def test_the_first_phase_proposes_only_tables_with_one_class_of_movers() -> None:
    """Every candidate of the first phase keeps the restriction on every configuration met
    before it was proposed, and the search meets such configurations (the check bites)."""
    inst = _instance(("ring:7", "3", "async", "exclusive-perpetual-exploration"))
    views = Views(inst)
    seen: list[tuple[bool, int]] = []
    judge = S._Search.judge

    def spy(self: S._Search, choice: dict[int, int], reached: set[int]):
        if "one class" in self.gates:
            seen.append((_movers_hold(views, choice, self.movers_done), self.movers_done))
        return judge(self, choice, reached)

    with mock.patch.object(S._Search, "judge", spy):
        got = S.synthesize(inst, views=views, max_seconds=60, one_mover=True)
    assert got.answer == "none" and got.one_mover == "exhausted"
    assert len(seen) > 10 and all(ok for ok, _ in seen)
    assert max(n for _, n in seen) >= 5
    # without the phase, some candidate moves two classes at once
    free: list[bool] = []
    views = Views(inst)

    def spy_free(self: S._Search, choice: dict[int, int], reached: set[int]):
        free.append(_movers_hold(views, choice, len(views.movers)))
        return judge(self, choice, reached)

    with mock.patch.object(S._Search, "judge", spy_free):
        S.synthesize(inst, views=views, max_seconds=60, one_mover=False)
    assert not all(free)


def test_an_empty_first_phase_goes_on_over_every_table(tmp_path: Path) -> None:
    """With no view allowed to stay, the restricted space is empty as soon as a
    configuration has two views: the search still finds the witness in the second phase, and
    the checker verifies it."""
    inst = _instance(("ring:7", "3", "async", "gathering"))
    views = Views(inst)
    new_key = Views._new_key

    def no_stay(self: Views, *args):
        k = new_key(self, *args)
        self.still[k] = []
        return k

    with mock.patch.object(Views, "_new_key", no_stay):
        got = S.synthesize(inst, views=views, max_seconds=60, one_mover=True)
    assert got.answer == "exists" and got.one_mover == "exhausted"
    spec = write_witness(str(tmp_path / "w.py"), inst, views, got.table)
    assert {r["verdict"] for r in check_witness(spec, inst, 60)} == {"VERIFIED"}


def test_a_none_after_the_first_phase_has_a_certificate_that_rechecks(tmp_path: Path) -> None:
    inst = _instance(("ring:6", "3", "ssync", "gathering"))
    views = Views(inst)
    got = S.synthesize(inst, views=views, max_seconds=60, one_mover=True)
    assert got.answer == "none" and got.one_mover == "exhausted"
    path = str(tmp_path / "c.json")
    write_certificate(path, inst, views, got.counterexamples, got.literals, got.tree,
                      S.certificate_stats(got))
    verify_certificate(path)


def test_a_first_phase_out_of_time_never_answers_none() -> None:
    """A first phase given no time ends at once ("time"), and the answer is the second
    phase's."""
    inst = _instance(("ring:6", "3", "ssync", "gathering"))
    with mock.patch.object(S, "ONE_MOVER_SHARE", 0.0):
        got = S.synthesize(inst, max_seconds=60, one_mover=True)
    assert got.answer == "none" and got.one_mover == "time"


def test_the_command_says_how_the_first_phase_ended(tmp_path: Path) -> None:
    """On by default (its witness verified by the checker); ``--no-one-mover`` has none."""
    from tests.test_synthesis import cli

    common = ("--task", "gathering", "--multiplicity", "global-weak", "--scheduler", "async",
              "--witness", str(tmp_path / "w.py"), "--certificate", str(tmp_path / "c.json"),
              "--json")
    run = cli("--world", "ring:7", "--robots", "3", *common)
    assert run.returncode == 0, run.stderr
    report = json.loads(run.stdout)
    assert report["answer"] == "exists" and report["one_mover"] == "witness"
    assert report["one_robot"] == "witness"
    assert report["checker"]["verdicts"] == ["VERIFIED"]
    run = cli("--world", "ring:5", "--robots", "2", "--no-one-mover", *common)
    report = json.loads(run.stdout)
    assert report["answer"] == "none" and report["one_mover"] is report["one_robot"] is None


@pytest.mark.parametrize("n", [9, pytest.param(11, marks=pytest.mark.slow),
                               pytest.param(12, marks=pytest.mark.slow)])
def test_lamani_s_five_robots_explore_and_stop_under_async(n: int, tmp_path: Path) -> None:
    """Lamani, Potop-Butucaru and Tixeuil's five robots on a ring whose size is coprime with
    5: the first step finds an algorithm for every start under ASYNC, and the checker, every
    reduction off, verifies it (docs/rings-results.md)."""
    from tests.test_synthesis import cli

    run = cli("--world", f"ring:{n}", "--robots", "5", "--task", "exploration-with-stop",
              "--multiplicity", "global-weak", "--scheduler", "async", "--json", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    report = json.loads(run.stdout)
    assert report["answer"] == "exists" and report["one_robot"] == "witness"
    assert report["checker"]["verdicts"] == ["VERIFIED"]


@pytest.mark.parametrize("world", [["--world", "rendezvous", "--lights", "1"],
                                   ["--world", "grid", "--robots", "0,0 2,1", "--meeting", "1,1"],
                                   ["--world", "grid", "--box", "2x2", "--robots", "2",
                                    "--meeting", "1", "--minimum"]])
def test_one_mover_is_refused_where_no_search_has_it(world: list[str]) -> None:
    """The rendezvous world and the infinite grid have no first phase: the flag is an error
    there (one line, exit 2), not silently ignored."""
    from tests.test_synthesis import cli, one_line

    run = cli(*world, "--scheduler", "fsync", "--one-mover")
    assert run.returncode == 2 and "--one-mover" in one_line(run)


def _solves(inst, views: Views, table: dict[int, int], scheduler: str) -> tuple[bool, ...]:
    """Per start: whether ``table`` (its unmet views staying) solves the task under
    ``scheduler``."""
    out = []
    for idx in range(len(inst.configurations)):
        s, findings = S.explore(S.replace(inst, scheduler=scheduler), views, S.Table(table),
                                idx, set(), Limits(max_states=200_000, max_seconds=60))
        assert s.stopped is None
        out.append(not findings)
    return tuple(out)


def _verdicts(task: str, step: str, share: float
              ) -> list[tuple[tuple[bool, ...], tuple[bool, ...]]]:
    """Per candidate of the first phase's ``step`` (``task``, 3 robots, ring:7): its
    answers from every start under FSYNC and under ASYNC."""
    inst = _instance(("ring:7", "3", "async", task))
    views = Views(inst)
    got: list[tuple[tuple[bool, ...], tuple[bool, ...]]] = []
    judge = S._Search.judge

    def spy(self: S._Search, choice: dict[int, int], reached: set[int]):
        if next(iter(self.gates), None) == step:
            table = dict(choice)
            got.append((_solves(inst, views, table, "fsync"),
                        _solves(inst, views, table, "async")))
        return judge(self, choice, reached)

    with mock.patch.object(S._Search, "judge", spy), \
            mock.patch.object(S, "ONE_ROBOT_SHARE", share):
        S.synthesize(inst, views=views, max_seconds=60, one_mover=True)
    return got


def test_a_first_step_candidate_answers_alike_under_fsync_and_async() -> None:
    """When one robot moves per configuration the robots act one at a time whatever the
    adversary: every candidate of the first step solves the task from a start under ASYNC
    exactly when it does under FSYNC. The second step's candidates (twins may move) do not
    (the check bites)."""
    first = _verdicts("gathering", "one robot", S.ONE_ROBOT_SHARE)
    assert len(first) > 3 and any(all(f) for f, _ in first) and not all(all(f) for f, _ in first)
    assert all(f == a for f, a in first)
    second = _verdicts("exclusive-perpetual-exploration", "one class", 0.0)
    assert any(f != a for f, a in second)


def test_the_first_step_proposes_only_tables_where_one_robot_moves() -> None:
    """A view two robots of its configuration hold (twins, a tower) stays in every candidate
    of the first step, and the search meets such views."""
    inst = _instance(("ring:7", "3", "async", "exclusive-perpetual-exploration"))
    views = Views(inst)
    seen: list[int] = []
    judge = S._Search.judge

    def spy(self: S._Search, choice: dict[int, int], reached: set[int]):
        if "one robot" in self.gates:
            crowded = views.crowded[:self.crowded_done]
            assert all(choice[k] in views.still[k] for k in crowded)
            seen.append(len(crowded))
        return judge(self, choice, reached)

    with mock.patch.object(S._Search, "judge", spy):
        got = S.synthesize(inst, views=views, max_seconds=60, one_mover=True)
    assert got.answer == "none" and got.one_robot == "exhausted"
    assert seen and max(seen) >= 1


def _random_table(views: Views, seed: int, crowded_move: bool) -> S.Table:
    """A random table, decided configuration by configuration as the exploration meets
    them: at most one view of each moves (one robot; with ``crowded_move``, the view may be
    one that twins or a tower hold, so several robots move)."""
    decided: dict[int, int] = {}

    def fresh(k: int) -> int:
        if k not in decided:
            _, seen, _, _ = views.first[k]
            held = Counter(views.occurrence(seen, v, c)[0] for v, c in seen)
            keys = sorted(held)
            rng = random.Random(f"{seed}:{[views.texts[j] for j in keys]}")
            movers = [j for j in keys if crowded_move or held[j] == 1]
            mover = rng.choice(movers) if movers and rng.random() < 0.9 else None
            for j in keys:
                moves = [o for o in range(len(views.options[j])) if o not in views.still[j]]
                decided[j] = (rng.choice(moves) if j == mover and moves
                              else views.still[j][0])
        return decided[k]

    return S.Table({}, fresh)


RANDOM_CASES = [("ring:6", "3", "gathering"), ("ring:7", "3", "gathering"),
                ("ring:7", "4", "gathering"), ("ring:8", "4", "exploration-with-stop"),
                ("ring:9", "5", "exploration-with-stop")]


def _moves(case: tuple[str, str, str], seed: int, crowded_move: bool, scheduler: str
           ) -> list[set[tuple[tuple[int, ...], tuple[int, ...]]]]:
    """Per start, the moves between configurations (the robots' nodes, as sets with
    repetition) of every execution of a random table under ``scheduler``; a configuration
    where no robot moves any more steps to itself."""
    from gather_verify.engine.world_search import search

    world, robots, task = case
    inst = _instance((world, robots, scheduler, task))
    views = Views(inst)
    table = _random_table(views, seed, crowded_move)

    def actions(state):  # noqa: ANN001, ANN202
        return [acts[table[k]] for k, acts in views.robots(state)]

    out = []
    for start, colours in inst.configurations:
        s = search(inst.world, start, actions, scheduler, colours=colours,
                   limits=Limits(max_states=200_000, max_seconds=60))
        assert s.stopped is None
        nodes = [tuple(sorted(v for v, _, _ in robots)) for robots, _, _ in s.keys]
        steps = {(nodes[a], nodes[b]) for a, edges in enumerate(s.edges)
                 for b, _, _ in edges if nodes[a] != nodes[b]}
        steps |= {(nodes[a], nodes[a]) for a in range(len(nodes)) if s.final[a]}
        out.append(steps)
    return out


@settings(max_examples=25, deadline=None)
@given(case=st.sampled_from(RANDOM_CASES), seed=st.integers(0, 10**6))
def test_a_random_one_robot_table_moves_alike_under_fsync_and_async(
        case: tuple[str, str, str], seed: int) -> None:
    """Any table in which at most one robot moves per configuration (not only the search's
    candidates) makes the same moves between configurations, and ends in the same ones,
    under ASYNC as under FSYNC, from every start: its executions are the FSYNC ones with
    pauses, so it solves a task under one exactly when it does under the other."""
    assert _moves(case, seed, False, "async") == _moves(case, seed, False, "fsync")


def test_random_tables_where_twins_move_do_not_move_alike() -> None:
    """The property above needs the restriction: let a view that two robots hold move, and
    some random table makes moves under ASYNC that it never makes under FSYNC."""
    assert any(_moves(case, seed, True, "async") != _moves(case, seed, True, "fsync")
               for case in RANDOM_CASES[:3] for seed in range(5))
