"""The deck schema is one module per keyword family, and the package re-exports each family's names."""
from __future__ import annotations

import importlib

import pytest

from sphfem_cli.deck import schema

FAMILIES = ("control", "materials", "sections", "parts", "sets", "boundaries", "initial", "loads", "interaction",
            "output", "shapes")


@pytest.mark.parametrize("family", FAMILIES)
def test_every_public_name_of_a_family_is_the_package_s(family):
    module = importlib.import_module(f"sphfem_cli.deck.schema.{family}")
    assert module.__all__, family
    for name in module.__all__:
        assert getattr(schema, name) is getattr(module, name), f"{family}.{name}"
        assert name in schema.__all__, f"{family}.{name}"

