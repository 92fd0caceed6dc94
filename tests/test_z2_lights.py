"""Luminous robots on the paper's world, Z² (SEMANTICS.md §10): lights that cannot leak
into a view, the Look that changes a light, a luminous algorithm that needs its light and a
broken twin the checker refuses, invariance under the grid's symmetries, and ``--lights 1``
equal to the oblivious run."""

from __future__ import annotations

import json
import subprocess
import sys
from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import schedulers.async_
import schedulers.base
from gather_verify import kernels
from gather_verify.cli import main
from gather_verify.engine import lit_bulk
from gather_verify.engine.encoding import Limits
from gather_verify.engine.explore import explore_reference
from gather_verify.engine.search import explore
from gather_verify.errors import InvalidInput
from gather_verify.model import geometry
from gather_verify.model.configuration import Configuration
from gather_verify.model.view import LightHidden, Lights, LuminousView, MultiplicityHidden
from gather_verify.plane_check import run_check, sorted_colours
from gather_verify.replay import NoLongerReproduces, replay
from gather_verify.worlds.moves import parse_lights

CLI = [sys.executable, "-m", "gather_verify"]
BEACON = Configuration([(1, 1), (3, 2)], [(0, 0), (4, 0)], initial=True)
"""Two robots nearest to different meeting nodes (class I22)."""


def cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([*CLI, *args], capture_output=True, text=True, timeout=120)


# -- lights cannot leak into a Z² view --------------------------------------------------------

def view(variant: str, detection: str = "global-weak", frame: int = 0) -> LuminousView:
    """The robot with colour 1 on (0, 0), which it shares with a robot of colour 2; one robot
    of colour 0 on (3, 0)."""
    c = Configuration([(0, 0), (0, 0), (3, 0)], [(1, 1)])
    return LuminousView.luminous(c, (0, 0), frame, detection, Lights(3, variant),
                                 {(0, 0): Counter({1: 1, 2: 1}), (3, 0): Counter({0: 1})}, 1)


def test_full_lights_show_every_colour() -> None:
    v = view("full")
    assert v.light == 1 and v.colours() == {1, 2} and v.colours((3, 0)) == {0}
    assert v.colours((1, 0)) == frozenset()  # an empty node has no light


def test_external_lights_hide_the_robots_own_colour() -> None:
    v = view("external")
    with pytest.raises(LightHidden):
        v.light  # noqa: B018
    assert v.colours() == {2} and v.colours((3, 0)) == {0}


def test_internal_lights_hide_every_other_colour() -> None:
    v = view("internal")
    assert v.light == 1
    for node in ((0, 0), (3, 0)):
        with pytest.raises(LightHidden):
            v.colours(node)


def test_colour_counts_need_strong_detection() -> None:
    with pytest.raises(MultiplicityHidden):
        view("full").colour_counts((3, 0))
    with pytest.raises(MultiplicityHidden):  # local-strong: counts on its own node only
        view("full", "local-strong").colour_counts((3, 0))
    assert view("full", "local-strong").colour_counts() == {1: 1, 2: 1}
    assert view("full", "global-strong").colour_counts((3, 0)) == {0: 1}


@pytest.mark.parametrize("g", geometry.ALL)
def test_the_colours_stay_on_their_robots_in_every_frame(g: int) -> None:
    v = view("full", frame=g)
    other = geometry.apply(g, (3, 0))  # the robot of colour 0, in this frame
    assert other in v.robots and v.colours(other) == {0} and v.light == 1


def test_a_luminous_view_keys_what_it_shows() -> None:
    assert view("full").key() != view("internal").key() != view("external").key()
    c = Configuration([(0, 0), (3, 0)], [(1, 1)])
    key = [LuminousView.luminous(c, (0, 0), 0, "none", Lights(2, "internal"),
                                 {(0, 0): Counter({0: 1}), (3, 0): Counter({k: 1})}, 0).key()
           for k in (0, 1)]
    assert key[0] == key[1]  # another robot's colour is no part of an internal view


@pytest.mark.parametrize(("variant", "words"), [("2:external", "own colour"),
                                                ("2:internal", "no other robot's colour")])
