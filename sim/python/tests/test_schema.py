"""The scenario format's JSON Schema (`scenarios/carfollow-scenario.schema.json`, from
`carfollow schema`) checked as an editor checks a file: every shipped scenario validates
against it, and a misspelt key fails it."""

import json
from pathlib import Path

import pytest

jsonschema = pytest.importorskip("jsonschema")
tomllib = pytest.importorskip("tomllib")

SCENARIOS = Path(__file__).resolve().parents[3] / "scenarios"


def validator():
    schema = json.loads((SCENARIOS / "carfollow-scenario.schema.json").read_text())
    return jsonschema.Draft202012Validator(schema)


@pytest.mark.parametrize("path", sorted(SCENARIOS.glob("*.toml")), ids=lambda p: p.stem)
def test_every_shipped_scenario_validates(path):
    errors = [e.message for e in validator().iter_errors(tomllib.loads(path.read_text()))]
    assert errors == []


def test_an_unknown_key_fails():
    scenario = tomllib.loads((SCENARIOS / "nist-grounds.toml").read_text())
    scenario["tracker"]["lamda"] = 0.7
    errors = [e.message for e in validator().iter_errors(scenario)]
    assert any("lamda" in e for e in errors), errors


def test_a_wrong_type_fails():
    scenario = tomllib.loads((SCENARIOS / "nist-grounds.toml").read_text())
    scenario["duration_s"] = "ninety"
    assert list(validator().iter_errors(scenario))
