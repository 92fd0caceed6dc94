"""A user's mistake on the newer surfaces (graph files, world traces and scenarios, results
databases of world sweeps, certificates, options that apply to one world only) is one line
on stderr and exit 2, never a traceback and never taken silently (docs/reliability.md,
"Hostile input")."""

from __future__ import annotations

import json
import sqlite3
import subprocess
import sys
from pathlib import Path

import pytest

from gather_verify.cli import main


def cli(*argv: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "gather_verify", *argv], cwd=cwd,
                          capture_output=True, text=True, timeout=180)


def refused(capsys: pytest.CaptureFixture[str], argv: list[str], *words: str) -> str:
    """``argv`` run in this process: exit 2 and one line holding ``words``."""
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2, err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    for word in words:
        assert word in err, err
    return err


GRAPHS = {  # file name -> (its text, what the line says)
    "parallel.graphml": ('<?xml version="1.0"?><graphml xmlns="http://graphml.graphdrawing.org/'
                         'xmlns"><graph edgedefault="undirected"><node id="a"/><node id="b"/>'
                         '<node id="c"/><edge source="a" target="b"/><edge source="a" '
                         'target="b"/><edge source="b" target="c"/></graph></graphml>',
                         "more than one edge between a and b"),
    "multi.gml": ('graph [\n multigraph 1\n node [ id 0 label "a" ]\n node [ id 1 label "b" ]\n'
                  ' node [ id 2 label "c" ]\n edge [ source 0 target 1 ]\n'
                  ' edge [ source 0 target 1 ]\n edge [ source 1 target 2 ]\n]\n',
                  "more than one edge between a and b"),
    "labels.gml": ('graph [\n node [ id 0 label "1" ]\n node [ id 1 label 1 ]\n'
                   ' node [ id 2 label "c" ]\n edge [ source 0 target 1 ]\n'
                   ' edge [ source 1 target 2 ]\n]\n', "two nodes are both written '1'"),
}


@pytest.mark.parametrize("name", sorted(GRAPHS))
def test_a_graph_file_that_is_no_simple_graph_is_one_line(tmp_path, capsys, name):
    """GraphML with parallel edges, GML with ``multigraph 1`` (tracebacks); a connected GML
    graph with labels ``1`` and ``"1"`` (called "not connected")."""
    text, words = GRAPHS[name]
    (tmp_path / name).write_text(text)
    refused(capsys, ["check", "--world", f"graph:{tmp_path / name}", "--robots", "a",
                     "--meeting", "c"], words)


@pytest.mark.parametrize("ids", ["² 1\n1 2\n", "--5 1\n1 2\n", "٣ 1\n1 2\n"])
def test_node_ids_that_look_numeric_are_read(tmp_path, capsys, ids):
    """Graph node ids such as ``²`` or ``--5``: the natural sort called ``isdigit()`` then
    ``int()``, a traceback."""
    (tmp_path / "g.edges").write_text(ids)
    assert main(["check", "--world", f"graph:{tmp_path / 'g.edges'}", "--robots", "1",
                 "--meeting", "2", "--algorithm", "go-to-target"]) == 0
    assert capsys.readouterr().out.startswith("VERIFIED")