def test_an_algorithm_reading_a_hidden_light_has_no_rule(variant: str, words: str) -> None:
    report = run_check(BEACON, algorithm="beacon", scheduler="async", lights=variant)
    assert report["property"] == "defined" and words in report["reason"]


def test_a_colour_out_of_range_is_a_crash_with_a_trace() -> None:
    report = run_check(BEACON, algorithm="beacon", scheduler="async", lights="1")
    assert report["property"] == "crash" and "colours 0..0" in report["reason"]
    assert report["trace"]["steps"]  # it steps towards a meeting node, then answers colour 1


# -- the Look that changes a light ------------------------------------------------------------

def test_a_colour_change_while_staying_is_an_event() -> None:
    """One robot on the meeting node: beacon claims it by turning its light on and staying."""
    c = Configuration([(0, 0)], [(0, 0)], initial=True)
    a = explore_reference(c, "beacon", "async", reduction=False, lights=Lights(2))
    assert (a.states, a.transitions) == (2, 1)
    (event, state), = a.concrete_successors(a.initial_state)
    assert event.kind == "look" and event.moves == () and event.lights == ((0, 0, 1),)
    assert state == (((0, 0), None, 1),)
    f = explore_reference(c, "beacon", "fsync", reduction=False, lights=Lights(2))
    assert (f.states, f.transitions) == (2, 2)  # the claim, then the null round (a self-loop)


def test_under_async_others_see_the_light_before_the_move() -> None:
    """A robot one step from a meeting node claims it at its Look: the light is on while the
    move is pending."""
    c = Configuration([(1, 0), (5, 3)], [(0, 0), (6, 0)], initial=True)
    e = explore_reference(c, "beacon", "async", reduction=False, lights=Lights(2))
    looks = [(ev, s) for ev, s in e.concrete_successors(e.initial_state) if ev.robots == (0,)]
    assert looks and all(s[0] == ((1, 0), (0, 0), 1) for _, s in looks)


# -- a luminous algorithm that needs its light, and its broken twin ---------------------------

@pytest.mark.parametrize(("scheduler", "verdict"), [("fsync", "VERIFIED"), ("ssync", "VIOLATED"),
                                                    ("async", "VERIFIED"),
                                                    ("centralized", "VERIFIED")])
def test_beacon_gathers_where_one_look_at_a_time_sets_a_light(scheduler: str,
                                                              verdict: str) -> None:
    report = run_check(BEACON, algorithm="beacon", scheduler=scheduler, lights="2")
    assert report["verdict"] == verdict
    if verdict == "VIOLATED":  # two robots claimed two meeting nodes in one round
        assert report["property"] == "final"
        last = report["trace"]["steps"][-1]
        assert [r["colour"] for r in last["state"]] == [1, 1]
        assert len(last["event"]["lights"]) == 2


@pytest.mark.parametrize("scheduler", ["fsync", "ssync", "async", "centralized"])
def test_beacon_without_its_light_is_refused(scheduler: str) -> None:
    report = run_check(BEACON, algorithm="broken-beacon", scheduler=scheduler, lights="2")
    assert (report["verdict"], report["property"]) == ("VIOLATED", "final")


def test_a_check_with_lights_says_which_engine_ran() -> None:
    report = run_check(BEACON, algorithm="beacon", scheduler="async", lights="2")
    assert report["engine"] == "bulk" and "engine_fallback" not in report
    assert report["lights"] == "2" and report["colours"] == [0, 0]
    assert "no-ungatherable" in report["not_applicable"]
    fast = run_check(BEACON, algorithm="beacon", scheduler="async", lights="2", engine="fast")
    assert fast["engine"] == "bulk"
    ref = run_check(BEACON, algorithm="beacon", scheduler="async", lights="2",
                    engine="reference")
    assert ref["engine"] == "reference" and "engine_fallback" not in ref
    # 13 colours: 65 actions a robot, more than a mask holds; auto says why it fell back
    many = run_check(BEACON, algorithm="beacon", scheduler="fsync", lights="13")
    assert many["engine"] == "reference"
    assert "more than 62 actions" in many["engine_fallback"]
    with pytest.raises(InvalidInput, match="cannot run this request"):
        run_check(BEACON, algorithm="beacon", scheduler="fsync", lights="13", engine="fast")


