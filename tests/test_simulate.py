"""The simulator and `gather-verify simulate`: reproducible, fair, and honest about outcomes."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from gather_verify.algorithms import REGISTRY, get_algorithm
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import manhattan
from gather_verify.paper import strings
from gather_verify.paper.classes import classify_configuration
from gather_verify.simulate import simulate

ROOT = Path(__file__).resolve().parent.parent
SCHEDULERS = ("fsync", "ssync", "async")
I1_SAMPLE = [  # (robots, meeting nodes), classes I11, I12, I13
    ([(0, 0), (4, 1), (2, 5)], [(1, 0), (3, 3), (0, 2)]),
    ([(0, 2), (3, 3), (-1, 0)], [(0, 0), (1, 1), (2, 0)]),
    ([(0, 3), (4, 0), (1, 1)], [(0, 0), (2, 0), (1, 0)]),
]


def gather(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "gather_verify", *args], capture_output=True,
                          text=True, cwd=ROOT, timeout=120)


@pytest.mark.parametrize("scheduler", SCHEDULERS)
def test_same_seed_same_run(scheduler):
    c = strings.from_string("001001400004000000000000404000400401000000100", 5)
    a = simulate(c, get_algorithm("paper"), scheduler, seed=5).to_json()
    b = simulate(c, get_algorithm("paper"), scheduler, seed=5).to_json()
    assert a == b


@pytest.mark.parametrize("scheduler", SCHEDULERS)
@pytest.mark.parametrize("robots, meeting", I1_SAMPLE)
def test_i1_gathers_on_the_target_with_the_sum_of_distances(scheduler, robots, meeting):
    c = Configuration(robots, meeting, initial=True)
    assert classify_configuration(c).name[:2] == "I1"
    algorithm = get_algorithm("paper:alpha=mer_f")
    target = algorithm.target(c)
    for seed in range(4):
        run = simulate(c, algorithm, scheduler, seed=seed)
        assert (run.outcome, run.meeting_node) == ("gathered", target)
        assert run.moves == sum(manhattan(r, target) for r in c.robots)


def test_asynchronous_runs_interleave_looks_and_moves():
    c = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)
    run = simulate(c, get_algorithm("go-to-target"), "async", seed=0)
    kinds = {e.kind for e in run.events}
    assert kinds == {"look", "move"} and run.moves == 9


def test_fairness_every_robot_moves_under_ssync():
    c = Configuration([(0, 0), (6, 0), (0, 6), (6, 6)], [(3, 3)], initial=True)
    for seed in range(5):
        run = simulate(c, get_algorithm("go-to-target"), "ssync", seed=seed)
        assert run.outcome == "gathered" and run.moves == 24


def test_unhandled_ends_the_run_with_the_message():
    c = Configuration([(0, 1), (2, 1)], [(0, 0), (2, 0), (0, 2), (2, 2)], initial=True)
    run = simulate(c, get_algorithm("paper"), "fsync")
    assert run.outcome == "unhandled" and "ungatherable" in run.message and not run.gathered


def test_deadlock_is_reported():
    c = Configuration([(0, 0), (4, 0)], [(2, 1), (2, -1)], initial=True)
    run = simulate(c, get_algorithm("nearest-centre"), "fsync")
    assert run.outcome == "deadlock" and run.steps == 0


def test_max_steps():
    c = Configuration([(0, 0)], [(9, 9)], initial=True)
    run = simulate(c, get_algorithm("go-to-target"), "fsync", max_steps=3)
    assert run.outcome == "max-steps" and run.steps == 3 and run.moves == 3


def test_cli_json():
    out = gather("simulate", "--robots", "0,0 3,1 1,4", "--meeting", "2,2", "--algorithm",
                 "go-to-target", "--scheduler", "ssync", "--seed", "2", "--json")
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    assert data["gathered"] is True and data["meeting_node"] == [2, 2]
    assert data["moves"] == 9 and data["steps"] == len(data["events"])


def test_cli_grids_and_unhandled():
    out = gather("simulate", "scenarios/classes/i41.json", "--scheduler", "fsync")
    assert out.returncode == 0, out.stderr
    assert "outcome: unhandled" in out.stdout
    out = gather("simulate", "--robots", "0,0 2,1", "--meeting", "2,2", "--scheduler", "fsync",
                 "--algorithm", "go-to-target")
    assert "step 0" in out.stdout and "[2]" in out.stdout


@pytest.mark.parametrize("args, word", [
    (["--robots", "0,0", "--meeting", "1,1", "--algorithm", "nope"], "nope"),
    (["--robots", "0,0", "--meeting", "1,1", "--multiplicity", "foo"], "foo"),
    (["--robots", "0,0 x", "--meeting", "1,1"], "x"),
    (["--robots", "0,0", "--meeting", "1,1", "--seed", "-1"], "seed"),
    (["--robots", "0,0"], "meeting"),
])
def test_cli_bad_input_one_line_exit_2(args, word):
    out = gather("simulate", *args)
    assert out.returncode == 2
    assert len(out.stderr.strip().splitlines()) == 1 and word in out.stderr


def test_docs_example_runs():
    text = (ROOT / "docs" / "algorithms.md").read_text()
    (code,) = re.findall(r"```python\n(.*?)```", text, re.S)
    namespace: dict = {}
    try:
        exec(compile(code, "docs/algorithms.md", "exec"), namespace)
    finally:
        REGISTRY.pop("nearest-mine", None)
    run = namespace["run"]  # the example's own run: it gathers where the page says it does
    assert (run.outcome, run.meeting_node, run.moves) == ("gathered", (2, 0), 6)


@pytest.mark.parametrize("name, seed, outcome, message", [
    ("i22-make-multiplicity-onto-guard", 1, "deadlock", ""),
    ("i22-two-robots-finalization-through-meeting-node", 0, "unhandled", "I42"),
    ("i32-symmetry-breaking-onto-meeting-node", 1, "unhandled", "I42"),
    ("i22-non-guard-as-far-as-guard", 1, "unhandled", "UNCLASSIFIED"),
    ("i21-diagonal-axis-guard-corner", 2, "unhandled", "guard placement"),
    ("i21-make-multiplicity-onto-guard", 1, "deadlock", ""),
    ("i31-symmetry-breaking-onto-robot", 0, "unhandled", "I41"),
])
def test_recorded_findings_reproduce(name, seed, outcome, message):
    """The paper's rules lead these I2/I3 configurations away from gathering (docs: findings)."""
    from gather_verify.scenario import load_scenario

    s = load_scenario(ROOT / "scenarios" / "algorithm" / f"{name}.json")
    run = simulate(s.configuration, get_algorithm(s.algorithm), s.scheduler, seed=seed)
    assert run.outcome == outcome and message in run.message