def test_regressions_of_a_world_sweep_are_world_scenarios(tmp_path, capsys, monkeypatch):
    """``report --db <a world sweep's database> --regressions DIR``: ``KeyError: 'box'`` on
    an unmodified database. The scenario written passes ``test``."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "stay.py").write_text("class Stay:\n    name = 'stay'\n\n"
                                      "    def decide(self, view):\n        return view.me\n")
    assert main(["sweep", "--world", "ring:5", "--robots", "2", "--meeting", "1", "--algorithm",
                 "stay.py:Stay", "--workers", "1", "--db", "r.sqlite"]) == 1
    assert main(["report", "--db", "r.sqlite", "--regressions", "reg"]) == 0
    written = sorted((tmp_path / "reg").iterdir())
    assert written and json.loads(written[0].read_text())["world"] == "ring:5"
    capsys.readouterr()
    assert main(["test", "reg"]) == 0


def test_a_world_check_stopped_by_the_watchdog_prints_its_line(tmp_path, capsys):
    """``check --world ring:6 ... --max-seconds 2`` with a ``decide`` that never returns: the
    INCOMPLETE line, then ``KeyError: 'engine'``."""
    (tmp_path / "loop.py").write_text("class Loop:\n    name = 'loop'\n\n    def decide(self, v):"
                                      "\n        while True:\n            pass\n")
    code = main(["check", "--world", "ring:6", "--robots", "0 3", "--meeting", "1",
                 "--algorithm", f"{tmp_path}/loop.py:Loop", "--max-seconds", "0.2"])
    out, err = capsys.readouterr()
    assert code == 3 and err == "", err
    assert out.startswith("INCOMPLETE") and "engine bulk" in out


def _world_trace(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> dict:
    (tmp_path / "stay.py").write_text("class Stay:\n    name = 'stay'\n\n"
                                      "    def decide(self, view):\n        return view.me\n")
    main(["check", "--world", "ring:6", "--robots", "0 3", "--meeting", "1", "--algorithm",
          f"{tmp_path}/stay.py:Stay", "--trace-out", str(tmp_path / "t.json")])
    capsys.readouterr()
    return json.loads((tmp_path / "t.json").read_text())


@pytest.mark.parametrize("field", ["property", "steps", "reason", "task"])
@pytest.mark.parametrize("command", ["check", "test"])
def test_a_world_scenario_with_a_partial_trace_is_refused_by_check_and_test(tmp_path, capsys,
                                                                            field, command):
    """``test`` on a world scenario with a partial ``trace``: ``KeyError: 'property'``, while
    ``check`` accepted the same file."""
    trace = _world_trace(tmp_path, capsys)
    del trace[field]
    scenario = tmp_path / "s.json"
    scenario.write_text(json.dumps({"world": "ring:6", "robots": [0, 3], "meeting_nodes": [1],
                                    "algorithm": "stay.py:Stay", "trace": trace}))
    refused(capsys, [command, str(scenario)], f"'{field}' must be", "its trace")


@pytest.fixture(scope="module")
def swept(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A sweep's database with counterexamples (their traces), made once."""
    db = tmp_path_factory.mktemp("swept") / "r.sqlite"
    assert main(["sweep", "--robots", "2", "--meeting", "1", "--box", "2x2", "--algorithm",
                 "broken-away", "--workers", "1", "--db", str(db)]) == 1
    return db


@pytest.mark.parametrize("damage, words", [
    ("UPDATE results SET ratio = 'abc'", "ratio holds 'abc', not a number"),
    ("UPDATE results SET robots = '[[0,'", "robots holds '[[0,', not a JSON list"),
    ("UPDATE results SET failing = '[\"fin'", "failing holds"),
    ("UPDATE results SET trace = '{\"a\":' WHERE trace IS NOT NULL", "trace holds"),
    ("UPDATE results SET class = NULL", "class holds NULL"),
    ("UPDATE results SET verdict = 'MAYBE'", "not a verdict"),
    ("UPDATE sweeps SET settings = '{\"x\":'", "not a JSON object"),
    ("UPDATE sweeps SET settings = '{}'", "its settings lack"),
])
@pytest.mark.parametrize("output", [[], ["--json"], ["--html", "r.html"],
                                    ["--regressions", "reg"]])
