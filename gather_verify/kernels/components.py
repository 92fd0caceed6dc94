"""Tarjan's strongly connected components in plain Python: the reading of the compiled
kernel (:func:`gather_verify.kernels.compiled.tarjan`) that the paper's graph properties
(:mod:`gather_verify.properties.graph`) and the finite worlds' tasks
(:mod:`gather_verify.tasks.base`) share, written once. It imports nothing of the project
(a finite world's check imports none of the paper's properties)."""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence


def components_of(count: int, successors: Callable[[int], Sequence[int]],
                  inside: Callable[[int], bool] | None = None) -> Iterator[list[int]]:
    """Tarjan's strongly connected components of the states ``0 .. count - 1`` that are
    ``inside`` (all by default), over the edges between them (an edge to a state past them
    is left out), iteratively: roots in id order, edges in the order ``successors`` gives
    them; each component as its states in the order they leave the stack, in the order the
    components close (the compiled kernel's order, :func:`gather_verify.kernels.compiled.tarjan`)."""
    ok = (lambda _v: True) if inside is None else inside
    index = [-1] * count
    low = [0] * count
    on_stack = [False] * count
    stack: list[int] = []
    counter = 0
    for root in range(count):
        if index[root] >= 0 or not ok(root):
            continue
        work = [(root, 0)]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack[root] = True
        while work:
            v, i = work[-1]
            edges = successors(v)
            if i < len(edges):
                work[-1] = (v, i + 1)
                w = edges[i]
                if w >= count or not ok(w):
                    continue
                if index[w] < 0:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on_stack[w] = True
                    work.append((w, 0))
                elif on_stack[w]:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on_stack[w] = False
                    comp.append(w)
                    if w == v:
                        break
                yield comp