# -- invariance under the grid's symmetries ---------------------------------------------------

@settings(max_examples=25, deadline=None)
@given(robots=st.lists(st.tuples(st.integers(0, 3), st.integers(0, 3)), min_size=2, max_size=2,
                       unique=True),
       meeting=st.lists(st.tuples(st.integers(0, 3), st.integers(0, 3)), min_size=1,
                        max_size=2, unique=True),
       colours=st.lists(st.integers(0, 1), min_size=2, max_size=2),
       g=st.sampled_from(geometry.ALL), t=st.tuples(st.integers(-3, 3), st.integers(-3, 3)),
       scheduler=st.sampled_from(["fsync", "ssync", "async", "centralized"]),
       reduction=st.booleans())
def test_luminous_results_do_not_change_under_d4_and_translations(
        robots: list, meeting: list, colours: list, g: int, t: tuple, scheduler: str,
        reduction: bool) -> None:
    def moved(v: tuple[int, int]) -> tuple[int, int]:
        return geometry.add(geometry.apply(g, v), t)

    kw = {"algorithm": "beacon", "scheduler": scheduler, "lights": "2",
          "reduction": reduction, "force": True, "max_seconds": 60}
    base = run_check(Configuration(robots, meeting, initial=True),
                     colours=sorted_colours(robots, colours), **kw)
    image = run_check(Configuration([moved(v) for v in robots], [moved(m) for m in meeting],
                                    initial=True),
                      colours=sorted_colours([moved(v) for v in robots], colours), **kw)
    for key in ("verdict", "property", "class", "states", "transitions", "max_moves"):
        assert base[key] == image[key], key


# -- one colour is the oblivious robot ----------------------------------------------------------

NOT_COMPARED = {"seconds", "peak_rss_mb", "lights", "colours", "engine", "engine_fallback"}


@pytest.mark.parametrize("algorithm", ["go-to-target", "broken-stay", "broken-wander"])
@pytest.mark.parametrize("scheduler", ["fsync", "ssync", "async", "centralized"])
@pytest.mark.parametrize("reduction", [True, False])
@pytest.mark.parametrize("engine", ["reference", "auto"])
def test_one_colour_is_the_oblivious_run_field_by_field(algorithm: str, scheduler: str,
                                                        reduction: bool, engine: str) -> None:
    """Every field of the report, the trace included (a region of a fixed margin: the runs
    stop at the same place, never at a clock), beside the oblivious run on the reference
    engine and on the bulk one (``auto``)."""
    c = Configuration([(0, 0), (2, 1)], [(1, 2)], initial=True)
    kw = {"algorithm": algorithm, "scheduler": scheduler, "reduction": reduction, "margin": 1}
    plain = run_check(c, engine=engine, **kw)
    lit = run_check(c, lights="1", **kw)
    assert lit["lights"] == "1"
    assert {k: v for k, v in lit.items() if k not in NOT_COMPARED} == \
        {k: v for k, v in plain.items() if k not in NOT_COMPARED}


# -- the command line and scenario files --------------------------------------------------------

BEACON_ARGS = ["--robots", "1,1 3,2", "--meeting", "0,0 4,0", "--algorithm", "beacon"]


def test_check_takes_lights_on_the_paper_world(capsys) -> None:  # noqa: ANN001
    assert main(["check", *BEACON_ARGS, "--lights", "2", "--scheduler", "ssync", "--json"]) == 1
    report = json.loads(capsys.readouterr().out)
    assert report["property"] == "final" and report["trace"]["lights"] == "2"
    assert main(["check", *BEACON_ARGS, "--lights", "2", "--scheduler", "ssync"]) == 1
    text = capsys.readouterr().out
    assert "r0 light 0->1" in text and "lights: r0=1 r1=1" in text


