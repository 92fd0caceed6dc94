"""The watchdog over the user's code (docs/reliability.md, "Honest limits"), and a quiet
Ctrl-C or killed parent under a sweep's workers ("Ctrl-C").

- An endless loop in ``decide`` (also one that catches ``Exception``, or ``BaseException``)
  ends the check INCOMPLETE with reason ``time``: never a crash, never VERIFIED; on Z² and
  on a finite world, in a check and in a sweep's row.
- An endless loop at the import of an algorithm or property file is one line, exit 2.
- :func:`gather_verify.watchdog.deadline` itself: it stops only the user's code, nests,
  keeps an alarm set before it, and does nothing off the main thread.
- Ctrl-C under ``sweep --dask local`` prints the one line the process pool prints, exit
  130; pool workers whose parent is killed end quietly.

Each command runs in a subprocess with a generous timeout; no assertion is on a time.
"""

from __future__ import annotations

import gc
import json
import os
import signal
import sqlite3
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from gather_verify.model.configuration import Configuration
from gather_verify.plane_check import run_check
from gather_verify.watchdog import (
    GRACE_SECONDS,
    MEMORY_SIGNAL,
    OverMemory,
    Overtime,
    bounded,
    deadline,
    guards,
    watched,
)

ROOT = Path(__file__).resolve().parent.parent

LOOPS = '''
class Loop:
    name = "loop"

    def decide(self, view):
        while True:
            pass


class Swallows:
    """Catches Exception, and loops on: the watchdog's Overtime is no Exception."""

    name = "swallows"

    def decide(self, view):
        while True:
            try:
                while True:
                    pass
            except Exception:
                pass


class SwallowsAll:
    """Catches BaseException once, then answers: an answer after the deadline is not used."""

    name = "swallows-all"

    def decide(self, view):
        try:
            while True:
                pass
        except BaseException:
            pass
        return (0, 0)


class Later:
    """Walks towards the meeting node, and loops from its 200th view on."""

    name = "later"

    def __init__(self):
        self.views = 0

    def decide(self, view):
        self.views += 1
        while self.views > 200:
            pass
        (m,) = view.meeting_nodes
        if m[0]:
            return (1 if m[0] > 0 else -1, 0)
        if m[1]:
            return (0, 1 if m[1] > 0 else -1)
        return (0, 0)
'''

RING_LOOP = '''
class Loop:
    name = "ring-loop"

    def decide(self, view):
        while True:
            pass
'''


