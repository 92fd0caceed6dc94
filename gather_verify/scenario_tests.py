"""Scenario expectations as tests: what ``gather-verify test``, the pytest plugin and ``check``
share.

A scenario file's ``expect`` block names the class its configuration must have
and, per algorithm and scheduler, the verdict (with the failing property, and
optionally ``max_moves``). Each is one *case*; a scenario that stores a
counterexample ``trace`` has one more case: its replay must confirm it. A case
that does not hold says what was expected, what came, and shows the trace as
ASCII grids with the command that reproduces it.

>>> from gather_verify.scenario import parse_scenario
>>> s = parse_scenario({"robots": [[0, 0], [2, 1]], "meeting_nodes": [[1, 1]],
...     "algorithm": "go-to-target", "expect": {"class": "I13", "verdicts": [
...     {"scheduler": "fsync", "verdict": "VERIFIED", "max_moves": 3},
...     {"scheduler": "ssync", "verdict": "VERIFIED", "max_moves": 2}]}}, "demo.json")
>>> [(c.name, c.run().passed) for c in cases(s)]
[('demo.json[class]', True), ('demo.json[go-to-target/fsync]', True), ('demo.json[go-to-target/ssync]', False)]
>>> print(cases(s)[2].run().message)
demo.json[go-to-target/ssync]: expected max_moves 2, got 3
property: -
(no trace)
reproduce: gather-verify check demo.json --algorithm go-to-target --scheduler ssync
"""

from __future__ import annotations

import shlex
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from gather_verify.errors import InvalidInput
from gather_verify.scenario import Expectation, Scenario, load_scenario

CHECK_OPTIONS = {
    "multiplicity", "frames", "properties", "reduction", "max_states", "max_seconds",
    "move_bound_c", "force",
}
"""What an expectation's ``options`` may set (and ``slow``: run only when asked)."""


def run_expectation(scenario: Scenario, expectation: Expectation) -> dict[str, Any]:
    """Run the explorer as the expectation says; the report of :func:`run_check`."""
    from gather_verify.plane_check import run_check, sorted_colours

    unknown = set(expectation.options) - CHECK_OPTIONS - {"slow"}
    if unknown:
        raise InvalidInput(f"{scenario.path}: unknown expectation options {sorted(unknown)}")
    options = {k: v for k, v in expectation.options.items() if k in CHECK_OPTIONS}
    options.setdefault("multiplicity", scenario.multiplicity)
    options.setdefault("frames", scenario.frames)
    from gather_verify.worlds import FINITE, entry_of
    from gather_verify.worlds.rendezvous import RENDEZVOUS

    if entry_of(scenario.world) == FINITE:
        return _run_world_expectation(scenario, expectation, options)
    if scenario.world == RENDEZVOUS:
        from gather_verify.rendezvous_check import run_rendezvous_check

        return run_rendezvous_check(
            expectation.algorithm, expectation.scheduler,
            movement=scenario.raw.get("movement", "non-rigid"),
            initial_colours=scenario.raw.get("initial_colours", "all"),
            max_states=options.pop("max_states", 2_000_000),
            max_seconds=options.pop("max_seconds", 600.0))
    return run_check(
        scenario.configuration,
        algorithm=expectation.algorithm,
        scheduler=expectation.scheduler,
        detection=options.pop("multiplicity"),
        frames=options.pop("frames"),
        properties=options.pop("properties", None),
        reduction=options.pop("reduction", True),
        max_states=options.pop("max_states", 2_000_000),
        max_seconds=options.pop("max_seconds", 600.0),
        lights=scenario.lights,
        colours=None if scenario.colours is None else sorted_colours(
            [tuple(v) for v in scenario.raw["robots"]], scenario.colours),
        **options,
    )


def _run_world_expectation(scenario: Scenario, expectation: Expectation,
                           options: dict[str, Any]) -> dict[str, Any]:
    """:func:`run_expectation` on a finite world (:func:`~gather_verify.world_check.run_world_check`)."""
    from gather_verify.world_check import run_world_check

    paper = set(options) & {"move_bound_c", "force"}
    if paper:
        raise InvalidInput(f"{scenario.path}: options {sorted(paper)} are the paper's world's")
    robots, meeting = scenario.nodes
    world = scenario.raw["world"]
    if world.startswith("graph:"):
        from pathlib import Path

        world = "graph:" + str(Path(scenario.path).resolve().parent / world[6:])
    return run_world_check(
        world, list(robots), list(meeting), expectation.algorithm, expectation.scheduler,
        task=scenario.task, properties=options.pop("properties", None),
        detection=options.pop("multiplicity"), frames=options.pop("frames"),
        visibility=scenario.visibility, lights=scenario.lights, colours=scenario.colours,
        reduction=options.pop("reduction", True),
        max_states=options.pop("max_states", 2_000_000),
        max_seconds=options.pop("max_seconds", 600.0))


