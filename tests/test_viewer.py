"""The trace viewer: what it computes (class, target, phase, stale snapshots, the cycle) and,
in a real browser, that the page shows the trace it was given."""

from __future__ import annotations

import copy
import json
import re
from pathlib import Path

import pytest

from gather_verify.cli import main
from gather_verify.trace import load_trace
from gather_verify.viewer import annotate, event_text, viewer_html, write_viewer

ROOT = Path(__file__).resolve().parent.parent
F4 = ROOT / "scenarios/algorithm/i22-make-multiplicity-onto-guard.json"
F6 = ROOT / "scenarios/algorithm/i22-livelock-guard-on-axis-of-M.json"
STALE = ROOT / "scenarios/regressions/i22-defined-paper-alpha-mer-f-async-df2289d6.json"
CYCLE_ASYNC = ROOT / "scenarios/regressions/i22-move-bound-paper-alpha-mer-f-async-faf0817f.json"


def stored(path: Path) -> dict:
    return load_trace(json.loads(path.read_text())["trace"])


def checked(tmp_path: Path, scenario: Path, scheduler: str) -> dict:
    """The trace ``check`` writes for a scenario."""
    out = tmp_path / "t.json"
    main(["check", str(scenario), "--scheduler", scheduler, "--trace-out", str(out)])
    return load_trace(out)


def state(robots, pending=None):
    pending = pending or {}
    return [{"node": list(v), "pending": list(pending[i]) if i in pending else None}
            for i, v in enumerate(robots)]


def step(kind, robots, moves, after):
    return {"event": {"kind": kind, "robots": robots, "moves": moves}, "state": after}


def synthetic_cycle() -> dict:
    """Two robots on a line. r0 looks in the prefix and moves in the cycle; when the cycle
    repeats, its Move executes the Look of event 7, on a snapshot taken after r1 moved."""
    a, b, c, d = (0, 0), (1, 0), (2, 0), (3, 0)
    steps = [
        step("look", [0], [[0, a, b]], state([a, d], {0: b})),                 # 1
        step("look", [1], [[1, d, c]], state([a, d], {0: b, 1: c})),           # 2 (cycle)
        step("move", [0], [[0, a, b]], state([b, d], {1: c})),                 # 3
        step("move", [1], [[1, d, c]], state([b, c])),                         # 4
        step("look", [0], [[0, b, a]], state([b, c], {0: a})),                 # 5
        step("move", [0], [[0, b, a]], state([a, c])),                         # 6
        step("look", [0], [[0, a, b]], state([a, c], {0: b})),                 # 7
        step("look", [1], [[1, c, d]], state([a, c], {0: b, 1: d})),           # 8
        step("move", [1], [[1, c, d]], state([a, d], {0: b})),                 # 9 = state 1
    ]
    return {"format": "gather-verify-trace", "version": 1,
            "initial": {"robots": [list(a), list(d)], "meeting_nodes": [[5, 5]]},
            "algorithm": "go-to-target", "scheduler": "async", "detection": "local-weak",
            "frames": "all", "steps": steps, "property": "termination",
            "reason": "a fair cycle", "cycle_start": 1, "detail": {}}


# -- what the viewer computes ---------------------------------------------------------------

def test_stale_snapshot_is_named_with_its_look_and_snapshot():
    data = annotate(stored(STALE))
    stale = {k: d for k, e in enumerate(data["events"], 1) for d in e["decisions"] if d["stale"]}
    assert sorted(stale) == [5, 10]
    assert stale[5] == {"robot": 2, "look": 2, "snapshot": 1, "stale": True,
                        "moved_since": ["r1"]}
    assert stale[10]["robot"] == 1 and stale[10]["look"] == 4
    # a Move right after its Look is current, not stale
    fresh = [d for e in data["events"] for d in e["decisions"] if not d["stale"]]
    assert fresh and all(not d["moved_since"] for d in fresh)


def test_a_move_on_an_unchanged_snapshot_is_not_stale():
    trace = stored(STALE)
    data = annotate(trace)
    assert data["events"][4]["decisions"][0]["stale"]
    # break the input: the robot r1 that moved between r2's Look and Move stays put instead
    broken = copy.deepcopy(trace)
    for k in (2, 3):  # events 3 (r1 moves) .. 4 (r1 looks again) keep r1 at its node
        broken["steps"][k]["state"][1]["node"] = trace["steps"][1]["state"][1]["node"]
    assert not annotate(broken)["events"][4]["decisions"][0]["stale"]


