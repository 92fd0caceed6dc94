"""The rendezvous world in the one pipeline against the naive referee (SEMANTICS.md §13):
the same states, the same edges with the same robots, the same verdict, cell by cell; a
counterexample's trace replays; the command line prints the verdict; bad input is one line.

The referee (``tests/rendezvous_referee.py``) is written from §13 alone; the world
(:mod:`gather_verify.worlds.rendezvous`), the phase scheduler (:mod:`schedulers.phases`)
and the check (:mod:`gather_verify.rendezvous_check`) are the product.
"""

from __future__ import annotations

import copy
import itertools
import json
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from rendezvous_referee import MODELS, Referee, check

from gather_verify import pipeline
from gather_verify.engine.bfs import breadth_first
from gather_verify.engine.encoding import Limits
from gather_verify.errors import InvalidInput
from gather_verify.rendezvous_check import (
    RendezvousCheck,
    RendezvousModel,
    phase_model,
    replay_rendezvous,
    run_rendezvous_check,
)
from gather_verify.replay import NoLongerReproduces
from gather_verify.sweeps import rendezvous as table_of
from gather_verify.worlds import rendezvous_rules as rr
from gather_verify.worlds.rendezvous import Rendezvous

A = rr.ALGORITHMS
CELLS = list(itertools.product(A, MODELS, rr.MOVEMENTS, rr.INITIAL_COLOURS))
SAMPLE = [("vig-2cols", m, "non-rigid", "all") for m in MODELS] + [
    ("vig-3cols", "async", "non-rigid", "all"), ("vig-3cols", "async-regular", "rigid", "same"),
    ("optimal", "async-move-safe", "non-rigid", "all"), ("to-half", "fsync", "rigid", "all"),
    ("to-other", "fsync", "rigid", "same"), ("wada-4ext", "async-lc-atomic", "non-rigid", "all"),
    ("flo-algo3ext", "async-cm-atomic", "non-rigid", "same")]


def graph_of(alg: rr.RendezvousAlgorithm, model: str, movement: str, colours: str):
    """The product's state graph: the states and the edges as (state, state, robots mask)."""
    world = Rendezvous(alg)
    m = RendezvousModel(world, phase_model(model), world.starts(movement, colours))
    walked = breadth_first(m)
    states = walked.stored
    edges = {(states[v], states[w], mask) for v, out in enumerate(m.edges)
             for w, mask, _ in out}
    return set(states), edges, walked.transitions


def referee_graph(alg: rr.RendezvousAlgorithm, model: str, movement: str, colours: str):
    ref = Referee(alg, model, movement, colours)
    ref.explore()
    states = [s[:3] for s in ref.states]
    edges = {(states[v], states[w], mask) for v, out in enumerate(ref.edges)
             for w, mask, _ in out}
    return set(states), edges, ref.transitions


def same_cell(name: str, model: str, movement: str, colours: str) -> None:
    alg = A[name]
    assert graph_of(alg, model, movement, colours) == referee_graph(alg, model, movement,
                                                                    colours)
    got = run_rendezvous_check(alg, model, movement=movement, initial_colours=colours)
    expected = check(alg, model, movement, colours).verdict
    assert got["verdict"] == {"PASS": "VERIFIED", "FAIL": "VIOLATED"}[expected]
    if got["verdict"] == "VIOLATED":
        assert replay_rendezvous(got["trace"]).confirmed


@pytest.mark.parametrize("cell", SAMPLE, ids="-".join)
def test_the_world_is_the_referee_on_a_sample(cell):
    """Field by field: every state, every edge with its robots, the verdict, and a failing
    cell's trace confirmed by replay."""
    same_cell(*cell)


@pytest.mark.slow
@pytest.mark.parametrize("cell", CELLS, ids="-".join)
def test_the_world_is_the_referee_on_every_cell(cell):
    same_cell(*cell)


def draw_rules(draw, k: int, light: str) -> dict:
    """One random answer (a move and a colour) per view that ``light`` shows with ``k``
    colours: (own colour, other's colour, position) -> (move, colour)."""
    own = [None] if light == "external" else range(k)
    other = [None] if light == "internal" else range(k)
    answer = st.tuples(st.sampled_from((rr.STAY, rr.TO_HALF, rr.TO_OTHER)),
                       st.integers(0, k - 1))
    return {(a, b, p): draw(answer) for a in own for b in other for p in range(3)}


@st.composite
def tables(draw):
    """A random algorithm of one or two colours: one answer per view its lights show."""
    k, light = draw(st.integers(1, 2)), draw(st.sampled_from(rr.LIGHTS))
    rules = tuple(draw_rules(draw, k, light).items())
    return rr.RendezvousAlgorithm("random", k, rules, lights=light)


