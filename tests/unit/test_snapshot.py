"""output.snapshot: the state of a Simulation captured by name and restored into a fresh build is the
same graph (same values, same sharing of arrays and objects), and both continue bit-identically."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from sphfem_cli.driver import load_model
from sphfem_cli.output.snapshot import SnapshotMismatch, capture, restore
from sphfem_cli.solver.explicit import Simulation

DECKS = sorted((Path(__file__).parents[2] / "decks").glob("*.yaml"))
# tens of seconds to build, or 8-17 s of CPU each here (7 December 2026): -m validation; their physics is covered
# by the smaller decks of each kind, and each still has its check and regression run in tests/regression
HEAVY = {"dam_break_3d.yaml", "underwater_explosion_3d_ale.yaml", "underwater_explosion_plate_3d_ale.yaml",
         "wedge_entry_zhao1996_ale.yaml"}


def _same(a, b) -> bool:
    (tree_a, arrays_a), (tree_b, arrays_b) = a, b
    return tree_a == tree_b and len(arrays_a) == len(arrays_b) and all(
        x.dtype == y.dtype and x.shape == y.shape and np.array_equal(x, y, equal_nan=True)
        for x, y in zip(arrays_a, arrays_b))


def _through_json(sim) -> tuple[dict, list[np.ndarray]]:
    tree, arrays = capture(sim)
    return json.loads(json.dumps(tree)), [a.copy() for a in arrays]


@pytest.mark.parametrize("deck", [pytest.param(d, marks=pytest.mark.validation) if d.name in HEAVY else d
                                  for d in DECKS], ids=lambda d: d.stem)
def test_every_shipped_deck_restores_to_the_same_state_and_continues_bit_identically(deck):
    sim = Simulation(load_model(str(deck)).model)
    for _ in range(3):
        sim.step()
    tree, arrays = _through_json(sim)
    fresh = Simulation(load_model(str(deck)).model)
    restore(tree, arrays, fresh)
    assert _same(capture(sim), capture(fresh))
    for _ in range(3):
        sim.step()
        fresh.step()
    assert _same(capture(sim), capture(fresh))


@pytest.fixture
def solid_deck(tmp_path):
    from tests.robustness import decks

    return decks.write(tmp_path, "solid")


def test_grown_lists_new_attributes_replaced_arrays_and_shared_references_are_restored(solid_deck):
    sim = Simulation(load_model(str(solid_deck)).model)
    sim.step()
    sim.eroded.append((1.0e-6, 3, "bar", "plastic strain"))  # a list that grew during the run
    sim.scratch = np.arange(5.0)  # an attribute set after __init__
    sim.state.hg_force = np.zeros((7, 2))  # an array replaced by one of another shape
    sim.twin = sim.state.v  # a second reference to one array
    tree, arrays = _through_json(sim)
    fresh = Simulation(load_model(str(solid_deck)).model)
    fresh.twin = np.zeros_like(fresh.state.v)
    fresh.scratch = None
    restore(tree, arrays, fresh)
    assert fresh.eroded == [(1.0e-6, 3, "bar", "plastic strain")]
    assert np.array_equal(fresh.scratch, np.arange(5.0)) and fresh.state.hg_force.shape == (7, 2)
    assert fresh.twin is fresh.state.v
    assert fresh.model is fresh.loads.model and fresh.curves is fresh.constraints.curves
    assert _same(capture(sim), capture(fresh))


def test_a_view_of_the_fresh_build_stays_a_view():
    class Holder:
        pass

    def build():
        h = Holder()
        h.buffer = np.zeros(10)
        h.head = h.buffer[:4]
        return h

    saved = build()
    saved.buffer[:] = np.arange(10.0)
    tree, arrays = _through_json(saved)
    fresh = build()
    restore(tree, arrays, fresh)
    fresh.buffer[0] = -1.0
    assert fresh.head[0] == -1.0 and np.array_equal(fresh.buffer[1:], np.arange(1.0, 10.0))


def test_a_state_of_another_model_is_a_mismatch(tmp_path, solid_deck):
    from tests.robustness import decks

    solid = Simulation(load_model(str(solid_deck)).model)
    tree, arrays = _through_json(solid)
    sph = Simulation(load_model(str(decks.write(tmp_path, "sph"))).model)
    with pytest.raises(SnapshotMismatch):
        restore(tree, arrays, sph)


def test_state_that_is_not_data_cannot_be_captured(solid_deck):
    sim = Simulation(load_model(str(solid_deck)).model)
    sim.callback = lambda: None
    with pytest.raises(TypeError, match="sim.callback"):
        capture(sim)
    del sim.callback
    sim.table = np.array([object()], dtype=object)
    with pytest.raises(TypeError, match="sim.table"):
        capture(sim)
