"""Readings (SEMANTICS.md §8): every option of ``paper`` changes a verdict somewhere, the
covering set is sound, and robustness is never claimed on fewer readings than were run."""

from __future__ import annotations

import itertools
import json
import random
from pathlib import Path

import pytest

from gather_verify.algorithms.base import Unhandled
from gather_verify.check import run_check
from gather_verify.cli import main
from gather_verify.model.configuration import Configuration
from gather_verify.paper.algorithm import DEFAULTS, READINGS, PaperAlgorithm, Reading, analyse
from gather_verify.paper.readings import (
    check_readings,
    covering,
    m_type,
    parse_readings,
    reading_name,
    relevant_options,
    robustness,
    robustness_table,
)
from gather_verify.scenario import load_scenario
from gather_verify.sweeps.census import enumerate_configurations

ROOT = Path(__file__).resolve().parents[1]
F9 = ROOT / "scenarios/regressions/i22-target-invariance-paper-alpha-mer-f-async-c22c1622.json"
F11_ROTATION = ROOT / "scenarios/regressions/i22-defined-paper-async-4cdeec30.json"
LIMITS = {"max_states": 10**5, "max_seconds": 120}


def verdict(c: Configuration, algorithm: str, scheduler: str = "async") -> tuple[str, str | None]:
    r = run_check(c, algorithm=algorithm, scheduler=scheduler, **LIMITS)
    return r["verdict"], r["property"]


def configuration(path: Path) -> Configuration:
    return load_scenario(str(path)).configuration


# -- each option changes a verdict ----------------------------------------------------


def test_metric_euclid_removes_f11_rotation_case():
    """Manhattan ties (0,0) and (2,3) at 7 from c; Euclidean makes (0,0) the unique farthest."""
    c = configuration(F11_ROTATION)
    assert verdict(c, "paper") == ("VIOLATED", "defined")
    assert verdict(c, "paper:metric=euclid") == ("VERIFIED", None)


def test_oscan_guard_alone_removes_a_target_flip():
    c = Configuration([(0, 0), (0, 1)], [(1, 0), (2, 1)], initial=True)
    assert verdict(c, "paper") == ("VIOLATED", "target-invariance")
    assert verdict(c, "paper:oscan=guard") == ("VERIFIED", None)


def test_f9_needs_oscan_guard_and_finalize_target_together():
    """F9 survives each of the two readings alone: they interact (the covering set is a
    product for that reason)."""
    c = configuration(F9)
    for algorithm in ("paper", "paper:oscan=guard", "paper:finalize=target"):
        assert verdict(c, algorithm) == ("VIOLATED", "target-invariance"), algorithm
    assert verdict(c, "paper:oscan=guard,finalize=target") == ("VERIFIED", None)


def test_finalize_target_has_failures_of_its_own():
    """The walking guard is on a MER corner again and O'' picks the other tied node."""
    c = Configuration([(0, 0), (1, 2)], [(1, 2), (2, 1)], initial=True)
    assert verdict(c, "paper") == ("VERIFIED", None)
    assert verdict(c, "paper:finalize=target") == ("VIOLATED", "target-invariance")


def test_finalize_literal_walks_both_robots():
    """Algorithm 4 whenever n1 = 2: two robots off meeting nodes both qualify as r."""
    c = Configuration([(0, 0), (0, 1)], [(0, 2), (1, 0)], initial=True)
    assert verdict(c, "paper") == ("VERIFIED", None)
    assert verdict(c, "paper:finalize=literal")[0] == "VIOLATED"
    plan = analyse(c, finalize="literal")
    assert plan.phase == "I2 finalization (literal)"
    assert plan.moves[(0, 0)] == {(0, 1)} and plan.moves[(0, 1)] == {(0, 0)}
    both_on_meeting = Configuration([(0, 0), (1, 0)], [(0, 0), (1, 0), (1, 2), (2, 2)])
    with pytest.raises(Unhandled, match="no robot qualifies"):
        analyse(both_on_meeting, finalize="literal")


