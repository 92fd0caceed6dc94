"""Rings as the papers state them (docs/howto/rings.md): start sets (periodic, aperiodic,
symmetric, rigid) against an independent reading of the gaps, per-start answers and the
starts a none rests on, the cheapest adversary first (an FSYNC none holds under SSYNC and
ASYNC, and its certificate says so and re-checks), counterexamples restarted at a later
start, seeds, and gap rules: their reading, their keys against the checker's move sets,
and one algorithm for a range of ring sizes, verified at each."""

from __future__ import annotations

import json
import random
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

pytest.importorskip("pysat", reason="synthesize needs python-sat (extra synth)")

from gather_verify.algorithms.gap_rules import GapRules, Rule  # noqa: E402
from gather_verify.errors import InvalidInput  # noqa: E402
from gather_verify.synthesis import starts  # noqa: E402
from gather_verify.synthesis.certificate import (  # noqa: E402
    CertificateError,
    replay,
    verify_certificate,
)
from gather_verify.synthesis.gapviews import GapViews, exact_rules, rules_of  # noqa: E402
from gather_verify.synthesis.restart import restart  # noqa: E402
from gather_verify.synthesis.search import synthesize  # noqa: E402
from gather_verify.synthesis.views import Views, make_instance  # noqa: E402
from gather_verify.worlds import get_world  # noqa: E402
from gather_verify.worlds.moves import WorldMoves  # noqa: E402
from tests.test_synthesis import cli, one_line  # noqa: E402

# -- start sets ------------------------------------------------------------------------------


def _gaps(n: int, nodes: tuple[int, ...]) -> tuple[int, ...]:
    return tuple((b - a) % n for a, b in zip(nodes, nodes[1:] + nodes[:1], strict=True)) \
        if len(nodes) > 1 else (n,)


def _words(n: int, nodes: tuple[int, ...]) -> tuple[bool, bool]:
    """(periodic, symmetric) read off the gap sequence: a non-trivial rotation of it is
    itself, or some rotation of its reversal is (a reflection)."""
    g = _gaps(n, nodes)
    k = len(g)
    turns = [g[r:] + g[:r] for r in range(k)]
    periodic = any(t == g for t in turns[1:])
    mirror = g[::-1]
    reflected = any(mirror[r:] + mirror[:r] == g for r in range(k))
    return periodic, periodic or reflected


@settings(max_examples=40, deadline=None)
@given(n=st.integers(3, 12), data=st.data())
def test_start_words_agree_with_the_gaps(n: int, data: st.DataObject) -> None:
    k = data.draw(st.integers(1, n - 1))
    ring = get_world(f"ring:{n}")
    every = starts.starts(ring, k, "all")
    for nodes in every:
        periodic, symmetric = _words(n, nodes)
        assert starts.periodic(ring, nodes) == periodic
        assert (not starts.rigid(ring, nodes)) == symmetric
    assert starts.starts(ring, k, "periodic") == [c for c in every if _words(n, c)[0]]
    assert starts.starts(ring, k, "aperiodic") == [c for c in every if not _words(n, c)[0]]
    assert starts.starts(ring, k, "rigid") == starts.starts(ring, k, "asymmetric") == \
        [c for c in every if not _words(n, c)[1]]
    assert starts.starts(ring, k, "symmetric") == [c for c in every if _words(n, c)[1]]


def test_ring_nine_three_robots() -> None:
    ring = get_world("ring:9")
    assert starts.starts(ring, 3, "periodic") == [(0, 3, 6)]
    assert len(starts.starts(ring, 3, "all")) == 7
    assert starts.counts(ring, starts.starts(ring, 3)) == {"periodic": 1, "symmetric": 3,
                                                           "rigid": 3}


