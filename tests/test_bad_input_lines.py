"""Every user mistake found by the hostile tests is one line on stderr and exit 2, never a
traceback; a read never writes (docs/reliability.md)."""

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
                          capture_output=True, text=True, timeout=120)


def one_line(done: subprocess.CompletedProcess, *words: str) -> None:
    assert done.returncode == 2, done.stderr
    assert "Traceback" not in done.stderr and len(done.stderr.strip().splitlines()) == 1, \
        done.stderr
    for word in words:
        assert word in done.stderr, done.stderr


SWEEP = ("sweep", "--robots", "2", "--meeting", "1", "--box", "2x2", "--algorithm",
         "go-to-target", "--workers", "1")


@pytest.mark.parametrize("argv, words", [
    (("classify", "/dev/zero"), ("character device", "not a file")),  # never read at all
    (("check", "--robots", "1_0,0", "--meeting", "1,1"), ("digits 0-9",)),
    (("check", "--robots", "\u0661,0", "--meeting", "1,1"), ("digits 0-9",)),
    (("check", "--robots", "0,0", "--meeting", "1,1", "--algorithm", ""), ("empty",)),
    ((*SWEEP, "--readings-types", "garbage", "--db", "x.sqlite"), ("needs --readings",)),
    ((*SWEEP, "--dask", "foo", "--db", "x.sqlite"), ("--dask foo",)),
    ((*SWEEP, "--db", "/nonexistent-folder/x.sqlite"), ("folder does not exist",)),
    # the only property asked for is outside its scope: refused, never VERIFIED with nothing
    # checked (as check refuses it)
    ((*SWEEP, "--frames", "compass", "--property", "no-ungatherable", "--db", "x.sqlite"),
     ("no-ungatherable does not apply under --frames compass", "orientation")),
    ((*SWEEP, "--lights", "2", "--property", "no-ungatherable", "--db", "x.sqlite"),
     ("no-ungatherable does not apply with --lights 2",)),
])
def test_silently_accepted_or_traceback_inputs_are_one_line(tmp_path, argv, words):
    one_line(cli(*argv, cwd=tmp_path), *words)


def test_a_sweep_refuses_target_invariance_for_an_algorithm_with_no_target(tmp_path):
    """As check does: left out of every configuration, the rest would read VERIFIED."""
    (tmp_path / "stay.py").write_text(
        "from gather_verify.algorithms.base import Algorithm\n\n\n"
        "class Stay(Algorithm):\n    name = 'stay'\n\n"
        "    def decide(self, view):\n        return (0, 0)\n")
    argv = ("--robots", "2", "--meeting", "1", "--box", "2x2", "--algorithm", "stay.py:Stay",
            "--property", "target-invariance")
    one_line(cli("sweep", *argv, "--workers", "1", "--db", "x.sqlite", cwd=tmp_path),
             "target-invariance does not apply", "no target()")
    one_line(cli("check", "--robots", "0,0 0,1", "--meeting", "0,0", "--algorithm",
                 "stay.py:Stay", "--property", "target-invariance", cwd=tmp_path),
             "target-invariance does not apply", "no target()")


def test_a_trace_that_is_not_utf8_and_a_partial_stored_trace(tmp_path):
    (tmp_path / "bad.json").write_bytes(b"\xff\xfe{")
    one_line(cli("replay", "bad.json", cwd=tmp_path), "not UTF-8")
    trace = json.loads((Path(__file__).resolve().parent.parent /
                        "scenarios/regressions/i22-final-paper-async-c933bc2a.json").read_text())
    trace["trace"] = {"property": "final"}  # partial: check and test say the same
    (tmp_path / "p.json").write_text(json.dumps(trace))
    for command in ("check", "test"):
        one_line(cli(command, "p.json", cwd=tmp_path), "its trace")
    trace = json.loads((Path(__file__).resolve().parent.parent /
                        "scenarios/regressions/i22-final-paper-async-c933bc2a.json").read_text())
    trace["trace"]["detection"] = "psychic"
    (tmp_path / "t.json").write_text(json.dumps(trace["trace"]))
    one_line(cli("replay", "t.json", cwd=tmp_path), "psychic")


