"""``ring-explore``: exclusive perpetual exploration of a ring (``--world ring:N``) by
k < N robots that share a sense of direction (``--frames chirality``).

A robot steps forward (to its neighbour 1 in its frame) when that node is empty, and
stays otherwise. Only a robot's predecessor can move onto a node, so no two robots
ever meet or cross, and the robots go round for ever. Without chirality each robot's
"forward" is the adversary's choice: two robots may step onto one empty node, and a
single robot may be sent back and forth between two nodes (the verifier shows both;
the field knows one robot cannot perpetually explore a ring without a direction).
"""

from __future__ import annotations

from typing import Any


class RingExplore:
    name = "ring-explore"
    plane = False  # it reads a finite world's view (view.me, view.neighbours())

    def forward(self, view: Any) -> Any:
        """The neighbour the robot calls forward: node 1 of its ring frame."""
        return view.me + 1

    def decide(self, view: Any) -> Any:
        ahead = self.forward(view)
        return view.me if ahead in view.robots else ahead
