"""``synthesize`` (SEMANTICS.md §12): every exists witness passes the ordinary checker with
every reduction off, every none certificate passes ``--verify`` and a broken one fails it,
a tiny limit gives unknown (never none), bad input is one line with exit 2, and the answer
and the view keys do not change under the world's symmetries."""

from __future__ import annotations

import ast
import contextlib
import copy
import io
import json
import os
import subprocess
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

pytest.importorskip("pysat", reason="synthesize needs python-sat (extra synth)")

from gather_verify.cli import main  # noqa: E402
from gather_verify.synthesis import viewkey  # noqa: E402
from gather_verify.synthesis.certificate import (  # noqa: E402
    CertificateError,
    verify_certificate,
)
from gather_verify.synthesis.search import synthesize  # noqa: E402
from gather_verify.synthesis.views import Views, make_instance  # noqa: E402
from gather_verify.world_check import run_world_check  # noqa: E402


def cli(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    """The command in this process (the same ``main`` the console script runs)."""
    out, err = io.StringIO(), io.StringIO()
    here = os.getcwd()
    try:
        if cwd is not None:
            os.chdir(cwd)
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main(["synthesize", *args])
    finally:
        os.chdir(here)
    return subprocess.CompletedProcess(args, code, out.getvalue(), err.getvalue())


def one_line(run: subprocess.CompletedProcess[str]) -> str:
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1, run.stderr
    assert "Traceback" not in run.stderr
    return lines[0]


def rejected(certificate: dict[str, Any], tamper: Callable[[dict[str, Any]], None],
             tmp_path: Path) -> Path:
    """A copy of ``certificate`` broken by ``tamper``, written to a file that ``--verify``
    must reject (exit 1, one line): its path."""
    doc = copy.deepcopy(certificate)
    tamper(doc)
    path = tmp_path / "broken.json"
    path.write_text(json.dumps(doc))
    run = cli("--verify", str(path))
    assert run.returncode == 1, (run.returncode, run.stderr)
    assert one_line(run).startswith("certificate REJECTED")
    return path


# -- exists: the witness, checked by the ordinary checker -----------------------------------

EXISTS = [
    ("ring:6", "0 2", "fsync", "gathering", ["--multiplicity", "global-weak"]),
    ("ring:5", "3", "fsync", "gathering", ["--multiplicity", "global-weak"]),
    ("ring:5", "2", "async", "exclusive-perpetual-exploration", ["--frames", "chirality"]),
    ("grid:2x2", "2", "ssync", "gathering-on-meeting-nodes",
     ["--meeting", "0,0", "--multiplicity", "none"]),
    ("ring:5", "3", "fsync", "exploration-with-stop", ["--multiplicity", "global-weak"]),
    ("ring:4", "2", "round-robin", "gathering", ["--multiplicity", "global-weak"]),
]


@pytest.mark.parametrize(("world", "robots", "scheduler", "task", "more"), EXISTS)
def test_exists_witness_passes_the_ordinary_checker(tmp_path: Path, world: str, robots: str,
                                                    scheduler: str, task: str,
                                                    more: list[str]) -> None:
    witness = tmp_path / "alg.py"
    run = cli("--world", world, "--robots", robots, "--scheduler", scheduler, "--task", task,
              *more, "--witness", str(witness), "--json")
    assert run.returncode == 0, run.stderr
    report = json.loads(run.stdout)
    assert report["answer"] == "exists"
    assert report["checker"] == {"verdicts": ["VERIFIED"], "reductions": "off",
                                 "states": report["checker"]["states"]}
    assert report["witness"] == f"{witness}:Synthesized" and "seconds" not in report
    assert imports_first(witness)
    # the file stands on its own: the plain checker loads it and verifies it again
    inst = make_instance(world, robots, _opt(more, "--meeting", ""), scheduler, task,
                         _opt(more, "--multiplicity", "local-weak"),
                         _opt(more, "--frames", "all"))
    for nodes, _ in inst.configurations:
        got = run_world_check(world, list(nodes), sorted(inst.meeting), report["witness"],
                              scheduler, task=task, detection=inst.detection,
                              frames=inst.frames, reduction=False)
        assert got["verdict"] == "VERIFIED", got["reason"]


def imports_first(path: Path) -> bool:
    """A witness file's imports come before its code, the standard library's before
    gather-verify's, as import-order linters want."""
    body = ast.parse(path.read_text(encoding="utf-8")).body[1:]  # after the docstring
    kinds = [isinstance(node, (ast.Import, ast.ImportFrom)) for node in body]
    ours = [(node.module or "").startswith("gather_verify") if isinstance(node, ast.ImportFrom)
            else node.names[0].name.startswith("gather_verify")
            for node in body if isinstance(node, (ast.Import, ast.ImportFrom))]
    return (any(kinds) and kinds == sorted(kinds, reverse=True) and ours == sorted(ours))


def _opt(more: list[str], name: str, default: str) -> str:
    return more[more.index(name) + 1] if name in more else default


def test_witness_is_a_function_of_the_view_up_to_isomorphism(tmp_path: Path) -> None:
    """Every frame of one view gets one key, and the answers, mapped back, are the answer's
    orbit under the view's symmetries: the same move set the synthesis computed."""
    witness = tmp_path / "w.py"
    run = cli("--world", "ring:7", "--robots", "3", "--scheduler", "fsync", "--task",
              "gathering", "--multiplicity", "global-weak", "--witness", str(witness))
    assert run.returncode in (0, 1), run.stderr
    if run.returncode == 1:
        pytest.skip("no witness on this instance")
    import importlib.util

    from gather_verify.worlds.view import WorldView

    spec = importlib.util.spec_from_file_location("w", witness)
    module = importlib.util.module_from_spec(spec)  # type: ignore[arg-type]
    spec.loader.exec_module(module)  # type: ignore[union-attr]
    inst = make_instance("ring:7", "3", "", "fsync", "gathering", "global-weak")
    views = Views(inst)
    algo = module.Synthesized()
    from collections import Counter

    for robots, _ in inst.configurations:
        counts = Counter(robots)
        for v in robots:
            frames = inst.world.frames(v, None, "all")
            keys = set()
            moves = set()
            for frame in frames:
                view = WorldView(inst.world, counts, frozenset(), v, frame, "global-weak")
                keys.add(viewkey.key_text(viewkey.canonical(
                    views.group, viewkey.observe(view, "global-weak", 1, "full"))[0]))
                moves.add(frame.inverse[algo.decide(view)])
            assert len(keys) == 1
            k, acts = views.occurrence(tuple(sorted((u, 0) for u in robots)), v, 0)
            option = module.TABLE[keys.pop()]
            o = views.options[k].index(option)
            assert moves == {d for d, _ in acts[o]}


# -- none: the certificate, re-checked, and broken on purpose ------------------------------

NONE = [
    ("ring:6", "2", "ssync", "gathering", ["--multiplicity", "global-weak"]),
    ("ring:6", "0 3", "async", "gathering", ["--multiplicity", "global-strong"]),
    ("ring:6", "2", "async", "exclusive-perpetual-exploration", []),
    ("ring:4", "2", "fsync", "exclusive-perpetual-exploration", ["--lights", "2",
                                                                  "--visibility", "1"]),
    ("ring:6", "2", "async", "exploration-with-stop", ["--multiplicity", "global-weak"]),
]


@pytest.mark.parametrize(("world", "robots", "scheduler", "task", "more"), NONE)
def test_none_certificate_passes_verify(tmp_path: Path, world: str, robots: str,
                                        scheduler: str, task: str, more: list[str]) -> None:
    cert = tmp_path / "c.json"
    run = cli("--world", world, "--robots", robots, "--scheduler", scheduler, "--task", task,
              *more, "--certificate", str(cert), "--witness", str(tmp_path / "w.py"), "--json")
    assert run.returncode == 1, run.stderr
    report = json.loads(run.stdout)
    assert report["answer"] == "none" and report["certificate"] == str(cert)
    assert report["views"] > 0 and report["candidates"] > 0
    again = cli("--verify", str(cert))
    assert again.returncode == 0, again.stderr
    assert again.stdout.startswith("certificate holds: none")


@pytest.fixture(scope="module")
def certificate(tmp_path_factory: pytest.TempPathFactory) -> dict:
    path = tmp_path_factory.mktemp("cert") / "c.json"
    run = cli("--world", "ring:6", "--robots", "2", "--scheduler", "ssync", "--task",
              "gathering", "--multiplicity", "global-weak", "--certificate", str(path))
    assert run.returncode == 1, run.stderr
    return json.loads(path.read_text())


def _break_event(doc: dict) -> None:
    cex = max(doc["counterexamples"], key=lambda c: len(c["events"]))
    cex["events"] = cex["events"][:-1]  # a cycle that no longer closes


def _break_move(doc: dict) -> None:
    for cex in doc["counterexamples"]:
        for event in cex["events"]:
            if event["moves"]:
                i, a, _ = event["moves"][0]
                event["moves"][0] = [i, a, (a + 3) % 6]  # not a neighbour
                return


def _break_leaf(doc: dict) -> None:
    def leaves(node, path=()):
        if isinstance(node, int):
            yield path
            return
        for j, child in enumerate(node[1]):
            yield from leaves(child, (*path, j))
    first = next(leaves(doc["tree"]))
    node = doc["tree"]
    for j in first[:-1]:
        node = node[1][j]
    leaf = node[1][first[-1]]
    others = [j for j in range(len(doc["counterexamples"])) if j != leaf]
    node[1][first[-1]] = others[0]


def _break_branch(doc: dict) -> None:
    doc["tree"][1].pop()


def _break_scheduler(doc: dict) -> None:
    doc["instance"]["scheduler"] = "centralized"  # no counterexample is a run of that one


def _break_property(doc: dict) -> None:
    for cex in doc["counterexamples"]:
        cex["property"] = "termination" if cex["property"] != "termination" else \
            "gathered-when-final"


def _break_configuration(doc: dict) -> None:
    doc["instance"]["configurations"] = doc["instance"]["configurations"][:1]


@pytest.mark.parametrize("tamper", [_break_event, _break_move, _break_leaf, _break_branch,
                                    _break_scheduler, _break_property, _break_configuration])
def test_a_broken_certificate_fails_verify(tmp_path: Path, certificate: dict, tamper) -> None:
    path = rejected(certificate, tamper, tmp_path)
    with pytest.raises(CertificateError):
        verify_certificate(str(path))


def test_not_a_certificate_is_bad_input(tmp_path: Path) -> None:
    path = tmp_path / "x.json"
    path.write_text("{}")
    run = cli("--verify", str(path))
    assert run.returncode == 2 and "not a synthesis certificate" in one_line(run)


# -- unknown: a limit, named, never none ----------------------------------------------------

def test_a_tiny_limit_says_unknown_and_names_it(tmp_path: Path) -> None:
    run = cli("--world", "ring:6", "--robots", "2", "--scheduler", "ssync", "--task",
              "gathering", "--multiplicity", "global-weak", "--max-candidates", "1",
              "--certificate", str(tmp_path / "c.json"), "--json")
    assert run.returncode == 3, run.stderr
    report = json.loads(run.stdout)
    assert report["answer"] == "unknown" and report["limit"] == "max-candidates"
    assert report["certificate"] is None and not (tmp_path / "c.json").exists()
    run = cli("--world", "ring:6", "--robots", "2", "--scheduler", "ssync", "--task",
              "gathering", "--max-states", "3", "--certificate", str(tmp_path / "c.json"))
    assert run.returncode == 3 and "max-states" in run.stdout


# -- bad input: one line, exit 2 --------------------------------------------------------------

@pytest.mark.parametrize(("args", "words"), [
    (["--world", "grid", "--robots", "2"], "--meeting"),
    (["--robots", "2"], "--world"),
    (["--world", "ring:6"], "--robots"),
    (["--world", "ring:6", "--robots", "2", "--lights", "2:external"], "external"),
    (["--world", "ring:6", "--robots", "2", "--task", "nope"], "unknown task"),
    (["--world", "ring:6", "--robots", "0 0"], "distinct"),
    (["--world", "ring:6", "--robots", "9"], "between 1 and 6"),
    (["--world", "ring:6", "--robots", "2", "--task", "gathering-on-meeting-nodes"],
     "meeting"),
    (["--world", "ring:6", "--robots", "2", "--scheduler", "nope"], "unknown scheduler"),
    (["--world", "ring:6", "--robots", "2", "--multiplicity", "nope"], "multiplicity"),
    (["--world", "ring:6", "--robots", "2", "--witness", "x.txt"], ".py"),
    (["--world", "ring:6", "--robots", "3-2", "--minimum"], "A <= B"),
    (["--world", "ring:6", "--robots", "2", "--minimum", "--scheduler", "fsync,nope"],
     "unknown scheduler"),
    (["--world", "ring:6", "--robots", "2", "--colours", "0 1"], "one configuration"),
    (["--world", "ring:6", "--robots", "0 1", "--lights", "2", "--colours", "0 2"],
     "each in 0..1"),
])
def test_bad_input_is_one_line_and_exit_2(tmp_path: Path, args: list[str], words: str) -> None:
    run = cli(*args, cwd=tmp_path)
    assert run.returncode == 2, (run.returncode, run.stderr)
    assert words in one_line(run)


def test_a_graph_file_and_a_torus(tmp_path: Path) -> None:
    """Aut(G) of a graph file keys its views (the pendant node breaks the square's
    symmetry: two robots gather); on the 3 x 3 torus two robots never do under SSYNC."""
    graph = tmp_path / "g.edgelist"
    graph.write_text("a b\nb c\nc d\nd a\nd e\n")
    run = cli("--world", f"graph:{graph}", "--robots", "2", "--scheduler", "async", "--task",
              "gathering", "--multiplicity", "global-weak", "--witness",
              str(tmp_path / "w.py"), "--json")
    assert run.returncode == 0, run.stderr
    assert json.loads(run.stdout)["checker"]["verdicts"] == ["VERIFIED"]
    cert = tmp_path / "t.json"
    run = cli("--world", "torus:3x3", "--robots", "2", "--scheduler", "ssync", "--task",
              "gathering", "--multiplicity", "global-weak", "--certificate", str(cert))
    assert run.returncode == 1, run.stderr
    assert verify_certificate(str(cert))["holds"]


def test_a_myopic_graph_file_is_refused(tmp_path: Path) -> None:
    graph = tmp_path / "g.edgelist"
    graph.write_text("a b\nb c\nc d\nd a\nd e\n")
    run = cli("--world", f"graph:{graph}", "--robots", "2", "--visibility", "1",
              "--task", "gathering", cwd=tmp_path)
    assert run.returncode == 2 and "not up to isomorphism" in one_line(run)


# -- invariance under the world's symmetries -------------------------------------------------

def test_answer_and_keys_are_invariant_under_the_world_symmetries() -> None:
    """Moving the initial configuration by any automorphism of the ring changes neither the
    answer nor the keys of the views met (the keys are up to isomorphism)."""
    base = (0, 1, 3)
    answers = set()
    for p in make_instance("ring:7", "0 1 3", "", "fsync", "gathering").world.automorphisms:
        robots = " ".join(str(p[v]) for v in base)
        inst = make_instance("ring:7", robots, "", "fsync", "gathering", "global-weak")
        views = Views(inst)
        got = synthesize(inst, views=views, max_seconds=60)
        answers.add((got.answer, got.views, frozenset(views.texts)))
    assert len(answers) == 1
    assert next(iter(answers))[0] in ("exists", "none")


def test_grid_keys_are_invariant_under_the_grid_symmetries() -> None:
    inst = make_instance("grid:3x3", "0,0 1,2", "", "async", "gathering", "global-strong")
    views = Views(inst)
    world = inst.world
    robots = [world.index[(0, 0)], world.index[(1, 2)]]
    for p in world.automorphisms:
        moved = [p[v] for v in robots]
        seen = tuple(sorted((v, 0) for v in moved))
        keys = sorted(views.texts[views.occurrence(seen, v, 0)[0]] for v in moved)
        seen0 = tuple(sorted((v, 0) for v in robots))
        assert keys == sorted(views.texts[views.occurrence(seen0, v, 0)[0]] for v in robots)



def test_a_new_world_says_how_its_frames_act_and_synthesis_needs_nothing_else() -> None:
    """A world the synthesis has never heard of (a cycle that is no ``Ring``) keys its views
    through its own :meth:`~gather_verify.worlds.base.World.frame_group`: the same answers
    and view keys as ``ring:N``, and no line of the synthesis names it. A world that gives
    no group is refused in one line."""
    import dataclasses

    from gather_verify.errors import InvalidInput
    from gather_verify.worlds.base import World

    class Necklace(World):
        kind = "necklace"

        def __init__(self, n: int):
            self.n = n
            super().__init__(f"necklace:{n}", range(n), ((v, (v + 1) % n) for v in range(n)))

        def frame_labels(self, v, ball, frames):
            directions = (1, -1) if frames == "all" else (1,)
            return [{u: (s * (u - v)) % self.n for u in ball} for s in directions]

        def frame_group(self, frames, visibility):
            return ["ring", self.n, [1, -1] if frames == "all" else [1]]

    for robots, scheduler in (("0 1 3", "fsync"), ("0 2", "ssync")):
        ring = make_instance("ring:7", robots, "", scheduler, "gathering", "global-weak")
        necklace = dataclasses.replace(ring, world=Necklace(7))
        got = []
        for inst in (ring, necklace):
            views = Views(inst)
            result = synthesize(inst, views=views, max_seconds=60)
            got.append((result.answer, result.views, tuple(views.texts)))
        assert got[0] == got[1] and got[0][0] in ("exists", "none")

    class Blank(Necklace):
        def frame_group(self, frames, visibility):
            return World.frame_group(self, frames, visibility)

    with pytest.raises(InvalidInput, match="does not know the frames of necklace:7"):
        Views(dataclasses.replace(ring, world=Blank(7)))

# -- a witness the checker rejects is our bug, said so -------------------------------------

def test_a_witness_the_checker_rejects_is_reported_as_our_bug(tmp_path: Path, monkeypatch
                                                             ) -> None:
    from gather_verify.synthesis import witness

    def rejected(spec, inst, max_seconds):  # noqa: ANN001, ANN202
        return [{"verdict": "VIOLATED", "robots": [0, 2], "property": "termination",
                 "reason": "planted", "states": 1}]

    monkeypatch.setattr(witness, "check_witness", rejected)
    run = cli("--world", "ring:6", "--robots", "0 2", "--scheduler", "fsync", "--task",
              "gathering", "--multiplicity", "global-weak", "--witness",
              str(tmp_path / "w.py"))
    assert run.returncode == 70
    assert "bug of gather-verify's synthesis" in one_line(run)


# -- minimum resources, stored and resumed ----------------------------------------------------

def test_minimum_prints_the_least_count_stores_it_and_resumes(tmp_path: Path) -> None:
    from gather_verify.sweeps.store import Store

    db = tmp_path / "min.sqlite"
    args = ["--minimum", "--world", "ring:4-5", "--robots", "1-3", "--scheduler",
            "fsync,ssync", "--task", "exclusive-perpetual-exploration", "--db", str(db),
            "--json"]
    first = cli(*args)
    assert first.returncode == 0, first.stderr
    got = json.loads(first.stdout)
    least = {(r["world"], r["scheduler"]): r["least"] for r in got["minimum"]}
    assert least == {("ring:4", "fsync"): ">3", ("ring:4", "ssync"): ">3",
                     ("ring:5", "fsync"): "3", ("ring:5", "ssync"): ">3"}
    for row in got["rows"]:  # every answer has its file, and a none re-checks
        if row["answer"] == "none":
            assert verify_certificate(row["files"]["certificate"])["holds"]
        else:
            assert row["answer"] == "exists" and Path(row["files"]["witness"].rsplit(":", 1)[0]
                                                      ).is_file()
    store = Store(db)
    stored = sum(len(store.results(i)) for i, _ in store.sweeps())
    store.close()
    assert stored == len(got["rows"]) == 3 + 3 + 3 + 3
    again = cli(*args)  # resumed: the same answers, from the store
    assert again.returncode == 0 and json.loads(again.stdout) == got


# -- keys are up to isomorphism: Hypothesis over worlds, capabilities and symmetries ---------

WORLDS = ["ring:5", "ring:6", "grid:3x2", "grid:3x3", "torus:3x3"]


@settings(max_examples=60, deadline=None)
@given(world=st.sampled_from(WORLDS), data=st.data(),
       detection=st.sampled_from(["none", "local-weak", "global-strong"]),
       frames=st.sampled_from(["all", "chirality"]),
       visibility=st.sampled_from([None, 1]), lights=st.sampled_from([None, "2"]))
def test_keys_and_move_sets_follow_the_symmetries(world: str, data, detection: str,
                                                  frames: str, visibility, lights) -> None:
    """For any configuration and any symmetry p of the world under the frames, the robot on
    p(v) in p(C) has the key of the robot on v in C, and each option's actions move by p."""
    inst = make_instance(world, "1", "", "fsync", "gathering", detection, frames, visibility,
                         lights)
    views = Views(inst)
    w = inst.world
    n = data.draw(st.integers(1, 3))
    nodes = data.draw(st.lists(st.integers(0, w.size - 1), min_size=n, max_size=n))
    colours = data.draw(st.lists(st.integers(0, inst.lights.colours - 1), min_size=n,
                                 max_size=n))
    p = data.draw(st.sampled_from(w.symmetries(frames)))
    seen = tuple(sorted(zip(nodes, colours, strict=True)))
    moved = tuple(sorted((p[v], c) for v, c in seen))
    for v, c in set(seen):
        k, acts = views.occurrence(seen, v, c)
        k2, acts2 = views.occurrence(moved, p[v], c)
        assert views.texts[k] == views.texts[k2]
        assert [frozenset((p[d], col) for d, col in a) for a in acts] == list(acts2)


# -- round-robin: the safety search of terminating exploration is reduced --------------------

ROUND_ROBIN_EXPLORATION = [
    ("ring:4", "2", ["--frames", "chirality", "--lights", "2"]),  # exists
    ("ring:5", "2", []),  # none
    ("grid:2x3", "2", []),  # none
]


@pytest.mark.parametrize(("world", "robots", "more"), ROUND_ROBIN_EXPLORATION)
def test_round_robin_exploration_reduces_and_answers_as_unreduced(tmp_path: Path, monkeypatch,
                                                                 world: str, robots: str,
                                                                 more: list[str]) -> None:
    """Under round-robin the safety search of exploration-with-stop reduces, as the checker
    does (robots relabelled with the order, symmetries moving nodes only): the answer is that
    of the same synthesis with that search unreduced; a none certificate verifies, an exists
    witness passes the checker with every reduction off."""
    from gather_verify.synthesis import search as synthesis_search
    from gather_verify.synthesis.certificate import write_certificate
    from gather_verify.synthesis.search import certificate_stats
    from gather_verify.synthesis.witness import check_witness, write_witness

    real = synthesis_search.search
    reduced: list[bool] = []

    def recording(*args: Any, **kwargs: Any) -> Any:
        s = real(*args, **kwargs)
        if kwargs.get("visits"):
            reduced.append(s.reduced)
        return s

    def unreduced(*args: Any, **kwargs: Any) -> Any:
        return real(*args, **{**kwargs, "anonymity": False, "symmetries": ()})

    got: list[str] = []
    for wrapper in (recording, unreduced):
        monkeypatch.setattr(synthesis_search, "search", wrapper)
        inst = make_instance(world, robots, "", "round-robin", "exploration-with-stop",
                             _opt(more, "--multiplicity", "local-weak"),
                             _opt(more, "--frames", "all"),
                             lights=_opt(more, "--lights", "1"))
        views = Views(inst)
        result = synthesize(inst, views=views, max_seconds=120)
        assert result.answer in ("exists", "none"), result.limit
        got.append(result.answer)
        if wrapper is recording:
            assert reduced and all(reduced)  # the reduced search ran, and reduced
            if result.answer == "none":
                cert = tmp_path / "c.json"
                write_certificate(str(cert), inst, views, result.counterexamples,
                                  result.literals, result.tree, certificate_stats(result))
                assert verify_certificate(str(cert))["holds"]
            else:
                spec = write_witness(str(tmp_path / "w.py"), inst, views, result.table)
                assert [r["verdict"] for r in check_witness(spec, inst, 60)] == \
                    ["VERIFIED"] * len(inst.configurations)
    assert got[0] == got[1]
