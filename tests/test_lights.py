"""Luminous robots and the centralized and round-robin adversaries on finite worlds:
SEMANTICS.md §10's numbers, a naive BFS referee, lights that cannot leak, invariance under
the world's symmetries, and one line for each bad input."""

from __future__ import annotations

import itertools
import json
import subprocess
import sys
from collections import Counter

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gather_verify.errors import InvalidInput
from gather_verify.world_check import run_world_check
from gather_verify.worlds import get_world
from gather_verify.worlds.view import LightHidden, Lights, WorldView

CLI = [sys.executable, "-m", "gather_verify"]


def cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([*CLI, *args], capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize(("scheduler", "states", "transitions"),
                         [("fsync", 36, 90), ("ssync", 144, 756), ("async", 576, 1440)])
def test_bounce_counts_of_semantics_10(scheduler: str, states: int, transitions: int) -> None:
    run = cli("check", "--world", "ring:6", "--robots", "0 2", "--algorithm", "bounce",
              "--lights", "2", "--task", "gathering", "--scheduler", scheduler,
              "--no-reduction", "--json")
    report = json.loads(run.stdout)
    assert (report["states"], report["transitions"]) == (states, transitions), run.stderr


# -- an independent referee for the new adversaries ------------------------------------------

def naive(world_name: str, robots: tuple[int, ...], scheduler: str, lights: int,
          rule) -> tuple[int, int]:  # noqa: ANN001
    """States and transitions by a plain BFS from §4 and §10: ``rule(world, node, colour)`` is
    a robot's set of (destination, colour); centralized activates one robot, round-robin one
    robot per turn in an order fixed at the start (its state holds the order and the turn)."""
    w = get_world(world_name)
    n = len(robots)
    base = tuple((v, 0) for v in robots)
    if scheduler == "round-robin":
        starts = [(base, order, 0) for order in itertools.permutations(range(n))]
    else:
        starts = [(base, None, 0)]
    seen, queue, transitions = set(starts), list(starts), 0
    for robots_, order, turn in queue:
        who = range(n) if scheduler == "centralized" else [order[turn]]
        for i in who:
            v, c = robots_[i]
            for d, c2 in sorted(rule(w, v, c)):
                succ = robots_[:i] + ((d, c2),) + robots_[i + 1:]
                nxt = (succ, order, (turn + 1) % n if order else 0)
                if scheduler == "centralized" and succ == robots_:
                    continue
                transitions += 1
                if nxt not in seen:
                    seen.add(nxt)
                    queue.append(nxt)
    return len(seen), transitions


def bounce_rule(w, v: int, c: int) -> set[tuple[int, int]]:  # noqa: ANN001
    return {(v, 1)} if c == 0 else {(u, 0) for u in w.adjacency[v]}


@pytest.mark.parametrize("scheduler", ["centralized", "round-robin"])
@pytest.mark.parametrize("world_name", ["ring:6", "grid:2x3", "torus:3x3"])
def test_new_adversaries_agree_with_a_naive_bfs(scheduler: str, world_name: str) -> None:
    w = get_world(world_name)
    robots = (0, w.size - 1)
    got = run_world_check(w, list(robots), [], "bounce", scheduler, task="gathering",
                          lights="2", reduction=False)
    assert (got["states"], got["transitions"]) == naive(world_name, robots, scheduler, 2,
                                                         bounce_rule)


def test_yardstick_counts_of_the_new_adversaries() -> None:
    """The counts docs/worlds.md gives for go-to-target and bounce."""
    g = run_world_check("ring:9", "0 3 5", "7", "go-to-target", "centralized", reduction=False)
    r = run_world_check("ring:9", "0 3 5", "7", "go-to-target", "round-robin", reduction=False)
    b = run_world_check("ring:6", "0 2", "", "bounce", "centralized", task="gathering",
                        lights="2", reduction=False)
    assert (g["states"], g["transitions"], r["states"], r["transitions"]) == (45, 96, 84, 84)
    assert (b["states"], b["transitions"]) == (144, 432) == naive("ring:6", (0, 2),
                                                                   "centralized", 2, bounce_rule)


def test_a_round_robin_order_runs_that_order_only() -> None:
    every = run_world_check("ring:9", "0 3 5", "7", "go-to-target", "round-robin",
                            reduction=False)
    one = run_world_check("ring:9", "0 3 5", "7", "go-to-target", "round-robin:order=2 0 1",
                          reduction=False)
    assert one["verdict"] == every["verdict"] == "VERIFIED" and one["states"] < every["states"]


# -- lights cannot leak --------------------------------------------------------------------

def view(variant: str, detection: str = "global-weak") -> WorldView:
    w = get_world("ring:8")
    frame = w.frames(0, None, "all")[0]
    return WorldView(w, Counter({0: 2, 3: 1}), frozenset(), 0, frame, detection,
                     Lights(3, variant), {0: Counter({1: 1, 2: 1}), 3: Counter({0: 1})}, 1)


def test_full_lights_show_every_colour() -> None:
    v = view("full")
    assert v.light == 1 and v.colours() == {1, 2} and v.colours(3) == {0}


def test_external_lights_hide_the_robots_own_colour() -> None:
    v = view("external")
    with pytest.raises(LightHidden):
        v.light  # noqa: B018
    assert v.colours() == {2} and v.colours(3) == {0}


def test_internal_lights_hide_every_other_colour() -> None:
    v = view("internal")
    assert v.light == 1
    for node in (0, 3):
        with pytest.raises(LightHidden):
            v.colours(node)


def test_colour_counts_need_strong_detection() -> None:
    from gather_verify.model.view import MultiplicityHidden

    with pytest.raises(MultiplicityHidden):
        view("full").colour_counts(3)
    assert view("full", "global-strong").colour_counts() == {1: 1, 2: 1}


def test_an_algorithm_reading_a_hidden_light_has_no_rule() -> None:
    report = run_world_check("ring:6", "0 2", "", "bounce", "async", task="gathering",
                             lights="2:external")
    assert report["property"] == "defined" and "own colour" in report["reason"]


def test_a_colour_out_of_range_is_a_crash_with_a_trace() -> None:
    report = run_world_check("ring:6", "0 2", "", "bounce", "async", task="gathering")
    assert report["property"] == "crash" and "colours 0..0" in report["reason"]
    assert report["trace"]["steps"]


def test_an_oblivious_algorithm_keeps_working_with_lights() -> None:
    a = run_world_check("ring:9", "0 3 5", "7", "go-to-target", "async", reduction=False)
    b = run_world_check("ring:9", "0 3 5", "7", "go-to-target", "async", lights="3",
                        reduction=False)
    assert (a["verdict"], a["states"], a["transitions"]) == \
        (b["verdict"], b["states"], b["transitions"])


# -- invariance -----------------------------------------------------------------------------

@settings(max_examples=30, deadline=None)
@given(world_name=st.sampled_from(["ring:5", "ring:6", "torus:3x3"]), seed=st.integers(0, 10**6),
       scheduler=st.sampled_from(["fsync", "ssync", "async", "centralized", "round-robin"]))
def test_luminous_results_do_not_change_under_the_symmetries(world_name: str, seed: int,
                                                             scheduler: str) -> None:
    import random

    rnd = random.Random(seed)
    w = get_world(world_name)
    robots = rnd.sample(range(w.size), 2)
    colours = [rnd.randrange(2), rnd.randrange(2)]
    p = rnd.choice(w.symmetries("all"))
    algorithm = "ring-inchworm" if w.kind == "ring" else "bounce"
    task = "exclusive-perpetual-exploration" if w.kind == "ring" else "gathering"
    kw = {"task": task, "lights": "2", "colours": colours,
          "visibility": 2 if w.kind == "ring" else None}
    base = run_world_check(w, robots, [], algorithm, scheduler, **kw)
    moved = run_world_check(w, [p[v] for v in robots], [], algorithm, scheduler, **kw)
    for key in ("verdict", "property", "states", "transitions"):
        assert base[key] == moved[key], key


# -- the luminous ring algorithm and its broken twin --------------------------------------------

@pytest.mark.parametrize("scheduler", ["fsync", "ssync", "async", "centralized", "round-robin"])
def test_ring_inchworm_explores_and_its_twin_collides(scheduler: str) -> None:
    kw = {"task": "exclusive-perpetual-exploration", "lights": "2", "colours": [1, 0],
          "visibility": 2}
    good = run_world_check("ring:7", "0 1", "", "ring-inchworm", scheduler, **kw)
    assert good["verdict"] == "VERIFIED"
    bad = run_world_check("ring:7", "0 1", "", "broken-ring-inchworm", scheduler, **kw)
    if scheduler != "fsync":  # under FSYNC the tail always moves with the head
        assert bad["property"] == "exclusivity"


# -- bad input ------------------------------------------------------------------------------

@pytest.mark.parametrize(("args", "words"), [
    (("--lights", "0"), "[1, 64]"),
    (("--lights", "2:sideways"), "external or internal"),
    (("--lights", "2", "--colours", "0 2"), "0..1"),
    (("--lights", "2", "--colours", "0"), "one per robot"),
    (("--scheduler", "round-robin:order=0 5"), "each of the robots"),
    (("--scheduler", "round-robin:order=x"), "robot indices"),
    (("--scheduler", "fsync:order=1 0"), "only round-robin"),
])
def test_bad_lights_and_adversaries_are_one_line(args: tuple[str, ...], words: str) -> None:
    run = cli("check", "--world", "ring:6", "--robots", "0 2", "--algorithm", "bounce",
              "--task", "gathering", *args)
    assert run.returncode == 2 and words in run.stderr, run.stderr
    assert len(run.stderr.strip().splitlines()) == 1


def test_a_round_robin_order_naming_an_unknown_robot_on_the_plane_is_one_line() -> None:
    run = cli("check", "--robots", "0,0 3,1", "--meeting", "2,2", "--algorithm",
              "go-to-target", "--scheduler", "round-robin:order=0 5")
    assert run.returncode == 2 and "each of the robots 0..1" in run.stderr
    assert len(run.stderr.strip().splitlines()) == 1


def test_a_scenario_colour_outside_the_lights_is_one_line(tmp_path) -> None:  # noqa: ANN001
    path = tmp_path / "bad.scenario.json"
    path.write_text(json.dumps({"world": "ring:6", "robots": [0, 2], "meeting_nodes": [],
                                "lights": "2", "colours": [0, 3]}))
    run = cli("check", str(path))
    assert run.returncode == 2 and "'colours'" in run.stderr
    with pytest.raises(InvalidInput):
        run_world_check("ring:6", "0 2", "", "bounce", "async", lights="2", colours=[0, 3])


MEET = "docs/examples/lit_meet.py:Meet"


@pytest.mark.parametrize("scheduler", ["fsync", "ssync", "async"])
def test_the_docs_luminous_example_gathers_from_one_lit_robot_only(scheduler: str) -> None:
    """docs/examples/lit_meet.py, as docs/worlds.md runs it: one robot lit, it gathers under
    every scheduler; both unlit, the adversary makes them swap over the last edge and wait."""
    lit = run_world_check("ring:7", "0 3", "", MEET, scheduler, task="gathering", lights="2",
                          colours=[1, 0])
    assert lit["verdict"] == "VERIFIED", lit["properties"]
    dark = run_world_check("ring:7", "0 3", "", MEET, scheduler, task="gathering", lights="2")
    assert dark["verdict"] == "VIOLATED"
    assert dark["properties"]["gathered-when-final"]["holds"] is False


@pytest.mark.parametrize("scheduler", ["centralized", "round-robin"])
def test_the_docs_luminous_example_gathers_one_robot_at_a_time(scheduler: str) -> None:
    """One robot per activation: the two unlit robots never swap, so both colourings gather."""
    for colours in ([1, 0], [0, 0]):
        r = run_world_check("ring:7", "0 3", "", MEET, scheduler, task="gathering", lights="2",
                            colours=colours)
        assert r["verdict"] == "VERIFIED", (colours, r["properties"])
