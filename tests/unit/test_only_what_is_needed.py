"""A scene pays only for the physics it has: a deck without ALE parts compiles no ALE kernel, and
likewise for SPH, FEM and contact (issue 5). The element geometry FEM and ALE share (fem/geometry.py)
belongs to both.

Each deck runs a few steps in a fresh interpreter, which then reports the sphfem kernel modules it
imported and the compiled kernels (numba dispatchers with at least one signature) among them.
"""
from __future__ import annotations

import functools
import json
import subprocess
import sys
from pathlib import Path

import pytest

DECKS = Path(__file__).resolve().parents[2] / "decks"

_PROBE = r"""
import json, sys
from sphfem_cli.driver import load_model
from sphfem_cli.solver.explicit import Simulation
sim = Simulation(load_model(sys.argv[1]).model)
for _ in range(3):
    sim.step()
report = {}
for name in ("fem", "sph", "ale", "contact"):
    # the kernel modules of the folder: those that define numba dispatchers
    # fem/geometry.py is the element geometry FEM and ALE share (an ALE deck compiles it on a cold cache)
    mods = [m for key, m in list(sys.modules.items()) if key.startswith(f"sphfem_cli.{name}.")
            and key != "sphfem_cli.fem.geometry" and any(
        getattr(getattr(v, "py_func", None), "__module__", None) == key for v in vars(m).values())]
    compiled = sorted(k for m in mods for k, v in vars(m).items()
                      if getattr(v, "signatures", None) and v.py_func.__module__ == m.__name__)
    report[name] = {"imported": bool(mods), "compiled": compiled}
print(json.dumps(report))
"""