def test_finalize_n1_and_unclassified_unhandled_change_verdicts():
    c = Configuration([(0, 0), (0, 2)], [(1, 0), (1, 1)], initial=True)
    assert verdict(c, "paper") == ("VERIFIED", None)
    assert verdict(c, "paper:finalize=n1") == ("VIOLATED", "defined")
    c = Configuration([(0, 1), (1, 1)], [(0, 0), (2, 2)], initial=True)
    assert verdict(c, "paper") == ("VERIFIED", None)
    assert verdict(c, "paper:unclassified=unhandled") == ("VIOLATED", "defined")


def test_bad_reading_values_are_refused():
    with pytest.raises(ValueError, match="metric"):
        parse_readings("metric=taxicab")
    with pytest.raises(ValueError, match="unknown option"):
        parse_readings("colour")
    with pytest.raises(ValueError, match="needs the algorithm paper"):
        parse_readings("all", "go-to-target")


# -- the covering set is sound ----------------------------------------------------------


def _plan(c: Configuration, values: dict[str, str]) -> object:
    try:
        return analyse(c, values)
    except Unhandled as error:
        return f"Unhandled: {error}"


def _snapshots() -> list[Configuration]:
    """Initial configurations of every M type and snapshots reached by moving robots."""
    rng = random.Random(14)
    out = []
    for n, m in ((2, 2), (2, 3), (3, 2), (3, 4)):
        out += rng.sample(list(enumerate_configurations(n, m, 3, 3)), 12)
    out += rng.sample(list(enumerate_configurations(3, 2, 4, 4)), 12)
    for c in list(out):  # a robot moved one step: snapshots met during runs
        r = rng.choice(sorted(c.robots))
        step = rng.choice([(1, 0), (-1, 0), (0, 1), (0, -1)])
        moved = (r[0] + step[0], r[1] + step[1])
        if moved not in c.robots:
            out.append(Configuration([v for v in c.robots if v != r] + [moved], c.meeting_nodes))
    return out


def _covering_failures(snapshots: list[Configuration]) -> list[tuple]:
    """Snapshots where changing an option their M type does not read changes the plan."""
    rng = random.Random(8)
    failures = []
    for c in snapshots:
        read = relevant_options(c)
        for _ in range(3):
            values = {o: rng.choice(v) for o, v in READINGS.items()}
            plan = _plan(c, values)
            failures += [(c, option, other) for option in set(READINGS) - set(read)
                         for other in READINGS[option]
                         if _plan(c, {**values, option: other}) != plan]
    return failures


def test_options_not_read_on_an_M_do_not_change_any_plan():
    """The covering claim of :mod:`gather_verify.paper.readings`: for every snapshot, changing an
    option its M type does not read leaves the plan (or the Unhandled reason) equal."""
    snapshots = _snapshots()
    assert {m_type(c) for c in snapshots} == {"I1-ordered", "I13", "reflection", "rotation"}
    assert _covering_failures(snapshots) == []


def test_the_covering_claim_would_catch_an_option_read_where_it_is_said_not_to_be(monkeypatch):
    """Broken on purpose: claim that rotational M do not read ``metric``."""
    from gather_verify.paper import readings

    monkeypatch.setitem(readings._READ, "rotation", tuple(
        o for o in readings._READ["rotation"] if o != "metric"))
    failures = _covering_failures([configuration(F11_ROTATION)])
    assert failures and {option for _, option, _ in failures} == {"metric"}


# -- robustness ---------------------------------------------------------------------------


def test_robustness_labels():
    assert robustness(["VIOLATED"] * 3) == "ROBUST-VIOLATED"
    assert robustness(["VERIFIED"] * 3) == "ROBUST-VERIFIED"
    assert robustness(["VERIFIED", "VIOLATED", "INCOMPLETE"]) == "READING-DEPENDENT"
    assert robustness(["VIOLATED", "INCOMPLETE"]) == "INCOMPLETE"  # never robust on fewer
    assert robustness(["VERIFIED", "INCOMPLETE"]) == "INCOMPLETE"
    assert robustness(["NOT-APPLICABLE"] * 2) == "NOT-APPLICABLE"