def test_start_words_refused_where_undefined() -> None:
    run = cli("--world", "grid:3x3", "--robots", "2", "--start", "periodic", "--task",
              "gathering")
    assert run.returncode == 2 and "rings only" in one_line(run)
    run = cli("--world", "ring:6", "--robots", "0 2", "--start", "all", "--task", "gathering")
    assert run.returncode == 2 and "count of robots" in one_line(run)
    run = cli("--world", "ring:4", "--robots", "2", "--start", "rigid", "--task", "gathering")
    assert run.returncode == 2 and "no initial configuration" in one_line(run)


# -- per start, together, and what a none rests on ---------------------------------------------

def test_per_start_answers(tmp_path: Path) -> None:
    run = cli("--world", "ring:9", "--robots", "3", "--start", "all", "--task", "gathering",
              "--multiplicity", "global-weak", "--scheduler", "fsync", "--witness",
              str(tmp_path / "w.py"), "--certificate", str(tmp_path / "c.json"), "--json")
    report = json.loads(run.stdout)
    assert run.returncode == 0 and report["answer"] == "mixed"
    rows = {r["robots"]: r for r in report["rows"]}
    assert rows["0 3 6"]["answer"] == "none" and rows["0 3 6"]["kind"] == "periodic"
    assert rows["0 3 6"]["holds_under"] == ["fsync", "ssync", "async"]
    assert rows["0 3 6"]["one_mover"] == rows["0 3 6"]["one_robot"] == "exhausted"
    verify_certificate(rows["0 3 6"]["certificate"])
    for robots, row in rows.items():
        if robots != "0 3 6":
            assert row["answer"] == "exists" and row["checker"] == ["VERIFIED"]


def test_together_none_rests_on_the_periodic_start(tmp_path: Path) -> None:
    cert = tmp_path / "c.json"
    run = cli("--world", "ring:9", "--robots", "3", "--task", "gathering", "--multiplicity",
              "global-weak", "--scheduler", "ssync", "--certificate", str(cert))
    assert run.returncode == 1, run.stderr
    assert "rests on 1 of 7 starts: 0 3 6 (periodic)" in run.stdout
    assert "mirror-symmetric" in run.stdout and "holds under fsync, ssync, async" in run.stdout
    verified = cli("--verify", str(cert), "--explain")
    assert verified.returncode == 0 and "rests on 1 of 7" in verified.stdout
    aperiodic = cli("--world", "ring:9", "--robots", "3", "--start", "aperiodic", "--together",
                    "--task", "gathering", "--multiplicity", "global-weak", "--scheduler",
                    "ssync", "--witness", str(tmp_path / "w.py"), "--json")
    report = json.loads(aperiodic.stdout)
    assert aperiodic.returncode == 0 and report["configurations"] == 6
    assert report["checker"]["verdicts"] == ["VERIFIED"]


def test_a_none_in_words_names_each_group_of_robots(tmp_path: Path) -> None:
    """Four robots on ring:8: the none rests on the periodic start 0 1 4 5; the adversary
    sends the two pairs apart and back, one group each way."""
    cert = tmp_path / "c.json"
    run = cli("--world", "ring:8", "--robots", "4", "--task", "exploration-with-stop",
              "--multiplicity", "global-weak", "--scheduler", "ssync", "--certificate",
              str(cert), "--json")
    report = json.loads(run.stdout)
    assert run.returncode == 1 and report["rests_on"] == [[0, 1, 4, 5]]
    told = " ".join(report["explanation"])
    assert "robots step clockwise (1->2, 5->6)" in told and "robots steps" not in told
    verified = json.loads(cli("--verify", str(cert), "--explain", "--json").stdout)
    assert verified["explanation"] == report["explanation"]


def test_a_none_in_words_says_when_every_robot_stays(tmp_path: Path) -> None:
    """Two robots never explore ring:8 exclusively: where the algorithm stays, the words say
    that every robot stays for ever and which node is never visited (not "that cycle")."""
    run = cli("--world", "ring:8", "--robots", "2", "--start", "aperiodic", "--together",
              "--task", "exclusive-perpetual-exploration", "--multiplicity", "global-weak",
              "--scheduler", "fsync", "--certificate", str(tmp_path / "c.json"), "--json")
    report = json.loads(run.stdout)
    assert run.returncode == 1 and report["answer"] == "none"
    stays = [line for line in report["explanation"] if "answers stay: then:" in line]
    assert stays and all("every robot stays for ever" in line and "is never visited again"
                         in line and "that cycle" not in line for line in stays)


