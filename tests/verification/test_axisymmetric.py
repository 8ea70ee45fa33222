"""Axisymmetric quad4 solids (``dimension: axisymmetric``, fem/axisymmetric.py) against exact solutions.

- hydrostatic patch: a solid cylinder with its axis under a uniform pressure on side and top has the
  uniform stress -p and u = -p (1 - 2 nu) x / E; the one-point element with the ring pressure loads
  must reproduce it to round-off (1e-6 relative, the relaxation's stopping level);
- Lame thick cylinder (plane strain, u_z = 0), internal pressure: radial displacement and hoop stress
  within 1 % at 16 and 32 radial elements, and the hoop error falling at an observed order >= 1.5;
- thick spherical shell (meridian quarter annulus; axis and equator), internal pressure: u_R and hoop
  stress within 1 % at 16 elements through the wall; the max-norm errors fall at an observed order
  >= 0.9 (they sit in the elements on the axis, where the one-point volume-weighted form is first order);
- thin free rod (R/L = 0.01), step velocity at one end: the front's speed within 2 % of the bar speed
  sqrt(E/rho) (a thin rod rather than a laterally constrained one, so that the hoop strain, the
  Poisson contraction, is what makes the speed; the constrained rod would give the P-wave speed
  whatever the hoop term did; the two differ by 16 % at nu = 0.3);
- free rod: axial momentum conserved to round-off (1e-12 of the initial) through a sharp internal impact
  and a smooth motion, no node off the axis crosses it, and the solver's energy balance converging with dt
  (the element's own power identity, sum f . v = -V sigma : d, to round-off: test_fem_kernels.py).
Quasi-static cases by dynamic relaxation (axisymmetric_cases.relax).
"""
from __future__ import annotations

import numpy as np
import pytest

import axisymmetric_cases as cases
from sphfem_cli.materials.slots import H_EPS
from conftest import crossing_times

pytestmark = pytest.mark.usefixtures("single_thread")


def test_hydrostatic_patch_with_axis(sim_from_deck):
    sim = sim_from_deck(cases.hydrostatic_cylinder_deck(6))
    assert cases.relax(sim, cases.CP, 1.0 / cases.CP) > 0
    x0 = sim.model.coordinates
    u_exact = -cases.PRESSURE * (1 - 2 * cases.NU) / cases.E * x0
    assert np.abs(sim.state.x - x0 - u_exact).max() <= 1e-6 * np.abs(u_exact).max()
    assert np.abs(sim.state.stress[:, :3] + cases.PRESSURE).max() <= 1e-6 * cases.PRESSURE
    assert np.abs(sim.state.stress[:, 3]).max() <= 1e-6 * cases.PRESSURE


def _lame(sim):
    m, st = sim.model, sim.state
    r = m.coordinates[:, 0]
    u_exact, _ = cases.lame_cylinder_exact(r)
    rc = m.coordinates[m.connectivity, 0].mean(axis=1)
    _, hoop_exact = cases.lame_cylinder_exact(rc)
    err_u = np.abs(st.x[:, 0] - r - u_exact).max() / np.abs(u_exact).max()
    err_hoop = np.abs(st.stress[:, 2] - hoop_exact).max() / hoop_exact.max()
    return err_u, err_hoop


def test_lame_thick_cylinder(sim_from_deck):
    levels = (8, 16, 32)
    errors = []
    for n in levels:
        sim = sim_from_deck(cases.lame_cylinder_deck(n))
        assert cases.relax(sim, cases.CP / cases.OUTER, (cases.OUTER - cases.INNER) / cases.CP) > 0
        errors.append(_lame(sim))
    err_u, err_hoop = np.array(errors).T
    assert (err_u[1:] < 0.01).all() and (err_hoop[1:] < 0.01).all(), errors
    assert cases.observed_order([1.0 / n for n in levels], err_hoop) >= 1.5, errors


def _sphere(sim):
    m, st = sim.model, sim.state
    radius = np.linalg.norm(m.coordinates, axis=1)
    u_exact, _ = cases.spherical_shell_exact(radius)
    centre = np.linalg.norm(m.coordinates[m.connectivity].mean(axis=1), axis=1)
    _, hoop_exact = cases.spherical_shell_exact(centre)
    err_u = np.abs(np.linalg.norm(st.x, axis=1) - radius - u_exact).max() / np.abs(u_exact).max()
    err_hoop = np.abs(st.stress[:, 2] - hoop_exact).max() / hoop_exact.max()
    return err_u, err_hoop


