"""``synthesize --minimum --lights A-B``: the least number of colours for which an algorithm
exists (SEMANTICS.md §10, §12), and ``report`` reading the stored ``--minimum`` tables.

Ooshita and Tixeuil: two myopic robots (visibility 1) explore a ring perpetually under
FSYNC with 2 colours, and not with 1. Every exists is a witness the ordinary checker
verifies, every none a certificate ``--verify`` accepts (and a broken one it rejects); the
answers are stored and reused only under the same settings and fingerprint."""

from __future__ import annotations

import json
import sqlite3
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("pysat", reason="synthesize needs python-sat (extra synth)")

from gather_verify.synthesis.certificate import verify_certificate  # noqa: E402
from gather_verify.world_check import run_world_check  # noqa: E402
from tests.test_synthesis import cli, one_line, rejected  # noqa: E402

MYOPIC = ["--minimum", "--world", "ring:5", "--robots", "0 1", "--visibility", "1",
          "--multiplicity", "global-weak", "--task", "exclusive-perpetual-exploration",
          "--scheduler", "fsync"]


def _least(tmp_path: Path, *more: str, code: int = 0) -> dict[str, Any]:
    run = cli(*MYOPIC, "--db", str(tmp_path / "min.sqlite"), "--json", *more)
    assert run.returncode == code, run.stderr
    return json.loads(run.stdout)


@pytest.fixture(scope="module")
def some(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict[str, Any]]:
    """The literature's point: from some initial colouring, 2 colours, not 1."""
    folder = tmp_path_factory.mktemp("some")
    return folder, _least(folder, "--lights", "1-3", "--colours", "some")


def test_two_myopic_robots_need_two_colours(some: tuple[Path, dict[str, Any]]) -> None:
    _, got = some
    assert got["resource"] == "colours"
    assert got["minimum"] == [{"world": "ring:5", "scheduler": "fsync", "least": "2"}]
    assert [(r["colours"], r["answer"]) for r in got["rows"]] == [(1, "none"), (2, "exists")]


def test_each_none_has_certificates_that_verify_and_the_witness_is_checked(
        some: tuple[Path, dict[str, Any]]) -> None:
    """1 colour: the one colouring 0 0 is none. 2 colours: 0 0 is none, and 0 1 has a
    witness that the ordinary checker verifies, every reduction off."""
    _, got = some
    one, two = got["rows"]
    (cert,) = one["files"]["certificates"]
    assert verify_certificate(cert)["instance"]["colours"] == "0 0"
    assert [verify_certificate(c)["instance"]["colours"] for c in two["files"]["certificates"]
            ] == ["0 0"]
    assert two["files"]["initial_colours"] == "0 1"
    again = run_world_check("ring:5", [0, 1], [], two["files"]["witness"], "fsync",
                            task="exclusive-perpetual-exploration", detection="global-weak",
                            visibility=1, lights="2", colours=[0, 1], reduction=False)
    assert again["verdict"] == "VERIFIED"
    # the same witness from the colouring it was not made for: not VERIFIED (it is a
    # witness for 0 1; 0 0 has no algorithm at all)
    other = run_world_check("ring:5", [0, 1], [], two["files"]["witness"], "fsync",
                            task="exclusive-perpetual-exploration", detection="global-weak",
                            visibility=1, lights="2", colours=[0, 0], reduction=False)
    assert other["verdict"] != "VERIFIED"


def _drop_branch(doc: dict[str, Any]) -> None:
    doc["tree"][1].pop()


def _other_colours(doc: dict[str, Any]) -> None:
    """The certificate of 0 0 claimed for 0 1, from which an algorithm exists."""
    doc["instance"]["colours"] = "0 1"
    for c in doc["instance"]["configurations"]:
        c["colours"] = [0, 1]


def _drop_event(doc: dict[str, Any]) -> None:
    cex = max(doc["counterexamples"], key=lambda c: len(c["events"]))
    cex["events"] = cex["events"][1:]  # the rest no longer follows from the start


@pytest.mark.parametrize("tamper", [_drop_branch, _other_colours, _drop_event])
def test_a_broken_certificate_of_one_colour_fails_verify(
        some: tuple[Path, dict[str, Any]], tmp_path: Path, tamper: Any) -> None:
    _, got = some
    path = Path(got["rows"][1]["files"]["certificates"][0])  # 2 colours, 0 0
    assert cli("--verify", str(path)).returncode == 0
    rejected(json.loads(path.read_text()), tamper, tmp_path)