@settings(max_examples=25, deadline=None)
@given(alg=tables(), model=st.sampled_from(list(MODELS)),
       movement=st.sampled_from(rr.MOVEMENTS))
def test_random_algorithms_the_world_is_the_referee(alg, model, movement):
    assert graph_of(alg, model, movement, "all") == referee_graph(alg, model, movement, "all")
    got = run_rendezvous_check(alg, model, movement=movement)["verdict"]
    assert (got == "VERIFIED") == (check(alg, model, movement).verdict == "PASS")


def test_a_broken_algorithm_fails_with_a_trace_that_replays():
    """Moving to the other under FSYNC swaps the robots for ever (the trivial move fails)."""
    r = run_rendezvous_check("to-other", "fsync", movement="rigid")
    assert r["verdict"] == "VIOLATED" and r["property"] == "rendezvous"
    done = replay_rendezvous(r["trace"])
    assert done.confirmed and done.steps == len(r["trace"]["steps"]) - 1
    # a move's ends are written as positions, never spelled out letter by letter
    ends = {end for step in r["trace"]["steps"][1:]
            for _, *pair in step["event"]["moves"] for end in pair}
    assert ends and ends <= {"far", "near", "same"}, ends


def test_a_trace_that_does_not_match_itself_is_one_line():
    r = run_rendezvous_check("vig-2cols", "async", movement="rigid")
    bad = copy.deepcopy(r["trace"])
    bad["steps"][1]["state"]["position"] = "far"
    with pytest.raises(InvalidInput, match="step 1"):
        replay_rendezvous(bad)



def test_a_trace_whose_algorithm_changed_no_longer_reproduces():
    """A trace of moving to the other, replayed as moving to the midpoint: its first Look
    chose to-other, which the algorithm it names no longer answers (exit 5, not 2)."""
    trace = run_rendezvous_check("to-other", "fsync", movement="rigid")["trace"]
    trace["algorithm"] = "to-half"
    with pytest.raises(NoLongerReproduces, match="no longer answers"):
        replay_rendezvous(trace)


def test_a_stopped_search_is_incomplete_never_verified():
    r = run_rendezvous_check("vig-3cols", "async-lc-atomic", max_states=20)
    assert r["verdict"] == "INCOMPLETE" and r["stopped"] == "states"


def test_unknown_names_are_one_line():
    with pytest.raises(InvalidInput, match="unknown synchrony model"):
        run_rendezvous_check("vig-2cols", "round-robin")
    with pytest.raises(InvalidInput, match="unknown rendezvous algorithm"):
        run_rendezvous_check("paper", "async")
    with pytest.raises(InvalidInput, match="movement"):
        run_rendezvous_check("vig-2cols", "async", movement="jumpy")


def test_the_watchdog_report_is_incomplete():
    checker = RendezvousCheck("vig-2cols", "async", "rigid", "all", Limits())
    report = checker.overtime(1.5, pipeline.Watch())
    assert report["verdict"] == "INCOMPLETE" and report["trace"] is None


def _cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "gather_verify", *args], capture_output=True,
                          text=True, timeout=120)


def test_the_issue_command_prints_the_verdict(tmp_path):
    done = _cli("check", "--world", "rendezvous", "--algorithm", "vig-3cols", "--scheduler",
                "async-lc-atomic", "--movement", "non-rigid", "--initial-colours", "all", "--json")
    report = json.loads(done.stdout)
    assert done.returncode == 0 and report["verdict"] == "VERIFIED"
    ref = Referee(A["vig-3cols"], "async-lc-atomic")
    ref.explore()
    assert (report["states"], report["transitions"]) == (len(ref.states), ref.transitions)
    assert report["initial_states"] == 27  # 3 positions x 9 colour pairs
    out = tmp_path / "t.json"
    done = _cli("check", "--world", "rendezvous", "--algorithm", "vig-2cols", "--scheduler",
                "async", "--trace-out", str(out))
    assert done.returncode == 1 and "VIOLATED" in done.stdout
    done = _cli("replay", str(out), "--json")
    assert done.returncode == 1 and json.loads(done.stdout)["confirmed"] is True


def test_options_of_other_worlds_are_refused_in_one_line():
    done = _cli("check", "--world", "rendezvous", "--algorithm", "vig-2cols", "--scheduler",
                "async", "--robots", "0 1")
    assert done.returncode == 2 and done.stderr.count("\n") == 1 and "--robots" in done.stderr
    done = _cli("check", "--world", "ring:6", "--robots", "0 2", "--movement", "rigid")
    assert done.returncode == 2 and "rendezvous" in done.stderr


