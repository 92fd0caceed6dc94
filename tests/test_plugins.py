"""A user's own algorithm, piece by piece: loading, fingerprints, crashes, scenario tests, the API, the
small fixes. The whole path as a new user walks it is tests/test_new_user.py."""

from __future__ import annotations

import json
import os
import sqlite3
import subprocess
import sys
from pathlib import Path

import pytest

import gather_verify as gv
from gather_verify.algorithms import AlgorithmCrash, get_algorithm
from gather_verify.cli import main
from gather_verify.model.configuration import Configuration
from gather_verify.plane_check import run_check
from gather_verify.replay import replay
from gather_verify.simulate import simulate

ROOT = Path(__file__).resolve().parent.parent
TWO = Configuration([(0, 0), (3, 1)], [(2, 2)], initial=True)
ALGORITHM = '''\
from {helper} import step

class Home:
    name = "home"

    def __init__(self, lazy="0"):
        self.lazy = lazy == "1"

    def decide(self, view):
        (target,) = view.meeting_nodes
        return (0, 0) if self.lazy else step(target)

HOME = Home()
'''
HELPER = '''\
def step(target):
    x, y = target
    return ((x > 0) - (x < 0), 0) if x else (0, (y > 0) - (y < 0))
'''


def write_algorithm(folder: Path, helper: str = "plug_helper") -> str:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "home_alg.py").write_text(ALGORITHM.format(helper=helper))
    (folder / f"{helper}.py").write_text(HELPER)
    return str(folder / "home_alg.py")


# -- loading ------------------------------------------------------------------------------

def test_file_specs_class_factory_object_and_options(tmp_path: Path) -> None:
    path = write_algorithm(tmp_path, "plug_helper_a")
    assert run_check(TWO, algorithm=f"{path}:Home", scheduler="async")["verdict"] == "VERIFIED"
    lazy = run_check(TWO, algorithm=f"{path}:Home:lazy=1", scheduler="async")
    assert (lazy["verdict"], lazy["property"]) == ("VIOLATED", "final")
    assert lazy["trace"]["algorithm"] == f"{path}:Home:lazy=1"  # replayable by its name
    assert replay(lazy["trace"]).confirmed
    assert get_algorithm(f"{path}:HOME").decide  # an object with decide
    with pytest.raises(ValueError, match="takes no options"):
        get_algorithm(f"{path}:HOME:lazy=1")
    with pytest.raises(ValueError, match="defines no 'Nope'"):
        get_algorithm(f"{path}:Nope")
    with pytest.raises(ValueError, match="no such file"):
        get_algorithm(f"{tmp_path}/missing.py:Home")


def test_relative_file_specs_and_module_specs(tmp_path: Path, monkeypatch) -> None:
    write_algorithm(tmp_path / "pkg_gv_plug", "plug_helper_b")
    (tmp_path / "pkg_gv_plug" / "__init__.py").write_text("")
    monkeypatch.chdir(tmp_path)
    assert get_algorithm("pkg_gv_plug/home_alg.py:Home").name == \
        f"{tmp_path}/pkg_gv_plug/home_alg.py:Home"
    monkeypatch.syspath_prepend(str(tmp_path / "pkg_gv_plug"))  # for its helper
    monkeypatch.syspath_prepend(str(tmp_path))
    algorithm = get_algorithm("pkg_gv_plug.home_alg:Home")
    assert algorithm.name == "pkg_gv_plug.home_alg:Home"
    assert run_check(TWO, algorithm="pkg_gv_plug.home_alg:Home",
                     scheduler="fsync")["verdict"] == "VERIFIED"


