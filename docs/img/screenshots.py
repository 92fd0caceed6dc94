"""Regenerate the screenshots of docs/img/ with headless chromium (the system's) via Playwright.

    pip install -e '.[plot,browser]'
    gather-verify sweep --robots 2-3 --meeting 2-4 --box 3x3 --algorithm paper --scheduler async --db out/paper.sqlite
    python docs/img/screenshots.py out/paper.sqlite
    python docs/img/screenshots.py --worlds    # the pictures of finite worlds only
    python -m sphinx -W -n --keep-going -b html docs docs/_build/html
    python docs/img/screenshots.py --site      # the built site's landing and findings pages
    python docs/img/screenshots.py --rendezvous  # a rendezvous counterexample in the viewer only

Writes viewer-f4-deadlock.png, viewer-f6-livelock.png, viewer-async-stale.png, report.png,
trace-svg.png and moves.png next to this file, and the pictures of finite worlds
(docs/worlds.md): world-viewer-ring.png, world-viewer-graph.png, world-viewer-lights.png,
z2-viewer-lights.png and world-svg-torus.png, and the rendezvous world's step-by-step
picture in the viewer (docs/rendezvous.md): rendezvous-vig2-async-miss.png (PNG, palette-reduced to stay
small). ``--site`` builds nothing: it photographs the landing page
and the findings page of a site already built in docs/_build/html (site-index.png,
site-findings.png, 1200 pixels wide, the top of each page).
"""

from __future__ import annotations

import base64
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from PIL import Image
from playwright.sync_api import sync_playwright

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
ALGORITHM = ROOT / "scenarios/algorithm"
REGRESSIONS = ROOT / "scenarios/regressions"


def gv(*args: str) -> None:
    # from the repository's root: a graph file is named by its relative path in the pictures
    subprocess.run(["gather-verify", *args], check=False, capture_output=True, cwd=ROOT)


def small(path: Path) -> None:
    """Palette PNG: the pictures are flat colours, so 256 colours lose nothing visible."""
    image = Image.open(path).convert("RGB")
    image.quantize(colors=256, method=Image.Quantize.MEDIANCUT).save(path, optimize=True)


def main(db: str) -> None:
    work = Path(tempfile.mkdtemp())
    f4, f6, stale = work / "f4.html", work / "f6.html", work / "stale.html"
    gv("check", str(ALGORITHM / "i22-make-multiplicity-onto-guard.json"), "--html", str(f4),
       "--svg", str(work / "trace.svg"))
    gv("check", str(ALGORITHM / "i22-livelock-guard-on-axis-of-M.json"), "--scheduler", "fsync",
       "--property", "final", "--property", "termination", "--html", str(f6))
    gv("replay", str(REGRESSIONS / "i22-defined-paper-alpha-mer-f-async-df2289d6.json"),
       "--quiet", "--html", str(stale))
    gv("report", "--db", str(Path(db).resolve()), "--html", str(work / "report.html"),
       "--plot", str(work / "moves.png"))

    chromium = shutil.which("chromium") or "/usr/bin/chromium"
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium, args=["--disable-gpu", "--no-sandbox"])
        page = browser.new_page(viewport={"width": 1100, "height": 760})
        for source, step, out in ((f4, "End", "viewer-f4-deadlock.png"),
                                  (f6, 1, "viewer-f6-livelock.png"),
                                  (stale, 5, "viewer-async-stale.png")):
            page.goto(source.as_uri())
            page.evaluate(f"window.viewer.go({step if step != 'End' else 'Infinity'})")
            page.screenshot(path=HERE / out, full_page=True)
        page.goto((work / "report.html").as_uri())
        page.screenshot(path=HERE / "report.png", full_page=True)
        svg = base64.b64encode((work / "trace.svg").read_bytes()).decode()
        page.set_viewport_size({"width": 640, "height": 300})
        page.set_content(f"<body style='margin:8px'><img src='data:image/svg+xml;base64,{svg}'>")
        page.screenshot(path=HERE / "trace-svg.png", full_page=True)
        browser.close()
    shutil.copy(work / "moves.png", HERE / "moves.png")
    for name in ("viewer-f4-deadlock.png", "viewer-f6-livelock.png", "viewer-async-stale.png",
                 "report.png", "trace-svg.png", "moves.png"):
        small(HERE / name)
        print(f"{name}: {(HERE / name).stat().st_size // 1024} KB")
    worlds()


