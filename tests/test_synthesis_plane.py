"""``synthesize --world grid``: the paper's world. Theorem 1 for every algorithm (a
certificate of none that ``--verify`` re-checks, and refuses once broken), never a none
where an algorithm exists (a common compass gathers a configuration of U: exists, and the
ordinary checker verifies the witness), exists outside U, and Theorem 1's automorphism
exists exactly on U (SEMANTICS.md §2, §6, §12)."""

from __future__ import annotations

import copy
import json
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

pytest.importorskip("pysat", reason="synthesize needs python-sat (extra synth)")

from gather_verify.model.configuration import Configuration  # noqa: E402
from gather_verify.model.symmetry import Automorphism  # noqa: E402
from gather_verify.paper.classes import classify_configuration  # noqa: E402
from gather_verify.plane_check import run_check  # noqa: E402
from gather_verify.synthesis import plane  # noqa: E402
from tests.test_synthesis import cli, imports_first, one_line  # noqa: E402

U_ROBOTS, U_MEETING = "0,1 2,1", "0,0 2,0"  # UNCLASSIFIED, in U: the axis x = 1 is empty


@pytest.fixture(scope="module")
def certificate(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    folder = tmp_path_factory.mktemp("plane")
    run = cli("--world", "grid", "--box", "3x3", "--robots", "2", "--meeting", "2",
              "--select", "u", "--scheduler", "fsync", "--rounds", "3", "--json",
              "--certificate", "u.cert.json", cwd=folder)
    assert run.returncode == 1, run.stderr
    report = json.loads(run.stdout)
    assert report["answer"] == "none" and report["answers"]["none"] == len(report["rows"]) > 0
    assert all(r["in_U"] for r in report["rows"])
    return json.loads((folder / "u.cert.json").read_text())  # type: ignore[no-any-return]


def test_theorem1_none_is_reverified_without_search(tmp_path: Path,
                                                    certificate: dict[str, Any]) -> None:
    path = tmp_path / "c.json"
    path.write_text(json.dumps(certificate))
    run = cli("--verify", str(path), "--json")
    assert run.returncode == 0, run.stderr
    got = json.loads(run.stdout)
    assert got["configurations"] == len(certificate["configurations"])
    assert got["states"] == sum(e["states"] for e in certificate["configurations"])


def _phi_moved(cert: dict[str, Any]) -> None:
    cert["configurations"][0]["phi"]["t"][0] += 1


def _phi_not_a_frame(cert: dict[str, Any]) -> None:
    cert["instance"]["frames"] = "compass"


def _robot_moved(cert: dict[str, Any]) -> None:
    cert["configurations"][0]["robots"][0][1] += 5


def _digest(cert: dict[str, Any]) -> None:
    cert["configurations"][0]["digest"] = "0" * 64


def _fewer_states(cert: dict[str, Any]) -> None:
    cert["configurations"][0]["states"] -= 1


def _dropped(cert: dict[str, Any]) -> None:
    del cert["configurations"][-1]


def _scheduler(cert: dict[str, Any]) -> None:
    cert["instance"]["scheduler"] = "round-robin"


def _task(cert: dict[str, Any]) -> None:
    cert["instance"]["task"] = "gathering"


def _meeting_on_axis(cert: dict[str, Any]) -> None:
    """A meeting node on the axis (or centre): phi still maps M onto itself, but a gathered
    configuration there would be symmetric too."""
    for e in cert["configurations"]:
        phi = Automorphism(e["phi"]["g"], tuple(e["phi"]["t"]))  # type: ignore[arg-type]
        fixed = [(x, y) for x in range(-4, 5) for y in range(-4, 5) if phi.fixes((x, y))
                 and [x, y] not in e["robots"]]
        if fixed:
            e["meeting_nodes"].append(list(fixed[0]))
            return
    raise AssertionError("no phi with a fixed node in the certificate")


def _class(cert: dict[str, Any]) -> None:
    cert["configurations"][0]["class"] = "I41" if cert["configurations"][0]["class"] != "I41" \
        else "I42"


def _not_in_u(cert: dict[str, Any]) -> None:
    cert["configurations"][0]["in_U"] = False


def _describe(cert: dict[str, Any]) -> None:
    cert["configurations"][0]["phi"]["describe"] = "rotation 90 about (0, 0) [node]"


def _order(cert: dict[str, Any]) -> None:
    cert["configurations"][0]["phi"]["k"] = 4


def _claim(cert: dict[str, Any]) -> None:
    cert["claim"] = cert["claim"].replace("every algorithm", "every algorithm, with lights")


@pytest.mark.parametrize("tamper", [_phi_moved, _phi_not_a_frame, _robot_moved, _digest,
                                    _fewer_states, _dropped, _scheduler, _task,
                                    _meeting_on_axis, _class, _not_in_u, _describe, _order,
                                    _claim])
def test_a_broken_certificate_fails_verify(tmp_path: Path, certificate: dict[str, Any],
                                           tamper: Any) -> None:
    broken = copy.deepcopy(certificate)
    tamper(broken)
    path = tmp_path / "broken.json"
    path.write_text(json.dumps(broken))
    run = cli("--verify", str(path))
    assert run.returncode == 1, (run.returncode, run.stdout, run.stderr)
    assert one_line(run).startswith("certificate REJECTED")


def test_a_certificate_of_zero_rounds_is_refused(tmp_path: Path,
                                                certificate: dict[str, Any]) -> None:
    """With 0 rounds the adversary's step is checked on no configuration: refused in one
    line, exit 2, though its states and digest are those of 0 rounds."""
    zero = copy.deepcopy(certificate)
    views = plane.PlaneViews("local-weak", "all")
    for e in zero["configurations"]:
        c = Configuration([tuple(v) for v in e["robots"]],
                          [tuple(v) for v in e["meeting_nodes"]], initial=True)
        phi = Automorphism(e["phi"]["g"], tuple(e["phi"]["t"]))  # type: ignore[arg-type]
        closure = plane.adversary_closure(c, phi, views, 0)
        e.update(rounds=0, states=closure.states, digest=closure.digest)
    path = tmp_path / "zero.json"
    path.write_text(json.dumps(zero))
    run = cli("--verify", str(path))
    assert run.returncode == 2, (run.returncode, run.stdout, run.stderr)
    assert "rounds 0" in one_line(run)


def test_the_adversary_check_fails_on_views_that_break_the_symmetry(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """A view code under which phi-images answer differently (a deliberately broken model)
    makes the over-approximation fail: the certificate leans on the views, not on trust."""
    c = Configuration([(0, 1), (2, 1)], [(0, 0), (2, 0)], initial=True)
    phi = plane.theorem1_phi(c, "all")
    assert phi is not None
    views = plane.PlaneViews("local-weak", "all")
    plane.adversary_closure(c, phi, views, 3)  # holds
    real = plane.PlaneViews._compute

    def lopsided(self: plane.PlaneViews, d: Configuration, node: Any) -> Any:
        k, opts = real(self, d, node)
        return (k, opts) if node[0] < 1 else (k + 1000, opts)

    monkeypatch.setattr(plane.PlaneViews, "_compute", lopsided)
    with pytest.raises(plane.CertificateError, match="different keys"):
        plane.adversary_closure(c, phi, plane.PlaneViews("local-weak", "all"), 3)


def test_no_none_where_an_algorithm_exists(tmp_path: Path) -> None:
    """With a common compass the robots tell the two sides of the axis apart: the same
    configuration of U is gathered by some algorithm, so no certificate may be claimed, and
    the witness passes the ordinary checker."""
    c = Configuration([(0, 1), (2, 1)], [(0, 0), (2, 0)], initial=True)
    assert plane.theorem1_phi(c, "compass") is None
    run = cli("--world", "grid", "--robots", U_ROBOTS, "--meeting", U_MEETING, "--scheduler",
              "fsync", "--frames", "compass", "--json", "--witness", "w.py", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    report = json.loads(run.stdout)
    assert report["answer"] == "exists" and report["certificate"] is None
    spec = str(tmp_path / "w.py") + ":Synthesized"
    got = run_check(c, algorithm=spec, scheduler="fsync", frames="compass",
                    properties=["final", "termination"], reduction=False, max_seconds=60)
    assert got["verdict"] == "VERIFIED", got


def test_exists_outside_u_and_the_checker_verifies_the_witness(tmp_path: Path) -> None:
    run = cli("--world", "grid", "--robots", "0,0 2,1", "--meeting", "1,1", "--scheduler",
              "async", "--json", "--witness", "w.py", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    report = json.loads(run.stdout)
    assert report["answer"] == "exists" and imports_first(tmp_path / "w.py")
    assert report["rows"][0]["checker"] == {"verdict": "VERIFIED", "states":
                                            report["rows"][0]["checker"]["states"],
                                            "reductions": "off"}
    c = Configuration([(0, 0), (2, 1)], [(1, 1)], initial=True)
    got = run_check(c, algorithm=str(tmp_path / "w.py") + ":Synthesized", scheduler="async",
                    properties=["final", "termination"], reduction=False, max_seconds=60)
    assert got["verdict"] == "VERIFIED"


def test_one_algorithm_for_every_configuration_of_a_box(tmp_path: Path) -> None:
    """--together: one table gathers from every configuration outside U of the box, and the
    ordinary checker verifies it from each of them."""
    run = cli("--world", "grid", "--box", "2x2", "--robots", "2", "--meeting", "1",
              "--select", "outside-u", "--together", "--scheduler", "async", "--json",
              "--witness", "w.py", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    report = json.loads(run.stdout)
    assert report["answer"] == "exists" and report["checker"]["verdicts"] == ["VERIFIED"]
    spec = str(tmp_path / "w.py") + ":Synthesized"
    for c in plane.box_configurations(2, 2, range(2, 3), range(1, 2), "outside-u"):
        got = run_check(c, algorithm=spec, scheduler="async", reduction=False,
                        properties=["final", "termination"], max_seconds=60, force=True)
        assert got["verdict"] == "VERIFIED", (c, got)


NODES = st.tuples(st.integers(0, 3), st.integers(0, 3))


@settings(max_examples=60, deadline=None)
@given(st.sets(NODES, min_size=1, max_size=4), st.sets(NODES, min_size=1, max_size=4))
def test_theorem1_automorphism_exists_exactly_on_u(robots: set, meeting: set) -> None:
    """Disoriented robots: a certificate's phi exists exactly for the configurations in U
    (§2), so the box's none covers U and nothing else."""
    c = Configuration(sorted(robots), sorted(meeting), initial=True)
    assert (plane.theorem1_phi(c, "all") is not None) == classify_configuration(c).in_U


@settings(max_examples=15, deadline=None)
@given(st.sets(NODES, min_size=1, max_size=2), st.sets(NODES, min_size=1, max_size=2),
       st.sampled_from([0, 1, 2, 3, 4, 5, 6, 7]), st.sampled_from(["local-weak",
                                                                  "global-strong"]))
def test_mirrored_configurations_get_the_same_answer(robots: set, meeting: set, g: int,
                                                     detection: str) -> None:
    """The certificate is invariant under the grid's isometries: a configuration and its
    image both have a phi or neither, and their adversaries reach as many configurations."""
    a = Automorphism(g, (5, -2))
    c = Configuration(sorted(robots), sorted(meeting), initial=True)
    d = Configuration(sorted(map(a, robots)), sorted(map(a, meeting)), initial=True)
    pc, pd = plane.theorem1_phi(c, "all"), plane.theorem1_phi(d, "all")
    assert (pc is None) == (pd is None)
    if pc is not None and pd is not None:
        views = plane.PlaneViews(detection, "all")
        assert (plane.adversary_closure(c, pc, views, 2).states
                == plane.adversary_closure(d, pd, views, 2).states)


@pytest.mark.parametrize(("args", "words"), [
    (["--world", "grid", "--robots", "0,1 2,1"], "--meeting"),
    (["--world", "grid", "--robots", U_ROBOTS, "--meeting", U_MEETING, "--lights", "2"],
     "lights"),
    (["--world", "grid", "--robots", U_ROBOTS, "--meeting", U_MEETING, "--scheduler",
      "round-robin"], "round-robin"),
    (["--world", "grid", "--robots", U_ROBOTS, "--meeting", U_MEETING, "--task",
      "exploration-with-stop"], "task"),
    (["--world", "grid", "--box", "3x", "--robots", "2", "--meeting", "2"], "--box"),
    (["--world", "grid", "--box", "3x3", "--robots", "2-x", "--meeting", "2"], "--robots"),
    (["--world", "ring:6", "--box", "3x3", "--robots", "2"], "--box"),
    (["--world", "grid", "--box", "3x3", "--robots", "2", "--meeting", "2", "--together"],
     "--together"),
    (["--world", "grid", "--box", "2x2", "--robots", "1", "--meeting", "1", "--select",
      "u"], "no configuration"),
    (["--world", "grid", "--robots", "0,0 2,1", "--meeting", "1,1", "--seed", "no-such"],
     "no-such"),
    (["--world", "ring:6", "--robots", "2", "--seed", "no-such"], "no-such"),
])
def test_bad_input_is_one_line_and_exit_2(tmp_path: Path, args: list[str], words: str) -> None:
    run = cli(*args, cwd=tmp_path)
    assert run.returncode == 2, (run.returncode, run.stderr)
    assert words in one_line(run)


@pytest.mark.slow
@pytest.mark.parametrize(("robots", "meeting"), [
    ("0,0 1,2", "0,1 2,1"),  # F10: the paper's algorithm reaches UNCLASSIFIED, robust
    ("0,0 0,1 0,2", "0,0 0,2"),  # F7: SymmetryBreaking lands on an occupied node
])
def test_a_configuration_the_paper_fails_is_gathered_by_a_synthesised_algorithm(
        tmp_path: Path, robots: str, meeting: str) -> None:
    """The faults are the algorithm's, not the characterization's: from these initial
    configurations outside U some algorithm gathers under ASYNC, and the ordinary checker,
    every property on, every reduction off, verifies it."""
    run = cli("--world", "grid", "--robots", robots, "--meeting", meeting, "--scheduler",
              "async", "--json", "--witness", "w.py", "--max-seconds", "300", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    c = Configuration([tuple(map(int, v.split(","))) for v in robots.split()],
                      [tuple(map(int, v.split(","))) for v in meeting.split()], initial=True)
    got = run_check(c, algorithm=str(tmp_path / "w.py") + ":Synthesized", scheduler="async",
                    reduction=False, max_seconds=120, force=True)
    assert got["verdict"] == "VERIFIED", got


# the configurations outside U that the search left unknown and docs/examples/meet_by_hand.py
# gathers (docs/findings.md, "The paper's characterization, checked by synthesis")
SEARCH_UNKNOWN = [("1,1 2,1", "0,0 0,2"), ("1,0 1,2", "0,0 0,1 2,0 2,1"),
                  ("1,1 1,2", "0,0 0,1 2,0 2,1"), ("0,0 2,1", "0,0 0,1 1,2 2,2")]
SEARCH_UNKNOWN_3 = [("0,0 0,2 2,0", "0,0 0,2 2,0 2,2"), ("0,0 0,2 2,1", "0,0 0,2 2,0 2,2")]


def _nodes(text: str) -> list[tuple[int, int]]:
    return [(int(x), int(y)) for x, y in (p.split(",") for p in text.split())]


@pytest.mark.parametrize(("robots", "meeting", "name"),
                         [(r, m, "TwoMeet") for r, m in SEARCH_UNKNOWN]
                         + [(r, m, "ThreeMeet") for r, m in SEARCH_UNKNOWN_3])
def test_the_hand_written_algorithms_gather_outside_u(robots: str, meeting: str,
                                                      name: str) -> None:
    """Outside U, so the paper says gatherable; the ordinary checker verifies the docs'
    hand-written algorithm from it under ASYNC, every reduction off."""
    c = Configuration(_nodes(robots), _nodes(meeting), initial=True)
    assert not classify_configuration(c).in_U
    assert plane.theorem1_phi(c, "all") is None
    got = run_check(c, algorithm=f"docs/examples/meet_by_hand.py:{name}", scheduler="async",
                    properties=["final", "termination"], reduction=False, max_seconds=60,
                    force=True)
    assert got["verdict"] == "VERIFIED", got


@pytest.mark.parametrize(("robots", "meeting"), [SEARCH_UNKNOWN[1], SEARCH_UNKNOWN[3]])
def test_the_careless_variant_ends_on_two_meeting_nodes(robots: str, meeting: str) -> None:
    """Walking onto another meeting node on the way ends with the robots on two meeting
    nodes, for ever: the checker must catch it."""
    c = Configuration(_nodes(robots), _nodes(meeting), initial=True)
    got = run_check(c, algorithm="docs/examples/meet_by_hand.py:Careless", scheduler="async",
                    properties=["final", "termination"], reduction=False, max_seconds=60,
                    force=True)
    assert got["verdict"] == "VIOLATED"


def test_three_meet_without_its_tie_rule_deadlocks() -> None:
    """ThreeMeet's tie rule is needed: a robot facing one other occupied meeting node that
    waits leaves the multiplicity and itself apart for ever."""
    c = Configuration(_nodes("0,0 0,2 2,0"), _nodes("0,0 0,2 2,0 2,2"), initial=True)
    got = run_check(c, algorithm="docs/examples/meet_by_hand.py:ThreeMeetNoTie",
                    scheduler="async", properties=["final", "termination"], reduction=False,
                    max_seconds=60, force=True)
    assert got["verdict"] == "VIOLATED"


# -- the search: exact clauses from fair cycles, seeds as phases -----------------------------

def _search(robots: str, meeting: str, seeds: list[Any] | None,
            max_candidates: int) -> tuple[plane.SearchResult, plane.PlaneInstance,
                                          plane.PlaneViews, Configuration]:
    c = Configuration(_nodes(robots), _nodes(meeting), initial=True)
    inst = plane.PlaneInstance([c], "async", "local-weak", "all")
    views = plane.PlaneViews("local-weak", "all")
    found = plane.search_algorithm([c], inst, views, max_seconds=300,
                                   max_candidates=max_candidates, max_states=200_000,
                                   seeds=seeds)
    return found, inst, views, c


@pytest.mark.parametrize(("robots", "meeting"), SEARCH_UNKNOWN[:1] + SEARCH_UNKNOWN[2:3])
def test_a_configuration_the_old_search_left_unknown_is_settled(robots: str,
                                                                meeting: str) -> None:
    """With the nearest-meeting-node rule alone as its seed, the search used to give up on
    these (more than 4,000 candidates): a fair cycle's clause named every view of every
    configuration on its trace. Naming only the views the cycle's robots act on, and the
    stays that make it fair, it settles them within a few hundred candidates, and the
    checker verifies the witness."""
    found, inst, views, c = _search(robots, meeting, [None], 400)
    assert found.answer == "exists", found
    got = run_check(c, algorithm=plane.TableAlgorithm(views, found.table, 10**6),
                    scheduler="async", properties=["final", "termination"],
                    reduction=False, max_seconds=60, force=True)
    assert got["verdict"] == "VERIFIED", got


def _cycles(monkeypatch: pytest.MonkeyPatch) -> tuple[plane.PlaneViews, Configuration,
                                                     list[tuple[dict[int, int],
                                                                dict[str, Any]]]]:
    """The fair cycles the search meets on its way (each with the candidate table that has
    it), recorded from its calls to :func:`plane.literals`."""
    seen: list[tuple[dict[int, int], dict[str, Any]]] = []
    real = plane.literals

    def spy(views: plane.PlaneViews, trace: dict[str, Any], meeting: Any,
            choice: dict[int, int] | None = None) -> Any:
        if trace.get("cycle_start") is not None and choice is not None:
            seen.append((dict(choice), copy.deepcopy(trace)))
        return real(views, trace, meeting, choice)

    monkeypatch.setattr(plane, "literals", spy)
    found, _, views, c = _search("1,1 2,1", "0,0 0,2", [None], 400)
    monkeypatch.setattr(plane, "literals", real)
    assert found.answer == "exists" and seen
    return views, c, seen


def _replays(views: plane.PlaneViews, configs: list[Configuration], trace: dict[str, Any],
             table: dict[int, int]) -> None:
    """Every Look (every activated robot) of the trace takes a move that ``table`` gives."""
    state = [{"node": v, "pending": None} for v in trace["initial"]["robots"]]
    for j, step in enumerate(trace["steps"]):
        if step["event"]["kind"] in ("look", "round"):
            for i in step["event"]["robots"]:
                node = tuple(state[i]["node"])
                after = step["state"][i]
                dest = tuple(after["pending"] or after["node"])
                k, opts = views.occurrence(configs[j], node)
                assert dest in opts[table[k]], (j, i, node, dest)
        state = step["state"]


def test_a_cycle_clause_excludes_only_tables_that_fail(monkeypatch: pytest.MonkeyPatch) -> None:
    """Every table that keeps the options a fair cycle's clause names has that same cycle:
    change every other view at random and the checker still finds a violation. The clause
    names fewer views than every view of the trace's configurations (the old clause), and,
    for a robot that never acts on the cycle, the stay that keeps the cycle fair."""
    import random

    views, c, seen = _cycles(monkeypatch)
    rng = random.Random(1)
    smaller = idle = 0
    for table, trace in seen[:6]:
        configs, used = plane.literals(views, trace, c.meeting_nodes, table)
        assert used is not None
        every = {views.occurrence(d, v)[0] for d in configs for v in d.occupied}
        assert used <= every
        smaller += used < every
        cs = trace["cycle_start"]
        if {i for step in trace["steps"][cs:] for i in step["event"]["robots"]} != {0, 1}:
            idle += 1
            assert any(views.options[k][table[k]] == (0, 0) for k in used)
        for _ in range(3):
            other = {k: o if k in used else rng.randrange(len(views.options[k]))
                     for k, o in table.items()}
            _replays(views, configs, trace, other)
            got = run_check(c, algorithm=plane.TableAlgorithm(views, other, 10**6),
                            scheduler="async", properties=["final", "termination"],
                            reduction=False, max_seconds=60, force=True, margin=8)
            assert got["verdict"] == "VIOLATED", (used, got)
    assert smaller and idle


def test_a_broken_seed_still_gives_a_verified_witness(tmp_path: Path) -> None:
    """A seed is only the answer tried first: seeded with a deliberately broken algorithm
    (``Careless`` ends on two meeting nodes from this configuration), the search still
    answers with a table the checker verifies."""
    robots, meeting = SEARCH_UNKNOWN[1]
    seed = "docs/examples/meet_by_hand.py:Careless"
    run = cli("--world", "grid", "--robots", robots, "--meeting", meeting, "--scheduler",
              "async", "--seed", str(Path(seed).resolve()), "--json", "--witness", "w.py",
              cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    report = json.loads(run.stdout)
    assert report["answer"] == "exists"
    assert report["rows"][0]["checker"]["verdict"] == "VERIFIED"


def test_a_broken_witness_is_refused_by_the_checker(tmp_path: Path) -> None:
    """The witness is an ordinary algorithm file, judged by the checker alone: make every
    answer of its table "stay" and the checker finds the deadlock."""
    robots, meeting = SEARCH_UNKNOWN[0]
    run = cli("--world", "grid", "--robots", robots, "--meeting", meeting, "--scheduler",
              "async", "--json", "--witness", "w.py", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    text = (tmp_path / "w.py").read_text()
    head, table = text.split("TABLE = {", 1)
    table, tail = table.split("}\n", 1)
    stays = "".join(line.rsplit(":", 1)[0] + ": (0, 0),\n"
                    for line in table.splitlines() if line.strip())
    (tmp_path / "broken.py").write_text(head + "TABLE = {\n" + stays + "}\n" + tail)
    c = Configuration(_nodes(robots), _nodes(meeting), initial=True)
    for name, want in (("w.py", "VERIFIED"), ("broken.py", "VIOLATED")):
        got = run_check(c, algorithm=str(tmp_path / name) + ":Synthesized", scheduler="async",
                        properties=["final", "termination"], reduction=False,
                        max_seconds=60, force=True)
        assert got["verdict"] == want, (name, got)


@pytest.mark.slow
@pytest.mark.parametrize(("robots", "meeting"), [
    ("0,1 1,1 2,1", "0,0 2,2"),  # I32: a robot on the centre of M's rotation
    ("0,0 1,1 2,2", "0,0 0,2 2,0 2,2"),  # I32, four meeting nodes
    ("0,0 0,1 2,2", "0,0 2,2"),  # I22
])
def test_configurations_a_weaker_search_left_unknown_are_gathered(tmp_path: Path, robots: str,
                                                                 meeting: str) -> None:
    """Outside U, and left unknown (at 20 to 120 s) by a search with coarser livelock
    clauses and no seed: gathered by a synthesised table that the checker verifies."""
    run = cli("--world", "grid", "--robots", robots, "--meeting", meeting, "--scheduler",
              "async", "--json", "--witness", "w.py", "--max-seconds", "240", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    c = Configuration(_nodes(robots), _nodes(meeting), initial=True)
    got = run_check(c, algorithm=str(tmp_path / "w.py") + ":Synthesized", scheduler="async",
                    properties=["final", "termination"], reduction=False, max_seconds=120,
                    force=True)
    assert got["verdict"] == "VERIFIED", got
