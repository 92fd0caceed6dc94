"""Every limit bounds every step, setup included: a world too large to build, a graph whose
automorphisms take too long, a round of very many events, a synthesis or a certificate of a
huge world, a FIFO given as a file. Each ends INCOMPLETE (or ``unknown``) naming the limit
and the step, or one line, never VERIFIED and never a hang (docs/reliability.md, "Honest
limits")."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from gather_verify.cli import main
from gather_verify.engine.encoding import rss_mb
from gather_verify.words import counted
from gather_verify.world_check import run_world_check


def cli(*argv: str, cwd: Path, timeout: float = 120) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "gather_verify", *argv], cwd=cwd,
                          capture_output=True, text=True, timeout=timeout)


def one_line(done: subprocess.CompletedProcess, code: int, *words: str) -> None:
    assert done.returncode == code, (done.returncode, done.stderr)
    assert "Traceback" not in done.stderr and len(done.stderr.strip().splitlines()) == 1, \
        done.stderr
    for word in words:
        assert word in done.stderr, done.stderr


ENDLESS = "class Loop:\n    name = 'loop'\n\n    def decide(self, view):\n        while True:\n            pass\n"


def test_a_world_union_class_with_an_endless_decide_hands_its_configurations_on(tmp_path):
    """``sweep --world ... --max-seconds-per-config 2`` on the default union engine, with a
    ``decide`` that never returns: no row after 400 s. The class's union search is under the
    watchdog, so it decides nothing and each configuration's own check stops at its limit."""
    (tmp_path / "loop.py").write_text(ENDLESS)
    script = textwrap.dedent(f"""\
        from gather_verify.sweeps.sweep import SweepSettings, _census
        from gather_verify.sweeps.world_union import decide_world_class
        one = SweepSettings(robots=2, meeting=1, box=(0, 0), algorithm={str(tmp_path / 'loop.py:Loop')!r},
                            scheduler="async", world="ring:5", task="gathering-on-meeting-nodes",
                            max_seconds=0.2)
        items = [(i, c) for i, (c, _) in enumerate(_census(one))]
        decided = decide_world_class(one, items)
        print(len(decided.rows), sorted(decided.reasons) == [i for i, _ in items])
        """)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "0 True"  # every one left to its own check, with why


FOUR = ("class Four:\n    name = 'four'\n\n    def decide(self, view):\n"
        "        return sorted(view.neighbours())[0]\n")


@pytest.mark.parametrize("engine", ["bulk", "reference"])
@pytest.mark.parametrize("scheduler", ["fsync", "ssync"])
def test_a_round_of_very_many_events_stops_at_the_states_limit(tmp_path, engine, scheduler):
    """``ring:40`` with 20 robots of 2 moves each, SSYNC, ``--max-states 10``: 6.4 GB at 40 s;
    FSYNC: 1,048,577 states. Here 6 robots of 4 moves each on ``torus:3x3`` (4,096 events a
    round under FSYNC): the round is weighed before it is made (the bulk engine) or cut
    inside the state (the reference), so at most 10 + 1,024 states are stored."""
    (tmp_path / "four.py").write_text(FOUR)
    report = run_world_check("torus:3x3", "0,0 1,0 2,0 0,1 1,1 2,1", "", f"{tmp_path}/four.py:Four",
                             scheduler, task="gathering", reduction=False, max_states=10,
                             engine=engine)
    assert report["verdict"] == "INCOMPLETE" and report["stopped"] == "states", report["reason"]
    assert report["states"] <= 10 + 1024 + 1
    assert report["engine"] == engine


def test_twenty_robots_of_two_moves_stop_at_the_states_limit(tmp_path):
    """The hostile input itself, on the reference engine (a ring of 40 with 20 robots does not
    fit the bulk engine's 63-bit states)."""
    (tmp_path / "two.py").write_text(FOUR.replace("Four", "Two"))
    robots = " ".join(str(2 * i) for i in range(20))
    report = run_world_check("ring:40", robots, "", f"{tmp_path}/two.py:Two", "fsync",
                             task="gathering", max_states=10, max_seconds=30)
    assert report["verdict"] == "INCOMPLETE" and report["stopped"] == "states"
    assert report["states"] <= 10 + 1024 + 1