def test_finding_alpha_over_mer_moves_the_i11_target():
    from gather_verify.scenario import load_scenario

    c = load_scenario(ROOT / "scenarios/algorithm/i11-alpha-over-mer-target-moves.json").configuration
    assert get_algorithm("paper").target(c) == (2, 1)
    run = simulate(c, get_algorithm("paper"), "async", seed=0)
    assert run.gathered and run.meeting_node == (0, 0)
    run = simulate(c, get_algorithm("paper:alpha=mer_f"), "async", seed=0)
    assert run.meeting_node == get_algorithm("paper:alpha=mer_f").target(c)


def test_finding_livelock_when_the_guard_is_on_an_axis_of_M():
    from gather_verify.scenario import load_scenario

    s = load_scenario(ROOT / "scenarios/algorithm/i22-livelock-guard-on-axis-of-M.json")
    run = simulate(s.configuration, get_algorithm("paper"), "fsync", seed=0, max_steps=40)
    assert run.outcome == "max-steps"
    assert len({tuple(sorted(n for n, _ in st)) for st in run.states}) <= 6  # it cycles


def test_finding_alpha_over_mer_moves_the_i12_target():
    from gather_verify.scenario import load_scenario

    c = load_scenario(ROOT / "scenarios/algorithm/i12-alpha-over-mer-target-moves.json").configuration
    assert get_algorithm("paper").target(c) == (1, 1)
    assert simulate(c, get_algorithm("paper"), "fsync", seed=0).meeting_node == (3, 3)
    assert get_algorithm("paper:alpha=mer_f").target(c) == (3, 3)
    assert simulate(c, get_algorithm("paper:alpha=mer_f"), "fsync", seed=0).meeting_node == (3, 3)


@pytest.mark.slow
@pytest.mark.parametrize("scheduler", SCHEDULERS)
def test_census_i1_gathers_on_the_predicted_node(scheduler):
    """Every I1 configuration of 3 robots and 3 meeting nodes in a 3 x 3 box (paper:alpha=mer_f)."""
    from gather_verify.sweeps.census import enumerate_configurations

    algorithm = get_algorithm("paper:alpha=mer_f")
    checked = 0
    for c in enumerate_configurations(3, 3, 3, 3):
        if classify_configuration(c).name[:2] != "I1":
            continue
        target = algorithm.target(c)
        run = simulate(c, algorithm, scheduler, seed=checked)
        assert (run.meeting_node, run.moves) == (target, sum(manhattan(r, target)
                                                             for r in c.robots)), c
        checked += 1
    assert checked == 380 + 362 + 89  # I11, I12, I13 configurations of the census