def test_per_state_class_target_phase_and_move_sets():
    data = annotate(stored(STALE))
    first, last = data["states"][0], data["states"][-1]
    assert (first["class"], first["phase"], first["target"]) == ("I22", "I2 make multiplicity",
                                                                [1, 1])
    assert first["guard"] == [0, 0]
    assert last["phase"] == "no rule" and "I42" in last["unhandled"]
    assert data["states"][5]["moves"]["0,0"] == [[0, 1], [1, 0]]


def test_deadlock_shows_every_robot_staying(tmp_path):
    data = annotate(checked(tmp_path, F4, "fsync"))
    last = data["states"][-1]
    assert all(len(v) == 1 for v in last["moves"].values())
    assert all(list(map(int, k.split(","))) == v[0] for k, v in last["moves"].items())


def test_cycle_decisions_when_the_cycle_repeats():
    data = annotate(synthetic_cycle())
    move3 = data["events"][2]
    assert move3["decisions"] == [{"robot": 0, "look": 1, "snapshot": 0, "stale": False,
                                   "moved_since": []}]
    # when the cycle repeats, r0's Move executes its Look of event 7, taken while r1 stood
    # on (2, 0): since then r1 moved back to (3, 0)
    assert move3["loop_decisions"] == [{"robot": 0, "look": 7, "snapshot": 6, "stale": True,
                                        "moved_since": ["r1"]}]
    assert data["events"][3]["decisions"][0]["stale"]  # r1's move after r0 moved
    assert data["pending_since"][2] == [1, 2]


def test_algorithm_without_phases_and_unknown_algorithm():
    trace = synthetic_cycle()
    data = annotate(trace)
    assert data["states"][0]["phase"] is None  # go-to-target has no plan
    assert data["provides"] == {"phase": False, "guard": False, "target": True}
    assert data["loaded"]
    assert annotate(stored(STALE))["provides"] == {"phase": True, "guard": True, "target": True}
    trace["algorithm"] = "someone-elses"
    data = annotate(trace)
    assert data["states"][0]["class"] and data["states"][0]["moves"] is None
    assert not data["loaded"] and not any(data["provides"].values())


def test_an_algorithm_s_own_phase_is_shown_without_a_plan():
    from gather_verify.algorithms.go_to_target import GoToTarget

    class Named(GoToTarget):
        name = "go-to-target"

        def phase(self, configuration):
            return "walking"

    import gather_verify.viewer as viewer

    trace = synthetic_cycle()
    original = viewer._load_algorithm
    viewer._load_algorithm = lambda name, load_code=True: Named()
    try:
        data = annotate(trace)
    finally:
        viewer._load_algorithm = original
    assert data["provides"] == {"phase": True, "guard": False, "target": True}
    assert {info["phase"] for info in data["states"]} == {"walking"}


def test_event_text():
    assert event_text({"kind": "move", "robots": [2], "moves": [[2, [1, 2], [1, 1]]]}) == \
        "move(r2): r2 (1, 2)->(1, 1)"


def test_page_is_self_contained_and_escapes_the_data():
    trace = stored(STALE)
    trace["reason"] = "</script><script>alert(1)</script> <!-- x"
    page = viewer_html(trace)
    assert page.count("</script>") == 2  # the data block and the viewer's script
    assert "alert(1)</script>" not in page
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", page)
    assert "@import" not in page and "<link" not in page
    assert re.findall(r"https?://[^\"' ]+", page) == ["http://www.w3.org/2000/svg"]  # a name


def test_cli_check_and_replay_write_the_viewer(tmp_path, capsys):
    out = tmp_path / "v.html"
    # the scenario expects this VIOLATED verdict: check says it matched (exit 0)
    assert main(["check", str(F4), "--scheduler", "fsync", "--html", str(out)]) == 0
    assert "trace-data" in out.read_text()
    again = tmp_path / "r.html"
    assert main(["replay", str(STALE), "--quiet", "--html", str(again)]) == 1
    assert json.dumps(2) in again.read_text()
    assert main(["replay", str(STALE), "--html", str(tmp_path / "no/such/dir.html")]) == 2
    assert "--html" in capsys.readouterr().err


# -- in a real browser ---------------------------------------------------------------------

