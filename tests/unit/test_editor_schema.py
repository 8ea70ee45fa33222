"""`sphfem schema`: the deck's JSON Schema accepts every shipped deck, rejects what the deck models
reject key by key, and the repository's copy (schema/deck.schema.json, what decks point editors at)
is the one the code generates."""
from __future__ import annotations

import copy
import json
from pathlib import Path

import jsonschema
import pytest
from click.testing import CliRunner

from sphfem_cli.cli import main
from sphfem_cli.deck.editor_schema import deck_schema, schema_text
from sphfem_cli.deck.loader import load

ROOT = Path(__file__).resolve().parents[2]
DECKS = sorted((ROOT / "decks").glob("*.yaml"))


@pytest.fixture(scope="module")
def validator():
    schema = deck_schema()
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


@pytest.mark.parametrize("deck", DECKS, ids=lambda p: p.stem)
def test_every_shipped_deck_validates(validator, deck):
    data, _ = load(deck)
    errors = [f"{list(e.path)}: {e.message}" for e in validator.iter_errors(data)]
    assert not errors, errors


def test_bad_keys_types_and_ranges_are_rejected(validator):
    data, _ = load(ROOT / "decks" / "cantilever_2d.yaml")
    for path, value in ((("control", "timestep_scale"), -1.0), (("control", "end_tme"), 1.0),
                        (("control", "end_time"), "soon"), (("dimension",), 4)):
        bad = copy.deepcopy(data)
        node = bad
        for key in path[:-1]:
            node = node[key]
        node[path[-1]] = value
        assert list(validator.iter_errors(bad)), path


def test_the_repository_copy_is_current():
    assert (ROOT / "schema" / "deck.schema.json").read_text() == schema_text(), \
        "run: sphfem schema -o schema/deck.schema.json"


def test_cli_writes_the_schema(tmp_path):
    out = tmp_path / "deck.schema.json"
    result = CliRunner().invoke(main, ["schema", "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert json.loads(out.read_text())["$schema"].endswith("2020-12/schema")
    result = CliRunner().invoke(main, ["schema"])
    assert result.exit_code == 0 and json.loads(result.output)["title"].startswith("sphfem deck")


@pytest.mark.parametrize("deck", DECKS, ids=lambda p: p.stem)
def test_every_shipped_deck_points_editors_at_the_schema(deck):
    first = deck.read_text().splitlines()[0]
    assert first == "# yaml-language-server: $schema=../schema/deck.schema.json"
    assert (deck.parent / "../schema/deck.schema.json").resolve().is_file()
