"""``gathering`` and ``gathering-on-meeting-nodes`` on a finite world (SEMANTICS.md §11).

Every final state (no robot can do anything but stay, nothing pending) has every robot
on one node (on a meeting node, for the paper's task); a final state with robots on two
or more nodes is a deadlock. ``termination``: no fair execution stays forever among
states that are not final (§5's livelock test).
"""

from __future__ import annotations

from gather_verify.engine.world_search import WorldSearch
from gather_verify.tasks.base import Context, Finding, Task, final_states, livelock


class Gathering(Task):
    name = "gathering"
    summary = "every robot ends on one node, and every fair execution ends"
    parts = ("gathered-when-final", "termination")
    liveness = ("termination",)
    on_meeting_node = False

    def check(self, s: WorldSearch, ctx: Context) -> dict[str, Finding | None]:
        safety = self.parts[0]
        out: dict[str, Finding | None] = {safety: None}
        for sid in final_states(s):
            nodes = {v for v, *_ in s.keys[sid][0]}
            if len(nodes) > 1:
                out[safety] = Finding(safety, sid, f"deadlock: no robot can move, robots on "
                                      f"{len(nodes)} nodes")
                break
            if self.on_meeting_node and not nodes <= ctx.meeting:
                out[safety] = Finding(safety, sid, "the robots stopped together on a node "
                                      "that is not a meeting node")
                break
        out["termination"] = livelock(
            s, ctx, "termination", "livelock: a fair execution never reaches a final state")
        return out


class GatheringOnMeetingNodes(Gathering):
    name = "gathering-on-meeting-nodes"
    summary = "every robot ends on one meeting node (the paper's task), and every fair " \
              "execution ends"
    parts = ("final", "termination")
    on_meeting_node = True
    needs_meeting = True
