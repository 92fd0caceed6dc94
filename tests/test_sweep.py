"""Sweeps: census agreement, resume after SIGKILL, and identical results whoever runs them."""

from __future__ import annotations

import json
import os
import signal
import sqlite3
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from gather_verify.cli import main
from gather_verify.sweeps.store import Store
from gather_verify.sweeps.sweep import SweepSettings, run_sweep, summarise

SMALL = SweepSettings(robots=2, meeting=2, box=(3, 3), algorithm="go-to-target", scheduler="async")


def results_table(db: Path) -> list[tuple]:
    """The deterministic part of a store: every result row, timings excluded."""
    with sqlite3.connect(db) as con:
        return con.execute(
            "SELECT s.settings, r.* FROM results r JOIN sweeps s ON s.id = r.sweep "
            "ORDER BY s.settings, r.key"
        ).fetchall()


def test_sweep_classes_equal_census(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["census", "--robots", "2", "--meeting", "2", "--box", "3x3", "--json"]) == 0
    census = json.loads(capsys.readouterr().out)
    main(["sweep", "--robots", "2", "--meeting", "2", "--box", "3x3", "--algorithm",
          "go-to-target", "--db", str(tmp_path / "s.sqlite"), "--workers", "1", "--json"])
    summary = json.loads(capsys.readouterr().out)
    assert summary["total"] == census["total"]
    assert summary["classes"] == census["classes"]
    assert sum(sum(v.values()) for v in summary["verdicts"].values()) == census["total"]