def test_a_report_never_writes_and_refuses_what_is_not_a_database(tmp_path):
    (tmp_path / "notes.txt").write_text("")
    one_line(cli("report", "--db", "notes.txt", cwd=tmp_path), "not a gather-verify")
    assert (tmp_path / "notes.txt").read_bytes() == b""  # still the empty text file
    one_line(cli("report", "--db", "missing.sqlite", cwd=tmp_path), "no such")
    assert not (tmp_path / "missing.sqlite").exists()


def test_a_damaged_database_is_one_line(tmp_path):
    assert cli(*SWEEP, "--db", "r.sqlite", cwd=tmp_path).returncode in (0, 1)
    data = bytearray((tmp_path / "r.sqlite").read_bytes())
    middle = len(data) // 2
    data[middle:middle + 2048] = b"\x00garbage" * 256
    (tmp_path / "r.sqlite").write_bytes(bytes(data))
    for argv in (("report", "--db", "r.sqlite"), (*SWEEP, "--db", "r.sqlite", "--fresh")):
        done = cli(*argv, cwd=tmp_path)
        assert done.returncode in (0, 1, 2) and "Traceback" not in done.stderr, done.stderr


@pytest.mark.parametrize("message", ["attempt to write a readonly database",
                                     "database or disk is full"])
def test_a_read_only_database_or_a_full_disk_is_one_line(tmp_path, monkeypatch, capsys,
                                                         message):
    from gather_verify.sweeps import store

    def refuse(self, sweep, rows):  # noqa: ANN001
        raise sqlite3.OperationalError(message)

    monkeypatch.setattr(store.Store, "add", refuse)
    code = main([*SWEEP, "--db", str(tmp_path / "r.sqlite")])
    err = capsys.readouterr().err
    assert code == 2 and message in err and "kept" in err and len(err.strip().splitlines()) == 1


def test_a_lost_worker_is_noticed_not_awaited_for_ever(tmp_path):
    """A pool worker killed (as the out-of-memory killer would) ends the sweep with one line
    and exit 2 within seconds; the rows stored before are kept."""
    import os
    import signal
    import time

    (tmp_path / "slow.py").write_text(
        "import time\n\nclass Slow:\n    name = 'slow'\n\n    def decide(self, view):\n"
        "        time.sleep(0.05)\n        return (0, 0)\n")
    proc = subprocess.Popen([sys.executable, "-m", "gather_verify", "sweep", "--robots", "2-3",
                             "--meeting", "1", "--box", "3x3", "--algorithm", "slow.py:Slow",
                             "--workers", "2", "--engine", "per-config", "--db", "r.sqlite"],
                            cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    deadline = time.monotonic() + 60
    children: list[int] = []
    while len(children) < 2 and time.monotonic() < deadline:  # both workers (a loaded machine
        # starts them one by one)
        time.sleep(0.5)
        children = [int(p) for p in Path(f"/proc/{proc.pid}/task/{proc.pid}/children")
                    .read_text().split()] if Path(f"/proc/{proc.pid}").exists() else []
    assert children, "no worker started"
    for child in children:  # the workers (and any helper process the pool started)
        os.kill(child, signal.SIGKILL)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 2 and "a worker process died" in err, err
    assert "Traceback" not in err


def test_a_property_that_cannot_apply_says_so_instead_of_passing(tmp_path):
    """``target-invariance`` of an algorithm with no ``target()``: listed as not applicable
    (never 'holds'), and one line, exit 2, when asked for by name."""
    from gather_verify.model.configuration import Configuration
    from gather_verify.plane_check import run_check

    c = Configuration([(0, 0), (2, 1)], [(1, 1)], initial=True)
    report = run_check(c, algorithm="random", scheduler="async", margin=2)
    assert "target-invariance" not in report["properties"]
    assert "no target()" in report["not_applicable"]["target-invariance"]
    one_line(cli("check", "--robots", "0,0 2,1", "--meeting", "1,1", "--algorithm", "random",
                 "--property", "target-invariance", cwd=tmp_path), "does not apply")
