"""Honest limits, determinism, Ctrl-C and memory (docs/reliability.md).

- Every limit (states, seconds, memory, region) ends in INCOMPLETE with the reason and
  the statistics so far, and can never end in VERIFIED.
- The same command prints byte-identical ``--json`` across runs, worker counts and hash
  seeds, traces included.
- Ctrl-C during ``check`` or ``sweep`` exits 130 with one line saying what was kept and
  how to resume, never a traceback.
- A check or sweep over a space larger than the memory limit stops with INCOMPLETE.
"""

from __future__ import annotations

import json
import os
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gather_verify.cli import main
from gather_verify.model.configuration import Configuration
from gather_verify.plane_check import run_check
from gather_verify.sweeps.store import Store

ROOT = Path(__file__).resolve().parent.parent
YARD = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)
GUARD = Configuration([(0, 0), (0, 1)], [(0, 2), (1, 0)], initial=True)  # paper: guard phases
CASES = [(YARD, "go-to-target", "async"), (GUARD, "paper:alpha=mer_f", "async"),
         (YARD, "paper:alpha=mer_f", "ssync")]


def full(c: Configuration, algorithm: str, scheduler: str) -> dict:
    return run_check(c, algorithm=algorithm, scheduler=scheduler, max_states=10**6,
                     max_seconds=600)


@pytest.fixture(scope="module")
def baselines() -> dict:
    out = {}
    for c, algorithm, scheduler in CASES:
        report = full(c, algorithm, scheduler)
        assert report["verdict"] == "VERIFIED", (algorithm, scheduler, report["reason"])
        out[(c.robots, algorithm, scheduler)] = report
    return out


def assert_incomplete(report: dict, reason: str) -> None:
    """INCOMPLETE, the limit named, the statistics so far, and no property claimed to hold."""
    assert report["verdict"] == "INCOMPLETE", report["verdict"]
    assert report["reason"].startswith(reason), report["reason"]
    assert report["states"] >= 1 and report["transitions"] >= 0
    assert set(report["limits"]) >= {"max_states", "max_seconds", "max_memory_mb", "margin"}
    if "while lifting" not in report["reason"]:  # else the safety properties were settled
        assert all(r["holds"] is not True for r in report["properties"].values()), report

# -- each limit: INCOMPLETE with reason and statistics, never VERIFIED ------------------------


@pytest.mark.parametrize("case", range(len(CASES)))
def test_state_limit(case: int, baselines: dict) -> None:
    c, algorithm, scheduler = CASES[case]
    report = run_check(c, algorithm=algorithm, scheduler=scheduler, max_states=2,
                       max_seconds=600)
    assert_incomplete(report, "states")


@settings(max_examples=25, deadline=None)
@given(case=st.integers(0, len(CASES) - 1), fraction=st.floats(0.0, 1.5))
def test_state_limit_never_verifies_an_unfinished_space(case: int, fraction: float) -> None:
    """Whatever the state limit, VERIFIED only when the whole space was explored (the same
    states as without a limit); below the size of the space, always INCOMPLETE."""
    c, algorithm, scheduler = CASES[case]
    whole = full(c, algorithm, scheduler)
    limit = max(1, int(fraction * whole["states"]))
    report = run_check(c, algorithm=algorithm, scheduler=scheduler, max_states=limit,
                       max_seconds=600)
    if report["verdict"] == "VERIFIED":
        assert report["states"] == whole["states"] and limit >= whole["states"]
    else:
        assert_incomplete(report, "states")
    if limit < whole["states"]:
        assert report["verdict"] == "INCOMPLETE"


@pytest.mark.parametrize("case", range(len(CASES)))
def test_time_limit(case: int) -> None:
    c, algorithm, scheduler = CASES[case]
    report = run_check(c, algorithm=algorithm, scheduler=scheduler, max_states=10**6,
                       max_seconds=1e-9)
    assert_incomplete(report, "time")


@settings(max_examples=10, deadline=None)
@given(case=st.integers(0, len(CASES) - 1), megabytes=st.floats(0.001, 8.0))
def test_memory_limit(case: int, megabytes: float) -> None:
    """Any limit below the interpreter's own footprint stops the search at once."""
    c, algorithm, scheduler = CASES[case]
    report = run_check(c, algorithm=algorithm, scheduler=scheduler, max_states=10**6,
                       max_seconds=600, max_memory_mb=megabytes)
    assert_incomplete(report, "memory")


def test_region_limit() -> None:
    """The guard steps out of the initial MER: a fixed margin 0 stops the search (by
    default the margin grows by itself, and the same configuration is VERIFIED)."""
    report = run_check(GUARD, algorithm="paper:alpha=mer_f", scheduler="async",
                       max_states=10**6, max_seconds=600, margin=0)
    assert_incomplete(report, "region")
    assert full(GUARD, "paper:alpha=mer_f", "async")["verdict"] == "VERIFIED"