def gv(argv: list[str], cwd: Path) -> subprocess.CompletedProcess:
    """``python -m gather_verify ARGV`` from ``cwd`` (a generous timeout: a hang fails)."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run([sys.executable, "-m", "gather_verify", *argv], capture_output=True,
                          text=True, cwd=cwd, env=env, timeout=60, check=False)


@pytest.fixture
def loops(tmp_path: Path) -> Path:
    (tmp_path / "loops.py").write_text(LOOPS)
    return tmp_path


# -- the command line ---------------------------------------------------------------------


@pytest.mark.parametrize("name", ["Loop", "Swallows", "SwallowsAll"])
def test_an_endless_decide_ends_incomplete_time(loops: Path, name: str) -> None:
    got = gv(["check", "--robots", "0,0 3,1", "--meeting", "2,2", "--algorithm",
              f"loops.py:{name}", "--max-seconds", "1", "--json"], loops)
    assert got.returncode == 3, got.stderr
    report = json.loads(got.stdout)
    assert report["verdict"] == "INCOMPLETE" and report["reason"].startswith("time"), report
    assert "watchdog" in report["reason"] and report["trace"] is None
    assert all(r["holds"] is None for r in report["properties"].values())  # no crash either
    assert got.stderr == ""


def test_the_text_output_says_time_in_one_line(loops: Path) -> None:
    got = gv(["check", "--robots", "0,0 3,1", "--meeting", "2,2", "--algorithm",
              "loops.py:Loop", "--max-seconds", "1"], loops)
    assert got.returncode == 3, got.stderr
    assert got.stdout.startswith("INCOMPLETE")
    reason = [line for line in got.stdout.splitlines() if line.startswith("reason:")]
    assert len(reason) == 1 and reason[0].startswith("reason: time (the watchdog"), got.stdout
    assert "Traceback" not in got.stdout + got.stderr


def test_an_endless_import_is_one_line_exit_2(tmp_path: Path) -> None:
    (tmp_path / "hangs.py").write_text("while True:\n    pass\n")
    got = gv(["check", "--robots", "0,0 3,1", "--meeting", "2,2", "--algorithm",
              "hangs.py:Alg", "--max-seconds", "1"], tmp_path)
    assert got.returncode == 2, got.stderr
    lines = got.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: algorithm file "), got.stderr
    assert "hangs.py" in lines[0] and "did not finish importing within 2 s" in lines[0]
    assert got.stdout == ""


def test_an_endless_property_file_is_one_line_exit_2(tmp_path: Path) -> None:
    (tmp_path / "prop.py").write_text("while True:\n    pass\n")
    got = gv(["check", "--robots", "0,0 3,1", "--meeting", "2,2", "--algorithm",
              "go-to-target", "--property", "prop.py:P", "--max-seconds", "1"], tmp_path)
    assert got.returncode == 2, got.stderr
    lines = got.stderr.strip().splitlines()
    assert len(lines) == 1 and "prop.py did not finish importing within 2 s" in lines[0]


def test_an_endless_decide_on_a_ring_ends_incomplete(tmp_path: Path) -> None:
    (tmp_path / "ring_loop.py").write_text(RING_LOOP)
    got = gv(["check", "--world", "ring:6", "--robots", "0 2", "--algorithm",
              "ring_loop.py:Loop", "--max-seconds", "1", "--json"], tmp_path)
    assert got.returncode == 3, got.stderr
    report = json.loads(got.stdout)
    assert report["verdict"] == "INCOMPLETE" and report["reason"].startswith("time"), report
    assert report["trace"] is None and got.stderr == ""


@pytest.mark.parametrize("engine", ["union", "per-config"])
def test_a_sweep_row_of_an_endless_decide_is_incomplete_time(loops: Path, engine: str) -> None:
    db = loops / f"{engine}.sqlite"
    got = gv(["sweep", "--robots", "2", "--meeting", "1", "--box", "2x2", "--algorithm",
              "loops.py:Swallows", "--max-seconds-per-config", "1", "--workers", "1",
              "--limit", "1", "--engine", engine, "--db", str(db), "--json"], loops)
    assert got.returncode == 3, got.stderr
    with sqlite3.connect(db) as con:
        rows = con.execute("SELECT verdict, reason FROM results").fetchall()
    assert len(rows) == 1 and rows[0][0] == "INCOMPLETE" and rows[0][1].startswith("time"), rows


def test_an_endless_import_ends_a_sweep_before_any_work(tmp_path: Path) -> None:
    (tmp_path / "hangs.py").write_text("while True:\n    pass\n")
    got = gv(["sweep", "--robots", "2", "--meeting", "1", "--box", "2x2", "--algorithm",
              "hangs.py:Alg", "--max-seconds-per-config", "1", "--db", "s.sqlite"], tmp_path)
    assert got.returncode == 2, got.stderr
    lines = got.stderr.strip().splitlines()
    assert len(lines) == 1 and "did not finish importing within 2 s" in lines[0]


# -- run_check ----------------------------------------------------------------------------


def test_a_decide_that_stops_returning_is_never_verified_nor_a_crash(loops: Path) -> None:
    """Some states are searched first: the report keeps how many. (The limit leaves the
    search time to meet its 200 views on a loaded machine: stopped on its own clock first,
    the check would go on to its next step, and the loop be met there.)"""
    spec = f"{loops / 'loops.py'}:Later"
    report = run_check(Configuration([(0, 0), (4, 3), (1, 5)], [(2, 2)], initial=True),
                       algorithm=spec, scheduler="async", reduction=False, max_seconds=2)
    assert report["verdict"] == "INCOMPLETE" and report["reason"].startswith("time"), report
    assert report["states"] >= 1 and "crash" not in report["properties"], report


# -- deadline itself ----------------------------------------------------------------------


def spin_until(stop: list[bool]) -> None:
    while not stop[0]:
        pass


def test_a_deadline_stops_the_user_code_only() -> None:
    with pytest.raises(Overtime) as stopped, deadline(0.05), watched():
        while True:
            pass
    assert stopped.value.seconds == 0.05 and not isinstance(stopped.value, Exception)
    # the verifier's own code is never cut: the user's next block raises instead
    with deadline(0.05):
        began = time.monotonic()
        while time.monotonic() - began < 0.2:
            pass
        with pytest.raises(Overtime), watched():
            pass
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)  # disarmed


def test_user_code_that_swallows_the_overtime_is_stopped_again() -> None:
    calls = [0]

    @guards
    def stubborn() -> str:
        try:
            while True:
                pass
        except BaseException:
            calls[0] += 1
            return "too late"

    with pytest.raises(Overtime), deadline(0.05):
        stubborn()  # returns, but after the deadline: the answer is not used
    assert calls[0] == 1


def test_deadlines_nest_and_an_earlier_alarm_stays_in_charge() -> None:
    with deadline(30):
        outer = signal.getitimer(signal.ITIMER_REAL)[0]
        with pytest.raises(Overtime) as inner, deadline(0.05), watched():
            while True:
                pass
        assert inner.value.seconds == 0.05
        assert 0 < signal.getitimer(signal.ITIMER_REAL)[0] <= outer  # the outer one, re-armed
        with deadline(60):  # later than the outer one: not armed, the outer one rings first
            assert signal.getitimer(signal.ITIMER_REAL)[0] <= outer
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)


def test_an_alarm_of_another_library_is_kept() -> None:
    rang: list[int] = []

    def theirs(*_: object) -> None:
        rang.append(1)

    previous = signal.signal(signal.SIGALRM, theirs)
    try:
        signal.setitimer(signal.ITIMER_REAL, 30)
        with deadline(0.05), watched():
            pass
        assert signal.getsignal(signal.SIGALRM) is theirs
        assert 0 < signal.getitimer(signal.ITIMER_REAL)[0] <= 30
        signal.setitimer(signal.ITIMER_REAL, 0.01)
        time.sleep(0.2)
        assert rang == [1]  # its own handler, put back
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def test_no_deadline_off_the_main_thread_nor_without_a_bound() -> None:
    seen: list[object] = []

    def other() -> None:
        with deadline(0.01), watched():
            time.sleep(0.1)
            seen.append(signal.getitimer(signal.ITIMER_REAL))

    thread = threading.Thread(target=other)
    thread.start()
    thread.join()
    assert seen == [(0.0, 0.0)]
    with deadline(None), watched():
        assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)
    with deadline(float("inf")):
        assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)
    assert GRACE_SECONDS >= 1


def busy(seconds: float) -> None:
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        pass


@pytest.mark.filterwarnings("ignore::pytest.PytestUnraisableExceptionWarning")
def test_a_memory_stop_that_is_swallowed_is_raised_again() -> None:
    """A stop that lands in a garbage collector's callback (where Python only prints an
    exception) or that code catches is raised again: the watch rings until the block ends.
    A memory stop that landed once in Hypothesis's gc callback ended a check on the
    engine's own limit instead, without the step's name."""
    over = lambda: 10.0**9  # noqa: E731 - always past the limit
    caught, rang_in_gc = [0], [0]

    def slow_callback(phase: str, info: object) -> None:
        if phase == "start" and not rang_in_gc[0]:
            try:
                busy(1.0)
            except OverMemory:
                rang_in_gc[0] += 1
                raise

    gc.callbacks.append(slow_callback)
    try:
        with pytest.raises(OverMemory), bounded(None, 1.0, over):
            gc.collect()  # the first ring lands in the callback, and is ignored there
            busy(10.0)
    finally:
        gc.callbacks.remove(slow_callback)
    assert rang_in_gc == [1]
    with pytest.raises(OverMemory), bounded(None, 1.0, over):
        try:
            busy(10.0)
        except OverMemory:
            caught[0] += 1  # caught once, as the user's code may
        busy(10.0)
    assert caught == [1]
    assert signal.getsignal(MEMORY_SIGNAL) in (signal.SIG_DFL, None)  # put back


def test_a_limit_that_stops_the_users_code_is_no_crash_of_it() -> None:
    """A memory stop (or a time stop) that lands in ``decide``, ``target`` or an algorithm's
    constructor goes through as the limit it is: never a crash counterexample (a VIOLATED
    out of a search stopped by a limit) nor bad input."""
    from gather_verify.algorithms.base import target_of
    from gather_verify.algorithms.loading import instantiate
    from gather_verify.algorithms.moves import ask

    class Stopped:
        name = "stopped"

        def __init__(self, stop: BaseException) -> None:
            self.stop = stop

        def decide(self, view: object) -> None:
            raise self.stop

        def target(self, configuration: object) -> None:
            raise self.stop

    class Builds:
        def __init__(self) -> None:
            raise OverMemory

    for stop in (OverMemory(), Overtime(1.0)):
        algorithm = Stopped(stop)
        with pytest.raises((OverMemory, Overtime)):
            ask(algorithm, algorithm.decide, None, None)  # type: ignore[arg-type]
        with pytest.raises((OverMemory, Overtime)):
            target_of(algorithm, None)  # type: ignore[arg-type]
    with pytest.raises(OverMemory):
        instantiate(Builds, {}, "builds")


# -- Ctrl-C and a killed parent under a sweep's workers -----------------------------------


def default_ctrl_c() -> None:
    """The child hears Ctrl-C even when the runner ignores it (ignored signals outlive exec)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def rows_of(db: Path) -> int:
    if not db.exists():
        return 0
    try:
        with sqlite3.connect(db, timeout=1) as con:
            return con.execute("SELECT COUNT(*) FROM results").fetchone()[0]
    except sqlite3.Error:
        return 0