def test_entry_point_group(tmp_path: Path, monkeypatch) -> None:
    write_algorithm(tmp_path / "site", "plug_helper_c")
    info = tmp_path / "site" / "gv_plug_demo-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: gv-plug-demo\nVersion: 1.0\n")
    (info / "entry_points.txt").write_text(
        "[gather_verify.algorithms]\nhome-from-ep = home_alg:Home\n")
    monkeypatch.syspath_prepend(str(tmp_path / "site"))
    algorithm = get_algorithm("home-from-ep:lazy=1")
    assert algorithm.name == "home-from-ep:lazy=1" and algorithm.lazy
    with pytest.raises(ValueError, match="home-from-ep"):  # listed among the known names
        get_algorithm("nope-nope")


def test_scenario_paths_are_relative_to_the_file(tmp_path: Path, monkeypatch) -> None:
    """Relative to the file's folder; outside that folder, allowed from the project folder
    it lies in (the working directory), refused elsewhere (tests/test_trust_model.py)."""
    write_algorithm(tmp_path / "algs", "plug_helper_d")
    (tmp_path / "sc").mkdir()
    path = tmp_path / "sc" / "a.json"
    path.write_text(json.dumps({"robots": [[0, 0], [3, 1]], "meeting_nodes": [[2, 2]],
                                "algorithm": "../algs/home_alg.py:Home:lazy=1",
                                "expect": {"verdicts": [{"verdict": "VIOLATED",
                                                         "property": "final"}]}}))
    with pytest.raises(gv.InvalidInput, match="own folder or the working directory"):
        gv.load_scenario(path)
    monkeypatch.chdir(tmp_path)
    s = gv.load_scenario(path)
    assert s.algorithm == s.expectations[0].algorithm == \
        f"{tmp_path}/algs/home_alg.py:Home:lazy=1"


# -- fingerprints and the store ------------------------------------------------------------

def test_fingerprint_follows_the_source_and_options(tmp_path: Path) -> None:
    from gather_verify.fingerprint import algorithm_fingerprint

    path = write_algorithm(tmp_path, "plug_helper_e")
    before = algorithm_fingerprint(f"{path}:Home")
    assert sorted(Path(f).name for f in before["files"]) == ["home_alg.py", "plug_helper_e.py"]
    assert algorithm_fingerprint(f"{path}:Home:lazy=1")["digest"] != before["digest"]
    (tmp_path / "plug_helper_e.py").write_text(HELPER + "\n# edited\n")
    assert algorithm_fingerprint(f"{path}:Home")["digest"] != before["digest"]
    assert algorithm_fingerprint("paper") == algorithm_fingerprint("paper")


def test_sweep_recomputes_after_an_edit_and_fresh_drops_rows(tmp_path: Path) -> None:
    from gather_verify.cli.common import without_timings
    from gather_verify.sweeps.store import Store
    from gather_verify.sweeps.sweep import SweepSettings, run_sweep

    path = write_algorithm(tmp_path, "plug_helper_f")
    settings = SweepSettings(robots=2, meeting=1, box=(3, 3), algorithm=f"{path}:Home",
                             scheduler="fsync")
    db = str(tmp_path / "r.sqlite")
    first = run_sweep(settings, db, workers=1, progress=False, limit=6)
    assert first["verdicts"]["I13"] == {"VERIFIED": 6}
    (tmp_path / "plug_helper_f.py").write_text("def step(target):\n    return (0, 0)\n")
    again = run_sweep(settings, db, workers=1, progress=False, limit=6)
    assert again["verdicts"]["I13"] == {"VIOLATED": 6}
    fresh = run_sweep(settings, str(tmp_path / "f.sqlite"), workers=1, progress=False, limit=6)
    assert without_timings(again) == without_timings(fresh)
    store = Store(db)  # tamper with a stored row: --fresh computes it again
    sweep = store.sweep_id(settings.key())
    store.db.execute("UPDATE results SET verdict = 'VERIFIED' WHERE sweep = ?", (sweep,))
    store.db.commit()
    store.close()
    assert run_sweep(settings, db, workers=1, progress=False, limit=6)["verdicts"]["I13"] == \
        {"VERIFIED": 6}
    assert run_sweep(settings, db, workers=1, progress=False, limit=6,
                     fresh=True)["verdicts"]["I13"] == {"VIOLATED": 6}


