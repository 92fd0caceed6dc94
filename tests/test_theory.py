"""The registry of the paper's theory (gather_verify.theory): the generic layers read the
paper's facts and precondition there, whatever was imported first."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from gather_verify import theory
from gather_verify.errors import InvalidInput
from gather_verify.model.configuration import Configuration
from gather_verify.plane_check import run_check

ROOT = Path(__file__).resolve().parent.parent
IN_U = Configuration([(0, 1), (2, 1)], [(0, 0), (2, 0)], initial=True)  # UNCLASSIFIED, in U
YARD = Configuration([(0, 0), (3, 1), (1, 4)], [(2, 2)], initial=True)  # I13


def test_check_finds_the_paper_without_importing_it_first() -> None:
    """A fresh interpreter that imports only check: the first lookup loads the paper."""
    code = ("import sys\n"
            "from gather_verify.plane_check import run_check\n"
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


# -- the scope of a paper's property, and the sweep table's legend ------------------------

def test_the_paper_scopes_no_ungatherable_to_oblivious_disoriented_robots(monkeypatch) -> None:
    """The paper's registration is what drops no-ungatherable under a compass: without it the
    check would decide a property whose U means nothing there."""
    r = run_check(YARD, algorithm="go-to-target", scheduler="fsync", frames="compass")
    assert "no-ungatherable" not in r["properties"]
    assert r["not_applicable"] == {"no-ungatherable": "U (Theorem 1) is for robots with no "
                                   "common orientation, not --frames compass"}
    with pytest.raises(InvalidInput, match="^no-ungatherable does not apply under --frames "
                       "chirality: U \\(Theorem 1\\) is for robots with no common orientation$"):
        run_check(YARD, algorithm="go-to-target", scheduler="fsync", frames="chirality",
                  properties=["no-ungatherable"])
    scope = theory.scope_of("no-ungatherable")
    assert scope is not None and scope.with_colours(2) is not None and scope.with_colours(1) is None
    monkeypatch.delitem(theory._SCOPES, "no-ungatherable")  # a paper that forgot it
    r = run_check(YARD, algorithm="go-to-target", scheduler="fsync", frames="compass")
    assert r["properties"]["no-ungatherable"] == {"holds": True} and "not_applicable" not in r


@pytest.fixture
def second_paper(monkeypatch):
    """A second paper's property, ``stuck-free`` (``final`` under another name), that it
    defines for robots with a common chirality or none (not a compass), and not for lights."""
    from dataclasses import replace

    from gather_verify.properties import registry
    from gather_verify.properties.builtin import FINAL

    theory.preconditions()  # the built-in theory first
    monkeypatch.setattr(theory, "_SCOPES", dict(theory._SCOPES))
    prop = registry.register(replace(FINAL, name="stuck-free"))
    theory.scope("stuck-free", frames=("all", "chirality"), frames_why="a compass tells them apart",
                 oblivious=True, lights_why="colours tell them apart")
    yield prop
    registry.unregister("stuck-free")


def test_check_leaves_out_a_second_papers_property_where_it_says(second_paper) -> None:
    r = run_check(YARD, algorithm="broken-stay", scheduler="fsync", frames="chirality")
    assert r["properties"]["stuck-free"]["holds"] is False  # checked where it applies
    r = run_check(YARD, algorithm="broken-stay", scheduler="fsync", frames="compass")
    assert "stuck-free" not in r["properties"]
    assert r["not_applicable"] == {
        "no-ungatherable": "U (Theorem 1) is for robots with no common orientation, "
                           "not --frames compass",
        "stuck-free": "a compass tells them apart, not --frames compass"}
    with pytest.raises(InvalidInput, match="^stuck-free does not apply under --frames compass: "
                       "a compass tells them apart$"):
        run_check(YARD, algorithm="broken-stay", scheduler="fsync", frames="compass",
                  properties=["stuck-free"])
    beacon = Configuration([(1, 1), (3, 2)], [(0, 0), (4, 0)], initial=True)
    r = run_check(beacon, algorithm="beacon", scheduler="fsync", lights="2")
    assert r["not_applicable"]["stuck-free"] == "colours tell them apart"
    with pytest.raises(InvalidInput, match="^stuck-free does not apply with --lights 2: colours"):
        run_check(beacon, algorithm="beacon", scheduler="fsync", lights="2",
                  properties=["stuck-free"])
    assert "stuck-free" in run_check(beacon, algorithm="beacon", scheduler="fsync",
                                     lights="1")["properties"]


def test_the_union_engine_leaves_it_out_as_check_does(second_paper) -> None:
    """The sweep's union engine asks the same registry: its rows equal each configuration's
    own check, and no row under a compass fails the property left out."""
    from gather_verify.sweeps.census import enumerate_configurations
    from gather_verify.sweeps.mclass import class_tasks, decide_class
    from gather_verify.sweeps.sweep import SweepSettings, configuration_key, verify_one

    for frames, fails in (("chirality", True), ("compass", False)):
        s = SweepSettings(robots=2, meeting=1, box=(3, 3), algorithm="broken-stay",
                          scheduler="async", frames=frames)
        items = list(enumerate(enumerate_configurations(2, 1, 3, 3, frames)))
        rows = [r for members in class_tasks(items, frames)
                for r in decide_class(s, members, configuration_key).rows]
        assert rows and any("final" in r["failing"] for r in rows)
        assert any("stuck-free" in r["failing"] for r in rows) is fails
        for r in rows:
            own = verify_one(s, r["index"], items[r["index"]][1])
            assert {**r, "seconds": 0} == {**own, "seconds": 0}


def test_a_scope_is_registered_once_with_its_reasons(monkeypatch) -> None:
    theory.preconditions()
    monkeypatch.setattr(theory, "_SCOPES", dict(theory._SCOPES))
    known = theory.scope_of("no-ungatherable")
    assert known is not None
    assert theory.scope("no-ungatherable", frames=known.frames, frames_why=known.frames_why,
                        oblivious=True, lights_why=known.lights_why) == known  # a reload
    with pytest.raises(ValueError, match="registered already"):
        theory.scope("no-ungatherable", frames=("all",), frames_why="another reason")
    with pytest.raises(ValueError, match="say why"):
        theory.scope("x", frames=("all",))


def test_the_sweep_tables_legend_is_the_preconditions(monkeypatch) -> None:
    """The line under the sweep's class table names what each precondition's NOT-APPLICABLE
    means, as its paper registered it; with none registered, only the ratio."""
    from gather_verify.sweeps.sweep import format_summary

    summary = {"total": 1, "classes": {"I13": 1}, "verdicts": {"I13": {"VERIFIED": 1}},
               "max_ratio": {}, "failing_properties": {}, "slowest": []}

    def legend() -> str:
        lines: list[str] = []
        format_summary(summary, lines.append)
        return lines[4]

    assert legend() == ("max ratio: the largest total moves / (D·n) of the class; "
                        "NOT-APPLICABLE: in U or UNCLASSIFIED, where the impossibility checks "
                        "apply (--force checks them)")
    theory.preconditions()
    monkeypatch.setattr(theory, "_PRECONDITIONS", [theory.Precondition(
        "three robots", lambda c, frames: None, "NOT-APPLICABLE: three robots")])
    assert legend() == ("max ratio: the largest total moves / (D·n) of the class; "
                        "NOT-APPLICABLE: three robots")
    monkeypatch.setattr(theory, "_PRECONDITIONS", [])
    assert legend() == "max ratio: the largest total moves / (D·n) of the class"


WANDER = Configuration([(0, 2), (2, 2)], [(0, 0), (3, 0), (1, 1), (2, 1)], initial=True)
"""broken-wander reaches U from here (no-ungatherable fails)."""


def test_the_paper_s_words_for_no_ungatherable_are_registered_by_the_paper(monkeypatch) -> None:
    """The reason a no-ungatherable violation gives, and why it holds from U, are the
    paper's words, registered with it: the built-in property says what the registry holds
    (another paper's words would be said instead), and names none of U's classes itself."""
    words = theory.words_of("no-ungatherable")
    assert words.message == "a configuration in U (I41/I42) is reached from one outside U"
    r = run_check(WANDER, algorithm="broken-wander", scheduler="fsync")
    assert (r["verdict"], r["property"], r["reason"]) == ("VIOLATED", "no-ungatherable",
                                                          words.message)
    r = run_check(IN_U, algorithm="go-to-target", scheduler="fsync", force=True)
    assert r["properties"]["no-ungatherable"]["reason"] == words.vacuous == \
        "initial configuration is in U"
    monkeypatch.setitem(theory._WORDS, "no-ungatherable", theory.Words(
        "no-ungatherable", "another paper's reason", "another paper's vacuity"))
    r = run_check(WANDER, algorithm="broken-wander", scheduler="fsync")
    assert r["reason"] == "another paper's reason"
    builtin = (ROOT / "gather_verify/properties/builtin.py").read_text()
    assert "I41" not in builtin and "I42" not in builtin
    with pytest.raises(ValueError, match="registered already"):
        theory.words("no-ungatherable", message="a third")
    with pytest.raises(KeyError, match="no theory registers the words of the property 'nope'"):
        theory.words_of("nope")
