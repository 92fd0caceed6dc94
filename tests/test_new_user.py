"""A new user with an algorithm of their own, in a folder outside the project.

They write an algorithm file (it imports a helper module next to it), check it from the
command line, sweep it with two workers and on a local Dask cluster, edit the helper and
sweep the same database again (the results change and equal a fresh database's), run a
crashing algorithm (property ``crash`` with a trace), write regression files and replay
them, and run ``gather-verify test`` and ``pytest`` on a scenario folder with and without
a wrong expectation. Everything goes through the installed console entry points, in a
temporary directory, as docs/algorithms.md tells it.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

ALGORITHM = '''\
"""Walk to the meeting node: along x first, then along y (in the robot's own frame)."""
from homeward_steps import step


class Homeward:
    name = "homeward"

    def __init__(self, patience="0"):
        self.patience = int(patience)

    def decide(self, view):
        (target,) = view.meeting_nodes  # one meeting node
        return step(target, self.patience)
'''
HELPER = '''\
def step(target, patience):
    x, y = target
    if x:
        return ((x > 0) - (x < 0), 0)
    return (0, (y > 0) - (y < 0))
'''
HELPER_EDITED = '''\
def step(target, patience):
    x, y = target
    if abs(x) + abs(y) == 1:  # "wait next to it": a deadlock when nobody moves
        return (0, 0)
    if x:
        return ((x > 0) - (x < 0), 0)
    return (0, (y > 0) - (y < 0))
'''
CRASHING = '''\
class Boom:
    name = "boom"

    def decide(self, view):
        if len(view.robots) == 1:  # everybody on one node: divide by the distance
            (x, y), = view.meeting_nodes
            return (1 // (abs(x) + abs(y) - abs(x) - abs(y)), 0)
        (x, y), = view.meeting_nodes
        return ((x > 0) - (x < 0), 0) if x else (0, (y > 0) - (y < 0))
'''


def gv(cwd: Path, *argv: str, timeout: float = 300) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONHASHSEED": "0"}
    return subprocess.run([sys.executable, "-m", "gather_verify", *argv], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=timeout, check=False)


def sweep(cwd: Path, db: str, *extra: str) -> dict:
    done = gv(cwd, "sweep", "--robots", "2", "--meeting", "1", "--box", "3x3", "--algorithm",
              "homeward.py:Homeward", "--scheduler", "async", "--db", db, "--json", *extra)
    assert done.returncode in (0, 1), done.stderr  # (Dask may warn on stderr: a busy port)
    assert "Traceback" not in done.stderr, done.stderr
    return json.loads(done.stdout)


def scenario(expect: dict) -> str:
    return json.dumps({"robots": [[0, 0], [2, 1]], "meeting_nodes": [[1, 1]],
                       "algorithm": "../homeward.py:Homeward", "scheduler": "async",
                       "expect": {"class": "I13", "verdicts": [expect]}})


def test_a_new_user_outside_the_repository(tmp_path: Path) -> None:
    home = tmp_path / "research"
    home.mkdir()
    assert not home.resolve().is_relative_to(ROOT)
    (home / "homeward.py").write_text(ALGORITHM)
    (home / "homeward_steps.py").write_text(HELPER)

    # check it from the command line
    done = gv(home, "check", "--robots", "0,0 2,1", "--meeting", "1,1", "--algorithm",
              "homeward.py:Homeward", "--scheduler", "async")
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.startswith("VERIFIED")

    # sweep it with two workers, and on a local Dask cluster: the same results
    first = sweep(home, "results.sqlite", "--workers", "2")
    assert first["verdicts"]["I13"] == {"VERIFIED": first["total"]} and first["total"] > 10
    on_dask = sweep(home, "dask.sqlite", "--dask", "local", "--workers", "2")
    assert on_dask == first

    # edit the helper it imports: the same database recomputes, as a fresh one would
    (home / "homeward_steps.py").write_text(HELPER_EDITED)
    again = sweep(home, "results.sqlite", "--workers", "2")
    fresh = sweep(home, "fresh.sqlite", "--workers", "2")
    assert again != first and again == fresh
    assert again["settings"]["fingerprint"] != first["settings"]["fingerprint"]
    assert again["failing_properties"]["I13"]["final"] > 0
    report = gv(home, "report", "--db", "results.sqlite")
    assert first["settings"]["fingerprint"] in report.stdout
    assert again["settings"]["fingerprint"] in report.stdout

    # the regression files of that sweep replay, and check says they match
    done = gv(home, "report", "--db", "fresh.sqlite", "--regressions", "out/regressions")
    files = sorted((home / "out" / "regressions").glob("*.scenario.json"))
    assert files, done.stderr
    written = json.loads(files[0].read_text())
    assert written["algorithm"] == "../../homeward.py:Homeward"
    assert f"gather-verify replay out/regressions/{files[0].name}" in written["description"]
    assert gv(home, "replay", str(files[0].relative_to(home)), "--quiet").returncode == 1
    assert gv(home, "check", str(files[0].relative_to(home))).returncode == 0
    # ... and run as tests from the project folder, by gather-verify and by pytest
    done = gv(home, "test", "out/regressions")
    assert done.returncode == 0, done.stdout + done.stderr
    done = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                           "out/regressions"], cwd=home, capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0 and f"{3 * len(files)} passed" in done.stdout, done.stdout  # class, verdict, replay
    # ... and after the fix, the trace no longer reproduces: exit 5
    (home / "homeward_steps.py").write_text(HELPER)
    done = gv(home, "replay", str(files[0].relative_to(home)), "--quiet")
    assert done.returncode == 5 and "NO LONGER REPRODUCES" in done.stdout

    # a crashing algorithm: property crash, with a trace, the view and the user's frame
    (home / "boom.py").write_text(CRASHING)
    done = gv(home, "check", "--robots", "0,0 2,0", "--meeting", "1,1", "--algorithm",
              "boom.py:Boom", "--scheduler", "fsync", "--trace-out", "boom.json")
    assert done.returncode == 1, done.stderr
    assert "property crash" in done.stdout and "ZeroDivisionError" in done.stdout
    assert "its view in its own frame" in done.stdout and "boom.py:7 in decide" in done.stdout
    trace = json.loads((home / "boom.json").read_text())
    assert trace["property"] == "crash" and len(trace["steps"]) > 0
    assert gv(home, "replay", "boom.json", "--quiet").returncode == 1
    done = gv(home, "sweep", "--robots", "2", "--meeting", "1", "--box", "3x3", "--algorithm",
              "boom.py:Boom", "--workers", "2", "--db", "boom.sqlite", "--json")
    summary = json.loads(done.stdout)
    assert done.returncode == 1 and summary["total"] == first["total"]
    assert summary["failing_properties"]["I13"]["crash"] > 0

    # scenario expectations as tests: one wrong expectation fails and is named
    folder = home / "scenarios"
    folder.mkdir()
    (folder / "good.scenario.json").write_text(scenario({"verdict": "VERIFIED"}))
    (folder / "wrong.scenario.json").write_text(
        scenario({"verdict": "VIOLATED", "property": "final"}))
    done = gv(home, "test", "scenarios", "--junit", "out/junit.xml")
    assert done.returncode == 1
    assert "FAIL scenarios/wrong.scenario.json" in done.stdout and "1 failed" in done.stdout
    assert "expected VIOLATED (final), got VERIFIED" in done.stdout
    assert "wrong.scenario.json" in (home / "out" / "junit.xml").read_text()
    pytest_run = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "scenarios"]
    done = subprocess.run(pytest_run, cwd=home, capture_output=True, text=True, timeout=300,
                          check=False)
    assert done.returncode == 1, done.stdout
    assert "wrong.scenario.json" in done.stdout and "expected VIOLATED (final)" in done.stdout
    assert "3 passed" in done.stdout and "1 failed" in done.stdout
    (folder / "wrong.scenario.json").unlink()
    assert gv(home, "test", "scenarios").returncode == 0
    done = subprocess.run(pytest_run, cwd=home, capture_output=True, text=True, timeout=300,
                          check=False)
    assert done.returncode == 0, done.stdout


@pytest.mark.parametrize("spec", ["homeward.py:Nope", "homeward.py:", "nope.py:Homeward"])
def test_bad_algorithm_specs_are_one_line_errors(tmp_path: Path, spec: str) -> None:
    (tmp_path / "homeward.py").write_text(ALGORITHM)
    (tmp_path / "homeward_steps.py").write_text(HELPER)
    done = gv(tmp_path, "check", "--robots", "0,0", "--meeting", "1,1", "--algorithm", spec)
    assert done.returncode == 2 and done.stderr.count("\n") == 1, done.stderr
