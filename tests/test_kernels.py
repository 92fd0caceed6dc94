"""The compiled kernels (``gather_verify.kernels``) against the numpy/Python reference
path they replace, field by field: the explorations (keys, parents, graph, counts,
violations) and the whole ``run_check`` reports (verdicts, per-property results, max moves,
traces), on every scenario under ``scenarios/`` and on whole small boxes; and the round
schedulers' bulk step on random frontiers."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from gather_verify import kernels
from gather_verify.engine.bulk_step import successor_keys
from gather_verify.engine.canonical_keys import Canon
from gather_verify.engine.columns import GrowingBits, GrowingIds, first_sources
from gather_verify.engine.fast_explore import explore_fast
from gather_verify.engine.key_index import KeyIndex
from gather_verify.model.configuration import Configuration
from gather_verify.plane_check import run_check
from gather_verify.properties.graph import longest_path, strongly_connected
from gather_verify.scenario import load_scenario
from gather_verify.scenario_tests import run_expectation
from gather_verify.sweeps.census import enumerate_configurations
from schedulers import Frontier, get_scheduler
from schedulers.base import bulk_round_keys, bulk_rounds, numpy_rounds

pytestmark = pytest.mark.skipif(not kernels.available(), reason="numba is not installed")

ROOT = Path(__file__).resolve().parent.parent / "scenarios"
FILES = [p for p in sorted(ROOT.rglob("*.json")) if load_scenario(p).world == "grid"]
VOLATILE = ("seconds", "peak_rss_mb")


def both(run):
    """``run()`` with the kernels on, then off (the reference path)."""
    try:
        kernels.use(True)
        fast = run()
        kernels.use(False)
        ref = run()
    finally:
        kernels.use(None)
    return fast, ref


def same_report(a: dict, b: dict) -> None:
    strip = {k: v for k, v in a.items() if k not in VOLATILE}
    assert strip == {k: v for k, v in b.items() if k not in VOLATILE}


def same_exploration(a, b) -> None:
    assert (a.states, a.transitions, a.stopped, a.changed_loops) == \
        (b.states, b.transitions, b.stopped, b.changed_loops)
    for field in ("keys", "parents", "offsets", "targets", "weights"):
        assert np.array_equal(getattr(a, field).array, getattr(b, field).array), field
    assert a.violations == b.violations
    assert a.vacuous == b.vacuous
    if a.stopped is not None:  # the graph analyses run on complete searches only
        return
    la, lb = longest_path(a), longest_path(b)
    assert (la.max_moves, la.path) == (lb.max_moves, lb.path)
    if a.states <= 20_000:
        assert strongly_connected(a) == strongly_connected(b)


def _cases() -> list:
    cases = []
    for path in FILES:
        scenario = load_scenario(path)
        for i, expectation in enumerate(scenario.expectations):
            marks = [pytest.mark.slow] if expectation.options.get("slow") else []
            cases.append(pytest.param(path, i, marks=marks,
                                      id=f"{path.relative_to(ROOT)}[{i}]"))
    return cases


@pytest.mark.parametrize(("path", "index"), _cases())
def test_every_scenario_gives_the_same_report(path: Path, index: int) -> None:
    scenario = load_scenario(path)
    expectation = scenario.expectations[index]
    fast, ref = both(lambda: run_expectation(scenario, expectation))
    same_report(fast, ref)


def _box(algorithm: str):
    out = []
    for n in (1, 2, 3):
        for m in (1, 2):
            out += [(algorithm, c) for c in enumerate_configurations(n, m, 3, 3)]
    return out


BOXES = [pytest.param(a, s, r, marks=[] if (a, s, r) == ("go-to-target", "async", False)
                       else [pytest.mark.slow])
         for a in ("go-to-target", "paper") for s in ("async", "ssync") for r in (True, False)]


@pytest.mark.parametrize(("algorithm", "scheduler", "reduction"), BOXES)
def test_whole_small_box_gives_the_same_reports(algorithm, scheduler, reduction) -> None:
    """The 3 x 3 census, n <= 3, m <= 2: every configuration, every property."""
    checked = 0
    for _, c in _box(algorithm):
        fast, ref = both(lambda c=c: run_check(c, algorithm=algorithm, scheduler=scheduler,
                                               reduction=reduction, max_states=200_000,
                                               max_seconds=600, force=True))
        same_report(fast, ref)
        checked += 1
    assert checked > 100


@pytest.mark.parametrize(("robots", "meeting", "algorithm"), [
    ([(0, 0), (3, 1), (1, 4)], [(2, 2)], "go-to-target"),
    ([(0, 0), (3, 1)], [(2, 2)], "broken-away"),
    ([(0, 0), (0, 1), (3, 3)], [(1, 2), (2, 1)], "paper"),
    ([(1, 2), (3, 2)], [(0, 0), (4, 0), (0, 3)], "broken-drift"),
])
@pytest.mark.parametrize("scheduler", ["async", "ssync", "fsync"])
def test_explorations_are_the_same_field_by_field(robots, meeting, algorithm, scheduler) -> None:
    c = Configuration(robots, meeting, initial=True)
    for reduction in (False, True):
        fast, ref = both(lambda r=reduction: explore_fast(c, algorithm, scheduler, reduction=r))
        same_exploration(fast, ref)


@pytest.mark.slow
def test_the_issue_8_instance_is_the_same() -> None:
    """4,939,200 states: the full verdict with reductions off, both paths."""
    c = Configuration([(0, 0), (5, 1), (1, 5), (6, 6), (3, 0)], [(3, 3)], initial=True)
    fast, ref = both(lambda: run_check(c, algorithm="go-to-target", scheduler="async",
                                       reduction=False, max_states=30_000_000,
                                       max_seconds=3600))
    same_report(fast, ref)
    assert fast["states"] == 4_939_200 and fast["max_moves"] == 23


def test_the_compiled_index_numbers_keys_as_the_reference() -> None:
    rng = np.random.default_rng(7)
    a, b = KeyIndex(bits=4, compiled=True), KeyIndex(bits=4, compiled=False)
    for _ in range(30):
        q = rng.integers(0, 5000, size=int(rng.integers(0, 2000))).astype(np.uint64)
        ia, fa = a.find_or_add(q)
        ib, fb = b.find_or_add(q)
        assert ia.tolist() == ib.tolist() and fa.tolist() == fb.tolist()
        if rng.random() < 0.2:
            a.truncate(a.count // 2)
            b.truncate(b.count // 2)
    assert a.count == b.count and a.keys[:a.count].tolist() == b.keys[:b.count].tolist()


@settings(max_examples=60, deadline=None)
@given(st.lists(st.lists(st.integers(0, 40), max_size=300), min_size=1, max_size=6),
       st.sampled_from([1, 2**40, 2**63]))
def test_the_compiled_index_numbers_repeated_keys_as_the_reference(batches, scale) -> None:
    """Keys repeated within a call (the compiled pass finds them in its call's own table)
    and keys alike in their low bits (long probe runs there): the same ids and first
    occurrences as the reference, call after call, larger calls after smaller ones."""
    a, b = KeyIndex(bits=3, compiled=True), KeyIndex(bits=3, compiled=False)
    for batch in batches:
        q = (np.array(batch, dtype=np.uint64) * np.uint64(scale)) if batch else \
            np.empty(0, dtype=np.uint64)
        ia, fa = a.find_or_add(q)
        ib, fb = b.find_or_add(q)
        assert ia.tolist() == ib.tolist() and fa.tolist() == fb.tolist()
    assert a.keys[:a.count].tolist() == b.keys[:b.count].tolist()


def test_the_compiled_index_outgrows_its_tagged_slots(monkeypatch) -> None:
    """Ids past the tagged slots' id bits (6 here, 24 in a search): the table is rebuilt
    without tags and numbers on as the reference."""
    monkeypatch.setattr("gather_verify.engine.key_index.TAGGED_IDS", 6)
    rng = np.random.default_rng(3)
    a, b = KeyIndex(bits=3, compiled=True), KeyIndex(bits=3, compiled=False)
    for _ in range(12):
        q = rng.integers(0, 400, size=40).astype(np.uint64)
        ia, fa = a.find_or_add(q)
        ib, fb = b.find_or_add(q)
        assert ia.tolist() == ib.tolist() and fa.tolist() == fb.tolist()
    assert a.idbits == 31 and a.count == b.count > 63


def test_longest_path_kernel_finds_cycles_and_bounds() -> None:
    # 0 -> 1 -> 2, 0 -> 2 (weights 1, 1, 0): best from 0 is 2; a self-loop is no edge
    off = np.array([0, 2, 4, 5], dtype=np.int32)
    tgt = np.array([1, 2, 2, 1, 2], dtype=np.int32)
    w = np.array([1, 0, 1, 0, 5], dtype=np.int8)
    assert kernels.longest_path(off, tgt, w).tolist() == [2, 1, 0]
    tgt[3] = 0  # 1 -> 0: a cycle
    assert kernels.longest_path(off, tgt, w)[0] == -1
    # an edge to a smaller id without a cycle (the depth-first search, not the sweep):
    # 0 -> 2 (1), 2 -> 1 (1), 1 -> 1 (a self-loop, no edge)
    off = np.array([0, 1, 2, 3], dtype=np.int32)
    tgt = np.array([2, 1, 1], dtype=np.int32)
    w = np.array([1, 7, 1], dtype=np.int8)
    assert kernels.longest_path(off, tgt, w).tolist() == [2, 0, 1]


def test_switching_the_kernels_off_runs_the_reference(monkeypatch) -> None:
    monkeypatch.setenv(kernels.ENV, "numpy")
    assert not kernels.enabled()
    assert not KeyIndex().compiled
    monkeypatch.setenv(kernels.ENV, "1")
    assert kernels.enabled() and KeyIndex().compiled


@pytest.mark.parametrize(("n", "m"), [(2, 1), (3, 1), (2, 3), (3, 3)])  # m = 2: a rotation swaps them
def test_never_in_u_is_exact_on_a_whole_box(n, m) -> None:
    """Where every symmetry of M fixes a meeting node, no configuration is in U (the shortcut
    of FactsTable.in_u_of), with multiplicities too; and the shortcut does not claim more."""
    from gather_verify.model.symmetry import meeting_automorphisms
    from gather_verify.paper.classes import classify_configuration, never_in_u

    claimed = 0
    for c in enumerate_configurations(n, m, 3, 3):
        aut = meeting_automorphisms(c)
        if never_in_u(aut, c.meeting_nodes):
            claimed += 1
            merged = Configuration((c.robots[0],) + c.robots[:-1], c.meeting_nodes)
            assert not any(classify_configuration(x, aut_m_all=aut).in_U for x in (c, merged))
    assert claimed
    # where a symmetry of M fixes no meeting node, U is possible: no claim
    c = Configuration([(0, 1), (2, 1)], [(0, 0), (2, 0)])
    assert classify_configuration(c).in_U
    assert not never_in_u(meeting_automorphisms(c), c.meeting_nodes)


@pytest.mark.parametrize("sizes", [(1024, 1 << 14, 0), (4, 16, 64)])
def test_the_hashed_successor_rows_give_the_same_exploration(monkeypatch, sizes) -> None:
    """Past ``PairRows.DIRECT_ROWS`` rows the (row, cell, step) triples go through a hash
    index: forced here from the first row; and a direct table that doubles, is then
    reserved whole, then hands over to the hash index within one search."""
    from gather_verify.engine.bulk_step import PairRows

    for name, value in zip(("FIRST_ROWS", "SMALL_ROWS", "DIRECT_ROWS"), sizes, strict=True):
        monkeypatch.setattr(PairRows, name, value)
    c = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)
    fast, ref = both(lambda: explore_fast(c, "go-to-target", "async", reduction=False))
    same_exploration(fast, ref)
    fast, ref = both(lambda: run_check(c, algorithm="paper", scheduler="async",
                                       reduction=False, max_seconds=600))
    same_report(fast, ref)


@st.composite
def round_frontiers(draw):
    """A frontier of idle robots with arbitrary move masks (empty, staying only, any steps),
    a neighbour table with cells outside the region (-1), an event budget, and a round
    scheduler's name or a matrix of activated subsets (any rows, an empty one included)."""
    n, s, cells = draw(st.integers(1, 5)), draw(st.integers(0, 12)), draw(st.integers(1, 30))
    codes = draw(arrays(np.int64, (s, n), elements=st.integers(0, cells - 1))) * 5
    masks = draw(arrays(np.uint8, (s, n), elements=st.integers(0, 31)))
    neighbour = draw(arrays(np.int64, (cells, 4), elements=st.integers(-1, cells - 1)))
    subsets = draw(st.sampled_from(["ssync", "fsync", "centralized"])
                   | arrays(np.bool_, st.tuples(st.integers(1, 6), st.just(n))))
    return Frontier(codes, masks, neighbour), draw(st.integers(1, 4000)), subsets


@settings(max_examples=80, deadline=None)
@given(round_frontiers())
def test_compiled_rounds_are_the_numpy_rounds(case) -> None:
    """The round schedulers' compiled bulk step gives the numpy reference's events, field by
    field and dtype by dtype: the states taken within the budget, each event's source and
    weight, each change's event, robot and new code (-1 when it leaves the region)."""
    frontier, budget, subsets = case

    def run():
        if isinstance(subsets, str):
            return get_scheduler(subsets).bulk_successors(frontier, budget)
        return bulk_rounds(frontier, budget, subsets) if kernels.enabled() else \
            numpy_rounds(frontier, budget, subsets)

    fast, ref = both(run)
    assert fast.states == ref.states
    for field in ("source", "weight", "robot", "code", "event"):
        a, b = getattr(fast, field), getattr(ref, field)
        assert a.dtype == b.dtype and a.tolist() == b.tolist(), field


@settings(max_examples=15, deadline=None)
@given(st.integers(6, 8), st.integers(1, 4), st.integers(1, 20000), st.data())
def test_compiled_rounds_of_many_subsets(n, s, budget, data) -> None:
    """SSYNC with 6 to 8 robots: 63 to 255 activated subsets a state (masks of up to two
    choices, a step outside the region among them): the compiled step is the numpy one."""
    cells = 12
    codes = data.draw(arrays(np.int64, (s, n), elements=st.integers(0, cells - 1))) * 5
    masks = data.draw(arrays(np.uint8, (s, n), elements=st.sampled_from([16, 1, 17, 6, 24])))
    neighbour = data.draw(arrays(np.int64, (cells, 4), elements=st.integers(-1, cells - 1)))
    frontier = Frontier(codes, masks, neighbour)
    fast, ref = both(lambda: get_scheduler("ssync").bulk_successors(frontier, budget))
    assert fast.states == ref.states >= 1
    for field in ("source", "weight", "robot", "code", "event"):
        a, b = getattr(fast, field), getattr(ref, field)
        assert a.dtype == b.dtype and a.tolist() == b.tolist(), field


@settings(max_examples=80, deadline=None)
@given(round_frontiers(), st.booleans(), st.integers(0, 3), st.randoms(use_true_random=False))
def test_compiled_event_keys_are_the_numpy_keys(case, anonymity, images, rnd) -> None:
    """Several changes per event: the compiled successor keys are the numpy reference's (the
    successors' codes packed; under the reductions sorted and the least over random code
    tables), and so are the changed robots' old codes."""
    frontier, budget, subsets = case
    bulk = get_scheduler(subsets).bulk_successors(frontier, budget) \
        if isinstance(subsets, str) else numpy_rounds(frontier, budget, subsets)
    if bulk.event is None:  # one change per event: the other compiled path
        return
    inside = np.ones(len(bulk.source), dtype=bool)  # events whose robots all stay in the region
    inside[bulk.event[bulk.code < 0]] = False
    keep = inside[bulk.event]
    renumber = np.cumsum(inside) - 1
    src, robot, new = bulk.source[inside], bulk.robot[keep], bulk.code[keep]
    event = renumber[bulk.event[keep]]
    cells = len(frontier.neighbour)
    tables = [[rnd.randrange(5 * cells) for _ in range(5 * cells)] for _ in range(images)]
    reduced = anonymity or images > 0
    enc = SimpleNamespace(anonymity=anonymity, tables=tables, base=5 * cells)
    canon = Canon(enc, frontier.codes.shape[1])  # type: ignore[arg-type]
    codes = frontier.codes[:bulk.states]
    keys = canon.keys(codes)
    fast, old, none = successor_keys(keys, codes, src, robot, new, event, canon, reduced, True)
    ref, ref_old, ref_codes = successor_keys(keys, codes, src, robot, new, event, canon, reduced,
                                             False)
    assert none is None and ref_codes is not None
    assert fast.tolist() == ref.tolist() == canon.keys(ref_codes).tolist()
    assert old.tolist() == ref_old.tolist()


@settings(max_examples=80, deadline=None)
@given(round_frontiers())
def test_compiled_round_keys_are_the_numpy_rounds_keyed(case) -> None:
    """``bulk_round_keys`` (events and successor keys in one compiled pass) against the numpy
    rounds and the numpy keys of their successors: the same states taken, then, up to the
    first event that leaves the region (included, and the list stops there), the same
    sources, weights and keys of the successors' codes packed."""
    if not kernels.enabled():
        pytest.skip("the compiled kernels are off (numba missing, or GATHER_VERIFY_KERNELS)")
    frontier, budget, subsets = case
    if isinstance(subsets, str):
        subsets = get_scheduler(subsets).activations(frontier.codes.shape[1])
    n, cells = frontier.codes.shape[1], len(frontier.neighbour)
    canon = Canon(SimpleNamespace(anonymity=False, tables=[], base=5 * cells), n)  # type: ignore[arg-type]
    keys = canon.keys(frontier.codes)
    got = bulk_round_keys(frontier, budget, subsets, keys, canon.powers)
    ref = numpy_rounds(frontier, budget, subsets)
    assert got.states == ref.states
    leaving = ref.event[ref.code < 0]
    cut = int(leaving[0]) + 1 if len(leaving) else len(ref.source)
    assert got.leaves == bool(len(leaving))
    assert got.source.tolist() == ref.source[:cut].tolist()
    assert got.weight.dtype == ref.weight.dtype
    assert got.weight.tolist() == ref.weight[:cut].tolist()
    succ = frontier.codes[ref.source]
    succ[ref.event, ref.robot] = ref.code
    inside = cut - got.leaves  # the leaving event's key is none
    assert got.keys[:inside].tolist() == canon.keys(succ[:inside]).tolist()


def random_graph(seed: int, states: int = 60, edges: int = 200) -> tuple[np.ndarray, np.ndarray]:
    """A CSR graph over ``states`` ids (every state expanded), random targets."""
    rng = np.random.default_rng(seed)
    degrees = rng.multinomial(edges, np.ones(states) / states)
    offsets = np.zeros(states + 1, dtype=np.int32)
    np.cumsum(degrees, out=offsets[1:])
    return offsets, rng.integers(0, states, edges).astype(np.int32)


@pytest.mark.parametrize("seed", range(5))
def test_parents_read_off_the_edges(seed: int) -> None:
    # the compiled first_sources and its numpy reference: per state, the first (id, edge)
    # with an edge to it; -1 for the seeds and for states no edge reaches
    offsets, targets = random_graph(seed)
    seeds = seed % 3 + 1
    compiled = first_sources(offsets, targets, seeds, 60)
    kernels.use(False)
    try:
        plain = first_sources(offsets, targets, seeds, 60)
    finally:
        kernels.use(None)
    expected = [-1] * 60
    for s in range(60):
        for t in targets[offsets[s]:offsets[s + 1]].tolist():
            if t >= seeds and expected[t] < 0:
                expected[t] = s
    assert compiled.tolist() == plain.tolist() == expected


@pytest.mark.parametrize("seed", range(5))
def test_longest_path_kernel_reads_bits_as_bytes(seed: int) -> None:
    # weights packed a bit each (what a search keeps while they are all 0 or 1) give the
    # same totals as a byte each, on an acyclic graph (edges to larger ids) and a cyclic one
    offsets, targets = random_graph(seed)
    src = np.repeat(np.arange(60), np.diff(offsets))
    weights = np.random.default_rng(seed).integers(0, 2, len(targets)).astype(np.int8)
    bits = GrowingBits(4)
    for part in np.array_split(weights, 7):  # appended in chunks of any length
        bits.extend(part)
    column = bits.column()
    assert list(column) == weights.tolist() == column.array.tolist()
    assert column[3:50] == weights[3:50].tolist() and column[-1] == weights[-1]
    for tgt in (np.maximum(targets, src + 1).clip(max=59).astype(np.int32), targets):
        one = kernels.longest_path(offsets, tgt, weights, False)
        assert one.tolist() == kernels.longest_path(offsets, tgt, column.bits, True).tolist()
    acyclic = np.maximum(targets, src + 1).clip(max=59).astype(np.int32)
    zero = np.zeros_like(column.bits)  # a column whose bits were lost reads as no move
    assert kernels.longest_path(offsets, acyclic, zero, True).max() == 0 < \
        kernels.longest_path(offsets, acyclic, column.bits, True).max()


@pytest.mark.parametrize("seed", range(3))
def test_target_ids_three_bytes_each(seed: int) -> None:
    # ids kept three bytes each while below 2**24, widened in place to four past it; the
    # kernels read the packed column as they read int32 ids
    rng = np.random.default_rng(seed)
    ids = GrowingIds(8)
    values: list[int] = []
    for _ in range(30):
        part = rng.integers(0, 1 << 24, rng.integers(0, 40))
        ids.extend(part, 1 << 24)
        values += part.tolist()
    column = ids.column()
    assert column.packed and len(column.raw) == 3 * len(values)
    assert list(column) == column.array.tolist() == values == column[:]
    assert [column[i] for i in range(-3, 0)] == values[-3:]
    offsets, targets = random_graph(seed)
    packed = GrowingIds()
    packed.extend(targets.astype(np.int64), 60)
    raw = packed.column().raw
    for a, b in ((targets, False), (raw, True)):
        assert first_sources(offsets, packed.column() if b else a, 1, 60).tolist() == \
            first_sources(offsets, targets, 1, 60).tolist()
    assert kernels.longest_path(offsets, raw, np.ones(len(targets), np.int8), False, True)[0] \
        == kernels.longest_path(offsets, targets, np.ones(len(targets), np.int8))[0]
    one, two = kernels.tarjan_csr(offsets, raw, True, True), kernels.tarjan_csr(offsets, targets, True)
    assert one[0].tolist() == two[0].tolist() and one[1].tolist() == two[1].tolist()
    big = rng.integers(1 << 24, 1 << 30, 50)  # past 2**24: four bytes each from now on
    ids.extend(big, 1 << 30)
    column = ids.column()
    assert not column.packed and list(column) == values + big.tolist()


MEETINGS = [[(3, 3)], [(1, 1), (5, 5)], [(1, 1), (5, 1), (1, 5), (5, 5)], [(2, 3), (4, 3)],
            [(0, 0), (2, 1)]]
"""Meeting nodes with ``Aut(M)`` of 8, 4 (two diagonal nodes), 8 (a square's corners), 4 and
1 element(s): the symmetry tables of :class:`Encoding` over the box ``(0, 0, 6, 6)``."""


@settings(max_examples=150, deadline=None)
@given(st.sampled_from(MEETINGS), st.booleans(), st.integers(1, 6), st.data())
def test_compiled_one_change_canonical_keys_are_the_reference(meeting, anonymity, n,
                                                              data) -> None:
    """One change per event under the reductions: the compiled keys, made from each source's
    images with one code changed, are ``Canon.keys`` of the successors' codes (sorted, the
    least over the real symmetry tables of ``Aut(M)``), on random states with towers (robots
    drawn from a few cells), sources in any order and many events per source."""
    from gather_verify.engine.encoding import Encoding, symmetry_group

    initial = Configuration([(0, 0)], meeting, initial=True)
    enc = Encoding((0, 0, 6, 6), symmetry_group(initial, "all"), anonymity=anonymity)
    canon = Canon(enc, n)
    few = data.draw(st.lists(st.integers(0, enc.base - 1), min_size=1, max_size=4))
    code = st.sampled_from(few) | st.integers(0, enc.base - 1)  # towers, or anywhere
    s = data.draw(st.integers(1, 6))
    codes = np.array(data.draw(st.lists(st.lists(code, min_size=n, max_size=n), min_size=s,
                                        max_size=s)), dtype=np.int64)
    events = data.draw(st.lists(st.tuples(st.integers(0, s - 1), st.integers(0, n - 1), code),
                                min_size=1, max_size=40))
    if data.draw(st.booleans()):
        events.sort()  # as a scheduler gives them: by source
    src, robot, new = (np.array(c, dtype=np.int64) for c in zip(*events, strict=True))
    keys = canon.keys(codes)
    fast, old, _ = successor_keys(keys, codes, src, robot, new, None, canon, True, True)
    ref, ref_old, ref_codes = successor_keys(keys, codes, src, robot, new, None, canon, True,
                                             False)
    assert ref_codes is not None
    assert fast.tolist() == ref.tolist() == canon.keys(ref_codes).tolist()
    assert old.tolist() == ref_old.tolist()


@settings(max_examples=40, deadline=None)
@given(st.integers(1, 6), st.integers(1, 300), st.data())
def test_compiled_async_step_is_the_numpy_step(n, s, data) -> None:
    """ASYNC's compiled bulk step gives the numpy reference's events, field by field and dtype
    by dtype (``int32`` sources, robots and codes: a chunk's largest arrays)."""
    cells = 12
    codes = data.draw(arrays(np.int64, (s, n), elements=st.integers(0, 5 * cells - 1)))
    masks = data.draw(arrays(np.uint8, (s, n), elements=st.integers(0, 15)))
    neighbour = data.draw(arrays(np.int64, (cells, 4), elements=st.integers(-1, cells - 1)))
    frontier = Frontier(codes, masks, neighbour)
    fast, ref = both(lambda: get_scheduler("async").bulk_successors(frontier, 1 << 19))
    assert fast.states == ref.states == s and fast.event is ref.event is None
    for field in ("source", "weight", "robot", "code"):
        a, b = getattr(fast, field), getattr(ref, field)
        assert a.dtype == b.dtype and a.tolist() == b.tolist(), field
    assert fast.source.dtype == np.int32


@pytest.mark.parametrize("known", [0.0, 0.5, 1.0])
def test_successor_rows_settles_the_known_and_lists_the_rest(known: float) -> None:
    """``successor_rows`` against a direct reading of its table: a known successor row (stored
    plus one) is read, the rest are listed with their slots, past the list's first 1,024
    entries too (it grows as they come)."""
    if not kernels.enabled():
        pytest.skip("the compiled kernels are off (numba missing, or GATHER_VERIFY_KERNELS)")
    from gather_verify.kernels.codes import Z2_DEGREE, Z2_SLOTS

    rng = np.random.default_rng(7)
    n, states, m, cells = 3, 50, 5000, 30
    neighbour = rng.integers(-1, cells, (cells, Z2_DEGREE))
    rows = rng.integers(0, 40, states)
    rank = rng.integers(0, n, (states, n))
    src = np.sort(rng.integers(0, states, m)).astype(np.int32)
    robot = rng.integers(0, n, m).astype(np.int32)
    old = (rng.integers(0, cells, m) * Z2_SLOTS).astype(np.int32)
    step = rng.integers(0, Z2_DEGREE + 1, m)  # the last: a cell no step of it reaches
    dest = np.where(step < Z2_DEGREE, neighbour[old // Z2_SLOTS, np.minimum(step, 3)], -2)
    new = np.where(rng.random(m) < 0.2, old, np.maximum(dest, 0) * Z2_SLOTS).astype(np.int32)
    succ = np.zeros((40, n, Z2_DEGREE), dtype=np.int32)
    fill = rng.random(succ.shape) < known
    succ[fill] = rng.integers(0, 1000, int(fill.sum())) + 1
    out, miss, slot = kernels.successor_rows(rows, rank, src, robot, old, new, neighbour, succ)
    want_miss, want_slot = [], []
    for e in range(m):
        s, oc, nc = src[e], old[e] // Z2_SLOTS, new[e] // Z2_SLOTS
        if oc == nc:
            assert out[e] == rows[s]
            continue
        ks = [d for d in range(Z2_DEGREE) if neighbour[oc, d] == nc]
        at = (rows[s] * n + rank[s, robot[e]]) * Z2_DEGREE + ks[0] if ks else -1
        if at >= 0 and succ.reshape(-1)[at] > 0:
            assert out[e] == succ.reshape(-1)[at] - 1
            continue
        want_miss.append(e)
        want_slot.append(at)
    assert miss.tolist() == want_miss and slot.tolist() == want_slot
    assert out.dtype == np.int32 and (known < 1.0) == (len(miss) > 1024)