def test_an_older_database_gains_the_failing_column(tmp_path: Path) -> None:
    from gather_verify.sweeps.store import Store

    db = tmp_path / "old.sqlite"
    with sqlite3.connect(db) as con:
        con.executescript("""
        CREATE TABLE sweeps (id INTEGER PRIMARY KEY, settings TEXT NOT NULL UNIQUE);
        CREATE TABLE results (sweep INTEGER NOT NULL, key TEXT NOT NULL, "index" INTEGER NOT NULL,
            robots TEXT, meeting_nodes TEXT, class TEXT, verdict TEXT, property TEXT, reason TEXT,
            states INTEGER, transitions INTEGER, max_moves INTEGER, D INTEGER, n INTEGER,
            ratio REAL, trace TEXT, PRIMARY KEY (sweep, key));
        CREATE TABLE timings (sweep INTEGER NOT NULL, key TEXT NOT NULL, seconds REAL,
            PRIMARY KEY (sweep, key));
        INSERT INTO results(sweep, key, "index", class, verdict) VALUES (1, 'k', 0, 'I13', 'VERIFIED');
        """)
    store = Store(db)
    assert store.results(1)[0]["failing"] is None
    store.close()


def test_summary_counts_every_failing_property() -> None:
    from gather_verify.sweeps.sweep import format_summary, summarise

    row = {"class": "I22", "verdict": "VIOLATED", "property": "target-invariance",
           "ratio": None, "robots": [], "meeting_nodes": []}
    rows = [row | {"failing": ["target-invariance", "termination"]},
            row | {"failing": ["target-invariance"]}]
    summary = summarise(rows)
    assert summary["failing_properties"] == {"I22": {"target-invariance": 2}}
    assert summary["failing_every"] == {"I22": {"target-invariance": 2, "termination": 1}}
    lines: list[str] = []
    format_summary(summary, lines.append)
    assert "  I22: target-invariance x2, termination x1" in lines


# -- crashes --------------------------------------------------------------------------------

@pytest.mark.parametrize("engine", ["reference", "fast"])
def test_a_crash_is_a_counterexample_with_the_view(engine: str) -> None:
    r = run_check(TWO, algorithm="broken-crash", scheduler="async", engine=engine)
    assert (r["verdict"], r["property"]) == ("VIOLATED", "crash")
    detail = r["trace"]["detail"]
    assert detail["exception"].startswith("ZeroDivisionError") and detail["call"] == "decide"
    assert any("broken.py" in f and "decide" in f for f in detail["traceback"])
    last = r["trace"]["steps"][-1]["state"]
    assert detail["robot_node"] in [robot["node"] for robot in last]
    assert replay(r["trace"]).confirmed
    from gather_verify.render import render_trace

    text = render_trace(r["trace"])
    assert "its view in its own frame" in text and " @" in text


def test_a_sweep_records_crashes_and_goes_on(tmp_path: Path) -> None:
    from gather_verify.sweeps.sweep import SweepSettings, run_sweep

    summary = run_sweep(SweepSettings(robots=2, meeting=1, box=(3, 3), algorithm="broken-crash",
                                      scheduler="async"), str(tmp_path / "c.sqlite"),
                        workers=1, progress=False)
    assert summary["total"] == 28 and summary["failing_properties"]["I13"]["crash"] > 0


def test_crash_outside_a_search_is_one_message_exit_1(capsys) -> None:
    code = main(["simulate", "--robots", "0,0 3,1", "--meeting", "2,2", "--algorithm",
                 "broken-crash", "--seed", "1"])
    err = capsys.readouterr().err
    assert code == 1 and err.startswith("crash: algorithm 'broken-crash' crashed in decide")
    assert "Traceback" not in err
    with pytest.raises(AlgorithmCrash):
        simulate(TWO, get_algorithm("broken-crash"), "fsync")


# -- replay: no longer reproduces ------------------------------------------------------------

