"""``gather-verify classify`` and ``census``: output, JSON, and bad input -> exit 2, one line."""

import json
import shutil
import subprocess
import sys

import pytest

from gather_verify.cli import main
from gather_verify.paper.classes import CLASS_NAMES

STRING2 = "001001400004000000000000404000400401000000100"


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_classify_scenario_json(capsys):
    code, out, err = run(capsys, "classify", "scenarios/paper/string2.json", "--json")
    assert code == 0 and err == ""
    data = json.loads(out)
    assert data["class"] == "I21" and data["in_U"] is False
    assert data["key_string"] == STRING2 and data["key_corner"] == [[0, 0]]
    assert data["symmetry"]["kind"] == "reflection" and data["symmetry"]["axis"] == "vertical"
    for key in ("leading_corner", "leading_corner_mer_f", "alpha_string", "alpha_string_mer_f"):
        assert key in data


def test_classify_points_text(capsys):
    code, out, _ = run(capsys, "classify", "--robots", "0,1 2,1", "--meeting", "0,0 2,0")
    assert code == 0
    assert "class: UNCLASSIFIED" in out and "rotation 180 about (1, 0)" in out
    assert "key string: 410041" in out and "over MER_F" in out


def test_classify_order1_leading_corner(capsys):
    code, out, _ = run(capsys, "classify", "scenarios/paper/order1.json", "--json")
    data = json.loads(out)
    assert data["alpha_string"] == "01000001000000010100000000001001000"
    assert data["leading_corner"] == [[0, 0]] and len(data["alpha_string_mer_f"]) == 28


def test_classify_in_U(capsys):
    _, out, _ = run(capsys, "classify", "scenarios/classes/i42.json", "--json")
    assert json.loads(out)["in_U"] is True


def test_census_json_and_table(capsys):
    code, out, _ = run(capsys, "census", "--robots", "2", "--meeting", "2", "--box", "3x3", "--json")
    assert code == 0
    data = json.loads(out)
    assert set(data["classes"]) == set(CLASS_NAMES)
    assert data["total"] == sum(data["classes"].values()) == 131
    assert data["classes"]["I11"] == 0  # zeros are present
    code, out, _ = run(capsys, "census", "--robots", "2", "--meeting", "2", "--box", "3x3",
                       "--examples", "1")
    assert code == 0 and "UNCLASSIFIED" in out and "total" in out and "131" in out


BAD_CLASSIFY = [
    ["--robots", "a,b", "--meeting", "0,0"],
    ["--robots", "1,2,3", "--meeting", "0,0"],
    ["--robots", "1.5,2", "--meeting", "0,0"],
    ["--robots", "1e400,0", "--meeting", "0,0"],
    ["--robots", "0,0 0,0", "--meeting", "1,1"],
    ["--robots", "0,0", "--meeting", "1,1 1,1"],
    ["--robots", "", "--meeting", "0,0"],
    ["--robots", "0,0", "--meeting", ""],
    ["--robots", "0,0"],
    ["--robots", "99999999,0", "--meeting", "0,0"],
    ["no/such/file.json"],
    [],
]
BAD_CENSUS = [
    ["--robots", "3", "--meeting", "3", "--box", "0x3"],
    ["--robots", "-1", "--meeting", "3", "--box", "3x3"],
    ["--robots", "3", "--meeting", "-2", "--box", "3x3"],
    ["--robots", "17", "--meeting", "1", "--box", "4x4"],
    ["--robots", "1", "--meeting", "17", "--box", "4x4"],
    ["--robots", "x", "--meeting", "1", "--box", "4x4"],
    ["--robots", "1.5", "--meeting", "1", "--box", "4x4"],
    ["--robots", "1", "--meeting", "1", "--box", "4"],
    ["--robots", "1", "--meeting", "1", "--box", "9x9"],
    ["--robots", "1", "--meeting", "1", "--box", "-3x3"],
    ["--robots", "8", "--meeting", "8", "--box", "8x8"],
    ["--robots", "1", "--meeting", "1"],
]


@pytest.mark.parametrize("argv", [["classify", *a] for a in BAD_CLASSIFY]
                         + [["census", *a] for a in BAD_CENSUS], ids=repr)
def test_bad_input_exit_2_one_line(capsys, argv):
    code, out, err = run(capsys, *argv)
    assert code == 2
    assert out == ""
    assert err.count("\n") == 1 and err.startswith("error: ")
    assert "Traceback" not in err


def test_bad_input_names_the_value(capsys):
    _, _, err = run(capsys, "classify", "--robots", "1.5,2", "--meeting", "0,0")
    assert "'1.5,2'" in err
    _, _, err = run(capsys, "census", "--robots", "17", "--meeting", "1", "--box", "4x4")
    assert "n=17" in err
    _, _, err = run(capsys, "classify", "--robots", "0,0", "--meeting", "1,1 1,1")
    assert "duplicate meeting node [1, 1]" in err


def test_console_script_subprocess():
    exe = shutil.which("gather-verify")
    argv = [exe] if exe else [sys.executable, "-m", "gather_verify"]
    bad = subprocess.run([*argv, "census", "--robots", "3", "--meeting", "3", "--box", "0x3"],
                         capture_output=True, text=True, timeout=60)
    assert bad.returncode == 2 and bad.stdout == ""
    assert bad.stderr.count("\n") == 1 and "0x3" in bad.stderr
    good = subprocess.run([*argv, "classify", "--robots", "0,1", "--meeting", "0,0 2,0", "--json"],
                          capture_output=True, text=True, timeout=60)
    assert good.returncode == 0 and json.loads(good.stdout)["class"] == "I22"


def test_classify_points_override_the_scenario(capsys):
    code, out, _ = run(capsys, "classify", "scenarios/classes/i22.json", "--robots", "0,1 2,1", "--json")
    assert code == 0 and json.loads(out)["class"] == "UNCLASSIFIED"