def test_thick_spherical_shell(sim_from_deck, tmp_path):
    levels = (4, 8, 16)
    errors = []
    for n in levels:
        mesh = tmp_path / f"sphere_{n}.vtu"
        cases.spherical_shell_mesh(mesh, n)
        sim = sim_from_deck(cases.spherical_shell_deck(str(mesh)))
        assert (sim.model.coordinates[:, 0] == 0.0).sum() == n + 1  # the axis nodes, u_r = 0 by themselves
        assert cases.relax(sim, cases.CP / cases.OUTER, (cases.OUTER - cases.INNER) / cases.CP) > 0
        errors.append(_sphere(sim))
    err_u, err_hoop = np.array(errors).T
    assert err_u[-1] < 0.01 and err_hoop[-1] < 0.01, errors
    sizes = [1.0 / n for n in levels]
    assert cases.observed_order(sizes, err_u) >= 0.9 and cases.observed_order(sizes, err_hoop) >= 0.9, errors


def test_thin_rod_bar_wave_speed(sim_from_deck):
    sim = sim_from_deck(cases.rod_wave_deck(2, 400))
    m = sim.model
    n1, n2 = m.node_sets["station1"], m.node_sets["station2"]
    assert len(n1) == len(n2) == 3
    w1, w2 = m.mass[n1] / m.mass[n1].sum(), m.mass[n2] / m.mass[n2].sum()
    times, v1, v2 = [0.0], [0.0], [0.0]
    while sim.state.time < sim.control.end_time * (1 - 1e-9):
        sim.step()
        times.append(sim.state.time)
        v1.append(float(w1 @ sim.state.v[n1, 1]))
        v2.append(float(w2 @ sim.state.v[n2, 1]))
    t = np.array(times)
    t1 = crossing_times(t, np.array(v1), 0.5, rising=True)[0]
    t2 = crossing_times(t, np.array(v2), 0.5, rising=True)[0]
    speed = 0.5 * cases.ROD_LENGTH / (t2 - t1)
    print(f"front speed / sqrt(E/rho) - 1 = {speed / cases.C0 - 1.0:+.4f}, / P-wave speed - 1 = {speed / cases.CP - 1.0:+.4f}")
    assert abs(speed / cases.C0 - 1.0) < 0.02, (speed, cases.C0, cases.CP)


def _axial_momentum_and_energy_error(sim):
    """Run to the end; the initial axial momentum and kinetic energy, the largest |axial momentum -
    initial| and the largest change of the solver's balance KE + IE + HG - work from its value after
    the first step (the start, v^0 taken for v^{1/2}, left out)."""
    m, st = sim.model, sim.state
    p0 = float(m.mass @ st.v[:, 1])
    ke0 = 0.5 * float(m.mass @ (st.v * st.v).sum(axis=1))
    worst_p = worst_e = 0.0
    e1 = None
    while st.time < sim.control.end_time * (1 - 1e-9):
        sim.step()
        worst_p = max(worst_p, abs(float(m.mass @ st.v[:, 1]) - p0))
        row = sim.solids.energies()
        balance = row.kinetic + row.internal + row.hourglass - row.work
        e1 = balance if e1 is None else e1
        worst_e = max(worst_e, abs(balance - e1))
        assert (st.x[m.coordinates[:, 0] > 0.0, 0] > 0.0).all()  # nothing crosses the axis
    return p0, ke0, worst_p, worst_e


def test_free_rod_impact_conserves_axial_momentum(sim_from_deck):
    """A sharp internal impact: axial momentum to round-off."""
    p0, _, worst_p, _ = _axial_momentum_and_energy_error(sim_from_deck(cases.rod_impact_deck(4.0e-5)))
    assert p0 != 0.0 and worst_p <= 1e-12 * abs(p0)


