"""Scenario loader (scenario.py): every malformed file is rejected with a precise message."""

import json

import pytest

from gather_verify.scenario import ScenarioError, load_scenario, parse_scenario

GOOD = {"name": "ok", "description": "d", "robots": [[0, 0], [3, 1]], "meeting_nodes": [[2, 2]],
        "expect": {"class": "I13"}}


def _write(tmp_path, text):
    path = tmp_path / "s.json"
    path.write_text(text)
    return path


def test_good_file_round_trip(tmp_path):
    s = load_scenario(_write(tmp_path, json.dumps(GOOD)))
    assert s.name == "ok" and s.expected_class == "I13"
    assert s.configuration.robots == ((0, 0), (3, 1))
    assert s.configuration.meeting_nodes == frozenset({(2, 2)})


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"robots": None}, "missing field 'robots'"),
        ({"meeting_nodes": None}, "missing field 'meeting_nodes'"),
        ({"robots": "0,0"}, "field 'robots' must be a list"),
        ({"name": 3}, "field 'name' must be a string"),
        ({"expect": []}, "field 'expect' must be an object"),
        ({"colour": "red"}, "unknown field 'colour'"),
        ({"robots": [[0, 0], [0, 0]]}, r"duplicate robot \[0, 0\]"),
        ({"meeting_nodes": [[1, 1], [1, 1]]}, r"duplicate meeting node \[1, 1\]"),
        ({"robots": [[0.5, 0]]}, "coordinates must be integers"),
        ({"robots": [[1.0, 0]]}, "coordinates must be integers"),
        ({"robots": [[True, 0]]}, "coordinates must be integers"),
        ({"robots": [[10**30, 0]]}, r"\|coordinate\| > 1000000"),
        ({"robots": [[0, 0, 0]]}, "exactly two coordinates"),
        ({"robots": [{"x": 0}]}, "pair of integers"),
        ({"robots": []}, "no robots"),
        ({"meeting_nodes": []}, "no meeting nodes"),
        ({"scheduler": "sometimes"}, "unknown scheduler 'sometimes'"),
        ({"expect": {"class": "I99"}}, "unknown class 'I99'"),
        ({"expect": {"class": 11}}, "'expect.class' must be a string"),
        ({"expect": {"klass": "I11"}}, "unknown field 'expect.klass'"),
        ({"expect": {"verdicts": [{"verdict": "MAYBE"}]}}, r"expect.verdicts\[0\]: verdict"),
        ({"expect": {"verdicts": [{"verdict": "VIOLATED"}]}}, "names its 'property'"),
        ({"expect": {"verdicts": [{"verdict": "VERIFIED", "max_moves": True}]}}, "'max_moves'"),
        ({"expect": {"verdicts": [{"verdict": "VERIFIED", "max_moves": -1}]}}, "'max_moves'"),
        ({"expect": {"verdicts": [{"verdict": "VERIFIED", "algorithm": 3}]}}, "'algorithm' must be a string"),
        ({"expect": {"verdicts": [{"verdict": "VERIFIED", "colour": 1}]}}, "unknown field 'colour'"),
    ],
)
def test_malformed_fields(change, message):
    data = {**GOOD, **change}
    data = {k: v for k, v in data.items() if v is not None}
    with pytest.raises(ScenarioError, match=message) as error:
        parse_scenario(data, "bad.json")
    assert str(error.value).startswith("bad.json: ")
    assert "\n" not in str(error.value)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ('{"robots": [[0, 0]], "meeting_nodes": [[1', "invalid JSON at line 1"),
        ("", "invalid JSON at line 1"),
        ("[1, 2]", "must be a JSON object"),
        ('{"robots": [[0, 0]], "robots": [[1, 0]], "meeting_nodes": [[1, 1]]}', "duplicate key 'robots'"),
        ('{"robots": [[%s, 0]], "meeting_nodes": [[1, 1]]}' % ("9" * 5000), "invalid JSON"),
        ('{"robots": [[1e400, 0]], "meeting_nodes": [[1, 1]]}', "coordinates must be integers"),
        ('{"robots": [[NaN, 0]], "meeting_nodes": [[1, 1]]}', "coordinates must be integers"),
        ("[" * 100000 + "]" * 100000, "nested too deeply|must be a JSON object"),
    ],
)
def test_malformed_files(tmp_path, text, message):
    path = _write(tmp_path, text)
    with pytest.raises(ScenarioError, match=message) as error:
        load_scenario(path)
    assert str(error.value).startswith(str(path))


def test_missing_file_and_bad_encoding(tmp_path):
    with pytest.raises(ScenarioError, match="no such file"):
        load_scenario(tmp_path / "nope.json")
    path = tmp_path / "bin.json"
    path.write_bytes(b"\xff\xfe\x00")
    with pytest.raises(ScenarioError, match="not UTF-8"):
        load_scenario(path)