def shown(web) -> dict:
    """What the page shows now: the step, and each robot's node and pending move."""
    page = web.page
    robots = page.eval_on_selector_all(
        "#now g.robot", "gs => gs.map(g => [Number(g.dataset.robot), g.dataset.node, "
        "g.dataset.pending])")
    return {"step": int(page.eval_on_selector("body", "b => b.dataset.step")),
            "robots": sorted(robots),
            "event": page.inner_text("#event")}


def expected(trace: dict, k: int) -> dict:
    st = [{"node": r, "pending": None} for r in trace["initial"]["robots"]] if k == 0 \
        else trace["steps"][k - 1]["state"]
    return {"step": k,
            "robots": sorted([i, f"{r['node'][0]},{r['node'][1]}",
                              "" if r["pending"] is None else f"{r['pending'][0]},{r['pending'][1]}"]
                             for i, r in enumerate(st)),
            "event": "initial configuration" if k == 0
            else f"event {k}: {event_text(trace['steps'][k - 1]['event'])}"}


def open_viewer(web, tmp_path: Path, trace: dict, name: str = "v.html"):
    path = tmp_path / name
    write_viewer(trace, str(path))
    web.page.clock.install()  # timers run only when the test says so
    web.page.goto(path.as_uri())
    return web.page


def test_browser_steps_through_the_trace(web, tmp_path):
    trace = stored(STALE)
    page = open_viewer(web, tmp_path, trace)
    n = len(trace["steps"])
    assert shown(web) == expected(trace, 0)
    for k in range(1, n + 1):  # forward with the arrow key
        page.keyboard.press("ArrowRight")
        assert shown(web) == expected(trace, k)
        stale_box = page.is_visible("#snap-fig")
        assert stale_box == (k in (5, 10)), k
    page.keyboard.press("ArrowRight")  # past the end: stays at the end
    assert shown(web)["step"] == n
    for k in range(n - 1, 2, -1):  # back with the button
        page.click("#prev")
        assert shown(web) == expected(trace, k)
    changed = page.eval_on_selector_all("#robots td.changed", "ts => ts.map(t => "
                                        "[t.closest('tr').dataset.robot, t.className])")
    assert changed == [["1", "node changed"], ["1", "pending changed"]]  # event 3: r1 moved
    page.fill("#slider", "5")  # the slider
    assert shown(web) == expected(trace, 5)
    assert "Stale snapshot" in page.inner_text("#decision")
    assert "event 2" in page.inner_text("#decision")
    snapshot = page.eval_on_selector_all("#snap g.robot", "gs => gs.map(g => g.dataset.node)")
    assert sorted(snapshot) == sorted(f"{x},{y}" for x, y in
                                      (r["node"] for r in trace["steps"][0]["state"]))
    decided = page.eval_on_selector_all("#snap line.pending", "ls => ls.map(l => [l.dataset.robot, "
                                        "l.getAttribute('marker-end')])")
    assert len(decided) == 1 and decided[0][0] == "2" and decided[0][1].startswith("url(#")
    page.click("#last")
    assert "defined fails" in page.inner_text("#end")
    page.click("#steps li[data-k='3']")  # a row of the timeline
    assert shown(web) == expected(trace, 3)
    heads = page.eval_on_selector_all("#now line.pending", "ls => ls.map(l => l.getAttribute("
                                      "'marker-end'))")
    assert heads and all(h.startswith("url(#") for h in heads)
    assert page.inner_text("#info .v-class") == "I22"
    x, y = annotate(trace)["states"][3]["target"]  # the target moved (F9): shown per state
    assert page.inner_text("#info .v-target") == f"({x}, {y})" == "(2, 0)"
    assert web.errors == [] and web.remote == []


