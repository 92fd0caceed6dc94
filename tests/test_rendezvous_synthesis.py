"""Synthesis on the rendezvous world against the theorems (SEMANTICS.md §12, §13): the
least colours per model and light kind, witnesses verified by the ordinary check,
``none`` certificates re-checked and refused when tampered with."""

from __future__ import annotations

import copy
import json
import subprocess
import sys

import pytest

from gather_verify.rendezvous_check import run_rendezvous_check
from gather_verify.synthesis.rendezvous import Setting, algorithm_of, synthesize, verify


def witness_verdict(r):
    setting = Setting(r["colours"], r["lights"], r["scheduler"], r["movement"],
                      r["initial_colours"])
    table = {tuple(v): tuple(a) for v, a in r["witness"]}
    alg = algorithm_of(setting, table, "w")
    return run_rendezvous_check(alg, r["scheduler"], movement=r["movement"],
                                initial_colours=r["initial_colours"])["verdict"]


def test_viglietta_two_colours_in_ssync_and_not_one():
    """Viglietta: 2 full colours suffice in SSYNC (non-rigid); 1 does not."""
    one = synthesize(1, "full", "ssync")
    assert one["answer"] == "none" and verify(one["certificate"])
    two = synthesize(2, "full", "ssync")
    assert two["answer"] == "exists" and witness_verdict(two) == "VERIFIED"


def test_two_colours_in_async_when_zero_distance_is_seen():
    """Heriban-Défago-Tixeuil: 2 colours in ASYNC, non-rigid, for robots that see whether
    they share a point (as this world's robots do); 1 colour does not."""
    assert synthesize(1, "full", "async")["answer"] == "none"
    two = synthesize(2, "full", "async")
    assert two["answer"] == "exists" and witness_verdict(two) == "VERIFIED"


def test_no_one_colour_external_algorithm_in_async():
    """Okumura-Wada-Défago: no colour-only external-light algorithm in ASYNC (K = 1 here;
    K = 2 under -m slow)."""
    r = synthesize(1, "external", "async")
    assert r["answer"] == "none" and verify(r["certificate"])


@pytest.mark.slow
@pytest.mark.parametrize("scheduler", ["async", "async-lc-atomic"])
def test_no_two_colour_external_algorithm(scheduler):
    r = synthesize(2, "external", scheduler)
    assert r["answer"] == "none" and verify(r["certificate"])


def test_a_tampered_certificate_is_refused():
    cert = synthesize(1, "full", "ssync")["certificate"]
    assert verify(cert)
    other = {**cert, "scheduler": "fsync"}  # to the midpoint gathers under fsync
    assert not verify(other)
    cut = copy.deepcopy(cert)
    cut["tree"]["children"] = cut["tree"]["children"][:-1]  # an answer left out
    assert not verify(cut)
    lying = copy.deepcopy(cert)
    lying["tree"] = {"refuted": True}  # the empty table refutes nothing
    assert not verify(lying)


def test_the_time_limit_says_unknown():
    r = synthesize(3, "full", "async-safe", max_seconds=0.01)
    assert r["answer"] == "unknown" and "time" in r["reason"]


def _cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "gather_verify", *args], capture_output=True,
                          text=True, timeout=120)


def test_the_issue_command_prints_answer(tmp_path):
    done = _cli("synthesize", "--world", "rendezvous", "--lights", "2", "--scheduler", "ssync",
                "--movement", "non-rigid", "--initial-colours", "all", "--json")
    assert done.returncode == 0 and json.loads(done.stdout)["answer"] == "exists"
    cert = tmp_path / "c.json"
    done = _cli("synthesize", "--world", "rendezvous", "--minimum", "--lights", "1-3",
                "--scheduler", "ssync", "--certificate", str(cert), "--json")
    out = json.loads(done.stdout)
    assert out["minimum"] == 2 and [r["answer"] for r in out["rows"]] == ["none", "exists"]
    done = _cli("synthesize", "--verify", str(cert))
    assert done.returncode == 0 and "holds" in done.stdout
    done = _cli("synthesize", "--world", "rendezvous", "--lights", "1-3", "--scheduler", "ssync")
    assert done.returncode == 2


def test_two_external_colours_in_lc_strict_async_by_the_referee_too():
    """A finding: 2 external colours suffice in LC-strict ASYNC (non-rigid). The witness
    passes the independent referee there and fails LC-atomic."""
    from rendezvous_referee import check

    r = synthesize(2, "external", "async-lc-strict")
    assert r["answer"] == "exists"
    setting = Setting(2, "external", "async-lc-strict", "non-rigid", "all")
    alg = algorithm_of(setting, {tuple(v): tuple(a) for v, a in r["witness"]}, "w")
    assert check(alg, "async-lc-strict").verdict == "PASS"
    assert check(alg, "async-lc-atomic").verdict == "FAIL"


def test_a_malformed_certificate_is_one_line_or_refused():
    from gather_verify.errors import InvalidInput

    cert = synthesize(1, "full", "ssync")["certificate"]
    with pytest.raises(InvalidInput, match="bad certificate"):
        verify({**cert, "colours": 99})
    with pytest.raises(InvalidInput, match="unknown synchrony model"):
        verify({**cert, "scheduler": "nope"})
    assert not verify({**cert, "tree": {"view": 5, "children": []}})
    assert not verify({**cert, "tree": [1, 2]})
