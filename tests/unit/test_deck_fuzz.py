"""Deck fuzzing: mutated shipped decks either check cleanly or fail with one deck error; never a traceback."""
from __future__ import annotations

import math
import re
from pathlib import Path

import yaml
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sphfem_cli.cli import main
from sphfem_cli.deck import loader

DECKS = sorted((Path(__file__).parents[2] / "decks").glob("*.yaml"))

REPLACEMENTS = [
    None, "text", "steel", "", -1, 0, 1, 3, 2.5, -2.5e3, 1e308, -1e308, math.nan, math.inf, -math.inf,
    10**12, True, [], {}, [1.0], [1.0, 2.0, 3.0, 4.0], {"type": "elastic"}, {"unknown": 1},
]


def _leaves(node, path=()):
    """Every (path, value) below the root, containers included."""
    if isinstance(node, dict):
        for key, value in node.items():
            yield path + (key,), value
            yield from _leaves(value, path + (key,))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            yield path + (i,), value
            yield from _leaves(value, path + (i,))


def _mutate(tree, path, action, replacement):
    parent = tree
    for key in path[:-1]:
        parent = parent[key]
    key = path[-1]
    if action == "delete":
        del parent[key]
    else:
        parent[key] = replacement


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_mutated_decks_exit_0_or_65(tmp_path, data):
    deck = data.draw(st.sampled_from(DECKS), label="deck")
    tree, _ = loader.loads(deck.read_text(), str(deck))
    leaves = list(_leaves(tree))
    path, _ = data.draw(st.sampled_from(leaves), label="where")
    action = data.draw(st.sampled_from(["delete", "replace"]), label="action")
    replacement = data.draw(st.sampled_from(REPLACEMENTS), label="value")
    _mutate(tree, path, action, replacement)
    text = yaml.safe_dump(tree, sort_keys=False, allow_unicode=True)
    mutated = tmp_path / deck.name
    mutated.write_text(text)

    result = CliRunner().invoke(main, ["check", str(mutated)])
    output = result.output or ""
    assert "Traceback" not in output and result.exception is None or isinstance(result.exception, SystemExit), output
    assert result.exit_code in (0, 65), f"{path} {action} {replacement!r}: exit {result.exit_code}: {output}"
    if result.exit_code == 65:
        lines = output.strip().splitlines()
        assert len(lines) == 1 and re.match(rf"^{re.escape(str(mutated))}:\d+:\d+: \S+: .+", lines[0]), output


def test_model_too_large_is_refused_before_allocation(tmp_path):
    deck = tmp_path / "huge.yaml"
    deck.write_text("""
dimension: 3
control: {end_time: 1.0}
materials:
  steel: {type: elastic, density: 7850.0, youngs_modulus: 2.1e11, poisson_ratio: 0.3}
sections:
  solid: {type: solid}
parts:
  cube: {material: steel, section: solid, geometry: {box: {min: [0, 0, 0], max: [1, 1, 1], divisions: [5000, 5000, 5000]}}}
""")
    result = CliRunner().invoke(main, ["check", str(deck)])
    assert result.exit_code == 65
    assert re.search(r":9:\d+: parts\.cube\.geometry: the model needs about \d+\.\d GiB, more than the", result.output)