def test_check_readings_reports_every_reading_run():
    c = configuration(F11_ROTATION)
    report = check_readings(c, "all", algorithm="paper", scheduler="async", **LIMITS)
    specs = [r["algorithm"] for r in report["readings"]]
    assert len(specs) == len(set(specs)) == 1536 == len(covering(parse_readings("all"), c))
    assert specs[0] == reading_name({o: v[0] for o, v in READINGS.items()})
    assert report["algorithm"] == specs[0] and report["verdict"] == "VIOLATED"
    assert report["robustness"] == "READING-DEPENDENT"
    assert report["readings_not_read"] == {"alpha": ["mer", "mer_f"]}
    assert sum(r["readings"] for r in report["runs"]) == 1536 > len(report["runs"])
    removed = {r["algorithm"] for r in report["readings"] if r["verdict"] == "VERIFIED"}
    assert removed and all("metric=euclid" in a or "placement=reachable" in a for a in removed)


def test_a_finite_run_over_the_constant_refutes_no_claim(capsys):
    """Every reading's run goes over c·D·n with c = 0.1 and gathers: move-bound is VIOLATED
    under each, the robustness is ROBUST-VERIFIED, and the run is over the constant."""
    c = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)
    report = check_readings(c, "all", algorithm="paper", scheduler="async", move_bound_c=0.1,
                            **LIMITS)
    assert report["verdict"] == "VIOLATED" and report["property"] == "move-bound"
    assert report["runs"][0]["fault"] == "VERIFIED"
    assert report["robustness"] == "ROBUST-VERIFIED"
    over = report["over_constant"]  # 9 moves, D = 4, n = 3
    assert over == {"runs": 1, "readings": 1, "moves": 9, "bound": pytest.approx(1.2)}
    assert main(["check", "--robots", "0,0 3,1 1,4", "--meeting", "2,2", "--readings", "all",
                 "--move-bound-c", "0.1"]) == 0
    out = capsys.readouterr().out
    assert "over the project's constant" in out and "robustness: ROBUST-VERIFIED" in out


@pytest.mark.slow
def test_the_walk_away_over_the_constant_is_not_robust():
    """The I31 run that walks away under placement=reachable, survivor=off-target: 33 moves
    over 4·D·n = 32, the search stopped by its region, so its other claims are undecided:
    INCOMPLETE, never a fault."""
    c = Configuration([(0, 0), (1, 1), (1, 2), (2, 1)], [(0, 1), (0, 2), (1, 0), (2, 0)],
                      initial=True)
    report = check_readings(c, "placement=reachable,survivor=off-target", algorithm="paper",
                            scheduler="async")
    assert report["verdict"] == "VIOLATED" and report["property"] == "move-bound"
    assert report["robustness"] == "INCOMPLETE"
    assert report["over_constant"] == {"runs": 1, "readings": 1, "moves": 33, "bound": 32.0}


def test_check_readings_incomplete_is_never_robust():
    c = configuration(F11_ROTATION)
    report = check_readings(c, "metric", algorithm="paper", scheduler="async", max_states=2,
                            max_seconds=60)
    assert {r["verdict"] for r in report["readings"]} <= {"INCOMPLETE", "VIOLATED"}
    assert report["robustness"] in ("INCOMPLETE",)


