"""Theorem 1 as a check: the adversary keeps U ungathered, and the check can fail."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gather_verify.algorithms.go_to_target import nearest, step_towards
from gather_verify.algorithms.moves import move_set
from gather_verify.algorithms.random_equivariant import RandomEquivariant
from gather_verify.cli import main
from gather_verify.cli.impossibility import algorithms_for
from gather_verify.model import geometry
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import ORIGIN, Node
from gather_verify.model.view import View
from gather_verify.paper.impossibility import (
    AdversaryError,
    check_impossibility,
    in_v_prime,
    symmetry_defect,
)
from gather_verify.scenario import load_scenario

ROOT = Path(__file__).resolve().parent.parent
SCENARIOS = sorted((ROOT / "scenarios" / "impossibility").glob("*.json"))
EDGE_CENTRE = ROOT / "scenarios" / "impossibility" / "i42-edge-centre-180.json"


def algorithms(k: int, seed: int = 0) -> list:
    """``k`` random equivariant algorithms, and the paper's once it is registered."""
    return algorithms_for(k, seed)[0]


class JoinNeighbour:
    """Walks to the nearest meeting node; on a meeting node, joins the robot on the
    neighbouring meeting node in its own +x direction, else stays. Its move set on a
    meeting node is {stay, join}: a symmetric adversary makes both stay or both swap,
    an adversary that lets one orbit split lets one join the other."""

    name = "join-neighbour"

    def decide(self, view: View) -> Node:
        if ORIGIN in view.meeting_nodes:
            east = (1, 0)
            return east if east in view.meeting_nodes and east in view.robots else ORIGIN
        target = nearest(view.meeting_nodes, ORIGIN)
        return ORIGIN if target is None else step_towards(target)


class CompassOnly:
    """Go east: not equivariant once frames are restricted to the compass."""

    name = "east"

    def decide(self, view: View) -> Node:
        return (1, 0)


def test_scenarios_cover_both_kinds_and_every_centre():
    kinds = set()
    for path in SCENARIOS:
        s = load_scenario(str(path))
        r = check_impossibility(s.configuration, [], steps=1, beyond_u=True)
        assert r.class_name == s.expected_class
        phi = r.automorphism
        assert phi is not None
        kinds.add((r.class_name, phi.axis_through or phi.centre_kind, phi.order))
    assert {("I41", "nodes", 2), ("I41", "edges", 2), ("I42", "node", 4), ("I42", "node", 2),
            ("I42", "edge", 2), ("I42", "square", 4), ("I42", "square", 2)} <= kinds


@pytest.mark.parametrize("path", SCENARIOS, ids=lambda p: p.stem)
def test_theorem_holds_on_every_scenario(path):
    s = load_scenario(str(path))
    beyond_u = s.expected_class not in ("I41", "I42")  # Theorem 1 outside U (UNCLASSIFIED)
    r = check_impossibility(s.configuration, algorithms(3), steps=4, max_states=150,
                            beyond_u=beyond_u)
    assert r.partitive and r.class_name == s.expected_class
    assert r.runs and all(run.rounds >= 1 for run in r.runs)
    assert r.holds, json.dumps([run.to_json() for run in r.failures])[:2000]
    assert not r.gathered
    r = check_impossibility(s.configuration, algorithms(2, seed=7), steps=25, explore="random",
                            beyond_u=beyond_u)
    assert r.holds and all(run.rounds >= 1 for run in r.runs)


