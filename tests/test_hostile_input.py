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
    '{"robots": [[0, 0], [600, 0]], "meeting_nodes": [[1, 1]]}',
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


# -- every command: limits, options and files of every subcommand -------------------------

MORE_BAD = [
    ["check", *GOOD, "--max-memory-mb", "0"],
    ["check", *GOOD, "--max-memory-mb", "lots"],
    ["check", *GOOD, "--max-memory-mb", "inf"],
    ["check", *GOOD, "--margin", "-1"],
    ["check", *GOOD, "--move-bound-c", "inf"],
    ["check", *GOOD, "--max-states", "0"],
    ["check", *GOOD, "--algorithm", "mutant-no-such-bug"],
    ["check", *GOOD, "--algorithm", "paper:alpha"],
    ["check", *GOOD, "--algorithm", "paper:alpha=mer_x"],
    ["simulate", *GOOD, "--scheduler", "x"],
    ["simulate", *GOOD, "--frames", "x"],
    ["simulate", *GOOD, "--multiplicity", "x"],
    ["simulate", *GOOD, "--max-steps", "1e3"],
    ["sweep", "--robots", "2", "--meeting", "1", "--box", "3x3", "--max-memory-mb", "-1"],
    ["sweep", "--robots", "3-2", "--meeting", "1", "--box", "3x3"],
    ["sweep", "--robots", "2", "--meeting", "1", "--box", "3x3", "--max-states-per-config", "0"],
    ["sweep", "--robots", "2", "--meeting", "1", "--box", "3x3", "--multiplicity", "x"],
    ["sweep", "--robots", "2", "--meeting", "1", "--box", "3x3", "--limit", "0"],
    ["sweep", "--robots", "2", "--meeting", "1", "--box", "65x3"],
    ["sweep", "--robots", "2", "--meeting", "1"],
    ["impossibility", *GOOD, "--explore", "x"],
    ["impossibility", *GOOD, "--seed", "-1"],
    ["bench", "--max-seconds", "0"],
    ["bench", "--max-seconds", "x"],
    ["bench", "--nope"],
    ["mutants"],  # mutation testing is python -m tools.mutants, not a command
    ["report"],
    ["replay"],
    ["classify", *GOOD, "/nonexistent/extra.json"],
    ["check", "--robots", "0,0 999999,999999", "--meeting", "500000,500000"],  # MER too large
    ["classify", "--robots", "-1000000,0", "--meeting", "1000000,0"],
]


@pytest.mark.parametrize("argv", MORE_BAD, ids=lambda a: " ".join(a))
def test_every_command_rejects_bad_options(argv: list[str],
                                           capsys: pytest.CaptureFixture[str]) -> None:
    assert_usage_error(argv, capsys)