def test_free_rod_energy_balance_converges(sim_from_deck):
    """A smooth start (axial v_z = 20 (1 - z/L)^2, radial v_r = 5 r/R m/s: hoop strain from the first
    step). The solver's energy balance (glstat: KE of the half-step velocities against the whole-step
    internal energy) is first order in dt, in plane strain as here: measured 3.0 % at timestep_scale
    0.9 and 1.2 % at 0.45 axisymmetric, 2.1 % and 0.9 % for the same rod in plane strain. Asked: under
    5 % and at least halved with dt. The element itself balances to round-off: test_fem_kernels'
    axisymmetric power identity."""
    errors = []
    for scale in (0.9, 0.45):
        sim = sim_from_deck(cases.rod_impact_deck(4.0e-5, scale, impact=False))
        x0 = sim.model.coordinates
        sim.state.v[:, 1] = 20.0 * (1.0 - x0[:, 1] / 0.1) ** 2
        sim.state.v[:, 0] = 5.0 * x0[:, 0] / 0.01
        p0, ke0, worst_p, worst_e = _axial_momentum_and_energy_error(sim)
        assert worst_p <= 1e-12 * abs(p0)
        errors.append(worst_e / ke0)
    assert errors[0] <= 0.05 and errors[0] / errors[1] >= 2.0, errors


def _thin_ring_deck(material: str) -> str:
    """A thin ring (r 1 to 1.002 m, 2 mm high, one element) whose inner nodes move out at 10 m/s (reached over 0.1 ms):
    hoop strain rate 10/s, the outer surface and the top free, z = 0 symmetric, so the stress is uniaxial hoop
    (sigma_rr ~ sigma_tt h / 2r = 1e-3 sigma_tt)."""
    return f"""
title: thin ring, uniaxial hoop stretch
dimension: axisymmetric
control: {{end_time: 1.0e-3}}
curves:
  ramp: {{points: [[0.0, 0.0], [1.0e-4, 1.0]]}}
materials:
  metal: {material}
sections:
  solid: {{type: solid}}
parts:
  ring: {{material: metal, section: solid, geometry: {{box: {{min: [1.0, 0.0], max: [1.002, 0.002], divisions: [1, 1]}}}}}}
sets:
  inner: {{type: node, part: ring, side: left}}
  bottom: {{type: node, part: ring, side: bottom}}
boundaries:
  - {{type: prescribed_velocity, set: inner, velocity: [10.0, null], curve: ramp}}
  - {{type: symmetry, set: bottom, normal: y}}
"""


@pytest.mark.parametrize("model", ["elastic_plastic", "johnson_cook"])
def test_plastic_models_in_hoop_stretch(sim_from_deck, model):
    """The material models take the hoop rate in slot zz: after 1 % hoop strain a perfectly plastic
    ring carries its yield stress as hoop stress, a Johnson-Cook one A + B eps_p^n times
    (1 + C ln(10/s / 1/s)) (0.3 K of adiabatic heating neglected), within 2 %, with eps_p the hoop
    strain less the elastic part sigma/E, within 2 %."""
    e, sy = 1.24e11, 2.5e8
    if model == "elastic_plastic":
        text = f"{{type: elastic_plastic, density: 8960.0, youngs_modulus: {e}, poisson_ratio: 0.34, yield_stress: {sy}}}"
    else:
        text = (f"{{type: johnson_cook, density: 8960.0, youngs_modulus: {e}, poisson_ratio: 0.34, A: 9.0e7, B: 2.92e8, "
                "n: 0.31, C: 0.025, m: 1.09, reference_strain_rate: 1.0, melt_temperature: 1356.0, room_temperature: 293.0, "
                "specific_heat: 383.0}")
    sim = sim_from_deck(_thin_ring_deck(text))
    while sim.state.time < sim.control.end_time * (1 - 1e-9):
        sim.step()
    m, st = sim.model, sim.state
    hoop_strain = np.log(st.x[m.connectivity[0], 0].mean() / m.coordinates[m.connectivity[0], 0].mean())
    assert 0.009 < hoop_strain < 0.0105
    s = st.stress[0]
    eps_p = st.hist[0, H_EPS]
    assert eps_p == pytest.approx(hoop_strain - s[2] / e, rel=0.02)
    flow = sy if model == "elastic_plastic" else (9.0e7 + 2.92e8 * eps_p ** 0.31) * (1 + 0.025 * np.log(10.0))
    assert s[2] == pytest.approx(flow, rel=0.02)
    assert abs(s[0]) < 0.01 * s[2] and abs(s[1]) < 0.01 * s[2]


