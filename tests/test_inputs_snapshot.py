"""Every input a sweep's rows depend on is read once, and a row is stored only under the key
of the inputs it was computed from: an edit of any input while a two-worker sweep runs
leaves the same table as a fresh database's (docs/reliability.md, "Never stale")."""

from __future__ import annotations

import json
import os
import sqlite3
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

EDITOR = textwrap.dedent("""\
    import os

    CALLS = [0]


    def edit_once():
        \"\"\"At this process's 3rd decision, once per test: EDIT_TARGET gets EDIT_WITH's bytes
        (an editor saving a file while the sweep runs).\"\"\"
        CALLS[0] += 1
        target, source = os.environ.get("EDIT_TARGET"), os.environ.get("EDIT_WITH")
        if CALLS[0] != 3 or not target:
            return
        try:
            os.close(os.open(target + ".edited", os.O_CREAT | os.O_EXCL | os.O_WRONLY))
        except FileExistsError:
            return
        with open(source, "rb") as f:
            data = f.read()
        with open(target + ".tmp", "wb") as f:
            f.write(data)
        os.replace(target + ".tmp", target)
    """)

WALK = textwrap.dedent("""\
    import json
    import os

    from editor import edit_once
    from steps import toward


    class Walk:
        \"\"\"On a finite world: towards the nearest meeting node, unless params.json says stay.\"\"\"

        name = "walk"

        def decide(self, view):
            edit_once()
            with open(os.environ["PARAMS"]) as f:  # data the algorithm reads: an extra file
                if json.load(f)["stay"]:
                    return view.me
            return toward(view)


    class Plane:
        \"\"\"On the paper's grid: one step along x, then along y, towards the meeting node.\"\"\"

        name = "plane"

        def decide(self, view):
            edit_once()
            ((x, y),) = view.meeting_nodes
            if (x, y) == (0, 0):
                return (0, 0)
            return ((1 if x > 0 else -1), 0) if x else (0, (1 if y > 0 else -1))
    """)

STEPS = textwrap.dedent("""\
    def toward(view):
        m = min(view.meeting_nodes, key=lambda x: (view.distance(view.me, x), str(x)))
        if view.me == m:
            return view.me
        return min((u for u in view.neighbours()
                    if view.distance(u, m) < view.distance(view.me, m)), key=str)
    """)
STEPS_EDITED = "def toward(view):\n    return view.me  # the edit: never moves\n"

PROPERTY = textwrap.dedent("""\
    from gather_verify.properties import Property

    MARGIN = 1


    def outside(s):
        x0, y0, x1, y1 = s.initial.mer()
        return [v for v in s.configuration.robots if not (
            x0 - MARGIN <= v[0] <= x1 + MARGIN and y0 - MARGIN <= v[1] <= y1 + MARGIN)]


    NEAR = Property("near", "state", holds=lambda s: not outside(s),
                    message=lambda s: f"robots {outside(s)} left", doc="stays near")
    """)

GRAPH = "0 1\n1 2\n2 3\n3 4\n4 5\n5 0\n1 4\n"  # a ring of 6 with a chord
GRAPH_EDITED = "0 1\n1 2\n2 3\n3 4\n4 5\n"  # a path


def project(tmp_path: Path) -> Path:
    """A folder with an algorithm, its helper, the editor, a property file, a graph file and
    a parameter file the algorithm reads."""
    for name, text in (("walk.py", WALK), ("steps.py", STEPS), ("editor.py", EDITOR),
                       ("prop.py", PROPERTY), ("live.edges", GRAPH),
                       ("params.json", '{"stay": false}')):
        (tmp_path / name).write_text(text)
    return tmp_path


def sweep(cwd: Path, argv: tuple[str, ...], db: str, edit: tuple[str, str] | None = None,
          ) -> subprocess.CompletedProcess:
    env = {**os.environ, "PARAMS": str(cwd / "params.json")}
    if edit is not None:
        env.update(EDIT_TARGET=str(cwd / edit[0]), EDIT_WITH=str(cwd / edit[1]))
    return subprocess.run([sys.executable, "-m", "gather_verify", "sweep", *argv, "--db", db,
                           "--workers", "2", "--json"], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=300)


def table(db: Path) -> dict[str, tuple]:
    with sqlite3.connect(db) as con:
        return {key: rest for key, *rest in con.execute(
            "SELECT key, verdict, property, states, transitions FROM results")}


RING = ("--world", "ring:6", "--robots", "2", "--meeting", "1", "--algorithm", "walk.py:Walk",
        "--engine", "per-config")
PLANE = ("--robots", "2", "--meeting", "1", "--box", "3x2", "--algorithm", "walk.py:Plane",
         "--property", "prop.py:NEAR", "--property", "final", "--engine", "per-config")
GRAPH_WORLD = ("--world", "graph:live.edges", "--robots", "2", "--meeting", "1",
               "--algorithm", "walk.py:Walk")

SNAPSHOTTED = {  # input edited -> (its edited text, the sweep)
    "walk.py": (WALK.replace("return toward(view)", "return view.me"), RING),
    "steps.py": (STEPS_EDITED, RING),
    "prop.py": (PROPERTY.replace("MARGIN = 1", "MARGIN = -9"), PLANE),
    "live.edges": (GRAPH_EDITED, GRAPH_WORLD),
}