def test_report_on_a_damaged_database_is_one_line(tmp_path, capsys, monkeypatch, swept,
                                                  damage, words, output):
    """``report`` on a database whose ``ratio`` holds text, whose ``robots`` is not JSON,
    whose ``failing`` or ``trace`` is truncated JSON, or whose ``class`` is NULL."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "r.sqlite").write_bytes(swept.read_bytes())
    with sqlite3.connect("r.sqlite") as con:
        con.execute(damage)
    capsys.readouterr()
    refused(capsys, ["report", "--db", "r.sqlite", *output], "a damaged results database",
            words)


@pytest.mark.parametrize("edit, words", [
    ({"robots": 2}, "instance field 'robots' is 2, not text"),
    ({"lights": 2}, "instance field 'lights' is 2"),
    ({"visibility": "1"}, "instance field 'visibility' is \"1\""),
])
def test_a_certificate_with_fields_of_the_wrong_type_is_rejected_in_one_line(
        tmp_path, capsys, edit, words):
    """``synthesize --verify`` of a certificate with integer ``robots`` or ``lights``, or
    ``"visibility": "1"`` ("'<' not supported between...")."""
    cert = tmp_path / "c.json"
    assert main(["synthesize", "--world", "ring:6", "--robots", "0 3", "--scheduler", "fsync",
                 "--task", "gathering", "--certificate", str(cert),
                 "--witness", str(tmp_path / "w.py")]) == 1
    doc = json.loads(cert.read_text())
    doc["instance"].update(edit)
    cert.write_text(json.dumps(doc))
    capsys.readouterr()
    assert main(["synthesize", "--verify", str(cert)]) == 1
    err = capsys.readouterr().err
    assert err.startswith("certificate REJECTED") and len(err.strip().splitlines()) == 1
    assert words in err, err


def test_a_certificate_nested_100000_deep_is_one_line(tmp_path, capsys):
    cert = tmp_path / "deep.json"
    cert.write_text('{"format": "gather-verify synthesis certificate 1", "tree": '
                    + "[" * 100_000 + "0" + "]" * 100_000 + "}")
    refused(capsys, ["synthesize", "--verify", str(cert)], "nested too deeply")


def test_a_positional_scenario_is_never_ignored_with_a_world(tmp_path, capsys):
    """``check nonexistent.json --world ring:6 --robots "0 3" --meeting 1`` said VERIFIED,
    exit 0; ``--colours 1 0`` turned its ``0`` into that positional."""
    refused(capsys, ["check", str(tmp_path / "nonexistent.json"), "--world", "ring:6",
                     "--robots", "0 3", "--meeting", "1"], "no such file")
    scenario = tmp_path / "s.json"
    scenario.write_text(json.dumps({"world": "ring:6", "robots": [0, 3], "meeting_nodes": [1]}))
    refused(capsys, ["check", str(scenario), "--world", "ring:7"], "a scenario of ring:6")
    assert main(["check", "--world", "ring:6", "--robots", "0 3", "--meeting", "1",
                 "--lights", "2", "--colours", "1", "0", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["verdict"] == "VERIFIED"


@pytest.mark.parametrize("robots, meeting, words", [
    ("0 0", "1", "node 0 is given twice"), ("0 2", "1 1", "node 1 is given twice")])
def test_a_finite_world_refuses_two_robots_on_a_node_and_a_repeated_meeting_node(
        capsys, robots, meeting, words):
    refused(capsys, ["check", "--world", "ring:6", "--robots", robots, "--meeting", meeting],
            words)


@pytest.mark.parametrize("node", [1.0, [1], "1", True, 0.5])
def test_a_node_of_the_wrong_json_type_is_named_as_written(tmp_path, capsys, node):
    """A float, list or string node in a trace or scenario read "-1 is not a node of ring:6";
    ``true`` was taken as node 1."""
    scenario = tmp_path / "s.json"
    scenario.write_text(json.dumps({"world": "ring:6", "robots": [node, 3],
                                    "meeting_nodes": [2]}))
    refused(capsys, ["check", str(scenario)], f"{json.dumps(node)} is not a node of ring:6")


@pytest.mark.parametrize("field", ["robots", "meeting_nodes", "step"])
@pytest.mark.parametrize("node", [1.0, [1], "1", True])
def test_a_trace_s_node_of_the_wrong_json_type_is_named_as_written(tmp_path, capsys, field,
                                                                   node):
    """The same in a world trace given to ``replay``: its robots, meeting nodes or a step."""
    trace = _world_trace(tmp_path, capsys)
    if field == "step":
        trace["steps"][0]["robots"][0][0] = node
    else:
        trace[field][0] = node
    (tmp_path / "t.json").write_text(json.dumps(trace))
    refused(capsys, ["replay", str(tmp_path / "t.json")],
            f"{json.dumps(node)} is not a node of ring:6")


@pytest.mark.parametrize("argv, words", [
    (["check", "--world", "ring:５", "--robots", "0 1"], "digits 0-9"),
    (["check", "--world", "ring:٥", "--robots", "0 1"], "digits 0-9"),
    (["check", "--world", "ring:0", "--robots", "0 1"], "a ring has at least 3 nodes"),
    (["check", "--world", "ring:6", "--robots", "0 1", "--lights", ""], "--lights ''"),
    (["check", "--world", "ring:6", "--robots", "0 1", "--lights", "2:"], "--lights '2:'"),
    (["check", "--world", "ring:6", "--robots", "0 1", "--move-bound-c", "2"],
     "--move-bound-c is an option of the paper's world"),
    (["sweep", "--world", "ring:6", "--robots", "2", "--move-bound-c", "2"],
     "--move-bound-c is an option of the paper's world"),
    (["synthesize", "--world", "ring:5", "--robots", "2", "--together"],
     "--together goes with --box"),
    (["synthesize", "--world", "grid", "--robots", "0,0 1,1", "--meeting", "0,1",
      "--together"], "--together asks one algorithm for every configuration of a box"),
    (["check", "--world", "ring:12", "--robots", "٠ 1"], "'٠' is not a node of ring:12"),
    (["check", "--world", "ring:12", "--robots", "1_0 2"], "'1_0' is not a node of ring:12"),
    (["check", "--world", "grid:3x3", "--robots", "0,٠ 1,1"], "'0,٠' is not a node"),
    (["check", "--world", "ring:6", "--robots", "0 3", "--lights", "2", "--colours", "١ 0"],
     "--colours '١ 0'"),
    (["synthesize", "--world", "ring:6", "--robots", "٢"], "'٢' is not a node of ring:6"),
])
def test_options_taken_silently_are_refused(capsys, argv, words):
    """``ring:５``, ``ring:٥``, ``--lights ''``, ``--lights 2:`` were accepted;
    ``--move-bound-c`` on a world and ``synthesize --together`` without ``--box`` ignored;
    ``ring:0`` said "out of range [1, 10000]" though a ring needs 3 nodes. Likewise a node or
    a colour written with other digits than 0-9 (``int`` takes ``٠`` and ``1_0``)."""
    refused(capsys, argv, words)


def test_a_graph_trace_without_a_digest_names_the_changed_graph(tmp_path, capsys):
    """A world trace without ``graph_digest`` replayed on a changed file exited 5 instead of
    naming the graph."""
    graph = tmp_path / "g.edges"
    graph.write_text("0 1\n1 2\n2 3\n3 0\n")
    (tmp_path / "stay.py").write_text("class Stay:\n    name = 'stay'\n\n"
                                      "    def decide(self, view):\n        return view.me\n")
    main(["check", "--world", f"graph:{graph}", "--robots", "0 2", "--meeting", "1",
          "--algorithm", f"{tmp_path}/stay.py:Stay", "--trace-out", str(tmp_path / "t.json")])
    trace = json.loads((tmp_path / "t.json").read_text())
    del trace["graph_digest"]
    (tmp_path / "t.json").write_text(json.dumps(trace))
    capsys.readouterr()
    assert main(["replay", str(tmp_path / "t.json")]) == 1  # the same graph: it replays
    capsys.readouterr()
    graph.write_text("0 1\n1 2\n2 3\n3 0\n0 2\n")  # another graph under the same name
    refused(capsys, ["replay", str(tmp_path / "t.json")], f"the graph file of graph:{graph}")


def test_test_on_a_device_says_what_it_is(capsys):
    """``test /dev/zero`` said "no such file or folder"."""
    refused(capsys, ["test", "/dev/zero"], "a character device, not a file")


def test_ring_sweeps_speak_of_their_world_and_name_the_failing_configurations(
        tmp_path, capsys, monkeypatch):
    """Ring sweeps listed the classes I11 ... I42 (all zero) in their JSON, showed a
    moves/(D·n) column and the grid's properties in their HTML report, and said nowhere
    which configurations failed."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "stay.py").write_text("class Stay:\n    name = 'stay'\n\n"
                                      "    def decide(self, view):\n        return view.me\n")
    argv = ["sweep", "--world", "ring:5", "--robots", "2", "--meeting", "1", "--algorithm",
            "stay.py:Stay", "--workers", "1", "--db", "r.sqlite"]
    assert main([*argv, "--json"]) == 1
    summary = json.loads(capsys.readouterr().out)
    assert set(summary["classes"]) == {"ring:5"} and summary["plane"] is False
    assert summary["failing_configurations"][0] == {
        "class": "ring:5", "robots": [0, 1], "meeting_nodes": [0], "property": "final"}
    assert len(summary["failing_configurations"]) == summary["verdicts"]["ring:5"]["VIOLATED"]
    assert main(argv) == 1
    text = capsys.readouterr().out
    assert "failing configurations" in text and "ring:5  robots=[0, 1] meeting=[0]: final" in text
    assert "max ratio" not in text and "I11" not in text
    assert main(["report", "--db", "r.sqlite", "--html", "r.html"]) == 0
    page = (tmp_path / "r.html").read_text()
    assert "D·n" not in page and "no-ungatherable" not in page and "move-bound" not in page


def test_check_help_says_where_each_option_applies(capsys):
    """``check --help`` offered ``--property FILE.py:NAME`` and ``--graph-out``, which rings
    refuse."""
    with pytest.raises(SystemExit):
        main(["check", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    for option in ("--graph-out FILE the paper's world only", "--margin MARGIN the paper's "
                   "world only", "--force the paper's world only", "on a finite world a part "
                   "of the --task"):
        assert option in text, option


def test_the_semantics_page_says_synthesis_is_built():
    """docs/explanation/semantics.md §12 still said synthesis is not built."""
    page = (Path(__file__).parent.parent / "docs/explanation/semantics.md").read_text()
    section = page[page.index("## §12 Synthesis"):]
    assert "Not built" not in section and "gather-verify synthesize" in section
