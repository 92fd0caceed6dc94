"""Export of the reachable state graph: networkx DiGraph, GraphML and DOT (``--graph-out``)."""

from __future__ import annotations

import networkx as nx
import pytest

from gather_verify.cli import main
from gather_verify.engine.explore import explore_reference
from gather_verify.engine.export import dot, to_networkx
from gather_verify.engine.fast_explore import explore_fast
from gather_verify.model.configuration import Configuration

YARD = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)
ARGS = ["check", "--robots", "0,0 3,1 1,4", "--meeting", "2,2", "--algorithm", "go-to-target"]


@pytest.mark.parametrize("search", [explore_reference, explore_fast])
@pytest.mark.parametrize("reduction", [False, True])
def test_the_graph_is_the_stored_graph(search, reduction: bool) -> None:
    e = search(YARD, "go-to-target", "async", reduction=reduction)
    g = to_networkx(e)
    assert g.number_of_nodes() == e.states
    assert sum(d["events"] for _, _, d in g.edges(data=True)) == e.transitions
    stored: dict[tuple[int, int], int] = {}
    for sid in range(e.states):
        for j in e.successors(sid):
            pair = (sid, int(e.targets[j]))
            stored[pair] = max(stored.get(pair, 0), int(e.weights[j]))
    assert {(u, v): d["weight"] for u, v, d in g.edges(data=True)} == stored
    assert g.nodes[0]["robots"] == "0,0 1,4 3,1" and g.nodes[0]["pending"] == "- - -"
    assert g.graph["anonymity"] is reduction and g.graph["stopped"] == ""
    # the longest path in moves is the report's max_moves on this acyclic graph
    if not reduction:
        assert nx.is_directed_acyclic_graph(nx.DiGraph((u, v) for u, v in g.edges if u != v))


def test_a_graph_that_disagrees_with_the_scheduler_is_refused() -> None:
    e = explore_reference(YARD, "go-to-target", "fsync", reduction=False)
    e.targets[0] = e.targets[-1] if e.targets[-1] != e.targets[0] else 0
    with pytest.raises(AssertionError, match="not the stored edges"):
        to_networkx(e)


def test_an_exploration_without_edges_is_refused() -> None:
    from gather_verify.errors import InvalidInput

    with pytest.raises(InvalidInput, match="graph=False"):
        to_networkx(explore_fast(YARD, "go-to-target", "async", graph=False))


def test_check_graph_out_graphml(tmp_path, capsys) -> None:
    out = tmp_path / "yard.graphml"
    assert main([*ARGS, "--scheduler", "ssync", "--no-reduction", "--graph-out", str(out)]) == 0
    g = nx.read_graphml(out)
    assert g.number_of_nodes() == 216 and g.graph["scheduler"] == "ssync"
    assert sum(d["events"] for _, _, d in g.edges(data=True)) == 2556
    assert all({"robots", "pending"} <= set(d) for _, d in g.nodes(data=True))
    assert all({"event", "weight"} <= set(d) for _, _, d in g.edges(data=True))


def test_check_graph_out_dot(tmp_path) -> None:
    out = tmp_path / "yard.dot"
    assert main([*ARGS, "--scheduler", "fsync", "--graph-out", str(out)]) == 0
    text = out.read_text()
    g = to_networkx(explore_reference(YARD, "go-to-target", "fsync"))
    assert text == dot(g)
    assert text.startswith('digraph "gather-verify" {') and text.endswith("}\n")
    assert text.count(" -> ") == g.number_of_edges() == 39


def test_dot_escapes_quotes() -> None:
    g = nx.DiGraph(name='a "b" \\ c')
    g.add_node(0, robots="0,0")
    assert 'name="a \\"b\\" \\\\ c"' in dot(g)


def test_an_unknown_graph_format_is_refused_before_the_search(tmp_path, capsys) -> None:
    out = tmp_path / "yard.png"
    assert main([*ARGS, "--graph-out", str(out), "--max-states", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "unknown graph format '.png'" in err
    assert not out.exists()


@pytest.mark.parametrize("search", [explore_reference, explore_fast])
def test_a_stopped_search_exports_its_reason_as_a_plain_string(search, tmp_path) -> None:
    """``stopped`` is a :class:`Stop` (a ``str`` enum); GraphML takes plain strings only."""
    from gather_verify.engine.encoding import Limits, Stop

    e = search(YARD, "go-to-target", "async", reduction=False, limits=Limits(max_states=50))
    assert e.stopped is Stop.STATES
    out = tmp_path / "stopped.graphml"
    nx.write_graphml(to_networkx(e), out)
    assert nx.read_graphml(out).graph["stopped"] == "states"
