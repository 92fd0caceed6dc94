"""Replay of finite worlds' traces: every world kind, every task part a trace can show (with
lights and a stateful scheduler), a tampered trace refused (exit 2), a step the algorithm no
longer takes and a repaired algorithm (exit 5, step-not-taken / property-holds), and a
liveness trace whose cycle is fair by itself."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from gather_verify import kernels
from gather_verify.cli import main
from gather_verify.errors import InvalidInput
from gather_verify.world_check import run_world_check
from gather_verify.world_replay import NoLongerReproduces, replay_world

ROOT = Path(__file__).resolve().parent.parent
PETERSEN = ROOT / "scenarios/worlds/petersen.graphml"

CASES = {
    # name: (world, robots, meeting, algorithm, scheduler, options, the failing part)
    "ring-deadlock": ("ring:6", "0 2", "", "ring-gather", "fsync",
                      {"task": "gathering", "detection": "global-weak"}, "gathered-when-final"),
    "ring-livelock": ("ring:6", "0 1 3", "", "broken-ring-gather", "fsync",
                      {"task": "gathering", "detection": "global-weak"}, "termination"),
    "ring-livelock-async": ("ring:6", "0 2 3", "", "broken-ring-explore", "async",
                            {"task": "gathering", "frames": "chirality"}, "termination"),
    "ring-collision": ("ring:6", "0 3", "", "ring-explore", "async",
                       {"task": "exclusive-perpetual-exploration"}, "exclusivity"),
    "ring-crossing": ("ring:5", "0 1", "", "bounce", "fsync",
                      {"task": "exclusive-perpetual-exploration", "lights": "2",
                       "colours": [1, 1]}, "exclusivity"),
    "ring-one-robot": ("ring:5", "0", "", "ring-explore", "ssync",
                       {"task": "exclusive-perpetual-exploration"}, "perpetual-exploration"),
    "ring-stuck-pair": ("ring:7", "0 1", "", "ring-inchworm", "async",
                        {"task": "exclusive-perpetual-exploration", "lights": "2",
                         "colours": [0, 0], "visibility": 2}, "perpetual-exploration"),
    "ring-round-robin": ("ring:6", "0 2 3", "", "broken-ring-explore", "round-robin",
                         {"task": "gathering", "frames": "chirality"}, "termination"),
    "ring-undefined": ("ring:6", "0 1", "", "ring-gather", "fsync", {"task": "gathering"},
                       "defined"),
    "grid-meeting": ("grid:3x3", "0,0 2,2", "1,1", "broken-stay", "ssync", {}, "final"),
    "grid-crash": ("grid:3x2", "0,0 2,1", "", "ring-explore", "round-robin",
                   {"task": "exclusive-perpetual-exploration"}, "crash"),
    "torus-explore": ("torus:3x3", "0,0 1,1", "2,2", "go-to-target", "async",
                      {"task": "exploration-with-stop"}, "explored-when-final"),
    "graph-explore": (f"graph:{PETERSEN}", "p0 p7", "p3", "go-to-target", "async",
                      {"task": "exploration-with-stop"}, "explored-when-final"),
    "graph-lights": (f"graph:{PETERSEN}", "p0 p7", "", "bounce", "ssync",
                     {"task": "gathering", "lights": "2"}, "termination"),
}


def trace_of(name: str) -> dict:
    world, robots, meeting, algorithm, scheduler, options, part = CASES[name]
    r = run_world_check(world, robots, meeting, algorithm, scheduler, **options)
    assert r["verdict"] == "VIOLATED" and r["property"] == part, (r["verdict"], r["reason"])
    return json.loads(json.dumps(r["trace"]))


def replayed(tmp_path: Path, trace: dict, capsys: pytest.CaptureFixture[str]
             ) -> tuple[int, dict]:
    path = tmp_path / "t.json"
    path.write_text(json.dumps(trace))
    code = main(["replay", str(path), "--json"])
    out = capsys.readouterr().out
    return code, json.loads(out) if out else {}


@pytest.mark.parametrize("name", sorted(CASES))
def test_the_check_s_trace_replays_and_confirms(name):
    trace = trace_of(name)
    result = replay_world(trace)
    assert result.confirmed, result.message
    assert result.steps == len(trace["steps"]) - 1


@pytest.mark.parametrize("name", ["ring-livelock", "torus-explore", "graph-explore",
                                  "ring-crossing"])
def test_replay_command_confirms_with_exit_1(tmp_path, capsys, name):
    code, out = replayed(tmp_path, trace_of(name), capsys)
    assert code == 1 and out["confirmed"] and out["property"] == CASES[name][-1]
    assert "why" not in out


def test_both_engines_write_traces_that_replay():
    world, robots, meeting, algorithm, scheduler, options, part = CASES["ring-livelock-async"]
    for engine in ("reference", "bulk"):
        r = run_world_check(world, robots, meeting, algorithm, scheduler, engine=engine,
                            **options)
        assert r["property"] == part and replay_world(r["trace"]).confirmed


def _first(trace: dict, kind: str) -> int:
    return next(k for k, step in enumerate(trace["steps"])
                if step["event"] and step["event"]["kind"] == kind)


def test_a_step_that_jumps_two_edges_is_refused(tmp_path, capsys):
    trace = trace_of("ring-collision")
    k = _first(trace, "look")
    robot, src, _ = trace["steps"][k]["event"]["moves"][0]
    far = (src + 2) % 6
    trace["steps"][k]["event"]["moves"][0][2] = far
    trace["steps"][k]["robots"][robot][1] = far
    path = tmp_path / "t.json"
    path.write_text(json.dumps(trace))
    assert main(["replay", str(path)]) == 2
    assert f"cannot reach {far} from {src} in one edge" in capsys.readouterr().err


def test_a_state_the_event_does_not_reach_is_refused():
    trace = trace_of("ring-livelock")
    trace["steps"][1]["robots"][2][0] = 4  # r2 did not move in that round
    with pytest.raises(InvalidInput, match="does not reach the recorded state"):
        replay_world(trace)


def test_an_event_of_the_wrong_scheduler_is_refused():
    trace = trace_of("ring-livelock")
    trace["scheduler"] = "async"  # a round is no ASYNC event
    with pytest.raises(InvalidInput, match="not allowed"):
        replay_world(trace)


def test_edited_visited_nodes_are_refused():
    trace = trace_of("torus-explore")
    trace["steps"][-1]["visited"] = trace["steps"][-1]["visited"][:-1]
    with pytest.raises(InvalidInput, match="visited nodes"):
        replay_world(trace)


def test_a_legal_step_the_algorithm_does_not_take_exits_5(tmp_path, capsys):
    """On the 3 x 3 torus r0 at 0,0 looks towards the meeting node 2,2 (across the wrap-around,
    to 2,0); the edited trace has it decide 1,0 instead: a legal move, not go-to-target's."""
    trace = trace_of("torus-explore")
    step = trace["steps"][1]
    assert step["event"]["moves"] == [[0, [0, 0], [2, 0]]]
    step["event"]["moves"][0][2] = [1, 0]
    step["robots"][0][1] = [1, 0]
    code, out = replayed(tmp_path, trace, capsys)
    assert code == 5 and out["why"] == "step-not-taken" and not out["confirmed"]
    assert "step 1: the algorithm no longer lets robot 0 do 1,0" in out["message"]


