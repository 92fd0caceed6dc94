"""The installed package works without a source checkout (no scenarios/, no tools/).

Slow (builds a wheel and a virtual environment): ``pytest -m slow tests/test_wheel.py``.
"""

from __future__ import annotations

import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.slow
def test_a_wheel_installed_outside_the_checkout_checks(tmp_path: Path) -> None:
    wheels = tmp_path / "whl"
    subprocess.run([sys.executable, "-m", "pip", "wheel", str(ROOT), "-w", str(wheels),
                    "--no-deps", "-q"], check=True, cwd=tmp_path)
    (wheel,) = wheels.glob("gather_verify-*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    assert not any(n.startswith(("tools/", "scenarios/", "tests/")) for n in names)
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    subprocess.run([str(venv / "bin" / "pip"), "install", "-q", str(wheel)], check=True,
                   cwd=tmp_path)
    run = subprocess.run(
        [str(venv / "bin" / "gather-verify"), "check", "--robots", "0,0 3,1 1,4", "--meeting",
         "2,2", "--algorithm", "go-to-target", "--scheduler", "async"],
        cwd=tmp_path, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert run.stdout.startswith("VERIFIED  class I13  go-to-target / async")
    alone = subprocess.run([str(venv / "bin" / "python"), "-c", "import schedulers"],
                           cwd=tmp_path, capture_output=True, text=True)
    assert alone.returncode == 0, alone.stderr
