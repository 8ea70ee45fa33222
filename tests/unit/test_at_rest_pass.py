"""fem.at_rest (the initial zero step of solids at rest, in numpy: plane quad4, axisymmetric quad4, hex8) gives
bit for bit what the element kernels give, on every shipped deck it covers and on a distorted hex8 mesh; on the
others it declines. ale.at_rest (the ALE force kernels' pressures, bulk moduli, viscosity and stable step of the
initial state, in numpy) gives the force kernels' bits on every shipped ALE deck (all covered) and on synthetic
plane, ring and hex8 meshes in motion with every equation of state, mixed cells, voids, a burn scale and
cavitation. Bits: ndarray.tobytes() equality (assert_array_equal would let -0.0 pass for +0.0)."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from conftest import distorted_box
from sphfem_cli.driver import load_model
from sphfem_cli.fem import kernels as fem
from sphfem_cli.fem.at_rest import at_rest_element_pass
from sphfem_cli.materials.slots import NHIST, P_EOS_TYPE

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


def _pass(m, st, x=None, vol0=None):
    return at_rest_element_pass(
        st["x"] if x is None else x, st["v"], m.connectivity, m.element_active, m.element_material, m.element_section,
        m.material_type, m.material_param, m.section_param, m.volume0 if vol0 is None else vol0, 0.0, st["stress"],
        st["hg_force"], st["f_elem"], st["dt_elem"], st["vol"], st["q_visc"], m.axisymmetric)


def _kernel(m, st, x=None, vol0=None):
    if m.axisymmetric:
        from sphfem_cli.fem.axisymmetric import axisymmetric_element_forces as element_forces
    else:
        element_forces = fem.solid_element_forces
    element_forces(
        st["x"] if x is None else x, st["v"], m.connectivity, m.element_active, m.element_material, m.element_section,
        m.material_type, m.material_param, m.section_param, m.volume0 if vol0 is None else vol0, 0.0, st["stress"],
        st["hist"], st["energy"], st["hg_energy"], st["hg_force"], st["f_elem"], st["dt_elem"], st["vol"], st["q_visc"])


@pytest.mark.parametrize("deck", DECKS, ids=lambda d: d.stem)
def test_at_rest_pass_is_the_kernels_bit_for_bit(deck):
    m = load_model(str(deck)).model
    if m.n_elements == 0:
        pytest.skip("no solid elements")
    ours, ref = _state(m), _state(m)
    # covered at rest (the state here): every shipped solid (plane, axisymmetric, hex8) but those with an EOS
    eos = (m.material_param[m.element_material[m.element_active], P_EOS_TYPE] >= 0).any()
    if not _pass(m, ours):
        assert not any(ours["dt_elem"]), "declined but wrote"
        assert eos, f"{deck.name}: not covered"
        pytest.skip("not covered (a solid with an equation of state): the kernel's")
    assert not eos
    _kernel(m, ref)
    for name in ("dt_elem", "vol", "q_visc", "stress", "hist", "energy", "hg_energy", "hg_force"):
        assert _same_bits(ours[name], ref[name]), f"{deck.name}: {name} differs"
    f_ref = np.zeros((m.n_nodes, m.dim))
    fem.gather_nodal_forces(ref["f_elem"], m.node_elem_ptr, m.node_elem_idx, f_ref)
    assert _same_bits(np.zeros((m.n_nodes, m.dim)), f_ref), "the kernel's nodal forces at rest are not +0"
    assert not ours["f_elem"].any() and np.array_equal(ours["f_elem"], ref["f_elem"])


@pytest.mark.parametrize("deck", ["cantilever_3d", "taylor_bar_axisymmetric"])
def test_at_rest_pass_on_a_distorted_mesh_bit_for_bit(deck):
    """The shipped hex8 / axisymmetric mesh with every node moved by up to 0.1 of the shortest edge (V0 the
    undistorted volumes, so rho != rho0 too): every element a different shape, the same bits as the kernel."""
    m = load_model(str(DECKS[0].parent / f"{deck}.yaml")).model
    rng = np.random.default_rng(7)
    c, conn = m.coordinates, m.connectivity
    h = min(np.linalg.norm(c[conn[:, 1]] - c[conn[:, 0]], axis=1).min(),
            np.linalg.norm(c[conn[:, 3]] - c[conn[:, 0]], axis=1).min())
    x = m.coordinates + 0.2 * h * (rng.random(m.coordinates.shape) - 0.5)
    if m.axisymmetric:
        x[m.coordinates[:, 0] == 0.0, 0] = 0.0  # the axis stays the axis
    ours, ref = _state(m), _state(m)
    assert _pass(m, ours, x=x)
    _kernel(m, ref, x=x)
    for name in ("dt_elem", "vol", "q_visc"):
        assert _same_bits(ours[name], ref[name]), f"{deck} distorted: {name} differs"
    assert np.unique(ours["dt_elem"]).size > m.n_elements // 2  # the shapes differ


def test_at_rest_copies_of_the_kernels_tables():
    """fem.at_rest and ale.at_rest hold copies of numba modules' tables and constants (to import no numba)."""
    from sphfem_cli.ale import at_rest as ale_rest
    from sphfem_cli.ale import lagrange, ring_geometry
    from sphfem_cli.fem import at_rest as fem_rest
    from sphfem_cli.fem import axisymmetric

    assert fem_rest.TWO_PI == axisymmetric.TWO_PI and ale_rest.PI_3 == ring_geometry.PI_3
    assert ale_rest.RHO_VOID == lagrange.RHO_VOID and ale_rest.RHO_CAVITATED == lagrange.RHO_CAVITATED


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