def test_a_repaired_algorithm_reports_property_holds(tmp_path, capsys):
    """The deadlock of two robots on ring:6 replays step for step (there is no step), but an
    algorithm that moves has no deadlock there: property-holds."""
    trace = trace_of("ring-deadlock")
    trace["algorithm"] = "ring-explore"
    code, out = replayed(tmp_path, trace, capsys)
    assert code == 5 and out["why"] == "property-holds"
    assert "not final" in out["message"]


def test_a_repaired_livelock_reports_property_holds(tmp_path, capsys):
    """The same rounds of broken-ring-gather's livelock, replayed against an algorithm that
    also allows them, but that gathers when the pair is adjacent... here the trace's own cycle
    is cut: the last state is not the one the cycle starts from."""
    trace = trace_of("ring-livelock")
    trace["steps"] = trace["steps"][:-1]
    code, out = replayed(tmp_path, trace, capsys)
    assert code == 5 and out["why"] == "property-holds" and "does not return" in out["message"]


def test_a_crash_fixed_reports_property_holds(tmp_path, capsys):
    trace = trace_of("grid-crash")
    trace["algorithm"] = "go-to-target"  # no meeting node: it stays, and does not crash
    code, out = replayed(tmp_path, trace, capsys)
    assert code == 5 and out["why"] == "property-holds"


