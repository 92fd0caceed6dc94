"""pytest plugin: scenario files as test items (registered under the ``pytest11`` entry point).

Once gather-verify is installed, ``pytest`` collects every ``*.scenario.json``
file it meets: one item per case of :mod:`gather_verify.scenario_tests` (the
class, each expected verdict, the replay of a stored trace). ``--gv-scenarios
PATH`` (repeatable) collects every scenario JSON under ``PATH`` whatever its
name (alone, when no other path is named on the command line). An expectation
with ``"options": {"slow": true}`` is marked ``slow``. A failing item shows
the property, the trace as ASCII grids and the command that reproduces it.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

from gather_verify.errors import GatherVerifyError
from gather_verify.scenario_tests import Case, cases

if TYPE_CHECKING:
    from _pytest._code.code import TerminalRepr


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.getgroup("gather-verify").addoption(
        "--gv-scenarios", action="append", default=[], metavar="PATH",
        help="collect every scenario JSON file under PATH as tests (repeatable)")


def pytest_configure(config: pytest.Config) -> None:
    paths = [str(Path(p).resolve()) for p in config.getoption("gv_scenarios") or []]
    config._gv_scenarios = paths  # type: ignore[attr-defined]
    if paths:
        if config.args_source != pytest.Config.ArgsSource.ARGS:
            config.args[:] = paths  # only the scenarios, not the configured testpaths
        else:
            config.args.extend(p for p in paths if p not in config.args)


def _under_gv_paths(config: pytest.Config, path: Path) -> bool:
    here = path.resolve()
    return any(here.is_relative_to(p) for p in getattr(config, "_gv_scenarios", ()))


def pytest_collect_file(file_path: Path, parent: pytest.Collector) -> pytest.Collector | None:
    if file_path.name.endswith(".scenario.json") or (
            file_path.suffix == ".json" and _under_gv_paths(parent.config, file_path)):
        return ScenarioFile.from_parent(parent, path=file_path)
    return None


class ScenarioFile(pytest.File):
    """A scenario file: its cases as items."""

    def collect(self) -> Iterator[pytest.Item]:
        from gather_verify.scenario import load_scenario

        for case in cases(load_scenario(self.path)):
            label = case.name[case.name.rindex("["):]
            item = ScenarioItem.from_parent(self, name=label, case=case)
            if case.slow:
                item.add_marker(pytest.mark.slow)
            yield item


class ScenarioFailure(GatherVerifyError):
    """An expectation of a scenario that did not hold (the message says why, with the trace).

    Cause: the verdict of a scenario's case differs from the one the scenario expects.
    Fix: read the trace in the message; correct the algorithm, or the expectation when the
    algorithm is right."""


class ScenarioItem(pytest.Item):
    """One case of a scenario."""

    def __init__(self, *, case: Case, **kwargs: Any):
        super().__init__(**kwargs)
        self.case = case

    def runtest(self) -> None:
        outcome = self.case.run()
        if not outcome.passed:
            raise ScenarioFailure(outcome.message)

    def repr_failure(self, excinfo: pytest.ExceptionInfo[BaseException],
                     style: Any = None) -> str | TerminalRepr:
        if isinstance(excinfo.value, ScenarioFailure):
            return str(excinfo.value)
        return super().repr_failure(excinfo)

    def reportinfo(self) -> tuple[Path, int | None, str]:
        return self.path, None, self.case.name