def test_one_colouring_for_every_number_of_colours(tmp_path: Path) -> None:
    """``--colours 0 1`` from 2 colours on: 2 suffice. All at 0 (the default): a mirror pair
    FSYNC keeps symmetric, so no number of colours helps (``>B``), each none certified."""
    got = _least(tmp_path, "--lights", "2-3", "--colours", "0 1")
    assert got["minimum"][0]["least"] == "2"
    got = _least(tmp_path, "--lights", "1-2", code=0)
    assert got["minimum"][0]["least"] == ">2"
    for row in got["rows"]:
        assert row["answer"] == "none"
        assert all(verify_certificate(c)["holds"] for c in row["files"]["certificates"])


def test_a_count_of_robots_every_class_at_colour_0(tmp_path: Path) -> None:
    run = cli("--minimum", "--world", "ring:4", "--robots", "2", "--lights", "1-2",
              "--task", "gathering", "--multiplicity", "global-weak", "--scheduler", "fsync",
              "--db", str(tmp_path / "m.sqlite"), "--json")
    assert run.returncode == 0, run.stderr
    got = json.loads(run.stdout)
    assert got["minimum"][0]["least"] == ">2"  # two robots an odd distance apart stay mirrored


def test_unknown_below_gives_a_question_mark_and_exit_3(tmp_path: Path) -> None:
    got = _least(tmp_path, "--lights", "1-2", "--colours", "some", "--max-candidates", "1",
                 code=3)
    assert got["minimum"][0]["least"] == ">2?"
    assert {r["answer"] for r in got["rows"]} == {"unknown"}
    assert "max-candidates" in got["rows"][0]["limit"]


def test_a_witness_the_checker_rejects_is_our_bug(tmp_path: Path, monkeypatch: Any) -> None:
    from gather_verify.synthesis import witness

    monkeypatch.setattr(witness, "check_witness", lambda spec, inst, s: [
        {"verdict": "VIOLATED", "robots": [0, 1], "property": "planted", "reason": "planted",
         "states": 1}])
    run = cli(*MYOPIC, "--lights", "2-2", "--colours", "0 1", "--db",
              str(tmp_path / "m.sqlite"))
    assert run.returncode == 70 and "bug of gather-verify's synthesis" in one_line(run)


# -- stored, and reused only under the same settings and fingerprint -------------------------

def _searches(monkeypatch: Any) -> list[int]:
    from gather_verify.synthesis import search

    calls: list[int] = []
    real = search.synthesize

    def counted(*args: Any, **kwargs: Any) -> Any:
        calls.append(1)
        return real(*args, **kwargs)

    monkeypatch.setattr(search, "synthesize", counted)
    return calls


def test_rows_are_reused_only_when_the_fingerprint_matches(tmp_path: Path,
                                                           monkeypatch: Any) -> None:
    from gather_verify import fingerprint

    calls = _searches(monkeypatch)
    args = ("--lights", "1-2", "--colours", "some")
    first = _least(tmp_path, *args)
    assert len(calls) == 3  # 1 colour: 0 0; 2 colours: 0 0, then 0 1 exists
    assert _least(tmp_path, *args) == first and len(calls) == 3  # every row reused
    # the task changes: the stored rows are another question's, never reused
    changed = cli(*[a if a != "exclusive-perpetual-exploration" else "gathering"
                    for a in MYOPIC], "--db", str(tmp_path / "min.sqlite"), "--json", *args)
    assert changed.returncode in (0, 3), changed.stderr
    assert len(calls) > 3
    # each question's files keep their own names: the first run's are still its own
    cert = first["rows"][0]["files"]["certificates"][0]
    assert verify_certificate(cert)["instance"]["task"] == "exclusive-perpetual-exploration"
    done = len(calls)
    # gather-verify's own source changes: computed again
    monkeypatch.setattr(fingerprint, "own_digest", lambda: "an-edited-verifier")
    assert _least(tmp_path, *args)["minimum"] == first["minimum"]
    assert len(calls) == done + 3
    db = sqlite3.connect(tmp_path / "min.sqlite")
    classes = {c for (c,) in db.execute("SELECT class FROM results")}
    db.close()
    assert classes == {None}  # the world is the sweep's setting, not a row's class


# -- bad input: one line, exit 2 ---------------------------------------------------------------