def expectation_mismatch(expectation: Expectation, report: dict[str, Any]) -> str | None:
    """Why ``report`` does not meet ``expectation`` (None: it does)."""
    got = (report["verdict"], report.get("property"))
    want = (expectation.verdict, expectation.property)
    if got != want:
        return (f"expected {_pair(want)}, got {_pair(got)}"
                + (f": {report['reason']}" if report.get("reason") else ""))
    if expectation.max_moves is not None and report.get("max_moves") != expectation.max_moves:
        got = report.get("max_moves")
        return (f"expected max_moves {expectation.max_moves}, got "
                + (str(got) if got is not None else "no move count (the graph was not "
                   "finished, or has a cycle with moves)"))
    return None


def _pair(pair: tuple[str, str | None]) -> str:
    return pair[0] + (f" ({pair[1]})" if pair[1] else "")


@dataclass
class Outcome:
    """One case's result: ``passed``, and when not, ``message`` (with the trace as grids)."""

    name: str
    passed: bool
    message: str = ""
    property: str | None = None
    trace: dict[str, Any] | None = None
    seconds: float = 0.0

    def junit_case(self) -> dict[str, Any]:
        """The case as :func:`gather_verify.junit.junit_xml` reads it (a failure is VIOLATED)."""
        return {"name": self.name, "verdict": "VERIFIED" if self.passed else "VIOLATED",
                "property": self.property or "expectation", "reason": self.message,
                "trace": self.trace, "seconds": self.seconds}


@dataclass
class Case:
    """One expectation of one scenario, runnable on its own (a pytest item, a JUnit case)."""

    scenario: Scenario
    name: str
    kind: str  # class, verdict or replay
    expectation: Expectation | None = None
    slow: bool = False

    def run(self) -> Outcome:
        import time

        started = time.perf_counter()
        outcome = {"class": _run_class, "verdict": _run_verdict, "replay": _run_replay}[
            self.kind](self)
        outcome.seconds = time.perf_counter() - started
        return outcome


def reproduce_command(scenario: Scenario, expectation: Expectation) -> str:
    """The command line that checks ``scenario`` as ``expectation`` says."""
    words = ["gather-verify", "check", scenario.path, "--algorithm", expectation.algorithm,
             "--scheduler", expectation.scheduler]
    return " ".join(shlex.quote(w) for w in words)


def _run_class(case: Case) -> Outcome:
    from gather_verify.theory import get_fact

    c = case.scenario.configuration
    found = get_fact("class").of(c)
    if found == case.scenario.expected_class:
        return Outcome(case.name, True)
    reason = get_fact("class_reason").of(c)
    return Outcome(case.name, False, f"{case.scenario.path}: class {found} ({reason}), "
                   f"expected {case.scenario.expected_class}", "class")


def _run_verdict(case: Case) -> Outcome:
    from gather_verify.render import render_trace

    expectation = case.expectation
    assert expectation is not None
    report = run_expectation(case.scenario, expectation)
    why = expectation_mismatch(expectation, report)
    if why is None:
        return Outcome(case.name, True)
    trace = report.get("trace")
    if trace and trace.get("world") == "rendezvous":
        from gather_verify.rendezvous_check import render_rendezvous_trace as render_trace
    elif trace and "world" in trace:
        from gather_verify.world_check import render_world_trace as render_trace
    lines = [f"{case.name}: {why}",
             f"property: {report.get('property') or expectation.property or '-'}",
             render_trace(trace) if trace else "(no trace)",
             f"reproduce: {reproduce_command(case.scenario, expectation)}"]
    if trace:
        lines.append(f"replay: gather-verify replay {shlex.quote(_saved(trace))}")
    return Outcome(case.name, False, "\n".join(lines),
                   report.get("property") or expectation.property, trace)


def _saved(trace: dict[str, Any]) -> str:
    """The trace written to a temporary file, so the replay command can name it."""
    import json
    import os
    import tempfile

    handle, path = tempfile.mkstemp(prefix="gather-verify-trace-", suffix=".json")
    with os.fdopen(handle, "w", encoding="utf-8") as out:
        out.write(json.dumps(trace, indent=1) + "\n")
    return path


