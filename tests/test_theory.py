"""The registry of the paper's theory (gather_verify.theory): the generic layers read the
paper's facts and precondition there, whatever was imported first."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from gather_verify import theory
from gather_verify.check import run_check
from gather_verify.model.configuration import Configuration

ROOT = Path(__file__).resolve().parent.parent
IN_U = Configuration([(0, 1), (2, 1)], [(0, 0), (2, 0)], initial=True)  # UNCLASSIFIED, in U
YARD = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)  # I13


def test_check_finds_the_paper_without_importing_it_first() -> None:
    """A fresh interpreter that imports only check: the first lookup loads the paper."""
    code = ("import sys\n"
            "from gather_verify.check import run_check\n"
            "from gather_verify.model.configuration import Configuration\n"
            "print('gather_verify.paper' in sys.modules)\n"
            "c = Configuration([(0, 1), (2, 1)], [(0, 0), (2, 0)], initial=True)\n"
            "r = run_check(c, algorithm='go-to-target', scheduler='fsync')\n"
            "print(r['verdict'], r['class'], 'gather_verify.paper' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True,
                         check=True).stdout.splitlines()
    assert out == ["False", "NOT-APPLICABLE UNCLASSIFIED True"]


def test_the_paper_registers_its_facts_and_precondition() -> None:
    assert theory.get_fact("class").values[-1] == "UNCLASSIFIED"
    assert theory.get_fact("class").of(YARD) == "I13" and not theory.get_fact("in_U").of(YARD)
    assert theory.not_applicable(IN_U, "all") == (
        "initial configuration is UNCLASSIFIED: use the impossibility checks (or --force)")
    assert theory.not_applicable(IN_U, "chirality") is None
    with pytest.raises(KeyError, match="no theory registers the fact 'nope'"):
        theory.get_fact("nope")
    with pytest.raises(ValueError, match="registered already"):
        theory.fact("class")(lambda c, aut_m_all=None: "I11")


def test_check_asks_every_registered_precondition(monkeypatch) -> None:
    """A precondition of another paper makes check NOT-APPLICABLE (--force checks anyway)."""
    theory.preconditions()  # the built-in ones first
    monkeypatch.setattr(theory, "_PRECONDITIONS", [*theory._PRECONDITIONS, theory.Precondition(
        "three robots", lambda c, frames: "three robots" if c.n == 3 else None)])
    r = run_check(YARD, algorithm="go-to-target", scheduler="fsync")
    assert (r["verdict"], r["reason"]) == ("NOT-APPLICABLE", "three robots")
    assert run_check(YARD, algorithm="go-to-target", scheduler="fsync", force=True)["verdict"] == \
        "VERIFIED"


@pytest.mark.parametrize("engine", ["reference", "fast"])
def test_both_engines_read_in_u_from_the_registry(monkeypatch, engine) -> None:
    """Broken on purpose: an ``in_U`` that holds on every configuration but the initial one
    (no shortcut declared) makes no-ungatherable fail, on the reference and the bulk engine."""
    theory.preconditions()
    broken = theory.Fact("in_U", lambda c, aut_m_all=None: c.robots != YARD.robots)
    monkeypatch.setitem(theory._FACTS, "in_U", broken)
    r = run_check(YARD, algorithm="go-to-target", scheduler="fsync", engine=engine,
                  properties=["no-ungatherable"], reduction=False)
    assert (r["verdict"], r["property"]) == ("VIOLATED", "no-ungatherable")
    monkeypatch.undo()
    r = run_check(YARD, algorithm="go-to-target", scheduler="fsync", engine=engine,
                  properties=["no-ungatherable"], reduction=False)
    assert r["verdict"] == "VERIFIED"


def test_a_reload_of_the_paper_registers_it_again_once() -> None:
    import importlib

    import gather_verify.paper

    count = len(theory.preconditions())
    importlib.reload(gather_verify.paper)
    assert len(theory.preconditions()) == count
    assert theory.get_fact("in_U").of(IN_U) is True
