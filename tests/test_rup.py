"""The resolution proof of a certificate of ``none`` (synthesis/rup.py, synthesis/refute.py):
the compiled check against a naive one and against brute force, the solver's proofs
trimmed, and certificates in that form accepted by --verify, or rejected once broken."""

from __future__ import annotations

import itertools
import json
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

pytest.importorskip("pysat", reason="the proofs come from python-sat (extra synth)")

from gather_verify.synthesis import refute, rup  # noqa: E402
from gather_verify.synthesis.certificate import CertificateError, verify_certificate  # noqa: E402
from tests.test_synthesis import cli, rejected  # noqa: E402

VARS = 5
literal = st.integers(1, VARS).flatmap(lambda v: st.sampled_from([v, -v]))
clause = st.lists(literal, min_size=0, max_size=3)
cnf = st.lists(clause.filter(bool), min_size=1, max_size=14)
proof = st.lists(st.one_of(clause, clause.map(lambda c: [0, *c])), max_size=8).map(
    lambda steps: [*steps, []])


def satisfiable(clauses: list[list[int]]) -> bool:
    """Brute force over every assignment of 1..VARS."""
    for bits in itertools.product((False, True), repeat=VARS):
        if all(any(bits[abs(x) - 1] == (x > 0) for x in c) for c in clauses):
            return True
    return False


def propagates_to_conflict(clauses: list[list[int]], assumed: list[int]) -> bool:
    """Unit propagation, naively: every literal of ``assumed`` true, then every clause with
    one literal left not false makes it true, until a clause is all false (True) or nothing
    moves (False)."""
    true = set(assumed)
    if any(-x in true for x in true):
        return True
    while True:
        moved = False
        for c in clauses:
            if any(x in true for x in c):
                continue
            left = {x for x in c if -x not in true}
            if not left:
                return True
            if len(left) == 1:
                true |= left
                moved = True
        if not moved:
            return False


def naive_check(base: list[list[int]], steps: list[list[int]]) -> bool:
    """The DRUP check the plain way: each lemma by unit propagation from its negation over
    the clauses held so far; a deletion drops one clause with the same literals."""
    held = [list(c) for c in base]
    if any(not c for c in held):
        return True
    for step in steps:
        if step and step[0] == 0:
            for j, c in enumerate(held):
                if set(c) == set(step[1:]):
                    del held[j]
                    break
            continue
        if not propagates_to_conflict(held, [-x for x in step]):
            return False
        if not step:
            return True
        held.append(list(step))
    return False


@settings(max_examples=80, deadline=None)
@given(cnf, proof)
def test_the_compiled_check_is_the_naive_one_and_never_proves_a_satisfiable_cnf(
        base: list[list[int]], steps: list[list[int]]) -> None:
    got = rup.check(VARS, base, steps)
    assert got.holds == naive_check(base, steps)
    if got.holds:
        assert not satisfiable(base)


@settings(max_examples=40, deadline=None)
@given(cnf)
def test_the_solver_s_proof_trimmed_still_holds_and_uses_only_what_it_keeps(
        base: list[list[int]]) -> None:
    steps = refute._solve(base, float("inf"))
    if steps is None:
        assert satisfiable(base)
        return
    core, trimmed = rup.trim(VARS, base, steps)
    kept = [base[j] for j in core]
    assert rup.check(VARS, kept, trimmed).holds
    assert naive_check(kept, trimmed)
    assert not satisfiable(kept)


def test_a_lemma_that_does_not_follow_is_named() -> None:
    base = [[1, 2], [-1, 2], [1, -2], [-1, -2]]
    assert rup.check(2, base, [[1], []]).holds
    got = rup.check(2, base[:3], [[-2, 1], []])  # the base holds with 1 and 2 both true
    assert not got.holds and got.step == 1
    assert rup.check(2, base, [[2]]).why == "the proof never adds the empty clause"
    with pytest.raises(ValueError, match="not a variable"):
        rup.check(2, base, [[3], []])


@pytest.fixture(scope="module")
def proved(tmp_path_factory: pytest.TempPathFactory) -> dict:
    """Two robots on ring:6, SSYNC, gathering (none), with --max-tree 1: a proof."""
    path = tmp_path_factory.mktemp("proof") / "c.json"
    run = cli("--world", "ring:6", "--robots", "2", "--scheduler", "ssync", "--task",
              "gathering", "--multiplicity", "global-weak", "--certificate", str(path),
              "--max-tree", "1")
    assert run.returncode == 1, run.stderr
    assert "a resolution proof of 1 lemma" in run.stdout
    doc = json.loads(path.read_text())
    assert doc["tree"] is None and doc["proof"]["steps"]
    return doc


def test_a_proof_certificate_passes_verify(tmp_path: Path, proved: dict) -> None:
    path = tmp_path / "c.json"
    path.write_text(json.dumps(proved))
    got = verify_certificate(str(path))
    assert got["proof_lemmas"] >= 1 and got["holds_under"] == ["fsync", "ssync", "async"]
    run = cli("--verify", str(path), "--explain")
    assert run.returncode == 0, run.stderr
    assert "a resolution proof of" in run.stdout and "rests on 2 of 3 starts" in run.stdout


def _drop_counterexample(doc: dict) -> None:
    doc["counterexamples"].pop(0)


def _no_empty_clause(doc: dict) -> None:
    doc["proof"]["steps"] = [[1]]


def _one_counterexample_left(doc: dict) -> None:
    doc["counterexamples"] = doc["counterexamples"][:1]  # one table escapes it


def _a_literal_out_of_range(doc: dict) -> None:
    doc["proof"]["steps"] = [[99], []]


def _not_integers(doc: dict) -> None:
    doc["proof"]["steps"] = [["1"], []]


@pytest.mark.parametrize("tamper", [_drop_counterexample, _no_empty_clause, _one_counterexample_left,
                                    _a_literal_out_of_range, _not_integers])
def test_a_broken_proof_fails_verify(tmp_path: Path, proved: dict, tamper) -> None:
    path = rejected(proved, tamper, tmp_path)
    with pytest.raises(CertificateError):
        verify_certificate(str(path))


def test_no_proof_in_time_is_unknown_naming_max_tree(monkeypatch: pytest.MonkeyPatch) -> None:
    """Past --max-tree, a none is given only with its proof: none found, ``unknown``."""
    from gather_verify.synthesis import search
    from gather_verify.synthesis.views import make_instance

    monkeypatch.setattr(search, "refutation", lambda *_args: None)
    inst = make_instance("ring:6", "2", "", "ssync", "gathering", "global-weak")
    res = search.synthesize(inst, max_tree=1)
    assert res.answer == "unknown" and res.limit.startswith("max-tree")
    assert search.synthesize(inst, max_tree=10).answer == "none"
