"""A check resolves its algorithm and scheduler once, at the edge, and the engines take the
objects: ``run_check`` loads an algorithm once however often the region grows, and the
engines handed objects never look a name up."""

from __future__ import annotations

from typing import Any

import pytest

import gather_verify.algorithms as algorithms
import schedulers
from gather_verify.algorithms import get_algorithm
from gather_verify.engine import explore as explore_module
from gather_verify.engine import fast_explore
from gather_verify.engine.search import explore
from gather_verify.model.configuration import Configuration
from gather_verify.plane_check import run_check
from gather_verify.world_check import run_world_check
from schedulers import get_scheduler

LONE = Configuration([(0, 0)], [(0, 1)], initial=True)  # broken-wander walks east for ever


def test_run_check_loads_the_algorithm_once(monkeypatch: pytest.MonkeyPatch) -> None:
    calls: list[Any] = []

    def counted(spec: Any) -> Any:
        calls.append(spec)
        return get_algorithm(spec)

    for module in (algorithms, explore_module, fast_explore):  # the engines resolve in explore
        monkeypatch.setattr(module, "get_algorithm", counted, raising=False)
    r = run_check(LONE, algorithm="broken-wander", scheduler="async", max_states=100_000,
                  max_seconds=600, properties=["final"])
    assert r["limits"]["margin"] == 32  # five searches, one region after another
    assert calls == ["broken-wander"]


@pytest.mark.parametrize("engine", ["fast", "reference"])
def test_engines_handed_objects_look_up_no_name(monkeypatch: pytest.MonkeyPatch,
                                                engine: str) -> None:
    algo, sched = get_algorithm("go-to-target"), get_scheduler("ssync")
    c = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)
    by_name = explore(c, "go-to-target", "ssync", engine=engine)

    def refused(name: Any) -> Any:
        raise AssertionError(f"looked up {name!r}")

    for module in (explore_module, fast_explore):  # the engines resolve in explore (resolve)
        monkeypatch.setattr(module, "get_algorithm", refused, raising=False)
    monkeypatch.setattr(schedulers, "get_scheduler", refused)
    e = explore(c, algo, sched, engine=engine)
    assert (e.states, e.transitions, e.scheduler_name) == (
        by_name.states, by_name.transitions, "ssync")


def test_world_check_resolves_the_scheduler_once(monkeypatch: pytest.MonkeyPatch) -> None:
    calls: list[str] = []

    def counted(name: str) -> Any:
        calls.append(name)
        return get_scheduler(name)

    monkeypatch.setattr(schedulers, "get_scheduler", counted)
    import gather_verify.world_check as wc

    monkeypatch.setattr(wc, "get_scheduler", counted)
    r = run_world_check("ring:6", "0 3", "1", "go-to-target", "async")
    assert r["states"] > 0 and r["scheduler"] == "async"
    assert calls == ["async"]