def test_v_prime_matches_the_paper():
    phi = check_impossibility(load_scenario(str(EDGE_CENTRE)).configuration, [], steps=1)
    assert not any(in_v_prime(phi.automorphism, (x, y)) for x in range(-5, 6) for y in range(-5, 6))
    nodes = load_scenario(str(ROOT / "scenarios/impossibility/i41-vertical-axis-through-nodes.json"))
    phi = check_impossibility(nodes.configuration, [], steps=1).automorphism
    assert [v for v in [(1, 0), (1, 7), (0, 0), (2, 3)] if in_v_prime(phi, v)] == [(1, 0), (1, 7)]
    centre = load_scenario(str(ROOT / "scenarios/impossibility/i42-node-centre-90.json"))
    phi = check_impossibility(centre.configuration, [], steps=1).automorphism
    assert phi.order == 4
    assert [v for v in [(0, 0), (1, 0), (1, 1)] if in_v_prime(phi, v)] == [(0, 0)]


@pytest.mark.parametrize(
    "robots, meeting, name",
    [([(0, 0), (3, 1), (1, 4)], [(2, 2)], "I13"),
     ([(0, 1), (2, 1)], [(0, 0), (2, 0), (1, 1), (1, -1)], "UNCLASSIFIED"),  # axis: meeting
     ([(0, 1)], [(0, 0), (3, 0), (1, 1), (2, 1)], "I21")],
)
def test_outside_U_is_not_partitive(robots, meeting, name):
    r = check_impossibility(Configuration(robots, meeting, initial=True), algorithms(2))
    assert (r.partitive, r.class_name, r.runs, r.holds) == (False, name, [], False)
    assert r.to_json()["partitive"] is False


def test_theorem_1_beyond_U_on_an_unclassified_configuration():
    c = Configuration([(0, 1), (2, 1)], [(0, 0), (2, 0)], initial=True)
    assert check_impossibility(c, [], steps=1).partitive  # in U as §3.2 describes it
    r = check_impossibility(c, algorithms(3), steps=4, max_states=150, beyond_u=True)
    assert r.class_name == "UNCLASSIFIED" and r.partitive and r.holds
    assert r.automorphism.describe() == "reflection, vertical axis x = 1 through nodes"
    with_robot_on_axis = Configuration([(0, 1), (2, 1), (1, 1)], [(0, 0), (2, 0)], initial=True)
    assert not check_impossibility(with_robot_on_axis, [], beyond_u=True).partitive


def test_symmetric_adversary_never_gathers_join_neighbour():
    c = load_scenario(str(EDGE_CENTRE)).configuration
    r = check_impossibility(c, [JoinNeighbour()], steps=50)
    run = r.runs[0]
    assert r.holds and run.complete and run.repeated  # closed: every run loops forever
    assert run.states == 2  # start; both on meeting nodes (swapping gives the same)


def test_broken_adversary_makes_the_check_fail_by_gathering():
    c = load_scenario(str(EDGE_CENTRE)).configuration
    r = check_impossibility(c, [JoinNeighbour()], steps=50, split_orbit=True)
    run = r.runs[0]
    assert not r.holds and r.gathered and run.gathered
    last = Configuration([tuple(v) for v in run.trace[-1]["configuration"]["robots"]],
                         [tuple(v) for v in run.trace[-1]["configuration"]["meeting_nodes"]])
    assert last.is_gathered
    assert [step["round"] for step in run.trace] == list(range(len(run.trace)))
    assert all("moves" in step for step in run.trace[:-1])


def test_broken_adversary_makes_the_check_fail_by_losing_symmetry():
    for path in SCENARIOS:
        c = load_scenario(str(path)).configuration
        r = check_impossibility(c, algorithms(3), steps=4, max_states=150, split_orbit=True,
                                beyond_u=True)
        assert not r.holds, path.stem
        assert any(not run.symmetry_kept or run.gathered for run in r.runs)


def test_symmetry_defect_names_the_problem():
    c = load_scenario(str(EDGE_CENTRE)).configuration
    phi = check_impossibility(c, [], steps=1).automorphism
    assert symmetry_defect(phi, c) is None
    assert "robots" in symmetry_defect(phi, c.moved([((0, 1), (0, 2))]))
    centre = load_scenario(str(ROOT / "scenarios/impossibility/i42-node-centre-180.json"))
    phi = check_impossibility(centre.configuration, [], steps=1).automorphism
    one_on_centre = Configuration([(0, 0), (2, 2), (-2, -2)], [(1, 0), (-1, 0)])
    assert "V'" in symmetry_defect(phi, one_on_centre)