def test_limits_from_the_command_line(capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["check", "--robots", "0,0 0,1", "--meeting", "0,2 1,0", "--algorithm",
            "paper:alpha=mer_f", "--json"]
    for extra, reason in ((["--max-states", "1"], "states"), (["--max-seconds", "0.001"], None),
                          (["--max-memory-mb", "1"], "memory"), (["--margin", "0"], "region")):
        code = main([*argv, *extra])
        out = json.loads(capsys.readouterr().out)
        if reason is None and out["verdict"] == "VERIFIED":  # finished within a millisecond
            assert code == 0
            continue
        assert code == 3 and out["verdict"] == "INCOMPLETE", (extra, out["verdict"])
        assert reason is None or out["reason"].startswith(reason)
        assert out["states"] >= 1


# -- memory: a check or sweep larger than the memory limit stops with INCOMPLETE -------------


def test_check_over_the_memory_limit_is_incomplete(capsys: pytest.CaptureFixture[str]) -> None:
    """The grid instance of `bench` (4.9 million states) with a 1 MB limit stops at once instead of
    growing until the system kills it."""
    code = main(["check", "--robots", "0,0 5,1 1,5 6,6 3,0", "--meeting", "3,3", "--algorithm",
                 "go-to-target", "--no-reduction", "--max-memory-mb", "1", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 3 and out["verdict"] == "INCOMPLETE" and out["reason"] == "memory"
    assert out["limits"]["max_memory_mb"] == 1


def test_sweep_over_the_memory_limit_is_incomplete(tmp_path: Path,
                                                    capsys: pytest.CaptureFixture[str]) -> None:
    db = tmp_path / "mem.sqlite"
    code = main(["sweep", "--robots", "2", "--meeting", "1", "--box", "3x3", "--algorithm",
                 "go-to-target", "--workers", "1", "--max-memory-mb", "1", "--db", str(db),
                 "--json"])
    summary = json.loads(capsys.readouterr().out)
    assert code == 3
    verdicts = {v for by in summary["verdicts"].values() for v in by}
    assert verdicts <= {"INCOMPLETE", "NOT-APPLICABLE"} and "INCOMPLETE" in verdicts
    assert summary["settings"]["max_memory_mb"] == 1
    store = Store(db)
    try:
        rows = store.results(store.sweeps()[0][0])
    finally:
        store.close()
    assert {r["reason"] for r in rows if r["verdict"] == "INCOMPLETE"} == {"memory"}


def test_default_memory_limit_fits_the_machine() -> None:
    from gather_verify.engine.explore import DEFAULT_MAX_MEMORY_MB
    from gather_verify.engine.resources import machine_memory_mb, memory_budget_mb

    total = machine_memory_mb()
    budget = memory_budget_mb()
    assert budget <= DEFAULT_MAX_MEMORY_MB
    if total is not None:
        assert budget < total and memory_budget_mb(workers=4) <= total / 4
    report = run_check(YARD, algorithm="go-to-target", scheduler="fsync", max_states=100,
                       max_seconds=60)
    assert report["limits"]["max_memory_mb"] == budget


# -- determinism: byte-identical --json across runs, worker counts and hash seeds -------------


def cli(argv: list[str], seed: str, cwd: Path | None = None) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONHASHSEED": seed}
    return subprocess.run([sys.executable, "-m", "gather_verify", *argv], capture_output=True,
                          env=env, cwd=cwd, timeout=600, check=False)


def test_check_json_is_byte_identical_across_hash_seeds() -> None:
    """A violated check (with its trace) and a verified one, under three hash seeds."""
    violated = ["check", str(ROOT / "scenarios/algorithm/i22-non-guard-as-far-as-guard.json"),
                "--scheduler", "async", "--json"]
    verified = ["check", str(ROOT / "scenarios/mutants/i22-async.json"), "--json"]
    for argv in (violated, verified):
        outs = [cli(argv, seed) for seed in ("0", "1", "4242")]
        assert all(o.stderr == b"" for o in outs), outs[0].stderr
        assert len({o.stdout for o in outs}) == 1
        report = json.loads(outs[0].stdout)
        assert "seconds" not in report and "peak_rss_mb" not in report
    assert json.loads(outs[0].stdout)["verdict"] == "VERIFIED"


def test_other_json_outputs_are_byte_identical_across_hash_seeds() -> None:
    for argv in (["simulate", str(ROOT / "scenarios/mutants/i22-async.json"), "--seed", "3",
                  "--json"],
                 ["impossibility", str(ROOT / "scenarios/classes/i41.json"), "--algorithms", "2",
                  "--json"],
                 ["census", "--robots", "2", "--meeting", "2", "--box", "3x3", "--json"]):
        outs = [cli(argv, seed) for seed in ("0", "99")]
        assert outs[0].stdout and outs[0].stdout == outs[1].stdout, argv


def results_table(db: Path) -> list[tuple]:
    with sqlite3.connect(db) as con:
        return con.execute("SELECT s.settings, r.* FROM results r JOIN sweeps s ON s.id = r.sweep "
                           "ORDER BY s.settings, r.key").fetchall()


def test_sweep_json_and_traces_are_identical_across_workers_and_seeds(tmp_path: Path) -> None:
    base = ["sweep", "--robots", "2", "--meeting", "2", "--box", "3x3", "--algorithm", "paper",
            "--scheduler", "ssync", "--json"]
    outs, tables = [], []
    for seed, workers in (("0", "1"), ("1", "2"), ("777", "2"), ("3", "1")):
        db = tmp_path / f"s{seed}-{workers}.sqlite"
        got = cli([*base, "--workers", workers, "--db", str(db)], seed)
        assert got.returncode in (0, 1, 3), got.stderr
        outs.append(got.stdout)
        tables.append(results_table(db))
    assert len(set(outs)) == 1
    assert all(t == tables[0] for t in tables)
    assert any(row[-1] is not None for row in tables[0])  # traces are compared too


# -- Ctrl-C: one line, what was kept, how to resume, exit 130 ------------------------------


def default_ctrl_c() -> None:
    """The child hears Ctrl-C even when the runner ignores it (ignored signals outlive exec)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def interrupt_when(proc: subprocess.Popen, ready, timeout: float = 120) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and proc.poll() is None and not ready():
        time.sleep(0.05)
    if proc.poll() is not None:
        pytest.skip("the command finished before it could be interrupted")
    os.killpg(proc.pid, signal.SIGINT)  # a terminal's Ctrl-C reaches the whole process group


def test_ctrl_c_during_check() -> None:
    # a space of minutes even with the compiled kernels (the grid instance of `bench` now ends in 5 s)
    argv = ["check", "--robots", "0,0 9,1 1,9 10,10 5,0", "--meeting", "5,5", "--algorithm",
            "go-to-target", "--no-reduction", "--max-memory-mb", "12000", "--json"]
    proc = subprocess.Popen([sys.executable, "-m", "gather_verify", *argv], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, start_new_session=True,
                            preexec_fn=default_ctrl_c)
    started = time.monotonic()
    interrupt_when(proc, lambda: time.monotonic() - started > 2.5)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    lines = err.decode().strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("interrupted"), err
    assert "run the same command again" in lines[0] and "Traceback" not in err.decode()
    assert out == b""


def test_ctrl_c_during_sweep_keeps_results_and_resumes(tmp_path: Path) -> None:
    db = tmp_path / "sweep.sqlite"
    # one meeting node: 588 rows, seconds of work to interrupt (two meeting nodes: 5254 rows,
    # a minute of CPU for the resume, and nothing more checked)
    argv = ["sweep", "--robots", "3", "--meeting", "1", "--box", "4x4", "--algorithm",
            "go-to-target", "--scheduler", "async", "--workers", "2", "--db", str(db), "--json",
            "--engine", "per-config"]  # rows a few at a time (union: this box is one class)

    def rows() -> int:
        if not db.exists():
            return 0
        try:
            with sqlite3.connect(db, timeout=1) as con:
                return con.execute("SELECT COUNT(*) FROM results").fetchone()[0]
        except sqlite3.Error:
            return 0

    proc = subprocess.Popen([sys.executable, "-m", "gather_verify", *argv], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, start_new_session=True,
                            preexec_fn=default_ctrl_c)
    interrupt_when(proc, lambda: rows() >= 8)
    out, err = proc.communicate(timeout=60)
    text = err.decode()
    assert proc.returncode == 130, text
    lines = text.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in text, text
    assert str(db) in lines[0] and "run the same command again to resume" in lines[0]
    kept = rows()
    assert kept >= 8
    resumed = cli(argv, "0")
    assert resumed.returncode in (0, 1, 3), resumed.stderr
    assert json.loads(resumed.stdout)["total"] > kept


_RSS_AFTER_FORK = """
import os
from gather_verify.engine.explore import rss_mb

before = rss_mb()
block = b"\\x01" * (96 << 20)  # written: every page resident
assert rss_mb() > before + 64, (before, rss_mb())
read, write = os.pipe()
pid = os.fork()
if pid == 0:  # the child frees the block: its size drops, the parent's does not
    del block
    os.write(write, str(rss_mb()).encode())
    os._exit(0)
os.waitpid(pid, 0)
child = float(os.read(read, 64))
assert child < rss_mb() - 64, (child, rss_mb())
"""


def test_the_resident_size_read_is_this_process_s_own_after_a_fork() -> None:
    """The memory limits read ``/proc/self/statm`` through a file kept open: it must follow
    an allocation, and a forked worker must read its own size, not its parent's. Run in a
    fresh interpreter: inside the test session other tests' memory is freed concurrently
    (the garbage collector, the allocator giving pages back), which moved the reading."""
    done = subprocess.run([sys.executable, "-c", _RSS_AFTER_FORK], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr
