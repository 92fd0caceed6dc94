"""Tasks on finite worlds, by name (SEMANTICS.md §11): one module and one line each.

>>> sorted(TASKS)
['exclusive-perpetual-exploration', 'exploration-with-stop', 'gathering', 'gathering-on-meeting-nodes']
"""

from __future__ import annotations

from gather_verify.errors import InvalidInput
from gather_verify.tasks.base import Context, Finding, Task
from gather_verify.tasks.exploration import ExclusivePerpetualExploration, ExplorationWithStop
from gather_verify.tasks.gathering import Gathering, GatheringOnMeetingNodes

TASKS: dict[str, Task] = {t.name: t for t in (
    Gathering(), GatheringOnMeetingNodes(), ExclusivePerpetualExploration(),
    ExplorationWithStop())}

__all__ = ["TASKS", "Context", "Finding", "Task", "get_task"]


def get_task(name: str) -> Task:
    if name not in TASKS:
        raise InvalidInput(f"unknown task {name!r}: use one of {', '.join(sorted(TASKS))}")
    return TASKS[name]
