"""The union engine's compiled kernel (engine/union_kernels.py) against the numpy
reference: per-seed counts on random acyclic graphs, and whole sweep rows."""

from __future__ import annotations

import os

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gather_verify import kernels
from gather_verify.engine import union, union_kernels
from gather_verify.sweeps.census import enumerate_configurations
from gather_verify.sweeps.mclass import class_tasks, decide_class
from gather_verify.sweeps.sweep import SweepSettings, configuration_key

pytestmark = pytest.mark.skipif(not kernels.available(), reason="numba is not installed")


def _analyse(path: str, *args):
    """``union._analyse`` on the ``numpy`` or ``numba`` path."""
    old = os.environ.get("GATHER_VERIFY_KERNELS")
    os.environ["GATHER_VERIFY_KERNELS"] = path
    try:
        return union._analyse(*args)
    finally:
        if old is None:
            os.environ.pop("GATHER_VERIFY_KERNELS", None)
        else:
            os.environ["GATHER_VERIFY_KERNELS"] = old


def _peeled(S: int, edges: list[tuple[int, int]]):
    """The CSR arrays and the numpy path's peeling rounds (the reference) for a DAG."""
    src = np.array([a for a, _ in edges], dtype=np.int64)
    tgt = np.array([b for _, b in edges], dtype=np.int64)
    w = np.ones(len(edges), dtype=np.int64)
    flags = np.zeros(S, dtype=np.uint8)
    box = np.zeros((S, 4), dtype=np.int64)
    _, _, _, rounds, pred_off, pred_src, out_off, out_tgt = _analyse("numpy", S, src, tgt, w,
                                                                     flags, box)
    return rounds, pred_off, pred_src, out_off, out_tgt


def _topo(rounds):
    """Every state after its predecessors (the kernel's order: the rounds reversed)."""
    return np.concatenate([r[::-1] for r in rounds[::-1]]) if rounds else np.zeros(0, np.int64)


@st.composite
def dags(draw):
    S = draw(st.integers(1, 150))
    pairs = draw(st.lists(st.tuples(st.integers(0, S - 1), st.integers(0, S - 1)), max_size=400))
    edges = sorted({(a, b) for a, b in pairs if a < b})  # a < b: acyclic
    seeds = draw(st.lists(st.integers(0, S - 1), min_size=1, max_size=140))
    events = draw(st.lists(st.integers(0, 30), min_size=S, max_size=S))
    return S, edges, np.array(seeds, dtype=np.int64), np.array(events, dtype=np.int64)


@settings(max_examples=150, deadline=None)
@given(dags())
def test_seed_counts_equal_the_numpy_reference(dag):
    S, edges, seeds, events = dag
    rounds, pred_off, pred_src, out_off, out_tgt = _peeled(S, edges)
    counts = np.full(len(seeds), -1, dtype=np.int64)
    transitions = np.full(len(seeds), -1, dtype=np.int64)
    union._count(seeds, np.arange(len(seeds)), rounds, pred_off, pred_src, events, S, counts,
                 transitions)
    topo = _topo(rounds)
    got = union_kernels.seed_counts(topo, pred_off, pred_src, out_off, out_tgt, seeds, events)
    assert got[0].tolist() == counts.tolist()
    assert got[1].tolist() == transitions.tolist()


@settings(max_examples=10, deadline=None)
@given(dags(), st.integers(1025, 2600), st.randoms(use_true_random=False))
def test_seed_counts_of_many_seeds_equal_the_numpy_reference(dag, many, rng):
    """More seeds than one pass of the kernel takes (``64 * SEED_WORDS``), repeats included."""
    S, edges, _, events = dag
    seeds = np.array([rng.randrange(S) for _ in range(many)], dtype=np.int64)
    rounds, pred_off, pred_src, out_off, out_tgt = _peeled(S, edges)
    counts = np.full(many, -1, dtype=np.int64)
    transitions = np.full(many, -1, dtype=np.int64)
    union._count(seeds, np.arange(many), rounds, pred_off, pred_src, events, S, counts,
                 transitions)
    got = union_kernels.seed_counts(_topo(rounds), pred_off, pred_src, out_off, out_tgt, seeds,
                                    events)
    assert got[0].tolist() == counts.tolist()
    assert got[1].tolist() == transitions.tolist()


def test_a_wrong_count_is_caught():
    """The comparison can fail: the kernel without the seeds' own states counts less."""
    rounds, pred_off, pred_src, out_off, out_tgt = _peeled(3, [(0, 1), (1, 2)])
    topo = _topo(rounds)
    graph = (pred_off, pred_src, out_off, out_tgt)
    counts, _ = union_kernels.seed_counts(topo, *graph, np.array([0]), np.ones(3))
    assert counts.tolist() == [3]
    assert union_kernels.seed_counts(topo[1:], *graph, np.array([0]),
                                     np.ones(3))[0].tolist() != [3]


@pytest.mark.parametrize("n,m,scheduler", [(2, 2, "async"), (3, 2, "async"), (2, 2, "fsync"),
                                            (2, 2, "ssync"), (3, 2, "round-robin")])
def test_sweep_rows_equal_under_both_paths(monkeypatch, n, m, scheduler):
    s = SweepSettings(robots=n, meeting=m, box=(3, 3), algorithm="paper", scheduler=scheduler,
                      max_memory_mb=8000)
    items = list(enumerate(enumerate_configurations(n, m, 3, 3)))

    def rows():
        out = {}
        for members in class_tasks(items):
            for r in decide_class(s, members, configuration_key).rows:
                out[r["index"]] = {k: v for k, v in r.items() if k != "seconds"}
        return out

    compiled = rows()
    monkeypatch.setenv("GATHER_VERIFY_KERNELS", "numpy")
    assert not kernels.enabled()
    assert rows() == compiled
    assert len(compiled) > 50


@settings(max_examples=150, deadline=None)
@given(dags(), st.lists(st.integers(0, 7), max_size=150), st.data())
def test_peeling_equals_the_numpy_reference(monkeypatch_dag, flag_bits, data):
    """Reachable flags, longest paths and boxes, with some states on cycles (a CYCLE flag)."""
    S, edges, _, _ = monkeypatch_dag
    flags = np.zeros(S, dtype=np.uint8)
    for k, b in enumerate(flag_bits[:S]):
        flags[k] = (1 << b) if b < 6 else 0
    src = np.array([a for a, _ in edges], dtype=np.int64)
    tgt = np.array([b for _, b in edges], dtype=np.int64)
    w = np.array(data.draw(st.lists(st.integers(0, 4), min_size=len(edges), max_size=len(edges))),
                 dtype=np.int64)
    box = np.array(data.draw(st.lists(st.tuples(*[st.integers(-5, 5)] * 4), min_size=S,
                                      max_size=S)), dtype=np.int64).reshape(S, 4)
    ref = _analyse("numpy", S, src, tgt, w, flags, box)
    got = _analyse("numba", S, src, tgt, w, flags, box)
    for a, b in zip(ref[:3], got[:3], strict=True):
        assert a.tolist() == b.tolist()
    assert sorted(_topo(ref[3]).tolist()) == sorted(_topo(got[3]).tolist())  # the peeled states
