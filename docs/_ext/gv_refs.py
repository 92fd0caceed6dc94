"""Resolve the short Python names the docstrings use, as a reader of the code would, and
link every "SEMANTICS.md §n" citation to its summary (explanation/semantics.md).

The docstrings name objects the way their module sees them (``:class:`Unhandled```,
``:mod:`explore```). When Sphinx finds no object of that exact name, this looks for the
documented objects whose dotted name ends with it and takes the one nearest the module the
reference is written in (the longest common prefix of dotted names), then the shortest
name. Failing that, the name is imported (relative to that module, then absolute): an object
documented under its defining module's name is linked there, and one that exists but is not
documented (a private helper, a constant without a docstring) is printed as it is, unlinked.
A tie, or a name that does not exist, leaves the reference unresolved, and the nitpicky
build fails on it.
"""

from __future__ import annotations

import importlib
import re

from docutils import nodes
from sphinx.transforms.post_transforms import SphinxPostTransform


def _shared(a: str, b: str) -> int:
    count = 0
    for x, y in zip(a.split("."), b.split("."), strict=False):
        if x != y:
            break
        count += 1
    return count


def resolve(app, env, node, contnode):  # noqa: ANN001, ANN201 - Sphinx's event signature
    if node.get("refdomain") != "py":
        return None
    target = node["reftarget"].lstrip(".~")
    if not target:
        return None
    domain = env.get_domain("py")
    types = set(domain.objtypes_for_role(node["reftype"]) or ())
    suffix = "." + target
    candidates = [name for name, entry in domain.objects.items()
                  if (name.endswith(suffix) or name == target)
                  and (not types or entry.objtype in types)]
    module = node.get("py:module") or ""
    here = f"{module}.{node['py:class']}" if node.get("py:class") else module
    if candidates:
        nearest = sorted(candidates, key=lambda name: (-_shared(name, here), name.count(".")))
        key = (_shared(nearest[0], here), nearest[0].count("."))
        if len(nearest) == 1 or key != (_shared(nearest[1], here), nearest[1].count(".")):
            return _link(app, env, node, contnode, nearest[0])
        return None
    found = _import(target, module)
    if found is None:
        return None
    name = _canonical(found)
    if name and name in domain.objects:
        return _link(app, env, node, contnode, name)
    return contnode  # it exists, but is not documented: plain text


def _link(app, env, node, contnode, name):  # noqa: ANN001, ANN202
    found = env.get_domain("py").resolve_xref(env, node["refdoc"], app.builder,
                                              node["reftype"], name, node, contnode)
    return found if isinstance(found, nodes.Element) else None


_MISSING = object()


def _import(target: str, module: str) -> object | None:
    """The object ``target`` names, relative to ``module`` and its packages, then absolute."""
    parts = module.split(".") if module else []
    bases = [".".join(parts[:k]) for k in range(len(parts), 0, -1)] + [""]
    for base in bases:
        dotted = f"{base}.{target}" if base else target
        pieces = dotted.split(".")
        for cut in range(len(pieces), 0, -1):
            try:
                value = importlib.import_module(".".join(pieces[:cut]))
            except ImportError:
                continue
            for attribute in pieces[cut:]:
                value = getattr(value, attribute, _MISSING)
                if value is _MISSING:
                    break
            if value is not _MISSING:
                return value
            break
    return None


def _canonical(value: object) -> str | None:
    """``module.qualname`` of a class, function or module, where it is defined."""
    if hasattr(value, "__spec__") and hasattr(value, "__name__") and not callable(value):
        return value.__name__
    module, qualname = getattr(value, "__module__", None), getattr(value, "__qualname__", None)
    return f"{module}.{qualname}" if module and qualname else None


CITATION = re.compile(r"SEMANTICS(?:\.md)? §(\d+)")
SEMANTICS_PAGE = "explanation/semantics"


class LinkCitations(SphinxPostTransform):
    """"SEMANTICS.md §n" in running text (not in code) links to section n of the summary
    of the model, whose targets are ``semantics-n``."""

    default_priority = 800
    formats = ("html",)

    def run(self) -> None:
        docname = self.env.docname
        for text in list(self.document.findall(nodes.Text)):
            parent = text.parent
            if parent is None or isinstance(parent, (nodes.literal, nodes.literal_block,
                                                     nodes.reference, nodes.title,
                                                     nodes.raw)):
                continue
            value = str(text)
            if not CITATION.search(value):
                continue
            uri = self.app.builder.get_relative_uri(docname, SEMANTICS_PAGE)
            pieces: list[nodes.Node] = []
            last = 0
            for match in CITATION.finditer(value):
                pieces.append(nodes.Text(value[last:match.start()]))
                pieces.append(nodes.reference("", match.group(0), internal=True,
                                              refuri=f"{uri}#semantics-{match.group(1)}"))
                last = match.end()
            pieces.append(nodes.Text(value[last:]))
            parent.replace(text, pieces)


def setup(app):  # noqa: ANN001, ANN201 - Sphinx's extension entry point
    app.connect("missing-reference", resolve)
    app.add_post_transform(LinkCitations)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
