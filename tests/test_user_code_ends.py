"""The trust model for user code that would end the verifier: a ``KeyboardInterrupt``, a
``SystemExit`` or a call of ``os._exit`` in ``decide`` is the algorithm's crash (the
``crash`` counterexample, with its trace), in a check and in every worker of a sweep; only a
real Ctrl-C is an interrupt; a worker killed by a signal is one line (docs/reliability.md)."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ENDS = textwrap.dedent("""\
    import os
    import signal


    class Interrupt:
        name = "interrupt"

        def decide(self, view):
            raise KeyboardInterrupt


    class Exit0:
        name = "exit0"

        def decide(self, view):
            os._exit(0)


    class Kill:
        name = "kill"

        def decide(self, view):
            os.kill(os.getpid(), signal.SIGKILL)


    class PlaneInterrupt:
        name = "plane-interrupt"

        def decide(self, view):
            raise KeyboardInterrupt
    """)


def cli(cwd: Path, *argv: str) -> subprocess.CompletedProcess:
    (cwd / "ends.py").write_text(ENDS)
    return subprocess.run([sys.executable, "-m", "gather_verify", *argv], cwd=cwd,
                          capture_output=True, text=True, timeout=300)


@pytest.mark.parametrize("name, words", [("Interrupt", "KeyboardInterrupt"),
                                         ("Exit0", "os._exit(0)")])
def test_an_algorithm_that_would_end_the_check_is_a_crash_with_a_trace(tmp_path, name, words):
    """``raise KeyboardInterrupt`` in ``decide``: ``check`` exited 130 ("interrupted");
    ``os._exit(0)``: exit 0 and no output at all."""
    done = cli(tmp_path, "check", "--world", "ring:6", "--robots", "0 3", "--meeting", "1",
               "--algorithm", f"ends.py:{name}", "--json")
    assert done.returncode == 1, done.stderr
    report = json.loads(done.stdout)
    assert report["property"] == "crash" and words in report["reason"]
    assert report["trace"]["steps"] and report["trace"]["property"] == "crash"


def test_a_keyboard_interrupt_in_decide_on_the_paper_s_grid_is_a_crash(tmp_path):
    done = cli(tmp_path, "check", "--robots", "0,0 2,1", "--meeting", "1,1",
               "--algorithm", "ends.py:PlaneInterrupt", "--json")
    assert done.returncode == 1, done.stderr
    assert json.loads(done.stdout)["property"] == "crash"


@pytest.mark.parametrize("name", ["Interrupt", "Exit0"])
def test_a_sweep_s_workers_report_it_as_crash_rows(tmp_path, name):
    """``sweep --workers 2`` with ``raise KeyboardInterrupt`` in ``decide`` printed ~97 lines of
    worker tracebacks, "a worker process was lost" and exit 2, on every rerun."""
    argv = ("sweep", "--world", "ring:6", "--robots", "2", "--meeting", "1", "--algorithm",
            f"ends.py:{name}", "--workers", "2", "--db", "r.sqlite", "--json")
    done = cli(tmp_path, *argv)
    assert done.returncode == 1, done.stderr
    assert "Traceback" not in done.stderr and done.stderr.strip() == ""
    summary = json.loads(done.stdout)
    assert summary["verdicts"]["ring:6"] == {"VIOLATED": summary["total"]}
    assert summary["failing_properties"]["ring:6"] == {"crash": summary["total"]}


def test_a_worker_killed_by_a_signal_is_one_line(tmp_path):
    """What the verifier cannot catch (a signal the algorithm sends its own process) ends the
    sweep with one line naming the signal, exit 2, never a hang or a traceback."""
    done = cli(tmp_path, "sweep", "--world", "ring:5", "--robots", "2", "--meeting", "1",
               "--algorithm", "ends.py:Kill", "--workers", "2", "--db", "k.sqlite")
    assert done.returncode == 2, done.stderr
    assert len(done.stderr.strip().splitlines()) == 1 and "Traceback" not in done.stderr
    assert "a worker process died (killed by SIGKILL)" in done.stderr


def test_only_a_counted_sigint_is_a_real_interrupt():
    """The rule itself: a KeyboardInterrupt is an interrupt only where SIGINTs are counted and
    one arrived (or where they are not counted at all: a library caller's process)."""
    from gather_verify import watchdog

    error = KeyboardInterrupt()
    saved = watchdog._counting, watchdog._interrupts
    try:
        watchdog._counting, watchdog._interrupts = False, 0
        assert watchdog.real_interrupt(error)
        watchdog._counting = True
        assert not watchdog.real_interrupt(error)
        assert not watchdog.real_interrupt(SystemExit(0))
        watchdog._interrupts = 1
        assert watchdog.real_interrupt(error)
    finally:
        watchdog._counting, watchdog._interrupts = saved
