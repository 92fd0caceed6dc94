"""The text outputs are for people: no Python or JSON leaks into them (``None``, ``null``,
a raw dict of settings). Each command runs on small inputs through every kind of outcome;
``--json`` is the place for ``null``."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from gather_verify.cli import main

ROOT = Path(__file__).resolve().parent.parent
LEAK = re.compile(r"\bNone\b|\bnull\b|\{'|\{\"")
TWO = ["--robots", "0,0 3,1", "--meeting", "2,2"]
LIVELOCK = str(ROOT / "scenarios" / "algorithm" / "i22-livelock-guard-on-axis-of-M.json")


def _text(capsys: pytest.CaptureFixture[str], *argv: str) -> str:
    main(list(argv))
    got = capsys.readouterr()
    text = got.out + got.err
    leak = LEAK.search(text)
    assert leak is None, (f"gather-verify {' '.join(argv)} printed {leak.group()!r}:\n"
                          f"{text[max(0, leak.start() - 300):leak.end() + 100]}")
    return text


CHECKS = {
    "verified": [*TWO, "--algorithm", "go-to-target", "--scheduler", "async"],
    "incomplete": [*TWO, "--algorithm", "go-to-target", "--max-states", "3"],
    "not-applicable": ["--robots", "0,0 2,0", "--meeting", "1,1 1,-1", "--algorithm", "paper"],
    "livelock": [LIVELOCK, "--scheduler", "fsync"],
    "walk-away": [*TWO, "--algorithm", "broken-away", "--scheduler", "fsync"],
    "crash": [*TWO, "--algorithm", "broken-crash", "--scheduler", "async"],
    "undefined": [*TWO, "--algorithm", "broken-undefined", "--scheduler", "ssync"],
    "target": [*TWO, "--algorithm", "broken-drift", "--scheduler", "async",
               "--property", "target-invariance"],
    "readings": [*TWO, "--algorithm", "paper", "--readings", "alpha"],
    "world": ["--world", "ring:6", "--robots", "0 3", "--algorithm", "ring-gather",
              "--scheduler", "fsync", "--multiplicity", "global-strong"],
    "world-incomplete": ["--world", "ring:5", "--robots", "0 1", "--meeting", "3",
                         "--algorithm", "go-to-target", "--max-states", "5"],
}


@pytest.mark.parametrize("case", list(CHECKS))
def test_check_prints_no_none_or_null(case: str, capsys: pytest.CaptureFixture[str]) -> None:
    _text(capsys, "check", *CHECKS[case])


def test_a_scenario_expectation_of_moves_unmet_prints_no_none(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    scenario = json.loads(Path(LIVELOCK).read_text())
    scenario["expect"]["verdicts"] = [{"algorithm": "paper", "scheduler": "fsync",
                                       "verdict": "VIOLATED", "property": "termination",
                                       "max_moves": 3}]
    path = tmp_path / "moves.json"
    path.write_text(json.dumps(scenario))
    assert "got no move count" in _text(capsys, "check", str(path))
    assert "got no move count" in _text(capsys, "test", str(path))


def test_simulate_and_replay_print_no_none_or_null(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    for algorithm in ("go-to-target", "broken-stay", "broken-undefined", "broken-crash"):
        _text(capsys, "simulate", *TWO, "--algorithm", algorithm, "--max-steps", "40")
    for name, argv in (("stay", [*TWO, "--algorithm", "broken-stay"]),
                       ("live", CHECKS["livelock"]), ("away", CHECKS["walk-away"])):
        trace = tmp_path / f"{name}.json"
        _text(capsys, "check", *argv, "--trace-out", str(trace))
        assert "CONFIRMED" in _text(capsys, "replay", str(trace))


def test_sweep_and_report_print_no_none_or_null(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    db = str(tmp_path / "r.sqlite")
    _text(capsys, "sweep", "--robots", "2", "--meeting", "1", "--box", "3x3",
          "--algorithm", "broken-away", "--scheduler", "fsync", "--db", db)
    _text(capsys, "sweep", "--world", "ring:5", "--robots", "2", "--meeting", "0",
          "--algorithm", "ring-gather", "--scheduler", "fsync", "--db", db)
    report = _text(capsys, "report", "--db", db, "--workers-curve", "1,2")
    assert "box=3x3" in report and "properties=all" in report  # a setting reads as text
    assert "visibility=unlimited" in report


def test_pictures_of_a_verdict_without_counterexample_are_not_written_and_it_says_so(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    files = [tmp_path / name for name in ("v.html", "v.svg", "t.json")]
    code = main(["check", *CHECKS["verified"], "--html", str(files[0]), "--svg", str(files[1]),
                 "--trace-out", str(files[2])])
    err = capsys.readouterr().err
    assert code == 0 and not any(f.exists() for f in files)
    assert "VERIFIED has no counterexample trace" in err and "not written" in err
    assert all(str(f) in err for f in files)