def _run_replay(case: Case) -> Outcome:
    """The scenario's stored trace replayed: a finite world's by its own replay
    (:mod:`gather_verify.world_replay`), a trace of Z² by :mod:`gather_verify.replay`."""
    from gather_verify.render import render_trace
    from gather_verify.replay import NoLongerReproduces, replay
    from gather_verify.viewer import is_world_trace
    from gather_verify.world_check import render_world_trace
    from gather_verify.world_replay import NoLongerReproduces as WorldNoLonger
    from gather_verify.world_replay import replay_world

    trace = case.scenario.trace
    assert trace is not None
    if trace.get("world") == "rendezvous":
        return _replay_rendezvous(case, trace)
    on_world = is_world_trace(trace)
    why = "the stored trace no longer reproduces"
    try:
        outcome = (replay_world(trace, Path(case.scenario.path).resolve().parent) if on_world
                   else replay(trace))
        ok, message = outcome.confirmed, outcome.message
    except (NoLongerReproduces, WorldNoLonger) as error:  # the algorithm changed since
        ok, message = False, str(error)
    except ValueError as error:  # its algorithm cannot be loaded, or the trace is malformed
        ok, message, why = False, str(error), "the stored trace cannot be replayed"
    if ok:
        return Outcome(case.name, True)
    shown = render_world_trace(trace) if on_world else render_trace(trace)
    return Outcome(case.name, False, f"{case.name}: {why}: "
                   f"{message}\n{shown}\n"
                   f"replay: gather-verify replay {shlex.quote(case.scenario.path)}",
                   trace.get("property"), trace)


def _replay_rendezvous(case: Case, trace: dict[str, Any]) -> Outcome:
    """A rendezvous scenario's stored trace, replayed (:func:`~gather_verify.rendezvous_check.replay_rendezvous`)."""
    from gather_verify.rendezvous_check import render_rendezvous_trace, replay_rendezvous
    from gather_verify.replay import NoLongerReproduces

    try:
        outcome = replay_rendezvous(trace)
        ok, message, why = outcome.confirmed, outcome.message, "the stored trace no longer " \
            "reproduces"
    except NoLongerReproduces as error:
        ok, message, why = False, str(error), "the stored trace no longer reproduces"
    except ValueError as error:
        ok, message, why = False, str(error), "the stored trace cannot be replayed"
    if ok:
        return Outcome(case.name, True)
    return Outcome(case.name, False, f"{case.name}: {why}: {message}\n"
                   f"{render_rendezvous_trace(trace)}", trace.get("property"), trace)


def cases(scenario: Scenario) -> list[Case]:
    """Every case of a scenario: its class, each expected verdict, its stored trace."""
    out = []
    if scenario.expected_class is not None:
        out.append(Case(scenario, f"{scenario.path}[class]", "class"))
    for expectation in scenario.expectations:
        out.append(Case(scenario, f"{scenario.path}[{expectation.algorithm}/"
                        f"{expectation.scheduler}]", "verdict", expectation,
                        slow=bool(expectation.options.get("slow"))))
    if scenario.trace is not None:
        out.append(Case(scenario, f"{scenario.path}[replay]", "replay"))
    return out


def scenario_files(paths: Iterable[str | Path], pattern: str = "*.json") -> list[Path]:
    """The files named, and every file matching ``pattern`` under the folders named (sorted);
    ValueError for a path that does not exist."""
    out: list[Path] = []
    for path in map(Path, paths):
        if path.is_dir():
            out += sorted(p for p in path.rglob(pattern) if p.is_file())
        elif path.exists():  # a file, or what is not one: the reader says which
            out.append(path)
        else:
            raise InvalidInput(f"{path}: no such file or folder")
    return list(dict.fromkeys(out))


def run_cases(paths: Iterable[str | Path], slow: bool = False) -> Iterator[Outcome]:
    """Every case of every scenario under ``paths``; slow ones only when ``slow``."""
    for path in scenario_files(paths):
        for case in cases(load_scenario(path)):
            if case.slow and not slow:
                continue
            yield case.run()


def expectation_for(scenario: Scenario, algorithm: str, scheduler: str) -> Expectation | None:
    """The scenario's expectation for this algorithm and scheduler, if it has one."""
    from gather_verify.algorithms.loading import absolute_spec

    for expectation in scenario.expectations:
        if (absolute_spec(expectation.algorithm) == absolute_spec(algorithm)
                and expectation.scheduler == scheduler):
            return expectation
    return None