def test_the_storyboard_draws_each_robots_colour() -> None:
    from gather_verify.render import trace_svg

    trace = run_check(BEACON, algorithm="beacon", scheduler="ssync", lights="2")["trace"]
    svg = trace_svg(trace)
    last = svg.rsplit("<g", 1)[-1]  # the last panel: both robots lit
    assert svg.count('class="light"') == 2 * (len(trace["steps"]) + 1)
    assert last.count('data-colour="1"') == 2


def test_the_viewer_shows_each_robots_colour_and_the_lights_an_event_changed() -> None:
    from gather_verify.viewer import annotate

    trace = run_check(BEACON, algorithm="beacon", scheduler="ssync", lights="2")["trace"]
    data = annotate(trace)
    assert [s["colours"] for s in data["states"]][-1] == [1, 1]
    assert data["states"][0]["colours"] == [0, 0]
    assert "r0 light 0->1" in data["events"][-1]["text"]
    assert all(s["moves"] is None for s in data["states"])  # no oblivious move sets


@pytest.mark.parametrize(("args", "words"), [
    (("--lights", "0"), "number of colours"),
    (("--lights", "2", "--colours", "0 2"), "initial colours"),
    (("--lights", "2", "--colours", "0"), "initial colours"),
    (("--colours", "0 1"), "give --lights"),
    (("--lights", "13", "--engine", "bulk"), "more than 62 actions"),
    (("--lights", "2", "--scheduler", "round-robin:order=1 2"), "each of the robots"),
])
def test_bad_lights_on_the_paper_world_are_one_line(args: tuple[str, ...], words: str,
                                                    capsys) -> None:  # noqa: ANN001
    assert main(["check", *BEACON_ARGS, *args]) == 2
    err = capsys.readouterr().err
    assert words in err and len(err.strip().splitlines()) == 1, err


def test_colours_follow_the_robots_as_written(capsys) -> None:  # noqa: ANN001
    """Robot (0, 0) starts lit on a meeting node, written second: then even SSYNC gathers."""
    args = ["check", "--meeting", "0,0 4,0", "--algorithm", "beacon", "--lights", "2",
            "--scheduler", "ssync", "--json"]
    assert main([*args, "--robots", "3,2 0,0", "--colours", "0 1"]) == 0
    assert json.loads(capsys.readouterr().out)["colours"] == [1, 0]  # sorted: (0, 0) first
    assert main([*args, "--robots", "3,2 0,0", "--colours", "1 0"]) != 0  # (3, 2) lit, stuck


def test_bad_lights_are_one_line_without_a_traceback() -> None:
    run = cli("check", *BEACON_ARGS, "--lights", "2", "--colours", "0 2")
    assert run.returncode == 2 and "Traceback" not in run.stderr
    assert len(run.stderr.strip().splitlines()) == 1, run.stderr


def test_a_grid_scenario_colour_outside_the_lights_is_one_line(tmp_path, capsys) -> None:  # noqa: ANN001
    path = tmp_path / "s.json"
    path.write_text(json.dumps({"robots": [[1, 1], [3, 2]], "meeting_nodes": [[0, 0], [4, 0]],
                                "lights": "2", "colours": [0, 2], "algorithm": "beacon"}))
    assert main(["check", str(path)]) == 2
    assert "'colours'" in capsys.readouterr().err


def test_a_trace_with_lights_replays_and_a_changed_colour_does_not(tmp_path,
                                                                   capsys) -> None:  # noqa: ANN001
    report = run_check(BEACON, algorithm="broken-beacon", scheduler="async", lights="2")
    assert replay(report["trace"]).confirmed
    path = tmp_path / "t.json"
    path.write_text(json.dumps(report["trace"]))
    assert main(["replay", str(path)]) == 1  # confirmed: the violation is real
    assert "CONFIRMED" in capsys.readouterr().out
    good = run_check(BEACON, algorithm="beacon", scheduler="ssync", lights="2")["trace"]
    assert replay(good).confirmed
    bad = json.loads(json.dumps(good))
    bad["steps"][-1]["state"][0]["colour"] = 0  # the light the round set, taken back
    with pytest.raises(InvalidInput, match="does not reach the recorded state"):
        replay(bad)
    bad["steps"][-1]["event"]["lights"] = bad["steps"][-1]["event"]["lights"][1:]
    with pytest.raises(NoLongerReproduces, match="no longer lets robot"):  # legal, not beacon's
        replay(bad)


