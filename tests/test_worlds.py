"""Finite worlds: SEMANTICS.md §9's numbers, an independent BFS as referee, invariance under
Aut(G), myopic views that leak nothing, and one line for every bad input."""

from __future__ import annotations

import itertools
import json
import subprocess
import sys
from collections import Counter
from pathlib import Path

import networkx as nx
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gather_verify.algorithms import get_algorithm
from gather_verify.engine.world_search import search
from gather_verify.errors import InvalidInput
from gather_verify.model.view import MultiplicityHidden
from gather_verify.world_check import run_world_check
from gather_verify.worlds import get_world
from gather_verify.worlds.moves import WorldMoves
from gather_verify.worlds.view import WorldView

CLI = [sys.executable, "-m", "gather_verify"]


def cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([*CLI, *args], capture_output=True, text=True, timeout=120)


# -- §9's test data ---------------------------------------------------------------------

@pytest.mark.parametrize(("scheduler", "states", "transitions"),
                         [("fsync", 5, 4), ("ssync", 45, 264), ("async", 225, 560)])
def test_ring9_go_to_target_counts_of_semantics_9(scheduler: str, states: int,
                                                 transitions: int) -> None:
    run = cli("check", "--world", "ring:9", "--robots", "0 3 5", "--meeting", "7",
              "--algorithm", "go-to-target", "--scheduler", scheduler, "--no-reduction",
              "--json")
    assert run.returncode == 0, run.stderr
    report = json.loads(run.stdout)
    assert (report["states"], report["transitions"]) == (states, transitions)
    assert report["verdict"] == "VERIFIED" and report["world"] == "ring:9"


# -- an independent referee ---------------------------------------------------------------

def naive_counts(world_name: str, robots: tuple[int, ...], meeting: int,
                 scheduler: str) -> tuple[int, int]:
    """States and transitions of go-to-target by a plain BFS written from §4 and §9 alone:
    networkx distances, move set = every neighbour strictly closer to m (stay on m), no
    reductions, a step that changes nothing is no transition."""
    w = get_world(world_name)
    g = w.graph
    dist = nx.single_source_shortest_path_length(g, meeting)

    def options(v: int) -> list[int]:
        if v == meeting:
            return [v]
        return sorted(u for u in g[v] if dist[u] < dist[v])

    start = tuple((v, None) for v in robots)
    seen, queue, transitions = {start}, [start], 0
    for state in queue:
        succs = []
        n = len(state)
        if scheduler == "async":
            for i, (v, p) in enumerate(state):
                if p is None:
                    succs += [state[:i] + ((v, d),) + state[i + 1:] for d in options(v) if d != v]
                else:
                    succs.append(state[:i] + ((p, None),) + state[i + 1:])
        else:
            subsets = [tuple(range(n))] if scheduler == "fsync" else [
                s for k in range(1, n + 1) for s in itertools.combinations(range(n), k)]
            for active in subsets:
                for choice in itertools.product(*(options(state[i][0]) for i in active)):
                    nodes = [v for v, _ in state]
                    for i, d in zip(active, choice, strict=True):
                        nodes[i] = d
                    succ = tuple((v, None) for v in nodes)
                    if succ != state:
                        succs.append(succ)
        for succ in succs:
            transitions += 1
            if succ not in seen:
                seen.add(succ)
                queue.append(succ)
    return len(seen), transitions


WORLDS = ["ring:7", "grid:3x3", "torus:3x4", "grid:2x4"]


