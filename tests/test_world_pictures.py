"""Pictures of finite worlds: each world's drawing (rings as circles, a finite grid's border, a
torus's wrap-around, a graph file's fixed layout), the SVG storyboard drawn from it (node
counts, the same bytes every time), the report of a world sweep, and, in a real browser, the
viewer on a ring and on a graph file: one circle per node, the robots on their nodes, the
failing property, stepping, stale snapshots, visited nodes, lights. Hostile node names show as
text. The browser tests skip with the reason where chromium or Playwright is missing."""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from gather_verify.cli import main
from gather_verify.render import thumbnail_svg, trace_svg
from gather_verify.viewer import annotate, viewer_html, write_viewer
from gather_verify.world_check import run_world_check
from gather_verify.worlds import get_world

ROOT = Path(__file__).resolve().parent.parent
PETERSEN = ROOT / "scenarios/worlds/petersen.graphml"
NS = "{http://www.w3.org/2000/svg}"


def text(label) -> str:
    """A node label of a trace as the pictures write it."""
    return ",".join(map(str, label)) if isinstance(label, list) else str(label)


def ring_trace() -> dict:
    """ring-explore without a common direction under ASYNC: r1 moves on a stale snapshot onto
    the node r0 just reached (exclusivity)."""
    r = run_world_check("ring:6", "0 3", "", "ring-explore", "async",
                        task="exclusive-perpetual-exploration")
    assert r["property"] == "exclusivity"
    return r["trace"]


def graph_trace(path: Path = PETERSEN, robots: str = "p0 p7", meeting: str = "p3") -> dict:
    """go-to-target on the Petersen graph, checked for exploration with stop: both robots stop
    on the meeting node with nodes never visited."""
    r = run_world_check(f"graph:{path}", robots, meeting, "go-to-target", "async",
                        task="exploration-with-stop")
    assert r["property"] == "explored-when-final"
    return r["trace"]


def torus_trace() -> dict:
    """go-to-target on a torus: r0 reaches the meeting node across the wrap-around."""
    r = run_world_check("torus:4x3", "0,0 2,1", "3,2", "go-to-target", "ssync",
                        task="exploration-with-stop")
    assert r["property"] == "explored-when-final"
    return r["trace"]


def grid_trace() -> dict:
    """go-to-target on a finite grid: the robots stop on the meeting node, nodes unvisited."""
    r = run_world_check("grid:3x3", "0,0 2,2", "1,1", "go-to-target", "async",
                        task="exploration-with-stop")
    assert r["property"] == "explored-when-final"
    return r["trace"]


def lit_trace() -> dict:
    """The luminous yardstick bounce: two robots lit 1 step onto one node."""
    r = run_world_check("ring:6", "0 2", "", "bounce", "ssync", lights="2",
                        task="exclusive-perpetual-exploration")
    assert r["property"] == "exclusivity"
    return r["trace"]


# -- what each world says about its drawing ----------------------------------------------------

@pytest.mark.parametrize("spec", ["ring:3", "ring:7", "grid:3x2", "grid:1x4", "torus:3x4",
                                  "torus:5x5", f"graph:{PETERSEN}"])
def test_a_drawing_has_every_node_and_every_edge_once(spec):
    world = get_world(spec)
    d = world.drawing()
    assert [n["label"] for n in d["nodes"]] == [world.node_to_json(v) for v in range(world.size)]
    assert [n["text"] for n in d["nodes"]] == [world.format_node(v) for v in range(world.size)]
    ends = sorted(tuple(sorted(e["ends"])) for e in d["edges"])
    assert ends == sorted((a, b) for a in range(world.size) for b in world.adjacency[a] if a < b)
    for n in d["nodes"]:
        assert math.isclose(math.hypot(*n["side"]), 1, abs_tol=1e-3)
    json.dumps(d)  # JSON, nothing else


def test_a_ring_is_a_circle_with_arcs():
    d = get_world("ring:8").drawing()
    radii = {round(math.hypot(n["x"], n["y"]), 3) for n in d["nodes"]}
    assert len(radii) == 1 and d["outline"] is None
    (radius,) = radii
    for e in d["edges"]:  # every point of an arc lies on the circle
        assert len(e["lines"]) == 1 and len(e["lines"][0]) > 2
        assert all(math.isclose(math.hypot(*p), radius, abs_tol=2e-3) for p in e["lines"][0])
    adjacent = [math.dist((d["nodes"][a]["x"], d["nodes"][a]["y"]),
                          (d["nodes"][b]["x"], d["nodes"][b]["y"])) for a, b in
                (e["ends"] for e in d["edges"])]
    assert all(math.isclose(x, 1, abs_tol=1e-3) for x in adjacent)  # scaled: an edge is 1 long