def test_a_world_too_large_to_build_ends_incomplete_time():
    """``torus:1000x1000`` with ``--max-seconds 5``: 39 s and 2.8 GB before any limit."""
    report = run_world_check("torus:1000x1000", "0,0 5,5", "1,1", "go-to-target", "async",
                             max_seconds=0.5)
    assert report["verdict"] == "INCOMPLETE" and report["stopped"] == "time"
    assert "building torus:1000x1000" in report["reason"]
    assert all(r["holds"] is None for r in report["properties"].values())


def test_a_world_too_large_for_the_memory_limit_ends_incomplete_memory():
    report = run_world_check("torus:1000x1000", "0,0 5,5", "1,1", "go-to-target", "async",
                             max_memory_mb=rss_mb() + 100)
    assert report["verdict"] == "INCOMPLETE" and report["stopped"] == "memory", report["reason"]
    assert "building torus:1000x1000" in report["reason"]


def test_the_automorphisms_of_a_long_path_end_incomplete_time(tmp_path):
    """An 8,001-node path graph with ``--max-seconds 3``: 62 s (the isomorphism matcher)."""
    path = tmp_path / "path.edges"
    path.write_text("".join(f"{i} {i + 1}\n" for i in range(8000)))
    report = run_world_check(f"graph:{path}", "0 10", "5", "go-to-target", "async",
                             max_seconds=0.5)
    assert report["verdict"] == "INCOMPLETE" and report["stopped"] == "time"
    assert report["reason"].startswith("time (building graph:")


def test_a_sweep_of_a_world_too_large_is_one_line_incomplete(tmp_path):
    """``sweep --world ring:10000 ... --max-seconds-per-config 5``: 5 GB; ``--world
    ring:5-100000`` refused only after 76 s (every ring built first)."""
    done = cli("sweep", "--world", "ring:10000", "--robots", "2", "--meeting", "1",
               "--algorithm", "go-to-target", "--max-seconds-per-config", "0.5", "--db",
               "s.sqlite", cwd=tmp_path)
    one_line(done, 3, "INCOMPLETE: time (building ring:10000", "no configuration was checked")
    done = cli("sweep", "--world", "ring:5-100000", "--robots", "2", "--algorithm",
               "go-to-target", "--db", "s.sqlite", cwd=tmp_path)
    one_line(done, 2, "world size 100000 is out of range")


def test_a_synthesis_of_a_world_too_large_is_unknown_naming_the_step(tmp_path, capsys):
    """``synthesize --world ring:10000 --robots 2 --max-seconds 5``: 7.5 GB, no answer at
    60 s."""
    code = main(["synthesize", "--world", "ring:10000", "--robots", "2", "--max-seconds", "0.5",
                 "--json", "--witness", str(tmp_path / "w.py"),
                 "--certificate", str(tmp_path / "c.json")])
    report = json.loads(capsys.readouterr().out)
    assert code == 3 and report["answer"] == "unknown"
    assert report["limit"].startswith("time (building the views of ring:10000")


def _certificate(tmp_path: Path, **instance: object) -> Path:
    """A certificate of none (ring:6, FSYNC, gathering from 0 3), its instance edited."""
    cert = tmp_path / "c.json"
    assert main(["synthesize", "--world", "ring:6", "--robots", "0 3", "--scheduler", "fsync",
                 "--task", "gathering", "--certificate", str(cert),
                 "--witness", str(tmp_path / "w.py")]) == 1
    doc = json.loads(cert.read_text())
    doc["instance"].update(instance)
    cert.write_text(json.dumps(doc))
    return cert


def test_a_certificate_naming_a_huge_world_is_not_re_checked_past_the_limit(tmp_path, capsys):
    """``synthesize --verify`` of a certificate naming ``ring:10000``: 7.7 GB, still running at
    300 s."""
    cert = _certificate(tmp_path, world="ring:10000", robots="2", colours=None)
    capsys.readouterr()
    assert main(["synthesize", "--verify", str(cert), "--max-seconds", "0.5"]) == 3
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("certificate NOT RE-CHECKED")
    assert "time (re-checking the certificate of ring:10000" in err[0]