def worlds() -> None:
    """The pictures of finite worlds (docs/worlds.md): the viewer on a ring and on a graph
    file, the SVG storyboard of a torus. They need no database: ``--worlds`` makes them
    alone."""
    work = Path(tempfile.mkdtemp())
    ring, graph, torus = work / "ring.html", work / "graph.html", work / "torus.svg"
    lit = work / "lit.html"  # a user's file in a folder of their own, as docs/worlds.md runs it
    mine = Path(tempfile.mkdtemp(prefix="my-algorithms-"))
    shutil.copy(ROOT / "docs/examples/lit_meet.py", mine)
    subprocess.run(["gather-verify", "check", "--world", "ring:7", "--robots", "0 3",
                    "--algorithm", "lit_meet.py:Meet", "--task", "gathering", "--lights", "2",
                    "--scheduler", "async", "--html", str(lit)], check=False,
                   capture_output=True, cwd=mine)
    gv("check", "--world", "ring:6", "--robots", "0 3", "--algorithm", "ring-explore",
       "--task", "exclusive-perpetual-exploration", "--scheduler", "async", "--html", str(ring))
    gv("check", "--world", "graph:scenarios/worlds/petersen.graphml", "--robots", "p0 p7",
       "--meeting", "p3", "--task", "exploration-with-stop", "--scheduler", "async",
       "--html", str(graph))
    gv("check", "--world", "torus:4x3", "--robots", "0,0 2,1", "--meeting", "3,2",
       "--task", "exploration-with-stop", "--scheduler", "ssync", "--svg", str(torus))
    beacon = work / "beacon.html"  # lights on Z²
    gv("check", "--robots", "1,1 3,2", "--meeting", "0,0 4,0", "--algorithm", "beacon",
       "--lights", "2", "--scheduler", "ssync", "--html", str(beacon))
    chromium = shutil.which("chromium") or "/usr/bin/chromium"
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium, args=["--disable-gpu", "--no-sandbox"])
        page = browser.new_page(viewport={"width": 1100, "height": 760})
        for source, step, out in ((ring, "Infinity", "world-viewer-ring.png"),
                                  (graph, 7, "world-viewer-graph.png"),
                                  (lit, 6, "world-viewer-lights.png"),
                                  (beacon, "Infinity", "z2-viewer-lights.png")):
            page.goto(source.as_uri())
            page.evaluate(f"window.viewer.go({step})")
            page.screenshot(path=HERE / out, full_page=True)
        svg = base64.b64encode(torus.read_bytes()).decode()
        page.set_viewport_size({"width": 1000, "height": 300})
        page.set_content(f"<body style='margin:8px'><img src='data:image/svg+xml;base64,{svg}'>")
        page.screenshot(path=HERE / "world-svg-torus.png", full_page=True)
        browser.close()
    for name in ("world-viewer-ring.png", "world-viewer-graph.png", "world-viewer-lights.png",
                 "z2-viewer-lights.png", "world-svg-torus.png"):
        small(HERE / name)
        print(f"{name}: {(HERE / name).stat().st_size // 1024} KB")
    rendezvous()


def rendezvous() -> None:
    """A rendezvous counterexample in the viewer (two robots on a segment, their lights and
    pending moves), at event 15 of vig-2cols's ASYNC counterexample (rigid moves): A moving
    to B, B's move a miss."""
    page_file = Path(tempfile.mkdtemp()) / "vig2.html"
    gv("check", "--world", "rendezvous", "--algorithm", "vig-2cols", "--scheduler", "async",
       "--movement", "rigid", "--html", str(page_file))
    out = "rendezvous-vig2-async-miss.png"
    chromium = shutil.which("chromium") or "/usr/bin/chromium"
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium, args=["--disable-gpu", "--no-sandbox"])
        page = browser.new_page(viewport={"width": 1100, "height": 640})
        page.goto(page_file.as_uri())
        page.evaluate("window.viewer.go(15)")
        page.screenshot(path=HERE / out)
        browser.close()
    small(HERE / out)
    print(f"{out}: {(HERE / out).stat().st_size // 1024} KB")


SITE = ROOT / "docs/_build/html"


def site() -> None:
    """The built docs site's landing page and findings page, the top of each (a full page
    of findings would be tens of thousands of pixels tall). Builds nothing: run the Sphinx
    build first."""
    pages = [("index.html", "site-index.png"), ("findings.html", "site-findings.png")]
    missing = [name for name, _ in pages if not (SITE / name).exists()]
    if missing:
        sys.exit(f"not built: {', '.join(missing)} in docs/_build/html (run the Sphinx build)")
    chromium = shutil.which("chromium") or "/usr/bin/chromium"
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium, args=["--disable-gpu", "--no-sandbox"])
        page = browser.new_page(viewport={"width": 1200, "height": 900})
        for name, out in pages:
            page.goto((SITE / name).as_uri())
            page.screenshot(path=HERE / out)
        browser.close()
    for _, out in pages:
        small(HERE / out)
        print(f"{out}: {(HERE / out).stat().st_size // 1024} KB")


if __name__ == "__main__":
    if sys.argv[1:] == ["--worlds"]:
        worlds()
    elif sys.argv[1:] == ["--site"]:
        site()
    elif sys.argv[1:] == ["--rendezvous"]:
        rendezvous()
    else:
        main(sys.argv[1] if len(sys.argv) > 1 else "out/paper.sqlite")