# ----------------------------------------------------------------------------------------------- ALE (ale.at_rest)

# the two largest ALE meshes (1e5 nodes: most of this file's CPU in model set-up) run under -m validation; the hex8
# and plane passes stay covered by underwater_explosion_3d_ale and the other decks
_LARGE = {"underwater_explosion_plate_3d_ale", "wedge_entry_zhao1996_ale"}
ALE_DECKS = [pytest.param(d, marks=pytest.mark.validation) if d.stem in _LARGE else d
             for d in DECKS if "ale_multi_material" in d.read_text()]
_ALE_OUT = ("pres_m", "bulk_m", "q_elem", "dt_elem")


def _ale_pass(ale) -> tuple[bool, dict]:
    """ale.at_rest of the system's state into fresh arrays: (covered, arrays)."""
    from sphfem_cli.ale.at_rest import initial_element_pass

    out = {k: np.zeros_like(getattr(ale, k)) for k in _ALE_OUT}
    opt = ale.options
    covered = initial_element_pass(ale.x, ale.velocity, ale.conn, ale.vol_m, ale.mass_m, ale.ener_m, ale.e_lag,
                                   ale.mat_eos, ale.mat_q, ale.mat_rho0, opt.q1, opt.q2, opt.phi_eps, ale.pscale,
                                   ale.pressure_cutoff, ale.axisymmetric, out["pres_m"], out["bulk_m"], out["q_elem"],
                                   out["dt_elem"])
    return covered, out


def _ale_against_kernel(ale, what: str) -> dict:
    covered, out = _ale_pass(ale)
    assert covered, f"{what}: not covered"
    ale._forces()  # the force kernel of the geometry (plane, ring, hex8)
    for name in _ALE_OUT:
        assert _same_bits(out[name], getattr(ale, name)), f"{what}: {name} differs"
    return out


@pytest.mark.parametrize("deck", ALE_DECKS, ids=lambda d: d.stem)
def test_ale_initial_pass_is_the_force_kernels_bit_for_bit(deck):
    """Every shipped ALE deck's initial state, as the loop builds it (boundaries, burn), is covered: the bird decks
    in motion (a bird at 100 m/s in void, r-z, Tait water), the explosions (JWL, Gruneisen with a cut-off, burn;
    plane, r-z and hex8) and the rest at rest."""
    from sphfem_cli.solver.ale_domain import AleDomain

    model = load_model(str(deck)).model
    ale = AleDomain(model, model.options.ale).system
    ale._burn_scale()
    _ale_against_kernel(ale, deck.name)


def _fluid(eos, density: float, explosive: bool = False) -> np.ndarray:
    from sphfem_cli.deck.schema import materials as sm
    from sphfem_cli.materials.tables import pack_material

    mat = (sm.HighExplosive(type="high_explosive", density=density, detonation_velocity=6930.0, eos="e") if explosive
           else sm.Fluid(type="fluid", density=density, eos="e"))
    return pack_material(mat, eos)[1]


