"""``synthesize --minimum --world grid --box WxH``: the least number of robots for which one
algorithm gathers from every selected configuration of the box (SEMANTICS.md §12). Each
answer carries what backs it: exists, a witness the checker verifies from each
configuration (a broken one is refused); none, Theorem 1's certificate of one
configuration, that ``--verify`` re-checks (a broken one is refused); unknown, the limit."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("pysat", reason="synthesize needs python-sat (extra synth)")

from gather_verify.synthesis import plane  # noqa: E402
from tests.test_synthesis import cli, one_line  # noqa: E402

BOX = ["--minimum", "--world", "grid", "--box", "2x2", "--meeting", "2"]


def _least(tmp_path: Path, *more: str) -> tuple[int, dict[str, Any]]:
    run = cli(*BOX, "--db", str(tmp_path / "min.sqlite"), "--json", *more)
    assert run.returncode in (0, 3), run.stderr
    return run.returncode, json.loads(run.stdout)


def _stays(witness: Path, broken: Path) -> None:
    """The witness with every answer of its table turned into "stay"."""
    head, table = witness.read_text().split("TABLE = {", 1)
    table, tail = table.split("}\n", 1)
    stays = "".join(line.rsplit(":", 1)[0] + ": (0, 0),\n"
                    for line in table.splitlines() if line.strip())
    broken.write_text(head + "TABLE = {\n" + stays + "}\n" + tail)


def test_one_robot_suffices_and_its_witness_is_verified_from_each_configuration(
        tmp_path: Path) -> None:
    code, got = _least(tmp_path, "--robots", "1-2", "--scheduler", "fsync,async")
    assert code == 0
    assert [m["least"] for m in got["minimum"]] == ["1", "1"]
    for row in got["rows"]:
        assert (row["robots"], row["answer"]) == (1, "exists")
        spec = row["files"]["witness"]
        path = Path(spec.rsplit(":", 1)[0])
        _stays(path, tmp_path / "broken.py")
        inst = plane.make_instance("1", "2", row["scheduler"], None, "local-weak", "all",
                                   "2x2", "all")
        assert row["files"]["configurations"] == len(inst.configurations) > 1
        for c in inst.configurations:
            assert plane.check_witness(spec, inst, c, 60)["verdict"] == "VERIFIED"
        assert any(plane.check_witness(f"{tmp_path / 'broken.py'}:Synthesized", inst, c,
                                       60)["verdict"] == "VIOLATED"
                   for c in inst.configurations)


def test_two_robots_have_no_algorithm_and_the_certificate_re_checks(tmp_path: Path) -> None:
    code, got = _least(tmp_path, "--robots", "2", "--scheduler", "fsync")
    assert code == 0
    assert got["minimum"][0]["least"] == ">2"
    (row,) = got["rows"]
    assert row["answer"] == "none"
    path = row["files"]["certificate"]
    again = cli("--verify", path)
    assert again.returncode == 0, again.stderr
    cert = json.loads(Path(path).read_text())
    cert["configurations"][0]["phi"]["t"][0] += 1  # not an automorphism any more
    broken = tmp_path / "broken.cert.json"
    broken.write_text(json.dumps(cert))
    refused = cli("--verify", str(broken))
    assert refused.returncode == 1 and "REJECTED" in one_line(refused)


def test_a_limit_gives_unknown_and_says_which(tmp_path: Path) -> None:
    code, got = _least(tmp_path, "--robots", "1", "--scheduler", "fsync", "--max-seconds",
                       "0.001")
    assert code == 3
    assert got["minimum"][0]["least"] == ">1?"
    assert got["rows"][0]["answer"] == "unknown"
    assert got["rows"][0]["limit"].startswith("max-seconds")


def test_a_count_with_no_configuration_is_skipped(tmp_path: Path) -> None:
    # no configuration of one robot is in U: the count has no answer, the next one is asked
    code, got = _least(tmp_path, "--robots", "1-2", "--select", "u", "--scheduler", "fsync")
    assert code == 0
    assert [(r["robots"], r["answer"]) for r in got["rows"]] == [(1, "empty"), (2, "none")]
    assert got["minimum"][0]["least"] == ">2"


@pytest.mark.parametrize(("more", "words"), [
    (["--world", "grid", "--robots", "1-2", "--meeting", "2"], "needs --box"),
    (["--world", "grid", "--box", "2x2", "--robots", "1-2", "--meeting", "2", "--lights", "2"],
     "no lights"),
    (["--world", "grid", "--box", "2x2", "--robots", "1-2", "--meeting", "9"], "--meeting"),
])
def test_bad_input_is_one_line_and_exit_2(tmp_path: Path, more: list[str], words: str) -> None:
    run = cli("--minimum", "--db", str(tmp_path / "min.sqlite"), *more)
    assert run.returncode == 2 and words in one_line(run), run.stderr
