"""Every property fails on a deliberately broken algorithm, with a trace replay confirms."""

from __future__ import annotations

import pytest

from gather_verify.check import run_check
from gather_verify.model.configuration import Configuration as C
from gather_verify.properties import check_property_names
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
]


@pytest.mark.parametrize("reduction", [True, False])
@pytest.mark.parametrize("scheduler", ["fsync", "ssync", "async"])
@pytest.mark.parametrize("case", range(len(CASES)))
def test_property_fails_with_confirmed_trace(case, scheduler, reduction):
    algo, c, prop = CASES[case]
    r = run_check(c, algorithm=algo, scheduler=scheduler, max_states=10**5, max_seconds=60,
                  properties=None if prop == "defined" else [prop], reduction=reduction, margin=4)
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
