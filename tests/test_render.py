"""The SVG storyboard and thumbnails: nothing clipped, captions wrapped, arrowheads,
coordinates, robot identities."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from gather_verify.cli import main
from gather_verify.render import CHAR, thumbnail_svg, trace_svg, wrap
from gather_verify.trace import load_trace

ROOT = Path(__file__).resolve().parent.parent
F4 = ROOT / "scenarios/algorithm/i22-make-multiplicity-onto-guard.json"
STALE = ROOT / "scenarios/regressions/i22-defined-paper-alpha-mer-f-async-df2289d6.json"
NS = "{http://www.w3.org/2000/svg}"


def stored(path: Path) -> dict:
    return load_trace(json.loads(path.read_text())["trace"])


def f4_trace(tmp_path: Path) -> dict:
    out = tmp_path / "t.json"
    main(["check", str(F4), "--scheduler", "fsync", "--trace-out", str(out)])
    return load_trace(out)


def lines(svg: str) -> list[tuple[float, float, str]]:
    """(x, font size, text) of every line of text."""
    root = ET.fromstring(svg)
    out = []
    for text in root.iter(f"{NS}text"):
        size = float(text.get("font-size", 11))
        spans = list(text.iter(f"{NS}tspan"))
        for part in spans or [text]:
            out.append((float(part.get("x", text.get("x", 0))), size, part.text or ""))
    return out


@pytest.mark.parametrize("text,width", [("final: deadlock: no robot can move", 16),
                                         ("a " * 50, 7), ("x" * 40, 9), ("", 5)])
def test_wrap_keeps_every_word_and_every_line_short(text, width):
    out = wrap(text, width)
    assert all(len(line) <= width for line in out)
    assert "".join(out).replace(" ", "") == text.replace(" ", "")


def test_storyboard_clips_nothing(tmp_path):
    for trace in (f4_trace(tmp_path), stored(STALE)):
        svg = trace_svg(trace)
        root = ET.fromstring(svg)
        width = float(root.get("width"))
        for text in root.iter(f"{NS}text"):
            if text.get("text-anchor"):  # labels centred on a node or right of the y axis
                continue
            size = float(text.get("font-size"))
            for span in text.iter(f"{NS}tspan"):
                right = float(span.get("x")) + len(span.text or "") * CHAR * size / 11
                assert right <= width, (span.text, right, width)
        words = " ".join(t for _, _, t in lines(svg))
        assert " ".join(trace["reason"].split()) in " ".join(words.split())  # the whole reason


def test_storyboard_shows_identities_coordinates_and_arrowheads():
    trace = stored(STALE)
    svg = trace_svg(trace)
    texts = [t for _, _, t in lines(svg)]
    assert {"r0", "r1", "r2"} <= set(texts)
    assert {"0", "1", "2"} <= set(texts)  # coordinates
    root = ET.fromstring(svg)
    markers = {m.get("id") for m in root.iter(f"{NS}marker")}
    pending = [ln for ln in root.iter(f"{NS}line") if ln.get("stroke-dasharray")]
    assert pending and all(ln.get("marker-end")[5:-1] in markers for ln in pending)
    joined = " ".join(" ".join(texts).split())  # captions are wrapped over several lines
    assert "STALE: r2 moves on its Look at event 2; since then r1 moved" in joined
    assert "I22 - I2 make multiplicity - target (1, 1)" in joined  # class, phase of `paper`


def test_storyboard_marks_the_cycle(tmp_path):
    out = tmp_path / "t.json"
    main(["check", str(ROOT / "scenarios/algorithm/i22-livelock-guard-on-axis-of-M.json"),
          "--scheduler", "fsync", "--trace-out", str(out)])
    svg = trace_svg(load_trace(out))
    assert "cycle starts" in svg and 'stroke="#6a3dba"' in svg


def test_thumbnail_is_small_valid_svg():
    svg = thumbnail_svg(stored(STALE), uid="x1")
    root = ET.fromstring(svg)
    assert float(root.get("width")) < 300
    assert all(m.get("id").startswith("x1-") for m in root.iter(f"{NS}marker"))


def test_browser_storyboard_text_inside_the_picture(web, tmp_path):
    """Rendered by chromium, every line of text lies inside the SVG's width and height."""
    for k, trace in enumerate((f4_trace(tmp_path), stored(STALE))):
        path = tmp_path / f"s{k}.svg"
        path.write_text(trace_svg(trace))
        web.page.goto(path.as_uri())
        boxes = web.page.evaluate(
            "() => { const s = document.documentElement.getBoundingClientRect();"
            " return [s.width, s.height, Array.from(document.querySelectorAll('text')).map("
            "t => { const b = t.getBoundingClientRect(); return [b.right, b.bottom, t.textContent]; })]; }")
        width, height, texts = boxes
        outside = [t for t in texts if t[0] > width + 0.5 or t[1] > height + 0.5]
        assert texts and outside == []
    assert web.errors == []
