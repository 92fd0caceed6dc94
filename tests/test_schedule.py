"""Predicted wall time of a sweep on W workers (sweeps/schedule.py, report --workers-curve)."""

from __future__ import annotations

import json

import pytest
from hypothesis import given
from hypothesis import strategies as st

from gather_verify.cli import main
from gather_verify.sweeps.schedule import makespan, predict, task_seconds


@given(st.lists(st.floats(0, 100), min_size=1, max_size=40), st.integers(1, 12))
def test_makespan_bounds(seconds, workers):
    seconds = sorted(seconds, reverse=True)
    t = makespan(seconds, workers)
    assert t >= max(seconds) - 1e-9 and t >= sum(seconds) / workers - 1e-9
    assert t <= sum(seconds) / workers + max(seconds) + 1e-9  # list scheduling's bound
    assert makespan(seconds, 1) == pytest.approx(sum(seconds))


def test_tasks_are_shapes_of_m_per_sweep():
    rows = [{"sweep": 1, "index": 0, "meeting_nodes": [[0, 0], [1, 0]], "seconds": 1.0},
            {"sweep": 1, "index": 1, "meeting_nodes": [[5, 5], [5, 6]], "seconds": 2.0},  # same shape
            {"sweep": 1, "index": 2, "meeting_nodes": [[0, 0], [2, 1]], "seconds": 4.0},
            {"sweep": 2, "index": 0, "meeting_nodes": [[0, 0], [1, 0]], "seconds": 8.0}]
    # handed out as a sweep does: the most configurations first, then sweep and index
    assert task_seconds(rows) == [3.0, 4.0, 8.0]
    assert predict([8.0, 4.0, 3.0], [1, 2, 3]) == {1: 15.0, 2: 8.0, 3: 8.0}


def test_report_workers_curve(tmp_path, capsys):
    db = str(tmp_path / "s.sqlite")
    assert main(["sweep", "--robots", "2", "--meeting", "2", "--box", "3x3", "--algorithm",
                 "paper", "--workers", "1", "--db", db, "--json"]) in (0, 1)
    capsys.readouterr()
    assert main(["report", "--db", db, "--workers-curve", "1,2,64", "--json"]) == 0
    curve = json.loads(capsys.readouterr().out)["workers_curve"]
    assert curve["tasks"] > 1 and set(curve["wall"]) == {"1", "2", "64"}
    assert curve["wall"]["1"] == pytest.approx(curve["seconds"], abs=1e-2)
    assert curve["wall"]["64"] == pytest.approx(curve["largest"], abs=1e-2)
    assert main(["report", "--db", db, "--workers-curve", "two"]) == 2
    assert "bad --workers-curve" in capsys.readouterr().err


def test_a_finite_world_s_rows_are_cut_into_the_tasks_its_sweep_hands_out():
    """A finite world's nodes are numbers, not points: its rows are costed by the chunks of
    configurations its sweep hands out (``report --workers-curve`` on such a database)."""
    from gather_verify.sweeps.schedule import WORLD_CHUNK, task_seconds
    from gather_verify.sweeps.sweep import CHUNK

    assert WORLD_CHUNK == CHUNK
    rows = [{"sweep": 1, "index": k, "meeting_nodes": [] if k % 2 else [0], "seconds": 1.0}
            for k in range(2 * CHUNK + 1)]
    assert task_seconds(rows) == [CHUNK, CHUNK, 1.0]
