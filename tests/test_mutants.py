"""Mutation testing: every deliberate bug is caught by the property it is expected to break.

``python -m tools.mutants`` runs the explorer on ``scenarios/mutants/`` against each
mutant of :mod:`tools.mutants`; the score must reach the goal and every
survivor must be an argued equivalent mutant.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from gather_verify.plane_check import run_check
from gather_verify.replay import replay
from gather_verify.scenario import parse_scenario
from tools.mutants import (
    GOAL,
    MUTANTS,
    Mutant,
    MutationSiteError,
    get_mutant,
    load_mutant_scenarios,
    main,
    register_mutants,
    run_mutants,
)


def test_at_least_twelve_named_and_described_mutants() -> None:
    assert len(MUTANTS) >= 12
    names = [m.name for m in MUTANTS]
    assert len(set(names)) == len(names)
    assert {m.baseline for m in MUTANTS} == {"paper:alpha=mer_f", "go-to-target"}
    for m in MUTANTS:
        assert m.name.startswith("mutant-") and m.description
        assert m.expected or m.equivalent, f"{m.name}: expected properties or an argument"


@pytest.mark.parametrize("mutant", MUTANTS, ids=lambda m: m.name)
def test_each_mutant_is_a_real_code_mutation(mutant: Mutant) -> None:
    """The mutated module differs from the original exactly at its sites, and builds."""
    algorithm = mutant.build()
    assert algorithm.name == mutant.name
    source = Path(mutant.module.__file__).read_text(encoding="utf-8")
    for old, new in mutant.edits:
        assert source.count(old) == 1 and old != new


def test_a_vanished_mutation_site_is_one_line_error() -> None:
    ghost = Mutant("mutant-ghost", "go-to-target", "no such code", (("no such code", "x"),), ())
    with pytest.raises(MutationSiteError, match="occurs 0 times"):
        ghost.build()


def test_mutants_command_catches_every_mutant_by_its_expected_property(
        capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["--json"])
    summary = json.loads(capsys.readouterr().out)
    assert code == 0
    assert summary["total"] == len(MUTANTS) and summary["score"] >= GOAL
    assert "seconds" not in summary  # reproducible output
    for m in summary["mutants"]:
        mutant = get_mutant(m["mutant"])
        if m["caught"]:
            assert set(mutant.expected) <= set(m["caught_by"]), m
            assert m["witness"]
        else:
            assert mutant.equivalent, f"{m['mutant']} survived without an argument"
    assert summary["survivors"] == summary["equivalent_survivors"]


def test_mutants_text_table(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["--mutant", "mutant-gtt-stops-one-short",
                 "--mutant", "mutant-paper-i11-first-of-O"])
    out = capsys.readouterr().out
    assert code == 1  # 1 of 2 is below the goal
    assert "mutant-gtt-stops-one-short" in out and "final" in out
    assert "SURVIVED (equivalent)" in out and "score 1/2" in out


def test_a_mutant_counterexample_replays() -> None:
    register_mutants()
    (scenario,) = [s for s in load_mutant_scenarios() if s.name == "mutants-gtt-two-meeting-nodes"]
    report = run_check(scenario.configuration, algorithm="mutant-gtt-stops-one-short",
                       scheduler="fsync", max_states=1000, max_seconds=60)
    assert report["verdict"] == "VIOLATED" and report["property"] == "final"
    assert replay(report["trace"]).confirmed


def test_a_scenario_whose_baseline_fails_is_refused() -> None:
    bad = parse_scenario({"robots": [[0, 0], [1, 1]], "meeting_nodes": [[0, 0], [2, 0]],
                          "algorithm": "go-to-target", "scheduler": "fsync",
                          "expect": {"verdicts": [{"verdict": "VERIFIED"}]}}, "tie.json")
    with pytest.raises(ValueError, match="not VERIFIED"):
        run_mutants([get_mutant("mutant-gtt-stops-one-short")], [bad])


def test_an_unknown_mutant_is_one_line_exit_2(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--mutant", "mutant-nope"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: unknown mutant 'mutant-nope'") and err.count("\n") == 1


def test_the_paper_keeps_no_function_that_exists_only_as_a_mutation_site() -> None:
    from gather_verify.paper import algorithm as paper

    assert not hasattr(paper, "_canonical_view")


def test_cli_passes_through_with_the_mutants_registered(tmp_path, capsys) -> None:
    trace = tmp_path / "t.json"
    args = ["cli", "check", "--robots", "0,0 3,1", "--meeting", "2,2", "--scheduler", "fsync",
            "--algorithm", "mutant-gtt-stops-one-short", "--trace-out", str(trace)]
    assert main(args) == 1
    assert "property final" in capsys.readouterr().out
    assert main(["cli", "replay", str(trace)]) == 1  # 1: the violation is confirmed