def test_report_rejects_files_that_are_not_results(tmp_path: Path,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    text = tmp_path / "text.sqlite"
    text.write_text("hello")
    assert "not a gather-verify results database" in assert_usage_error(
        ["report", "--db", str(text)], capsys)
    import sqlite3

    other = tmp_path / "other.sqlite"
    with sqlite3.connect(other) as con:
        con.execute("CREATE TABLE sweeps (x INTEGER)")
    assert "table sweeps" in assert_usage_error(["report", "--db", str(other)], capsys)
    assert_usage_error(["report", "--db", str(tmp_path)], capsys)
    assert_usage_error(["sweep", "--robots", "1", "--meeting", "1", "--box", "2x2",
                        "--workers", "1", "--db", str(other)], capsys)


def test_deeply_nested_json(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "deep.json"
    path.write_text("[" * 100_000)
    assert_usage_error(["classify", str(path)], capsys)
    assert_usage_error(["replay", str(path)], capsys)


def test_unwritable_outputs(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert_usage_error(["check", "--robots", "0,0", "--meeting", "1,1", "--algorithm",
                        "broken-stay", "--trace-out",
                        str(tmp_path / "no" / "such" / "dir" / "t.json")], capsys)


# -- traces that do not match their configuration ------------------------------------------


@pytest.fixture(scope="module")
def good_trace() -> dict:
    from gather_verify.model.configuration import Configuration
    from gather_verify.plane_check import run_check

    report = run_check(Configuration([(0, 0), (3, 1)], [(2, 2)], initial=True),
                       algorithm="broken-stay", scheduler="async",
                       max_states=10_000, max_seconds=60)
    assert report["verdict"] == "VIOLATED" and len(report["trace"]["steps"]) >= 3
    return report["trace"]


def _set(trace: dict, path: tuple, value: object) -> dict:
    out = json.loads(json.dumps(trace))
    target = out
    for key in path[:-1]:
        target = target[key]
    target[path[-1]] = value
    return out


TRACE_DEFECTS = {
    "robot moved in the initial configuration": (("initial", "robots", 0), [9, 9]),
    "duplicate meeting node": (("initial", "meeting_nodes"), [[2, 2], [2, 2]]),
    "recorded state is not reached": (("steps", 0, "state", 0, "node"), [5, 5]),
    "pending move that is not a unit step": (("steps", 0, "state", 0, "pending"), [7, 7]),
    "robot index out of range": (("steps", 0, "event", "robots"), [7]),
    "event kind": (("steps", 0, "event", "kind"), "teleport"),
    "move with a string robot": (("steps", 0, "event", "moves"), [["a", [0, 0], [1, 0]]]),
    "too few robots in a state": (("steps", 0, "state"), [{"node": [0, 0], "pending": None}]),
    "unknown algorithm": (("algorithm",), "nope"),
    "algorithm of the wrong type": (("algorithm",), ["go-to-target"]),
    "unknown scheduler": (("scheduler",), "lockstep"),
    "unknown detection": (("detection",), "telepathic"),
    "frames of the wrong type": (("frames",), 3),
    "unknown property": (("property",), "liveness-ish"),
    "cycle start beyond the steps": (("cycle_start",), 99),
    "cycle start that is a boolean": (("cycle_start",), True),
    "detail that is not an object": (("detail",), "x"),
    "steps that are not a list": (("steps",), {"a": 1}),
    "version": (("version",), 2),
    "format": (("format",), "something-else"),
}


@pytest.mark.parametrize("defect", sorted(TRACE_DEFECTS))
def test_replay_rejects_traces_that_do_not_match(defect: str, good_trace: dict, tmp_path: Path,
                                                  capsys: pytest.CaptureFixture[str]) -> None:
    path, value = TRACE_DEFECTS[defect]
    bad = tmp_path / "bad-trace.json"
    bad.write_text(json.dumps(_set(good_trace, path, value)))
    assert_usage_error(["replay", str(bad)], capsys)


def test_move_bound_trace_without_numbers(good_trace: dict, tmp_path: Path,
                                          capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "mb.json"
    trace = _set(good_trace, ("property",), "move-bound")
    bad.write_text(json.dumps(_set(trace, ("detail",), {"c": "4", "D": 2, "n": 2})))
    assert "numbers c, D and n" in assert_usage_error(["replay", str(bad)], capsys)


def _paths(obj: object, prefix: tuple = ()) -> list[tuple]:
    out = [prefix] if prefix else []
    if isinstance(obj, dict):
        for k, v in obj.items():
            out += _paths(v, (*prefix, k))
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            out += _paths(v, (*prefix, i))
    return out


@settings(max_examples=150, deadline=None)
@given(data=st.data())
def test_fuzz_trace_replay(good_trace: dict, data: st.DataObject) -> None:
    """A trace with any one value replaced replays, or is refused with a one-line ValueError."""
    from gather_verify.replay import replay

    path = data.draw(st.sampled_from(_paths(good_trace)), label="path")
    value = data.draw(json_values, label="value")
    try:
        replay(_set(good_trace, path, value))
    except ValueError as error:
        assert "\n" not in str(error)


EXPENSIVE_TOKENS = ["--robots", "--meeting", "0,0", "1,1 2,2", "0,0 0,2", "x", "-1", "2",
                    "--algorithm", "go-to-target", "paper", "paper:alpha=mer_f", "nope",
                    "--scheduler", "fsync", "async", "--max-states", "200", "--seed", "--json",
                    "--multiplicity", "none", "--frames", "compass", "--property", "final",
                    "--max-steps", "--steps", "--algorithms", "--margin", ""]


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(command=st.sampled_from(["simulate", "check", "impossibility"]),
       tokens=st.lists(st.sampled_from(EXPENSIVE_TOKENS), max_size=7))
def test_fuzz_configuration_commands(command: str, tokens: list[str],
                                     capsys: pytest.CaptureFixture[str]) -> None:
    """Random argument lists over tiny configurations: a verdict's exit code or 2, one line,
    never a traceback."""
    code = main([command, *tokens])
    err = capsys.readouterr().err
    assert code in (0, 1, 2, 3, 4), (tokens, code, err)
    assert "Traceback" not in err
    if code == 2:
        assert len(err.strip().splitlines()) == 1, (tokens, err)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(command=st.sampled_from(["sweep", "report", "replay", "bench"]),
       tokens=st.lists(st.sampled_from(TOKENS + ["--db", "--workers", "--limit", "1-2", "0x3",
                                                 "--mutant", "--list", "--quick"]), max_size=6))
def test_fuzz_other_parsers(command: str, tokens: list[str]) -> None:
    """The argument parsers of the long-running commands answer UsageError or a namespace."""
    from gather_verify.cli import build_parser
    from gather_verify.cli.common import UsageError

    try:
        build_parser().parse_args([command, *tokens])
    except UsageError as error:
        assert "\n" not in str(error)


FINDING = str(Path(__file__).resolve().parent.parent / "scenarios" / "algorithm"
              / "i22-make-multiplicity-onto-guard.json")


@pytest.mark.parametrize("argv", [
    ["check", FINDING, "--trace-out", "/proc/no-such/t.json"],
    ["check", FINDING, "--svg", "/proc/no-such/t.svg"],
    ["check", FINDING, "--junit", "/proc/no-such/j.xml"],
    ["sweep", "--robots", "2", "--meeting", "2", "--box", "3x3", "--junit", "/proc/no-such/j.xml"],
])
def test_unwritable_outputs_fail_before_any_work(argv: list[str], tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    """An output that could not be written is refused up front (one line, exit 2), never
    after a long search whose result would be lost; nothing is stored meanwhile."""
    db = tmp_path / "s.sqlite"
    extra = ["--db", str(db)] if argv[0] == "sweep" else []
    line = assert_usage_error([*argv, *extra], capsys)
    assert "/proc/no-such" in line
    assert not db.exists()


def test_a_missing_output_folder_is_refused_before_the_check(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["check", FINDING, "--trace-out", str(tmp_path / "new" / "t.json")])
    out, err = capsys.readouterr()
    assert code == 2 and err.strip().endswith("its folder does not exist")
    assert out == ""  # refused before the search, not after it
