"""Sweeps of finite worlds: the census up to the frames' symmetries, the verdict of each
class equal to every member's own check, resume, and one line for bad input."""

from __future__ import annotations

import itertools
import json
import subprocess
import sys

import pytest

from gather_verify.cli import main
from gather_verify.sweeps.world_census import world_configurations
from gather_verify.world_check import run_world_check
from gather_verify.worlds import get_world

CLI = [sys.executable, "-m", "gather_verify"]


def orbits(world_name: str, k: int, m: int, frames: str) -> int:
    """Classes counted the plain way: the orbits of every configuration under the group."""
    w = get_world(world_name)
    seen, count = set(), 0
    for robots in itertools.combinations(range(w.size), k):
        for meeting in itertools.combinations(range(w.size), m):
            if (robots, meeting) in seen:
                continue
            count += 1
            for p in w.symmetries(frames):
                seen.add((tuple(sorted(p[v] for v in robots)),
                          tuple(sorted(p[v] for v in meeting))))
    return count


@pytest.mark.parametrize("world_name", ["ring:6", "ring:7", "grid:3x3", "torus:3x3"])
@pytest.mark.parametrize("frames", ["all", "chirality", "compass"])
def test_census_counts_the_orbits(world_name: str, frames: str) -> None:
    w = get_world(world_name)
    for k, m in ((2, 0), (2, 1), (3, 1)):
        assert len(list(world_configurations(w, k, m, frames))) == orbits(world_name, k, m,
                                                                            frames)



@pytest.mark.parametrize("world_name", ["ring:6", "grid:3x3", "torus:3x3"])
@pytest.mark.parametrize("frames", ["all", "chirality", "compass"])
def test_census_with_colours_is_the_world_s_canonical_form(world_name: str, frames: str) -> None:
    """With lights, the census keeps each class of (robots, colours, meeting nodes) by its
    least member under the world's own canonical form (``World.canonical`` with the colours):
    each kept configuration is its canonical form, every configuration's canonical form is
    kept, and the colours never move with the symmetries."""
    w = get_world(world_name)
    kept = {(c.robots, c.colours, c.meeting)
            for c in world_configurations(w, 2, 1, frames, colours=2)}
    for robots in itertools.combinations(range(w.size), 2):
        for meeting in itertools.combinations(range(w.size), 1):
            for lit in itertools.product(range(2), repeat=2):
                least, least_meeting = w.canonical(robots, meeting, frames, colours=lit)
                nodes = tuple(v for v, _ in least)
                assert (nodes, tuple(c for _, c in least), least_meeting) in kept
                assert sorted(lit) == sorted(c for _, c in least)
    assert all(w.canonical(r, m, frames, colours=c) == (tuple(zip(r, c, strict=True)), m)
               for r, c, m in kept)


@pytest.mark.parametrize("frames", ["all", "chirality", "compass"])
def test_each_class_verdict_is_every_members_verdict(tmp_path, frames: str, capsys) -> None:  # noqa: ANN001
    """A direction-reading algorithm on rings: a sweep row stands for every member of its class."""
    db = tmp_path / "r.sqlite"
    code = main(["sweep", "--world", "ring:5-6", "--robots", "2-3", "--meeting",
                 "0", "--algorithm", "broken-ring-explore", "--scheduler", "ssync",
                 "--task", "exclusive-perpetual-exploration", "--frames", frames,
                 "--db", str(db), "--workers", "1", "--json"])
    assert code in (0, 1), capsys.readouterr().err
    from gather_verify.sweeps.store import Store

    store = Store(db, read_only=True)
    rows = [r for sweep, _ in store.sweeps() for r in store.results(sweep)]
    store.close()
    assert rows
    for row in rows:
        w = get_world(row["class"])
        robots = [w.node_from_json(v) for v in row["robots"]]
        for p in w.automorphisms:  # every image, allowed or not, of the symmetries' orbit
            image = [p[v] for v in robots]
            if p not in w.symmetries(frames):
                continue
            got = run_world_check(w, image, [], "broken-ring-explore", "ssync",
                                  task="exclusive-perpetual-exploration", frames=frames)
            assert got["verdict"] == row["verdict"], (row["robots"], image)


def test_a_world_sweep_resumes_and_reports_each_size(tmp_path) -> None:  # noqa: ANN001
    db = str(tmp_path / "w.sqlite")
    args = [*CLI, "sweep", "--world", "ring:5-7", "--robots", "2", "--meeting", "1",
            "--algorithm", "go-to-target", "--db", db, "--workers", "1", "--json"]
    first = subprocess.run(args, capture_output=True, text=True, timeout=300)
    assert first.returncode == 0, first.stderr
    summary = json.loads(first.stdout)
    assert {name: k for name, k in summary["classes"].items() if k} == {
        "ring:5": orbits("ring:5", 2, 1, "all"), "ring:6": orbits("ring:6", 2, 1, "all"),
        "ring:7": orbits("ring:7", 2, 1, "all")}
    again = subprocess.run(args[:-1], capture_output=True, text=True, timeout=300)
    assert again.returncode == 0 and "(0 computed now" in again.stdout, again.stdout


@pytest.mark.parametrize(("args", "words"), [
    (("--world", "ring:9-5"), "empty"),
    (("--world", "ring:2"), "at least 3"),
    (("--world", "ring:6", "--box", "3x3"), "paper's world"),
    (("--world", "ring:6", "--task", "juggling"), "unknown task"),
    (("--world", "grid", "--box", "3x3", "--task", "gathering"), "finite world"),
])
def test_bad_world_sweeps_are_one_line(args: tuple[str, ...], words: str, tmp_path, capsys) -> None:  # noqa: ANN001
    """In-process (main returns the exit code); the command's own process is run by
    test_a_world_sweep_resumes_and_reports_each_size."""
    code = main(["sweep", "--robots", "2", "--meeting", "1", *args, "--db",
                 str(tmp_path / "x.sqlite")])
    err = capsys.readouterr().err
    assert code == 2 and words in err, err
    assert len(err.strip().splitlines()) == 1


def test_a_gathering_sweep_needs_no_meeting_nodes_and_names_no_causes(tmp_path, capsys) -> None:  # noqa: ANN001
    """On a finite world ``--meeting`` defaults to 0; a finite world's rows record no rule, so
    the summary shows no causes rather than calling every row "not recorded"."""
    code = main(["sweep", "--world", "ring:5", "--robots", "2", "--task",
                 "gathering", "--algorithm", "go-to-target", "--scheduler", "fsync",
                 "--db", str(tmp_path / "g.sqlite"), "--workers", "1"])
    run = capsys.readouterr()
    assert code == 1, run.err  # two robots do not gather on a ring
    assert "VIOLATED" in run.out and "by cause" not in run.out, run.out
    code = main(["sweep", "--robots", "2", "--box", "3x3", "--db", str(tmp_path / "p.sqlite")])
    err = capsys.readouterr().err
    assert code == 2 and "--meeting is required" in err, err