def test_dev_zero_is_refused_before_it_is_read(tmp_path):
    """``synthesize --verify /dev/zero``: killed at 50 s (the whole file was parsed before the
    size check); ``--fingerprint-extra /dev/zero`` read without bound."""
    one_line(cli("synthesize", "--verify", "/dev/zero", cwd=tmp_path), 2, "character device")
    one_line(cli("sweep", "--world", "ring:5", "--robots", "2", "--algorithm", "go-to-target",
                 "--fingerprint-extra", "/dev/zero", "--db", "x.sqlite", cwd=tmp_path), 2,
             "--fingerprint-extra /dev/zero", "character device")
    big = tmp_path / "big.json"
    with open(big, "wb") as f:  # sparse: 65 MiB that take no room
        f.truncate(65 << 20)
    one_line(cli("synthesize", "--verify", str(big), cwd=tmp_path), 2, "larger than 64 MiB")


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
@pytest.mark.parametrize("argv, what", [
    (("check", "{fifo}"), "scenario"),
    (("replay", "{fifo}"), "trace"),
    (("test", "{fifo}"), "scenario"),
    (("check", "--world", "graph:{fifo}", "--robots", "0", "--meeting", "1"), "graph file"),
    (("synthesize", "--verify", "{fifo}"), "certificate"),
])
def test_a_fifo_with_no_writer_is_one_line_not_a_wait(tmp_path, argv, what):
    """A FIFO with no writer given as a graph file, trace or scenario blocked for ever."""
    fifo = tmp_path / "f.json"
    os.mkfifo(fifo)
    done = cli(*(a.format(fifo=fifo) for a in argv), cwd=tmp_path, timeout=60)
    one_line(done, 2, f"{what} {fifo}: a FIFO")


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
@pytest.mark.parametrize("argv, words", [
    (("check", "--world", "ring:6", "--robots", "0 3", "--meeting", "1", "--algorithm",
      "{fifo}:A"), "algorithm file {fifo}: a FIFO"),
    (("sweep", "--world", "ring:6", "--robots", "2", "--algorithm", "{fifo}:A", "--db",
      "s.sqlite"), "algorithm file {fifo}: a FIFO"),
    (("check", "--robots", "0,0 2,1", "--meeting", "1,1", "--property", "{fifo}:P"),
     "{fifo}: a FIFO"),
])
def test_a_code_file_that_is_a_fifo_says_so(tmp_path, argv, words):
    """An algorithm or property file that is a FIFO (or a device) said "no such file"."""
    fifo = tmp_path / "f.py"
    os.mkfifo(fifo)
    done = cli(*(a.format(fifo=fifo) for a in argv), cwd=tmp_path, timeout=60)
    one_line(done, 2, words.format(fifo=fifo))


def test_synthesize_shares_one_time_budget_and_a_memory_limit(tmp_path, monkeypatch, capsys):
    """``synthesize --max-seconds 280`` ran 298 s: the checker's run on the witness had a
    budget of its own. It is given the time left; the memory limit reaches the search."""
    from gather_verify.synthesis import search, witness

    asked: dict[str, float] = {}
    real_check, real_synth = witness.check_witness, search.synthesize

    def check(spec, inst, seconds):  # noqa: ANN001, ANN202
        asked["check"] = seconds
        return real_check(spec, inst, seconds)

    def synth(inst, **options):  # noqa: ANN001, ANN003, ANN202
        asked["memory"] = options["max_memory_mb"]
        return real_synth(inst, **options)

    monkeypatch.setattr(witness, "check_witness", check)
    monkeypatch.setattr(search, "synthesize", synth)
    assert main(["synthesize", "--world", "ring:5", "--robots", "2", "--scheduler", "fsync",
                 "--task", "gathering", "--max-seconds", "50", "--max-memory-mb", "4321",
                 "--witness", str(tmp_path / "w.py"), "--certificate",
                 str(tmp_path / "c.json")]) == 0
    assert 0 < asked["check"] < 50 and asked["memory"] == 4321


