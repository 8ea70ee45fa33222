"""fem.at_rest (the initial zero step of plane-strain solids at rest, in numpy) gives bit for bit what
the element kernel gives, on every shipped deck it covers; on the others it declines."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from sphfem_cli.driver import load_model
from sphfem_cli.fem import kernels as fem
from sphfem_cli.fem.at_rest import at_rest_element_pass
from sphfem_cli.materials.slots import NHIST

DECKS = sorted((Path(__file__).resolve().parents[2] / "decks").glob("*.yaml"))


def _state(m):
    """The arrays of solver.solid_domain.State 0 before the element pass (zero velocity)."""
    e, n, dim = m.n_elements, m.n_nodes, m.dim
    return dict(x=m.coordinates.copy(), v=np.zeros((n, dim)), stress=np.zeros((e, 6)),
                hist=np.zeros((e, NHIST)), energy=np.zeros(e), hg_energy=np.zeros(e),
                hg_force=np.zeros((e, 1 if dim == 2 else 4, dim)), f_elem=np.zeros((e, m.nodes_per_element, dim)),
                dt_elem=np.zeros(e), vol=m.volume0.copy(), q_visc=np.zeros(e))


def _same_bits(a, b) -> bool:
    return a.shape == b.shape and a.tobytes() == b.tobytes()


@pytest.mark.parametrize("deck", [d for d in DECKS if "3d" not in d.name], ids=lambda d: d.stem)
def test_at_rest_pass_is_the_kernels_bit_for_bit(deck):
    m = load_model(str(deck)).model
    if m.n_elements == 0 or m.dim != 2:
        pytest.skip("no plane-strain solid elements")
    ours, ref = _state(m), _state(m)
    covered = not m.axisymmetric and at_rest_element_pass(
        ours["x"], ours["v"], m.connectivity, m.element_active, m.element_material, m.element_section,
        m.material_type, m.material_param, m.section_param, m.volume0, 0.0, ours["stress"], ours["hg_force"],
        ours["f_elem"], ours["dt_elem"], ours["vol"], ours["q_visc"])
    if not covered:
        assert not any(ours["dt_elem"]), "declined but wrote"
        pytest.skip("not covered (EOS material, axisymmetric, ...): the kernel's")
    fem.solid_element_forces(
        ref["x"], ref["v"], m.connectivity, m.element_active, m.element_material, m.element_section,
        m.material_type, m.material_param, m.section_param, m.volume0, 0.0, ref["stress"], ref["hist"],
        ref["energy"], ref["hg_energy"], ref["hg_force"], ref["f_elem"], ref["dt_elem"], ref["vol"], ref["q_visc"])
    for name in ("dt_elem", "vol", "q_visc", "stress", "hist", "energy", "hg_energy", "hg_force"):
        assert _same_bits(ours[name], ref[name]), f"{deck.name}: {name} differs"
    f_ref = np.zeros((m.n_nodes, 2))
    fem.gather_nodal_forces(ref["f_elem"], m.node_elem_ptr, m.node_elem_idx, f_ref)
    assert _same_bits(np.zeros((m.n_nodes, 2)), f_ref), "the kernel's nodal forces at rest are not +0"
    assert not ours["f_elem"].any() and np.array_equal(ours["f_elem"], ref["f_elem"])


def test_at_rest_pass_declines_a_moving_state():
    m = load_model(str(DECKS[0].parent / "cantilever_2d.yaml")).model
    st = _state(m)
    st["v"][3, 1] = 1.0
    assert not at_rest_element_pass(st["x"], st["v"], m.connectivity, m.element_active, m.element_material,
                                    m.element_section, m.material_type, m.material_param, m.section_param,
                                    m.volume0, 0.0, st["stress"], st["hg_force"], st["f_elem"], st["dt_elem"],
                                    st["vol"], st["q_visc"])
    assert not st["dt_elem"].any()


def test_at_rest_pass_covers_plane_stress_bit_for_bit(tmp_path):
    """The shipped plane-strain cantilever with its section made plane_stress: the at-rest step is the kernel's
    to the bit, and longer than the plane-strain one by sqrt((K + 4G/3) / (E/(1 - nu^2))) (materials.kernels
    plane_stress_sound_speed)."""
    import yaml

    deck = yaml.safe_load((DECKS[0].parent / "cantilever_2d.yaml").read_text())
    for section in deck["sections"].values():
        section["formulation"] = "plane_stress"
    path = tmp_path / "cantilever_plane_stress.yaml"
    path.write_text(yaml.safe_dump(deck, sort_keys=False))
    m = load_model(str(path)).model
    strain = load_model(str(DECKS[0].parent / "cantilever_2d.yaml")).model
    ours, ref, plane_strain = _state(m), _state(m), _state(strain)

    def args(mm, s):
        return (s["x"], s["v"], mm.connectivity, mm.element_active, mm.element_material, mm.element_section,
                mm.material_type, mm.material_param, mm.section_param, mm.volume0, 0.0, s["stress"], s["hg_force"],
                s["f_elem"], s["dt_elem"], s["vol"], s["q_visc"])

    assert at_rest_element_pass(*args(m, ours)) and at_rest_element_pass(*args(strain, plane_strain))
    fem.solid_element_forces(
        ref["x"], ref["v"], m.connectivity, m.element_active, m.element_material, m.element_section,
        m.material_type, m.material_param, m.section_param, m.volume0, 0.0, ref["stress"], ref["hist"],
        ref["energy"], ref["hg_energy"], ref["hg_force"], ref["f_elem"], ref["dt_elem"], ref["vol"], ref["q_visc"])
    for name in ("dt_elem", "vol", "q_visc", "stress", "hist", "energy", "hg_energy", "hg_force"):
        assert _same_bits(ours[name], ref[name]), f"plane stress: {name} differs"
    nu = deck["materials"][m.material_names[0]]["poisson_ratio"]
    expected = np.sqrt((1 - nu) ** 2 / (1 - 2 * nu))
    assert np.allclose(ours["dt_elem"] / plane_strain["dt_elem"], expected, rtol=1e-12)