def _critical_step(model) -> float:
    """2 / omega_max of the linearised mesh (finite differences of the element forces about the initial
    state, lumped masses, the axis and z = 0 conditions): the exact central-difference stability limit."""
    from sphfem_cli.fem.axisymmetric import axisymmetric_element_forces
    from sphfem_cli.fem.kernels import gather_nodal_forces
    from sphfem_cli.materials.slots import NHIST

    m = model
    n, ne = m.n_nodes, m.n_elements
    stiffness = np.zeros((2 * n, 2 * n))
    eps = 1e-9
    for j in range(2 * n):
        u = np.zeros((n, 2))
        u.flat[j] = eps
        f_elem, f = np.zeros((ne, 4, 2)), np.zeros((n, 2))
        axisymmetric_element_forces(  # one step of length 1 from rest to x0 + u: stress C : grad u
            m.coordinates + u, u, m.connectivity, m.element_active, m.element_material, m.element_section,
            m.material_type, m.material_param, m.section_param, m.volume0, 1.0, np.zeros((ne, 6)),
            np.zeros((ne, NHIST)), np.zeros(ne), np.zeros(ne), np.zeros((ne, 1, 2)), f_elem, np.zeros(ne),
            np.zeros(ne), np.zeros(ne))
        gather_nodal_forces(f_elem, m.node_elem_ptr, m.node_elem_idx, f)
        stiffness[:, j] = -f.ravel() / eps
    free = np.ones((n, 2), dtype=bool)
    free[m.coordinates[:, 0] == 0.0, 0] = False
    free[m.node_sets["bottom"], 1] = False
    keep = free.ravel()
    w2 = np.linalg.eigvals(stiffness[np.ix_(keep, keep)] / np.repeat(m.mass, 2)[keep][:, None]).real
    return 2.0 / np.sqrt(w2.max())


@pytest.mark.parametrize("divisions", [(1, 1), (4, 4), (2, 8), (8, 2)])
def test_stable_step_bounds_the_critical_step_on_the_axis(model_from_deck, divisions):
    """Solid cylinders with their axis: the solver's step at timestep_scale 1 is at most the exact limit
    (measured 0.83, 0.84, 0.97, 0.72 of it for these meshes; the hoop term's share in the element length)."""
    from sphfem_cli.solver.explicit import Simulation

    deck = cases.hydrostatic_cylinder_deck(4).replace("divisions: [4, 4]", f"divisions: [{divisions[0]}, {divisions[1]}]")
    model = model_from_deck(deck.replace("timestep_scale: 0.5", "timestep_scale: 1.0")
                            .replace("type: stiffness, coefficient: 0.05", "type: viscous, coefficient: 0.0"))
    ratio = Simulation(model).state.dt / _critical_step(model)
    assert 0.5 < ratio <= 1.0, ratio


def test_a_loose_node_is_reflected_at_the_axis(sim_from_deck):
    """A ring whose elements were all eroded is a loose node; one moving inwards must not cross the axis
    (r < 0 is no ring): it comes back on its mirror image with its radial velocity reversed, the
    symmetric collision of the ring with itself (solver.solid_domain._reflect_at_axis). Before, such nodes of
    the Lagrangian bird reached r = -3 mm and were kicked to km/s. One ring element (r 5-10 mm) eroded by hand
    before the first step, its four loose nodes sent inwards at 50 m/s: they reach the axis by 0.2 ms and
    must come back out at the same speed."""
    deck = {
        "dimension": "axisymmetric",
        "control": {"end_time": 4.0e-4, "timestep_scale": 0.9},
        "materials": {"steel": {"type": "elastic", "density": 7850.0, "youngs_modulus": 2.1e11, "poisson_ratio": 0.3}},
        "sections": {"solid": {"type": "solid"}},
        "parts": {"ring": {"material": "steel", "section": "solid",
                           "geometry": {"box": {"min": [0.005, 0.0], "max": [0.01, 0.005], "divisions": [1, 1]}}}},
    }
    sim = sim_from_deck(deck)
    st = sim.state
    sim.solids._erode(st, np.array([0]), "test")  # the only element: every node is loose
    st.v[:, 0] = -50.0
    speed = np.abs(st.v[:, 0]).copy()
    least = [np.inf]
    sim.run(lambda s: least.__setitem__(0, min(least[0], float(s.x[:, 0].min()))))
    assert least[0] >= 0.0
    assert np.all(sim.state.v[:, 0] > 0.0)  # every node came back out
    assert np.allclose(np.abs(sim.state.v[:, 0]), speed, rtol=0, atol=1e-12)
