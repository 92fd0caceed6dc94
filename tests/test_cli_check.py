"""``gather-verify check`` / ``replay`` from the command line."""

from __future__ import annotations

import json

from gather_verify.cli import main

YARD = ["--robots", "0,0 3,1 1,4", "--meeting", "2,2"]


def test_check_json_verified(capsys):
    code = main(["check", *YARD, "--algorithm", "go-to-target", "--scheduler", "async",
                 "--no-reduction", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["verdict"] == "VERIFIED" and out["states"] == 2184
    for key in ("property", "transitions", "max_moves", "D", "n", "ratio", "trace",
                "class", "reason", "properties", "limits"):
        assert key in out
    assert "seconds" not in out  # reproducible by default; --timings adds the measurements
    main(["check", *YARD, "--algorithm", "go-to-target", "--json", "--timings"])
    timed = json.loads(capsys.readouterr().out)
    assert "seconds" in timed and "peak_rss_mb" in timed


def test_check_violation_trace_and_replay(tmp_path, capsys):
    trace, svg = tmp_path / "t.json", tmp_path / "t.svg"
    code = main(["check", "--robots", "0,0 3,1", "--meeting", "2,2", "--algorithm", "broken-stay",
                 "--scheduler", "ssync", "--trace-out", str(trace), "--svg", str(svg)])
    assert code == 1 and trace.exists() and svg.read_text().startswith("<svg")
    capsys.readouterr()
    assert main(["replay", str(trace)]) == 1
    assert "CONFIRMED" in capsys.readouterr().out


def test_bad_inputs_exit_2(tmp_path, capsys):
    assert main(["check", *YARD, "--algorithm", "go-to-target", "--property", "nope"]) == 2
    bad = tmp_path / "bad.json"
    bad.write_text("{}")
    assert main(["replay", str(bad)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 2


def test_limit_exit_3():
    assert main(["check", *YARD, "--algorithm", "go-to-target", "--scheduler", "async",
                 "--max-states", "5"]) == 3


def test_not_applicable_exit_4():
    assert main(["check", "--robots", "0,2 3,2", "--meeting", "0,0 3,0 1,1 2,1",
                 "--algorithm", "go-to-target"]) == 4


def test_check_junit_one_case_per_verdict(tmp_path, capsys):
    """--junit: a VIOLATED check is a failing test case naming its property, VERIFIED passes."""
    import xml.etree.ElementTree as ET

    bad, good = tmp_path / "bad.xml", tmp_path / "good.xml"
    assert main(["check", "--robots", "0,0 3,1", "--meeting", "2,2", "--algorithm", "broken-stay",
                 "--scheduler", "fsync", "--junit", str(bad)]) == 1
    assert main(["check", *YARD, "--algorithm", "go-to-target", "--junit", str(good)]) == 0
    capsys.readouterr()
    suite = ET.parse(bad).getroot()
    assert suite.get("tests") == "1" and suite.get("failures") == "1"
    assert "VIOLATED: final" in suite.find("testcase/failure").get("message")
    suite = ET.parse(good).getroot()
    assert suite.get("failures") == "0" and suite.find("testcase/failure") is None


def test_outputs_of_a_check_without_a_trace_say_they_were_not_written(tmp_path) -> None:  # noqa: ANN001
    import subprocess
    import sys

    html, svg = tmp_path / "v.html", tmp_path / "s.svg"
    run = subprocess.run([sys.executable, "-m", "gather_verify", "check", "--robots",
                          "0,0 3,1 1,4", "--meeting", "2,2", "--algorithm", "go-to-target",
                          "--html", str(html), "--svg", str(svg)],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0 and not html.exists() and not svg.exists()
    assert "no counterexample trace" in run.stderr and str(html) in run.stderr
