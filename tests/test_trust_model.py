"""The trust model: code named inside a scenario, trace or results database runs only from
that file's own folder (or with GATHER_VERIFY_ALLOW_CODE=1); opening a file never runs code
from elsewhere (docs/reliability.md, "Security")."""

from __future__ import annotations

import json
import sqlite3
import subprocess
import sys
from pathlib import Path

EVIL = ("from pathlib import Path\n"
        "Path({marker!r}).write_text('ran')\n"
        "class X:\n    name = 'x'\n\n    def decide(self, view):\n        return (0, 0)\n")


def cli(*argv: str, cwd: Path, env: dict | None = None) -> subprocess.CompletedProcess:
    import os

    return subprocess.run([sys.executable, "-m", "gather_verify", *argv], cwd=cwd, text=True,
                          capture_output=True, timeout=120, env={**os.environ, **(env or {})})


def scenario(folder: Path, algorithm: str) -> Path:
    path = folder / "s.json"
    path.write_text(json.dumps({"name": "s", "robots": [[0, 0], [2, 1]],
                                "meeting_nodes": [[1, 1]], "algorithm": algorithm,
                                "scheduler": "async"}))
    return path


def test_a_scenario_naming_code_outside_its_folder_runs_nothing(tmp_path):
    marker = tmp_path / "ran.txt"
    (tmp_path / "evil.py").write_text(EVIL.format(marker=str(marker)))
    inbox = tmp_path / "inbox"
    inbox.mkdir()
    for algorithm in ("../evil.py:X", "os.path:join"):
        path = scenario(inbox, algorithm)
        for command in (("check", str(path)), ("simulate", str(path))):
            done = cli(*command, cwd=inbox)
            assert done.returncode == 2, (command, done.stderr)
            assert "runs only from that file's own folder" in done.stderr, done.stderr
            assert len(done.stderr.strip().splitlines()) == 1
    assert not marker.exists()
    path = scenario(inbox, "../evil.py:X")
    allowed = cli("check", str(path), cwd=inbox, env={"GATHER_VERIFY_ALLOW_CODE": "1"})
    assert allowed.returncode in (0, 1), allowed.stderr  # consent given: it runs
    assert marker.exists()


def test_a_trace_naming_code_outside_its_folder_is_refused(tmp_path):
    marker = tmp_path / "ran.txt"
    (tmp_path / "evil.py").write_text(EVIL.format(marker=str(marker)))
    root = Path(__file__).resolve().parent.parent
    trace = json.loads((root / "scenarios/regressions/i22-final-paper-async-c933bc2a.json")
                       .read_text())["trace"]
    trace["algorithm"] = "../evil.py:X"
    inbox = tmp_path / "inbox"
    inbox.mkdir()
    (inbox / "t.json").write_text(json.dumps(trace))
    done = cli("replay", str(inbox / "t.json"), "--html", str(tmp_path / "t.html"), cwd=inbox)
    assert done.returncode == 2 and "own folder" in done.stderr, done.stderr
    assert not marker.exists()


def test_a_database_never_makes_the_report_run_code(tmp_path):
    marker = tmp_path / "ran.txt"
    (tmp_path / "evil.py").write_text(EVIL.format(marker=str(marker)))
    db = tmp_path / "r.sqlite"
    done = cli("sweep", "--robots", "2", "--meeting", "1", "--box", "2x2", "--algorithm",
               "broken-away", "--db", str(db), "--workers", "1", cwd=tmp_path)
    assert done.returncode in (0, 1, 3), done.stderr
    con = sqlite3.connect(db)
    with con:
        for key, trace in con.execute("SELECT key, trace FROM results WHERE trace IS NOT NULL"
                                      ).fetchall():
            t = json.loads(trace)
            t["algorithm"] = f"{tmp_path / 'evil.py'}:X"
            con.execute("UPDATE results SET trace = ? WHERE key = ?", (json.dumps(t), key))
        # the sweep's own algorithm too: whether it is the code on disk is read, never run
        for sweep, settings in con.execute("SELECT id, settings FROM sweeps").fetchall():
            s = {**json.loads(settings), "algorithm": f"{tmp_path / 'evil.py'}:X"}
            con.execute("UPDATE sweeps SET settings = ? WHERE id = ?", (json.dumps(s), sweep))
    con.close()
    done = cli("report", "--db", str(db), "--html", str(tmp_path / "report.html"), cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert "older code: not the code on disk now" in done.stdout  # its file was read
    assert (tmp_path / "report.html").exists() and not marker.exists()
