"""``check --progress SECONDS``: a line on stderr every SECONDS (states so far, seconds, what
is being done) from a daemon thread, the Z² and the finite-world checks alike; stdout is the
same with or without it; ``--progress 0`` prints none.

No assertion on time: the algorithm of these checks waits in its first ``decide`` until the
reporter has printed a line (when one runs), so a line is printed however fast the machine."""

from __future__ import annotations

import io
import json
import re
import time
from pathlib import Path

import pytest

from gather_verify.cli import main
from gather_verify.progress import PROGRESS, Reporter, default_every, progress_line

WAITS = '''
import time

from gather_verify.algorithms.go_to_target import GoToTarget
from gather_verify.algorithms.ring_gathering import RingGather
from gather_verify.progress import PROGRESS


def wait_for_a_progress_line():
    deadline = time.monotonic() + 120  # a guard against a hang, not a measurement
    while PROGRESS.reporting and PROGRESS.lines == 0 and time.monotonic() < deadline:
        time.sleep(0.005)


class Waits(GoToTarget):
    name = "waits"

    def decide(self, view):
        wait_for_a_progress_line()
        return super().decide(view)


class WaitsOnRing(RingGather):
    name = "waits-on-ring"

    def decide(self, view):
        wait_for_a_progress_line()
        return super().decide(view)
'''
LINE = re.compile(r"^… [\d,]+ states, \d+ s, \S.*$")
SECONDS = re.compile(r"\d+\.\d\ds")


@pytest.fixture
def waits(tmp_path: Path) -> Path:
    path = tmp_path / "waits.py"
    path.write_text(WAITS)
    return path


def _check(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[str, list[str]]:
    main(["check", *argv])
    got = capsys.readouterr()
    return got.out, got.err.splitlines()


CASES = {
    "plane": ["--robots", "0,0 3,1 1,4", "--meeting", "2,2", "--algorithm", "{waits}:Waits",
              "--scheduler", "async"],
    "world": ["--world", "ring:6", "--robots", "0 2 3", "--algorithm",
              "{waits}:WaitsOnRing", "--scheduler", "ssync", "--multiplicity", "global-strong"],
}


@pytest.mark.parametrize("case", list(CASES))
def test_progress_lines_go_to_stderr_and_leave_stdout_alone(case, waits, capsys):
    argv = [a.format(waits=waits) for a in CASES[case]]
    plain_out, plain_err = _check(capsys, *argv, "--progress", "0")
    assert plain_err == []  # --progress 0: none
    out, err = _check(capsys, *argv, "--progress", "0.2")
    assert err and all(LINE.match(line) for line in err), err
    assert SECONDS.sub("", out) == SECONDS.sub("", plain_out)  # the same, but for the seconds
    plain_json, _ = _check(capsys, *argv, "--progress", "0", "--json")
    json_out, err = _check(capsys, *argv, "--progress", "0.2", "--json")
    assert err and json_out == plain_json
    assert json.loads(json_out)["verdict"]


def test_no_progress_unless_stderr_is_a_terminal(waits, capsys):
    """The default: every 2 s on a terminal, never otherwise (pytest's stderr is no terminal)."""
    assert default_every(io.StringIO()) == 0.0

    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    assert default_every(Terminal()) == 2.0
    _, err = _check(capsys, *[a.format(waits=waits) for a in CASES["plane"]])
    assert err == []


def test_a_terminal_s_line_is_rewritten_in_place_and_erased():
    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    stream = Terminal()
    with Reporter(0.01, stream):
        PROGRESS.doing, PROGRESS.states = "exploring", 1234567
        deadline = time.monotonic() + 120  # a guard against a hang, not a measurement
        while PROGRESS.lines < 2 and time.monotonic() < deadline:
            time.sleep(0.001)
    text = stream.getvalue()
    assert text.startswith("\r… ") and "1,234,567 states" in text and "\n" not in text
    assert text.endswith("\r\033[K")  # nothing left on the terminal
    assert not PROGRESS.reporting


def test_the_line():
    PROGRESS.begin("searching the longest walk (move-bound)")
    PROGRESS.states = 12
    assert progress_line(PROGRESS, 3.4) == "… 12 states, 3 s, searching the longest walk (move-bound)"


@pytest.mark.parametrize("reduction", [[], ["--no-reduction"]])
def test_the_finite_world_bulk_search_counts_its_states_for_the_line(reduction, capsys):
    """The progress line's count on a finite world is the bulk search's stored states, chunk
    by chunk (it stayed 0 there once)."""
    PROGRESS.begin("a test")
    out, _ = _check(capsys, "--world", "ring:9", "--robots", "0 3 5", "--meeting", "7",
                    "--algorithm", "go-to-target", "--scheduler", "async", "--engine", "bulk",
                    "--progress", "0", "--json", *reduction)
    assert PROGRESS.states == json.loads(out)["states"] > 0
