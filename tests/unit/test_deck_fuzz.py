"""Deck fuzzing: mutated decks either check (or run) cleanly or fail with one deck error; never a traceback.

The bases are the shipped decks plus two small fluid-structure decks with `contacts` and `couplings`
(tests/data/fuzz). A mutation deletes a key or list entry, or replaces a value with another type, a
name nothing defines, an extreme or non-finite number or an enormous size. `check` sees every
mutation; `run` sees mutations of the small decks, capped at RUN_STEP_CAP steps (a guard stop, exit 3,
is a valid outcome of a run: it is one line and a diagnosis, not a traceback).
"""
from __future__ import annotations

import math
import re
from pathlib import Path

import pytest
import yaml
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sphfem_cli.cli import main
from sphfem_cli.deck import loader

FUZZ_DIR = Path(__file__).parents[1] / "data" / "fuzz"
DECKS = sorted((Path(__file__).parents[2] / "decks").glob("*.yaml")) + sorted(FUZZ_DIR.glob("*.yaml"))
RUN_DECKS = sorted(FUZZ_DIR.glob("*.yaml"))
RUN_STEP_CAP = 60

REPLACEMENTS = [
    None, "text", "steel", "", -1, 0, 1, 3, 2.5, -2.5e3, 1e308, -1e308, math.nan, math.inf, -math.inf,
    10**12, True, [], {}, [1.0], [1.0, 2.0, 3.0, 4.0], {"type": "elastic"}, {"unknown": 1},
    "no_such_name", 5e-324, 1e-300, -0.0, 10**9, [10**6, 10**6], [10**9, 1], [math.nan, 0.0], [math.inf, 1.0],
    {"type": "nodes_to_surface", "nodes": "no_such_name", "surface": "block"},
    {"type": "lagrange_in_solid", "structure": "tank", "fluid": "plate"},
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


CASES = {"check": 0, "run": 0}  # fuzz cases run in this session (printed by the last test)


def _mutated(tmp_path, data, decks) -> tuple[Path, str]:
    deck = data.draw(st.sampled_from(decks), label="deck")
    tree, _ = loader.loads(deck.read_text(), str(deck))
    leaves = list(_leaves(tree))
    path, _ = data.draw(st.sampled_from(leaves), label="where")
    action = data.draw(st.sampled_from(["delete", "replace"]), label="action")
    replacement = data.draw(st.sampled_from(REPLACEMENTS), label="value")
    _mutate(tree, path, action, replacement)
    text = yaml.safe_dump(tree, sort_keys=False, allow_unicode=True)
    mutated = tmp_path / deck.name
    mutated.write_text(text)
    return mutated, f"{path} {action} {replacement!r}"


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_mutated_decks_exit_0_or_65(tmp_path, data):
    mutated, what = _mutated(tmp_path, data, DECKS)
    CASES["check"] += 1

    result = CliRunner().invoke(main, ["check", str(mutated)])
    output = result.output or ""
    assert "Traceback" not in output and result.exception is None or isinstance(result.exception, SystemExit), output
    assert result.exit_code in (0, 65), f"{what}: exit {result.exit_code}: {output}"
    if result.exit_code == 65:
        lines = output.strip().splitlines()
        assert len(lines) == 1 and re.match(rf"^{re.escape(str(mutated))}:\d+:\d+: \S+: .+", lines[0]), output


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_mutated_decks_run_or_exit_65(tmp_path, data, monkeypatch_steps):
    mutated, what = _mutated(tmp_path, data, RUN_DECKS)
    CASES["run"] += 1
    result = CliRunner().invoke(main, ["run", "-q", str(mutated), "-o", str(tmp_path / "out"), "--overwrite"])
    output = result.output or ""
    assert "Traceback" not in output, output
    assert result.exception is None or isinstance(result.exception, SystemExit), f"{what}: {result.exception!r}"
    assert result.exit_code in (0, 3, 65), f"{what}: exit {result.exit_code}: {output}"
    lines = output.strip().splitlines()
    if result.exit_code == 65:
        assert len(lines) == 1 and re.match(rf"^{re.escape(str(mutated))}:\d+:\d+: \S+: .+", lines[0]), output
    if result.exit_code == 3:
        assert len(lines) == 1 and lines[0].startswith("run stopped: "), output
        assert (tmp_path / "out" / "diagnostics.txt").read_text().startswith("guard: ")


@pytest.fixture(scope="module")
def monkeypatch_steps():
    """Cap every fuzzed run at RUN_STEP_CAP steps (a mutated end_time may ask for billions)."""
    from sphfem_cli.solver import explicit

    patch = pytest.MonkeyPatch()
    original = explicit.Simulation.step

    def capped(self, stop=None):
        if self.state.step >= RUN_STEP_CAP:
            raise explicit.RunStopped(f"fuzz step cap {RUN_STEP_CAP} reached", "fuzz_cap")
        original(self, stop)

    patch.setattr(explicit.Simulation, "step", capped)
    yield
    patch.undo()


def test_fuzz_case_count():
    """Reports how many fuzz cases this session ran (run with -s to see it)."""
    print(f"deck fuzzing: {CASES['check']} check cases, {CASES['run']} run cases")
    assert CASES["check"] == 0 or CASES["check"] >= 100


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
