"""Shared CLI pieces: exit codes, configuration arguments, number parsing, JSON output."""

from __future__ import annotations

import argparse
import json
import os
import sys
from typing import TYPE_CHECKING, Any

from gather_verify.errors import InvalidInput
from gather_verify.model.configuration import Configuration
from gather_verify.model.geometry import parse_nodes

if TYPE_CHECKING:
    from gather_verify.scenario import Scenario

EXIT_OK, EXIT_VIOLATED, EXIT_USAGE, EXIT_INCOMPLETE, EXIT_NOT_APPLICABLE = 0, 1, 2, 3, 4
EXIT_NO_LONGER_REPRODUCES = 5
"""``replay``: the trace no longer reproduces (the algorithm changed since it was written)."""
EXIT_BUG = 70
"""An unexpected exception: a bug of gather-verify (``EX_SOFTWARE`` of ``sysexits.h``)."""
EXIT_INTERRUPTED = 130
"""Ctrl-C (SIGINT): 128 + 2, as shells report it; one line on stderr says what was kept."""
ANSWER_EXIT = {"exists": EXIT_OK, "none": EXIT_VIOLATED, "unknown": EXIT_INCOMPLETE,
               "mixed": EXIT_OK}
"""``synthesize``'s exit code of its answer (``mixed``: some starts exist, some are none)."""
TIMING_KEYS = ("seconds", "search_seconds", "peak_rss_mb", "computed", "written",
               "union_fallbacks")
"""Report fields that vary from run to run (``computed``: how many rows a sweep computed
rather than found stored; ``written``: when a stored sweep's rows were written;
``union_fallbacks``: why the union engine left some of those computed to their own checks,
which depends on the engine and the limits, never on the rows); ``--json`` leaves them out
unless ``--timings``."""
VERDICT_EXIT = {"VERIFIED": EXIT_OK, "VIOLATED": EXIT_VIOLATED, "INCOMPLETE": EXIT_INCOMPLETE,
                "NOT-APPLICABLE": EXIT_NOT_APPLICABLE}


class UsageError(InvalidInput):
    """Bad command-line usage; printed as one line, exit code 2.

    Cause: options that contradict each other, or an output path that cannot be written.
    Fix: the message names the option; change it (``gather-verify COMMAND --help``)."""


def add_json_arguments(parser: argparse.ArgumentParser, json_help: str | None, timings: str,
                       reproducible: bool = True) -> None:
    """``--json`` (``json_help``: what it prints) and ``--timings`` (``timings``: what it adds
    to the JSON, left out by default so that the output is byte for byte reproducible)."""
    parser.add_argument("--json", action="store_true", help=json_help)
    parser.add_argument("--timings", action="store_true",
                        help=f"with --json, also print {timings}" + (
                            " (left out by default so the output is byte-for-byte "
                            "reproducible)" if reproducible else ""))


def writable_outputs(**paths: str | None) -> None:
    """Fail before any work when an output file could not be written afterwards, so a long
    check or sweep never ends in an unwritable path."""
    for option, path in paths.items():
        if not path:
            continue
        name = f"--{option.replace('_', '-')} {path}"
        folder = os.path.dirname(os.path.abspath(path))
        if not os.path.isdir(folder):
            raise UsageError(f"{name}: its folder does not exist")
        if os.path.isdir(path) or not os.access(folder, os.W_OK) or (
                os.path.exists(path) and not os.access(path, os.W_OK)):
            raise UsageError(f"{name}: not a writable file")


def add_configuration_arguments(parser: argparse.ArgumentParser) -> None:
    """``[SCENARIO] [--robots "x,y ..."] [--meeting "x,y ..."]``."""
    parser.add_argument("scenario", nargs="?", help="scenario JSON file (docs/scenarios.md)")
    parser.add_argument("--robots", help='robot nodes, e.g. "0,0 3,1 1,4"')
    parser.add_argument("--meeting", help='meeting nodes, e.g. "2,2"')


def load_configuration(args: argparse.Namespace) -> tuple[Configuration, Scenario | None]:
    """The initial configuration named on the command line (file, or points, or both:
    points override the file's)."""
    from gather_verify.scenario import load_scenario
    from gather_verify.worlds import FINITE, entry_of

    scenario = load_scenario(args.scenario) if args.scenario else None
    if scenario is not None and entry_of(scenario.world) == FINITE:
        raise UsageError(f"{args.scenario} is a scenario of the finite world {scenario.world}: "
                         "use gather-verify check or test on it")
    if scenario is None and (args.robots is None or args.meeting is None):
        raise UsageError("give a SCENARIO file, or both --robots and --meeting")
    robots = parse_nodes(args.robots) if args.robots is not None else list(
        scenario.configuration.robots)  # type: ignore[union-attr]
    meeting = parse_nodes(args.meeting) if args.meeting is not None else list(
        scenario.configuration.meeting_nodes)  # type: ignore[union-attr]
    return Configuration(robots, meeting, initial=True), scenario


class Words(argparse.Action):
    """An option that takes one or more words, kept as one text (``--colours 1 0`` and
    ``--colours "1 0"`` alike): a second word is never taken for a positional argument."""

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace,
                 values: Any, option_string: str | None = None) -> None:
        setattr(namespace, self.dest, " ".join(values))


def bounded_int(low: int, high: int):  # noqa: ANN201 - argparse type factory
    """argparse type: an integer in ``[low, high]``."""

    def parse(text: str) -> int:
        try:
            value = int(text, 10)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(f"{value} is out of range [{low}, {high}]")
        return value

    return parse


def bounded_float(low: float, high: float):  # noqa: ANN201
    """argparse type: a finite number in ``[low, high]``."""

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
        if not low <= value <= high:  # also rejects nan and inf
            raise argparse.ArgumentTypeError(f"{text} is out of range [{low}, {high}]")
        return value

    return parse


def parse_box(text: str) -> tuple[int, int]:
    """``WxH`` with 1 <= W, H <= 64."""
    w, sep, h = text.lower().partition("x")
    try:
        width, height = int(w, 10), int(h, 10)
    except ValueError:
        raise argparse.ArgumentTypeError(f"bad box {text!r}: expected WxH, e.g. 4x4") from None
    if not sep or not (1 <= width <= 64 and 1 <= height <= 64):
        raise argparse.ArgumentTypeError(f"bad box {text!r}: W and H must be 1..64")
    return width, height


def _plain(value: Any) -> Any:
    """numpy scalars (counts from the bulk explorer) as plain numbers."""
    item = getattr(value, "item", None)
    if item is None:
        raise TypeError(f"{type(value).__name__} is not JSON serializable")
    return item()


def print_json(obj: Any) -> None:
    """One JSON object on stdout, keys in a stable order."""
    json.dump(obj, sys.stdout, sort_keys=True, default=_plain)
    sys.stdout.write("\n")


def without_timings(obj: Any) -> Any:
    """``obj`` without wall-clock and memory measurements (``TIMING_KEYS``, and the
    ``slowest`` list of a sweep summary, which is ordered by time), at any depth."""
    if isinstance(obj, dict):
        return {k: without_timings(v) for k, v in obj.items()
                if k not in TIMING_KEYS and k != "slowest"}
    if isinstance(obj, list):
        return [without_timings(v) for v in obj]
    return obj