SWEEP = ["sweep", "--robots", "3", "--meeting", "2", "--box", "4x4", "--algorithm",
         "go-to-target", "--scheduler", "async", "--workers", "2", "--json", "--engine",
         "per-config"]


def test_ctrl_c_under_dask_local_is_one_line(tmp_path: Path) -> None:
    pytest.importorskip("distributed")
    db = tmp_path / "dask.sqlite"
    proc = subprocess.Popen([sys.executable, "-m", "gather_verify", *SWEEP, "--db", str(db),
                             "--dask", "local"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            cwd=tmp_path, env={**os.environ, "PYTHONPATH": str(ROOT)},
                            start_new_session=True, preexec_fn=default_ctrl_c)
    deadline_at = time.monotonic() + 120
    while time.monotonic() < deadline_at and proc.poll() is None and rows_of(db) < 4:
        time.sleep(0.05)
    if proc.poll() is not None:
        pytest.skip("the sweep finished before it could be interrupted")
    os.killpg(proc.pid, signal.SIGINT)  # a terminal's Ctrl-C reaches the whole process group
    out, err = proc.communicate(timeout=60)
    text = err.decode()
    assert proc.returncode == 130, text
    lines = text.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in text, text
    assert str(db) in lines[0] and "run the same command again to resume" in lines[0]


def test_pool_workers_of_a_killed_sweep_end_quietly(tmp_path: Path) -> None:
    db = tmp_path / "killed.sqlite"
    err = tmp_path / "stderr.txt"
    with open(err, "wb") as sink:
        proc = subprocess.Popen([sys.executable, "-m", "gather_verify", *SWEEP, "--db", str(db)],
                                stdout=subprocess.DEVNULL, stderr=sink, cwd=tmp_path,
                                env={**os.environ, "PYTHONPATH": str(ROOT)},
                                start_new_session=True)
        deadline_at = time.monotonic() + 120
        while time.monotonic() < deadline_at and proc.poll() is None and rows_of(db) < 4:
            time.sleep(0.05)
        if proc.poll() is not None:
            pytest.skip("the sweep finished before it could be killed")
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=60)
        group = proc.pid  # its own session: the workers are the rest of its process group
        for _ in range(300):  # (each worker watches its parent every second)
            try:
                os.killpg(group, 0)
            except ProcessLookupError:
                break
            time.sleep(0.1)
        else:
            os.killpg(group, signal.SIGKILL)
            pytest.fail("the pool workers outlived their killed parent")
    assert err.read_text() == ""
