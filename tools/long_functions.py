"""The functions longer than a limit (80 lines by default), longest first: where a function
should be split where its phases split.

Test tooling, not part of the installed package. A function's length is the lines from its
``def`` (its first decorator) to its last line, as :mod:`ast` gives them; a function nested
in another counts inside the outer one and on its own. A function compiled by numba (a
decorator naming ``njit`` or ``jit``) is a kernel: it is listed apart, since a kernel's
loop is kept whole for speed. Run it from the repository's root::

    python -m tools.long_functions                  # gather_verify/ and schedulers/, > 80
    python -m tools.long_functions --limit 60 gather_verify/engine
    python -m tools.long_functions --json

>>> import textwrap
>>> src = textwrap.dedent('''
...     def short():
...         return 1
...     def long():
...     ''') + "    x = 1\\n" * 90
>>> [(f.name, f.lines) for f in long_functions_in(src, "m.py", 80)]
[('long', 91)]
"""

from __future__ import annotations

import argparse
import ast
import json
import sys
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import NamedTuple

LIMIT = 80
"""The longest function the house allows outside numba kernels."""
ROOTS = ("gather_verify", "schedulers")


class Long(NamedTuple):
    """A function over the limit: where it is, its qualified name, its length, and whether
    numba compiles it."""

    path: str
    line: int
    name: str
    lines: int
    kernel: bool


def _kernel(node: ast.FunctionDef | ast.AsyncFunctionDef) -> bool:
    """Whether a decorator names numba's ``njit`` or ``jit`` (``@njit``, ``@nb.njit(...)``,
    ``@kernel`` wrappers named so are not recognised)."""
    for deco in node.decorator_list:
        text = ast.unparse(deco)
        if "njit" in text or text.split("(")[0].endswith("jit"):
            return True
    return False


def long_functions_in(source: str, path: str, limit: int = LIMIT) -> Iterator[Long]:
    """The functions of one module's ``source`` longer than ``limit`` lines."""
    tree = ast.parse(source)

    def walk(node: ast.AST, prefix: str) -> Iterator[Long]:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                name = prefix + child.name
                first = min([child.lineno, *(d.lineno for d in child.decorator_list)])
                length = (child.end_lineno or child.lineno) - first + 1
                if length > limit:
                    yield Long(path, first, name, length, _kernel(child))
                yield from walk(child, name + ".")
            elif isinstance(child, ast.ClassDef):
                yield from walk(child, prefix + child.name + ".")
            else:
                yield from walk(child, prefix)

    yield from walk(tree, "")


def long_functions(roots: Iterable[str], limit: int = LIMIT) -> list[Long]:
    """Every function over ``limit`` lines in the Python files below ``roots``, longest
    first."""
    out: list[Long] = []
    for root in roots:
        base = Path(root)
        files = [base] if base.is_file() else sorted(base.rglob("*.py"))
        for path in files:
            out.extend(long_functions_in(path.read_text(encoding="utf-8"), str(path), limit))
    return sorted(out, key=lambda f: (-f.lines, f.path, f.line))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m tools.long_functions",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("roots", nargs="*", default=list(ROOTS))
    parser.add_argument("--limit", type=int, default=LIMIT)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args(argv)
    found = long_functions(args.roots, args.limit)
    if args.json:
        print(json.dumps([f._asdict() for f in found], indent=1))
        return 0
    plain = [f for f in found if not f.kernel]
    kernels = [f for f in found if f.kernel]
    print(f"{len(plain)} functions over {args.limit} lines outside numba kernels"
          f" ({len(kernels)} kernels over it)")
    for f in plain:
        print(f"  {f.lines:4d}  {f.path}:{f.line}  {f.name}")
    if kernels:
        print("kernels:")
        for f in kernels:
            print(f"  {f.lines:4d}  {f.path}:{f.line}  {f.name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