@pytest.mark.parametrize("name", [  # the code files' edits are slow: one each by default
    "live.edges", *(pytest.param(n, marks=pytest.mark.slow) for n in ("walk.py", "prop.py")),
    "steps.py"])
def test_a_code_or_graph_file_edited_during_a_two_worker_sweep_leaves_a_fresh_database_s_table(
        tmp_path, name):
    """``sweep --world graph:live.edges ... --workers 2`` with the file replaced by another
    graph mid-run (likewise the algorithm, its helper module, a property file): the workers
    compute from the bytes the sweep read at its start, so the table equals a fresh
    database's, and a rerun on the same database reuses every row."""
    cwd = project(tmp_path)
    edited, argv = SNAPSHOTTED[name]
    original = (cwd / name).read_text()
    (cwd / "edited").write_text(edited)
    first = sweep(cwd, argv, "same.sqlite", edit=(name, "edited"))
    assert first.returncode in (0, 1), first.stderr
    assert (cwd / name).read_text() == edited  # the edit did happen while it ran
    (cwd / name).write_text(original)
    fresh = sweep(cwd, argv, "fresh.sqlite")
    again = sweep(cwd, argv, "same.sqlite")
    assert table(cwd / "same.sqlite") == table(cwd / "fresh.sqlite")
    assert json.loads(again.stdout)["verdicts"] == json.loads(fresh.stdout)["verdicts"]
    assert json.loads(again.stdout)["total"] == json.loads(again.stdout)["total"] > 0


def test_an_extra_file_edited_during_a_two_worker_sweep_stores_no_stale_row(tmp_path):
    """``--fingerprint-extra params.json`` edited mid-sweep: the algorithm reads the file
    itself, so rows computed after the edit are not stored under the key of the original
    (one line, exit 2); every row kept is a fresh database's, and the same command then
    computes the edited file's table, as a fresh database does."""
    cwd = project(tmp_path)
    argv = (*RING, "--fingerprint-extra", "params.json")
    (cwd / "edited").write_text('{"stay": true}')
    first = sweep(cwd, argv, "same.sqlite", edit=("params.json", "edited"))
    assert (cwd / "params.json").read_text() == '{"stay": true}'  # edited while it ran
    assert first.returncode == 2, first.stderr
    assert "--fingerprint-extra" in first.stderr and "changed while the sweep ran" in first.stderr
    assert len(first.stderr.strip().splitlines()) == 1 and "Traceback" not in first.stderr
    kept = table(cwd / "same.sqlite")
    (cwd / "params.json").write_text('{"stay": false}')
    before = table(cwd / "before.sqlite") if sweep(cwd, argv, "before.sqlite").returncode \
        in (0, 1) else {}
    assert before and all(before[key] == row for key, row in kept.items())
    (cwd / "params.json").write_text('{"stay": true}')
    again = sweep(cwd, argv, "same.sqlite")
    fresh = sweep(cwd, argv, "fresh.sqlite")
    assert again.returncode == fresh.returncode == 1, (again.stderr, fresh.stderr)
    assert json.loads(again.stdout)["verdicts"] == json.loads(fresh.stdout)["verdicts"]
    assert set(json.loads(again.stdout)["verdicts"]["ring:6"]) == {"VIOLATED"}


@pytest.mark.parametrize("db", [":memory:", "file:x.db?mode=memory", "FILE:y.db"])
def test_a_database_that_is_no_file_is_refused(tmp_path, db):
    """``sweep --db :memory:`` (and ``file:x.db?mode=memory``) exited 0 with nothing kept."""
    done = subprocess.run([sys.executable, "-m", "gather_verify", "sweep", "--world", "ring:5",
                           "--robots", "2", "--algorithm", "go-to-target", "--workers", "1",
                           "--db", db], cwd=tmp_path, capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 2 and "a results database is a file" in done.stderr, done.stderr
    assert len(done.stderr.strip().splitlines()) == 1 and not list(tmp_path.iterdir())


def test_a_row_whose_inputs_are_not_its_key_s_is_not_stored():
    """The store's guard itself: a task that reports another digest for any input than the
    key's is refused, naming that input."""
    from gather_verify.errors import InvalidInput
    from gather_verify.sweeps.sweep import refuse_changed

    key = {"algorithm": "a", "graph file g": "1", "gather-verify's own source": "s"}
    refuse_changed(key, dict(key), 3)
    for name in key:
        with pytest.raises(InvalidInput, match=f"{name} changed while the sweep ran"):
            refuse_changed(key, {**key, name: "other"}, 3)


def test_a_worker_sees_an_edit_of_the_verifier_s_own_source(tmp_path, monkeypatch):
    """A process that imports a module of its own late may run code the digest does not
    name: a worker reports gather-verify's own source as edited once a file of it is not the
    one read at the start."""
    from gather_verify import fingerprint

    fingerprint.own_digest()
    assert fingerprint.own_code_changed() is None
    path, stamp = fingerprint._OWN_STAMPS[0]
    monkeypatch.setattr(fingerprint, "_OWN_STAMPS",
                        [(path, (*stamp[:-1], stamp[-1] + 1)), *fingerprint._OWN_STAMPS[1:]])
    assert fingerprint.own_code_changed() == path
    got = fingerprint.sweep_inputs("a", "ring:5", (), (), disk=True)
    assert got["gather-verify's own source"] == f"edited: {path}"
