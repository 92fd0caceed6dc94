"""``random``: a pseudo-random deterministic algorithm, equivariant by construction.

SEMANTICS.md §6 asks the impossibility check (Theorem 1) to hold against *any*
equivariant algorithm; random ones are a cheap supply. ``RandomEquivariant(seed)``
answers, for each view, one of the five moves (stay or a unit step) chosen by
a stable hash (SHA-256, not Python's ``hash``, which changes with
``PYTHONHASHSEED``) of the seed and the view's key in a canonical
serialisation (sorted nodes). Equal keys give equal answers, so it is a
deterministic oblivious algorithm; the answer does not depend on the run, the
process or the platform.

Why any such algorithm is equivariant. Let ``psi = (g, t)`` be a grid
isometry (``g`` in D4, ``t`` a translation) and ``S_C(v)`` the move set of
the robots on ``v`` in ``C``: the union over the 8 frames ``f`` of
``v + f^-1(decide(View(C, v, f)))``. Translating ``psi(C)`` so that
``psi(v)`` is at the origin gives ``g(C - v)``, so
``View(psi(C), psi(v), f) = View(C, v, f o g)`` (same key, same answer
``a``). Its move is ``psi(v) + f^-1(a) = psi(v + (f o g)^-1(a))``; as ``f``
ranges over D4 so does ``f o g``, hence ``S_psi(C)(psi(v)) = psi(S_C(v))``.
This holds for every deterministic ``decide``; in particular, when ``psi`` is
an automorphism of ``C`` the move sets are ``psi``-invariant, which is what
the adversary of Theorem 1 needs (tests/test_impossibility.py checks it with
Hypothesis).

>>> from gather_verify.model.configuration import Configuration
>>> from gather_verify.model.view import View
>>> c = Configuration([(0, 1), (1, -1)], [(0, 0), (1, 0)])
>>> a = RandomEquivariant(seed=3)
>>> a.decide(View(c, (0, 1), 0, "local-weak")) == RandomEquivariant(3).decide(
...     View(c, (0, 1), 0, "local-weak"))
True
>>> a.name
'random:seed=3'
"""

from __future__ import annotations

import hashlib
import json

from gather_verify.errors import InvalidInput
from gather_verify.model.geometry import ORIGIN, STEPS, Node
from gather_verify.model.view import View

MOVES: tuple[Node, ...] = (ORIGIN, *STEPS)
"""The five answers, in the order the hash indexes them."""


def canonical(value: object) -> object:
    """A JSON-serialisable, order-independent form of a view key component.

    >>> canonical(frozenset({(1, 0), (0, 0)}))
    [[0, 0], [1, 0]]
    """
    if isinstance(value, frozenset | set):
        return sorted(canonical(v) for v in value)
    if isinstance(value, tuple | list):
        return [canonical(v) for v in value]
    if value is None or isinstance(value, bool | int | str):
        return value
    raise TypeError(f"cannot serialise view key component {value!r}")


def stable_index(seed: int, key: tuple[object, ...], size: int) -> int:
    """``sha256(seed, key) mod size``: identical across runs and hash seeds."""
    text = json.dumps([seed, canonical(key)], separators=(",", ":"))
    digest = hashlib.sha256(text.encode()).digest()
    return int.from_bytes(digest[:8], "big") % size


class RandomEquivariant:
    """Answers a pseudo-random move per view key; ``seed`` picks the algorithm."""

    def __init__(self, seed: int | str = 0) -> None:
        try:
            self.seed = int(seed)
        except (TypeError, ValueError):
            raise InvalidInput(f"bad seed {seed!r} for the random algorithm: expected an integer") from None
        self.name = f"random:seed={self.seed}"

    def decide(self, view: View) -> Node:
        return MOVES[stable_index(self.seed, view.key(), len(MOVES))]
