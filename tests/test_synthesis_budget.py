"""``synthesize --max-seconds`` holds everywhere: a SAT call that would run for minutes (a
pigeonhole formula, which CaDiCaL cannot refute in seconds and whose ``interrupt()`` it
ignores), an analysis of a candidate that never returns, and the checker's run on a witness
all end with ``unknown`` naming the time limit. No timed assertion: each budget is far too
short for the work it stops, so any answer but ``unknown`` (or a hang) is a failure."""

from __future__ import annotations

import time
from collections.abc import Callable
from itertools import combinations
from typing import Any

import pytest

pytest.importorskip("pysat", reason="synthesize needs python-sat (extra synth)")

from gather_verify.model.configuration import Configuration  # noqa: E402
from gather_verify.synthesis import plane, search  # noqa: E402
from gather_verify.synthesis.views import Views, make_instance  # noqa: E402

OFFSET = 100_000
"""The pigeonhole's variables start here, far from the table's: the table stays free, and
the whole formula is unsatisfiable only through the pigeonhole."""


def pigeonhole(pigeons: int, holes: int, offset: int = 0) -> list[list[int]]:
    """Every pigeon in a hole, no two in one: unsatisfiable when pigeons > holes, and
    exponential for resolution (CDCL solvers take minutes from 12 into 11)."""
    var = {(p, h): offset + p * holes + h + 1 for p in range(pigeons) for h in range(holes)}
    return ([[var[p, h] for h in range(holes)] for p in range(pigeons)]
            + [[-var[p, h], -var[q, h]] for h in range(holes)
               for p, q in combinations(range(pigeons), 2)])


def with_a_hard_formula(monkeypatch: pytest.MonkeyPatch) -> None:
    """Every solver the searches make starts with a 12-into-11 pigeonhole: its first call
    cannot end within the tests' budgets."""
    real = search.solver_class()

    def make(*args: Any, **kwargs: Any) -> Any:
        solver = real(*args, **kwargs)
        for clause in pigeonhole(12, 11, OFFSET):
            solver.add_clause(clause)
        return solver

    monkeypatch.setattr(search, "solver_class", lambda: make)


def test_solve_within_answers_an_easy_formula_and_stops_a_hard_one() -> None:
    solver = search.solver_class()(name="cadical153", bootstrap_with=pigeonhole(4, 3))
    assert search.solve_within(solver, time.perf_counter() + 60) is False
    solver.delete()
    solver = search.solver_class()(name="cadical153", bootstrap_with=pigeonhole(3, 3))
    assert search.solve_within(solver, time.perf_counter() + 60) is True
    solver.delete()
    solver = search.solver_class()(name="cadical153", bootstrap_with=pigeonhole(12, 11))
    assert search.solve_within(solver, time.perf_counter() + 0.5) is None
    solver.delete()


EASY = ("0,0 2,1", "1,1")  # I13: the seed gathers from it, one candidate (docs/synthesis.md)


def _plane_search(max_seconds: float) -> plane.SearchResult:
    inst = plane.make_instance(*EASY, "async", None, "local-weak", "all")
    views = plane.PlaneViews(inst.detection, inst.frames)
    return plane.search_algorithm(inst.configurations, inst, views, max_seconds=max_seconds,
                                  max_candidates=100, max_states=10**6)


def test_the_plane_search_is_easy_without_the_hard_formula() -> None:
    assert _plane_search(60).answer == "exists"


def test_a_long_sat_call_on_the_plane_is_stopped_within_the_budget(
        monkeypatch: pytest.MonkeyPatch) -> None:
    with_a_hard_formula(monkeypatch)
    found = _plane_search(1.0)
    assert found.answer == "unknown"
    assert found.limit == "max-seconds (during the SAT solver's call)"
    assert found.candidates == 0


def test_a_long_sat_call_on_a_finite_world_is_stopped_within_the_budget(
        monkeypatch: pytest.MonkeyPatch) -> None:
    inst = make_instance("ring:6", "0 2", "", "fsync", "gathering", "global-weak", "all",
                         None, None)
    assert search.synthesize(inst, max_seconds=60, views=Views(inst)).answer == "exists"
    with_a_hard_formula(monkeypatch)
    got = search.synthesize(inst, max_seconds=1.0, views=Views(inst))
    # the solver's slice or the watchdog's alarm, whichever comes first on a loaded machine:
    # either way the search stops at the budget and says unknown with the limit
    assert got.answer == "unknown"
    assert got.limit in ("max-seconds (during the SAT solver's call)",
                         "max-seconds (cut by the watchdog)")


def _endless(*args: Any, **kwargs: Any) -> dict[str, Any]:
    """A check of a candidate that never returns (as a graph analysis that does not read
    the clock would, on a large graph): pure Python, so the alarm can cut it."""
    while True:
        pass


@pytest.mark.parametrize("where", ["candidate", "witness"])
def test_an_endless_check_is_cut_by_the_watchdog(monkeypatch: pytest.MonkeyPatch,
                                                 where: str) -> None:
    import gather_verify.plane_check

    monkeypatch.setattr(gather_verify.plane_check, "run_check", _endless)
    if where == "candidate":
        found = _plane_search(0.5)
        assert (found.answer, found.limit) == ("unknown", "max-seconds (cut by the watchdog)")
    else:
        inst = plane.make_instance(*EASY, "async", None, "local-weak", "all")
        c: Configuration = inst.configurations[0]
        checked = plane.check_witness("unused.py:Synthesized", inst, c, 0.5)
        assert plane.out_of_time(checked)


def test_a_witness_checked_out_of_time_is_unknown_not_a_fault(tmp_path: Any) -> None:
    from tests.test_synthesis import cli

    run: Callable[..., Any] = cli
    done = run("--world", "grid", "--robots", EASY[0], "--meeting", EASY[1], "--scheduler",
               "async", "--witness", "w.py", "--json", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    inst = plane.make_instance(*EASY, "async", None, "local-weak", "all")
    checked = plane.check_witness(f"{tmp_path / 'w.py'}:Synthesized", inst,
                                  inst.configurations[0], 0.0)
    assert plane.out_of_time(checked)
    assert plane.check_witness(f"{tmp_path / 'w.py'}:Synthesized", inst,
                               inst.configurations[0], 60)["verdict"] == "VERIFIED"