def test_replay_after_a_fix_exits_5_and_tampering_stays_2(tmp_path: Path, capsys) -> None:
    path = write_algorithm(tmp_path, "plug_helper_g")
    r = run_check(TWO, algorithm=f"{path}:Home:lazy=1", scheduler="ssync", margin=4)
    (tmp_path / "t.json").write_text(json.dumps(r["trace"]))
    assert main(["replay", str(tmp_path / "t.json"), "--quiet"]) == 1
    fixed = r["trace"] | {"algorithm": f"{path}:Home"}  # the fixed one leaves the deadlock
    (tmp_path / "fixed.json").write_text(json.dumps(fixed))
    r2 = run_check(TWO, algorithm="broken-stay", scheduler="ssync")
    tampered = json.loads(json.dumps(r2["trace"]))
    tampered["steps"][0]["state"][0]["node"] = [9, 9]
    (tmp_path / "bad.json").write_text(json.dumps(tampered))
    capsys.readouterr()
    assert main(["replay", str(tmp_path / "fixed.json"), "--quiet"]) == 5
    assert "NO LONGER REPRODUCES" in capsys.readouterr().out
    assert main(["replay", str(tmp_path / "bad.json")]) == 2


# -- scenario tests ---------------------------------------------------------------------------

def scenario_folder(tmp_path: Path, wrong: bool) -> Path:
    folder = tmp_path / "scn"
    folder.mkdir(exist_ok=True)
    good = {"robots": [[0, 0], [3, 1]], "meeting_nodes": [[2, 2]], "algorithm": "broken-stay",
            "scheduler": "fsync", "expect": {"class": "I13", "verdicts": [
                {"verdict": "VIOLATED", "property": "final"}]}}
    (folder / "good.json").write_text(json.dumps(good))
    if wrong:
        bad = good | {"expect": {"verdicts": [{"verdict": "VERIFIED"}]}}
        (folder / "bad.json").write_text(json.dumps(bad))
    return folder


def test_gather_verify_test_and_junit(tmp_path: Path, capsys) -> None:
    folder = scenario_folder(tmp_path, wrong=True)
    junit = tmp_path / "j.xml"
    assert main(["test", str(folder), "--junit", str(junit)]) == 1
    out = capsys.readouterr().out
    assert "FAIL" in out and "bad.json[broken-stay/fsync]: expected VERIFIED, got VIOLATED" in out
    assert "reproduce: gather-verify check" in out and " M " in out  # the trace as grids
    saved = out.split("replay: gather-verify replay ", 1)[1].split()[0]
    assert main(["replay", saved, "--quiet"]) == 1
    xml = junit.read_text()
    assert 'failures="1"' in xml and "property: final" in xml and "step 1" in xml
    (folder / "bad.json").unlink()
    assert main(["test", str(folder)]) == 0
    assert main(["test", str(tmp_path / "nothing-here")]) == 2


def test_check_says_whether_the_expectation_matched(tmp_path: Path, capsys) -> None:
    folder = scenario_folder(tmp_path, wrong=True)
    assert main(["check", str(folder / "good.json")]) == 0  # VIOLATED, as expected
    assert "expectation of" in capsys.readouterr().out
    assert main(["check", str(folder / "bad.json"), "--json"]) == 1
    report = json.loads(capsys.readouterr().out)
    assert report["expectation"]["matched"] is False and report["verdict"] == "VIOLATED"
    assert main(["check", str(folder / "good.json"), "--scheduler", "async", "--json"]) == 1
    assert "expectation" not in json.loads(capsys.readouterr().out)  # none for async


def test_pytest_plugin_collects_scenarios(tmp_path: Path) -> None:
    folder = scenario_folder(tmp_path, wrong=True)
    run = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--gv-scenarios",
           str(folder)]
    done = subprocess.run(run, cwd=tmp_path, capture_output=True, text=True, timeout=300,
                          check=False, env={**os.environ, "PYTHONHASHSEED": "0"})
    assert done.returncode == 1, done.stdout
    assert "bad.json" in done.stdout and "expected VERIFIED, got VIOLATED (final)" in done.stdout
    assert "2 passed" in done.stdout and "1 failed" in done.stdout