def test_non_equivariant_move_sets_are_reported_loudly():
    c = load_scenario(str(EDGE_CENTRE)).configuration
    with pytest.raises(AdversaryError, match="not equivariant"):
        check_impossibility(c, [CompassOnly()], frames=(geometry.IDENTITY,))


def test_same_seed_same_json():
    c = load_scenario(str(EDGE_CENTRE)).configuration
    for explore in ("all", "random"):
        a = check_impossibility(c, algorithms(2, 5), steps=6, explore=explore, seed=3).to_json()
        b = check_impossibility(c, algorithms(2, 5), steps=6, explore=explore, seed=3).to_json()
        assert a == b


def test_json_is_the_same_across_hash_seeds():
    outs = []
    for hash_seed in ("1", "2"):
        env = {**os.environ, "PYTHONHASHSEED": hash_seed}
        done = subprocess.run(
            [sys.executable, "-m", "gather_verify", "impossibility", str(EDGE_CENTRE),
             "--algorithms", "2", "--steps", "3", "--explore", "random", "--json"],
            capture_output=True, text=True, env=env, cwd=ROOT, check=False)
        assert done.returncode == 0, done.stderr
        outs.append(json.loads(done.stdout))
    assert outs[0] == outs[1]


def test_cli_exit_codes(capsys):
    assert main(["impossibility", str(EDGE_CENTRE), "--algorithms", "2", "--steps", "3"]) == 0
    assert main(["impossibility", "--robots", "0,0 3,1 1,4", "--meeting", "2,2", "--json"]) == 4
    assert json.loads(capsys.readouterr().out.splitlines()[-1])["class"] == "I13"
    assert main(["impossibility", str(EDGE_CENTRE), "--split-orbit", "--algorithms", "1"]) == 1
    assert "the run:" in capsys.readouterr().out
    assert main(["impossibility", str(EDGE_CENTRE), "--steps", "0"]) == 2
    assert main(["impossibility", "--robots", "0,0 0,0", "--meeting", "1,1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 2 and "Traceback" not in err


# -- equivariance of move sets (the adversary relies on it) ----------------------------

nodes = st.tuples(st.integers(-3, 3), st.integers(-3, 3))


@settings(max_examples=60, deadline=None)
@given(robots=st.lists(nodes, min_size=1, max_size=4), meeting=st.sets(nodes, min_size=1, max_size=3),
       seed=st.integers(0, 1000), g=st.integers(0, 7), t=nodes,
       detection=st.sampled_from(["none", "local-weak", "local-strong", "global-weak", "global-strong"]))
def test_move_sets_are_equivariant(robots, meeting, seed, g, t, detection):
    algorithm = RandomEquivariant(seed)
    c = Configuration(robots, meeting)
    image = c.transformed(g, t)

    def psi(v: Node) -> Node:
        return geometry.add(geometry.apply(g, v), t)

    for v in c.counts:
        assert move_set(algorithm, image, psi(v), detection) == {
            psi(u) for u in move_set(algorithm, c, v, detection)}


def test_random_algorithm_is_stable():
    c = Configuration([(0, 1), (1, -1)], [(0, 0), (1, 0)])
    answers = [RandomEquivariant(s).decide(View(c, (0, 1), 0, "local-weak")) for s in range(40)]
    assert set(answers) == {ORIGIN, *geometry.STEPS}  # all five moves occur
    assert answers == [RandomEquivariant(s).decide(View(c, (0, 1), 0, "local-weak"))
                       for s in range(40)]
    with pytest.raises(ValueError, match="bad seed"):
        RandomEquivariant("x")


# -- the measurement: every U configuration of the census ---------------------------------


def census_U(explore: str, steps: int, max_states: int,
             beyond_u: bool = False) -> tuple[dict, dict, str]:
    """Play the adversary on every U configuration of the census (n <= 4, m <= 4, 4 x 4 box)
    against K = 20 random algorithms and the paper's; a one-line summary. With
    ``beyond_u``: on every UNCLASSIFIED one that meets Theorem 1's hypothesis instead."""
    from collections import Counter

    from gather_verify.paper.classes import classify_configuration
    from gather_verify.sweeps.census import enumerate_configurations

    start, classes, stats = time.perf_counter(), Counter(), Counter()
    for n in range(1, 5):
        for m in range(1, 5):
            for c in enumerate_configurations(n, m, 4, 4):
                name = classify_configuration(c).name
                if (name != "UNCLASSIFIED") if beyond_u else (name not in ("I41", "I42")):
                    continue
                r = check_impossibility(c, algorithms(20), steps=steps, explore=explore,
                                        max_states=max_states, seed=sum(classes.values()),
                                        beyond_u=beyond_u)
                if not r.partitive:
                    classes["UNCLASSIFIED without"] += 1
                    continue
                assert r.holds, json.dumps(r.to_json())[:3000]
                classes[r.class_name] += 1
                for run in r.runs:
                    stats["runs"] += 1
                    stats["closed/repeated"] += run.repeated
                    stats["states"] += run.states
                    stats["paper unhandled"] += run.algorithm == "paper" and run.unhandled > 0
    return dict(classes), dict(stats), (f"{explore}: {dict(classes)} configurations, "
                                        f"{dict(stats)}, {time.perf_counter() - start:.0f} s")


U_CENSUS = {"I41": 252, "I42": 635}
"""The I41 and I42 configurations of the census n <= 4, m <= 4 in a 4 x 4 box."""


def _assert_every_U_configuration_held(classes: dict, stats: dict, expected: dict) -> None:
    """Each configuration was played (and held: ``census_U`` asserts it per run) against the
    paper's algorithm and 20 random ones."""
    assert classes == expected
    partitive = sum(v for k, v in classes.items() if k != "UNCLASSIFIED without")
    assert stats["runs"] == 21 * partitive


@pytest.mark.slow
def test_census_U_random_adversary():
    classes, stats, text = census_U("random", steps=30, max_states=0)
    print("\n" + text)
    _assert_every_U_configuration_held(classes, stats, U_CENSUS)


@pytest.mark.slow
def test_census_U_every_choice():
    classes, stats, text = census_U("all", steps=3, max_states=60)
    print("\n" + text)
    _assert_every_U_configuration_held(classes, stats, U_CENSUS)


@pytest.mark.slow
def test_census_unclassified_meeting_theorem_1():
    classes, stats, text = census_U("random", steps=30, max_states=0, beyond_u=True)
    print("\n" + text)
    # 371 UNCLASSIFIED configurations are in U (an empty axis), 1,326 are not (findings, F1)
    _assert_every_U_configuration_held(classes, stats,
                                       {"UNCLASSIFIED": 371, "UNCLASSIFIED without": 1326})


def test_beyond_u_is_deprecated_with_a_warning(capsys):
    """``--beyond-u`` changes nothing since U follows §3.2: it says so rather than stay silent."""
    from gather_verify.cli import main

    scenario = "scenarios/impossibility/i42-edge-centre-180.json"
    argv = ["impossibility", scenario, "--algorithms", "1", "--steps", "2", "--json"]
    assert main(argv) == 0
    plain = capsys.readouterr()
    assert main([*argv, "--beyond-u"]) == 0
    flagged = capsys.readouterr()
    assert flagged.out == plain.out  # a no-op ...
    assert plain.err == ""  # ... that warns in one line on stderr, and only when given
    assert flagged.err.startswith("warning: --beyond-u is deprecated")
    assert flagged.err.count("\n") == 1 and flagged.err.endswith("\n")
