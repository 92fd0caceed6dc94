"""The scenario regression suite: every file under ``scenarios/`` is a test.

Each scenario records its expected class and, per algorithm and scheduler, the
expected verdict (with the failing property and, optionally, ``max_moves``).
The test classifies the configuration and runs the explorer; if the result
changes it fails and prints the new verdict and trace. A scenario that stores
a counterexample ``trace`` also has it replayed from scratch, so the finding it
backs is confirmed independently of the explorer.

Expectations with ``"options": {"slow": true}`` run only under ``-m slow``.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from gather_verify.paper.classes import classify_configuration
from gather_verify.scenario import load_scenario
from gather_verify.scenario_tests import run_expectation

ROOT = Path(__file__).resolve().parent.parent / "scenarios"
FILES = sorted(ROOT.rglob("*.json"))
def _id(path: Path) -> str:
    return str(path.relative_to(ROOT))


def _expectation_cases() -> list:
    cases = []
    for path in FILES:
        scenario = load_scenario(path)
        for i, expectation in enumerate(scenario.expectations):
            marks = [pytest.mark.slow] if expectation.options.get("slow") else []
            cases.append(pytest.param(
                path, i, marks=marks,
                id=f"{_id(path)}[{expectation.algorithm}/{expectation.scheduler}]",
            ))
    return cases


def test_scenarios_exist() -> None:
    assert len(FILES) >= 10, "the regression suite lost its scenario files"


PLANE = [p for p in FILES if load_scenario(p).world == "grid"]
"""Scenarios of the paper's world (those of finite worlds have no class)."""


@pytest.mark.parametrize("path", PLANE, ids=_id)
def test_scenario_loads_and_classifies(path: Path) -> None:
    scenario = load_scenario(path)
    assert scenario.expected_class is not None, f"{path} records no expect.class"
    found = classify_configuration(scenario.configuration)
    assert found.name == scenario.expected_class, (
        f"{path}: class {found.name} ({found.reason}), expected {scenario.expected_class}"
    )


@pytest.mark.parametrize(("path", "index"), _expectation_cases())
def test_scenario_verdict(path: Path, index: int) -> None:
    scenario = load_scenario(path)
    expectation = scenario.expectations[index]
    report = run_expectation(scenario, expectation)
    got = (report["verdict"], report.get("property"))
    want = (expectation.verdict, expectation.property)
    if got != want:
        from gather_verify.render import trace_text
        from gather_verify.world_check import render_world_trace

        trace = report.get("trace")
        shown = ("(no trace)" if not trace else render_world_trace(trace) if "world" in trace
                 else trace_text(trace))
        pytest.fail(f"{path}: {want} became {got}: {report.get('reason')}\n{shown}")
    if expectation.max_moves is not None:
        assert report["max_moves"] == expectation.max_moves


@pytest.mark.parametrize(
    "path", [p for p in FILES if load_scenario(p).trace is not None], ids=_id
)
def test_stored_counterexample_replays(path: Path) -> None:
    from gather_verify.replay import replay

    scenario = load_scenario(path)
    if scenario.world == "rendezvous":  # the rendezvous world's trace, by its own replay
        from gather_verify.rendezvous_check import replay_rendezvous

        done = replay_rendezvous(scenario.trace)
        assert done.confirmed, f"{path}: stored trace no longer confirmed: {done.message}"
        return
    outcome = replay(scenario.trace)
    assert outcome.confirmed, f"{path}: stored trace no longer confirmed: {outcome.reason}"
