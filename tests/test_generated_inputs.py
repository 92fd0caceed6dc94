"""Generated hostile input, so that the next hostile test finds nothing: Hypothesis draws
the arguments of every subcommand, and malformed files of each kind (scenario, trace,
certificate, graph, results database), and every run must end with a documented exit code,
one line on stderr for a mistake, and never a traceback (docs/reliability.md).

Budgets are small (the suite stays fast); the commands run in this process, on tiny
configurations, with limits."""

from __future__ import annotations

import json
import shutil
import sqlite3
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gather_verify.cli import build_parser, main
from gather_verify.errors import InvalidInput

DOCUMENTED = {0, 1, 2, 3, 4, 5}
"""The exit codes a command may end with on any input (docs/reliability.md, "Exit codes");
70 is a bug of ours, and never allowed here."""

STAY = "class Stay:\n    name = 'stay'\n\n    def decide(self, view):\n        return view.me\n"


def assert_clean(code: int, err: str, what: object) -> None:
    """A documented exit code, no traceback, and one line for a mistake (exit 2)."""
    assert code in DOCUMENTED, (what, code, err)
    assert "Traceback" not in err and "internal error" not in err, (what, err)
    if code == 2:
        assert len(err.strip().splitlines()) == 1, (what, err)


@pytest.fixture(scope="module")
def samples(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """One valid file of each kind, made once: scenarios and traces of the grid and of a
    ring, a certificate, graph files in four formats, and two results databases."""
    home = tmp_path_factory.mktemp("samples")
    (home / "stay.py").write_text(STAY)
    out = {"stay": home / "stay.py"}
    out["scenario"] = home / "grid.json"
    out["scenario"].write_text(json.dumps({
        "robots": [[0, 0], [2, 1]], "meeting_nodes": [[1, 1]], "algorithm": "go-to-target",
        "scheduler": "async", "expect": {"verdicts": [
            {"algorithm": "go-to-target", "scheduler": "async", "verdict": "VERIFIED"}]}}))
    out["world scenario"] = home / "ring.json"
    out["world scenario"].write_text(json.dumps({
        "world": "ring:6", "robots": [0, 3], "meeting_nodes": [1], "algorithm": "go-to-target",
        "task": "gathering-on-meeting-nodes"}))
    out["trace"] = home / "grid-trace.json"
    assert main(["check", "--robots", "0,0 3,1", "--meeting", "2,2", "--algorithm",
                 "broken-away", "--trace-out", str(out["trace"])]) == 1
    out["world trace"] = home / "ring-trace.json"
    assert main(["check", "--world", "ring:6", "--robots", "0 3", "--meeting", "1",
                 "--algorithm", f"{home}/stay.py:Stay", "--trace-out",
                 str(out["world trace"])]) == 1
    out["certificate"] = home / "cert.json"
    assert main(["synthesize", "--world", "ring:6", "--robots", "0 3", "--scheduler", "fsync",
                 "--task", "gathering", "--certificate", str(out["certificate"]),
                 "--witness", str(home / "w.py")]) == 1
    for name, text in (("g.edges", "0 1\n1 2\n2 3\n3 0\n1 3\n"),
                       ("g.adjlist", "0 1 3\n1 2\n2 3\n"),
                       ("g.gml", 'graph [\n node [ id 0 label "0" ]\n node [ id 1 label "1" ]\n'
                                 ' node [ id 2 label "2" ]\n edge [ source 0 target 1 ]\n'
                                 ' edge [ source 1 target 2 ]\n]\n'),
                       ("g.graphml", '<?xml version="1.0"?><graphml xmlns="http://graphml.'
                                     'graphdrawing.org/xmlns"><graph edgedefault="undirected">'
                                     '<node id="0"/><node id="1"/><node id="2"/><edge '
                                     'source="0" target="1"/><edge source="1" target="2"/>'
                                     '</graph></graphml>')):
        out[name] = home / name
        out[name].write_text(text)
    out["database"] = home / "grid.sqlite"
    assert main(["sweep", "--robots", "2", "--meeting", "1", "--box", "2x2", "--algorithm",
                 "broken-away", "--workers", "1", "--db", str(out["database"])]) == 1
    out["world database"] = home / "ring.sqlite"
    assert main(["sweep", "--world", "ring:5", "--robots", "2", "--meeting", "1",
                 "--algorithm", f"{home}/stay.py:Stay", "--workers", "1", "--db",
                 str(out["world database"])]) == 1
    return out


# -- the arguments of every subcommand -----------------------------------------------------

VALUES = ["", " ", "0", "1", "2", "-1", "3-2", "nan", "inf", "1e99", "x", "0,0", "1,1 2,2",
          "0 3", "0 0", "0,0 0,0", "2x2", "0x3", "65x3", "async", "fsync", "ssync",
          "round-robin:order=1 0", "go-to-target", "paper", "paper:alpha", "nope.py:A",
          "ring:6", "ring:0", "ring:５", "ring:5-100000", "grid", "grid:3x3", "torus:3x3",
          "graph:/dev/zero", "graph:/nonexistent.gml", "/dev/zero", "/nonexistent.json", "2:",
          "2:internal", "all", "compass", "chirality", "final", "termination", "gathering",
          "local-weak", "none", "file:x.db?mode=memory", ":memory:", "٣", "²", "--5", "\x00"]
"""Values from the hostile tests: empty, absurd, non-ASCII digits, devices, missing files."""

SAFE = {  # appended to every run: a generated run is small and bounded (limits last win)
    "classify": [], "census": [], "test": [],
    "simulate": ["--max-steps", "20"],
    "check": ["--max-states", "3000", "--max-seconds", "5", "--max-memory-mb", "4000"],
    "replay": [],
    "sweep": ["--limit", "3", "--workers", "1", "--max-states-per-config", "3000",
              "--max-seconds-per-config", "5", "--max-memory-mb", "4000"],
    "report": [],
    "impossibility": ["--max-states", "2000"],
    "synthesize": ["--max-seconds", "5", "--max-candidates", "50", "--max-states", "3000",
                   "--max-memory-mb", "4000"],
}
"""Each command that runs, with the options that keep a generated run small."""

OUTPUTS = ("--trace-out", "--svg", "--html", "--junit", "--graph-out", "--db", "--witness",
           "--certificate", "--regressions", "--plot", "--out", "--verify")
"""Options that name a file or folder: their values are file names in the test's folder."""


def options_of(command: str) -> list[str]:
    """The long options of a command's parser, but ``--help`` and those the run's bounds
    fix (a generated ``--max-states 1e9`` would make a search long, not wrong)."""
    parser = build_parser(command)._subparsers._group_actions[0].choices[command]  # noqa: SLF001
    fixed = set(SAFE.get(command, ())) | {"--dask", "--workers-curve", "--progress",
                                          "--max-steps", "--readings", "--minimum"}
    return sorted(o for a in parser._actions for o in a.option_strings  # noqa: SLF001
                  if o.startswith("--") and o != "--help" and o not in fixed)


def argv_of(command: str, draw: Any, samples: dict[str, Path], folder: Path) -> list[str]:
    """A drawn argument list: options of the command, each with a hostile value, a sample
    file or a file name in ``folder``; perhaps a positional file."""
    files = [str(p) for p in samples.values()] + ["/dev/zero", str(folder / "missing.json")]
    out: list[str] = []
    for option in draw(st.lists(st.sampled_from(options_of(command)), max_size=4)):
        out.append(option)
        if option in OUTPUTS:
            out.append(str(folder / draw(st.sampled_from(["o.json", "o.html", "o.sqlite",
                                                           "d", "missing/o.json"]))))
        elif draw(st.booleans()):
            out.append(draw(st.sampled_from(VALUES + files)))
    if draw(st.booleans()):
        out.insert(0, draw(st.sampled_from(files)))
    return out


RUN = sorted(SAFE)

BASE = {  # a valid run of each command, which the drawn options then change
    "classify": ["--robots", "0,0 2,1", "--meeting", "1,1"],
    "census": ["--box", "2x2", "--robots", "2", "--meeting", "1"],
    "simulate": ["--robots", "0,0 2,1", "--meeting", "1,1"],
    "check": ["--world", "ring:6", "--robots", "0 3", "--meeting", "1"],
    "replay": ["{world trace}"],
    "sweep": ["--world", "ring:5", "--robots", "2", "--meeting", "1", "--db", "s.sqlite"],
    "report": ["--db", "{world database}"],
    "impossibility": ["--robots", "0,0 2,0", "--meeting", "1,1 1,-1"],
    "test": ["{world scenario}"],
    "synthesize": ["--world", "ring:5", "--robots", "2", "--scheduler", "fsync"],
}


@settings(max_examples=120, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(command=st.sampled_from(RUN), data=st.data())
def test_the_arguments_of_every_command(command, data, samples, tmp_path, capsys,
                                        monkeypatch):
    """Every subcommand that runs, on drawn options and values (``bench`` is parsed only:
    it measures for minutes by design)."""
    monkeypatch.chdir(tmp_path)
    base = [a.format(**{k: v for k, v in samples.items()}) if a.startswith("{") else a
            for a in BASE[command]] if data.draw(st.booleans()) else []
    argv = [command, *base, *argv_of(command, data.draw, samples, tmp_path), *SAFE[command]]
    code = main(argv)
    assert_clean(code, capsys.readouterr().err, argv)


@settings(max_examples=60, deadline=None)
@given(data=st.data())
def test_the_bench_arguments_parse_or_say_why(data):
    argv = ["bench", *argv_of("bench", data.draw, {}, Path("/nonexistent"))]
    try:
        build_parser("bench").parse_args(argv)
    except InvalidInput as error:
        assert "\n" not in str(error)


# -- malformed files of each kind ------------------------------------------------------------

json_values = st.recursive(
    st.none() | st.booleans() | st.integers(-10**6, 10**6) | st.floats(allow_nan=True)
    | st.text(max_size=6) | st.sampled_from(["ring:0", "graph:/dev/zero", "../x.py:A", "I11",
                                             "VIOLATED", "async", "fsync", "final"]),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=6), inner,
                                                               max_size=3),
    max_leaves=8)


