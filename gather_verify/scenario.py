"""Scenario files: a configuration with the settings to check it under and what to expect.

The format is JSON, documented in docs/scenarios.md. Loading validates every
field and raises :class:`ScenarioError` (a ``ValueError``) with one line that
names the file, the field and the problem.

>>> s = parse_scenario({"robots": [[0, 0], [3, 1]], "meeting_nodes": [[2, 2]]}, "inline")
>>> s.configuration.robots, s.algorithm, s.scheduler
(((0, 0), (3, 1)), 'paper', 'async')
>>> parse_scenario({"robots": [[0, 0], [0, 0]], "meeting_nodes": [[2, 2]]}, "x.json")
Traceback (most recent call last):
...
gather_verify.scenario.ScenarioError: x.json: duplicate robot [0, 0]: robots of an initial configuration stand on distinct nodes
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from gather_verify.errors import InvalidInput
from gather_verify.model.configuration import Configuration
from schedulers import SCHEDULERS

VERDICTS = ("VERIFIED", "VIOLATED", "INCOMPLETE", "NOT-APPLICABLE")
TOP_LEVEL = {
    "name": str,
    "description": str,
    "robots": list,
    "meeting_nodes": list,
    "algorithm": str,
    "scheduler": str,
    "multiplicity": str,
    "frames": str,
    "expect": dict,
    "trace": dict,
    "source": str,
    "world": str,
    "task": str,
    "visibility": int,
    "lights": str,
    "colours": list,
}


EXPECTATION_FIELDS = {"algorithm", "scheduler", "verdict", "property", "max_moves", "options"}


class ScenarioError(InvalidInput):
    """A scenario file is malformed; the message names the file and the problem.

    Cause: a missing or unknown key, a value of the wrong type, an unknown algorithm or
    scheduler name. Fix: correct the file as the message says (docs: the scenario format)."""


@dataclass(frozen=True)
class Expectation:
    """One expected verdict: under ``algorithm`` and ``scheduler``, ``verdict``
    (and, for VIOLATED, the failing ``property``)."""

    algorithm: str
    scheduler: str
    verdict: str
    property: str | None = None
    max_moves: int | None = None
    options: dict[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class Scenario:
    """A parsed scenario file."""

    name: str
    configuration: Configuration | None
    """The initial configuration on Z² (None on a finite world: see ``nodes``)."""
    description: str = ""
    algorithm: str = "paper"
    scheduler: str = "async"
    multiplicity: str = "local-weak"
    frames: str = "all"
    expected_class: str | None = None
    expectations: tuple[Expectation, ...] = ()
    trace: dict[str, Any] | None = None
    path: str = ""
    raw: dict[str, Any] = field(default_factory=dict, repr=False)
    world: str = "grid"
    """``grid`` (Z², the paper's) or a finite world (docs/worlds.md)."""
    nodes: tuple[tuple[int, ...], tuple[int, ...]] = ((), ())
    """On a finite world: the robots' and the meeting nodes' indices."""
    task: str | None = None
    visibility: int | None = None
    lights: str | None = None
    """``K`` or ``K:external`` / ``K:internal`` (finite worlds)."""
    colours: list[int] | None = None
    """Each robot's initial colour (default 0)."""


def _type_name(t: type) -> str:
    return {str: "a string", list: "a list", dict: "an object", int: "an integer"}[t]


def parse_scenario(data: object, where: str) -> Scenario:
    """Validate a decoded JSON object as a scenario; ``where`` names it in errors."""
    if not isinstance(data, dict):
        raise ScenarioError(f"{where}: a scenario must be a JSON object, not {type(data).__name__}")
    for key, value in data.items():
        if key not in TOP_LEVEL:
            raise ScenarioError(
                f"{where}: unknown field {key!r} (known: {', '.join(sorted(TOP_LEVEL))})"
            )
        if not isinstance(value, TOP_LEVEL[key]):
            raise ScenarioError(f"{where}: field {key!r} must be {_type_name(TOP_LEVEL[key])}")
    for key in ("robots", "meeting_nodes"):
        if key not in data:
            raise ScenarioError(f"{where}: missing field {key!r}")
    from gather_verify.worlds import DEFAULT_WORLD, PLANE, entry_of

    world = data.get("world", DEFAULT_WORLD).strip()
    nodes: tuple[tuple[int, ...], tuple[int, ...]] = ((), ())
    configuration = None
    try:
        if entry_of(world) == PLANE:
            for key in ("task", "visibility"):
                if key in data:
                    raise ScenarioError(f"{where}: {key!r} needs a finite 'world' (ring:N, "
                                        "grid:WxH, torus:WxH, graph:FILE)")
            configuration = Configuration(data["robots"], data["meeting_nodes"], initial=True)
            _check_colours(data, configuration.n, where)
        else:
            nodes = _world_nodes(data, where)
    except ScenarioError:
        raise
    except ValueError as error:
        raise ScenarioError(f"{where}: {error}") from None
    scheduler = data.get("scheduler", "async")
    if scheduler not in SCHEDULERS:
        raise ScenarioError(f"{where}: unknown scheduler {scheduler!r}: use one of {', '.join(SCHEDULERS)}")
    expected_class, expectations = _parse_expect(data.get("expect", {}), where, data)
    return Scenario(
        name=data.get("name", Path(where).stem),
        configuration=configuration,
        description=data.get("description", ""),
        algorithm=data.get("algorithm", "paper"),
        scheduler=scheduler,
        multiplicity=data.get("multiplicity", "local-weak"),
        frames=data.get("frames", "all"),
        expected_class=expected_class,
        expectations=expectations,
        trace=data.get("trace"),
        path=where,
        raw=data,
        world=world,
        nodes=nodes,
        task=data.get("task"),
        visibility=data.get("visibility"),
        lights=data.get("lights"),
        colours=data.get("colours"),
    )


def _world_nodes(data: dict[str, Any], where: str) -> tuple[tuple[int, ...], tuple[int, ...]]:
    """A finite world's robots and meeting nodes as node indices (robots on distinct nodes)."""
    from gather_verify.tasks import get_task
    from gather_verify.worlds import finite_world

    spec = data["world"]
    if spec.startswith("graph:") and not Path(spec[6:]).is_absolute():  # beside the scenario
        spec = "graph:" + str(Path(where).resolve().parent / spec[6:])
    world = finite_world(spec)
    robots = tuple(world.node_from_json(v) for v in data["robots"])
    meeting = tuple(world.node_from_json(v) for v in data["meeting_nodes"])
    if len(set(robots)) < len(robots):
        raise ScenarioError(f"{where}: two robots on one node: robots of an initial "
                            "configuration stand on distinct nodes")
    if "task" in data:
        get_task(data["task"])
    _check_colours(data, len(robots), where)
    if "expect" in data and "class" in data["expect"]:
        raise ScenarioError(f"{where}: 'expect.class' is a class of the paper's world (Z²)")
    return robots, meeting


def _check_colours(data: dict[str, Any], n: int, where: str) -> None:
    """The scenario's ``lights`` parse, and its ``colours`` give each robot one in range."""
    from gather_verify.worlds.moves import parse_lights

    k = parse_lights(data.get("lights")).colours
    colours = data.get("colours")
    if colours is not None and (len(colours) != n or any(
            isinstance(c, bool) or not isinstance(c, int) or not 0 <= c < k for c in colours)):
        raise ScenarioError(f"{where}: 'colours' must give each robot a colour in 0..{k - 1}")


def _parse_expect(
    expect: dict[str, Any], where: str, data: dict[str, Any]
) -> tuple[str | None, tuple[Expectation, ...]]:
    from gather_verify.theory import get_fact

    class_names = get_fact("class").values
    known = {"class", "verdicts"}
    for key in expect:
        if key not in known:
            raise ScenarioError(f"{where}: unknown field 'expect.{key}' (known: class, verdicts)")
    expected_class = expect.get("class")
    if expected_class is not None and not isinstance(expected_class, str):
        raise ScenarioError(f"{where}: 'expect.class' must be a string, one of {', '.join(class_names)}")
    if expected_class is not None and expected_class not in class_names:
        raise ScenarioError(f"{where}: unknown class {expected_class!r} in 'expect.class'")
    verdicts = expect.get("verdicts", [])
    if not isinstance(verdicts, list):
        raise ScenarioError(f"{where}: 'expect.verdicts' must be a list")
    out = []
    for i, item in enumerate(verdicts):
        at = f"{where}: expect.verdicts[{i}]"
        if not isinstance(item, dict):
            raise ScenarioError(f"{at} must be an object")
        for key in item:
            if key not in EXPECTATION_FIELDS:
                raise ScenarioError(
                    f"{at}: unknown field {key!r} (known: {', '.join(sorted(EXPECTATION_FIELDS))})")
        for key in ("algorithm", "scheduler", "property"):
            if key in item and not isinstance(item[key], str):
                raise ScenarioError(f"{at}: {key!r} must be a string")
        verdict = item.get("verdict")
        if verdict not in VERDICTS:
            raise ScenarioError(f"{at}: verdict must be one of {', '.join(VERDICTS)}")
        scheduler = item.get("scheduler", data.get("scheduler", "async"))
        if scheduler not in SCHEDULERS:
            raise ScenarioError(f"{at}: unknown scheduler {scheduler!r}")
        prop = item.get("property")
        if verdict == "VIOLATED" and not isinstance(prop, str):
            raise ScenarioError(f"{at}: a VIOLATED verdict names its 'property'")
        max_moves = item.get("max_moves")
        if max_moves is not None and (isinstance(max_moves, bool) or not isinstance(max_moves, int)
                                      or not 0 <= max_moves <= 10**12):
            raise ScenarioError(f"{at}: 'max_moves' must be an integer in [0, 10**12]")
        options = item.get("options", {})
        if not isinstance(options, dict):
            raise ScenarioError(f"{at}: 'options' must be an object")
        out.append(Expectation(
            algorithm=item.get("algorithm", data.get("algorithm", "paper")),
            scheduler=scheduler, verdict=verdict, property=prop, max_moves=max_moves,
            options=options,
        ))
    return expected_class, tuple(out)


def _no_duplicate_keys(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            raise ValueError(f"duplicate key {key!r}")
        out[key] = value
    return out


def load_scenario(path: str | Path) -> Scenario:
    """Read and validate a scenario file.

    Raises :class:`ScenarioError` for a missing or unreadable file, invalid JSON
    or any invalid field.
    """
    where = str(path)
    from gather_verify.inputs import read_text

    try:
        text = read_text(path, "scenario")
    except InvalidInput as error:
        raise ScenarioError(str(error)) from None
    try:
        data = json.loads(text, object_pairs_hook=_no_duplicate_keys)
    except json.JSONDecodeError as error:
        raise ScenarioError(f"{where}: invalid JSON at line {error.lineno}: {error.msg}") from None
    except RecursionError:
        raise ScenarioError(f"{where}: invalid JSON: nested too deeply") from None
    except ValueError as error:  # duplicate keys; integers of thousands of digits
        raise ScenarioError(f"{where}: invalid JSON: {str(error).split(';')[0]}") from None
    return _files_relative_to(parse_scenario(data, where), Path(path).resolve().parent, where)


def _files_relative_to(scenario: Scenario, folder: Path, where: str) -> Scenario:
    """The scenario with algorithm files (``PATH.py:NAME``) taken relative to ``folder``,
    under the trust model of :func:`~gather_verify.algorithms.loading.confined_spec`."""
    from dataclasses import replace

    from gather_verify.algorithms.loading import confined_spec

    trace = scenario.trace
    if isinstance(trace, dict) and isinstance(trace.get("algorithm"), str):  # its replay too
        trace = {**trace, "algorithm": confined_spec(trace["algorithm"], folder, where)}
    if trace is not None:  # a stored trace is whole, for check and test alike
        from gather_verify.trace import load_trace
        from gather_verify.viewer import is_world_trace, world_trace_problem

        try:  # a finite world's trace is read by its replay, when the scenario is tested:
            if not is_world_trace(trace):  # its fields are checked here
                load_trace(trace)
            elif (problem := world_trace_problem(trace)) is not None:
                raise InvalidInput(f"bad trace: {problem}")
        except InvalidInput as error:
            raise ScenarioError(f"{where}: its trace: {error}") from None
    return replace(scenario, algorithm=confined_spec(scenario.algorithm, folder, where),
                   expectations=tuple(replace(e, algorithm=confined_spec(e.algorithm, folder,
                                                                         where))
                                      for e in scenario.expectations), trace=trace)
