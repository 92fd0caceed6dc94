"""Traces: shortest counterexamples, replay rejects tampered traces, SVG storyboard."""

from __future__ import annotations

import copy
import json
from collections import deque

import pytest

from gather_verify.algorithms import get_algorithm
from gather_verify.algorithms.moves import move_sets
from gather_verify.model.configuration import Configuration as C
from gather_verify.plane_check import run_check
from gather_verify.render import render_trace, trace_svg
from gather_verify.replay import replay
from schedulers import configuration_of, get_scheduler, initial_state

TWO = C([(0, 0), (3, 1)], [(2, 2)], initial=True)


def independent_deadlock_depth(c, algorithm, scheduler):
    algo = get_algorithm(algorithm)

    def ms(robots):
        return move_sets(algo, C.trusted(robots, c.meeting_nodes))
    start = initial_state(c.robots)
    depth = {start: 0}
    queue = deque([start])
    while queue:
        s = queue.popleft()
        sets = ms(configuration_of(s))
        if all(v == {k} for k, v in sets.items()) and all(p is None for _, p in s) and not (
                len(set(configuration_of(s))) == 1 and s[0][0] in c.meeting_nodes):
            return depth[s]
        for _, t in get_scheduler(scheduler).successors(s, ms):
            if t not in depth:
                depth[t] = depth[s] + 1
                queue.append(t)
    return None


@pytest.mark.parametrize("scheduler", ["fsync", "ssync", "async"])
def test_deadlock_trace_is_shortest(scheduler):
    r = run_check(TWO, algorithm="broken-stay", scheduler=scheduler, max_states=10**5,
                  max_seconds=60, properties=["final"])
    assert len(r["trace"]["steps"]) == independent_deadlock_depth(TWO, "broken-stay", scheduler)


def violation():
    return run_check(TWO, algorithm="broken-stay", scheduler="async", max_states=10**5,
                     max_seconds=60, properties=["final"])["trace"]


def test_trace_round_trips_through_json(tmp_path):
    path = tmp_path / "t.json"
    path.write_text(json.dumps(violation()))
    assert replay(json.loads(path.read_text())).confirmed


def test_tampered_trace_is_rejected():
    t = violation()
    bad = copy.deepcopy(t)
    bad["steps"][0]["state"][0]["node"] = [9, 9]
    with pytest.raises(ValueError, match="step 1"):
        replay(bad)
    other = copy.deepcopy(t)
    other["initial"]["meeting_nodes"] = [[0, 5]]
    with pytest.raises(ValueError):
        replay(other)


def test_truncated_trace_not_confirmed():
    t = violation()
    t["steps"] = t["steps"][:-1]
    assert not replay(t).confirmed


def test_render_and_svg():
    t = violation()
    assert "[" in render_trace(t) or "M" in render_trace(t)
    svg = trace_svg(t)
    assert svg.startswith("<svg") and svg.rstrip().endswith("</svg>")