BLINK = """
class Blink:
    name = "blink"

    def decide(self, view):
        return view.me, 1 - view.light  # on for ever, off for ever: never still
"""


def test_a_luminous_livelock_is_found_and_replays(tmp_path) -> None:  # noqa: ANN001
    """A robot that only toggles its light never terminates (a colour change is an event):
    the cycle of the trace changes colours only, and replay confirms it fair."""
    (tmp_path / "blink.py").write_text(BLINK)
    c = Configuration([(0, 0)], [(0, 0)], initial=True)
    for scheduler in ("async", "fsync"):
        report = run_check(c, algorithm=f"{tmp_path}/blink.py:Blink", scheduler=scheduler,
                           lights="2")
        assert (report["verdict"], report["property"]) == ("VIOLATED", "termination")
        trace = report["trace"]
        assert trace["cycle_start"] is not None
        assert all(not step["event"]["moves"] for step in trace["steps"])
        assert replay(trace).confirmed


# -- the bulk engine with lights, field by field against the reference ------------------------

LIT_CONFIGURATIONS = [
    BEACON,
    Configuration([(0, 0), (2, 1)], [(1, 2)], initial=True),  # one meeting node, I11
    Configuration([(1, 0), (5, 3)], [(0, 0), (6, 0)], initial=True),
    Configuration([(0, 0), (2, 0), (1, 2)], [(1, 1)], initial=True),  # three robots
]
LIT_ALGORITHMS = ["beacon", "broken-beacon", "bounce"]
SCHEDULERS = ["fsync", "ssync", "async", "centralized"]
EXPLORATION_FIELDS = ("states", "transitions", "stopped", "changed_loops", "vacuous")


def exploration_fields(e: Any) -> dict[str, Any]:
    """Every field of a search the reports and traces are built from."""
    out = {f: getattr(e, f) for f in EXPLORATION_FIELDS}
    for column in ("keys", "parents", "offsets", "targets", "weights"):
        out[column] = list(getattr(e, column))
    out["violations"] = {name: (v.state, v.reason, v.event, v.successor, v.detail)
                         for name, v in e.violations.items()}
    return out


def lit_differences(c: Configuration, algorithm: str, scheduler: str, lights: str,
                    reduction: bool, **limits: Any) -> list[str]:
    """The fields in which the bulk search with lights differs from the reference's (none:
    []), the searches and the reports of ``run_check`` (traces included) compared."""
    light = parse_lights(lights)
    lim = Limits(**{"margin": 1, "max_states": 40_000, **limits})
    ref = explore(c, algorithm, scheduler, engine="reference", lights=light, reduction=reduction,
                  limits=lim)
    bulk = explore(c, algorithm, scheduler, engine="fast", lights=light, reduction=reduction,
                   limits=lim)
    assert (ref.engine, bulk.engine) == ("reference", "bulk")
    a, b = exploration_fields(ref), exploration_fields(bulk)
    out = [f"search {k}" for k in a if a[k] != b[k]]
    kw = {"algorithm": algorithm, "scheduler": scheduler, "lights": lights,
          "reduction": reduction, "force": True, "margin": 1, "max_states": 40_000}
    r1, r2 = run_check(c, engine="reference", **kw), run_check(c, engine="fast", **kw)
    assert (r1["engine"], r2["engine"]) == ("reference", "bulk")
    out += [f"report {k}" for k in r1 if k not in NOT_COMPARED and r1[k] != r2.get(k)]
    if r2["trace"] is not None:
        assert replay(r2["trace"]).confirmed
    return out


@pytest.mark.parametrize("scheduler", SCHEDULERS)
@pytest.mark.parametrize("algorithm", LIT_ALGORITHMS)
@pytest.mark.parametrize("lights", ["2", "3", "2:external", "2:internal"])
def test_the_bulk_engine_with_lights_is_the_reference(scheduler: str, algorithm: str,
                                                      lights: str) -> None:
    for reduction in (True, False):
        assert lit_differences(BEACON, algorithm, scheduler, lights, reduction) == []