def test_ranges_sum_the_census(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    total = 0
    for n in (1, 2):
        main(["census", "--robots", str(n), "--meeting", "2", "--box", "3x3", "--json"])
        total += json.loads(capsys.readouterr().out)["total"]
    main(["sweep", "--robots", "1-2", "--meeting", "2", "--box", "3x3", "--algorithm",
          "go-to-target", "--db", str(tmp_path / "r.sqlite"), "--workers", "1", "--json"])
    assert json.loads(capsys.readouterr().out)["total"] == total


def test_rerun_resumes_without_recomputing(tmp_path: Path) -> None:
    db = tmp_path / "s.sqlite"
    first = run_sweep(SMALL, str(db), workers=1, progress=False, limit=5)
    assert first["total"] == 5
    before = results_table(db)
    second = run_sweep(SMALL, str(db), workers=1, progress=False)
    after = results_table(db)
    assert set(before) <= set(after)
    assert second["total"] > 5


def test_the_summary_counted_in_the_store_is_the_summary_of_its_rows(tmp_path: Path) -> None:
    """``run_sweep`` counts its summary in SQL (``Store.totals``, ``Store.slowest``): the same
    dict as :func:`summarise` over the rows read back, down to the order of its keys (the
    text tables print them in that order)."""
    db = tmp_path / "s.sqlite"
    batch = [replace(SMALL, algorithm="broken-stay"), SMALL,
             SweepSettings(robots=3, meeting=2, box=(3, 3), algorithm="paper", scheduler="async")]
    summary = run_sweep(batch, str(db), workers=1, progress=False)
    store = Store(str(db))
    rows = [r for i, _ in store.sweeps() for r in store.results(i)]
    assert any(r["trace"] for r in rows)  # the stored rows carry their traces
    expected = summarise(rows)
    assert summary["failing_properties"] and summary["max_ratio"]  # something to count
    computed = summary.pop("computed")  # how many this run computed: not in the rows
    summary.pop("union_fallbacks")  # why the union engine left some to their own checks
    assert computed == len(rows)
    assert json.dumps(summary) == json.dumps(expected)


@pytest.mark.slow  # a pool, one process and a Dask cluster: the watchdog tests start Dask by default
def test_pool_and_dask_give_identical_results(tmp_path: Path) -> None:
    """A batch of sweeps (one pool or cluster runs them all, its workers sharing the
    configuration facts and the paper's plans) stores what one process stores."""
    pytest.importorskip("dask.distributed")
    batch = [SMALL] + [SweepSettings(robots=n, meeting=2, box=(3, 3), algorithm="paper",
                                     scheduler="async") for n in (2, 3)]
    run_sweep(batch, str(tmp_path / "pool.sqlite"), workers=2, progress=False)
    run_sweep(batch, str(tmp_path / "one.sqlite"), workers=1, progress=False)
    run_sweep(batch, str(tmp_path / "dask.sqlite"), workers=2, dask="local", progress=False)
    pool = results_table(tmp_path / "pool.sqlite")
    assert pool == results_table(tmp_path / "one.sqlite")
    assert pool == results_table(tmp_path / "dask.sqlite")
    assert len(pool) > 10


@pytest.mark.slow  # a long sweep: the default run keeps a shorter test of the same property
def test_handed_off_checks_store_the_same_rows(tmp_path: Path, monkeypatch: pytest.MonkeyPatch
                                               ) -> None:
    """A class that hands its per-configuration checks to the other workers (here all of
    them, at once) stores what one process stores, on a pool and on Dask."""
    pytest.importorskip("dask.distributed")
    from gather_verify.sweeps import sweep as sweep_module

    batch = [SweepSettings(robots=n, meeting=2, box=(3, 3), algorithm="paper",
                           scheduler="async") for n in (2, 3)]
    run_sweep(batch, str(tmp_path / "one.sqlite"), workers=1, progress=False)
    monkeypatch.setattr(sweep_module, "HAND_OFF_SECONDS", 0.0)
    run_sweep(batch, str(tmp_path / "pool.sqlite"), workers=2, progress=False)
    run_sweep(batch, str(tmp_path / "dask.sqlite"), workers=2, dask="local", progress=False)
    one = results_table(tmp_path / "one.sqlite")
    assert one == results_table(tmp_path / "pool.sqlite") == results_table(tmp_path / "dask.sqlite")
    # NOT-APPLICABLE rows always go to the per-configuration check: so some were handed off
    assert any(row[7] == "NOT-APPLICABLE" for row in one)


@pytest.mark.slow  # a long sweep: the default run keeps a shorter test of the same property
def test_sigkill_then_resume_equals_clean_run(tmp_path: Path) -> None:
    """Kill a running sweep with SIGKILL once some rows are committed; the resumed
    store ends with exactly the rows of an uninterrupted run."""
    argv = ["--robots", "3", "--meeting", "1", "--box", "4x3", "--algorithm", "go-to-target",
            "--scheduler", "async", "--workers", "1", "--json",
            "--engine", "per-config"]  # rows committed a few at a time (union: a class at a time)
    killed = tmp_path / "killed.sqlite"
    env = {**os.environ, "PYTHONHASHSEED": "0"}
    proc = subprocess.Popen([sys.executable, "-m", "gather_verify", "sweep", *argv, "--db",
                             str(killed)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            env=env)
    deadline = time.monotonic() + 120
    rows = 0
    while time.monotonic() < deadline and proc.poll() is None:
        if killed.exists():
            try:
                rows = len(Store(killed).done_keys(1))
            except (ValueError, sqlite3.OperationalError):
                rows = 0
            if rows >= 3:
                break
        time.sleep(0.05)
    if proc.poll() is not None:
        pytest.skip("the sweep finished before it could be killed")
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    partial = len(results_table(killed))
    assert partial > 0
    code = main(["sweep", *argv, "--db", str(killed)])
    clean = tmp_path / "clean.sqlite"
    assert main(["sweep", *argv, "--db", str(clean)]) == code
    assert results_table(killed) == results_table(clean)
    assert len(results_table(clean)) > partial


@given(st.lists(st.tuples(st.integers(-9, 9), st.integers(-9, 9)), min_size=1, max_size=5),
       st.sets(st.tuples(st.integers(-9, 9), st.integers(-9, 9)), min_size=1, max_size=4))
def test_configuration_keys_are_the_compact_json_stores_were_keyed_by(robots, meeting) -> None:
    """Rows of every earlier store are found by this key: it must stay this JSON, byte for byte."""
    from gather_verify.model.configuration import Configuration
    from gather_verify.sweeps.sweep import configuration_key

    c = Configuration(robots, meeting)
    assert configuration_key(c) == json.dumps(
        [sorted(map(list, c.robots)), sorted(map(list, c.meeting_nodes))], separators=(",", ":"))


def test_the_kernels_are_warmed_before_any_row_is_timed(tmp_path: Path, monkeypatch) -> None:
    """A sweep compiles (or loads) the bulk engine's kernels before its first row, once per
    scheduler, so no configuration is charged the compile time; a resumed sweep with
    nothing left to compute does not."""
    from gather_verify.sweeps import sweep as module

    calls: list[set[str]] = []
    monkeypatch.setattr(module, "warm_kernels", lambda schedulers: calls.append(set(schedulers)))
    db = str(tmp_path / "w.sqlite")
    run_sweep(SMALL, db, workers=1, progress=False)
    assert calls == [{SMALL.scheduler}]
    run_sweep(SMALL, db, workers=1, progress=False)
    assert calls == [{SMALL.scheduler}]