def test_check_cli_readings_json(capsys):
    code = main(["check", str(F11_ROTATION), "--readings", "metric,finalize=closest|n1",
                 "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 1 and out["robustness"] == "READING-DEPENDENT"
    assert [(r["algorithm"].split(",")[1], r["algorithm"].split(",")[3], r["verdict"])
            for r in out["readings"]] == [
        ("metric=manhattan", "finalize=closest", "VIOLATED"),
        ("metric=manhattan", "finalize=n1", "VIOLATED"),
        ("metric=euclid", "finalize=closest", "VERIFIED"),
        ("metric=euclid", "finalize=n1", "VIOLATED")]
    assert set(out["readings"][0]) == {"algorithm", "verdict", "property", "fault", "run"}
    assert main(["check", str(F11_ROTATION), "--readings", "metric=taxicab"]) == 2
    assert "metric" in capsys.readouterr().err


def test_check_cli_robust_verdicts(capsys):
    assert main(["check", "--robots", "0,0 3,1 1,4", "--meeting", "2,2", "--readings",
                 "all"]) == 0
    out = capsys.readouterr().out
    assert "robustness: ROBUST-VERIFIED" in out and "readings (1 run for 1 reading)" in out


def test_robustness_table_counts_only_complete_coverings():
    base, other = "paper:a", "paper:b"
    groups = [
        ({"algorithm": base, "extra": {"types": ["I1-ordered", "rotation", "I13",
                                                  "reflection"]}},
         [{"key": "k1", "class": "I22", "verdict": "VIOLATED"},
          {"key": "k2", "class": "I22", "verdict": "VERIFIED"},
          {"key": "k3", "class": "I22", "verdict": "VIOLATED"},
          {"key": "k4", "class": "I13", "verdict": "VERIFIED"},
          {"key": "k5", "class": "UNCLASSIFIED", "verdict": "NOT-APPLICABLE"},
          {"key": "k6", "class": "I22", "verdict": "VIOLATED"},
          {"key": "k7", "class": "I22", "verdict": "VIOLATED"}]),
        ({"algorithm": other, "extra": {"types": ["rotation"]}},
         [{"key": "k1", "class": "I22", "verdict": "VERIFIED"},
          {"key": "k6", "class": "I22", "verdict": "VIOLATED"}]),
        ({"algorithm": "paper:c", "extra": {"types": ["rotation"]}},  # interrupted before k6
         [{"key": "k1", "class": "I22", "verdict": "VIOLATED"}]),
    ]
    table = robustness_table(groups)
    assert table["I22"] == {"READING-DEPENDENT": 1, "PARTIAL": 1, "DEFAULT-ONLY": 3}
    complete = robustness_table(groups[:2])["I22"]
    assert complete == {"READING-DEPENDENT": 1, "ROBUST-VIOLATED": 1, "DEFAULT-ONLY": 3}
    assert table["I13"] == {"ROBUST-VERIFIED": 1}  # I13 reads no option: one reading is all
    assert table["UNCLASSIFIED"] == {"NOT-APPLICABLE": 1}


def test_robustness_table_counts_runs_over_the_constant_beside_the_robustness(capsys):
    from gather_verify.paper.readings import OVER, format_robustness

    base = {"algorithm": "paper", "extra": {"on": "all"}}
    dynamic = {"algorithm": "paper", "extra": {"on": "all", "covering": "dynamic"}}
    over = {"runs": 2, "readings": 80, "moves": 33, "bound": 32.0}
    rows = [{"key": k, "class": "I31", "verdict": v} for k, v in
            (("a", "VIOLATED"), ("b", "VIOLATED"), ("c", "VERIFIED"))]
    robust = [{"key": "a", "class": "I31", "verdict": "INCOMPLETE",
               "trace": {"over_constant": over}},
              {"key": "b", "class": "I31", "verdict": "ROBUST-VIOLATED",
               "trace": {"over_constant": None}},
              {"key": "c", "class": "I31", "verdict": "ROBUST-VERIFIED",
               "trace": {"over_constant": over}}]
    table = robustness_table([(base, rows), (dynamic, robust)])
    assert table["I31"] == {"INCOMPLETE": 1, "ROBUST-VIOLATED": 1, "ROBUST-VERIFIED": 1,
                            OVER: 2}
    format_robustness(table)
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("I31"))
    assert line.split()[:2] == ["I31", "3"] and line.split()[-1] == "2"


def test_sweep_readings_stores_every_reading(tmp_path, capsys):
    db = tmp_path / "r.sqlite"
    code = main(["sweep", "--robots", "2", "--meeting", "2", "--box", "3x2", "--readings",
                 "metric,oscan", "--db", str(db), "--workers", "1", "--json"])
    table = json.loads(capsys.readouterr().out)["robustness"]
    assert code in (0, 1)
    assert sum(sum(by.values()) for by in table.values()) == len(
        list(enumerate_configurations(2, 2, 3, 2)))
    assert main(["report", "--db", str(db)]) == 0
    assert "class x robustness" in capsys.readouterr().out
    assert main(["sweep", "--robots", "2", "--meeting", "2", "--box", "3x2", "--readings", "all",
                 "--readings-types", "spiral", "--db", str(db)]) == 2
    assert "spiral" in capsys.readouterr().err


# -- the audit's readings: placement, survivor, hidden ------------------------------------

A4_WITNESS = ROOT / "scenarios/regressions/i21-defined-paper-async-57a8f95c.json"
F4_N4 = (ROOT / "scenarios/regressions/i21-final-paper-async-83746d8b.json",
         ROOT / "scenarios/regressions/i31-final-paper-async-7f66536a.json")
F4_N3 = ROOT / "scenarios/algorithm/i22-make-multiplicity-onto-guard.json"
F7_I31 = (ROOT / "scenarios/algorithm/i31-symmetry-breaking-onto-robot.json",
          ROOT / "scenarios/regressions/i31-defined-paper-async-3b999754.json")
F11_DIAGONAL = ROOT / "scenarios/algorithm/i21-diagonal-axis-guard-corner.json"


def test_placement_reachable_removes_the_a4_witness():
    """Algorithm 2 line 5: the closest corner has no step that keeps the guard's distance
    from L; the closest corner it can approach so has one."""
    c = configuration(A4_WITNESS)
    assert verdict(c, "paper") == ("VIOLATED", "defined")
    assert verdict(c, "paper:placement=reachable") == ("VERIFIED", None)
    c = configuration(F11_DIAGONAL)
    assert verdict(c, "paper") == ("VIOLATED", "defined")
    assert verdict(c, "paper:placement=reachable") == ("VERIFIED", None)
    assert verdict(c, "paper:placement=reachable,finalize=target") == ("VERIFIED", None)


def test_placement_is_read_only_where_the_closest_corner_has_no_step():
    """The two placements agree wherever A4 has a step: there the option is not read."""
    guard_off_corner = Configuration([(0, 0), (-4, 2)], [(0, 2), (0, 3), (2, 0), (3, 0)])
    reading = Reading(DEFAULTS)
    plan = analyse(guard_off_corner, reading)
    assert plan.phase == "I2 guard placement" and "placement" not in reading.consulted
    assert analyse(guard_off_corner, placement="reachable") == plan


def test_survivor_not_both_and_off_target_remove_the_n4_deadlocks():
    for path in F4_N4:
        c = configuration(path)
        assert verdict(c, "paper") == ("VIOLATED", "final"), path.name
        assert verdict(c, "paper:survivor=not-both") == ("VERIFIED", None), path.name
        assert verdict(c, "paper:survivor=off-target") == ("VERIFIED", None), path.name


def test_survivor_off_target_removes_f4_and_not_both_does_not():
    c = configuration(F4_N3)
    assert verdict(c, "paper") == ("VIOLATED", "final")
    assert verdict(c, "paper:survivor=not-both") == ("VIOLATED", "final")
    assert verdict(c, "paper:survivor=off-target") == ("VERIFIED", None)


def test_survivor_rules_as_a_robot_sees_them():
    """F4's snapshot: the guard's node (0,0) holds two robots (invisible to the others),
    (0,1) one robot on the target. Each rule is a move per position and a move for the
    robots that see their own node as a multiplicity."""
    c = Configuration([(0, 0), (0, 1)], [(0, 1), (2, 1)])
    neither = analyse(c)
    assert neither.moves == {(0, 0): {(0, 1)}, (0, 1): {(0, 1)}}
    assert neither.if_multiplicity == {(0, 0): {(0, 0)}}
    not_both = analyse(c, survivor="not-both")
    assert not_both.moves == {(0, 0): {(0, 1)}, (0, 1): {(0, 0)}}
    assert not_both.if_multiplicity == {(0, 1): {(0, 1)}}
    off_target = analyse(c, survivor="off-target")
    assert off_target.moves == neither.moves and off_target.if_multiplicity == {}


def test_survivor_not_both_breaks_a_two_robot_run_the_default_gathers():
    """With one robot on each position, the robot on the target qualifies too: both walk."""
    c = Configuration([(0, 0), (0, 1)], [(0, 1), (2, 1)], initial=True)
    assert verdict(c, "paper") == ("VERIFIED", None)
    assert verdict(c, "paper:survivor=not-both")[0] == "VIOLATED"


def test_hidden_infer_removes_the_n3_f7_witnesses():
    for path in F7_I31:
        c = configuration(path)
        for scheduler in ("fsync", "async"):
            assert verdict(c, "paper", scheduler) == ("VIOLATED", "defined"), path.name
            for finalize in ("closest", "target"):
                assert verdict(c, f"paper:hidden=infer,finalize={finalize}", scheduler) == (
                    "VERIFIED", None), (path.name, scheduler, finalize)


def test_hidden_infer_acts_only_where_the_hidden_node_is_known():
    """Two positions: the robot off a multiplicity is the guard and steps away from L; three
    or more: it cannot tell which position holds the multiplicity, no rule."""
    two = Configuration([(0, 1), (1, 0)], [(0, 1), (0, 2), (1, 0), (2, 0)])
    with pytest.raises(Unhandled, match="^I41-looking snapshot: "):
        analyse(two)
    plan = analyse(two, hidden="infer")
    assert plan.moves[(1, 0)] == {(2, 0), (1, -1)} and plan.if_multiplicity[(1, 0)] == {(1, 0)}
    three = Configuration([(0, 1), (1, 0), (0, 3), (3, 0)], [(0, 1), (0, 2), (1, 0), (2, 0)])
    with pytest.raises(Unhandled, match=r"^I41-looking snapshot \(hidden=infer\): "):
        analyse(three, hidden="infer")


def _read_unrecorded(monkeypatch, hidden: str) -> None:
    """Break the tracker on purpose: ``hidden`` is read without being recorded."""
    def unrecorded(self, option):
        if option != hidden:
            self.consulted.add(option)
        return self.values[option]

    monkeypatch.setattr(Reading, "__getitem__", unrecorded)


# -- the proof of Theorem 8: GuardMovement starts when one position is off m ----------------

F4_N2 = ROOT / "scenarios/regressions/i22-final-paper-async-c933bc2a.json"
I21_PILE_ON_GUARD = [Configuration([(0, 0), (0, 1), (0, 2), (0, 3)], m, initial=True)
                     for m in ([(1, 0), (1, 1), (2, 2), (3, 2)], [(1, 0), (2, 0), (3, 1), (3, 2)])]


def test_movement_proof_removes_the_deadlocks_on_the_guards_node():
    """F4 with two robots and the two I21 runs whose non-guards all step onto the guard: the
    pseudo-code leaves every robot there without a move; the proof's GuardMovement walks
    them to m (every robot on the guard's node, then the multiplicity left behind)."""
    for c in [configuration(F4_N2), *I21_PILE_ON_GUARD]:
        assert verdict(c, "paper") == ("VIOLATED", "final"), c
        assert verdict(c, "paper:movement=proof") == ("VERIFIED", None), c


def test_movement_proof_acts_only_where_the_pseudo_code_has_no_rule():
    """Every robot on the placed guard's node: no move, or towards m. Finalization: the
    position off the target moves as before; only its robots on a multiplicity, to whom
    ``survivor=neither`` gives no move, get one; other parses of line 2 are left alone."""
    pile = Configuration([(0, 0)], [(1, 0), (1, 1), (2, 1), (2, 2)])
    reading = Reading(DEFAULTS)
    assert analyse(pile, reading).moves == {(0, 0): {(0, 0)}}
    assert "movement" in reading.consulted
    proof = analyse(pile, movement="proof")
    assert proof.moves == {(0, 0): {(1, 0)}} and proof.target == (1, 0)
    final = Configuration([(0, 0), (0, 1)], [(0, 1), (2, 1)])
    reading = Reading(DEFAULTS)
    plan = analyse(final, reading)
    assert "movement" not in reading.consulted  # read by the robot on the multiplicity only
    assert plan.if_multiplicity == {(0, 0): {(0, 0)}} and plan.proof_moves == {(0, 0): {(0, 1)}}
    for survivor in ("not-both", "off-target"):
        assert analyse(final, survivor=survivor).proof_moves == {}


def test_movement_is_read_when_a_robot_on_the_multiplicity_decides():
    """The option is consulted by ``allowed``, when a robot sees its own multiplicity at a
    position of ``proof_moves``; planned move sets and ``decide`` agree on it."""
    from gather_verify.algorithms.moves import frames_for, move_set

    one_each = Configuration([(0, 0), (0, 1)], [(0, 1), (2, 1)])
    two_on_guard = Configuration([(0, 0), (0, 0), (0, 1)], [(0, 1), (2, 1)])
    for movement, expected in (("algorithm", {(0, 0)}), ("proof", {(0, 1)})):
        algo = PaperAlgorithm(movement=movement)
        assert algo.move_sets(one_each, "local-weak", frames_for("all"))[(0, 0)] == {(0, 1)}
        assert "movement" not in algo.consulted
        planned = algo.move_sets(two_on_guard, "local-weak", frames_for("all"))
        assert planned[(0, 0)] == expected == move_set(algo, two_on_guard, (0, 0))
        assert "movement" in algo.consulted


def test_every_unhandled_of_paper_starts_with_its_own_rule_label():
    """The text before the first colon names the rule (another tool groups failures by it):
    one label per raise site."""
    import ast
    import inspect

    from gather_verify.paper import algorithm as paper

    labels = []
    for node in ast.walk(ast.parse(inspect.getsource(paper))):
        if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "Unhandled":
            first = node.args[0]
            if not isinstance(first, ast.Constant | ast.JoinedStr):
                continue  # a plan's Unhandled raised again
            parts = first.values if isinstance(first, ast.JoinedStr) else [first]
            text = "".join(p.value if isinstance(p, ast.Constant) else "{}" for p in parts)
            label, colon, _ = text.partition(":")
            assert colon and 0 < len(label) <= 60, text
            labels.append(label)
    assert len(labels) == len(set(labels)) >= 12, labels


# -- the dynamic covering is sound ----------------------------------------------------------


def _all_readings() -> list[dict[str, str]]:
    return [dict(zip(READINGS, combo, strict=True))
            for combo in itertools.product(*READINGS.values())]


def _tracker_failures(snapshots: list[Configuration], seed: int = 3) -> list[tuple]:
    """Snapshots where a reading that agrees with another on every option its plan consulted
    gets a different plan (or Unhandled reason)."""
    rng = random.Random(seed)
    everything = _all_readings()
    failures = []
    for c in snapshots:
        for values in rng.sample(everything, 4):
            reading = Reading(values)
            plan = _plan(c, reading)
            same = [r for r in everything if all(r[o] == values[o] for o in reading.consulted)]
            failures += [(c, values, r) for r in rng.sample(same, min(24, len(same)))
                         if _plan(c, r) != plan]
    return failures


def _finalization_snapshots() -> list[Configuration]:
    """Two positions, one on a meeting node (Algorithm 4), and the A4 and F7 snapshots."""
    out = [c for c in enumerate_configurations(2, 2, 3, 3)
           if sum(r in c.meeting_nodes for r in c.robots) == 1]
    return out + [Configuration([(-3, 1), (0, 0)], [(0, 2), (0, 3), (2, 0), (3, 0)]),
                  Configuration([(0, 1), (1, 0)], [(0, 1), (0, 2), (1, 0), (2, 0)])]


def test_readings_equal_on_the_consulted_options_plan_alike():
    """The claim behind the dynamic covering, on random snapshots of every M type and on
    every Algorithm 4 snapshot of two robots in a 3 x 3 box."""
    assert _tracker_failures(_snapshots() + _finalization_snapshots()) == []


def test_the_tracker_check_would_catch_an_option_read_unrecorded(monkeypatch):
    """Broken on purpose: ``survivor`` read without being recorded."""
    _read_unrecorded(monkeypatch, "survivor")
    failures = _tracker_failures(_finalization_snapshots())
    assert failures and all(a["survivor"] != b["survivor"] for _, a, b in failures)


def _dynamic_against_product(path: Path, readings: str, scheduler: str) -> list[tuple]:
    c = configuration(path)
    kw = dict(algorithm="paper", scheduler=scheduler, **LIMITS)
    dynamic = check_readings(c, readings, **kw)
    full = check_readings(c, readings, dynamic=False, **kw)
    assert len(full["runs"]) == len(full["readings"]) > len(dynamic["runs"])
    return [(a["algorithm"], a["verdict"], b["verdict"])
            for a, b in zip(dynamic["readings"], full["readings"], strict=True)
            if (a["algorithm"], a["verdict"], a["property"]) !=
            (b["algorithm"], b["verdict"], b["property"])]


def test_dynamic_covering_gives_every_reading_the_verdict_of_its_own_run():
    assert _dynamic_against_product(F11_DIAGONAL, "finalize,placement,survivor,hidden",
                                    "async") == []
    assert _dynamic_against_product(F7_I31[0], "finalize,outside,survivor,hidden",
                                    "fsync") == []
    # movement is read by a robot when it decides, not by a plan
    assert _dynamic_against_product(F4_N3, "movement,survivor,finalize=closest|literal",
                                    "async") == []


@pytest.mark.parametrize(("option", "path", "readings", "other"), [
    ("placement", F11_DIAGONAL, "placement,finalize=closest", "placement=reachable"),
    ("movement", F4_N3, "movement,survivor", "movement=proof")])
def test_dynamic_covering_check_would_catch_a_broken_tracker(monkeypatch, option, path,
                                                             readings, other):
    """Broken on purpose: ``option`` read without being recorded, so the runs under its
    first value claim the readings of the other too."""
    _read_unrecorded(monkeypatch, option)
    wrong = _dynamic_against_product(path, readings, "async")
    assert wrong and all(other in a for a, _, _ in wrong)


def test_check_cli_readings_all_on_the_a4_witness(capsys):
    code = main(["check", str(A4_WITNESS), "--readings", "all", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 1 and out["robustness"] == "READING-DEPENDENT"
    by = {r["algorithm"]: r["verdict"] for r in out["readings"]}
    assert len(by) == 384 and len(out["runs"]) < 384
    assert {v for a, v in by.items() if "placement=reachable" in a} == {"VERIFIED"}
    assert {v for a, v in by.items() if "placement=closest" in a} == {"VIOLATED"}


@pytest.mark.slow  # a long sweep: the default run keeps a shorter test of the same property
def test_a_readings_sweep_examines_every_configuration_by_the_dynamic_covering(tmp_path, capsys):
    """``sweep --readings``: every configuration the base reading applies to gets a
    robustness row, and each equals the robustness of the full product of its readings
    (``check_readings(..., dynamic=False)``), on a sample; the switches are counted.
    Four options (48 readings, those of the covering test above): ``all`` (192) costs eight
    times the CPU here and finds the same two robustness verdicts; ``--readings all`` is
    parsed as by ``check`` (test_check_cli_readings_all_on_the_a4_witness)."""
    from gather_verify.sweeps.store import Store

    db = tmp_path / "r.sqlite"
    readings = "finalize,placement,survivor,hidden"
    argv = ["sweep", "--robots", "2", "--meeting", "2", "--box", "3x2", "--readings", readings,
            "--db", str(db), "--workers", "1", "--json"]
    assert main(argv) == 1
    out = json.loads(capsys.readouterr().out)
    assert out["robustness"]["I22"]["READING-DEPENDENT"] > 0
    assert "survivor=not-both" in out["switches"]["I22"]["broken by"]
    store = Store(str(db))
    try:
        sweeps = store.sweeps()
        base = [r for i, s in sweeps if "covering" not in s["extra"] for r in store.results(i)]
        robust = [r for i, s in sweeps if s["extra"].get("covering") == "dynamic"
                  for r in store.results(i)]
    finally:
        store.close()
    applicable = [r for r in base if r["verdict"] != "NOT-APPLICABLE"]
    assert {r["key"] for r in robust} == {r["key"] for r in applicable}  # not the base alone
    sample = [r for r in robust if r["verdict"] == "READING-DEPENDENT"][:3] + \
        [r for r in robust if r["verdict"] == "ROBUST-VIOLATED"][:3]
    assert len(sample) == 6
    for row in sample:
        c = Configuration([tuple(v) for v in row["robots"]],
                          [tuple(v) for v in row["meeting_nodes"]], initial=True)
        full = check_readings(c, readings, dynamic=False, scheduler="async", memo=False)
        assert row["verdict"] == full["robustness"], row["key"]
    assert main(argv) == 1  # resumed: nothing to compute, the same tables
    assert json.loads(capsys.readouterr().out) == out


def test_the_default_readings_verdict_table_says_it_is_one_reading(tmp_path, capsys):
    """The README's main job: the verdict table of ``paper`` says its counts are the default
    reading's and points to --readings; another algorithm's table says nothing of it."""
    argv = ["sweep", "--robots", "2", "--meeting", "2", "--box", "2x2", "--workers", "1"]
    main([*argv, "--algorithm", "paper", "--db", str(tmp_path / "p.sqlite")])
    out = capsys.readouterr().out
    assert "under its default reading" in out and "--readings all" in out
    main([*argv, "--algorithm", "paper:alpha=mer_f", "--db", str(tmp_path / "f.sqlite")])
    assert "under the reading paper:alpha=mer_f" in capsys.readouterr().out
    main([*argv, "--algorithm", "go-to-target", "--db", str(tmp_path / "g.sqlite")])
    assert "--readings" not in capsys.readouterr().out