SPIN_RESULTS = Path(__file__).resolve().parent.parent / "bench" / "spin" / "light" / "results.json"


def test_the_table_beside_spin_on_a_sample(tmp_path):
    """The table's cells are the check's, SPIN's stored verdicts stand beside them (they agree),
    and every failure's trace is written and replays."""
    spin = table_of.load_spin(SPIN_RESULTS)
    t = table_of.table(["vig-2cols", "to-half"], ["fsync", "async", "async-lc-atomic"],
                       spin=spin, traces=tmp_path)
    assert len(t["cells"]) == 2 * 3 * 4 and t["compared"] == 24 and not t["disagreements"]
    for c in t["cells"]:
        r = run_rendezvous_check(c["algorithm"], c["scheduler"], movement=c["movement"],
                                 initial_colours=c["initial_colours"])
        assert (c["verdict"], c["states"]) == (r["verdict"], r["states"])
        assert ("trace" in c) == (c["verdict"] == "VIOLATED")
        if "trace" in c:
            assert replay_rendezvous(json.loads((tmp_path / c["trace"]).read_text())).confirmed
    text = table_of.markdown(t)
    assert "| vig-2cols | ✓✓✓✓ = | ✗✗✗✗ = | ✓✓✓✓ = |" in text


def test_a_disagreement_with_spin_is_shown():
    spin = table_of.load_spin(SPIN_RESULTS)
    key = "vig-2cols|async|rigid|all"
    spin = {key: {**spin[key], "verdict": "PASS"}}  # as if SPIN had verified it
    t = table_of.table(["vig-2cols"], ["async"], ["rigid"], ["all"], spin=spin)
    assert [c["verdict"] for c in t["disagreements"]] == ["VIOLATED"]
    assert "✗ ≠" in table_of.markdown(t)


def test_the_sweep_command_rebuilds_the_table(tmp_path):
    out = tmp_path / "table.md"
    done = _cli("sweep", "--world", "rendezvous", "--algorithm", "vig-3cols",
                "--scheduler", "async,async-regular", "--movement", "rigid",
                "--spin", str(SPIN_RESULTS), "--markdown", str(out), "--json")
    assert done.returncode == 0, done.stderr
    cells = json.loads(done.stdout)["cells"]
    assert [(c["scheduler"], c["verdict"], c["spin"]) for c in cells] == [
        ("async", "VERIFIED", "VERIFIED"), ("async", "VERIFIED", "VERIFIED"),
        ("async-regular", "VIOLATED", "VIOLATED"), ("async-regular", "VIOLATED", "VIOLATED")]
    assert "| vig-3cols | ✓✓ = | ✗✗ = |" in out.read_text()
    done = _cli("sweep", "--world", "rendezvous", "--robots", "2")
    assert done.returncode == 2 and "--robots" in done.stderr
    done = _cli("sweep", "--world", "ring:5", "--robots", "2", "--movement", "rigid")
    assert done.returncode == 2 and "rendezvous" in done.stderr
    done = _cli("sweep", "--world", "ring:5")
    assert done.returncode == 2 and "--robots" in done.stderr


def test_the_viewer_draws_every_step(tmp_path):
    """The viewer's page of a rendezvous trace carries one picture per state: the segment as
    long as the position, both robots filled with their lights, a pending move as an arrow
    (a miss dashed and crossed), the robots of the step outlined; ``check --html`` and
    ``replay --html`` write that page; a damaged trace is one line."""
    from gather_verify.rendezvous_picture import SPAN
    from gather_verify.viewer import annotate, viewer_html

    trace = run_rendezvous_check("vig-2cols", "async", movement="rigid")["trace"]
    data = annotate(trace)
    assert len(data["pictures"]) == len(trace["steps"]) == len(data["events"]) + 1
    for k, (step, picture) in enumerate(zip(trace["steps"], data["pictures"], strict=True)):
        body, state = picture["body"], step["state"]
        assert body.count("class='robot'") == 2 and data["states"][k]["summary"] == \
            state["position"]
        lights = [rr.colour_name(r["colour"]) for r in state["robots"]]
        assert [body.split(f"data-robot='{n}' data-light='")[1].split("'")[0]
                for n in "AB"] == lights
        x1, x2 = (float(body.split("class='segment' ")[1].split(f"{a}='")[1].split("'")[0])
                  for a in ("x1", "x2"))
        assert x2 - x1 == SPAN[state["position"]]
        pending = [r["pending"] for r in state["robots"] if r["pending"] != "stay"]
        assert body.count("class='pending'") == len(pending)
        assert body.count("stroke-dasharray") == pending.count("miss")
        outlined = body.count("stroke='#1f77b4'")
        assert outlined == (len(step["event"]["robots"]) if step["event"] else 0)
    page = viewer_html(trace)
    assert '"pictures":[' in page and "<script src" not in page
    out, again = tmp_path / "v.html", tmp_path / "r.html"
    stored = tmp_path / "t.json"
    stored.write_text(json.dumps(trace))
    done = _cli("check", "--world", "rendezvous", "--algorithm", "vig-2cols", "--scheduler",
                "async", "--movement", "rigid", "--html", str(out))
    assert done.returncode == 1 and out.read_text() == page
    done = _cli("replay", str(stored), "--html", str(again))
    assert done.returncode == 1 and again.read_text() == page
    broken = copy.deepcopy(trace)
    broken["steps"][3]["event"]["robots"] = [2]
    with pytest.raises(InvalidInput, match="step 3: an event's robots"):
        annotate(broken)
    broken = copy.deepcopy(trace)
    broken["steps"][2]["state"]["robots"][0]["colour"] = "<b>"
    with pytest.raises(InvalidInput, match="step 2"):
        annotate(broken)
    hostile = {**trace, "algorithm": "</script><img src=x onerror=alert(1)>"}
    assert "<img" not in viewer_html(hostile)  # a trace is data, never markup