def _ale_system(geometry: str, kind: str, seed: int):
    """A perturbed box (143 quads or rings, 210 hex8) in random motion (20 m/s: compression and expansion) holding
    kind = "general": Gruneisen water (down to 0.4 rho0: cavitated under the -1e5 cut-off), JWL products (a random
    burn scale), Tait water, a linear polynomial (tension and compression) and void, at random fractions with pure,
    mixed and empty cells (the general ``_mixture_pressure`` path); "one gas" (``gas_block``); "two gases"
    (``two_gas_block``)."""
    from sphfem_cli.ale import AleOptions, AleSystem
    from sphfem_cli.deck.schema import materials as sm
    from sphfem_cli.materials.tables import gas_row

    rng = np.random.default_rng(seed)
    axi = geometry == "ring"
    nodes, conn = distorted_box(rng, geometry)
    n = len(conn)
    if kind == "general":
        rows = [_fluid(sm.Gruneisen(type="gruneisen", c=1480.0, s1=1.92, gamma0=0.28), 1000.0),
                _fluid(sm.JWL(type="jwl", A=3.712e11, B=3.231e9, R1=4.15, R2=0.95, omega=0.30, e0=7.0e9), 1630.0,
                       explosive=True),
                _fluid(sm.Tait(type="tait", reference_density=1000.0, sound_speed=1483.0, gamma=7.0), 1000.0),
                _fluid(sm.LinearPolynomial(type="linear_polynomial", c0=1e5, c1=2.2e9, c2=5e9, c3=1e9, c4=0.3, c5=0.1,
                                           c6=0.05), 1000.0),
                None]
        rho = np.stack([1000.0 * rng.uniform(0.4, 1.1, n), 1630.0 * rng.uniform(0.3, 1.2, n),
                        1000.0 * rng.uniform(0.99, 1.01, n), 1000.0 * rng.uniform(0.95, 1.05, n), np.zeros(n)], 1)
        energy = np.stack([1e4 * rng.random(n), 4e6 * rng.uniform(0.5, 1.5, n), np.zeros(n), 1e3 * rng.random(n),
                           np.zeros(n)], 1)
    elif kind == "one gas":
        rows = [gas_row(1.4, 1.2)]
        rho, energy = 1.2 * rng.uniform(0.7, 1.3, (n, 1)), 2.5e5 * rng.uniform(0.5, 1.5, (n, 1))
    else:
        rows = [gas_row(4.4, 1000.0, 6e8), gas_row(1.4, 1.2)]
        rho = np.stack([1000.0 * rng.uniform(0.99, 1.01, n), 1.2 * rng.uniform(0.7, 1.3, n)], 1)
        energy = np.stack([1.6e6 * rng.uniform(0.9, 1.1, n), 2.5e5 * rng.uniform(0.5, 1.5, n)], 1)
    k = len(rows)
    fractions = rng.random((n, k)) * (rng.random((n, k)) < 0.6)  # about 40 % of each material absent
    fractions[np.arange(n), rng.integers(0, k, n)] += 0.05  # no cell empty of all
    fractions[: n // 4] = np.eye(k)[rng.integers(0, k, n // 4)]  # pure cells
    ale = AleSystem(nodes, conn, rows, fractions, rho, energy=energy,
                    velocity=20.0 * rng.standard_normal(nodes.shape),
                    options=AleOptions(pressure_cutoff=-1e5 if kind == "general" else None), axisymmetric=axi)
    ale.e_lag[:] = 1e-3 * rng.standard_normal(ale.e_lag.shape) * ale.ener_m / np.maximum(ale.mass_m, 1e-300)
    if kind == "general":
        ale.pscale[:, 1] = rng.random(n)  # the JWL products' burn fraction
    return ale


@pytest.mark.parametrize("kind", ["general", "one gas", "two gases"])
@pytest.mark.parametrize("geometry", ["plane", "ring", "hex8"])
def test_ale_initial_pass_in_motion_bit_for_bit(geometry, kind):
    ale = _ale_system(geometry, kind, seed=3)
    out = _ale_against_kernel(ale, f"{geometry}, {kind}")
    assert (out["q_elem"] > 0.0).any() and (out["q_elem"] == 0.0).any()  # compression and expansion
    assert np.isfinite(out["dt_elem"]).all()
    if kind == "general":
        present = out["bulk_m"] > 0.0
        rho = ale.mass_m / np.where(ale.vol_m > 0.0, ale.vol_m, 1.0)
        assert (present[:, 0] & (rho[:, 0] < 500.0)).any()  # cavitated Gruneisen water
        assert (present[:, 3] & (rho[:, 3] < 1000.0)).any() and (present[:, 3] & (rho[:, 3] > 1000.0)).any()
        assert ((ale.vol_m > 0.0).sum(axis=1) > 2).any()  # mixed cells of three and more


def test_ale_initial_pass_declines_a_non_finite_state():
    """A NaN energy in one cell: the pass writes nothing and leaves the state to the kernel (and its messages)."""
    ale = _ale_system("plane", "one gas", seed=5)
    ale.ener_m[7, 0] = np.nan
    for name in _ALE_OUT:
        getattr(ale, name)[:] = 0.0
    covered, out = _ale_pass(ale)
    assert not covered and not any(out[k].any() for k in _ALE_OUT)
    assert not ale._initial_pass() and not ale.dt_elem.any()


def test_ale_stable_dt_before_and_after_the_first_step():
    """AleSystem.stable_dt takes the pass before the first step (no force kernel run: f_elem untouched) and the
    kernel after it; the first step runs the force kernel itself, so the run is the kernel's."""
    ale = _ale_system("plane", "two gases", seed=6)
    dt0 = ale.stable_dt(0.5)
    assert not ale.f_elem.any() and ale._fresh_state and not ale._fresh
    ale.step(dt0)
    assert ale.f_elem.any() and not ale._fresh_state
    assert np.isfinite(ale.stable_dt(0.5)) and ale._fresh