def test_an_unfair_cycle_is_not_a_livelock(monkeypatch):
    """The cycle a trace shows must be fair by itself (§5). Written with the first cycle of
    the component (here it leaves a robot out), replay refuses it; the check's own trace walks
    through the component until every robot acted, and is confirmed."""
    import gather_verify.world_check as wc
    from gather_verify.tasks.base import cycle_in

    assert replay_world(trace_of("ring-livelock-async")).confirmed

    def first_cycle(s, component, n, start):
        c = cycle_in(s, component)
        return [(a, next(k for k, (t, _, _) in enumerate(s.edges[a]) if t == b))
                for a, b in zip(c, c[1:], strict=False)]

    monkeypatch.setattr(wc, "fair_walk", first_cycle)
    result = replay_world(trace_of("ring-livelock-async"))
    assert not result.confirmed and "not fair" in result.message


def test_the_graph_file_changed_is_refused(tmp_path):
    graph = tmp_path / "g.graphml"
    graph.write_text(PETERSEN.read_text())
    r = run_world_check(f"graph:{graph}", "p0 p7", "p3", "go-to-target", "async",
                        task="exploration-with-stop")
    trace = r["trace"]
    assert replay_world(trace).confirmed
    graph.write_text(PETERSEN.read_text().replace("p9", "q9"))
    with pytest.raises(InvalidInput, match="not the one the trace was written on"):
        replay_world(trace)


def test_a_relative_graph_file_is_taken_from_the_trace_s_folder(tmp_path, capsys,
                                                                monkeypatch):
    (tmp_path / "g.graphml").write_text(PETERSEN.read_text())
    monkeypatch.chdir(tmp_path)
    r = run_world_check("graph:g.graphml", "p0 p7", "p3", "go-to-target", "async",
                        task="exploration-with-stop")
    (tmp_path / "out").mkdir()
    (tmp_path / "out/g.graphml").write_text(PETERSEN.read_text())
    (tmp_path / "g.graphml").unlink()
    path = tmp_path / "out/t.json"
    path.write_text(json.dumps(r["trace"]))
    assert main(["replay", str(path), "--quiet"]) == 1
    assert "CONFIRMED: explored-when-final on graph:g.graphml" in capsys.readouterr().out


@pytest.mark.parametrize("edit, message", [
    (lambda t: t.update(world="ring:2"), "a ring has at least 3 nodes"),
    (lambda t: t.update(task="nope"), "unknown task"),
    (lambda t: t.update(property="move-bound"), "has no part 'move-bound'"),
    (lambda t: t["steps"][0]["robots"].pop(), "must list 2 pairs"),
    (lambda t: t["steps"][1]["robots"][0].__setitem__(0, 99), "99 is not a node of ring:6"),
    (lambda t: t.update(cycle_start=99), "cycle_start"),
    (lambda t: t["steps"][0].update(colours=[0, 5]), "colours in 0..0"),
    (lambda t: t.update(steps=[]), "'steps' is empty"),
])
def test_malformed_world_traces_get_one_line_and_exit_2(tmp_path, capsys, edit, message):
    trace = trace_of("ring-collision")
    edit(trace)
    path = tmp_path / "t.json"
    path.write_text(json.dumps(trace))
    assert main(["replay", str(path)]) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1


def test_replay_text_output_and_pictures(tmp_path, capsys):
    trace = trace_of("ring-stuck-pair")
    path = tmp_path / "t.json"
    path.write_text(json.dumps(trace))
    svg, html = tmp_path / "t.svg", tmp_path / "t.html"
    assert main(["replay", str(path), "--svg", str(svg), "--html", str(html)]) == 1
    out = capsys.readouterr().out
    assert "CONFIRMED: perpetual-exploration on ring:7 (0 steps)" in out
    assert "can stay in the last state for ever" in out
    assert svg.read_text().startswith("<svg") and "ring:7" in html.read_text()


def test_no_longer_reproduces_is_an_input_error_subclass():
    assert issubclass(NoLongerReproduces, InvalidInput)


