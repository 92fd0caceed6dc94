"""A certificate's decision tree pruned to the counterexamples it needs
(synthesis/certificate.py, ``prune``): on random unsatisfiable sets of clauses, every path of
the pruned tree still ends at a clause that holds on it, the kept clauses are the leaves, and
a question no leaf below reads is gone."""

from __future__ import annotations

import itertools
from typing import Any

from hypothesis import given, settings
from hypothesis import strategies as st

from gather_verify.synthesis.certificate import build_tree, prune


@st.composite
def _refuting(draw: st.DrawFn) -> tuple[list[dict[int, int]], list[int]]:
    """Clauses over a few views (each a partial table that fails) that together leave no
    table: random ones, then one per table they miss."""
    options = draw(st.lists(st.integers(2, 3), min_size=1, max_size=4))
    views = range(len(options))
    clauses: list[dict[int, int]] = []
    for _ in range(draw(st.integers(0, 8))):
        chosen = draw(st.lists(st.sampled_from(list(views)), min_size=1, unique=True))
        clauses.append({k: draw(st.integers(0, options[k] - 1)) for k in chosen})
    for table in itertools.product(*(range(n) for n in options)):
        if not any(all(table[k] == o for k, o in c.items()) for c in clauses):
            clauses.append(dict(enumerate(table)))
    return clauses, options


def _paths(node: Any, path: dict[int, int]) -> Any:
    if isinstance(node, int):
        yield dict(path), node
        return
    for o, child in enumerate(node[1]):
        yield from _paths(child, {**path, node[0]: o})


@settings(max_examples=200, deadline=None)
@given(_refuting())
def test_a_pruned_tree_still_refutes_every_table(got: tuple[list[dict[int, int]], list[int]]
                                                ) -> None:
    clauses, options = got
    tree, kept = prune(build_tree(clauses, options, 10_000), clauses)
    assert kept == sorted(set(kept)) and all(0 <= j < len(clauses) for j in kept)
    leaves = set()
    for path, leaf in _paths(tree, {}):
        leaves.add(leaf)
        clause = clauses[kept[leaf]]
        # every literal of the leaf's clause is answered on the path, the same way
        assert all(path.get(k) == o for k, o in clause.items())
    assert leaves == set(range(len(kept)))
    # every table meets a leaf: the tree asks each view at most once per path, and
    # covers every option of each question
    for table in itertools.product(*(range(n) for n in options)):
        node = tree
        while not isinstance(node, int):
            node = node[1][table[node[0]]]
        assert all(table[k] == o for k, o in clauses[kept[node]].items())


def test_a_question_no_leaf_reads_is_dropped() -> None:
    clauses = [{0: 0}, {0: 1}, {1: 0, 0: 0}]
    tree = [1, [[0, [0, 1]], [0, [0, 1]]]]  # asks view 1, which neither leaf reads
    assert prune(tree, clauses) == ([0, [0, 1]], [0, 1])
    tree = [0, [2, 1]]  # clause 0 is not used: it is dropped, the leaves renumbered
    assert prune(tree, clauses) == ([0, [1, 0]], [1, 2])