def test_browser_steps_through_a_rendezvous_trace(web, tmp_path):
    """In a browser the viewer steps through a rendezvous trace state by state: the picture
    shows both robots with the state's lights, the position, the robots' table changes with
    the state; the cycle plays in a loop; nothing fails, nothing is fetched."""
    from gather_verify.viewer import write_viewer

    trace = run_rendezvous_check("vig-2cols", "async", movement="rigid")["trace"]
    path = tmp_path / "v.html"
    write_viewer(trace, str(path))
    page = web.page
    page.clock.install()  # timers run only when the test says so
    page.goto(path.as_uri())
    shown = """() => [Number(document.body.dataset.step),
        [...document.querySelectorAll('#now g.robot')].map(g => g.dataset.light),
        document.querySelectorAll('#now .pending').length,
        document.getElementById('info').innerText, document.getElementById('robots').innerText]"""
    for k, step in enumerate(trace["steps"]):
        if k:
            page.keyboard.press("ArrowRight")
        at, lights, pending, info, rows = page.evaluate(shown)
        state = step["state"]
        assert at == k and lights == [rr.colour_name(r["colour"]) for r in state["robots"]], k
        assert pending == sum(r["pending"] != "stay" for r in state["robots"])
        assert state["position"] in info and all(r["pending"] in rows for r in state["robots"])
    assert "rendezvous fails" in page.inner_text("#end")
    page.keyboard.press("End")
    page.keyboard.press("l")  # loop the cycle: past the last state comes state cycle_start + 1
    page.clock.run_for(1000)
    assert int(page.eval_on_selector("body", "b => b.dataset.step")) == trace["cycle_start"] + 1
    assert not web.errors and not web.remote


def test_a_rendezvous_scenario_is_checked_and_tested(tmp_path):
    """A scenario of the rendezvous world: its expectations run through the one check, its
    stored trace replays; a wrong expectation fails; fields of other worlds are refused."""
    from gather_verify.scenario import ScenarioError, parse_scenario
    from gather_verify.scenario_tests import cases

    trace = run_rendezvous_check("to-other", "fsync", movement="rigid")["trace"]
    data = {"world": "rendezvous", "algorithm": "to-other", "scheduler": "fsync",
            "movement": "rigid",
            "expect": {"verdicts": [
                {"algorithm": "to-other", "scheduler": "fsync", "verdict": "VIOLATED",
                 "property": "rendezvous"},
                {"algorithm": "to-other", "scheduler": "centralized", "verdict": "VERIFIED"}]},
            "trace": trace}
    outcomes = [c.run() for c in cases(parse_scenario(data, "s.json"))]
    assert len(outcomes) == 3 and all(o.passed for o in outcomes), outcomes
    wrong = {**data, "expect": {"verdicts": [{"algorithm": "to-other", "scheduler": "fsync",
                                              "verdict": "VERIFIED"}]}}
    assert not [c.run() for c in cases(parse_scenario(wrong, "s.json"))][0].passed
    with pytest.raises(ScenarioError, match="no field of a rendezvous scenario"):
        parse_scenario({**data, "robots": [0, 1]}, "s.json")
    with pytest.raises(ScenarioError, match="unknown synchrony model"):
        parse_scenario({**data, "scheduler": "round-robin"}, "s.json")
    with pytest.raises(ScenarioError, match="rendezvous world"):
        parse_scenario({"robots": [[0, 0]], "meeting_nodes": [[1, 1]], "movement": "rigid"},
                       "s.json")