def test_a_finite_grid_has_its_border_and_no_wrap():
    d = get_world("grid:4x3").drawing()
    assert d["outline"]["wraps"] is False and "border" in d["outline"]["title"]
    xs = [p[0] for p in d["outline"]["points"]]
    assert (min(xs), max(xs)) == (-0.5, 3.5)
    assert not any(e.get("wraps") for e in d["edges"])


def test_a_torus_wraps_around_with_stubs_across_its_seam():
    w, h = 4, 3
    d = get_world(f"torus:{w}x{h}").drawing()
    wraps = [e for e in d["edges"] if e.get("wraps")]
    assert len(wraps) == w + h and d["outline"]["wraps"] is True
    for e in wraps:  # two stubs: one leaves its node to the seam, one comes back in
        (a, b), (first, second) = e["ends"], e["lines"]
        na, nb = d["nodes"][a], d["nodes"][b]
        assert first[0] == [na["x"], na["y"]] and second[-1] == [nb["x"], nb["y"]]
        assert math.isclose(math.dist(*first), 0.5) and math.isclose(math.dist(*second), 0.5)


def test_a_graph_file_is_laid_out_the_same_way_every_time(tmp_path):
    """The layout has a fixed seed: the same file gives the same drawing, from another path
    and in another process (another hash seed)."""
    first = get_world(f"graph:{PETERSEN}").drawing()
    copy = tmp_path / "elsewhere.graphml"
    shutil.copy(PETERSEN, copy)
    assert get_world(f"graph:{copy}").drawing() == first
    code = ("import json, sys; from gather_verify.worlds import get_world; "
            "print(json.dumps(get_world(sys.argv[1]).drawing(), sort_keys=True))")
    run = subprocess.run([sys.executable, "-c", code, f"graph:{copy}"], capture_output=True,
                         text=True, check=True, cwd=ROOT,
                         env={**os.environ, "PYTHONHASHSEED": "12345"})
    assert run.stdout.strip() == json.dumps(first, sort_keys=True)
    # no two nodes overlap: they are at least 0.625 edge lengths apart
    nodes = [(n["x"], n["y"]) for n in first["nodes"]]
    assert min(math.dist(p, q) for i, p in enumerate(nodes) for q in nodes[i + 1:]) >= 0.62


# -- the trace carries the drawing, and the visited nodes -------------------------------------

def test_a_world_trace_carries_its_drawing_and_the_visited_nodes():
    trace = ring_trace()
    assert trace["drawing"] == get_world("ring:6").drawing()
    # exclusive perpetual exploration keeps no visited set in its states: the trace counts it
    visited = [step["visited"] for step in trace["steps"]]
    assert visited[0] == [0, 3] and visited[-1] == [0, 1, 2, 3]
    assert all(set(a) <= set(b) for a, b in zip(visited, visited[1:], strict=False))
    # exploration with stop carries it in the state
    assert graph_trace()["steps"][-1]["visited"] == ["p0", "p2", "p3", "p4", "p7"]


def test_the_viewer_data_of_a_world_trace():
    data = annotate(ring_trace())
    assert [r["node"] for r in data["robots"][0]] == [0, 3]
    stale = [d for e in data["events"] for d in e["decisions"] if d["stale"]]
    assert stale == [{"robot": 1, "look": 4, "snapshot": 3, "stale": True,
                      "moved_since": ["r0"], "relit_since": []}]
    assert data["events"][0]["text"] == "look(r0): r0 decides 1"
    lit = annotate(lit_trace())
    assert lit["states"][1]["colours"] == [1, 1]
    assert lit["events"][0]["text"] == "round(r0,r1): r0 light 0->1, r1 light 0->1"


def test_a_broken_world_trace_is_refused_in_one_line():
    from gather_verify.errors import InvalidInput

    trace = ring_trace()
    trace["steps"][2]["robots"][0][0] = 99
    with pytest.raises(InvalidInput, match="99 is not a node"):
        viewer_html(trace)
    trace = ring_trace()
    trace["drawing"]["nodes"][0]["x"] = "left"
    with pytest.raises(InvalidInput, match="finite number"):
        trace_svg(trace)