# -- the API and the small ones --------------------------------------------------------------

@pytest.mark.parametrize(("algorithm", "options"), [
    ("go-to-target", {}), ("broken-away", {}), ("broken-crash", {}),
    ("go-to-target", {"max_states": 3}),
])
def test_check_report_round_trips_run_check(algorithm: str, options: dict) -> None:
    raw = run_check(TWO, algorithm=algorithm, scheduler="async", **options)
    report = gv.CheckReport.from_json(raw)
    assert report.to_json() == raw
    assert json.dumps(report.to_json(), sort_keys=True) == json.dumps(raw, sort_keys=True)
    u = run_check(Configuration([(0, 0), (2, 0)], [(1, 1), (1, -1)], initial=True),
                  algorithm="paper", scheduler="async")
    assert gv.CheckReport.from_json(u).to_json() == u


@pytest.mark.parametrize(("c", "algorithm", "options"), [
    (TWO, "broken-away", {"move_bound_c": 0.5}),  # move-bound's numbers, causes
    (TWO, "go-to-target", {"lights": "2", "colours": [1, 0]}),  # lights, not applicable
    (TWO, "go-to-target", {"lights": "13"}),  # the engine that ran, and why not the bulk one
    (Configuration([(0, 0)], [(0, 1)], initial=True), "broken-wander",
     {"max_states": 100_000, "properties": ["final", "termination"]}),  # a drift, INCOMPLETE
    (TWO, "go-to-target", {"frames": "compass", "max_states": 40}),  # not applicable
    (Configuration([(0, 0), (2, 1)], [(0, 1), (2, 0)], initial=True), "go-to-target",
     {}),  # I42, in U: NOT-APPLICABLE
])
def test_check_report_writes_run_checks_json_back_byte_for_byte(
        c: Configuration, algorithm: str, options: dict) -> None:
    """The typed report holds every key ``run_check`` writes, in its order: its JSON is the
    report's, text for text (what ``check --json`` prints)."""
    raw = run_check(c, algorithm=algorithm, scheduler="async", max_seconds=600, **options)
    assert json.dumps(gv.CheckReport.from_json(raw).to_json()) == json.dumps(raw)


def test_check_answers_the_report_run_check_writes() -> None:
    """``check`` and ``run_check`` build one typed report; ``run_check`` gives its JSON."""
    typed = gv.check(TWO, algorithm="broken-away", scheduler="async", move_bound_c=0.5)
    raw = run_check(TWO, algorithm="broken-away", scheduler="async", move_bound_c=0.5)
    assert isinstance(typed, gv.CheckReport) and typed.failing == ["move-bound"]
    timings = ("seconds", "peak_rss_mb")
    assert json.dumps({**typed.to_json(), **dict.fromkeys(timings)}) == \
        json.dumps({**raw, **dict.fromkeys(timings)})


def test_check_report_fields_are_named_as_the_json_keys() -> None:
    """One name per datum: a field of ``CheckReport`` is its JSON key (``class_`` for
    ``class``, reserved in Python); the older ``configuration_class`` still reads it."""
    import dataclasses

    raw = run_check(TWO, algorithm="go-to-target", scheduler="async")
    report = gv.CheckReport.from_json(raw)
    fields = {f.name.rstrip("_") for f in dataclasses.fields(report)}
    assert fields <= set(raw) | {"peak_rss_mb", "drift", "not_applicable", "lights", "colours",
                                 "engine", "engine_fallback"}
    assert report.class_ == raw["class"] == "I13"
    with pytest.warns(DeprecationWarning, match="class_"):
        assert report.configuration_class == report.class_


def test_abbreviations_and_semicolons_are_refused(capsys) -> None:
    assert main(["check", "--robot", "0,0 3,1", "--meeting", "2,2"]) == 2
    assert main(["check", "--robots", "0,0;3,1", "--meeting", "2,2"]) == 2
    err = capsys.readouterr().err
    assert "unrecognized arguments: --robot" in err and "separate points with spaces" in err