# -- the cheapest adversary first ------------------------------------------------------------

@pytest.fixture(scope="module")
def periodic_async(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    path = tmp_path_factory.mktemp("lad") / "c.json"
    run = cli("--world", "ring:9", "--robots", "0 3 6", "--task", "exploration-with-stop",
              "--multiplicity", "global-weak", "--scheduler", "async", "--certificate",
              str(path))
    assert run.returncode == 1, run.stderr
    return {"path": path, "doc": json.loads(path.read_text())}


def test_an_fsync_none_holds_under_ssync_and_async(periodic_async: dict[str, Any]) -> None:
    doc = periodic_async["doc"]
    assert doc["holds_under"] == ["fsync", "ssync", "async"]
    assert {c["scheduler"] for c in doc["counterexamples"]} == {"fsync"}
    got = verify_certificate(str(periodic_async["path"]))
    assert got["holds_under"] == ["fsync", "ssync", "async"] and got["found_under"] == ["fsync"]


@pytest.mark.parametrize("tamper", ["claim", "scheduler", "rounds"])
def test_a_ladder_certificate_broken_fails(periodic_async: dict[str, Any], tmp_path: Path,
                                           tamper: str) -> None:
    doc = json.loads(json.dumps(periodic_async["doc"]))
    if tamper == "claim":
        doc["holds_under"] = ["fsync", "centralized", "ssync", "async"]
    elif tamper == "scheduler":  # a round is no ASYNC event
        for cex in doc["counterexamples"]:
            cex["scheduler"] = "async"
    else:  # an FSYNC round split in two is no FSYNC run
        for cex in doc["counterexamples"]:
            for e in cex["events"]:
                e["moves"] = e["moves"][:1]
    path = tmp_path / "b.json"
    path.write_text(json.dumps(doc))
    with pytest.raises(CertificateError):
        verify_certificate(str(path))
    run = cli("--verify", str(path))
    assert run.returncode == 1 and one_line(run).startswith("certificate REJECTED")


def test_with_lights_an_fsync_none_stops_short_of_async(tmp_path: Path) -> None:
    path = tmp_path / "c.json"
    run = cli("--world", "ring:6", "--robots", "0 1", "--lights", "2", "--visibility", "1",
              "--task", "exclusive-perpetual-exploration", "--multiplicity", "global-weak",
              "--scheduler", "ssync", "--certificate", str(path))
    assert run.returncode == 1, run.stderr
    holds = verify_certificate(str(path))["holds_under"]
    assert "async" not in holds and "ssync" in holds


@pytest.mark.parametrize(("world", "robots", "scheduler", "task"), [
    ("ring:5", "3", "async", "gathering"),
    ("ring:6", "3", "ssync", "exclusive-perpetual-exploration"),
    ("ring:6", "2", "async", "exploration-with-stop"),
])
def test_ladder_and_plain_search_agree(world: str, robots: str, scheduler: str,
                                       task: str) -> None:
    """The answer does not depend on the ladder (it only orders the adversaries)."""
    inst = make_instance(world, robots, "", scheduler, task, "global-weak")
    with_ladder = synthesize(inst, max_seconds=60)
    plain = synthesize(inst, max_seconds=60, ladder=False)
    assert with_ladder.answer == plain.answer != "unknown"


# -- restarting a counterexample at a later start ----------------------------------------------

def test_restart_keeps_a_counterexample() -> None:
    """A run that passes through another start is told from there; it still replays, with
    no more literals."""
    inst = make_instance("ring:7", "3", "", "fsync", "exclusive-perpetual-exploration",
                         "global-weak")
    views = Views(inst)
    res = synthesize(inst, views=views, max_seconds=60)
    assert res.counterexamples
    moved = 0
    for cex in res.counterexamples:
        again = restart(inst, cex)
        assert len(replay(views, again).literals) <= len(replay(views, cex).literals)
        moved += again is not cex
    assert moved == 0  # the search restarts every one already: nothing left to shorten


# -- seeds ---------------------------------------------------------------------------------------

def test_a_seed_is_tried_first(tmp_path: Path) -> None:
    first = cli("--world", "ring:7", "--robots", "3", "--task", "gathering", "--multiplicity",
                "global-weak", "--scheduler", "fsync", "--witness", str(tmp_path / "a.py"),
                "--json")
    assert first.returncode == 0 and json.loads(first.stdout)["candidates"] > 1
    again = cli("--world", "ring:7", "--robots", "3", "--task", "gathering", "--multiplicity",
                "global-weak", "--scheduler", "fsync", "--witness", str(tmp_path / "b.py"),
                "--seed", f"{tmp_path / 'a.py'}:Synthesized", "--json")
    assert again.returncode == 0 and json.loads(again.stdout)["candidates"] == 1


# -- gap rules -------------------------------------------------------------------------------

def test_rule_reading() -> None:
    r = Rule("1 2+ *", "back", where="b>c", marks=".*T")
    assert r.matches((1, 5, 3), (0, 1, 1)) and not r.matches((1, 5, 3), (0, 1, 0))
    assert not r.matches((1, 3, 5), (0, 0, 1)) and not r.matches((1, 3), (0, 0))
    assert eval(repr(r), {"Rule": Rule}) == r
    for bad in [("1 x", "stay", "", ""), ("1 2", "jump", "", ""), ("1 2", "stay", "a<z", ""),
                ("1 2", "stay", "", "TTT")]:
        with pytest.raises(InvalidInput):
            Rule(bad[0], bad[1], where=bad[2], marks=bad[3])


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 10**6), n=st.integers(6, 9), k=st.integers(2, 4),
       cap=st.integers(2, 4), detection=st.sampled_from(["global-weak", "local-weak", "none"]))