# -- SVG -----------------------------------------------------------------------------------------

def svg_nodes(svg: str) -> list[str]:
    root = ET.fromstring(svg)  # well-formed
    return [c.get("data-node") for c in root.iter(f"{NS}circle")
            if (c.get("class") or "").split()[:1] == ["node"]]


@pytest.mark.parametrize("make,size", [(ring_trace, 6), (grid_trace, 9), (torus_trace, 12),
                                       (graph_trace, 10)])
def test_storyboard_of_every_world(make, size):
    trace = make()
    svg = trace_svg(trace)
    panels = len(trace["steps"])
    names = svg_nodes(svg)
    assert len(names) == size * panels  # one circle per node, in each panel
    assert names[:size] == [n["text"] for n in trace["drawing"]["nodes"]]
    assert trace_svg(json.loads(json.dumps(trace))) == svg  # the same bytes every time
    robots = [c for c in ET.fromstring(svg).iter(f"{NS}circle") if c.get("class") == "robot"]
    assert len(robots) == len(trace["robots"]) * panels
    # the last panel: each robot on its node
    last = robots[-len(trace["robots"]):]
    assert [c.get("data-node") for c in last] == [text(v) for v, _ in trace["steps"][-1]["robots"]]
    thumb = thumbnail_svg(trace, uid="x")
    assert len(svg_nodes(thumb)) == 2 * size and thumbnail_svg(trace, uid="x") == thumb


def test_storyboard_shows_what_each_world_adds():
    trace = torus_trace()
    torus = trace_svg(trace)
    assert 'class="edge wrap"' in torus and 'class="outline seam"' in torus
    # the moves just made: r0 0,0 -> 3,0 and 3,0 -> 3,2 across the seam (two pieces each, the
    # head on the second), r1 2,1 -> 2,2 -> 3,2 inside (one piece each)
    assert [e["event"]["moves"] for e in trace["steps"][1:]] == [
        [[0, [0, 0], [3, 0]], [1, [2, 1], [2, 2]]], [[0, [3, 0], [3, 2]], [1, [2, 2], [3, 2]]]]
    assert torus.count('stroke="#999" stroke-width="2"') == 6
    assert torus.count('marker-end="url(#s-m-done)"') == 4
    grid = trace_svg(grid_trace())
    assert 'class="outline border"' in grid and "edge wrap" not in grid
    ring = trace_svg(ring_trace())
    assert "<polyline" in ring and "outline" not in ring  # arcs, no border
    words = " ".join(t.text or "" for t in ET.fromstring(ring).iter(f"{NS}tspan"))
    assert "STALE: r1 moves on its Look at event 4; since then r0 moved" in words
    lit = trace_svg(lit_trace())
    assert lit.count('class="light"') == 2 * 3 and 'data-colour="1"' in lit
    graph = trace_svg(graph_trace())
    assert graph.count('class="meeting"') == len(graph_trace()["steps"])
    assert 'class="node visited"' in graph and "visited 5/10" in graph
    assert "r0 r1 on p3" in graph


def test_cli_check_writes_the_same_pictures_of_a_graph_file_twice(tmp_path, capsys):
    outs = []
    for k in (1, 2):
        svg, html = tmp_path / f"g{k}.svg", tmp_path / f"g{k}.html"
        code = main(["check", "--world", f"graph:{PETERSEN}", "--robots", "p0 p7", "--meeting",
                     "p3", "--task", "exploration-with-stop", "--scheduler", "async",
                     "--svg", str(svg), "--html", str(html)])
        assert code == 1
        outs.append((svg.read_bytes(), html.read_bytes()))
    assert outs[0] == outs[1]
    assert main(["check", "--world", "ring:6", "--robots", "0 3", "--algorithm", "go-to-target",
                 "--meeting", "1", "--html", str(tmp_path / "none.html")]) == 0
    assert "no counterexample trace" in capsys.readouterr().err
    assert not (tmp_path / "none.html").exists()


