"""The deck reference is generated from the schema and must stay true to it.

- docs/deck-reference.md is exactly what ``render_reference()`` gives today;
- every field of every deck model has a description, and every model a docstring;
- the example deck at the top of the reference is a valid deck.
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from sphfem_cli.deck import reference, reference_fields
from sphfem_cli.deck.reference import EXAMPLE_DECK, iter_models, render_reference
from sphfem_cli.deck.schema import Deck
from sphfem_cli.deck.validate import load_deck

DOC = Path(__file__).resolve().parents[2] / "docs" / "deck-reference.md"
REGENERATE = "python -m sphfem_cli.deck.reference"


@pytest.fixture(scope="module")
def rendered() -> str:
    return render_reference()


def test_committed_reference_matches_schema(rendered):
    assert DOC.exists(), f"{DOC} is missing; run `{REGENERATE}` and commit it"
    committed = DOC.read_text(encoding="utf-8")
    if committed != rendered:
        old, new = committed.splitlines(), rendered.splitlines()
        first = next((i for i, (a, b) in enumerate(zip(old, new)) if a != b), min(len(old), len(new)))
        pytest.fail(
            f"docs/deck-reference.md is out of date with the schema (first difference at line {first + 1}); "
            f"run `{REGENERATE}` and commit the result",
            pytrace=False,
        )


def test_every_field_has_a_description():
    missing = [
        f"{model.__module__}.{model.__name__}.{name}"
        for model in iter_models(Deck)
        for name, field in model.model_fields.items()
        if not (field.description or "").strip()
    ]
    assert not missing, "fields without description= (add one in sphfem_cli/deck/schema/): " + ", ".join(missing)


def test_every_model_has_a_docstring():
    missing = [f"{m.__module__}.{m.__name__}" for m in iter_models(Deck) if not (m.__dict__.get("__doc__") or "").strip()]
    assert not missing, "deck models without a docstring: " + ", ".join(missing)


def test_reference_covers_every_family_and_type(rendered):
    for name in Deck.model_fields:
        assert f'<a id="{reference_fields.anchor_of(name)}"></a>' in rendered, name
    for model in iter_models(Deck):
        if "type" in model.model_fields and model.model_fields["type"].is_required():
            assert f"with `type: {reference_fields.type_tag(model)}`" in rendered, model.__name__
    families = [line[4:-1] for line in rendered.splitlines() if line.startswith("## `")]
    assert families == list(Deck.model_fields)


def test_links_point_at_anchors(rendered):
    anchors = set(re.findall(r'<a id="([^"]+)"></a>', rendered))
    targets = set(re.findall(r"\]\(#([^)]+)\)", rendered))
    assert targets <= anchors, sorted(targets - anchors)


def test_example_deck_is_the_one_in_the_reference(rendered):
    block = re.search(r"```yaml\n(.*?)```", rendered, re.DOTALL)
    assert block is not None
    assert block.group(1) == EXAMPLE_DECK


def test_example_deck_validates(rendered, tmp_path):
    text = re.search(r"```yaml\n(.*?)```", rendered, re.DOTALL).group(1)
    path = tmp_path / "example.yaml"
    path.write_text(text, encoding="utf-8")
    deck = load_deck(path)
    assert deck.dimension == 2
    assert set(deck.parts) == {"plate"}


def test_type_rendering():
    t = reference_fields.field_type_text
    from sphfem_cli.deck.schema import BoxGeometry, Control, PrescribedVelocity

    assert t(Control.model_fields["end_time"].annotation, Control.model_fields["end_time"].metadata, "x") == "number > 0"
    f = Control.model_fields["timestep_scale"]
    assert t(f.annotation, f.metadata, "x") == "number in (0, 10]"
    f = BoxGeometry.model_fields["min"]
    assert t(f.annotation, f.metadata, "x") == "vector of `dimension` numbers"
    f = PrescribedVelocity.model_fields["velocity"]
    assert t(f.annotation, f.metadata, "x") == "vector of `dimension` numbers or nulls"
    f = BoxGeometry.model_fields["divisions"]
    assert t(f.annotation, f.metadata, "x") == "list of integers ≥ 1"


def test_check_entry_point(tmp_path, capsys):
    out = tmp_path / "ref.md"
    assert reference.main(["--check", "-o", str(out)]) == 1
    assert REGENERATE in capsys.readouterr().err
    assert reference.main(["-o", str(out)]) == 0
    assert reference.main(["--check", "-o", str(out)]) == 0
    assert out.read_text(encoding="utf-8") == render_reference()