def test_gap_keys_move_as_the_rules_do(seed: int, n: int, k: int, cap: int,
                                       detection: str) -> None:
    """Field by field: for a random table over the gap keys of every configuration (towers
    included), the move set the search computes for each robot is the one the ordinary
    move-set code computes for the rules written from that table."""
    inst = make_instance(f"ring:{n}", str(k), "", "fsync", "gathering", detection)
    views = GapViews(inst, cap)
    rng = random.Random(seed)
    world = inst.world
    seen_all = []
    for nodes in _multisets(n, k, rng):
        seen = tuple(sorted((v, 0) for v in nodes))
        seen_all.append(seen)
        for v in set(nodes):
            views.occurrence(seen, v, 0)
    table = {key: rng.randrange(len(views.options[key])) for key in range(len(views.texts))}
    algo = GapRules(rules_of(views, table))
    moves = WorldMoves(world, algo, frozenset(), detection)
    for seen in seen_all:
        got = moves.table(seen)
        for v, c in set(seen):
            key, acts = views.occurrence(seen, v, c)
            assert acts[table[key]] == got[v, c], (seen, v, algo.describe())


@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 10**6), n=st.integers(5, 8), k=st.integers(2, 4),
       detection=st.sampled_from(["global-weak", "global-strong", "local-weak"]))
def test_an_exact_table_as_gap_rules(seed: int, n: int, k: int, detection: str) -> None:
    """The gap rules printed for a ring witness are that very algorithm: a random table over
    the exact views gives each robot the move set the rules give it."""
    inst = make_instance(f"ring:{n}", str(k), "", "fsync", "gathering", detection)
    views = Views(inst)
    rng = random.Random(seed)
    seen_all = []
    for nodes in _multisets(n, k, rng):
        seen = tuple(sorted((v, 0) for v in nodes))
        seen_all.append(seen)
        for v in set(nodes):
            views.occurrence(seen, v, 0)
    table = {key: rng.randrange(len(views.options[key])) for key in range(len(views.texts))}
    rules = exact_rules(views, table)
    assert rules is not None
    moves = WorldMoves(inst.world, GapRules(rules), frozenset(), detection)
    for seen in seen_all:
        got = moves.table(seen)
        for v, c in set(seen):
            key, acts = views.occurrence(seen, v, c)
            assert acts[table[key]] == got[v, c], (seen, v, [str(r) for r in rules])


