"""LS-DYNA keyword meshes (.k) as geometry.file: *NODE, *ELEMENT_SOLID, *ELEMENT_SHELL, *PART headings
and *SET_NODE_LIST become nodes, elements and sets; what cannot be read is one deck error."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from sphfem_cli import api
from sphfem_cli.model.mesh import read_mesh

DATA = Path(__file__).resolve().parents[1] / "data"


def test_solids_parts_and_node_sets():
    m = read_mesh(DATA / "hex_2x1x1.k", 3)
    inp = read_mesh(DATA / "hex_2x1x1.inp", 3)
    assert np.array_equal(m.nodes, inp.nodes) and np.array_equal(m.elements, inp.elements)  # flipped one re-ordered
    assert set(m.element_sets) == {"part_1", "right_half"}  # a *PART heading names its set
    assert np.array_equal(m.element_sets["right_half"], [1])
    assert np.array_equal(np.sort(m.node_sets["set_7"]), np.sort(inp.node_sets["fixed"]))


def test_shells_are_the_2d_mesh():
    m = read_mesh(DATA / "quad_3x2_shells.k", 2)
    assert m.nodes.shape == (12, 2) and m.elements.shape == (6, 4)
    assert np.allclose(m.nodes.max(axis=0), [1.5, 0.5])


def _deck(mesh: Path) -> dict:
    return {"dimension": 3, "control": {"end_time": 1.0e-6},
            "materials": {"steel": {"type": "elastic", "density": 7850.0, "youngs_modulus": 2.1e11,
                                    "poisson_ratio": 0.3}},
            "sections": {"solid": {"type": "solid"}},
            "parts": {"brick": {"material": "steel", "section": "solid", "geometry": {"file": {"file": str(mesh)}}}}}


def test_a_deck_runs_on_a_keyword_mesh_and_uses_its_sets(tmp_path):
    deck = _deck(DATA / "hex_2x1x1.k")
    deck["boundaries"] = [{"type": "fixed", "set": "brick.set_7"}]  # a set of the file: <part>.<set>
    deck["initial"] = [{"type": "velocity", "set": "brick.right_half", "velocity": [0.0, 0.0, 1.0]}]
    loaded = api.load(deck, base_dir=tmp_path)
    assert np.array_equal(np.sort(loaded.model.node_sets["brick.set_7"]), [0, 3, 6, 9])
    result = api.run(loaded, tmp_path / "run")
    assert result.completed, result.message
    deck["boundaries"] = [{"type": "fixed", "set": "brick.clamp"}]
    with pytest.raises(api.DeckProblem, match=r"boundaries.0.set: the mesh file of part 'brick' has no set "
                                              r"'clamp' \(its sets: part_1, right_half, set_7\)"):
        api.load(deck, base_dir=tmp_path)


@pytest.mark.parametrize("text, why", [
    ("*NODE\nabc def\n*ELEMENT_SOLID\n", "a card that cannot be read: .*invalid literal .*'abc def'"),
    ("*ELEMENT_SOLID\n", "no \\*NODE keyword with nodes"),
    ("*NODE\n1,0,0,0\n2,1,0,0\n*ELEMENT_SOLID\n1,1,1,2,3,4,5,6,7,8\n", "names node 3, which \\*NODE does not define"),
    ("*NODE\n" + "".join(f"{i},{i % 2},{i // 2 % 2},{i // 4}\n" for i in range(1, 9))
     + "*ELEMENT_SOLID\n1,1,1,2,4,3,5,6,8,8\n", "repeats a node"),
    ("*NODE\n1,0,0,0\n", "no \\*ELEMENT_SOLID or \\*ELEMENT_SHELL"),
])
def test_bad_keyword_files_are_one_deck_error(tmp_path, text, why):
    mesh = tmp_path / "bad.k"
    mesh.write_text(text)
    with pytest.raises(api.DeckProblem, match=why) as err:
        api.load(_deck(mesh), base_dir=tmp_path)
    assert "\n" not in err.value.message and err.value.message.startswith(str(tmp_path / "deck-from-python.yaml:"))
