"""Check every internal link of the built HTML site.

After an HTML build, every ``href`` and ``src`` of every page that points inside the
site must name a file that was written, and its ``#fragment`` an ``id`` on that page.
A broken one is a warning, so ``-W`` fails the build. MyST already fails on a Markdown
link to a page or heading that does not exist; this also covers the pages generated from
the docstrings and from the parser, the images, and the theme's own navigation.
"""

from __future__ import annotations

import re
from pathlib import Path
from urllib.parse import unquote, urlsplit

from sphinx.util import logging

logger = logging.getLogger(__name__)

LINK = re.compile(r'(?:href|src)="([^"]*)"')
ID = re.compile(r'\bid="([^"]*)"')
SKIP = ("http:", "https:", "mailto:", "tel:", "data:", "javascript:")


def broken_links(outdir: Path) -> list[str]:
    """``page: link`` for every internal link of the HTML site under ``outdir`` that
    names a missing file or a missing id."""
    pages = {p.resolve(): p.read_text(encoding="utf-8") for p in outdir.rglob("*.html")
             if "_static" not in p.parts}
    ids = {p: set(ID.findall(text)) for p, text in pages.items()}
    broken = []
    for page, text in pages.items():
        for link in set(LINK.findall(text)):
            if not link or link.startswith(SKIP):
                continue
            parts = urlsplit(link)
            target = (page.parent / unquote(parts.path)).resolve() if parts.path else page
            if target.is_dir():
                target = target / "index.html"
            if not target.exists():
                broken.append(f"{page.relative_to(outdir.resolve())}: {link} (no such file)")
            elif parts.fragment and target in ids and unquote(parts.fragment) not in ids[target]:
                broken.append(f"{page.relative_to(outdir.resolve())}: {link} (no such id)")
    return sorted(broken)


def check(app, exception):  # noqa: ANN001, ANN201 - Sphinx's event signature
    if exception is not None or app.builder.format != "html":
        return
    for link in broken_links(Path(app.outdir)):
        logger.warning("broken internal link: %s", link, type="gv", subtype="link")


def setup(app):  # noqa: ANN001, ANN201 - Sphinx's extension entry point
    app.connect("build-finished", check)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