def _multisets(n: int, k: int, rng: random.Random) -> list[tuple[int, ...]]:
    out = {tuple(sorted(rng.randrange(n) for _ in range(k))) for _ in range(40)}
    return sorted(out)


def test_one_gap_rule_algorithm_for_a_range(tmp_path: Path) -> None:
    witness = tmp_path / "rules.py"
    run = cli("--world", "ring:7-9", "--robots", "3", "--start", "aperiodic", "--together",
              "--task", "gathering", "--multiplicity", "global-weak", "--scheduler", "fsync",
              "--witness", str(witness), "--json")
    assert run.returncode == 0, run.stderr
    report = json.loads(run.stdout)
    assert report["answer"] == "exists" and report["sizes"] == 3
    assert report["one_mover"] == "witness"  # how the first phase ended, as for one size
    assert report["checker"]["verdicts"] == ["VERIFIED"] and report["rules"]
    text = witness.read_text()
    assert "from gather_verify.algorithms.gap_rules import GapRules, Rule" in text
    from gather_verify.world_check import run_world_check

    for n in (7, 8, 9):  # the file stands on its own, at each size
        for nodes in starts.starts(get_world(f"ring:{n}"), 3, "aperiodic"):
            got = run_world_check(f"ring:{n}", list(nodes), [], f"{witness}:Synthesized",
                                  "fsync", task="gathering", detection="global-weak",
                                  reduction=False)
            assert got["verdict"] == "VERIFIED"


def test_a_range_needs_together() -> None:
    run = cli("--world", "ring:7-9", "--robots", "3", "--task", "gathering")
    assert run.returncode == 2 and "--together" in one_line(run)


ASYNC_EXPLORER = Path(__file__).parent / "fixtures" / "rings" / "explore3async.py"


def _explores(path: Path, n: int) -> list[str]:
    from gather_verify.world_check import run_world_check

    return sorted({run_world_check(f"ring:{n}", list(nodes), [], f"{path}:Synthesized",
                                   "async", task="exclusive-perpetual-exploration",
                                   detection="global-weak", reduction=False)["verdict"]
                   for nodes in starts.starts(get_world(f"ring:{n}"), 3, "aperiodic")})


@pytest.mark.parametrize("n", [10, 13])
def test_blins_three_robots_explore_under_async(n: int) -> None:
    """The gap rules synthesised for ring:10-20 under ASYNC (docs/rings-results.md) explore
    exclusively and perpetually from every aperiodic start, read by the checker alone."""
    assert _explores(ASYNC_EXPLORER, n) == ["VERIFIED"]


def test_blins_rules_broken_fail(tmp_path: Path) -> None:
    """The same rules with the robot at the end of a block of three stepping into it."""
    broken = tmp_path / "broken.py"
    broken.write_text(ASYNC_EXPLORER.read_text().replace("Rule('1 1 4+', 'back')",
                                                         "Rule('1 1 4+', 'forward')"))
    assert "VIOLATED" in _explores(broken, 10)


@pytest.mark.slow
def test_blins_three_robots_explore_at_every_size_of_the_range() -> None:
    for n in range(10, 21):
        assert _explores(ASYNC_EXPLORER, n) == ["VERIFIED"], n


def _least(tmp_path: Path, robots: str, *more: str) -> tuple[str, list[dict[str, Any]]]:
    run = cli("--minimum", "--world", "ring:6", "--robots", robots, "--task", "gathering",
              "--multiplicity", "global-weak", "--scheduler", "fsync", "--db",
              str(tmp_path / "m.sqlite"), "--out", str(tmp_path / "out"), "--json", *more)
    assert run.returncode == 0, run.stderr
    got = json.loads(run.stdout)
    return got["minimum"][0]["least"], got["rows"]