def test_browser_shows_the_paper_s_rows_only_for_an_algorithm_that_gives_them(web, tmp_path):
    rows = "ths => ths.map(t => t.textContent)"
    page = open_viewer(web, tmp_path, stored(STALE), "paper.html")
    assert page.eval_on_selector_all("#info th", rows) == [
        "class", "phase", "target meeting node", "guard"]
    assert "guard" in page.inner_text("#legend")
    page = open_viewer(web, tmp_path, synthetic_cycle(), "mine.html")  # go-to-target
    assert page.eval_on_selector_all("#info th", rows) == ["class", "target meeting node"]
    assert "guard" not in page.inner_text("#legend")
    assert "\u2014" not in page.inner_text("#info")
    unknown = synthetic_cycle()
    unknown["algorithm"] = "someone-elses"
    page = open_viewer(web, tmp_path, unknown, "unknown.html")
    assert page.eval_on_selector_all("#info th", rows) == ["class", "algorithm"]
    assert "not loaded" in page.inner_text("#info")
    assert "target meeting node" not in page.inner_text("#legend")
    page = open_viewer(web, tmp_path, stored(CYCLE_ASYNC), "cycle.html")
    assert "null" not in page.inner_text("#verdict")  # a cycle's move-bound has no max_moves
    assert web.errors == [] and web.remote == []


def test_browser_marks_and_loops_the_cycle(web, tmp_path):
    trace = stored(CYCLE_ASYNC)
    page = open_viewer(web, tmp_path, trace)
    cs, n = trace["cycle_start"], len(trace["steps"])
    marker = page.inner_text("#cycle-marker")
    assert f"states {cs}\u2013{n}" in marker and f"state {n} equals state {cs}" in marker
    in_cycle = page.eval_on_selector_all("#steps li.in-cycle", "ls => ls.map(l => Number(l.dataset.k))")
    assert in_cycle == list(range(cs + 1, n + 1))
    assert page.is_visible("#loop")
    page.keyboard.press("l")  # loop the cycle: it starts at the cycle's first state
    assert shown(web)["step"] == cs
    page.clock.run_for(900 * (n - cs) + 100)  # one turn of the cycle
    assert shown(web)["step"] == n
    page.clock.run_for(900)  # the turn after: back into the cycle, not to the start
    assert shown(web) == expected(trace, cs + 1)
    assert page.evaluate("window.viewer.pass()") == 1
    assert "pass 2" in page.inner_text("#counter")
    page.keyboard.press("l")  # off again: stepping stops at the end
    page.click("#last")
    page.keyboard.press("ArrowRight")
    assert shown(web)["step"] == n
    assert web.errors == [] and web.remote == []


def test_browser_livelock_and_deadlock_pages_load_cleanly(web, tmp_path):
    for name, scenario in (("f6.html", F6), ("f4.html", F4)):
        trace = checked(tmp_path, scenario, "fsync")
        page = open_viewer(web, tmp_path, trace, name)
        page.keyboard.press("End")
        assert shown(web) == expected(trace, len(trace["steps"]))
        assert f"{trace['property']} fails" in page.inner_text("#end")
        labels = page.eval_on_selector_all("#now text.xlabel", "ts => ts.map(t => t.textContent)")
        assert labels and labels == [str(x) for x in range(int(labels[0]), int(labels[-1]) + 1)]
        if trace["cycle_start"] is not None:
            assert page.is_visible("#cycle-marker .tag")
    assert web.errors == [] and web.remote == []


def test_browser_trace_without_events(web, tmp_path):
    """A violation in the initial state (no event at all) still shows the state and the end."""
    from gather_verify.model.configuration import Configuration
    from gather_verify.trace import build_trace

    trace = build_trace(Configuration([(0, 0), (1, 0)], [(3, 3)], initial=True), "go-to-target",
                        "async", "local-weak", "all", [], "final", "an initial deadlock")
    page = open_viewer(web, tmp_path, trace)
    assert shown(web) == expected(trace, 0)
    page.keyboard.press("ArrowRight")
    assert shown(web)["step"] == 0 and "final fails" in page.inner_text("#end")
    assert web.errors == [] and web.remote == []


@pytest.mark.parametrize("broken", ["throw", "wrong-state"])
def test_browser_test_catches_a_broken_viewer(web, tmp_path, broken):
    """The browser checks fail on a viewer that errors or shows the wrong state."""
    trace = stored(STALE)
    path = tmp_path / "bad.html"
    page_text = viewer_html(trace)
    if broken == "throw":
        page_text = page_text.replace("render();\n})();", "render(); undefinedFunction();\n})();")
    else:
        page_text = page_text.replace("const state = states[k], info", "const state = states[Math.max(0, k - 1)], info")
    path.write_text(page_text)
    web.page.goto(path.as_uri())
    if broken == "throw":
        assert web.errors
    else:
        web.page.keyboard.press("ArrowRight")
        web.page.keyboard.press("ArrowRight")
        assert shown(web) != expected(trace, 2)