def _paths(doc: Any, at: tuple = ()) -> list[tuple]:
    """Every place in a JSON document: the key or index path of each value."""
    out = [at]
    if isinstance(doc, dict):
        for k, v in doc.items():
            out += _paths(v, (*at, k))
    elif isinstance(doc, list):
        for i, v in enumerate(doc[:6]):
            out += _paths(v, (*at, i))
    return out


def mutated(text: str, draw: Any) -> str:
    """``text`` (a JSON document) with one drawn change: a value replaced by drawn JSON, a key
    deleted, or the bytes cut or spliced."""
    how = draw(st.sampled_from(["replace", "replace", "delete", "cut", "splice"]))
    if how in ("cut", "splice"):
        at = draw(st.integers(0, len(text)))
        return text[:at] + (draw(st.text(max_size=8)) if how == "splice" else "")
    doc = json.loads(text)
    path = draw(st.sampled_from(_paths(doc)))
    if not path:
        return json.dumps(draw(json_values))
    parent = doc
    for key in path[:-1]:
        parent = parent[key]
    if how == "delete" and isinstance(parent, dict):
        del parent[path[-1]]
    else:
        parent[path[-1]] = draw(json_values)
    return json.dumps(doc)


FILE_RUNS = {  # the kind of file -> the commands that read it (FILE: the mutated copy)
    "scenario": [["check", "FILE", *SAFE["check"]], ["test", "FILE"], ["classify", "FILE"]],
    "world scenario": [["check", "FILE", *SAFE["check"]], ["test", "FILE"]],
    "trace": [["replay", "FILE"], ["replay", "FILE", "--json"]],
    "world trace": [["replay", "FILE"], ["replay", "FILE", "--html", "o.html"]],
    "certificate": [["synthesize", "--verify", "FILE", "--max-seconds", "5"]],
}