def test_a_stored_least_count_is_not_the_answer_for_an_edited_graph_file(
        tmp_path: Path) -> None:
    """``--minimum --db`` keys its rows by the graph file's bytes, not its name: the same
    command on the edited file answers for the new graph (a 5-cycle has three robots that
    explore exclusively under FSYNC, a 6-cycle none of 1-3)."""
    graph = tmp_path / "g.edgelist"

    def least() -> str:
        run = cli("--minimum", "--world", f"graph:{graph}", "--robots", "1-3", "--task",
                  "exclusive-perpetual-exploration", "--multiplicity", "global-weak",
                  "--scheduler", "fsync", "--db", str(tmp_path / "m.sqlite"), "--out",
                  str(tmp_path / "out"), "--json")
        assert run.returncode == 0, run.stderr
        return json.loads(run.stdout)["minimum"][0]["least"]

    graph.write_text("0 1\n1 2\n2 3\n3 4\n4 0\n")
    assert least() == "3"
    graph.write_text("0 1\n1 2\n2 3\n3 4\n4 5\n5 0\n")
    assert least() == ">3"


def test_minimum_over_a_start_set(tmp_path: Path) -> None:
    """Three robots gather on ring:6 from every aperiodic start (Klasing et al.), not from
    every start ({0, 2, 4} is periodic): --minimum asks the least count for the set given;
    a count with no start in the set is ``empty``, never ``exists``."""
    assert _least(tmp_path, "2-3")[0] == ">3"
    least, rows = _least(tmp_path, "2-3", "--start", "aperiodic")
    assert least == "3" and [r["answer"] for r in rows] == ["none", "exists"]
    least, rows = _least(tmp_path, "1-3", "--start", "asymmetric")
    assert least == "3" and [r["answer"] for r in rows] == ["empty", "empty", "exists"]
    assert rows[0]["limit"] == "no start of 1 robot is asymmetric"
    run = cli("--minimum", "--world", "ring:6", "--robots", "0 1", "--lights", "1-2",
              "--start", "aperiodic")
    assert run.returncode == 2 and "--start with --minimum" in one_line(run)


FIXTURES = Path(__file__).parent / "fixtures" / "rings"
GATHER5 = FIXTURES / "gather5ring7async.py"
"""Five robots gathering on ring:7 under ASYNC, synthesised (docs/rings-results.md)."""
EXPLORE5 = FIXTURES / "explore5ring9async.py"
"""Lamani et al.'s five robots exploring ring:9 and stopping under ASYNC, synthesised."""


def _verdicts(path: Path, world: str, task: str) -> list[str]:
    """The gap rules' verdicts under ASYNC from every start of five robots on ``world``."""
    from gather_verify.world_check import run_world_check

    return sorted({run_world_check(world, list(nodes), [], f"{path}:Synthesized", "async",
                                   task=task, detection="global-weak",
                                   reduction=False)["verdict"]
                   for nodes in starts.starts(get_world(world), 5, "all")})


@pytest.mark.parametrize(("path", "world", "task"), [
    (GATHER5, "ring:7", "gathering"), (EXPLORE5, "ring:9", "exploration-with-stop")],
    ids=["gathering", "exploration-with-stop"])
def test_five_robots_solve_the_field_s_tasks_under_async(tmp_path: Path, path: Path,
                                                        world: str, task: str) -> None:
    """The witness's gap rules solve the task from every start, read by the checker alone;
    without their first rule (that view then stays), they do not."""
    assert _verdicts(path, world, task) == ["VERIFIED"]
    text = path.read_text()
    first = next(line for line in text.splitlines() if line.startswith("    Rule("))
    broken = tmp_path / "broken.py"
    broken.write_text(text.replace(first + "\n", "", 1))
    assert "VIOLATED" in _verdicts(broken, world, task)