@pytest.mark.parametrize("world_name", WORLDS)
@pytest.mark.parametrize("scheduler", ["fsync", "ssync", "async"])
def test_search_agrees_with_a_naive_bfs(world_name: str, scheduler: str) -> None:
    w = get_world(world_name)
    robots, meeting = (0, w.size // 2, w.size - 1), 1
    moves = WorldMoves(w, get_algorithm("go-to-target"), frozenset({meeting}))
    got = search(w, robots, moves.actions, scheduler)
    assert (got.states, got.transitions) == naive_counts(world_name, robots, meeting, scheduler)


def test_graph_file_world_agrees_with_a_naive_bfs(tmp_path) -> None:  # noqa: ANN001
    path = tmp_path / "house.graphml"
    g = nx.house_x_graph()
    nx.write_graphml(nx.relabel_nodes(g, {v: f"n{v}" for v in g}), path)
    name = f"graph:{path}"
    w = get_world(name)
    assert w.size == 5 and w.labels == ("n0", "n1", "n2", "n3", "n4")
    robots, meeting = (0, 4), 2
    for scheduler in ("fsync", "ssync", "async"):
        moves = WorldMoves(w, get_algorithm("go-to-target"), frozenset({meeting}))
        got = search(w, robots, moves.actions, scheduler)
        naive = naive_counts(name, robots, meeting, scheduler)
        # frames are the automorphisms of G: the union over them may hold fewer of the
        # closer neighbours than "any", never one the referee does not allow
        assert got.states <= naive[0]


# -- automorphisms ----------------------------------------------------------------------

@pytest.mark.parametrize(("name", "count"), [("ring:9", 18), ("grid:3x3", 8), ("grid:3x4", 4),
                                             ("torus:3x4", 48), ("torus:3x5", 60),
                                             ("torus:4x4", 384)])
def test_automorphism_group_sizes(name: str, count: int) -> None:
    """The group of the unlabelled graph: a torus's translations with the rectangle's
    symmetries, except where the graph has more (C4 x C4 is the 4-cube: 384, not 128)."""
    w = get_world(name)
    perms = w.automorphisms
    assert len(set(perms)) == count and perms[0] == tuple(range(w.size))
    edges = {frozenset((a, b)) for a in range(w.size) for b in w.adjacency[a]}
    for p in perms:
        assert {frozenset((p[a], p[b])) for a, b in map(tuple, edges)} == edges
    assert len(perms) == sum(1 for _ in nx.algorithms.isomorphism.GraphMatcher(
        w.graph, w.graph).isomorphisms_iter())


def test_petersen_graph_file_has_120_automorphisms(tmp_path) -> None:  # noqa: ANN001
    path = tmp_path / "petersen.edgelist"
    nx.write_edgelist(nx.petersen_graph(), path, data=False)
    assert len(get_world(f"graph:{path}").automorphisms) == 120


def test_symmetries_follow_the_frames() -> None:
    """Only automorphisms that move the robots' frames along are symmetries of the problem."""
    torus = get_world("torus:4x4")
    assert len(torus.symmetries("all")) == 128 < len(torus.automorphisms) == 384
    assert len(torus.symmetries("chirality")) == 64 and len(torus.symmetries("compass")) == 16
    ring = get_world("ring:7")
    assert [len(ring.symmetries(f)) for f in ("all", "chirality", "compass")] == [14, 7, 7]
    grid = get_world("grid:3x3")
    assert [len(grid.symmetries(f)) for f in ("all", "chirality", "compass")] == [8, 4, 1]


@settings(max_examples=40, deadline=None)
@given(world_name=st.sampled_from(["ring:6", "ring:7", "grid:3x3", "torus:3x3", "torus:4x4"]),
       seed=st.integers(0, 10**6), scheduler=st.sampled_from(["fsync", "ssync", "async"]),
       frames=st.sampled_from(["all", "chirality", "compass"]),
       task=st.sampled_from(["gathering-on-meeting-nodes", "exploration-with-stop",
                             "exclusive-perpetual-exploration"]))
def test_results_do_not_change_under_the_symmetries(world_name: str, seed: int, scheduler: str,
                                                    frames: str, task: str) -> None:
    import random

    rnd = random.Random(seed)
    w = get_world(world_name)
    robots = rnd.sample(range(w.size), 2)
    meeting = [rnd.randrange(w.size)]
    p = rnd.choice(w.symmetries(frames))
    algorithm = rnd.choice(["go-to-target", "ring-explore"]) if w.kind == "ring" else \
        "go-to-target"
    base = run_world_check(w, robots, meeting, algorithm, scheduler, task=task, frames=frames)
    moved = run_world_check(w, [p[v] for v in robots], [p[v] for v in meeting], algorithm,
                            scheduler, task=task, frames=frames)
    for key in ("verdict", "property", "states", "transitions"):
        assert base[key] == moved[key], key


# -- the tasks fail on broken algorithms --------------------------------------------------

@pytest.mark.parametrize(("args", "part"), [
    (("--world", "ring:7", "--robots", "0 1 3", "--task", "gathering", "--algorithm",
      "broken-ring-gather", "--scheduler", "fsync", "--multiplicity", "global-weak"),
     "termination"),
    (("--world", "ring:7", "--robots", "0 1 3", "--task", "gathering", "--algorithm",
      "broken-ring-gather", "--scheduler", "async", "--multiplicity", "global-weak"),
     "gathered-when-final"),
    (("--world", "ring:6", "--robots", "0 2 3", "--task", "exclusive-perpetual-exploration",
      "--algorithm", "broken-ring-explore", "--scheduler", "ssync", "--frames", "chirality"),
     "exclusivity"),
    (("--world", "ring:5", "--robots", "0", "--task", "exclusive-perpetual-exploration",
      "--algorithm", "ring-explore", "--scheduler", "fsync"), "perpetual-exploration"),
    (("--world", "ring:6", "--robots", "0 3", "--meeting", "1", "--task",
      "exploration-with-stop", "--algorithm", "go-to-target"), "explored-when-final"),
    (("--world", "ring:6", "--robots", "0 3", "--task", "exploration-with-stop",
      "--algorithm", "ring-explore", "--frames", "chirality"), "termination"),
])
def test_each_task_fails_on_a_broken_algorithm(args: tuple[str, ...], part: str) -> None:
    run = cli("check", *args, "--json")
    assert run.returncode == 1, run.stderr
    report = json.loads(run.stdout)
    assert report["verdict"] == "VIOLATED" and report["property"] == part
    assert report["properties"][part]["holds"] is False
    trace = report["trace"]
    assert trace["property"] == part and trace["steps"][0]["event"] is None


def test_gathering_on_meeting_nodes_fails_for_a_user_algorithm_that_stays(tmp_path) -> None:  # noqa: ANN001
    """A researcher's own algorithm, in a file outside the repository, on a ring."""
    path = tmp_path / "lazy.py"
    path.write_text("class Lazy:\n    name = 'lazy'\n\n    def decide(self, view):\n"
                    "        return view.me\n")
    run = cli("check", "--world", "ring:7", "--robots", "0 3", "--meeting", "5",
              "--algorithm", f"{path}:Lazy", "--json")
    assert run.returncode == 1, run.stderr
    report = json.loads(run.stdout)
    assert report["property"] == "final" and "deadlock" in report["reason"]


@pytest.mark.parametrize(("args", "task"), [
    (("--world", "ring:7", "--robots", "0 1 3", "--algorithm", "ring-gather",
      "--multiplicity", "global-weak"), "gathering"),
    (("--world", "ring:6", "--robots", "0 2 3", "--algorithm", "ring-explore",
      "--frames", "chirality"), "exclusive-perpetual-exploration"),
])
@pytest.mark.parametrize("scheduler", ["fsync", "ssync", "async"])
def test_the_ring_algorithms_solve_their_task(args: tuple[str, ...], task: str,
                                             scheduler: str) -> None:
    run = cli("check", *args, "--task", task, "--scheduler", scheduler, "--json")
    assert run.returncode == 0, run.stdout + run.stderr
    assert json.loads(run.stdout)["verdict"] == "VERIFIED"


def test_a_crash_in_decide_on_a_world_is_a_counterexample() -> None:
    report = run_world_check("ring:6", "0 2", "4", "broken-crash", "async")
    assert report["verdict"] == "VIOLATED" and report["property"] == "crash"
    assert report["trace"]["steps"]


def test_an_answer_that_is_not_a_neighbour_is_a_crash() -> None:
    class Jump:
        name = "jump"

        def decide(self, view):  # noqa: ANN001, ANN201
            return view.me + 2

    report = run_world_check("ring:6", "0 2", "4", Jump(), "async")
    assert report["property"] == "crash" and "neighbours" in report["reason"]


# -- views --------------------------------------------------------------------------------

def test_a_myopic_view_holds_nothing_beyond_its_ball() -> None:
    w = get_world("ring:12")
    for frame in w.frames(0, 2, "all"):
        view = WorldView(w, Counter({0: 1, 2: 2, 5: 1, 9: 3}), frozenset({6}), 0, frame,
                         "global-strong")
        assert len(view.graph) == 5 and view.meeting_nodes == frozenset()
        assert len(view.robots) == 2  # 0 and 2; 5 and 9 lie beyond 2 hops
        assert view.count(frame.labels[2]) == 2
        with pytest.raises(MultiplicityHidden):
            view.count(6)  # a label no visible node has


def test_myopic_robots_decide_on_their_ball_only() -> None:
    seen = []

    class Peek:
        name = "peek"

        def decide(self, view):  # noqa: ANN001, ANN201
            seen.append((len(view.graph), len(view.robots)))
            return view.me

    run_world_check("ring:12", "0 6", "", Peek(), "fsync", task="gathering", visibility=1)
    assert seen and all(size == 3 and robots == 1 for size, robots in seen)


def test_local_detection_hides_other_nodes_multiplicity() -> None:
    report = run_world_check("ring:7", "0 1 3", "", "ring-gather", "async", task="gathering")
    assert report["property"] == "defined" and "multiplicity" in report["reason"]


def test_grid_frames_are_d4_and_a_ring_has_two_directions() -> None:
    assert len(get_world("grid:3x2").frames(0, None, "all")) == 8
    assert len(get_world("grid:3x2").frames(0, None, "chirality")) == 4
    assert len(get_world("ring:5").frames(0, None, "all")) == 2
    assert len(get_world("ring:5").frames(0, None, "compass")) == 1


# -- reductions -----------------------------------------------------------------------------

@pytest.mark.parametrize("world_name", ["ring:8", "grid:3x3", "torus:3x3"])
def test_reductions_keep_the_safety_verdicts(world_name: str) -> None:
    w = get_world(world_name)
    for robots in itertools.combinations(range(w.size), 2):
        for scheduler in ("ssync", "async"):
            full = run_world_check(w, list(robots), [0], "go-to-target", scheduler,
                                   properties=["final"], reduction=False)
            reduced = run_world_check(w, list(robots), [0], "go-to-target", scheduler,
                                      properties=["final"])
            assert reduced["verdict"] == full["verdict"]
            assert reduced["states"] <= full["states"]


# -- bad input: one line, exit 2 ----------------------------------------------------------

@pytest.mark.parametrize(("args", "words"), [
    (("--world", "ring:2", "--robots", "0"), "at least 3"),
    (("--world", "ring:x", "--robots", "0"), "not an integer"),
    (("--world", "mobius:3", "--robots", "0"), "unknown world"),
    (("--world", "ring:9", "--robots", "0 11"), "not a node"),
    (("--world", "grid:3x3", "--robots", "0,0 3,3"), "not a node"),
    (("--world", "torus:2x5", "--robots", "0,0"), "out of range"),
    (("--world", "ring:9", "--robots", "0 3", "--visibility", "-1"), "negative"),
    (("--world", "ring:9", "--robots", "0 3", "--property", "move-bound"), "paper's world"),
    (("--world", "torus:3x3", "--robots", "0,0", "--property", "no-ungatherable"),
     "paper's world"),
    (("--world", "grid:3x3", "--robots", "0,0", "--property", "target-invariance"),
     "paper's world"),
    (("--world", "ring:9", "--robots", "0 3", "--task", "juggling"), "unknown task"),
    (("--world", "ring:9", "--robots", "0 3", "--task", "gathering-on-meeting-nodes"),
     "needs meeting nodes"),
    (("--world", "ring:9", "--robots", "0 3", "--readings", "all"), "paper's world"),
    (("--robots", "0,0 1,1", "--meeting", "0,0", "--task", "gathering"), "finite world"),
])
def test_bad_world_input_is_one_line_exit_2(args: tuple[str, ...], words: str) -> None:
    run = cli("check", *args)
    assert run.returncode == 2, run.stdout + run.stderr
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and words in lines[0] and "Traceback" not in run.stderr


def test_bad_graph_files_are_one_line_exit_2(tmp_path) -> None:  # noqa: ANN001
    apart = tmp_path / "apart.edgelist"
    apart.write_text("a b\nc d\n")
    garbage = tmp_path / "garbage.graphml"
    garbage.write_text("<graphml><node")
    for path, words in ((apart, "not connected"), (garbage, "not a readable graph"),
                        (tmp_path / "missing.gml", "graph file")):
        run = cli("check", "--world", f"graph:{path}", "--robots", "a")
        assert run.returncode == 2 and words in run.stderr, run.stderr
        assert len(run.stderr.strip().splitlines()) == 1
    with pytest.raises(InvalidInput, match="orientation"):
        path = tmp_path / "k4.edgelist"
        nx.write_edgelist(nx.complete_graph(4), path, data=False)
        run_world_check(f"graph:{path}", "0 1", "", "go-to-target", "async",
                        task="gathering", frames="chirality")


@pytest.mark.parametrize("frames", ["all", "chirality", "compass"])
def test_reductions_keep_the_verdicts_of_a_direction_reading_algorithm(frames: str) -> None:
    """ring-explore reads its direction: merging mirror images would be unsound under a
    common chirality; the symmetries of the frames never merge them."""
    w = get_world("ring:7")
    for robots in itertools.combinations(range(w.size), 3):
        for scheduler in ("ssync", "async"):
            full = run_world_check(w, list(robots), [], "broken-ring-explore", scheduler,
                                   task="exclusive-perpetual-exploration", frames=frames,
                                   properties=["exclusivity"], reduction=False)
            reduced = run_world_check(w, list(robots), [], "broken-ring-explore", scheduler,
                                      task="exclusive-perpetual-exploration", frames=frames,
                                      properties=["exclusivity"])
            assert reduced["verdict"] == full["verdict"]
            assert reduced["reductions"] != "off" and reduced["states"] <= full["states"]


PETERSEN = Path(__file__).resolve().parent.parent / "scenarios" / "worlds" / "petersen.graphml"


@pytest.mark.parametrize("world_name", ["ring:7", "grid:3x4", "torus:3x4", f"graph:{PETERSEN}"])
def test_a_frames_distances_and_neighbours_are_its_graphs(world_name: str) -> None:
    """A frame answers ``distance`` and ``neighbours`` without building its networkx graph:
    the same as networkx on that graph, in every frame, with and without a visibility."""
    w = get_world(world_name)
    for v in range(w.size):
        for visibility in (None, 1, 2):
            for frame in w.frames(v, visibility, "all"):
                g = frame.graph
                assert frame.distances == dict(nx.all_pairs_shortest_path_length(g))
                assert all(frame.neighbours(label) == tuple(sorted(g[label])) for label in g)
