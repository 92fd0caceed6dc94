"""Hostile input: every command answers malformed input with one line and exit code 2.

Each case runs the CLI in-process and checks three things: exit code 2, exactly
one line on stderr that starts with ``error:``, and no traceback. A Hypothesis
fuzzer throws random tokens at the argument parsers and the scenario loader.
"""

from __future__ import annotations

import importlib
import json
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from gather_verify.cli import COMMANDS, main
from gather_verify.scenario import ScenarioError, parse_scenario

GOOD = ["--robots", "0,0 3,1", "--meeting", "2,2"]


def available(command: str) -> bool:
    try:
        importlib.import_module(f"gather_verify.cli.{command}")
    except ModuleNotFoundError:
        return False
    return True


def assert_usage_error(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2, f"{argv}: exit {code}, stderr {err!r}"
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error:"), f"{argv}: {err!r}"
    assert "Traceback" not in err
    return lines[0]


BAD_POINTS = ["a,b", "1,2,3", "1.5,2", "1e400,0", "0,0 0,0", "", "  ", "1,", ",1", "0x1,2",
              "99999999999999999999,0", "nan,0", "[1,2]"]
CONFIG_COMMANDS = ["classify", "simulate", "check", "impossibility"]


@pytest.mark.parametrize("command", CONFIG_COMMANDS)
@pytest.mark.parametrize("points", BAD_POINTS)
def test_bad_robot_points(command: str, points: str, capsys: pytest.CaptureFixture[str]) -> None:
    if not available(command):
        pytest.skip(f"{command} not built")
    assert_usage_error([command, "--robots", points, "--meeting", "2,2"], capsys)


@pytest.mark.parametrize("command", CONFIG_COMMANDS)
@pytest.mark.parametrize("points", ["", "a,b", "2,2 2,2", "1.0,1"])
def test_bad_meeting_points(command: str, points: str, capsys: pytest.CaptureFixture[str]) -> None:
    if not available(command):
        pytest.skip(f"{command} not built")
    assert_usage_error([command, "--robots", "0,0", "--meeting", points], capsys)


@pytest.mark.parametrize("command", CONFIG_COMMANDS)
def test_missing_configuration(command: str, capsys: pytest.CaptureFixture[str]) -> None:
    if not available(command):
        pytest.skip(f"{command} not built")
    assert_usage_error([command], capsys)
    assert_usage_error([command, "/nonexistent/scenario.json"], capsys)


UNKNOWN_NAMES = [
    ["check", *GOOD, "--algorithm", "no-such-algorithm"],
    ["check", *GOOD, "--algorithm", "go-to-target:nonsense=1"],
    ["check", *GOOD, "--scheduler", "lockstep"],
    ["check", *GOOD, "--property", "liveness-ish"],
    ["check", *GOOD, "--multiplicity", "telepathic"],
    ["check", *GOOD, "--frames", "some"],
    ["check", *GOOD, "--max-states", "-1"],
    ["check", *GOOD, "--max-states", "1e99"],
    ["check", *GOOD, "--max-seconds", "nan"],
    ["check", *GOOD, "--max-seconds", "-5"],
    ["simulate", *GOOD, "--algorithm", "nope"],
    ["simulate", *GOOD, "--max-steps", "-3"],
    ["simulate", *GOOD, "--seed", "x"],
    ["census", "--robots", "3", "--meeting", "3", "--box", "0x3"],
    ["census", "--robots", "-1", "--meeting", "3", "--box", "4x4"],
    ["census", "--robots", "3", "--meeting", "3", "--box", "4by4"],
    ["census", "--robots", "20", "--meeting", "1", "--box", "4x4"],
    ["sweep", "--robots", "2", "--meeting", "1", "--box", "3x3", "--algorithm", "nope"],
    ["sweep", "--robots", "2", "--meeting", "1", "--box", "0x3"],
    ["sweep", "--robots", "2", "--meeting", "1", "--box", "3x3", "--workers", "0"],
    ["sweep", "--robots", "2", "--meeting", "1", "--box", "3x3", "--property", "x"],
    ["impossibility", *GOOD, "--algorithms", "-2"],
    ["impossibility", *GOOD, "--steps", "10000000000"],
    ["replay", "/nonexistent/trace.json"],
    ["report", "--db", "/nonexistent/dir/x.sqlite"],
    ["no-such-command"],
]


@pytest.mark.parametrize("argv", UNKNOWN_NAMES, ids=lambda a: " ".join(a))
def test_unknown_names_and_absurd_limits(argv: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    if argv[0] in COMMANDS and not available(argv[0]):
        pytest.skip(f"{argv[0]} not built")
    assert_usage_error(argv, capsys)


SCENARIO_TEXTS = [
    "",
    "{",
    '{"robots": [[0, 0]], "meeting_nodes": [[1, 1]]',
    "[]",
    '{"robots": [[0, 0]]}',
    '{"robots": [[0, 0]], "meeting_nodes": []}',
    '{"robots": [], "meeting_nodes": [[1, 1]]}',
    '{"robots": [[0, 0], [0, 0]], "meeting_nodes": [[1, 1]]}',
    '{"robots": [[0.5, 0]], "meeting_nodes": [[1, 1]]}',
    '{"robots": [[true, 0]], "meeting_nodes": [[1, 1]]}',
    '{"robots": [[1e400, 0]], "meeting_nodes": [[1, 1]]}',
    '{"robots": [[0, 0, 0]], "meeting_nodes": [[1, 1]]}',
    '{"robots": "0,0", "meeting_nodes": [[1, 1]]}',
    '{"robots": [[0, 0]], "meeting_nodes": [[1, 1]], "colour": "red"}',
    '{"robots": [[0, 0]], "meeting_nodes": [[1, 1]], "scheduler": "lockstep"}',
    '{"robots": [[0, 0]], "meeting_nodes": [[1, 1]], "expect": {"class": "I99"}}',
    '{"robots": [[0, 0]], "meeting_nodes": [[1, 1]], "expect": {"verdicts": [{"verdict": "OK"}]}}',
    '\u00ff\u00fe',
]


@pytest.mark.parametrize("text", SCENARIO_TEXTS)
def test_malformed_scenario_files(text: str, tmp_path: Path,
                                  capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "bad.json"
    path.write_text(text, encoding="utf-8")
    line = assert_usage_error(["classify", str(path)], capsys)
    assert "bad.json" in line


def test_unreadable_scenario_bytes(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "bin.json"
    path.write_bytes(b"\xff\xfe\x00garbage")
    assert_usage_error(["classify", str(path)], capsys)


def test_directory_as_scenario(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert_usage_error(["classify", str(tmp_path)], capsys)


json_values = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=5),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=4),
    max_leaves=12,
)


@settings(max_examples=300, deadline=None)
@given(st.dictionaries(
    st.sampled_from(["robots", "meeting_nodes", "name", "scheduler", "expect", "algorithm",
                     "frames", "trace", "extra"]),
    json_values, max_size=6))
def test_fuzz_scenario_loader(data: dict) -> None:
    """The loader either accepts a value or raises ScenarioError, nothing else."""
    try:
        parse_scenario(json.loads(json.dumps(data)), "fuzz.json")
    except ScenarioError as error:
        assert "\n" not in str(error)


TOKENS = ["--robots", "--meeting", "--box", "--algorithm", "--scheduler", "--max-states",
          "--seed", "--json", "0,0", "1,1 2,2", "x", "-1", "2", "2x3", "async", "paper", "1e9",
          "--property", "final", "--frames", "compass", ""]


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(command=st.sampled_from(["classify", "census"]),
       tokens=st.lists(st.sampled_from(TOKENS), max_size=6))
def test_fuzz_cli_arguments(command: str, tokens: list[str],
                            capsys: pytest.CaptureFixture[str]) -> None:
    """Random argument lists never produce a traceback: exit 0 or 2 only (cheap commands)."""
    code = main([command, *tokens])
    err = capsys.readouterr().err
    assert code in (0, 2), (tokens, code, err)
    assert "Traceback" not in err
    if code == 2:
        assert len(err.strip().splitlines()) == 1