@settings(max_examples=150, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(kind=st.sampled_from(sorted(FILE_RUNS)), data=st.data())
def test_malformed_json_files_of_every_kind(kind, data, samples, tmp_path, capsys,
                                            monkeypatch):
    monkeypatch.chdir(tmp_path)
    shutil.copy(samples["stay"], tmp_path / "stay.py")
    path = tmp_path / f"f-{kind.replace(' ', '-')}.json"
    path.write_bytes(mutated(samples[kind].read_text(), data.draw).encode("utf-8",
                                                                         "surrogatepass"))
    for argv in FILE_RUNS[kind]:
        argv = [str(path) if a == "FILE" else a for a in argv]
        code = main(argv)
        assert_clean(code, capsys.readouterr().err, (argv, path.read_bytes()[:300]))


GRAPH_LINES = ["0 1", "1 2", "a a", "1", "x y z", "² 1", "--5 1", "", "graph [", "]",
               ' node [ id 0 label "1" ]', " node [ id 1 label 1 ]", "edge [ source 0 target 1 ]",
               " multigraph 1", "<node id='9'/>", "</graph>", "<edge source='0' target='0'/>",
               "0 0", "1 0", "0 1 {'w': 3}", "\ufeff0 1"]


@settings(max_examples=100, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(name=st.sampled_from(["g.edges", "g.adjlist", "g.gml", "g.graphml"]), data=st.data())
def test_malformed_graph_files(name, data, samples, tmp_path, capsys):
    """A graph file with lines dropped, repeated, or replaced by hostile ones."""
    lines = samples[name].read_text().splitlines()
    for _ in range(data.draw(st.integers(1, 4))):
        at = data.draw(st.integers(0, len(lines)))
        how = data.draw(st.sampled_from(["insert", "drop", "replace"]))
        line = data.draw(st.sampled_from(GRAPH_LINES) | st.text(max_size=10))
        if how == "insert" or not lines:
            lines.insert(at, line)
        elif how == "drop":
            del lines[min(at, len(lines) - 1)]
        else:
            lines[min(at, len(lines) - 1)] = line
    path = tmp_path / name
    path.write_bytes(("\n".join(lines) + "\n").encode("utf-8", "surrogatepass"))
    robots = data.draw(st.sampled_from(["0 1", "0", "1 2", "a", "9"]))
    argv = ["check", "--world", f"graph:{path}", "--robots", robots, "--meeting", "2",
            *SAFE["check"]]
    code = main(argv)
    assert_clean(code, capsys.readouterr().err, (argv, path.read_bytes()))


DB_VALUES = st.one_of(st.none(), st.integers(-5, 10**12), st.floats(allow_nan=True),
                      st.text(max_size=8), st.binary(max_size=4),
                      st.sampled_from(["[", "{", "[1]", "{}", "[[0,", '{"a":1}', "null",
                                       "VERIFIED", "I11", "ring:5", '["final"]']))
COLUMNS = {"results": ["key", "index", "robots", "meeting_nodes", "class", "verdict",
                       "property", "reason", "states", "transitions", "max_moves", "D", "n",
                       "ratio", "trace", "failing", "cause"],
           "sweeps": ["settings"], "timings": ["seconds", "key"],
           "written": ["first", "last", "fingerprint_extra"]}


@settings(max_examples=50, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(which=st.sampled_from(["database", "world database"]), data=st.data())
def test_damaged_databases(which, data, samples, tmp_path, capsys, monkeypatch):
    """A results database with one value of one row replaced (a text where a number goes,
    truncated JSON, NULL, bytes), read by every output of ``report``."""
    monkeypatch.chdir(tmp_path)
    db = tmp_path / "d.sqlite"
    db.unlink(missing_ok=True)
    with sqlite3.connect(samples[which]) as src, sqlite3.connect(db) as dst:
        src.backup(dst)  # (its log too: a copy of the file alone may miss rows)
    table = data.draw(st.sampled_from(sorted(COLUMNS)))
    column = data.draw(st.sampled_from(COLUMNS[table]))
    value = data.draw(DB_VALUES)
    with sqlite3.connect(db) as con:
        rowids = [r for (r,) in con.execute(f"SELECT rowid FROM {table} ORDER BY rowid")]
        if rowids:
            try:
                con.execute(f'UPDATE {table} SET "{column}" = ? WHERE rowid = ?',
                            (value, data.draw(st.sampled_from(rowids))))
            except sqlite3.IntegrityError:  # (a NOT NULL or a key SQLite keeps itself)
                return
    for output in ([], ["--json"], ["--html", "r.html"], ["--regressions", "reg"]):
        argv = ["report", "--db", str(db), *output]
        code = main(argv)
        assert_clean(code, capsys.readouterr().err, (argv, table, column, value))