def test_report_of_a_world_sweep(tmp_path):
    db, out = tmp_path / "w.sqlite", tmp_path / "report.html"
    main(["sweep", "--world", "ring:6", "--robots", "2", "--meeting", "0", "--algorithm",
          "ring-gather", "--multiplicity", "global-weak", "--task", "gathering", "--scheduler",
          "ssync", "--workers", "1", "--db", str(db)])
    assert main(["report", "--db", str(db), "--html", str(out)]) == 0
    page = out.read_text()
    assert "gather-verify check --world ring:6 --robots &quot;0 1&quot; --algorithm ring-gather" \
        " --scheduler ssync --task gathering --multiplicity global-weak --html trace.html" in page
    thumbs = re.findall(r"<figure><a href='([^']+)'[^>]*>(<svg.*?</svg>)</a>", page, re.S)
    assert thumbs
    for viewer, svg in thumbs:
        assert len(svg_nodes(svg)) == 2 * 6
        assert '"drawing"' in (tmp_path / viewer).read_text()
    assert "plot-1.png" not in page  # moves against D·n: a Z² notion


# -- in a real browser ---------------------------------------------------------------------

def open_viewer(web, tmp_path: Path, trace: dict, name: str = "v.html"):
    path = tmp_path / name
    write_viewer(trace, str(path))
    web.page.clock.install()  # timers run only when the test says so
    web.page.goto(path.as_uri())
    return web.page


def shown(page) -> list[list]:
    """Each robot drawn now: its identity, its node, its pending move and how far its disc
    lies from the node's circle."""
    return page.evaluate("""() => {
      const node = {};
      for (const c of document.querySelectorAll('#now circle.node'))
        node[c.dataset.node] = [Number(c.getAttribute('cx')), Number(c.getAttribute('cy'))];
      return [...document.querySelectorAll('#now g.robot')].map(g => {
        const disc = g.querySelectorAll('circle');
        const c = disc[disc.length - 1].classList.contains('light') ? disc[disc.length - 2]
                  : disc[disc.length - 1];
        const at = node[g.dataset.node];
        return [Number(g.dataset.robot), g.dataset.node, g.dataset.pending,
                Math.hypot(Number(c.getAttribute('cx')) - at[0], Number(c.getAttribute('cy')) - at[1])];
      }).sort((a, b) => a[0] - b[0]);
    }""")


def expected(trace: dict, k: int) -> list[list]:
    return [[i, text(v), "" if p is None else text(p)]
            for i, (v, p) in enumerate(trace["steps"][k]["robots"])]


def check_every_step(web, page, trace: dict, size: int) -> None:
    """Stepping forward from the start, every state shows each robot on its node."""
    n = len(trace["steps"]) - 1
    seen = set()
    for k in range(n + 1):
        if k:
            page.keyboard.press("ArrowRight")
        assert int(page.eval_on_selector("body", "b => b.dataset.step")) == k
        assert page.eval_on_selector_all("#now circle.node", "cs => cs.length") == size
        now = shown(page)
        assert [r[:3] for r in now] == expected(trace, k), k
        assert all(r[3] < 0.3 * 84 for r in now)  # the disc on (or beside, in a tower) its node
        seen.add(json.dumps([r[1] for r in now]))
        visited = page.eval_on_selector_all("#now circle.node.visited", "cs => cs.map(c => "
                                            "c.dataset.node)")
        assert sorted(visited) == sorted(text(v) for v in trace["steps"][k].get("visited", []))
    assert len(seen) > 1  # stepping forward moved the robots
    assert f"{trace['property']} fails" in page.inner_text("#verdict")
    assert f"{trace['property']} fails" in page.inner_text("#end")
    assert web.errors == [] and web.remote == []


def test_browser_ring_counterexample(web, tmp_path):
    trace = ring_trace()
    page = open_viewer(web, tmp_path, trace)
    labels = page.eval_on_selector_all("#now circle.node", "cs => cs.map(c => c.dataset.node)")
    assert labels == [str(v) for v in range(6)]
    # the nodes lie on a circle
    places = page.eval_on_selector_all("#now circle.node", "cs => cs.map(c => "
                                       "[Number(c.getAttribute('cx')), Number(c.getAttribute('cy'))])")
    cx, cy = (sum(p[0] for p in places) / 6, sum(p[1] for p in places) / 6)
    assert max(math.dist(p, (cx, cy)) for p in places) - min(math.dist(p, (cx, cy))
                                                            for p in places) < 1
    check_every_step(web, page, trace, 6)
    # the last event: r1 moves on the snapshot of its Look at event 4, after r0 moved
    assert page.is_visible("#snap-fig") and "Stale snapshot" in page.inner_text("#decision")
    snapshot = page.eval_on_selector_all("#snap g.robot", "gs => gs.map(g => g.dataset.node)")
    assert sorted(snapshot) == ["1", "3"]
    assert page.eval_on_selector_all("#snap .pending", "ls => ls.map(l => l.dataset.robot)") == ["1"]
    assert page.eval_on_selector("#now text.count", "t => [t.dataset.node, t.textContent]") \
        == ["2", "\u00d72"]  # two robots on node 2
    page.keyboard.press("Home")
    page.keyboard.press("ArrowRight")  # r0's Look: a pending move along the arc, with a head
    heads = page.eval_on_selector_all("#now .pending", "ls => ls.map(l => [l.tagName, "
                                      "l.getAttribute('marker-end')])")
    assert len(heads) == 1 and heads[0][0] == "polyline" and heads[0][1].startswith("url(#")