def test_a_worker_without_the_file_receives_it(tmp_path: Path) -> None:
    """A Dask worker on another machine: the sweep ships the algorithm's files with the task;
    the worker loads its copy under the original path (the file is gone here)."""
    from gather_verify.algorithms.loading import ship
    from gather_verify.sweeps.sweep import SweepSettings, _run_task

    path = write_algorithm(tmp_path / "away", "plug_helper_h")
    sources = ship({f"{path}:Home:lazy=1", "paper"})
    assert sorted(sources[path]) == ["home_alg.py", "plug_helper_h.py"]
    moved = str(tmp_path / "elsewhere" / "home_alg.py")  # a path this process does not see
    settings = SweepSettings(robots=2, meeting=1, box=(3, 3), algorithm=f"{moved}:Home",
                             scheduler="fsync")
    chunk = [(0, TWO)]
    with pytest.raises(ValueError, match="no such file"):
        _run_task((1, settings, chunk))
    _, rows, *_ = _run_task((1, settings, chunk), shipped=({moved: sources[path]}, None))
    assert rows[0]["verdict"] == "VERIFIED"
    edited = {**sources[path], "plug_helper_h.py": "def step(target):\n    return (0, 0)\n"}
    _, rows, *_ = _run_task((1, settings, chunk), shipped=({moved: edited}, None))  # a later, edited one
    assert rows[0]["verdict"] == "VIOLATED"


BOOM = '''\
from {helper} import step

class Boom:
    name = "boom"

    def __init__(self, fixed="0"):
        self.fixed = fixed == "1"

    def decide(self, view):
        (target,) = view.meeting_nodes
        if not self.fixed and abs(target[0]) + abs(target[1]) == 1:
            raise RuntimeError("boom next to the meeting node")
        return step(target)
'''


def test_replay_exit_5_says_which_of_its_two_kinds_happened(tmp_path: Path, capsys) -> None:
    """Exit 5 has two causes, and the output names the one that happened: a step the changed
    algorithm no longer takes, or every step still taken but the property no longer failing
    at the end (here: a crash, fixed, with the moves before it unchanged)."""
    path = write_algorithm(tmp_path, "plug_helper_k")
    (tmp_path / "boom_alg.py").write_text(BOOM.format(helper="plug_helper_k"))
    boom = run_check(TWO, algorithm=f"{tmp_path / 'boom_alg.py'}:Boom", scheduler="ssync")
    assert (boom["verdict"], boom["property"]) == ("VIOLATED", "crash") and boom["trace"]["steps"]
    (tmp_path / "step.json").write_text(json.dumps(  # a lazy algorithm takes none of its moves
        boom["trace"] | {"algorithm": f"{path}:Home:lazy=1"}))
    (tmp_path / "end.json").write_text(json.dumps(  # the same moves, and no crash at the end
        boom["trace"] | {"algorithm": f"{tmp_path / 'boom_alg.py'}:Boom:fixed=1"}))
    capsys.readouterr()

    assert main(["replay", str(tmp_path / "step.json"), "--quiet"]) == 5
    out = capsys.readouterr().out
    assert "NO LONGER REPRODUCES (the algorithm no longer takes one of its steps)" in out
    assert "property no longer fails" not in out
    assert main(["replay", str(tmp_path / "end.json"), "--quiet"]) == 5
    out = capsys.readouterr().out
    assert "NO LONGER REPRODUCES (its steps replay, but the property no longer fails at the " \
           "end)" in out
    assert "no longer takes" not in out

    for name, why in (("step", "step-not-taken"), ("end", "property-holds")):
        assert main(["replay", str(tmp_path / f"{name}.json"), "--json"]) == 5
        answer = json.loads(capsys.readouterr().out)
        assert answer["confirmed"] is False and answer["why"] == why
