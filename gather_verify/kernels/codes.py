"""The values the engines' neighbour tables and robot codes share (SEMANTICS.md §4, §9).

A neighbour table ``table[node, k]`` holds the node at the far end of the node's ``k``-th
edge. Two values say there is no node there, and they mean different things:

- :data:`OUTSIDE`: the edge exists, but its far end lies outside the search region (the
  box of Z² the encoding covers). A move there is a limit of the search, never a fault of
  the algorithm: the region grows, or the search stops INCOMPLETE (``Stop.REGION``). The Z²
  engine's schedulers hand such a move on as the robot code :data:`OUTSIDE` too.
- :data:`NO_EDGE`: the node has no ``k``-th edge (a finite world's node of smaller degree
  than the table is wide). A move along it is illegal.

Z² has no :data:`NO_EDGE` (every node has 4 neighbours); a finite world has no
:data:`OUTSIDE` (its search region is the whole world). Both are negative, so a table entry
``>= 0`` is a node; code that has to tell them apart compares with the names.

:data:`Z2_SLOTS` is the Z² robot code's slots per cell, ``degree + 1`` (idle, or one pending
step of ``geometry.STEPS``): a code is ``cell * Z2_SLOTS + d``. The compiled kernels read it
here, as a module constant numba freezes when it compiles (a constant divisor stays a cheap
one); the model layer, above this one, derives its own (``geometry.SLOTS``) from
``len(geometry.STEPS) + 1``, and a test ties the two. Numba's disk cache is keyed on the
kernels' own files: after changing a value here, clear it (``__pycache__`` beside them).
"""
from __future__ import annotations

OUTSIDE = -1
"""A neighbour table's entry (and the Z² schedulers' new code) for a node outside the search
region: a limit of the search (INCOMPLETE, or a larger region), not an illegal move."""

NO_EDGE = -2
"""A neighbour table's entry for an edge the node does not have: an illegal move."""

Z2_DEGREE = 4
"""The degree of every node of Z² (``len(geometry.STEPS)``)."""

Z2_SLOTS = Z2_DEGREE + 1
"""A Z² robot code's slots per cell: ``cell * Z2_SLOTS + d``, ``d`` = 0 idle, else 1 + the
index of its pending step in ``geometry.STEPS``."""