@pytest.mark.parametrize("scheduler", SCHEDULERS)
@pytest.mark.parametrize("kernels_on", [True, False])
def test_the_bulk_engine_with_lights_on_its_numpy_path(scheduler: str, kernels_on: bool) -> None:
    """The compiled successor keys and the numpy ones (``GATHER_VERIFY_KERNELS=numpy``)."""
    kernels.use(kernels_on)
    try:
        for c in LIT_CONFIGURATIONS[1:3]:
            for reduction in (True, False):
                assert lit_differences(c, "beacon", scheduler, "2", reduction) == []
    finally:
        kernels.use(None)


@pytest.mark.slow
@pytest.mark.parametrize("scheduler", SCHEDULERS)
@pytest.mark.parametrize("algorithm", [*LIT_ALGORITHMS, "go-to-target"])
@pytest.mark.parametrize("lights", ["1", "2", "3", "2:external", "2:internal", "3:external",
                                    "3:internal"])
@pytest.mark.parametrize("c", LIT_CONFIGURATIONS[1:])
def test_the_bulk_engine_with_lights_is_the_reference_everywhere(
        scheduler: str, algorithm: str, lights: str, c: Configuration) -> None:
    for reduction in (True, False):
        assert lit_differences(c, algorithm, scheduler, lights, reduction) == []


def test_the_bulk_engine_with_lights_stops_where_the_reference_stops() -> None:
    """A state limit and a region too small (margin 0, no growth) cut both searches at the
    same state and transition."""
    for scheduler in ("ssync", "async"):
        assert lit_differences(LIT_CONFIGURATIONS[3], "bounce", scheduler, "2", False,
                               max_states=300) == []
        assert lit_differences(LIT_CONFIGURATIONS[3], "bounce", scheduler, "2", True,
                               margin=0) == []


def test_the_initial_colours_and_a_blinking_livelock_are_the_same(tmp_path) -> None:  # noqa: ANN001
    (tmp_path / "blink.py").write_text(BLINK)
    one = Configuration([(0, 0)], [(0, 0)], initial=True)
    for scheduler in SCHEDULERS:
        kw = {"algorithm": f"{tmp_path}/blink.py:Blink", "scheduler": scheduler, "lights": "2"}
        r1, r2 = run_check(one, engine="reference", **kw), run_check(one, **kw)
        assert r2["engine"] == "bulk" and r2["property"] == "termination"
        assert {k: v for k, v in r1.items() if k not in NOT_COMPARED} == \
            {k: v for k, v in r2.items() if k not in NOT_COMPARED}
        kw = {"algorithm": "beacon", "scheduler": scheduler, "lights": "2", "colours": [1, 0]}
        r1, r2 = run_check(BEACON, engine="reference", **kw), run_check(BEACON, **kw)
        assert {k: v for k, v in r1.items() if k not in NOT_COMPARED} == \
            {k: v for k, v in r2.items() if k not in NOT_COMPARED}


@pytest.mark.parametrize("path", sorted(Path("scenarios").glob("lights/*.scenario.json")),
                         ids=lambda p: p.name)
def test_every_lit_scenario_of_the_paper_world_is_the_same_on_both_engines(path: Path) -> None:
    data = json.loads(path.read_text())
    c = Configuration([tuple(v) for v in data["robots"]],
                      [tuple(m) for m in data["meeting_nodes"]], initial=True)
    colours = data.get("colours")
    if colours is not None:
        colours = sorted_colours([tuple(v) for v in data["robots"]], colours)
    for expected in data["expect"]["verdicts"]:
        kw = {"algorithm": expected["algorithm"], "scheduler": expected["scheduler"],
              "lights": data["lights"], "colours": colours}
        r1, r2 = run_check(c, engine="reference", **kw), run_check(c, **kw)
        assert r2["engine"] == "bulk" and r2["verdict"] == expected["verdict"]
        assert {k: v for k, v in r1.items() if k not in NOT_COMPARED} == \
            {k: v for k, v in r2.items() if k not in NOT_COMPARED}