def test_a_scenario_that_stores_a_world_trace_replays_it(tmp_path: Path,
                                                         capsys: pytest.CaptureFixture[str]) -> None:
    """``gather-verify test`` replays a finite world's stored trace with the world's replay
    (not the Z² loader), and a trace whose step was edited fails its case."""
    r = run_world_check("ring:6", "0 3", "", "broken-ring-explore", "ssync",
                        task="exclusive-perpetual-exploration")
    scenario = {"world": "ring:6", "robots": [0, 3], "meeting_nodes": [],
                "task": "exclusive-perpetual-exploration", "algorithm": "broken-ring-explore",
                "expect": {"verdicts": [{"algorithm": "broken-ring-explore", "scheduler": "ssync",
                                         "verdict": "VIOLATED",
                                         "property": r["trace"]["property"]}]},
                "trace": r["trace"]}
    path = tmp_path / "w.scenario.json"
    path.write_text(json.dumps(scenario))
    assert main(["test", str(path)]) == 0
    assert "[replay]" in capsys.readouterr().out
    scenario["trace"]["algorithm"] = "ring-explore"  # the fixed twin does not collide
    path.write_text(json.dumps(scenario))
    assert main(["test", str(path)]) == 1
    assert "no longer reproduces" in capsys.readouterr().out


# -- round-robin: the trace names the order its run started in, as on Z² ------------------

ROUND_ROBIN = {
    # name: (world, robots, meeting, algorithm, options, the failing part); the reductions
    # are on in the first two (safety parts only) and their runs start in an order other
    # than the first, so the robots' identities and the order must agree
    "ring-explore-stop": ("ring:6", [0, 1, 3], [5], "go-to-target",
                          {"task": "exploration-with-stop", "properties": ["explored-when-final"]},
                          "explored-when-final"),
    "torus-collision": ("torus:3x3", [0, 4, 5], [], "bounce",
                        {"task": "exclusive-perpetual-exploration", "properties": ["exclusivity"],
                         "lights": "2"}, "exclusivity"),
    "ring-livelock": ("ring:6", [0, 2, 3], [], "broken-ring-explore",
                      {"task": "gathering", "frames": "chirality"}, "termination"),
}
RR_ENGINES = ["reference", pytest.param("bulk", marks=pytest.mark.skipif(
    not kernels.available(), reason="numba is not installed"))]


def round_robin_trace(name: str, engine: str, reduction: bool) -> dict:
    world, robots, meeting, algorithm, options, part = ROUND_ROBIN[name]
    r = run_world_check(world, robots, meeting, algorithm, "round-robin", engine=engine,
                        reduction=reduction, **options)
    assert r["verdict"] == "VIOLATED" and r["property"] == part, (r["verdict"], r["reason"])
    assert r["engine"] == engine
    return json.loads(json.dumps(r["trace"]))


def order_of(trace: dict) -> list[int]:
    name, _, order = trace["scheduler"].partition(":order=")
    assert name == "round-robin" and order, trace["scheduler"]
    return [int(i) for i in order.split()]