def test_browser_graph_file_counterexample(web, tmp_path):
    trace = graph_trace()
    page = open_viewer(web, tmp_path, trace)
    labels = page.eval_on_selector_all("#now circle.node", "cs => cs.map(c => c.dataset.node)")
    assert labels == [f"p{k}" for k in range(10)]
    assert page.eval_on_selector_all("#now .edge", "es => es.length") == 15
    assert page.eval_on_selector("#now rect.meeting", "r => r.dataset.node") == "p3"
    check_every_step(web, page, trace, 10)
    assert "5 of 10 nodes" in page.inner_text("#info")
    assert "r0, r1 on p3" in page.inner_text("#info")


def test_browser_torus_lights_and_the_failing_node(web, tmp_path):
    trace = torus_trace()
    page = open_viewer(web, tmp_path, trace, "torus.html")
    assert page.eval_on_selector_all("#now .edge.wrap", "es => es.length") == 2 * (4 + 3)
    assert page.eval_on_selector_all("#now polygon.outline.seam", "ps => ps.length") == 1
    check_every_step(web, page, trace, 12)
    page.keyboard.press("Home")
    page.keyboard.press("ArrowRight")  # r0 went 0,0 -> 3,0 across the seam: two grey pieces
    assert page.eval_on_selector_all("#now .moved", "ls => ls.length") == 3
    trace = lit_trace()
    page = open_viewer(web, tmp_path, trace, "lit.html")
    page.keyboard.press("ArrowRight")
    assert page.eval_on_selector_all("#now circle.light", "cs => cs.map(c => c.dataset.colour)") \
        == ["1", "1"]
    assert page.eval_on_selector_all("#robots td.light", "ts => ts.map(t => t.textContent)") \
        == ["1", "1"]
    trace = run_world_check("ring:7", "0 1", "", "ring-inchworm", "async", lights="2",
                            visibility=2, task="exclusive-perpetual-exploration")["trace"]
    page = open_viewer(web, tmp_path, trace, "inchworm.html")
    assert page.eval_on_selector("#now circle.focus", "c => c.dataset.node") == "2"
    assert page.eval_on_selector_all("#now circle.light", "cs => cs.length") == 2  # lit 0
    from gather_verify.model.configuration import Configuration
    from gather_verify.plane_check import run_check  # the paper's world, lit: its header says so

    start = Configuration([(1, 1), (3, 2)], [(0, 0), (4, 0)], initial=True)
    trace = run_check(start, algorithm="beacon", scheduler="ssync", lights="2")["trace"]
    page = open_viewer(web, tmp_path, trace, "beacon.html")
    assert "lights 2" in page.inner_text("#meta")
    assert web.errors == [] and web.remote == []


PAYLOAD = "<img src=x onerror=\"window.__pwned=1\">'\"</script><b id=injected>"