def test_a_perturbed_colour_encoding_is_caught(monkeypatch) -> None:  # noqa: ANN001
    """The comparison is not blind: configurations looked up without their colours (a
    robot's actions read from another colour's row), or the actions tried in another order,
    make the bulk engine differ from the reference."""
    monkeypatch.setattr(lit_bulk.LitTable, "locate", _colour_blind_locate)
    assert lit_differences(BEACON, "beacon", "async", "2", False)
    monkeypatch.undo()
    assert lit_differences(BEACON, "beacon", "async", "2", False) == []
    for scheduler in ("async", "ssync"):  # bounce: a robot may step to any neighbour
        assert lit_differences(BEACON, "bounce", scheduler, "2", False) == []
    monkeypatch.setattr(schedulers.base, "luminous_order", _destinations_reversed)
    monkeypatch.setattr(schedulers.async_, "luminous_order", _destinations_reversed)
    for scheduler in ("async", "ssync"):
        assert lit_differences(BEACON, "bounce", scheduler, "2", False)


_LOCATE = lit_bulk.LitTable.locate


def _colour_blind_locate(self: lit_bulk.LitTable, codes: np.ndarray
                         ) -> tuple[np.ndarray, np.ndarray]:
    return _LOCATE(self, codes - codes % self.colours)  # every robot seen with colour 0


_ORDER = schedulers.base.luminous_order


def _destinations_reversed(colours: int) -> np.ndarray:
    return _ORDER(colours).reshape(5, colours)[::-1].reshape(-1)


# -- move-bound: a cycle that changes only colours leaves the moves bounded --------------------

FIXTURES = Path(__file__).resolve().parent / "fixtures"
GATHER_BLINK = f"{FIXTURES / 'blink.py'}:Blink"
GATHER_PACE = f"{FIXTURES / 'blink.py'}:Pace"
GATHER = Configuration([(0, 0), (2, 1)], [(1, 1)], initial=True)
"""Two robots 2 and 1 steps from the meeting node: 3 moves to gather."""


@pytest.mark.parametrize("scheduler", [*SCHEDULERS, "round-robin"])
def test_a_cycle_of_colours_leaves_the_moves_bounded(scheduler: str) -> None:
    """Robots that gather and then blink for ever: every cycle changes only colours, so the
    moves are bounded (3, the distances) on both engines, with and without the reductions,
    while termination fails; a robot that steps off and back instead has no bound."""
    for reduction in (True, False):
        kw = {"scheduler": scheduler, "lights": "2", "reduction": reduction}
        for engine in ("reference", "auto"):
            r = run_check(GATHER, algorithm=GATHER_BLINK, engine=engine, **kw)
            assert (r["max_moves"], r["max_moves_infinite"], r["property"]) == \
                (3, False, "termination")
            assert r["properties"]["move-bound"]["holds"] is True
            r = run_check(GATHER, algorithm=GATHER_BLINK, engine=engine,
                          properties=["move-bound"], **kw)
            assert (r["verdict"], r["max_moves"], r["ratio"]) == ("VERIFIED", 3, 3 / (2 * 2))
            r = run_check(GATHER, algorithm=GATHER_PACE, engine=engine,
                          properties=["move-bound"], **kw)
            assert (r["verdict"], r["max_moves_infinite"]) == ("VIOLATED", True)
            assert replay(r["trace"]).confirmed


def test_a_move_bound_cycle_that_changes_only_colours_is_not_confirmed() -> None:
    """Replay confirms a move-bound cycle only when it moves: the blinking livelock's cycle,
    relabelled as a move-bound witness, returns but makes no move."""
    r = run_check(Configuration([(0, 0)], [(0, 0)], initial=True), algorithm=GATHER_BLINK,
                  scheduler="async", lights="2")
    trace = {**r["trace"], "property": "move-bound"}
    assert r["property"] == "termination" and replay(r["trace"]).confirmed
    again = replay(trace)
    assert not again.confirmed and "makes no move" in again.message