@pytest.mark.parametrize("reduction", [True, False])
@pytest.mark.parametrize("engine", RR_ENGINES)
@pytest.mark.parametrize("name", sorted(ROUND_ROBIN))
def test_a_round_robin_trace_names_its_order_and_replay_follows_it(tmp_path, capsys, name,
                                                                   engine, reduction):
    """The trace names the order (a permutation of its robots) and replays under it alone;
    another order that puts another robot first is refused in one line (exit 2); the same
    trace without its order, as traces were written before, still replays (every order)."""
    trace = round_robin_trace(name, engine, reduction)
    order = order_of(trace)
    assert sorted(order) == list(range(len(trace["robots"])))
    assert trace["steps"][1]["event"]["robots"] == [order[0]]  # order[0] acts first
    code, out = replayed(tmp_path, trace, capsys)
    assert code == 1 and out["confirmed"], out
    other = order[1:] + order[:1]
    moved = {**trace, "scheduler": "round-robin:order=" + " ".join(map(str, other))}
    path = tmp_path / "moved.json"
    path.write_text(json.dumps(moved))
    assert main(["replay", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "step 1:" in err and moved["scheduler"] in err, err
    old = {**trace, "scheduler": "round-robin"}
    assert replay_world(old).confirmed


def test_the_reductions_do_not_hide_the_order_a_run_started_in():
    """With the reductions on, the failing run of these instances starts in an order other
    than the first (the one anonymity relabels every start to): the trace still names it in
    the robots' own identities, the same order as the unreduced search's trace."""
    for name in ("ring-explore-stop", "torus-collision"):
        on = round_robin_trace(name, "reference", True)
        off = round_robin_trace(name, "reference", False)
        assert order_of(on) != sorted(order_of(on)), name
        assert on["scheduler"] == off["scheduler"] and on["steps"] == off["steps"], name


def test_a_round_robin_order_for_other_robots_is_refused_in_one_line():
    trace = round_robin_trace("ring-livelock", "reference", False)
    trace["scheduler"] = "round-robin:order=1 0"
    with pytest.raises(InvalidInput, match=r"^bad trace: its scheduler: round-robin order 1 0 "
                                           r"must name each of the robots 0\.\.2 once$"):
        replay_world(trace)


SWAPS = {
    # name: (world, robots, algorithm, scheduler, options): a round in which two robots swap
    # nodes, with the reductions on; the class it reaches is stored as another member
    "ring-swap-fsync": ("ring:6", "0 1", "broken-ring-gather", "fsync",
                        {"detection": "global-weak"}),
    "ring-swap-ssync": ("ring:6", "0 1 3", "broken-ring-gather", "ssync",
                        {"detection": "global-weak"}),
    "grid-crossing": ("grid:3x3", "0,0 1,0", "bounce", "ssync",
                      {"lights": "2", "colours": [1, 1]}),
    "torus-crossing": ("torus:3x3", "0,0 1,0 1,1", "bounce", "ssync",
                       {"lights": "2", "colours": [1, 1, 0]}),
}


def _applied(before: list, step: dict) -> list:
    """The robots of a trace's step as its event makes them from the step before."""
    robots = [list(r) for r in before]
    for i, src, dst in step["event"]["moves"]:
        robots[i] = [src, dst] if step["event"]["kind"] == "look" else [dst, None]
    return robots


def _rounds_stored_elsewhere(name: str, engine: str) -> int:
    """How many crossing rounds of the reduced search reach a class stored as a member other
    than the round's own successor (so a trace that ended on the stored member would not be
    the round's successor)."""
    from gather_verify.algorithms import get_algorithm
    from gather_verify.engine import world_bulk, world_search
    from gather_verify.world_check import _apply
    from gather_verify.worlds import finite_world
    from gather_verify.worlds.moves import WorldMoves, parse_lights

    world, robots, algorithm, scheduler, options = SWAPS[name]
    w = finite_world(world)
    moves = WorldMoves(w, get_algorithm(algorithm), frozenset(),
                       options.get("detection", "local-weak"),
                       lights=parse_lights(options.get("lights")))
    kwargs = dict(colours=options.get("colours"), anonymity=True,
                  symmetries=w.symmetries("all"))
    s = (world_bulk.search(w, tuple(w.parse_nodes(robots)), moves, scheduler, **kwargs)
         if engine == "bulk" else
         world_search.search(w, tuple(w.parse_nodes(robots)), moves.actions, scheduler,
                             **kwargs))
    count = 0
    for sid, out in enumerate(s.edges):
        for target, _, event in out:
            crossing = {(a, b) for _, a, b in event.moves}
            if any((b, a) in crossing for a, b in crossing) and \
                    _apply(s.keys[sid], event) != s.keys[target][0]:
                count += 1
    return count


@pytest.mark.parametrize("engine", RR_ENGINES)
@pytest.mark.parametrize("name", sorted(SWAPS))
def test_a_reduced_transition_trace_ends_with_the_real_successor(name, engine):
    """The failing round of a transition part (exclusivity: two robots cross one edge) may
    reach a class the reduced search stored as another member (the swapped robots sorted
    back, or an image by Aut(G)). The trace ends with the round's own successor, not the
    stored member: every step is its event applied to the step before, and replay confirms
    it (a trace ending on the stored member is refused: it does not match itself)."""
    world, robots, algorithm, scheduler, options = SWAPS[name]
    assert _rounds_stored_elsewhere(name, engine) > 0  # the case at stake, on this engine
    r = run_world_check(world, robots, "", algorithm, scheduler, engine=engine,
                        task="exclusive-perpetual-exploration", properties=["exclusivity"],
                        **options)
    assert r["verdict"] == "VIOLATED" and r["property"] == "exclusivity", r["reason"]
    assert r["reductions"].startswith("anonymity") and r["engine"] == engine
    trace = json.loads(json.dumps(r["trace"]))
    steps = trace["steps"]
    for before, step in zip(steps, steps[1:], strict=False):
        assert step["robots"] == _applied(before["robots"], step), step
    result = replay_world(trace)
    assert result.confirmed and "cross" in result.message, result.message