def test_browser_hostile_node_names_show_as_text(web, tmp_path):
    """A graph file whose node ids are markup: the viewer and the SVG show them as text."""
    ids = [PAYLOAD + str(k) for k in range(4)]
    from xml.sax.saxutils import quoteattr

    graphml = ('<?xml version="1.0"?><graphml xmlns="http://graphml.graphdrawing.org/xmlns">'
               '<graph edgedefault="undirected">'
               + "".join(f"<node id={quoteattr(i)}/>" for i in ids)
               + "".join(f"<edge source={quoteattr(ids[k])} target={quoteattr(ids[(k + 1) % 4])}/>"
                         for k in range(4)) + "</graph></graphml>")
    path = tmp_path / "hostile.graphml"
    path.write_text(graphml)
    world = get_world(f"graph:{path}")  # ids with spaces: given as node indices
    r = run_world_check(world, [world.index[ids[0]], world.index[ids[2]]], [world.index[ids[1]]],
                        "go-to-target", "async", task="exploration-with-stop")
    trace = r["trace"]
    assert trace is not None
    trace["reason"] = PAYLOAD
    page = open_viewer(web, tmp_path, trace, "hostile.html")
    for _ in range(len(trace["steps"]) + 1):
        assert page.evaluate("() => window.__pwned === undefined")
        assert page.query_selector("#injected") is None and page.query_selector("img[src=x]") is None
        page.keyboard.press("ArrowRight")
    names = page.eval_on_selector_all("#now circle.node", "cs => cs.map(c => c.dataset.node)")
    assert sorted(names) == sorted(ids)  # shown, as text
    svg = trace_svg(trace)
    root = ET.fromstring(svg)
    assert not [e for e in root.iter() if e.tag.split("}")[-1] in ("img", "script", "b")]
    assert sorted(svg_nodes(svg)[:4]) == sorted(ids)
    (tmp_path / "s.svg").write_text(svg)
    page.goto((tmp_path / "s.svg").as_uri())
    assert page.evaluate("() => window.__pwned === undefined")
    assert web.errors == []


def test_a_hostile_world_database_shows_as_text_in_the_report(web, tmp_path):
    import sqlite3

    db, out = tmp_path / "w.sqlite", tmp_path / "report.html"
    main(["sweep", "--world", "ring:5", "--robots", "2", "--meeting", "0", "--algorithm",
          "ring-gather", "--multiplicity", "global-weak", "--task", "gathering", "--scheduler",
          "fsync", "--workers", "1", "--db", str(db)])
    con = sqlite3.connect(db)
    with con:
        for key, raw in con.execute("SELECT key, trace FROM results").fetchall():
            trace = json.loads(raw)
            for name in ("property", "reason", "algorithm", "world", "task", "lights"):
                trace[name] = PAYLOAD + str(trace[name])
            trace["detail"] = {PAYLOAD: PAYLOAD}
            for node in trace["drawing"]["nodes"]:
                node["text"] = PAYLOAD + node["text"]
            con.execute("UPDATE results SET trace = ?, class = ?, reason = ?, property = ?, "
                        "robots = ? WHERE key = ?", (json.dumps(trace), PAYLOAD, PAYLOAD,
                                                     PAYLOAD, json.dumps([PAYLOAD, 1]), key))
    con.close()
    assert main(["report", "--db", str(db), "--html", str(out)]) == 0
    page = web.page
    for target in [out, *sorted((tmp_path / "report-files").glob("*.html"))]:
        page.goto(target.as_uri())
        for _ in range(3):
            assert page.evaluate("() => window.__pwned === undefined")
            assert page.query_selector("#injected") is None
            assert page.query_selector("img[src=x]") is None
            page.keyboard.press("ArrowRight")
    assert len(list((tmp_path / "report-files").glob("*.html"))) == 1
    assert PAYLOAD.split(" ")[0] in page.inner_text("#verdict")  # the viewer shows it, as text


def test_replay_of_a_world_trace_draws_it(tmp_path, capsys):
    path = tmp_path / "t.json"
    path.write_text(json.dumps(ring_trace()))
    assert main(["replay", str(path), "--html", str(tmp_path / "v.html")]) == 1
    assert "CONFIRMED: exclusivity on ring:6" in capsys.readouterr().out
    assert "ring:6" in (tmp_path / "v.html").read_text()


@pytest.mark.parametrize("broken", ["previous-state", "node-places"])
def test_browser_checks_catch_a_broken_world_viewer(web, tmp_path, broken):
    """The checks above fail on a viewer that draws the state before, or puts the robots at
    the wrong node's place."""
    trace = ring_trace()
    page_text = viewer_html(trace)
    if broken == "previous-state":
        page_text = page_text.replace("const state = states[k], info",
                                      "const state = states[Math.max(0, k - 1)], info")
    else:
        page_text = page_text.replace("const [cx, cy] = at(node), where",
                                      "const [cx, cy] = at((node + 1) % WORLD.nodes.length), where")
    assert page_text != viewer_html(trace)
    path = tmp_path / "bad.html"
    path.write_text(page_text)
    web.page.goto(path.as_uri())
    with pytest.raises(AssertionError):
        check_every_step(web, web.page, trace, 6)
