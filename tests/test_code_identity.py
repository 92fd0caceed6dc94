"""A result is keyed by exactly the code that produced it, and user code cannot end, hang or
fool the verifier: end to end, through the command line (``docs/reliability.md``)."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
from pathlib import Path

BROKEN = "def step(view):\n    return (0, 0)  # never moves: a deadlock off the meeting node\n"
FIXED = textwrap.dedent("""\
    def step(view):
        ((x, y),) = view.meeting_nodes
        if (x, y) == (0, 0):
            return (0, 0)
        return ((1 if x > 0 else -1), 0) if x else (0, (1 if y > 0 else -1))
    """)


def cli(*argv: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "gather_verify", *argv], cwd=cwd,
                          capture_output=True, text=True, timeout=300)


def verdicts(db: Path) -> dict[str, int]:
    import sqlite3

    with sqlite3.connect(db) as con:
        return dict(con.execute("SELECT verdict, count(*) FROM results GROUP BY verdict"))


def test_an_algorithm_edited_while_a_sweep_runs_never_stores_another_code_s_verdicts(tmp_path):
    """The algorithm's helper module is fixed by the algorithm itself at its first ``decide``
    in a worker (as an editor would, mid-run), and the bug put back afterwards. The workers
    run the snapshot the sweep fingerprinted: every row is the broken code's, and a re-run
    on the same database agrees with a fresh database."""
    impl = tmp_path / "impl.py"
    impl.write_text(BROKEN)
    (tmp_path / "walker.py").write_text(textwrap.dedent(f"""\
        from pathlib import Path
        import impl

        ORIGINAL = Path({str(impl)!r})
        FIXED = {FIXED!r}


        class Walker:
            name = "walker"

            def decide(self, view):
                if ORIGINAL.read_text() != FIXED:
                    ORIGINAL.write_text(FIXED)  # the edit, while the sweep runs
                return impl.step(view)
        """))
    argv = ("sweep", "--robots", "2-3", "--meeting", "1", "--box", "3x3", "--workers", "2",
            "--engine", "per-config", "--algorithm", "walker.py:Walker", "--json")
    first = cli(*argv, "--db", "same.sqlite", cwd=tmp_path)
    assert first.returncode == 1, first.stderr
    assert impl.read_text() == FIXED  # the edit did happen during the run
    impl.write_text(BROKEN)  # the bug put back
    again = cli(*argv, "--db", "same.sqlite", cwd=tmp_path)
    fresh = cli(*argv, "--db", "fresh.sqlite", cwd=tmp_path)
    stored, clean = verdicts(tmp_path / "same.sqlite"), verdicts(tmp_path / "fresh.sqlite")
    assert set(stored) == {"VIOLATED"} and stored == clean, (stored, clean)
    assert json.loads(again.stdout)["verdicts"] == json.loads(fresh.stdout)["verdicts"]


def fingerprint(cwd: Path, *extra: str) -> str:
    done = cli("sweep", "--robots", "2", "--meeting", "1", "--box", "2x2", "--workers", "1",
               "--algorithm", "pkg/alg.py:Walk", "--db", "f.sqlite", "--json", *extra, cwd=cwd)
    assert done.returncode in (0, 1), done.stderr
    return json.loads(done.stdout)["settings"]["fingerprint"]


def test_the_fingerprint_follows_packages_relative_imports_property_files_and_extras(tmp_path):
    """An edit of a helper reached through a package ``__init__`` or a relative import, of a
    property file, or of a file named with ``--fingerprint-extra``, changes the key."""
    pkg = tmp_path / "pkg"
    (pkg / "helpers").mkdir(parents=True)
    (pkg / "alg.py").write_text("from helpers import step\n\n\nclass Walk:\n"
                                "    name = 'walk'\n\n    def decide(self, view):\n"
                                "        return step(view)\n")
    (pkg / "helpers" / "__init__.py").write_text("from .impl import step\n")
    (pkg / "helpers" / "impl.py").write_text(FIXED)
    (tmp_path / "prop.py").write_text(
        "from gather_verify.properties.builtin import FINAL\nMINE = FINAL\n")
    (tmp_path / "params.json").write_text('{"k": 1}')
    extra = ("--property", "prop.py:MINE", "--fingerprint-extra", "params.json")
    before = fingerprint(tmp_path, *extra)
    assert fingerprint(tmp_path, *extra) == before  # stable
    (pkg / "helpers" / "impl.py").write_text(FIXED + "\n# an edit\n")
    after_helper = fingerprint(tmp_path, *extra)
    assert after_helper != before
    (tmp_path / "prop.py").write_text((tmp_path / "prop.py").read_text() + "# an edit\n")
    after_property = fingerprint(tmp_path, *extra)
    assert after_property != after_helper
    (tmp_path / "params.json").write_text('{"k": 2}')
    assert fingerprint(tmp_path, *extra) != after_property


def test_the_local_modules_follow_an_edit_even_of_the_same_size_and_time(tmp_path, monkeypatch):
    """A module's imports are parsed once per text (a sweep's worker asks after every task),
    keyed by its bytes, never by its size and time: an edit that keeps both still adds the
    module it now imports; the same text is not parsed again."""
    import os

    from gather_verify.algorithms import loading

    alg, helper = tmp_path / "alg.py", tmp_path / "helper.py"
    helper.write_text("X = 1\n")
    alg.write_text("import json  # none of ours\n")
    stamp = alg.stat()
    assert loading.local_sources(alg) == [alg.resolve()]
    parsed = []
    monkeypatch.setattr(loading, "_parsed_imports", lambda *a: parsed.append(a) or {("json",)})
    assert loading.local_sources(alg) == [alg.resolve()] and parsed == []  # not parsed again
    monkeypatch.undo()
    alg.write_text("import helper # one of ours\n")
    os.utime(alg, ns=(stamp.st_atime_ns, stamp.st_mtime_ns))
    assert alg.stat().st_size == stamp.st_size
    assert loading.local_sources(alg) == sorted([alg.resolve(), helper.resolve()])


def test_gather_verify_s_own_source_is_in_the_fingerprint(monkeypatch):
    """An edit of the verifier (in a source checkout) is another verifier: its digest moves."""
    from gather_verify import fingerprint as fp

    base = fp.algorithm_fingerprint("go-to-target")["digest"]
    monkeypatch.setattr(fp, "own_digest", lambda: "an-edited-verifier")
    assert fp.algorithm_fingerprint("go-to-target")["digest"] != base


def test_an_empty_database_path_is_refused(tmp_path):
    done = cli("sweep", "--robots", "2", "--meeting", "1", "--box", "2x2",
               "--algorithm", "go-to-target", "--db", "", cwd=tmp_path)
    assert done.returncode == 2 and "path is empty" in done.stderr
    assert len(done.stderr.strip().splitlines()) == 1


EXITS = textwrap.dedent("""\
    class Exits:
        name = "exits"

        def __init__(self, code="0"):
            self.code = int(code)

        def decide(self, view):
            raise SystemExit(self.code)
    """)


def test_system_exit_in_decide_is_a_crash_counterexample(tmp_path):
    """``SystemExit`` (0 or 3) from ``decide`` is a crash with a trace, exit 1; a sweep with
    two workers finishes and says VIOLATED."""
    (tmp_path / "exits.py").write_text(EXITS)
    for code in ("0", "3"):
        done = cli("check", "--robots", "0,0 2,1", "--meeting", "1,1", "--algorithm",
                   f"exits.py:Exits:code={code}", "--json", cwd=tmp_path)
        report = json.loads(done.stdout)
        assert done.returncode == 1 and report["property"] == "crash", done.stderr
        assert "SystemExit" in report["reason"]
    done = cli("sweep", "--robots", "2", "--meeting", "1", "--box", "2x2", "--workers", "2",
               "--algorithm", "exits.py:Exits:code=3", "--db", "x.sqlite", "--json", cwd=tmp_path)
    assert done.returncode == 1, done.stderr
    assert set(json.loads(done.stdout)["verdicts"]["I13"]) == {"VIOLATED"}


def test_failures_of_user_code_at_import_and_construction_are_one_line(tmp_path):
    """A constructor that rejects its option, and a ``GeneratorExit`` or ``SystemExit`` at
    import: one line, exit 2, no traceback."""
    (tmp_path / "exits.py").write_text(EXITS)
    (tmp_path / "gen.py").write_text("raise GeneratorExit('at import')\n")
    (tmp_path / "quits.py").write_text("raise SystemExit(1)\n")
    for spec in ("exits.py:Exits:code=abc", "gen.py:X", "quits.py:X"):
        done = cli("check", "--robots", "0,0 2,1", "--meeting", "1,1", "--algorithm", spec,
                   cwd=tmp_path)
        assert done.returncode == 2, (spec, done.stderr)
        assert len(done.stderr.strip().splitlines()) == 1 and "Traceback" not in done.stderr


def test_the_fingerprint_is_the_same_inside_a_sweep_s_snapshot_and_outside(tmp_path):
    """A file inside the project tree (here, the tests' fixture) gets one digest whether it
    is read from disk or from a sweep's snapshot, so settings found outside a run name the
    run's rows."""
    from gather_verify.algorithms.loading import snapshot
    from gather_verify.fingerprint import algorithm_fingerprint

    spec = f"{Path(__file__).resolve().parent / 'fixtures' / 'min_sum_compass.py'}:MinSumCompass"
    outside = algorithm_fingerprint(spec)["digest"]
    with snapshot({spec}):
        inside = algorithm_fingerprint(spec)["digest"]
    assert inside == outside == algorithm_fingerprint(spec)["digest"]