@pytest.mark.parametrize(("args", "words"), [
    (["--lights", "3-1"], "empty"),
    (["--lights", "0-2"], "at least 1 colour"),
    (["--lights", "1-x"], "range A-B"),
    (["--lights", "1-65"], "at most 64"),
    (["--lights", "1-2:external"], "external"),
    (["--lights", "1-2", "--colours", "0 1"], "needs more colours than 1"),
    (["--lights", "1-2", "--colours", "0"], "one colour per robot"),
    (["--lights", "1-2", "--robots", "1-2"], "not both"),
    (["--lights", "1-2", "--robots", "2", "--colours", "some"], "one configuration"),
])
def test_bad_input_is_one_line_and_exit_2(tmp_path: Path, args: list[str], words: str) -> None:
    run = cli(*MYOPIC, "--db", str(tmp_path / "m.sqlite"), *args)
    assert run.returncode == 2, (run.returncode, run.stderr)
    assert words in one_line(run)


@pytest.mark.parametrize("args", [
    ["--minimum", "--world", "grid", "--box", "2x2", "--meeting", "1", "--robots", "2",
     "--lights", "1-2"],
    ["--minimum", "--world", "ring:5", "--robots", "1-2", "--colours", "0 1"],
])
def test_colours_where_they_cannot_be_asked(tmp_path: Path, args: list[str]) -> None:
    run = cli(*args, "--db", str(tmp_path / "m.sqlite"))
    assert run.returncode == 2, (run.returncode, run.stderr)
    assert "colour" in one_line(run)


# -- report reads the stored tables ---------------------------------------------------------

def _report(*args: str) -> tuple[int, str]:
    import contextlib
    import io

    from gather_verify.cli import main

    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = main(["report", *args])
    return code, out.getvalue()


def test_report_prints_the_stored_table(some: tuple[Path, dict[str, Any]]) -> None:
    folder, got = some
    code, text = _report("--db", str(folder / "min.sqlite"))
    assert code == 0
    assert "least colours with an algorithm (colours 1-2 stored" in text
    assert text.splitlines()[-2].split() == ["ring:5", "2"]
    code, text = _report("--db", str(folder / "min.sqlite"), "--json")
    (table,) = json.loads(text)["minimum"]
    assert table["resource"] == "colours" and table["least"] == got["minimum"]
    assert [(r["colours"], r["answer"]) for r in table["rows"]] == [(1, "none"), (2, "exists")]
    assert json.loads(text)["sweeps"] == []
    code, text = _report("--db", str(folder / "min.sqlite"), "--workers-curve", "1,2")
    assert code == 0 and "no stored rows" in text  # its answers are no sweep's tasks


def test_report_reads_an_older_store_of_the_least_robots(tmp_path: Path) -> None:
    """A store written before colours were counted: no ``minimum`` setting, the world in each
    row's class. Its table is the least number of robots; a gap is a question mark."""
    from gather_verify.sweeps.store import Store

    store = Store(tmp_path / "old.sqlite")
    for world, answers in (("ring:4", ["none", "none", "exists"]),
                           ("ring:5", ["none", "unknown", "exists"])):
        sweep = store.sweep_id({"command": "synthesize --minimum", "world": world,
                                "scheduler": "ssync", "task": "gathering",
                                "gather_verify": "an-older-one"})
        store.add(sweep, [{"key": f"k={k}", "index": k, "class": world, "verdict": a,
                           "n": k, "trace": {}, "seconds": 0.0}
                          for k, a in enumerate(answers, start=1)])
    sweep = store.sweep_id({"command": "synthesize --minimum", "world": "ring:6",
                            "scheduler": "ssync", "task": "gathering",
                            "gather_verify": "an-older-one"})
    store.add(sweep, [{"key": f"k={k}", "index": k, "class": "ring:6", "verdict": "none",
                       "n": k, "trace": {}, "seconds": 0.0} for k in (1, 3)])
    store.close()
    code, text = _report("--db", str(tmp_path / "old.sqlite"))
    assert code == 0
    assert "least robots with an algorithm (robots 1-3 stored" in text
    assert "older code" in text
    lines = text.splitlines()
    at = lines.index(next(line for line in lines if line.split() == ["ssync"]))
    assert [line.split() for line in lines[at + 1:at + 4]] == [
        ["ring:4", "3"], ["ring:5", "3?"], ["ring:6", ">3?"]]
