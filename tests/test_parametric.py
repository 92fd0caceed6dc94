"""``check --world ring:N+`` (docs/howto/rings.md): exclusivity of a gap-rule algorithm on every
ring size at once. The formula is held against the ordinary successors, configuration by
configuration, for random rules; a proof on a known algorithm, a counterexample on a broken
one that the ordinary checker confirms, and the cases it does not decide say so in one
line."""

from __future__ import annotations

import json
from itertools import combinations
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

pytest.importorskip("z3", reason="a proof for every ring size needs z3 (extra smt)")

from gather_verify.algorithms.gap_rules import GapRules, Rule  # noqa: E402
from gather_verify.cli import main  # noqa: E402
from gather_verify.parametric import breaks_at, prove, rounds_at  # noqa: E402
from gather_verify.worlds import get_world  # noqa: E402
from gather_verify.worlds.moves import WorldMoves  # noqa: E402
from schedulers import get_scheduler  # noqa: E402

EXPLORER = str(Path(__file__).parent / "fixtures" / "rings" / "explore3.py") + ":Synthesized"


def check(*args: str, capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    code = main(["check", *args])
    out = capsys.readouterr()
    return code, out.out, out.err


def rounds_by_search(algo: GapRules, n: int, nodes: tuple[int, ...], scheduler: str,
                     frames: str) -> tuple[set[tuple[int, ...]], bool]:
    """The rounds from ``nodes`` under the scheduler's own successors, as displacements (+1
    clockwise), and whether one puts two robots on one node or moves two across an edge."""
    moves = WorldMoves(get_world(f"ring:{n}"), algo, frozenset(), "global-weak", frames)
    robots = tuple((v, None, 0) for v in nodes)
    acts = moves.actions(robots)
    out, breaks = set(), False
    for event, succ, _ in get_scheduler(scheduler).luminous(robots, None, acts.__getitem__):
        after = [v for v, _, _ in succ]
        out.add(tuple((b - a + 1) % n - 1 for a, b in zip(nodes, after, strict=True)))
        crossing = {(a, b) for _, a, b in event.moves}
        breaks |= len(set(after)) < len(after) or any((b, a) in crossing for a, b in crossing)
    return out, breaks


TOKENS = st.sampled_from(["1", "2", "3", "1+", "2+", "3+", "*"])


@st.composite
def rule_sets(draw: st.DrawFn, k: int) -> GapRules:
    rules = []
    for _ in range(draw(st.integers(0, 5))):
        gaps = " ".join(draw(TOKENS) for _ in range(k))
        last = "abcd"[k - 1]
        where = draw(st.sampled_from(["", "a<b", f"a={last}", f"b>={last}"]))
        rules.append(Rule(gaps, draw(st.sampled_from(["stay", "forward", "back"])),
                          where=where, one_way=draw(st.booleans())))
    return GapRules(rules, draw(st.sampled_from(["stay", "forward", "back"])))


@settings(max_examples=15, deadline=None)
@given(data=st.data(), k=st.integers(2, 4), n=st.integers(5, 7),
       scheduler=st.sampled_from(["fsync", "ssync", "centralized"]),
       frames=st.sampled_from(["all", "chirality"]))
def test_the_formula_is_the_round(data: st.DataObject, k: int, n: int, scheduler: str,
                                  frames: str) -> None:
    """Field by field: for random rules, from every configuration of a small ring, the
    formula's rounds are the scheduler's successors (each robot's displacement), and it has
    one breaking exclusivity exactly when they do."""
    algo = data.draw(rule_sets(k))
    for nodes in combinations(range(n), k):
        if nodes[0] != 0:
            continue  # rotations give the same gaps
        gaps = [(b - a) % n for a, b in zip(nodes, nodes[1:] + nodes[:1], strict=True)]
        rounds, breaks = rounds_by_search(algo, n, nodes, scheduler, frames)
        assert rounds_at(algo, gaps, scheduler, frames) == rounds, (nodes, algo.describe())
        assert breaks_at(algo, gaps, scheduler, frames) == breaks, (nodes, algo.describe())


def test_a_proof_for_every_size(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = check("--world", "ring:10+", "--robots", "3", "--algorithm", EXPLORER,
                         "--scheduler", "ssync", "--task", "exclusive-perpetual-exploration",
                         capsys=capsys)
    assert code == 0 and out.startswith("VERIFIED  exclusivity  3 robots  ssync")
    assert "not decided here: perpetual-exploration (liveness)" in out


def test_the_async_explorer_is_exclusive_on_every_ring_of_four_or_more(
        capsys: pytest.CaptureFixture[str]) -> None:
    """The gap rules of docs/rings-results.md: exclusivity for every n >= 4 under SSYNC."""
    algo = str(Path(EXPLORER.rsplit(":", 1)[0]).with_name("explore3async.py")) + ":Synthesized"
    code, out, _ = check("--world", "ring:4+", "--robots", "3", "--algorithm", algo,
                         "--scheduler", "ssync", "--task", "exclusive-perpetual-exploration",
                         capsys=capsys)
    assert code == 0 and "every ring size n >= 4" in out, out


def test_a_counterexample_the_checker_confirms(tmp_path: Path,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    broken = tmp_path / "broken.py"
    broken.write_text(Path(EXPLORER.rsplit(":", 1)[0]).read_text().replace(
        "RULES = [", "RULES = [\n    Rule('1 * *', 'forward'),"))
    code, out, _ = check("--world", "ring:4+", "--robots", "3", "--algorithm",
                         f"{broken}:Synthesized", "--scheduler", "fsync", "--json",
                         capsys=capsys)
    report = json.loads(out)
    assert code == 1 and report["holds"] is False
    assert report["checker"]["verdict"] == "VIOLATED"
    assert report["checker"]["property"] == "exclusivity"
    assert report["n"] == sum(report["gaps"]) >= 4


def test_a_smallest_size() -> None:
    """A robot steps into a gap of 2 when the gap behind it is 4 or more. Without a common
    direction the robot at the other end of that gap reads the same and steps too: they meet,
    first on a ring of 6 nodes (gaps 2, 4). With one (chirality) only one of them moves."""
    algo = GapRules([Rule("2 4+", "forward", one_way=True)])
    assert prove(algo, 2, "fsync", low=3, frames="chirality")["holds"] is True
    got = prove(algo, 2, "fsync", low=3, frames="all")
    assert got["holds"] is False and got["n"] == 6


@pytest.mark.parametrize(("args", "says"), [
    (["--scheduler", "async"], "undecidable"),
    (["--algorithm", "ring-explore"], "gap-rule algorithm"),
    (["--robots", "0 1 2"], "count"),
    (["--task", "gathering"], "exclusivity"),
])
def test_what_it_does_not_decide(args: list[str], says: str,
                                 capsys: pytest.CaptureFixture[str]) -> None:
    base = {"--robots": "3", "--algorithm": EXPLORER, "--scheduler": "ssync"}
    for name, value in zip(args[::2], args[1::2], strict=True):
        base[name] = value
    code, _, err = check("--world", "ring:5+", *[x for kv in base.items() for x in kv],
                         *(a for a in args if a.startswith("--task")),
                         *(args[1:2] if args[0] == "--task" else []), capsys=capsys)
    assert code == 2 and says in err and len(err.strip().splitlines()) == 1