@functools.cache
def _compiled(deck: Path) -> dict:
    """The report of `deck`'s fresh interpreter; one interpreter per deck, shared by the tests that read it."""
    out = subprocess.run([sys.executable, "-c", _PROBE, str(deck)], capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    return json.loads(out.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize("deck, needed", [
    ("cantilever_2d.yaml", {"fem"}),
    ("dam_break_2d.yaml", {"sph"}),
    ("water_air_shock_tube.yaml", {"ale"}),
    ("hydrostatic_plate_sph.yaml", {"fem", "sph", "contact"}),
])
def test_a_deck_compiles_only_its_physics(deck, needed):
    report = _compiled(DECKS / deck)
    for name, seen in report.items():
        if name in needed:
            assert seen["compiled"], f"{deck}: expected {name} kernels to run"
        else:
            assert not seen["imported"] or not seen["compiled"], f"{deck} compiled {name} kernels {seen['compiled']}"
    # Modules of physics a deck does not have are not even imported (import costs, cached loads).
    for name in ("sph", "ale", "contact"):
        assert name in needed or not report[name]["imported"], f"{deck} imported {name} kernels"


# ALE kernels that only one dimension runs: the *_3d ones, and their 2D counterparts (face_fluxes serves both)
_ALE_2D_ONLY = {"lagrange_forces", "nodal_update", "lagrange_energy", "finish_remap_nodes", "quad_area"}


@pytest.mark.parametrize("deck, dim", [("water_air_shock_tube.yaml", 2), ("underwater_explosion_3d_ale.yaml", 3)])
def test_an_ale_deck_compiles_only_its_dimension(deck, dim):
    report = _compiled(DECKS / deck)
    compiled = set(report["ale"]["compiled"])
    three = {k for k in compiled if k.endswith("_3d")}
    if dim == 2:
        assert not three, f"{deck} compiled 3D ALE kernels {sorted(three)}"
    else:
        assert three and not (compiled & _ALE_2D_ONLY), f"{deck} compiled 2D ALE kernels {sorted(compiled & _ALE_2D_ONLY)}"
    assert not report["fem"]["compiled"] and not report["sph"]["compiled"]


_AXISYMMETRIC = {"axisymmetric_element_forces"}  # fem/axisymmetric.py (the initial ring volumes: numpy, model.mesh)
_SOLID_ELEMENTS = {"quad4_element_forces", "hex8_element_forces"}  # fem/kernels.py, the plane and 3D elements


@pytest.mark.parametrize("deck, axisymmetric", [("cantilever_2d.yaml", False), ("taylor_bar_axisymmetric.yaml", True)])
def test_only_an_axisymmetric_deck_compiles_the_axisymmetric_element(deck, axisymmetric):
    compiled = set(_compiled(DECKS / deck)["fem"]["compiled"])
    if axisymmetric:
        assert _AXISYMMETRIC <= compiled and not compiled & _SOLID_ELEMENTS, sorted(compiled)
    else:  # and the plane element alone: no hex8 code
        assert not (compiled & _AXISYMMETRIC), f"{deck} compiled axisymmetric kernels {sorted(compiled & _AXISYMMETRIC)}"
        assert "quad4_element_forces" in compiled and "hex8_element_forces" not in compiled, sorted(compiled)


# ale/axisymmetric.py: the ring forces (a twin); the other ring kernels are the quad4 ones' ring flag, and the initial
# ring volumes are numpy (ale.system.ring_volumes_set_up: no kernel ring_volumes)
_AXISYMMETRIC_ALE = {"lagrange_forces_rz"}
_RING_SHARED = {"lagrange_energy", "face_fluxes"}
_AXISYMMETRIC_ALE_DECK = """
title: axisymmetric ALE, a gas ring in a closed can
dimension: axisymmetric
control: {end_time: 1.0e-3}
equations_of_state:
  air: {type: ideal_gas, gamma: 1.4}
materials:
  air: {type: fluid, density: 1.0, eos: air}
sections:
  ale: {type: ale_multi_material}
parts:
  can:
    material: air
    section: ale
    geometry: {box: {min: [0.0, 0.0], max: [1.0, 1.0], divisions: [4, 4]}}
    fill:
      - {material: air, box: {min: [0.0, 0.25], max: [0.5, 0.75]}, pressure: 5.0e5}
boundaries:
  - {type: ale_boundary, part: can, sides: [right, bottom, top], condition: slip}
"""


@pytest.mark.parametrize("axisymmetric", [False, True])
def test_an_axisymmetric_deck_shares_the_plane_ale_kernels(axisymmetric, tmp_path):
    deck = DECKS / "water_air_shock_tube.yaml"
    if axisymmetric:
        deck = tmp_path / "can.yaml"
        deck.write_text(_AXISYMMETRIC_ALE_DECK)
    compiled = set(_compiled(deck)["ale"]["compiled"])
    if axisymmetric:
        assert _AXISYMMETRIC_ALE | _RING_SHARED <= compiled and "lagrange_forces" not in compiled, sorted(compiled)
        assert "ring_volumes" not in compiled, sorted(compiled)
    else:
        assert _RING_SHARED <= compiled and not (compiled & _AXISYMMETRIC_ALE), f"compiled {sorted(compiled)}"
    assert not {k for k in compiled if k.endswith("_3d")}, sorted(compiled)


_AXISYMMETRIC_SPH = {"axisymmetric_rates", "_axisymmetric_rates", "ring_smoothing_lengths",
                     "renormalise_ring_continuity"}  # sph/axisymmetric.py


@pytest.mark.parametrize("deck, axisymmetric", [
    ("dam_break_2d.yaml", False), ("underwater_explosion_sph.yaml", False),
    ("water_column_axisymmetric_sph.yaml", True), ("underwater_explosion_free_field_axisymmetric_sph.yaml", True)])
def test_only_an_axisymmetric_deck_compiles_the_axisymmetric_sph(deck, axisymmetric):
    compiled = set(_compiled(DECKS / deck)["sph"]["compiled"])
    explosive = "underwater" in deck  # the products' renormalised continuity: the plane or the r-z one
    if axisymmetric:
        assert {"_axisymmetric_rates", "ring_smoothing_lengths"} <= compiled and "_fluid_rates" not in compiled, sorted(compiled)
        assert ("renormalise_ring_continuity" in compiled) == explosive and "renormalise_continuity" not in compiled
    else:
        assert not (compiled & _AXISYMMETRIC_SPH), f"{deck} compiled axisymmetric kernels {sorted(compiled & _AXISYMMETRIC_SPH)}"
        assert ("renormalise_continuity" in compiled) == explosive, sorted(compiled)


_CHECK_PROBE = r"""
import json, sys
from sphfem_cli.cli import main
sys.argv = ["sphfem", "check", sys.argv[1]]
try:
    main()
except SystemExit as stop:
    assert not stop.code, stop.code
# every module of the package that defines a numba dispatcher, and numba itself
kernels = sorted(key for key, m in list(sys.modules.items()) if key.startswith("sphfem_cli.") and any(
    getattr(getattr(v, "py_func", None), "__module__", None) == key for v in vars(m).values()))
# the dispatchers compiled or loaded from the cache (with at least one signature)
compiled = sorted(k for key in kernels for k, v in vars(sys.modules[key]).items()
                  if getattr(v, "signatures", None) and v.py_func.__module__ == key)
print(json.dumps({"numba": "numba" in sys.modules, "kernels": kernels, "compiled": compiled}), file=sys.stderr)
"""


def _check(deck: Path) -> tuple[str, dict]:
    out = subprocess.run([sys.executable, "-c", _CHECK_PROBE, str(deck)], capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    assert "stable time step" in out.stdout
    return out.stdout, json.loads(out.stderr.strip().splitlines()[-1])


def test_check_of_a_solid_deck_at_rest_loads_no_kernel():
    """`sphfem check` of a plane-strain solid deck at rest gets its stable step from fem.at_rest: no
    kernel module is imported, nor numba (issue 17: check at most 3x `import numpy`)."""
    report = _check(DECKS / "cantilever_2d.yaml")[1]
    assert report == {"numba": False, "kernels": [], "compiled": []}, report


# the element force kernels: FEM plane / hex8 and axisymmetric, ALE plane, r-z and hex8
_FORCE_KERNELS = {"quad4_element_forces", "hex8_element_forces", "axisymmetric_element_forces", "lagrange_forces", "lagrange_forces_rz",
                  "lagrange_forces_3d"}


@pytest.mark.parametrize("deck", ["cantilever_3d.yaml", "water_air_shock_tube.yaml", "bird_strike_axisymmetric_ale.yaml",
                                  pytest.param("underwater_explosion_plate_3d_ale.yaml", marks=pytest.mark.validation)])
def test_check_takes_the_initial_stable_step_without_the_force_kernels(deck):
    """`sphfem check` of a hex8 solid deck at rest, of ALE decks at rest (plane; hex8 with a hex8 plate and
    non-reflecting sides, whose far-field pressure needs the initial pressures) and of the r-z ALE bird in motion
    (with its axisymmetric solid disc) gets the stable step and pressures from fem.at_rest and ale.at_rest: no
    force kernel is compiled or loaded (issue 17: 28-30 s of compiling on an empty cache before)."""
    report = _check(DECKS / deck)[1]
    assert not set(report["compiled"]) & _FORCE_KERNELS, report["compiled"]