def test_a_synthesis_stopped_by_the_memory_watch_keeps_its_counts(tmp_path, monkeypatch,
                                                                  capsys):
    """``synthesize --world ring:12 --robots 4 --max-memory-mb 300``, stopped by the
    command's memory watch after 28 s of search, printed "views met 0  candidates 0 ...
    states 0": the watch's stop (here raised where it lands, in an exploration) is the
    search's, with what it had done."""
    from gather_verify.synthesis import search
    from gather_verify.watchdog import OverMemory

    real, calls = search.explore, [0]

    def explore(*args, **kwargs):  # noqa: ANN002, ANN003, ANN202
        calls[0] += 1
        if calls[0] == 4:
            raise OverMemory
        return real(*args, **kwargs)

    monkeypatch.setattr(search, "explore", explore)
    code = main(["synthesize", "--world", "ring:7", "--robots", "2", "--max-memory-mb",
                 "99999", "--json", "--witness", str(tmp_path / "w.py"),
                 "--certificate", str(tmp_path / "c.json")])
    report = json.loads(capsys.readouterr().out)
    assert code == 3 and report["answer"] == "unknown"
    assert report["limit"] == "memory (the search over algorithms: past 99999 MB)"
    assert report["candidates"] >= 1 and report["views"] > 0 and report["states"] > 0


def test_minimum_on_a_finite_world_reads_the_memory_limit(tmp_path, monkeypatch):
    """``synthesize --minimum`` searched with the default memory limit, whatever
    ``--max-memory-mb`` said."""
    from gather_verify.synthesis import search

    asked: list[float] = []
    real = search.synthesize

    def synth(inst, **options):  # noqa: ANN001, ANN003, ANN202
        asked.append(options["max_memory_mb"])
        return real(inst, **options)

    monkeypatch.setattr(search, "synthesize", synth)
    monkeypatch.chdir(tmp_path)
    assert main(["synthesize", "--world", "ring:5", "--robots", "2-3", "--minimum",
                 "--scheduler", "fsync", "--task", "gathering", "--db", "m.sqlite",
                 "--max-memory-mb", "4321"]) in (0, 1)
    assert asked and set(asked) == {4321}


@pytest.mark.parametrize("argv", [
    ["--robots", "0,0 2,1", "--meeting", "1,1"],
    ["--robots", "2", "--meeting", "1", "--box", "2x2"],
    ["--robots", "2", "--meeting", "1", "--box", "2x2", "--minimum", "--db", "m.sqlite"],
])
def test_the_paper_s_world_refuses_a_memory_limit_it_would_not_read(tmp_path, capsys,
                                                                     monkeypatch, argv):
    """``synthesize --world grid ... --max-memory-mb 20`` answered exists: the paper's world's
    synthesis reads no memory limit, so the option is refused there, not ignored."""
    monkeypatch.chdir(tmp_path)
    assert main(["synthesize", "--world", "grid", *argv, "--max-memory-mb", "20"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "--max-memory-mb bounds synthesis on a " \
        "finite world" in err, err
    assert not list(tmp_path.iterdir())


def test_a_plane_certificate_s_re_check_refuses_a_memory_limit(tmp_path, capsys):
    cert = tmp_path / "u.cert.json"
    assert main(["synthesize", "--world", "grid", "--robots", "0,1 2,1", "--meeting",
                 "0,0 2,0", "--scheduler", "fsync", "--rounds", "3", "--certificate",
                 str(cert), "--witness", str(tmp_path / "w.py")]) == 1
    assert main(["synthesize", "--verify", str(cert)]) == 0
    capsys.readouterr()
    assert main(["synthesize", "--verify", str(cert), "--max-memory-mb", "20"]) == 2
    assert "--max-memory-mb bounds synthesis on a finite world" in capsys.readouterr().err


def test_synthesize_s_limits_are_in_its_help(capsys):
    """A hidden ``--max-states`` default of 2,000,000 (a run asked for 200 s came back
    ``unknown`` after 49 s), and no ``--max-memory-mb`` (8M states took 8.9 GB)."""
    with pytest.raises(SystemExit):
        main(["synthesize", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "(default 2000000)" in text and "--max-memory-mb MB" in text
    assert "the whole command" in text


def test_a_certificate_s_view_counts_agree(tmp_path, capsys):
    """``synthesize`` printed "views 14 ... decision tree of 1 views", ``--verify`` "13 views":
    the views met by the search, those the certificate relies on and the tree's questions
    are named apart, and both commands count the same."""
    cert = _certificate(tmp_path)
    made = capsys.readouterr().out
    assert main(["synthesize", "--verify", str(cert)]) == 0
    checked = capsys.readouterr().out
    stats = json.loads(cert.read_text())["stats"]
    said = (f"over {counted(stats['tree_views'], 'view')}, a decision tree of "
            f"{counted(stats['tree_nodes'], 'question')}")
    assert said in made and said in checked, (made, checked)
    assert f"views met {stats['views']}" in made
