"""The values the neighbour tables and robot codes share (gather_verify/kernels/codes.py):
the two "no neighbour" values are distinct and each says what it means, and the Z² code has
degree + 1 slots per cell everywhere it is read."""

from __future__ import annotations

import numpy as np

from gather_verify.engine.encoding import Encoding, LuminousEncoding
from gather_verify.engine.world_bulk import _Plan
from gather_verify.kernels import codes
from gather_verify.kernels.codes import NO_EDGE, OUTSIDE
from gather_verify.model import geometry
from gather_verify.model.geometry import STEPS
from gather_verify.worlds import finite_world
from schedulers import as_scheduler


def test_the_two_sentinels_are_distinct_and_no_node() -> None:
    assert OUTSIDE != NO_EDGE
    assert OUTSIDE < 0 and NO_EDGE < 0  # ">= 0" still means "a node"


def test_a_finite_world_table_holds_no_edge_where_a_node_has_no_edge() -> None:
    world = finite_world("grid:3x3")
    plan = _Plan(world, 1, 1, False, as_scheduler("async"), [])
    assert plan.adj.shape == (world.size, 4)
    for v, nbrs in enumerate(world.adjacency):
        row = plan.adj[v].tolist()
        assert row[:len(nbrs)] == list(nbrs)
        assert row[len(nbrs):] == [NO_EDGE] * (4 - len(nbrs))
    corners = [v for v, nbrs in enumerate(world.adjacency) if len(nbrs) == 2]
    assert len(corners) == 4
    assert OUTSIDE not in plan.adj  # the whole world is the region


def test_a_z2_table_holds_outside_at_the_border_of_its_region() -> None:
    enc = Encoding((0, 0, 2, 2))
    table = enc.neighbour
    assert table.shape == (9, len(STEPS))
    for cell in range(enc.cells):
        v = enc.node(cell)
        for k, step in enumerate(STEPS):
            w = geometry.add(v, step)
            want = enc.code(w, None) // enc.slots if enc.inside(w) else OUTSIDE
            assert table[cell, k] == want
    assert (table == OUTSIDE).sum() == 12  # 3 per side of the 3 x 3 box
    assert NO_EDGE not in table  # every node of Z² has its 4 edges


def test_a_move_out_of_the_region_is_handed_on_as_outside() -> None:
    """A robot on the box's east side, pending a step east: its Move's new code is OUTSIDE
    (a region limit, INCOMPLETE or a larger region), from the numpy path and the kernel."""
    from gather_verify import kernels

    enc = Encoding((0, 0, 2, 2))
    east = enc.code((2, 1), (3, 1))
    inward = enc.code((2, 1), (1, 1))
    frontier = enc.frontier(np.array([[east, inward]], dtype=np.int64),
                            np.zeros((1, 2), dtype=np.uint8))
    for compiled in (False, True) if kernels.available() else (False,):
        kernels.use(compiled)
        try:
            got = as_scheduler("async").bulk_successors(frontier, 1000)
        finally:
            kernels.use(None)
        assert got.code.tolist() == [OUTSIDE, enc.code((1, 1), None)]


def test_a_z2_code_has_degree_plus_one_slots_per_cell() -> None:
    """Every code of a small region decodes to a distinct (node, pending) pair and back, and
    together they are every node with every pending step or none: so the slots per cell are
    exactly the degree + 1, in the encoding, the model and the compiled kernels' constant."""
    assert geometry.SLOTS == len(STEPS) + 1 == codes.Z2_SLOTS
    assert geometry.DEGREE == len(STEPS) == codes.Z2_DEGREE
    enc = Encoding((-1, 2, 1, 3))
    assert enc.slots == len(STEPS) + 1
    assert enc.base == enc.cells * enc.slots
    robots = [enc.robot(c) for c in range(enc.base)]
    assert [enc.code(v, p) for v, p in robots] == list(range(enc.base))
    nodes = [(x, y) for x in range(-1, 2) for y in range(2, 4)]
    every = {(v, p) for v in nodes for p in [None, *(geometry.add(v, s) for s in STEPS)]}
    assert set(robots) == every and len(every) == enc.base
    for c, (_, p) in enumerate(robots):
        assert (p is None) == (c % enc.slots == 0)
    lit = LuminousEncoding((-1, 2, 1, 3), colours=3)
    assert lit.base == lit.cells * enc.slots * 3
